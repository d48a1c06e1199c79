// Tutorial 1: two glass beads collide head-on (Hertz-Mindlin). Prints the contact duration and
// the restitution coefficient next to Hertz theory (docs/physics.md).
#include <cstdio>

#include <granule/granule.hpp>

using namespace granule;
using Vec = Dim3::Vec;

int main() {
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Vec::Constant(-0.01);
  cfg.domain.hi = Vec::Constant(0.01);
  cfg.dt = 1e-8;  // [s]
  Simulation<Dim3, contact::HertzMindlin> sim(cfg);

  Material glass;
  glass.youngs_modulus = 64e9;  // [Pa]
  glass.poisson_ratio = 0.2;
  glass.density = 2500;         // [kg/m^3]
  glass.restitution = 0.9;
  glass.friction = 0.5;
  const auto mat = sim.add_material(glass);

  const double r = 1.5e-3, v = 0.5;  // radius [m], speed of each bead [m/s]
  sim.add_particle(Vec(-r - 1e-5, 0, 0), r, mat, Vec(v, 0, 0));
  sim.add_particle(Vec(r + 1e-5, 0, 0), r, mat, Vec(-v, 0, 0));

  double start = -1.0, end = -1.0;
  while (end < 0.0 && sim.time() < 1e-3) {
    sim.step();
    if (sim.contact_count() > 0 && start < 0.0) start = sim.time();
    if (sim.contact_count() == 0 && start >= 0.0) end = sim.time();
  }
  const auto& p = sim.particles();
  const double e = (p.v[sim.index_of(1)].x() - p.v[sim.index_of(0)].x()) / (2.0 * v);
  const PairMaterial pm = sim.materials().pair(mat, mat);
  const double m = p.mass[0];
  std::printf("contact duration  %.4e s  (elastic Hertz theory %.4e s)\n", end - start,
              hertz_collision_time(0.5 * m, pm.E_eff, 0.5 * r, 2.0 * v));
  std::printf("restitution       %.4f    (requested %.2f)\n", e, glass.restitution);
  return 0;
}
