#pragma once
// Symplectic (semi-implicit) Euler: v += dt F(x)/m; x += dt v  (a1 = 1, a2 = 0 in the
// kick-drift-kick form of velocity_verlet.hpp), the scheme many older DEM codes use.
//
// In this engine it is velocity Verlet seen at another moment of the step: both schemes evaluate
// the force after the first kick, so the positions, the forces and the contact history of the
// two are identical (measured: restitution and contact time agree to 2e-15, wave-front speeds to
// 1e-10; docs/performance.md, "Speed against error"). What differs is the velocity reported at
// the end of a step: here it is the one of the next half step, v(t + dt/2) to O(dt^2), so
// quantities computed from reported velocities (kinetic energy, coarse-grained momentum) carry a
// first-order error. Kept so that this can be shown, and for codes that report that velocity.
namespace granule::integrators {

struct SymplecticEuler {
  static constexpr double first_kick = 1.0;
  static constexpr double second_kick = 0.0;
  static constexpr const char* name = "SymplecticEuler";
};

}  // namespace granule::integrators
