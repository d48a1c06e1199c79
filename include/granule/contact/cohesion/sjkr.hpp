#pragma once
// Simplified JKR cohesion (SJKR, LIGGGHTS; paper 001 eq. A6-A7): an attractive normal force
// proportional to the contact area,  F_c = k_c A,  acting while the particles overlap.
//
// 3D: A = pi a^2 with the exact radius a of the circle where two spheres intersect,
//   a^2 = (-d + r1 + r2)(d - r1 + r2)(d + r1 - r2)(d + r1 + r2) / (4 d^2)     (d: centre distance)
//   (001 eq. A7 writes the same product with pi/4 / d^2), and for a sphere on a flat wall
//   a^2 = 2 r delta - delta^2.
// 2D (disks of thickness t): the contact is a strip of width 2a, so A = 2 a t.
// k_c [J/m^3 = N/m^2], A [m^2], F_c [N].
#include <cmath>
#include <numbers>

#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct SjkrCohesion {
  static std::string signature() { return "SjkrCohesion"; }
  struct Params {
    double k_c = 0.0;        ///< [J/m^3]
    double thickness = 1.0;  ///< 2D out-of-plane thickness [m]
  };
  static Params make(const PairMaterial& p, double thickness) { return {p.k_c, thickness}; }
  static constexpr bool lanes = true;  ///< eval is written over D::Real (core/lanes.hpp)

  /// Squared radius of the contact circle [m^2].
  template <class D>
  static typename D::Real contact_radius_sq(const ContactGeometry<D>& g) {
    using std::isfinite;
    using std::max;
    using R = typename D::Real;
    R a2 = 2.0 * g.r_i * g.overlap - g.overlap * g.overlap;  // a wall (flat-contact limit)
    where_assign(isfinite(g.distance), a2, [&]() -> R {
      const R d = g.distance, r1 = g.r_i, r2 = g.r_j;
      return (-d + r1 + r2) * (d - r1 + r2) * (d + r1 - r2) * (d + r1 + r2) / (4.0 * d * d);
    });
    return max(R(0.0), a2);
  }

  /// Contact area A [m^2].
  template <class D>
  static typename D::Real area(const Params& p, const ContactGeometry<D>& g) {
    using std::sqrt;
    const typename D::Real a2 = contact_radius_sq(g);
    if constexpr (D::dim == 3) {
      return std::numbers::pi * a2;
    } else {
      return 2.0 * sqrt(a2) * p.thickness;
    }
  }

  /// Attractive force magnitude [N] (subtracted from the normal force).
  template <class D>
  static typename D::Real eval(const Params& p, const ContactGeometry<D>& g) {
    return p.k_c * area(p, g);
  }
};

}  // namespace granule::contact
