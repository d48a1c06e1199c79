#pragma once
// Effective properties of a pair of materials (particle-particle or particle-wall).
//
//   1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2                 (Hertz; 000 eq. B8, 001 eq. A3)
//   1/G* = 2(2 - nu_1)(1 + nu_1)/E_1 + 2(2 - nu_2)(1 + nu_2)/E_2  (Mindlin; 000 eq. B9)
// The shear form above equals (2 - nu_1)/G_1 + (2 - nu_2)/G_2 with G = E/(2(1+nu)) (Di Renzo &
// Di Maio 2004). Paper 001 eq. A3 prints (2 + nu)(1 - nu), a typo: for nu = 0.2 it differs by
// 20 %; we use the Mindlin form, as LIGGGHTS does.
// Restitution, friction and rolling parameters of unlike materials default to the arithmetic
// mean and can be overridden per pair (PairOverride, MaterialTable::set_pair,
// Simulation::set_pair), as LIGGGHTS' per-type-pair matrices and LAMMPS' pair coefficients.
// A rigid wall material (Material::rigid) adds no compliance and hands the pair the particle's
// parameters: the limit E_wall -> inf, with e, mu, mu_r not averaged with the wall's.
#include <cmath>
#include <algorithm>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

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
  double surface_energy = 0.0;      ///< gamma [J/m^2]; JKR and DMT use w = 2 gamma
  double k_n_linear = 0.0;          ///< linear normal stiffness [N/m]
  double kt_ratio = 2.0 / 7.0;      ///< linear tangential stiffness ratio k_t/k_n [-]
  double rolling_stiffness_factor = 2.25;  ///< EPSD k_r factor [-]
  double k_roll = 0.0;              ///< SDS rolling spring [N/m]

  /// beta = ln e / sqrt(ln^2 e + pi^2) (000 eq. B7, 001 eq. A5); beta = 0 for e = 1.
  double beta() const {
    const double l = std::log(restitution);
    return l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
  }
};

/// Mixes two materials into effective pair properties.
inline PairMaterial mix(const Material& a, const Material& b) {
  // A rigid material's terms are zero (two rigid ones, a wall-wall pair that never touches: inf).
  const auto normal = [](const Material& m) {
    return m.rigid ? 0.0 : (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus;
  };
  const auto shear = [](const Material& m) {
    return m.rigid ? 0.0 : 2.0 * (2.0 - m.poisson_ratio) * (1.0 + m.poisson_ratio) / m.youngs_modulus;
  };
  PairMaterial p;
  p.E_eff = 1.0 / (normal(a) + normal(b));
  p.G_eff = 1.0 / (shear(a) + shear(b));
  if (a.rigid != b.rigid) {
    // Against a rigid wall the particle's own parameters; its linear half-contact (2 k, see
    // below) in series with an infinitely stiff one: k = 2 k_particle, the limit k_b -> inf.
    const Material& s = a.rigid ? b : a;
    p.restitution = s.restitution;
    p.mu_s = s.friction;
    p.mu_r = s.rolling_friction;
    p.rolling_damping = s.rolling_damping;
    p.k_c = s.cohesion_energy_density;
    p.surface_energy = s.surface_energy;
    p.k_n_linear = 2.0 * s.linear_normal_stiffness();
    p.kt_ratio = s.tangential_stiffness_ratio;
    p.rolling_stiffness_factor = s.rolling_stiffness_factor;
    p.k_roll = s.rolling_stiffness;
    return p;
  }
  p.restitution = 0.5 * (a.restitution + b.restitution);
  p.mu_s = 0.5 * (a.friction + b.friction);
  p.mu_r = 0.5 * (a.rolling_friction + b.rolling_friction);
  p.rolling_damping = 0.5 * (a.rolling_damping + b.rolling_damping);
  p.k_c = 0.5 * (a.cohesion_energy_density + b.cohesion_energy_density);
  // Like surfaces: Dupre's w = gamma_1 + gamma_2 - gamma_12 = 2 gamma; unlike ones take the
  // mean gamma (w = gamma_1 + gamma_2, gamma_12 unknown): set_pair overrides it.
  p.surface_energy = 0.5 * (a.surface_energy + b.surface_energy);
  // Linear stiffness: like materials keep their k_n (002's k_n = E d is the contact stiffness);
  // unlike ones combine as two half-contacts of stiffness 2 k in series: 2 k_a k_b / (k_a + k_b).
  const double ka = a.linear_normal_stiffness(), kb = b.linear_normal_stiffness();
  p.k_n_linear = (ka > 0.0 && kb > 0.0) ? 2.0 * ka * kb / (ka + kb) : std::max(ka, kb);
  p.kt_ratio = 0.5 * (a.tangential_stiffness_ratio + b.tangential_stiffness_ratio);
  p.rolling_stiffness_factor = 0.5 * (a.rolling_stiffness_factor + b.rolling_stiffness_factor);
  // SDS rolling spring: the two materials' springs in series, 2 k_a k_b / (k_a + k_b) (like
  // materials keep their k_roll; one side 0 leaves the other's). Against a rigid wall the
  // particle's k_roll, as a LAMMPS wall takes the pair coefficient.
  const double ra = a.rolling_stiffness, rb = b.rolling_stiffness;
  p.k_roll = (ra > 0.0 && rb > 0.0) ? 2.0 * ra * rb / (ra + rb) : std::max(ra, rb);
  return p;
}

/// Explicit values for one material pair (particle-particle or particle-wall) that replace
/// the mixed ones, as a LIGGGHTS per-type-pair matrix entry or a LAMMPS pair coefficient.
/// Fields left empty keep the pair's current value. Names follow Material's.
struct PairOverride {
  std::optional<double> restitution;              ///< e [-], (0, 1]
  std::optional<double> friction;                 ///< mu_s [-], [0, inf)
  std::optional<double> rolling_friction;         ///< mu_r [-], [0, inf)
  std::optional<double> rolling_damping;          ///< eta_r [-], [0, inf)
  std::optional<double> cohesion_energy_density;  ///< k_c [J/m^3], [0, inf)
  std::optional<double> surface_energy;           ///< gamma [J/m^2], [0, inf) (w = 2 gamma)
  std::optional<double> linear_normal_stiffness;  ///< k_n of the linear laws [N/m], (0, inf)
  std::optional<double> tangential_stiffness_ratio;  ///< k_t / k_n of the linear laws [-], (0, inf)
  std::optional<double> rolling_stiffness;        ///< k_roll of the SDS rolling law [N/m], (0, inf)

  /// Throws InvalidParameter naming the field, value and valid range.
  void validate(const std::string& where) const {
    const auto check = [&](const std::optional<double>& v, const char* name, bool zero_ok, const char* range) {
      if (v) require((zero_ok ? *v >= 0.0 : *v > 0.0) && std::isfinite(*v), where, name, *v, range);
    };
    if (restitution)
      require(*restitution > 0.0 && *restitution <= 1.0, where, "restitution", *restitution, "(0, 1]");
    check(friction, "friction", true, "[0, inf)");
    check(rolling_friction, "rolling_friction", true, "[0, inf)");
    check(rolling_damping, "rolling_damping", true, "[0, inf)");
    check(cohesion_energy_density, "cohesion_energy_density", true, "[0, inf) J/m^3");
    check(surface_energy, "surface_energy", true, "[0, inf) J/m^2");
    check(linear_normal_stiffness, "linear_normal_stiffness", false, "(0, inf) N/m");
    check(tangential_stiffness_ratio, "tangential_stiffness_ratio", false, "(0, inf)");
    check(rolling_stiffness, "rolling_stiffness", false, "(0, inf) N/m");
  }

  /// `p` with the fields that are set replaced.
  PairMaterial apply(PairMaterial p) const {
    p.restitution = restitution.value_or(p.restitution);
    p.mu_s = friction.value_or(p.mu_s);
    p.mu_r = rolling_friction.value_or(p.mu_r);
    p.rolling_damping = rolling_damping.value_or(p.rolling_damping);
    p.k_c = cohesion_energy_density.value_or(p.k_c);
    p.surface_energy = surface_energy.value_or(p.surface_energy);
    p.k_n_linear = linear_normal_stiffness.value_or(p.k_n_linear);
    p.kt_ratio = tangential_stiffness_ratio.value_or(p.kt_ratio);
    p.k_roll = rolling_stiffness.value_or(p.k_roll);
    return p;
  }
};

}  // namespace granule
