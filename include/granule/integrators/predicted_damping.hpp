#pragma once
// Velocity Verlet whose dashpots see a predicted end-of-step velocity.
//
// Why: in the kick-drift-kick step (velocity_verlet.hpp) the force of step n+1 is evaluated with
// the half-step velocity v(n+1/2). For springs that is exact enough (the spring increment
// v(n+1/2) dt is the midpoint rule for the displacement), but a dashpot should act on v(n+1):
// using v(n+1/2) delays the damping by dt/2 and makes restitution and contact duration first
// order in dt (docs/performance.md, "Speed against error": -2.8 % duration at e = 0.5 at the
// default step). Here the dashpots (normal and tangential damping, viscous rolling resistance)
// act on
//     v*(n+1) = v(n+1/2) + dt/2 F(n)/m,    omega*(n+1) = omega(n+1/2) + dt/2 T(n)/I,
// the end-of-step velocity extrapolated with the last known force: its error is O(dt^2), so the
// damped contact becomes second order as well. Springs, history increments and the Coulomb and
// rolling limits are unchanged, so for elastic contacts the scheme is velocity Verlet exactly
// (same positions, bit for bit). Costs one more relative velocity per contact and one pass over
// the particles per step.
//
// It is an explicit predictor, not an implicit dashpot: the stability limit stays the one of the
// explicit step (the Rayleigh-time rule of materials/time_step.hpp), measured in
// benchmarks/speed_vs_error.cpp.
namespace granule::integrators {

struct VelocityVerletPredictedDamping {
  static constexpr double first_kick = 0.5;
  static constexpr double second_kick = 0.5;
  static constexpr bool predicts_damping_velocity = true;
  static constexpr const char* name = "VelocityVerletPredictedDamping";
};

/// True for an integrator policy that asks the engine for predicted dashpot velocities.
template <class Integrator>
constexpr bool predicts_damping_velocity() {
  if constexpr (requires { Integrator::predicts_damping_velocity; }) {
    return Integrator::predicts_damping_velocity;
  } else {
    return false;
  }
}

}  // namespace granule::integrators
