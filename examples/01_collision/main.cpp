// Tutorial 1: two glass beads collide head-on (Hertz-Mindlin). Prints the contact duration and
// the restitution coefficient next to Hertz theory (docs/physics.md).
//
//   01_collision [--radius R] [--speed V] [--restitution E] [--dt DT]    (--help: the list)
#include <cstdio>

#include <granule/granule.hpp>

#include "../common/cli.hpp"

using namespace granule;
using Vec = Dim3::Vec;
namespace cli = granule::examples::cli;

namespace {

struct Options {
  double radius = 1.5e-3;    // [m]
  double speed = 0.5;        // of each bead, towards the other [m/s]
  double restitution = 0.9;  // requested [-]
  double dt = 1e-8;          // [s]
};

int collide(const Options& o) {
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Vec::Constant(-0.01);
  cfg.domain.hi = Vec::Constant(0.01);
  cfg.dt = o.dt;
  Simulation<Dim3, contact::HertzMindlin> sim(cfg);

  Material glass;
  glass.youngs_modulus = 64e9;  // [Pa]
  glass.poisson_ratio = 0.2;
  glass.density = 2500;         // [kg/m^3]
  glass.restitution = o.restitution;
  glass.friction = 0.5;
  const auto mat = sim.add_material(glass);

  const double r = o.radius, v = o.speed;
  sim.add_particle(Vec(-r - 1e-5, 0, 0), r, mat, Vec(v, 0, 0));
  sim.add_particle(Vec(r + 1e-5, 0, 0), r, mat, Vec(-v, 0, 0));

  double start = -1.0, end = -1.0;
  const double max_time = 1e-3;  // [s]
  while (end < 0.0 && sim.time() < max_time) {
    sim.step();
    if (sim.contact_count() > 0 && start < 0.0) start = sim.time();
    if (sim.contact_count() == 0 && start >= 0.0) end = sim.time();
  }
  if (end < 0.0) {
    std::fprintf(stderr, "01_collision: the beads did not %s within %g s\n",
                 start < 0.0 ? "touch" : "separate", max_time);
    return cli::exit_failed;
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

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app("Two glass beads (E = 64 GPa, nu = 0.2, 2500 kg/m^3) collide head-on; prints the "
               "contact duration and the restitution next to Hertz theory.",
               "01_collision");
  cli::configure(app);
  // The beads start side by side at the centre of a 2 cm box.
  cli::add_real(app, "--radius", o.radius, "bead radius [m]", cli::Range{0.0, 4e-3, false, true});
  cli::add_real(app, "--speed", o.speed, "speed of each bead towards the other [m/s]", cli::positive());
  cli::add_real(app, "--restitution", o.restitution, "requested coefficient of restitution [-]",
                cli::Range{0.0, 1.0, false, true});
  cli::add_real(app, "--dt", o.dt, "time step [s] (checked against the Rayleigh time)", cli::positive());
  return cli::run(app, argc, argv, [&] { return collide(o); });
}
