#pragma once
// JKR adhesion (Johnson, Kendall & Roberts 1971; Johnson, Contact Mechanics 1985, sec. 5.5;
// the LAMMPS granular "jkr" normal model). With the work of adhesion w = 2 gamma (Dupre, like
// surfaces) and the contact radius a, the elastic normal force and the overlap are
//
//   F(a)     = 4 E* a^3 / (3 R*) - sqrt(8 pi w E* a^3)
//   delta(a) = a^2 / R* - sqrt(2 pi w a / E*)
//
// At zero load a0^3 = 9 pi w R*^2 / (2 E*), delta0 = a0^2 / (3 R*). The largest pull (load
// control) is F = -3/2 pi w R* at a^3 = a0^3 / 4, delta = -a^2 / (3 R*). Under displacement
// control the contact breaks where d delta / da = 0: a_c^3 = pi w R*^2 / (8 E*),
//   delta_c = -3 a_c^2 / R* = -3/4 (pi^2 w^2 R* / E*^2)^(1/3),   F = -5/6 pi w R*.
// Hysteresis: the contact forms at touch (delta = 0, where F jumps from 0 to -8/9 of the pull-off
// force) and lasts to delta = -delta_c (tensile: ContactModel::pull_off_separation).
// Composition: the model hands every slot the Hertzian overlap of the same contact radius,
// a(delta)^2 / R* (elastic_overlap), so the Hertz law gives 4 E* a^3 / (3 R*) and its damping,
// and Mindlin k_t = 8 G* a (as LAMMPS' jkr); this slot then subtracts sqrt(8 pi w E* a^3).
// A tangential potential k_t(delta_H) |xi|^2 / 2 (SpringHistory::Potential) pushes with its
// delta_H-derivative times d delta_H / d delta, which ContactModel takes from
// elastic_overlap_slope (capped near the break, where it diverges).
// 3D spheres only. Scalar only (lanes = false: a Newton loop per contact).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct JkrCohesion {
  static std::string signature() { return "JkrCohesion"; }
  struct Params {
    double w = 0.0;      ///< work of adhesion 2 gamma [J/m^2]
    double E_eff = 0.0;  ///< E* [Pa]
  };
  static Params make(const PairMaterial& p, double /*thickness*/) { return {2.0 * p.surface_energy, p.E_eff}; }
  static constexpr bool lanes = false;
  static constexpr bool tensile = true;  ///< contacts last to negative overlap (pull_off_separation)

  /// Pull-off separation |delta_c| = 3/4 (pi^2 w^2 R* / E*^2)^(1/3) [m].
  static double separation(const Params& p, double r_eff) {
    return 0.75 * std::cbrt(std::numbers::pi * std::numbers::pi * p.w * p.w * r_eff / (p.E_eff * p.E_eff));
  }

  /// JKR force at contact radius a [N] (repulsive > 0).
  static double force(const Params& p, double a, double r_eff) {
    return 4.0 * p.E_eff * a * a * a / (3.0 * r_eff) - std::sqrt(8.0 * std::numbers::pi * p.w * p.E_eff * a * a * a);
  }

  /// Contact radius a(delta) on the stable branch a >= a_c [m]. With s = sqrt(a), delta(a) is
  /// f(s) = s^4 / R* - c s - delta = 0, c = sqrt(2 pi w / E*): f is convex, so Newton from
  /// s0 = (R* |delta|)^(1/4) + (c R*)^(1/3) (where f(s0) >= 0 and s0 >= s_c) falls monotonically
  /// onto the root. Beyond the break (delta <= -delta_c) a_c.
  static double contact_radius(const Params& p, double delta, double r_eff) {
    const double c = std::sqrt(2.0 * std::numbers::pi * p.w / p.E_eff);
    const double s_c = std::cbrt(0.25 * c * r_eff);
    if (delta <= -separation(p, r_eff)) return s_c * s_c;
    double s = std::sqrt(std::sqrt(r_eff * std::abs(delta))) + std::cbrt(c * r_eff);
    for (int it = 0; it < 100; ++it) {
      const double s2 = s * s;
      const double f = s2 * s2 / r_eff - c * s - delta;
      const double fp = 4.0 * s2 * s / r_eff - c;
      if (!(f > 0.0) || !(fp > 0.0)) break;
      const double next = std::max(s - f / fp, s_c);
      if (!(next < s)) break;
      s = next;
    }
    return s * s;
  }

  /// The overlap a Hertz contact of the same radius a(delta) has, a^2 / R* [m].
  static double elastic_overlap(const Params& p, double overlap, double r_eff) {
    const double a = contact_radius(p, overlap, r_eff);
    return a * a / r_eff;
  }

  /// Largest elastic_overlap_slope: the factor 1 / (1 - (a_c/a)^3/2) reaches it at a = 1.073 a_c.
  static constexpr double max_elastic_overlap_slope = 10.0;

  /// d delta_H / d delta, the slope of elastic_overlap in the real overlap, at the elastic
  /// overlap delta_H = a^2 / R* [-]. With delta_H = a^2 / R* and delta(a) above,
  ///   d delta_H / d delta = (2a/R*) / (2a/R* - sqrt(2 pi w / (E* a)) / 2) = 1 / (1 - (a_c/a)^3/2),
  /// since sqrt(2 pi w / E*) R* / (4 a^3/2) = (a_c/a)^3/2 (a_c^3 = pi w R*^2 / (8 E*)): 6/5 at the
  /// zero-load radius a0 (a_c^3 = a0^3 / 36), 3/2 at the load-controlled pull-off, -> 1 under
  /// large load, and unbounded at the break a -> a_c, where d delta / da = 0 (it grows as
  /// (delta + delta_c)^-1/2). A tangential potential k_t(delta_H) |xi|^2 / 2 has the normal force
  /// k_t'(delta_H) |xi|^2 / 2 times this factor (ContactModel::compose), which the Coulomb cap of
  /// |xi| alone does not bound: at the break mu |F_n| = 5/6 mu pi w R* and the coupling at full
  /// mobilisation is mu^2 (5/24) (E*/G*) |F_n| times the factor. So the factor is capped at
  /// max_elastic_overlap_slope = 10 (coupling then <= 10 mu^2 (5/24) (E*/G*) |F_n|, e.g. 2.5 |F_n|
  /// at mu = 0.5, nu = 0.3), which also keeps it finite at a = a_c, where contact_radius puts
  /// delta <= -delta_c and rounding may put a hair below a_c. The cap acts only for
  /// a < 1.073 a_c, the last 0.26 % of |delta_c| before the break; there the coupling does less
  /// work than the potential's force, by at most (k_t(1.073 a_c) - k_t(a_c)) |xi|^2 / 2 = 7.3 % of
  /// the spring energy k_t(a_c) |xi|^2 / 2 that the break drops anyway, and reversibly (the
  /// capped force is still a function of delta at fixed xi).
  static double elastic_overlap_slope(const Params& p, double elastic_overlap, double r_eff) {
    // (a_c/a)^3/2 = c R* / (4 a^3/2), a^3/2 = (R* delta_H)^3/4
    const double c = std::sqrt(2.0 * std::numbers::pi * p.w / p.E_eff);
    const double q = 0.25 * c * r_eff / std::sqrt(std::sqrt(r_eff * elastic_overlap) * r_eff * elastic_overlap);
    const double one_minus = 1.0 - q;
    return one_minus > 1.0 / max_elastic_overlap_slope ? 1.0 / one_minus : max_elastic_overlap_slope;
  }

  /// Adhesive pull sqrt(8 pi w E* a^3) [N]; g.overlap is elastic_overlap (ContactModel::evaluate).
  template <class D>
  static double eval(const Params& p, const ContactGeometry<D>& g) {
    static_assert(D::dim == 3, "JkrCohesion: JKR is a law of spheres (3D)");
    const double a3 = std::sqrt(g.r_eff * g.overlap) * g.r_eff * g.overlap;  // a^3 = (R* delta_H)^3/2
    return std::sqrt(8.0 * std::numbers::pi * p.w * p.E_eff * a3);
  }

  /// Potential of the whole JKR force, Hertz part included [J]; g is the geometry eval sees
  /// (g.overlap = a^2 / R*). Integrating F(a) d delta(a)/da over a from a = 0 gives
  ///   U(a) = 8 E* a^5 / (15 R*^2) - 4/(3 R*) sqrt(2 pi w E*) a^7/2 + pi w a^2,
  /// which is Johnson's total energy U_E - w pi a^2 (elastic energy of the Hertz load to a^2/R*
  /// followed by the flat-punch unload at radius a, minus the surface energy; JKR 1971, Maugis
  /// 2000 ch. 5), so dU/d delta = F on the equilibrium curve. Convention: zero for the separated
  /// pair, a = 0, the start of that curve at delta = 0. The curve reaches the stable branch a >= a_c
  /// only through the unstable one, which the engine never follows, so the stored energy jumps
  /// at both ends of the hysteresis, at constant delta (no work done): at touch from 0 to
  /// U(a_t) = -3/5 pi w a_t^2 (a_t^3 = 2 pi w R*^2 / E*, the jump-in), at the break from
  /// U(a_c) = +2/5 pi w a_c^2 to 0. The sum, 3/5 pi w a_t^2 + 2/5 pi w a_c^2, is the area of the
  /// hysteresis loop: what a touch-and-break cycle dissipates. Between the two jumps the pair's
  /// kinetic plus stored energy is constant (undamped). ContactModel::stored_energy takes this
  /// in place of the normal law's energy (tensile).
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>& g) {
    static_assert(D::dim == 3, "JkrCohesion: JKR is a law of spheres (3D)");
    const double a2 = g.r_eff * g.overlap, a = std::sqrt(a2);
    return 8.0 * p.E_eff * a2 * a2 * a / (15.0 * g.r_eff * g.r_eff) -
           4.0 / (3.0 * g.r_eff) * std::sqrt(2.0 * std::numbers::pi * p.w * p.E_eff) * a2 * a * std::sqrt(a) +
           std::numbers::pi * p.w * a2;
  }
};

}  // namespace granule::contact
