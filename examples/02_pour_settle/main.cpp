// Tutorial 2: pour glass beads into a box at a steady rate, let them settle under gravity and
// write what happened: a CSV time series (kinetic energy, contacts, bed height) and VTK frames
// (particles and contact network) for ParaView or OVITO.
//
//   02_pour_settle [--2d] [--particles N] [--rate R] [--out DIR] [--vtk-every N] [--threads N]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/granule.hpp>
#include <granule/io/csv.hpp>
#include <granule/io/progress.hpp>
#include <granule/io/vtk.hpp>
#include <granule/scene/pour.hpp>
#include <granule/scene/settle.hpp>

#include "../common/cli.hpp"

using namespace granule;
namespace cli = granule::examples::cli;

template <class D>
int run(std::size_t n, double rate, const std::filesystem::path& out, int vtk_every) {
  using Vec = typename D::Vec;
  const int up = D::dim - 1;        // gravity acts along the last axis
  const double r = 1e-3;            // bead radius [m]
  const double w = 0.03, h = 0.12;  // box width and height [m]

  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(w);
  cfg.domain.hi[up] = h;
  cfg.gravity = -9.81 * Vec::Unit(up);
  cfg.thickness = 2 * r;  // 2D: disks as thick as they are wide
  cfg.dt = 1e-5;          // [s] (0.08 x the Rayleigh time of the beads)
  Simulation<D, contact::HertzMindlin> sim(cfg);

  Material glass;
  glass.youngs_modulus = 5e6;  // soft glass-like beads [Pa]: allows a large time step
  glass.poisson_ratio = 0.25;
  glass.density = 2500;        // [kg/m^3]
  glass.restitution = 0.3;
  glass.friction = 0.4;
  const auto mat = sim.add_material(glass);
  const auto wall = sim.add_wall_material(glass);
  sim.add_wall(geometry::BoxContainerShape<D>(cfg.domain.lo, cfg.domain.hi), wall);

  // Insertion region: the top of the box; particles enter falling at 0.5 m/s.
  geometry::Aabb<D> region{Vec::Constant(r), Vec::Constant(w - r)};
  region.lo[up] = 0.7 * h;
  region.hi[up] = h - r;
  scene::Pour<decltype(sim)> pour(sim, region, scene::UniformSizes(0.8 * r, 1.2 * r),
                                  scene::StreamSchedule(rate, n), mat, Vec(-0.5 * Vec::Unit(up)));

  std::filesystem::create_directories(out);
  io::CsvWriter csv(out / "time_series.csv", {{"time", "s"}, {"particles", ""}, {"kinetic_energy", "J"},
                                               {"contacts", ""}, {"bed_height", "m"}});
  io::VtkWriter<D> particles(out, "particles");
  io::ContactVtkWriter<D> contacts(out, "contacts");
  sim.every(100, [&](auto& s) {
    pour.update();
    csv.write_row({s.time(), double(s.particles().owned()), s.kinetic_energy(), double(s.contact_count()),
                   scene::surface_height(s, up)});
  });
  if (vtk_every > 0)
    sim.every(vtk_every, [&](auto& s) {
      const auto frame = s.frame();
      particles.write(frame);
      contacts.write(frame);
    }, true);

  io::ProgressReporter progress({.end_time = 2.0, .label = "pour"});
  while (!pour.finished() && sim.time() < 2.0) {
    sim.run(100);
    progress.update(sim.step_count(), sim.time());
  }
  scene::SettleOptions so;
  so.max_time = 1.0;
  so.kinetic_energy_per_particle = 1e-10;
  so.on_check = [&](double t, double) { progress.update(sim.step_count(), t); };
  const auto settled = scene::settle(sim, so);
  progress.finish(sim.step_count(), sim.time());

  // Packing fraction of the bed: grain volume (area in 2D) over the box section times the bed
  // height, taken as the mean top of the highest grains (scene::surface_height).
  const auto& p = sim.particles();
  double grains = 0.0;
  for (std::size_t i = 0; i < p.owned(); ++i)
    grains += D::dim == 3 ? 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3) : std::numbers::pi * p.radius[i] * p.radius[i];
  const double bed = scene::surface_height(sim, up);
  const double section = D::dim == 3 ? w * w : w;
  std::printf("%zu particles poured in %.3f s, settled %s after %.3f s more; bed height %.4f m, packing fraction "
              "%.3f, %zu contacts\n",
              pour.inserted(), sim.time() - settled.time, settled.settled ? "yes" : "no (time limit)", settled.time,
              bed, grains / (section * bed), sim.contact_count());
  std::printf("output in %s\n", out.string().c_str());
  return settled.settled ? 0 : 1;
}

int main(int argc, char** argv) {
  bool two_d = false;
  std::size_t n = 2000;
  double rate = 4000.0;
  std::string out = "out/02_pour_settle";
  int vtk_every = 2000;
  int threads = 0;
  CLI::App app("Pours glass beads (radius 0.8-1.2 mm) into a 3 x 3 x 12 cm box and lets them settle; writes "
               "a CSV time series and VTK frames into --out.",
               "02_pour_settle");
  cli::configure(app);
  app.add_flag("--2d", two_d, "disks in a 3 x 12 cm cell instead of spheres");
  cli::add_whole<std::size_t>(app, "--particles", n, "particles to pour [-]", 1, 10'000'000);
  cli::add_real(app, "--rate", rate, "particles inserted per second [1/s]", cli::positive());
  cli::add_text(app, "--out", out, "output directory")->default_str(out);
  cli::add_whole(app, "--vtk-every", vtk_every, "steps between VTK frames (0: none) [-]", 0);
  cli::add_whole(app, "--threads", threads, "OpenMP threads (default: OpenMP's choice) [-]", 1, 1024, false);
  return cli::run(app, argc, argv, [&] {
#ifdef _OPENMP
    if (threads > 0) omp_set_num_threads(threads);
#endif
    return two_d ? run<Dim2>(n, rate, out, vtk_every) : run<Dim3>(n, rate, out, vtk_every);
  });
}
