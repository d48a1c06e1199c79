#pragma once
// Effective properties of a pair of materials (particle-particle or particle-wall).
//
//   1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2                 (Hertz; 000 eq. B8, 001 eq. A3)
//   1/G* = 2(2 - nu_1)(1 + nu_1)/E_1 + 2(2 - nu_2)(1 + nu_2)/E_2  (Mindlin; 000 eq. B9)
// The shear form above equals (2 - nu_1)/G_1 + (2 - nu_2)/G_2 with G = E/(2(1+nu)) (Di Renzo &
// Di Maio 2004). Paper 001 eq. A3 prints (2 + nu)(1 - nu), a typo: for nu = 0.2 it differs by
// 20 %; we use the Mindlin form, as LIGGGHTS does.
// Restitution, friction and rolling parameters of unlike materials default to the arithmetic
// mean and can be overridden per pair (MaterialTable::set_pair), as LIGGGHTS' per-pair matrices.
#include <cmath>
#include <algorithm>
#include <limits>
#include <numbers>

#include "granule/materials/material.hpp"

namespace granule {

struct PairMaterial {
  double E_eff = 0.0;               ///< E*  [Pa]
  double G_eff = 0.0;               ///< G*  [Pa]
  double restitution = 1.0;         ///< e   [-]
  double mu_s = 0.0;                ///< sliding friction [-]
  double mu_r = 0.0;                ///< rolling friction [-]
  double rolling_damping = 0.0;     ///< eta_r [-]
  double k_c = 0.0;                 ///< SJKR cohesion energy density [J/m^3]
  double k_n_linear = 0.0;          ///< linear normal stiffness [N/m]
  double kt_ratio = 2.0 / 7.0;      ///< linear tangential stiffness ratio k_t/k_n [-]
  double rolling_stiffness_factor = 2.25;  ///< EPSD k_r factor [-]

  /// beta = ln e / sqrt(ln^2 e + pi^2) (000 eq. B7, 001 eq. A5); beta = 0 for e = 1.
  double beta() const {
    const double l = std::log(restitution);
    return l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
  }
};

/// Mixes two materials into effective pair properties.
inline PairMaterial mix(const Material& a, const Material& b) {
  PairMaterial p;
  p.E_eff = 1.0 / ((1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                   (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
  p.G_eff = 1.0 / (2.0 * (2.0 - a.poisson_ratio) * (1.0 + a.poisson_ratio) / a.youngs_modulus +
                   2.0 * (2.0 - b.poisson_ratio) * (1.0 + b.poisson_ratio) / b.youngs_modulus);
  p.restitution = 0.5 * (a.restitution + b.restitution);
  p.mu_s = 0.5 * (a.friction + b.friction);
  p.mu_r = 0.5 * (a.rolling_friction + b.rolling_friction);
  p.rolling_damping = 0.5 * (a.rolling_damping + b.rolling_damping);
  p.k_c = 0.5 * (a.cohesion_energy_density + b.cohesion_energy_density);
  // Linear stiffness: like materials keep their k_n (002's k_n = E d is the contact stiffness);
  // unlike ones combine as two half-contacts of stiffness 2 k in series: 2 k_a k_b / (k_a + k_b).
  const double ka = a.linear_normal_stiffness(), kb = b.linear_normal_stiffness();
  p.k_n_linear = (ka > 0.0 && kb > 0.0) ? 2.0 * ka * kb / (ka + kb) : std::max(ka, kb);
  p.kt_ratio = 0.5 * (a.tangential_stiffness_ratio + b.tangential_stiffness_ratio);
  p.rolling_stiffness_factor = 0.5 * (a.rolling_stiffness_factor + b.rolling_stiffness_factor);
  return p;
}

}  // namespace granule
