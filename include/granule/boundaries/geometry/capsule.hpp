#pragma once
// Capsule (segment a-b swept by a sphere/disk of radius r) as a solid, particles outside.
// With q the point of the segment nearest to x, q = a + clamp((x - a).(b - a)/|b - a|^2, 0, 1)(b - a):
//   distance = |x - q| - r,  normal = (x - q)/|x - q|,  point = q + r normal.
// On the segment itself the normal is a fixed vector perpendicular to b - a. a == b is allowed
// (a sphere/disk of radius r; fallback normal = last axis).
#include <algorithm>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Solid capsule in 2D or 3D.
template <class D>
class CapsuleShape {
 public:
  using Dimension = D;
  using Vec = typename D::Vec;

  /// Segment end points `a`, `b` [m] and `radius` >= 0 [m].
  CapsuleShape(const Vec& a, const Vec& b, double radius) : a_(a), b_(b), radius_(radius) {
    require_non_negative(radius, "geometry::CapsuleShape", "radius");
    require(a.allFinite() && b.allFinite(), "geometry::CapsuleShape", "end points (max |coordinate|)",
            std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()), "finite numbers");
    const Vec ab = b - a;
    length2_ = ab.squaredNorm();
    fallback_ = length2_ > 0.0 ? Vec(detail::any_perpendicular(Vec(ab / std::sqrt(length2_))))
                               : detail::up_axis<D>();
  }

  const Vec& a() const { return a_; }
  const Vec& b() const { return b_; }
  double radius() const { return radius_; }

  /// Nearest point of the core segment to x [m].
  Vec segment_point(const Vec& x) const {
    if (length2_ == 0.0) return a_;
    const double t = std::clamp((x - a_).dot(b_ - a_) / length2_, 0.0, 1.0);
    return a_ + t * (b_ - a_);
  }

  SurfacePoint<D> closest(const Vec& x) const {
    const Vec q = segment_point(x);
    SurfacePoint<D> s = detail::outside_point<D>(x, q, fallback_);
    s.distance -= radius_;
    s.point = q + radius_ * s.normal;
    return s;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<D> s = closest(x);
    if (s.distance < r_cut) f(s);
  }

  Aabb<D> bounds() const {
    return Aabb<D>(a_.cwiseMin(b_), a_.cwiseMax(b_)).expanded(radius_);
  }

 private:
  Vec a_;
  Vec b_;
  double radius_;   // [m]
  double length2_;  // |b - a|^2 [m^2]
  Vec fallback_;
};

}  // namespace granule::geometry
