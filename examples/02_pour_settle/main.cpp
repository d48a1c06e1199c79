// Tutorial 2: pour glass beads into a box at a steady rate, let them settle under gravity and
// write what happened: a CSV time series (kinetic energy, contacts, bed height) and VTK frames
// (particles and contact network) for ParaView or OVITO.
//
//   02_pour_settle [--2d] [--particles N] [--rate R] [--out DIR] [--vtk-every N]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include <granule/granule.hpp>
#include <granule/io/csv.hpp>
#include <granule/io/progress.hpp>
#include <granule/io/vtk.hpp>
#include <granule/scene/pour.hpp>
#include <granule/scene/settle.hpp>

using namespace granule;

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

  std::printf("%zu particles poured in %.3f s, settled %s after %.3f s more; bed height %.4f m, %zu contacts\n",
              pour.inserted(), sim.time() - settled.time, settled.settled ? "yes" : "no (time limit)",
              settled.time, scene::surface_height(sim, up), sim.contact_count());
  std::printf("output in %s\n", out.string().c_str());
  return settled.settled ? 0 : 1;
}

int main(int argc, char** argv) {
  bool two_d = false;
  std::size_t n = 2000;
  double rate = 4000.0;
  std::filesystem::path out = "out/02_pour_settle";
  int vtk_every = 2000;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto next = [&]() -> std::string {
      if (a + 1 >= argc) { std::fprintf(stderr, "%s needs a value\n", arg.c_str()); std::exit(2); }
      return argv[++a];
    };
    if (arg == "--2d") two_d = true;
    else if (arg == "--particles") n = std::stoul(next());
    else if (arg == "--rate") rate = std::stod(next());
    else if (arg == "--out") out = next();
    else if (arg == "--vtk-every") vtk_every = std::stoi(next());
    else {
      std::printf("usage: 02_pour_settle [--2d] [--particles N (2000)] [--rate R particles/s (4000)]\n"
                  "                      [--out DIR (out/02_pour_settle)] [--vtk-every steps (2000; 0 = off)]\n");
      return arg == "--help" ? 0 : 2;
    }
  }
  return two_d ? run<Dim2>(n, rate, out, vtk_every) : run<Dim3>(n, rate, out, vtk_every);
}
