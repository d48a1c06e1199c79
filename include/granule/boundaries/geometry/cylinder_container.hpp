#pragma once
// Cylinder seen from inside (3D): a silo or a drum. Particles live inside the tube of centre c,
// unit axis a, radius R, half length H. With h = (x - c) . a, rho = (x - c) - h a and
// e_r = rho / |rho| (a fixed vector perpendicular to a on the axis):
//   side (feature 0): distance R - |rho|, normal -e_r, point c + h a + R e_r. This is the
//     exact distance to the side for |h| <= H. Beyond an open end (|h| > H) the nearest point is
//     the rim circle, p = c + sign(h) H a + R e_r, normal (x - p)/|x - p|: a particle leaving
//     the tube slides off the rim edge instead of losing its side contact in one step.
//   caps (closed tube only; features 1 lower, 2 upper): the planes h = -H (normal +a) and
//     h = +H (normal -a), distances h + H and H - h, treated as planes like a box container's
//     faces; the side is then the infinite cylinder surface (exact for every x inside).
// closest() returns the nearest of these (ties: side, then lower cap); for_each_contact()
// reports each one within r_cut, so a particle in the corner of a closed drum touches the
// side and a cap at once.
// The wall pass treats every surface point as a flat wall (contact radius = particle radius):
// the concave side's own curvature 1/R is not in the contact law (docs/physics.md, "Effective
// pair properties": about 3.8 % more overlap than the exact Hertz contact at R = 5 r).
//
// CircleContainerShape is the 2D analogue: disks inside a circle of centre c and radius R
// (a 2D drum), distance R - |x - c|, normal -e_r.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Finite cylinder, particles inside (3D only); open ends (a silo tube) or closed by flat caps (a drum).
class CylinderContainerShape {
 public:
  using Dimension = Dim3;
  using Vec = Dim3::Vec;

  /// `centre` [m], `axis` (normalised here), `radius` [m], `half_length` [m]; `closed` adds the
  /// two end caps.
  CylinderContainerShape(const Vec& centre, const Vec& axis, double radius, double half_length, bool closed = false)
      : centre_(centre), radius_(radius), half_length_(half_length), closed_(closed) {
    const double len = axis.norm();
    require(len > 0.0 && std::isfinite(len), "geometry::CylinderContainerShape", "|axis|", len, "(0, inf)");
    require_positive(radius, "geometry::CylinderContainerShape", "radius");
    require_positive(half_length, "geometry::CylinderContainerShape", "half_length");
    require(centre.allFinite(), "geometry::CylinderContainerShape", "centre (max |c_k|)",
            centre.cwiseAbs().maxCoeff(), "finite numbers");
    axis_ = axis / len;
    radial_fallback_ = detail::any_perpendicular(axis_);
  }

  const Vec& centre() const { return centre_; }
  const Vec& axis() const { return axis_; }
  double radius() const { return radius_; }
  double half_length() const { return half_length_; }
  bool closed() const { return closed_; }

  /// The side (feature 0), seen from x (valid for any x).
  SurfacePoint<Dim3> side(const Vec& x) const {
    const Vec rel = x - centre_;
    const double h = rel.dot(axis_);
    const Vec radial = rel - h * axis_;
    const double rho = radial.norm();
    const Vec e_r = rho > 0.0 ? Vec(radial / rho) : radial_fallback_;
    if (!closed_ && std::abs(h) > half_length_) {
      const double sign = h >= 0.0 ? 1.0 : -1.0;
      return detail::outside_point<Dim3>(x, centre_ + sign * half_length_ * axis_ + radius_ * e_r, -e_r);
    }
    SurfacePoint<Dim3> s;
    s.distance = radius_ - rho;
    s.normal = -e_r;
    s.point = centre_ + h * axis_ + radius_ * e_r;
    return s;
  }

  /// Cap k (1 lower, 2 upper) as its plane, seen from x.
  SurfacePoint<Dim3> cap(int k, const Vec& x) const {
    const double h = (x - centre_).dot(axis_);
    SurfacePoint<Dim3> s;
    s.distance = k == 1 ? h + half_length_ : half_length_ - h;
    s.normal = k == 1 ? axis_ : Vec(-axis_);
    s.point = x - s.distance * s.normal;
    s.feature = static_cast<std::uint32_t>(k);
    return s;
  }

  SurfacePoint<Dim3> closest(const Vec& x) const {
    SurfacePoint<Dim3> best = side(x);
    if (!closed_) return best;
    for (int k = 1; k <= 2; ++k) {
      const SurfacePoint<Dim3> s = cap(k, x);
      if (s.distance < best.distance) best = s;
    }
    return best;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<Dim3> s = side(x);
    if (s.distance < r_cut) f(s);
    if (!closed_) return;
    for (int k = 1; k <= 2; ++k) {
      const SurfacePoint<Dim3> c = cap(k, x);
      if (c.distance < r_cut) f(c);
    }
  }

  /// The cylinder's tight box: along world axis k the half extent is H |a_k| + R sqrt(1 - a_k^2).
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
  bool closed_;
};

/// Circle, particles inside (2D only): a 2D drum.
class CircleContainerShape {
 public:
  using Dimension = Dim2;
  using Vec = Dim2::Vec;

  /// `centre` [m], `radius` [m].
  CircleContainerShape(const Vec& centre, double radius) : centre_(centre), radius_(radius) {
    require_positive(radius, "geometry::CircleContainerShape", "radius");
    require(centre.allFinite(), "geometry::CircleContainerShape", "centre (max |c_k|)",
            centre.cwiseAbs().maxCoeff(), "finite numbers");
  }

  const Vec& centre() const { return centre_; }
  double radius() const { return radius_; }

  SurfacePoint<Dim2> closest(const Vec& x) const {
    const Vec rel = x - centre_;
    const double rho = rel.norm();
    // At the centre every direction is nearest: take -y, the floor of a drum under gravity.
    const Vec e_r = rho > 0.0 ? Vec(rel / rho) : Vec(-detail::up_axis<Dim2>());
    SurfacePoint<Dim2> s;
    s.distance = radius_ - rho;
    s.normal = -e_r;
    s.point = centre_ + radius_ * e_r;
    return s;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<Dim2> s = closest(x);
    if (s.distance < r_cut) f(s);
  }

  Aabb<Dim2> bounds() const { return Aabb<Dim2>(centre_ - Vec::Constant(radius_), centre_ + Vec::Constant(radius_)); }

 private:
  Vec centre_;
  double radius_;  // [m]
};

}  // namespace granule::geometry
