#pragma once
// Linear spring-dashpot normal law -- the reference law (read this file first when adding one).
//
//   F_n = k_n delta - gamma_n v_n,     gamma_n = 2 xi sqrt(m* k_n),
//   xi  = -ln e / sqrt(ln^2 e + pi^2)
// This damping gives exactly the restitution coefficient e for a contact that ends when the
// overlap returns to zero (the classical solution of the damped oscillator; e.g. Schwager &
// Poeschel 2007, paper 002 section 2.3 which writes xi = 1/sqrt(1 + (pi/ln e)^2)). The force is
// not clipped at zero so that this holds exactly; a small attraction appears just before
// separation, as in LAMMPS/LIGGGHTS hooke.
// k_n comes from the material: given directly, or k_n = E * L (2D disks, 002: k_n = E d).
// Units: k_n [N/m], gamma_n [N s/m], forces [N].
#include <cmath>
#include <numbers>

#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct LinearNormal {
  static std::string signature() { return "LinearNormal"; }
  struct Params {
    double k_n = 0.0;   ///< [N/m]
    double xi = 0.0;    ///< damping ratio [-]
  };
  static constexpr bool hertzian = false;
  static constexpr bool lanes = true;  ///< eval is written over D::Real (core/lanes.hpp)

  static Params make(const PairMaterial& p) {
    const double l = std::log(p.restitution);
    return {p.k_n_linear, -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi)};
  }

  template <class D>
  static NormalResultOf<D> eval(const Params& p, const ContactGeometry<D>& g) {
    using std::sqrt;
    using R = typename D::Real;
    const R gamma = 2.0 * p.xi * sqrt(g.m_eff * p.k_n);
    const R fe = p.k_n * g.overlap;
    return {fe - gamma * g.vn_damp, fe, p.k_n};
  }

  /// Elastic energy stored at overlap delta [J].
  static double elastic_energy(const Params& p, double overlap, double /*r_eff*/) {
    return 0.5 * p.k_n * overlap * overlap;
  }
};

}  // namespace granule::contact
