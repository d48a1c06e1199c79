#pragma once
// Integrators are written as kick-drift-kick splittings: a step is
//   v += a1 dt F/m;  x += dt v;  (forces at the new positions)  v += a2 dt F/m
// with the same for omega and torque. The engine never mentions the scheme beyond a1 and a2.
//
// VelocityVerlet (a1 = a2 = 1/2): second order, time reversible and symplectic for
// conservative forces (Swope et al. 1982). The default.
namespace granule::integrators {

struct VelocityVerlet {
  static constexpr double first_kick = 0.5;
  static constexpr double second_kick = 0.5;
  static constexpr const char* name = "VelocityVerlet";
};

}  // namespace granule::integrators
