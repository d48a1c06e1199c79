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
#include <algorithm>
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

  /// Potential of the cohesive force, -k_c int_0^delta A(delta') d delta' [J] (0 apart,
  /// continuous at touch). With S = r1 + r2, D = r1 - r2 and d = S - delta, a^2 =
  /// ((S^2 + D^2) - d^2 - S^2 D^2 / d^2) / 4 integrates over d' from d to S to
  ///   int_0^delta a^2 = delta^2 / 4 ((2 S + d) / 3 - D^2 / d)      (-> R* delta^2 for small delta),
  /// and for a sphere on a wall int_0^delta (2 r x - x^2) dx = r delta^2 - delta^3 / 3. 2D:
  /// A = 2 a t with a ~ sqrt(delta'), integrated by 8-point Gauss-Legendre in s, delta' = delta s^2,
  /// where the integrand is smooth (relative error ~1e-15 at the overlaps of a DEM contact).
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>& g) {
    const double delta = g.overlap;
    if (!(delta > 0.0)) return 0.0;
    const bool wall = !std::isfinite(g.distance);
    if constexpr (D::dim == 3) {
      double integral = 0.0;  // int_0^delta a^2 [m^3]
      if (wall) {
        integral = g.r_i * delta * delta - delta * delta * delta / 3.0;
      } else {
        const double S = g.r_i + g.r_j, Dr = g.r_i - g.r_j, d = S - delta;
        integral = 0.25 * delta * delta * ((2.0 * S + d) / 3.0 - Dr * Dr / d);
      }
      return -p.k_c * std::numbers::pi * integral;
    } else {
      // Gauss-Legendre on [0, 1]: nodes (1 + x_k) / 2, weights w_k / 2.
      constexpr double x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
      constexpr double wt[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
      const auto radius = [&](double dl) {  // a(delta') [m]: the same pair at overlap delta'
        ContactGeometry<D> at = g;
        at.overlap = dl;
        if (!wall) at.distance = g.r_i + g.r_j - dl;
        return std::sqrt(contact_radius_sq(at));
      };
      double integral = 0.0;  // int_0^delta a [m^2] = int_0^1 a(delta s^2) 2 delta s ds
      for (int k = 0; k < 4; ++k) {
        for (const double sign : {-1.0, 1.0}) {
          const double s = 0.5 * (1.0 + sign * x[k]);
          integral += 0.5 * wt[k] * radius(delta * s * s) * 2.0 * delta * s;
        }
      }
      return -p.k_c * 2.0 * p.thickness * integral;
    }
  }
};

}  // namespace granule::contact
