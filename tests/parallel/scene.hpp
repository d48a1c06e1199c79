#pragma once
// The scene of the distributed-engine tests (tests/parallel/distributed_suite.cpp) and of the
// single-process identity check: frictional Hertz-Mindlin spheres in a box, poured on a
// lattice with jitter, settling under gravity onto a floor plane on a body that slides along x
// (shearing the bed), periodic along x (and optionally z), fixed walls on the other axes.
// Deterministic (own LCG), so every rank and every build sets up the same particles in the
// same order.
#include <cstdint>
#include <vector>

#include "granule/granule.hpp"

namespace granule::test_parallel {

struct SceneOptions {
  int nx = 10, ny = 12, nz = 8;     ///< lattice of spheres
  bool periodic_z = false;
  double floor_speed = 0.05;        ///< floor velocity along x [m/s]
  double radius = 1.0e-3;           ///< mean radius [m]
};

/// The sheared slab: periodic along x and z, long along x (cut across the ranks along x), the
/// floor sliding at 0.5 m/s (the distributed, checkpoint and output suites).
inline SceneOptions sheared_slab() {
  SceneOptions o;
  o.nx = 24;
  o.ny = 6;
  o.nz = 7;
  o.periodic_z = true;
  o.floor_speed = 0.5;
  return o;
}

inline Domain<Dim3> scene_domain(const SceneOptions& o) {
  Domain<Dim3> d;
  const double s = 2.4 * o.radius;
  d.lo = Dim3::Vec::Zero();
  d.hi = Dim3::Vec(o.nx * s, (o.ny + 4) * s, o.nz * s);
  d.periodic[0] = true;
  d.periodic[2] = o.periodic_z;
  return d;
}

inline SimulationConfig<Dim3> scene_config(const SceneOptions& o) {
  SimulationConfig<Dim3> c;
  c.domain = scene_domain(o);
  c.gravity = Dim3::Vec(0.0, -30.0, 0.0);
  c.dt = 5.0e-6;
  c.skin = 0.2 * o.radius;
  return c;
}

/// Adds materials, the sliding floor, side walls and the spheres to `sim`.
template <class Sim>
void populate(Sim& sim, const SceneOptions& o) {
  using Vec = Dim3::Vec;
  Material m;
  m.name = "glass-ish";
  m.youngs_modulus = 5.0e7;
  m.poisson_ratio = 0.3;
  m.density = 2500.0;
  m.restitution = 0.4;
  m.friction = 0.5;
  const auto mat = sim.add_material(m);
  const auto wmat = sim.add_wall_material(m);
  const Domain<Dim3> dom = scene_domain(o);
  Body<Dim3> floor;
  floor.name = "floor";
  const double u = o.floor_speed;
  floor.velocity = [u](double) { return Vec(u, 0.0, 0.0); };
  const auto fb = sim.add_body(floor);
  sim.add_wall(geometry::PlaneShape<Dim3>(dom.lo, Vec::UnitY()), wmat, fb);
  sim.add_wall(geometry::PlaneShape<Dim3>(dom.hi, Vec(-Vec::UnitY())), wmat);
  if (!o.periodic_z) {
    sim.add_wall(geometry::PlaneShape<Dim3>(dom.lo, Vec::UnitZ()), wmat);
    sim.add_wall(geometry::PlaneShape<Dim3>(dom.hi, Vec(-Vec::UnitZ())), wmat);
  }
  std::uint64_t state = 0x2545F4914F6CDD1DULL;
  auto uniform = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) * (1.0 / 9007199254740992.0);
  };
  const double s = 2.4 * o.radius;
  for (int j = 0; j < o.ny; ++j)
    for (int k = 0; k < o.nz; ++k)
      for (int i = 0; i < o.nx; ++i) {
        const double r = o.radius * (0.85 + 0.3 * uniform());
        Vec x((i + 0.5) * s + 0.1 * o.radius * (uniform() - 0.5), (j + 0.5) * s,
              (k + 0.5) * s + 0.1 * o.radius * (uniform() - 0.5));
        Vec v(0.02 * (uniform() - 0.5), -0.05 * uniform(), 0.02 * (uniform() - 0.5));
        sim.add_particle(x, r, mat, v);
      }
}

}  // namespace granule::test_parallel
