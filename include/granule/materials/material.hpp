#pragma once
// Material of a particle species or a wall, in physical terms (SI units). Contact laws derive
// their stiffness and damping from these values; see docs/physics.md for every formula.
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "granule/core/error.hpp"

namespace granule {

struct Material {
  std::string name = "material";
  double youngs_modulus = 0.0;    ///< E  [Pa]
  double poisson_ratio = 0.0;     ///< nu [-], in [0, 0.5)
  double density = 0.0;           ///< rho [kg/m^3]; walls may leave it 0
  double restitution = 1.0;       ///< e [-], in (0, 1]
  double friction = 0.0;          ///< mu_s, sliding friction coefficient [-]
  double rolling_friction = 0.0;  ///< mu_r, rolling friction coefficient [-] (torque limit mu_r R* F_n)
  double rolling_damping = 0.0;   ///< eta_r, rolling viscous damping ratio [-] (EPSD, Ai et al. 2011)
  double cohesion_energy_density = 0.0;  ///< k_c, SJKR cohesion energy density [J/m^3]
  /// gamma, surface energy of one surface [J/m^2] (JKR, DMT: work of adhesion w = 2 gamma).
  double surface_energy = 0.0;
  /// Linear spring-dashpot only: normal stiffness [N/m]. 0 means "derive from E and the
  /// reference length": k_n = E * reference_length (2D disks, paper 002 section 2.3).
  double normal_stiffness = 0.0;
  double reference_length = 0.0;  ///< [m] length used in k_n = E * L when normal_stiffness == 0
  /// Linear laws: tangential stiffness as a fraction of k_n [-] (002 uses k_t = k_n / 2).
  double tangential_stiffness_ratio = 2.0 / 7.0;
  /// EPSD rolling stiffness factor c in k_r = c k_n mu_r^2 R*^2 [-]. Ai et al. (2011) eq. 13
  /// give 2.25; paper 001 eq. A14 prints 2.55 (see docs/physics.md).
  double rolling_stiffness_factor = 2.25;
  /// SDS rolling law only (contact/rolling/sds.hpp): k_roll [N/m], the rolling spring as a
  /// force on the rolling displacement R* theta (torque stiffness k_roll R*^2), as LAMMPS'
  /// `rolling sds`. 0 = not set; a model with SdsRolling refuses a pair with mu_r > 0 and k_roll 0.
  double rolling_stiffness = 0.0;
  /// Walls only: an infinitely stiff material. It adds nothing to 1/E* and 1/G* (its E and nu
  /// are not used), and a pair with it takes the particle's e, mu_s, mu_r, eta_r, k_c and
  /// linear stiffness instead of their means (pair_material.hpp); set_pair can override them.
  /// The limit of a wall of E -> inf, without the 1e6 E stand-in.
  bool rigid = false;

  /// A rigid wall material with the given name (its contact parameters come from the particles).
  static Material rigid_wall(std::string wall_name = "rigid wall") {
    Material m;
    m.name = std::move(wall_name);
    m.rigid = true;
    return m;
  }

  /// Throws InvalidParameter naming the field, value and valid range.
  /// `is_wall` relaxes the density requirement (walls have no mass).
  void validate(bool is_wall = false) const {
    const std::string where = "Material '" + name + "'";
    require(is_wall || !rigid, where, "rigid", 1.0,
            "{0} for a particle material (rigid = 1 is for wall materials: add_wall_material)");
    if (!rigid) {
      require(youngs_modulus > 0.0 && std::isfinite(youngs_modulus), where, "youngs_modulus",
              youngs_modulus, "(0, inf) Pa");
      require(poisson_ratio >= 0.0 && poisson_ratio < 0.5, where, "poisson_ratio", poisson_ratio,
              "[0, 0.5)");
    }
    if (!is_wall) {
      require(density > 0.0 && std::isfinite(density), where, "density", density, "(0, inf) kg/m^3");
    } else {
      require(density >= 0.0 && std::isfinite(density), where, "density", density, "[0, inf) kg/m^3");
    }
    require(restitution > 0.0 && restitution <= 1.0, where, "restitution", restitution, "(0, 1]");
    require(friction >= 0.0 && std::isfinite(friction), where, "friction", friction, "[0, inf)");
    require(rolling_friction >= 0.0 && std::isfinite(rolling_friction), where, "rolling_friction",
            rolling_friction, "[0, inf)");
    require(rolling_damping >= 0.0 && std::isfinite(rolling_damping), where, "rolling_damping",
            rolling_damping, "[0, inf)");
    require(cohesion_energy_density >= 0.0 && std::isfinite(cohesion_energy_density), where,
            "cohesion_energy_density", cohesion_energy_density, "[0, inf) J/m^3");
    require(surface_energy >= 0.0 && std::isfinite(surface_energy), where, "surface_energy", surface_energy,
            "[0, inf) J/m^2");
    require(normal_stiffness >= 0.0 && std::isfinite(normal_stiffness), where, "normal_stiffness",
            normal_stiffness, "[0, inf) N/m (0 = derive from E * reference_length)");
    require(reference_length >= 0.0 && std::isfinite(reference_length), where, "reference_length",
            reference_length, "[0, inf) m");
    require(tangential_stiffness_ratio > 0.0 && std::isfinite(tangential_stiffness_ratio), where,
            "tangential_stiffness_ratio", tangential_stiffness_ratio, "(0, inf)");
    require(rolling_stiffness_factor > 0.0 && std::isfinite(rolling_stiffness_factor), where,
            "rolling_stiffness_factor", rolling_stiffness_factor, "(0, inf)");
    require(rolling_stiffness >= 0.0 && std::isfinite(rolling_stiffness), where, "rolling_stiffness",
            rolling_stiffness, "[0, inf) N/m");
  }

  /// Shear modulus G = E / (2 (1 + nu)) [Pa].
  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  /// Linear normal stiffness k_n [N/m] (given, or E * reference_length).
  double linear_normal_stiffness() const {
    return normal_stiffness > 0.0 ? normal_stiffness : youngs_modulus * reference_length;
  }
};

}  // namespace granule
