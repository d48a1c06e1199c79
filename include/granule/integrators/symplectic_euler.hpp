#pragma once
// Symplectic (semi-implicit) Euler: v += dt F(x)/m; x += dt v  (a1 = 1, a2 = 0 in the
// kick-drift-kick form of velocity_verlet.hpp). First order, symplectic; the scheme many older
// DEM codes use. Kept for the speed-against-error study (docs/performance.md): it costs the same
// one force evaluation per step as velocity Verlet.
namespace granule::integrators {

struct SymplecticEuler {
  static constexpr double first_kick = 1.0;
  static constexpr double second_kick = 0.0;
  static constexpr const char* name = "SymplecticEuler";
};

}  // namespace granule::integrators
