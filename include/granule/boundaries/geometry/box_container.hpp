#pragma once
// Axis-aligned box seen from inside: particles live in [lo, hi]; each of the 2*dim faces is a
// plane wall with inward normal. For a face k (axis a = k/2, lower face when k is even):
//   lower: d = x_a - lo_a, normal +e_a;   upper: d = hi_a - x_a, normal -e_a.
// closest() returns the face with the smallest d (ties: lower axis first, lower face first).
// for_each_contact() reports every face with d < r_cut, so a particle in an inner corner
// touches two (2D) or three (3D) faces at once. The faces are treated as their planes: exact
// for every x inside the box; a particle that escaped is pushed back by the face(s) it crossed.
// SurfacePoint::feature is the face index k = 2 a + (0 lower | 1 upper).
#include <cstdint>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Box container (particles inside).
template <class D>
class BoxContainerShape {
 public:
  using Dimension = D;
  using Vec = typename D::Vec;
  static constexpr int kFaces = 2 * D::dim;

  /// Corners [m]; hi - lo must be positive in every component.
  BoxContainerShape(const Vec& lo, const Vec& hi) : lo_(lo), hi_(hi) {
    for (int a = 0; a < D::dim; ++a) {
      require(std::isfinite(lo[a]) && std::isfinite(hi[a]) && hi[a] > lo[a], "geometry::BoxContainerShape",
              "hi - lo (axis " + std::to_string(a) + ")", hi[a] - lo[a], "(0, inf)");
    }
  }

  const Vec& lo() const { return lo_; }
  const Vec& hi() const { return hi_; }

  /// Face k as a surface point seen from x (valid for any x).
  SurfacePoint<D> face(int k, const Vec& x) const {
    const int a = k / 2;
    SurfacePoint<D> s;
    s.normal = Vec::Zero();
    if (k % 2 == 0) {
      s.distance = x[a] - lo_[a];
      s.normal[a] = 1.0;
    } else {
      s.distance = hi_[a] - x[a];
      s.normal[a] = -1.0;
    }
    s.point = x - s.distance * s.normal;
    s.feature = static_cast<std::uint32_t>(k);
    return s;
  }

  SurfacePoint<D> closest(const Vec& x) const {
    SurfacePoint<D> best = face(0, x);
    for (int k = 1; k < kFaces; ++k) {
      const SurfacePoint<D> s = face(k, x);
      if (s.distance < best.distance) best = s;
    }
    return best;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    for (int k = 0; k < kFaces; ++k) {
      const SurfacePoint<D> s = face(k, x);
      if (s.distance < r_cut) f(s);
    }
  }

  /// The box itself: particles are expected inside.
  Aabb<D> bounds() const { return Aabb<D>(lo_, hi_); }

 private:
  Vec lo_;
  Vec hi_;
};

}  // namespace granule::geometry
