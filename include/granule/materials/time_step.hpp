#pragma once
// Time-step estimates for explicit DEM.
//
// Rayleigh time (Li, Xu & Thornton 2005; LIGGGHTS docs): the time a Rayleigh surface wave needs
// to cross a particle,  t_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766).
// Hertz collision time of a head-on impact at speed v (paper 001 eq. A17, after Johnson 1985):
//   tau_c = 2.94 ( m*^2 / ((16/15)^2 E*^2 R* v) )^(1/5)   with R* the effective radius.
// (001 writes R of the incident particle: for a particle hitting an equal particle R* = R/2;
// we use the effective radius, which is what the Hertz solution contains.)
// Linear spring-dashpot collision time: t_c = pi / sqrt(k/m* - (gamma/(2 m*))^2).
// Stability of velocity Verlet for a damped oscillator x'' = -w^2 x - 2 zeta w x' (the damping
// force from the mid-step velocity, as the engine evaluates it): dt <= 2 (sqrt(1 + zeta^2) -
// zeta) / w, the central-difference limit with damping (Belytschko, Liu & Moran 2000,
// "Nonlinear Finite Elements for Continua and Structures", section 6.3). It tends to 2/w
// without damping and to 1/(zeta w) = 2/(damping rate) when overdamped.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "granule/core/error.hpp"

namespace granule {

/// Rayleigh time of a particle of radius r [m], density rho [kg/m^3], shear modulus G [Pa],
/// Poisson ratio nu [-]. Returns seconds.
inline double rayleigh_time(double r, double rho, double G, double nu) {
  return std::numbers::pi * r * std::sqrt(rho / G) / (0.1631 * nu + 0.8766);
}

/// Hertz collision duration (001 eq. A17) for effective mass m* [kg], effective modulus E* [Pa],
/// effective radius R* [m] and normal impact speed v [m/s] (> 0). Returns seconds.
inline double hertz_collision_time(double m_eff, double E_eff, double r_eff, double v) {
  require_positive(v, "hertz_collision_time", "impact speed v");
  const double c = 16.0 / 15.0;
  return 2.94 * std::pow(m_eff * m_eff / (c * c * E_eff * E_eff * r_eff * v), 0.2);
}

/// Maximum overlap of an elastic Hertz impact: delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
inline double hertz_max_overlap(double m_eff, double E_eff, double r_eff, double v) {
  return std::pow(15.0 * m_eff * v * v / (16.0 * E_eff * std::sqrt(r_eff)), 0.4);
}

/// Collision time of a linear spring-dashpot with stiffness k [N/m], effective mass m* [kg] and
/// restitution e: t_c = sqrt(m*/k) sqrt(pi^2 + ln^2 e).
inline double linear_collision_time(double k, double m_eff, double restitution) {
  const double l = std::log(restitution);
  return std::sqrt(m_eff / k) * std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

/// Largest stable velocity-Verlet step of a damped oscillator with angular frequency omega
/// [rad/s] (> 0) and damping ratio zeta [-] (>= 0). Returns seconds.
inline double damped_oscillator_stability_limit(double omega, double zeta) {
  // sqrt(1 + z^2) - z written as 1 / (sqrt(1 + z^2) + z): no cancellation for large zeta.
  return 2.0 / (omega * (std::sqrt(1.0 + zeta * zeta) + zeta));
}

/// Critical time of a linear spring-dashpot pair [s] (k [N/m], m* [kg], restitution e): the
/// collision time t_c, or pi/2 x the step's stability limit under the pair's dashpot
/// (damped_oscillator_stability_limit) where that is smaller. Undamped the two agree (t_c = pi/w,
/// limit 2/w), so a fixed fraction of this time keeps the same margin below the limit at every
/// e. t_c alone does not: the dashpot lowers the limit while it lengthens t_c, and 0.2 t_c is
/// above the limit for e < 0.02 (a head-on collision at 0.2 t_c, e = 0.01, leaves with 1.2-2.0
/// times its impact speed). `damping_rate_factor` is 2 for integrators that hand the dashpots
/// the predicted end-of-step velocity (integrators::VelocityVerletPredictedDamping): it doubles
/// their rate per step.
inline double linear_critical_time(double k, double m_eff, double restitution, double damping_rate_factor = 1.0) {
  const double l = std::log(restitution);
  const double zeta = -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
  const double w = std::sqrt(k / m_eff);
  return std::min(linear_collision_time(k, m_eff, restitution),
                  0.5 * std::numbers::pi * damped_oscillator_stability_limit(w, damping_rate_factor * zeta));
}

}  // namespace granule
