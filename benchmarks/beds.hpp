// The two benchmark beds of issue 6 (docs/performance.md), shared by bench_scene_throughput
// (one process, against the peers) and bench_mpi_bed (distributed, the scaling measurements),
// so that both time the same scene from the same LAMMPS data file.
//
//   A  lunar bed (paper 001, table 2): R = 1.25 mm, rho = 2500 kg/m^3, E = 5 MPa, nu = 0.2,
//      e = 0.5, mu_s = 1.0, EPSD rolling mu_r = 0.8, rolling damping eta_r = 0 by default
//      (001 section 2.1: "the viscous damping component is neglected in this work"; table 2
//      lists 2), SJKR k_c = 1000 J/m^3, g = 1.625 m/s^2, dt = 1e-6 s; periodic across the
//      width x (2 cm, as in 001 section 2.2), floor z = 0 and end walls y = 0 and y = L;
//      channel length L = 10 x fill height (001: 2 m by 20 cm). contact::HertzMindlinEpsdSjkr.
//   B  intrusion bed (paper 000, table I): d = 2 mm, rho = 1100 kg/m^3, E = 5 MPa, nu = 0.3,
//      e = 0.2, mu = 0.5, g = 9.81 m/s^2, dt = 5e-6 s; a box closed by a floor and four side
//      walls (open top), square section S x S filled to 0.4 S (000 fig. 1: 25 cm x 25 cm
//      filled to 10 cm). contact::HertzMindlin.
// Walls are planes of the particle material.
#pragma once

#include <cmath>
#include <string>

#include <granule/granule.hpp>

namespace granule_bench {

using granule::Dim3;
using granule::Material;
using Vec3 = Dim3::Vec;

struct SceneSpec {
  char name = 'B';
  std::string model;
  Material material;
  double radius = 0.0;     // [m]
  double dt = 0.0;         // [s]
  double gravity = 0.0;    // [m/s^2], along -z
  double packing = 0.6;    // [-] expected packing fraction (box sizing only)
  bool periodic_x = false;
};

inline SceneSpec make_spec(char scene, double rolling_damping = 0.0) {
  SceneSpec s;
  s.name = scene;
  Material& m = s.material;
  if (scene == 'A') {
    s.model = "HertzMindlinEpsdSjkr";
    m.name = "lunar";
    m.youngs_modulus = 5.0e6;   // [Pa]
    m.poisson_ratio = 0.2;      // [-]
    m.density = 2500.0;         // [kg/m^3]
    m.restitution = 0.5;        // [-]
    m.friction = 1.0;           // [-]
    m.rolling_friction = 0.8;   // [-]
    m.rolling_damping = rolling_damping;  // [-]
    m.cohesion_energy_density = 1000.0;   // [J/m^3]
    s.radius = 1.25e-3;         // [m]
    s.dt = 1.0e-6;              // [s]
    s.gravity = 1.625;          // [m/s^2]
    s.packing = 0.58;
    s.periodic_x = true;
  } else {
    s.model = "HertzMindlin";
    m.name = "poppy";
    m.youngs_modulus = 5.0e6;   // [Pa]
    m.poisson_ratio = 0.3;      // [-]
    m.density = 1100.0;         // [kg/m^3]
    m.restitution = 0.2;        // [-]
    m.friction = 0.5;           // [-]
    s.radius = 1.0e-3;          // [m]
    s.dt = 5.0e-6;              // [s]
    s.gravity = 9.81;           // [m/s^2]
    s.packing = 0.60;
    s.periodic_x = false;
  }
  return s;
}

struct Box {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
};

// Horizontal extent of the bed for n particles; the z extent is set by the pour's lattice.
inline Box footprint(const SceneSpec& s, std::size_t n) {
  const double vp = Dim3::volume(s.radius, 1.0);
  const double bed = static_cast<double>(n) * vp / s.packing;  // [m^3]
  Box b;
  if (s.name == 'A') {
    const double width = 0.02;                          // [m] 001 section 2.2
    const double height = std::sqrt(bed / (10.0 * width));
    b.hi = Vec3(width, 10.0 * height, height);
  } else {
    const double side = std::cbrt(bed / 0.4);
    b.hi = Vec3(side, side, 0.4 * side);
  }
  return b;
}

inline granule::Domain<Dim3> domain_of(const SceneSpec& s, const Box& b) {
  granule::Domain<Dim3> dom;
  dom.lo = b.lo;
  dom.hi = b.hi;
  dom.periodic = granule::Domain<Dim3>::Flags(s.periodic_x, false, false);
  return dom;
}

// The configuration every timed run of a scene shares; callers set dt, skin and their flags.
inline granule::SimulationConfig<Dim3> config_of(const SceneSpec& s, const Box& box) {
  granule::SimulationConfig<Dim3> cfg;
  cfg.domain = domain_of(s, box);
  cfg.gravity = Vec3(0.0, 0.0, -s.gravity);
  cfg.dt = s.dt;
  return cfg;
}

// The container (floor, end walls, side walls unless x is periodic) in `material`; returns the
// particles' material id.
template <class Sim>
std::uint32_t add_container(Sim& sim, const SceneSpec& s, const Material& material, const Box& box) {
  const std::uint32_t mat = sim.add_material(material);
  const std::uint32_t wall_mat = sim.add_wall_material(material);
  using Plane = granule::geometry::PlaneShape<Dim3>;
  sim.add_wall(Plane(box.lo, Vec3::UnitZ()), wall_mat);
  sim.add_wall(Plane(box.lo, Vec3::UnitY()), wall_mat);
  sim.add_wall(Plane(box.hi, -Vec3::UnitY()), wall_mat);
  if (!s.periodic_x) {
    sim.add_wall(Plane(box.lo, Vec3::UnitX()), wall_mat);
    sim.add_wall(Plane(box.hi, -Vec3::UnitX()), wall_mat);
  }
  return mat;
}

}  // namespace granule_bench
