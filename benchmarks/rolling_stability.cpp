// Where a settled bed with EPSD rolling turns unstable, against the engine's rotational limit
// (Simulation::rolling_stability_limit, docs/physics.md "Time step"). Pours --particles spheres
// of paper 001's regolith (R = 1.25 mm, rho = 2500 kg/m^3, E = 5 MPa, nu = 0.2, mu_s = 1,
// mu_r = 0.8, eta_r = --eta, e = 0.5) into a 2 cm x 2 cm box at g = 9.81 m/s^2, settles them,
// checkpoints the bed, then runs --time seconds from it at dt = f x the limit for every f of
// --factors and prints, as CSV on stdout, the rotational kinetic energy per particle at the
// end. Where the explicit rolling dashpot is unstable the spin grows until the springs are fully
// mobilised (EPSD then drops the dashpot): the energy jumps by orders of magnitude.
//
//   bench_rolling_stability [--particles 800] [--eta 2] [--time 0.01]
//                           [--factors 0.5,1,1.3,1.6,1.9,2.2,2.5] [--bed rolling_bed.ckpt]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "granule/granule.hpp"
#include "granule/io/checkpoint.hpp"
#include "granule/scene/pour.hpp"
#include "granule/scene/settle.hpp"

using namespace granule;
using Vec = Dim3::Vec;
using Sim = Simulation<Dim3, contact::HertzMindlinEpsd>;

namespace {

constexpr double kR = 1.25e-3;

std::unique_ptr<Sim> make_box(double eta, double dt) {
  SimulationConfig<Dim3> cfg;
  cfg.domain.hi = Vec(0.02, 0.02, 0.06);
  cfg.gravity = Vec(0, 0, -9.81);
  cfg.dt = dt;
  cfg.allow_large_time_step = true;  // the scan goes past the limit on purpose
  auto sim = std::make_unique<Sim>(cfg);
  Material m{.youngs_modulus = 5e6, .poisson_ratio = 0.2, .density = 2500.0, .restitution = 0.5, .friction = 1.0};
  m.rolling_friction = 0.8;
  m.rolling_damping = eta;
  sim->add_material(m);
  const auto wall = sim->add_wall_material(m);
  sim->add_wall(geometry::BoxContainerShape<Dim3>(cfg.domain.lo, cfg.domain.hi), wall);
  return sim;
}

double rotational_energy_per_particle(const Sim& sim) {
  const auto& p = sim.particles();
  double e = 0.0;
  for (std::size_t i = 0; i < p.owned(); ++i) e += 0.5 / p.inv_inertia[i] * p.omega[i].squaredNorm();
  return p.owned() > 0 ? e / static_cast<double>(p.owned()) : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t particles = 800;
  double eta = 2.0, time = 0.01;
  std::vector<double> factors{0.5, 1.0, 1.3, 1.6, 1.9, 2.2, 2.5};
  std::string bed = "rolling_bed.ckpt";
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string k = argv[a], v = argv[a + 1];
    if (k == "--particles") {
      particles = std::stoul(v);
    } else if (k == "--eta") {
      eta = std::stod(v);
    } else if (k == "--time") {
      time = std::stod(v);
    } else if (k == "--bed") {
      bed = v;
    } else if (k == "--factors") {
      factors.clear();
      std::stringstream s(v);
      for (std::string f; std::getline(s, f, ',');) factors.push_back(std::stod(f));
    } else {
      std::fprintf(stderr, "unknown option %s (see the comment at the top of rolling_stability.cpp)\n", k.c_str());
      return 2;
    }
  }
  if ((argc - 1) % 2 != 0) {
    std::fprintf(stderr, "options come in pairs: --name value\n");
    return 2;
  }
  // The bed: poured and settled at 2e-6 s, well below the limit.
  if (!std::filesystem::exists(bed)) {
    auto sim = make_box(eta, 2e-6);
    scene::Pour pour(*sim, {Vec(0.002, 0.002, 0.01), Vec(0.018, 0.018, 0.058)}, scene::UniformSizes(kR, kR),
                     scene::StreamSchedule(particles, particles), 0);
    while (!pour.finished()) {
      pour.update();
      sim->run(100);
    }
    scene::settle(*sim, {.max_time = 0.5, .kinetic_energy_per_particle = 1e-13});
    io::write_checkpoint(*sim, bed);
    std::fprintf(stderr, "settled %zu particles at t = %g s -> %s\n", sim->particles().owned(), sim->time(), bed.c_str());
  }
  auto probe = make_box(eta, 2e-6);
  io::read_checkpoint(*probe, bed, {.allow_other_materials = true});  // (the bed may have another eta_r)
  probe->step();
  const auto lim = probe->rolling_stability_limit();
  std::fprintf(stderr, "limit %.4e s at particle id %llu (%zu contacts); 0.2 t_R = %.4e s\n", lim.limit,
               static_cast<unsigned long long>(probe->particles().id[lim.particle]), lim.contacts,
               0.2 * probe->critical_time_step());
  std::printf("eta_r,factor,dt_s,limit_s,rotational_energy_per_particle_J\n");
  for (const double f : factors) {
    auto sim = make_box(eta, 2e-6);  // the checkpoint's step; changed after reading it
    io::read_checkpoint(*sim, bed, {.allow_other_materials = true});
    sim->set_dt(f * lim.limit);
    sim->run_until(sim->time() + time);
    std::printf("%g,%g,%.6e,%.6e,%.6e\n", eta, f, f * lim.limit, lim.limit, rotational_energy_per_particle(*sim));
    std::fflush(stdout);
  }
}
