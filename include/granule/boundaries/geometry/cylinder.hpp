#pragma once
// Finite solid cylinder with flat caps (3D), particles outside: centre c, unit axis a,
// radius R, half length H. With h = (x - c) . a, the radial vector rho = (x - c) - h a and
// e_r = rho / |rho|:
//   outside (|h| > H or |rho| > R): nearest point p = c + clamp(h, -H, H) a + min(|rho|, R) e_r,
//     which is on the side, on a cap, or on a rim edge; normal (x - p)/|x - p|.
//   inside: the side (depth R - |rho|, normal e_r) or the nearer cap (depth H - |h|, normal
//     sign(h) a), whichever is shallower; distance = -depth. Ties go to the side, then to the
//     upper cap (h >= 0). On the axis, e_r is a fixed vector perpendicular to a.
#include <algorithm>
#include <cmath>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Solid finite cylinder with flat caps (3D only).
class CylinderShape {
 public:
  using Dimension = Dim3;
  using Vec = Dim3::Vec;

  /// `centre` [m], `axis` (normalised here), `radius` [m], `half_length` [m].
  CylinderShape(const Vec& centre, const Vec& axis, double radius, double half_length)
      : centre_(centre), radius_(radius), half_length_(half_length) {
    const double len = axis.norm();
    require(len > 0.0 && std::isfinite(len), "geometry::CylinderShape", "|axis|", len, "(0, inf)");
    require_positive(radius, "geometry::CylinderShape", "radius");
    require_positive(half_length, "geometry::CylinderShape", "half_length");
    require(centre.allFinite(), "geometry::CylinderShape", "centre (max |c_k|)", centre.cwiseAbs().maxCoeff(),
            "finite numbers");
    axis_ = axis / len;
    radial_fallback_ = detail::any_perpendicular(axis_);
  }

  const Vec& centre() const { return centre_; }
  const Vec& axis() const { return axis_; }
  double radius() const { return radius_; }
  double half_length() const { return half_length_; }

  SurfacePoint<Dim3> closest(const Vec& x) const {
    const Vec rel = x - centre_;
    const double h = rel.dot(axis_);
    const Vec radial = rel - h * axis_;
    const double rho = radial.norm();
    const Vec e_r = rho > 0.0 ? Vec(radial / rho) : radial_fallback_;
    if (std::abs(h) <= half_length_ && rho <= radius_) {
      SurfacePoint<Dim3> s;
      const double side_depth = radius_ - rho;
      const double cap_depth = half_length_ - std::abs(h);
      if (side_depth <= cap_depth) {
        s.distance = -side_depth;
        s.normal = e_r;
        s.point = centre_ + h * axis_ + radius_ * e_r;
      } else {
        const double sign = h >= 0.0 ? 1.0 : -1.0;
        s.distance = -cap_depth;
        s.normal = sign * axis_;
        s.point = centre_ + sign * half_length_ * axis_ + radial;
      }
      return s;
    }
    const double hc = std::clamp(h, -half_length_, half_length_);
    const Vec p = centre_ + hc * axis_ + std::min(rho, radius_) * e_r;
    return detail::outside_point<Dim3>(x, p, e_r);
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<Dim3> s = closest(x);
    if (s.distance < r_cut) f(s);
  }

  /// Tight box: along world axis k the half extent is H |a_k| + R sqrt(1 - a_k^2).
  Aabb<Dim3> bounds() const {
    Vec half;
    for (int k = 0; k < 3; ++k) {
      const double ak = axis_[k];
      half[k] = half_length_ * std::abs(ak) + radius_ * std::sqrt(std::max(0.0, 1.0 - ak * ak));
    }
    return Aabb<Dim3>(centre_ - half, centre_ + half);
  }

 private:
  Vec centre_;
  Vec axis_;
  Vec radial_fallback_;
  double radius_;       // [m]
  double half_length_;  // [m]
};

}  // namespace granule::geometry
