#pragma once
// Infinite plane (a line in 2D) through `point` with unit normal n; particles live on the side
// n points to. Signed distance d(x) = (x - point) . n, nearest point x - d n, normal n
// (the half-space x . n >= point . n is the particle side).
#include <limits>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Infinite plane / line wall.
template <class D>
class PlaneShape {
 public:
  using Dimension = D;
  using Vec = typename D::Vec;

  /// `point` on the plane [m]; `normal` towards the particle side (normalised here).
  PlaneShape(const Vec& point, const Vec& normal) : point_(point) {
    const double len = normal.norm();
    require(len > 0.0 && std::isfinite(len), "geometry::PlaneShape", "|normal|", len, "(0, inf)");
    require(point.allFinite(), "geometry::PlaneShape", "point (max |p_k|)", point.cwiseAbs().maxCoeff(),
            "finite numbers");
    normal_ = normal / len;
  }

  const Vec& point() const { return point_; }
  const Vec& normal() const { return normal_; }

  SurfacePoint<D> closest(const Vec& x) const {
    SurfacePoint<D> s;
    s.distance = (x - point_).dot(normal_);
    s.normal = normal_;
    s.point = x - s.distance * normal_;
    return s;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<D> s = closest(x);
    if (s.distance < r_cut) f(s);
  }

  /// Unbounded.
  Aabb<D> bounds() const { return Aabb<D>::infinite(); }

 private:
  Vec point_;
  Vec normal_;
};

}  // namespace granule::geometry
