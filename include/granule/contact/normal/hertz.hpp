#pragma once
// Hertz normal law with the viscoelastic damping of LIGGGHTS (paper 000 appendix B, paper 001
// eq. A1-A5; Tsuji et al. 1992 form with the restitution fit of Antypov & Elliott 2011):
//
//   F_n     = k_n delta - gamma_n v_n,     k_n = 4/3 E* sqrt(R* delta)   (so F_e = 4/3 E* sqrt(R*) delta^3/2)
//   gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*),   S_n = 2 E* sqrt(R* delta),
//   beta    = ln e / sqrt(ln^2 e + pi^2)
// (000 eq. B2 prints 2*5/6 without the square root; 001 eq. A4 and LIGGGHTS use sqrt(5/6).)
// With the force not clipped at zero, this damping realises the restitution e exactly, at any
// impact speed (Antypov & Elliott 2011: gamma = sqrt(5) |beta| sqrt(m* k_H) delta^1/4 with
// k_H = 4/3 E* sqrt(R*)); tests/contact check the engine against the one-contact ODE.
#include <cmath>
#include <numbers>

#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct HertzNormal {
  static std::string signature() { return "HertzNormal"; }
  struct Params {
    double E_eff = 0.0;        ///< [Pa]
    double damping = 0.0;      ///< -2 sqrt(5/6) beta  (>= 0) [-]
  };
  static constexpr bool hertzian = true;
  static constexpr bool lanes = true;  ///< eval is written over D::Real (core/lanes.hpp)

  static Params make(const PairMaterial& p) {
    return {p.E_eff, -2.0 * std::sqrt(5.0 / 6.0) * p.beta()};
  }

  template <class D>
  static NormalResultOf<D> eval(const Params& p, const ContactGeometry<D>& g) {
    using std::sqrt;
    using R = typename D::Real;
    const R a = sqrt(g.r_eff * g.overlap);           // contact radius [m]
    const R kn = 4.0 / 3.0 * p.E_eff * a;            // secant stiffness [N/m]
    const R sn = 2.0 * p.E_eff * a;                  // tangent stiffness [N/m]
    const R gamma = p.damping * sqrt(sn * g.m_eff);  // [N s/m]
    const R fe = kn * g.overlap;
    return {fe - gamma * g.vn_damp, fe, kn};
  }

  /// Elastic energy stored at overlap delta: 8/15 E* sqrt(R*) delta^5/2 [J].
  static double elastic_energy(const Params& p, double overlap, double r_eff) {
    return 8.0 / 15.0 * p.E_eff * std::sqrt(r_eff) * std::pow(overlap, 2.5);
  }
};

}  // namespace granule::contact
