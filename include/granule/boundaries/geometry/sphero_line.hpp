#pragma once
// 2D sphero-line wall (Fakih et al. 2019, as used in paper 002, section 2.3, eq. 1-3): the
// segment C1C2 with round caps of radius r_w, particles outside. With C the mid-point,
// L = |C1C2|, u = (C2 - C1)/L and v the right-handed unit normal (u rotated by +90 deg),
// the position of a particle centre O relative to C selects the case:
//   CO.u <= -L/2 : distance = |O - C1| - r_w                       (eq. 1, cap at C1)
//   CO.u >=  L/2 : distance = |O - C2| - r_w                       (eq. 2, cap at C2)
//   otherwise    : distance = |CO.v| - r_w, normal = sign(CO.v) v   (eq. 3, flat side)
// The paper writes the overlap of a particle of diameter d_i as delta = (d_i + d_w)/2 - |...|,
// i.e. r_i - distance here. Identical to CapsuleShape<Dim2>; kept as its own type because the
// paper's scenes are written in these terms (C1, C2, r_w, u, v).
#include <cmath>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Sphero-line (2D only).
class SpheroLineShape {
 public:
  using Dimension = Dim2;
  using Vec = Dim2::Vec;

  /// End points C1 != C2 [m] and cap radius r_w >= 0 [m].
  SpheroLineShape(const Vec& c1, const Vec& c2, double r_w) : c1_(c1), c2_(c2), r_w_(r_w) {
    require_non_negative(r_w, "geometry::SpheroLineShape", "r_w");
    length_ = (c2 - c1).norm();
    require(length_ > 0.0 && std::isfinite(length_), "geometry::SpheroLineShape", "|C2 - C1|", length_,
            "(0, inf)");
    centre_ = 0.5 * (c1 + c2);
    u_ = (c2 - c1) / length_;
    v_ = Vec(-u_.y(), u_.x());
  }

  const Vec& c1() const { return c1_; }
  const Vec& c2() const { return c2_; }
  double r_w() const { return r_w_; }
  double length() const { return length_; }
  const Vec& u() const { return u_; }
  const Vec& v() const { return v_; }

  SurfacePoint<Dim2> closest(const Vec& x) const {
    const Vec co = x - centre_;
    const double s = co.dot(u_);
    SurfacePoint<Dim2> out;
    if (s <= -0.5 * length_ || s >= 0.5 * length_) {
      const Vec& cap = s <= -0.5 * length_ ? c1_ : c2_;  // eq. 1 / eq. 2
      out = detail::outside_point<Dim2>(x, cap, v_);
      out.distance -= r_w_;
      out.point = cap + r_w_ * out.normal;
      return out;
    }
    const double w = co.dot(v_);  // eq. 3
    out.normal = w >= 0.0 ? v_ : Vec(-v_);
    out.distance = std::abs(w) - r_w_;
    out.point = centre_ + s * u_ + r_w_ * out.normal;
    return out;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<Dim2> s = closest(x);
    if (s.distance < r_cut) f(s);
  }

  Aabb<Dim2> bounds() const { return Aabb<Dim2>(c1_.cwiseMin(c2_), c1_.cwiseMax(c2_)).expanded(r_w_); }

 private:
  Vec c1_;
  Vec c2_;
  double r_w_;     // [m]
  double length_;  // [m]
  Vec centre_;
  Vec u_;
  Vec v_;
};

}  // namespace granule::geometry
