// Tutorial 2, distributed (built as 02_pour_settle_mpi only with -DGRANULE_MPI=ON; docs/mpi.md):
// glass beads dropped into the same 3 x 3 x 12 cm box as 02_pour_settle and settled under gravity,
// run on several MPI ranks with parallel::MpiDomains. Every rank builds the same scene with the
// same calls (the beads start on a jittered lattice in the upper part of the box, all inserted
// before the first step; a scene::Pour during the run would work too, docs/mpi.md); the box is cut
// between the ranks and recut as the beads fall (rebalance at max/mean 1.2). Output: a CSV time
// series written by rank 0 (kinetic energy and contacts, summed over the ranks), VTK frames as
// one .vtu piece per rank with a .pvtu and particles.pvd for ParaView, and a checkpoint at the
// end that restarts on any number of ranks or in one process.
//
//   mpirun -np 2 02_pour_settle_mpi [--particles N] [--out DIR] [--vtk-every N] [--max-time T]
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include <granule/granule.hpp>
#include <granule/io/checkpoint.hpp>
#include <granule/io/csv.hpp>
#include <granule/io/vtk_pieces.hpp>
#include <granule/parallel/mpi_domains.hpp>

#include "../common/cli.hpp"

using namespace granule;
namespace cli = granule::examples::cli;
using Vec = Dim3::Vec;
using Sim = Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList, integrators::VelocityVerlet,
                       parallel::MpiDomains>;

int run(const parallel::MpiContext& mpi, std::size_t n, const std::filesystem::path& out, int vtk_every,
        double max_time) {
  const double r = 1e-3;            // bead radius [m]
  const double w = 0.03, h = 0.12;  // box width and height [m]
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec(w, w, h);
  cfg.gravity = Vec(0.0, 0.0, -9.81);
  cfg.dt = 1e-5;
  Sim sim(cfg, parallel::MpiDomains(mpi).rebalance(1.2));

  Material glass;
  glass.youngs_modulus = 5e6;
  glass.poisson_ratio = 0.25;
  glass.density = 2500;
  glass.restitution = 0.3;
  glass.friction = 0.4;
  const auto mat = sim.add_material(glass);
  const auto wall = sim.add_wall_material(glass);
  sim.add_wall(geometry::BoxContainerShape<Dim3>(cfg.domain.lo, cfg.domain.hi), wall);

  // The beads: a lattice of spacing 2.6 r from the top down, radii 0.8-1.2 r, the same on every
  // rank (a fixed pseudo-random sequence).
  std::uint64_t state = 0x9E3779B97F4A7C15ULL;
  auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) * (1.0 / 9007199254740992.0);
  };
  const double s = 2.6 * r;
  const int per_row = static_cast<int>((w - 2 * r) / s);
  for (std::size_t k = 0; k < n; ++k) {
    const int layer = static_cast<int>(k / std::size_t(per_row * per_row));
    const int i = static_cast<int>(k % std::size_t(per_row)), j = static_cast<int>((k / std::size_t(per_row)) % std::size_t(per_row));
    const Vec x(r + s * (i + 0.5), r + s * (j + 0.5), h - r - s * (layer + 0.5));
    if (x[2] < 2 * r) throw cli::UsageError("--particles: more beads than the box holds on the lattice");
    sim.add_particle(x + 0.05 * r * Vec(uniform() - 0.5, uniform() - 0.5, 0.0), r * (0.8 + 0.4 * uniform()), mat,
                     Vec(0.0, 0.0, -0.5));
  }

  if (mpi.root()) std::filesystem::create_directories(out);
  std::optional<io::CsvWriter> csv;
  if (mpi.root()) csv.emplace(out / "time_series.csv", std::vector<io::CsvColumn>{{"time", "s"}, {"kinetic_energy", "J"}, {"contacts", ""}});
  io::PieceVtkWriter<Dim3> vtk(out, "particles");
  double ke = 0.0;
  std::uint64_t steps = 0;
  while (sim.time() < max_time) {
    sim.run(100);
    steps += 100;
    ke = sim.kinetic_energy();  // collective: every rank calls
    const double contacts = double(sim.contact_count());
    if (csv) csv->write_row({sim.time(), ke, contacts});
    if (vtk_every > 0 && steps % std::uint64_t(vtk_every) == 0) vtk.write(sim);
    if (ke / double(n) < 1e-10 && sim.time() > 0.1) break;  // settled
  }
  io::write_checkpoint(sim, (out / "settled.ckpt").string());
  const std::size_t contacts = sim.contact_count();  // collective
  const auto frame = sim.gathered_frame();           // rank 0: every bead
  if (mpi.root()) {
    std::vector<double> tops;
    for (std::size_t i = 0; i < frame.size(); ++i) tops.push_back(frame.x[i][2] + frame.radius[i]);
    std::sort(tops.rbegin(), tops.rend());
    double bed = 0.0;
    const std::size_t top = std::min<std::size_t>(20, tops.size());
    for (std::size_t i = 0; i < top; ++i) bed += tops[i] / double(top);
    std::printf("%zu beads on %d ranks: %.3f s simulated, kinetic energy %.3g J, bed height %.4f m, %zu contacts; "
                "%lu rebalances, %lu migrations on rank 0\n",
                frame.size(), mpi.size(), sim.time(), ke, bed, contacts,
                (unsigned long)sim.parallel_engine().rebalances, (unsigned long)sim.parallel_engine().migrated);
    std::printf("output in %s (particles.pvd, time_series.csv, settled.ckpt)\n", out.string().c_str());
  }
  return 0;
}

int main(int argc, char** argv) {
  parallel::MpiContext mpi(argc, argv);
  std::size_t n = 2000;
  std::string out = "out/02_pour_settle_mpi";
  int vtk_every = 2000;
  double max_time = 1.5;
  CLI::App app("Drops glass beads (radius 0.8-1.2 mm) into a 3 x 3 x 12 cm box on several MPI ranks and lets "
               "them settle; writes a CSV time series, VTK pieces and a checkpoint into --out.",
               "02_pour_settle_mpi");
  cli::configure(app);
  cli::add_whole<std::size_t>(app, "--particles", n, "beads [-]", 1, 10'000'000);
  cli::add_text(app, "--out", out, "output directory")->default_str(out);
  cli::add_whole(app, "--vtk-every", vtk_every, "steps between VTK frames, a multiple of 100 (0: none) [-]", 0);
  cli::add_real(app, "--max-time", max_time, "longest simulated time [s]", cli::positive());
  return mpi.run([&] { return cli::run(app, argc, argv, [&] { return run(mpi, n, out, vtk_every, max_time); }); });
}
