// Costs of a distributed run (issue 28; docs/mpi.md), for the scaling measurements on a quiet
// machine: a bed of spheres (100k by default) settling in a box, run on the ranks mpirun gives
// it, with OpenMP inside each rank as usual. After a warm-up it times `--steps` steps and prints
// one block per run:
//   time per particle-step: wall time / (N x steps), and x ranks x threads (core-seconds),
//   per step: halo and migration bytes and non-empty messages sent (summed over the ranks),
//   per rebuild: migration seconds, halo-build seconds; per step: ghost-refresh seconds;
//   rebalances and their seconds; particles and ghosts per rank (max/mean).
// Built only with -DGRANULE_MPI=ON, as bench_mpi_bed (not part of the default build):
//   cmake --build build-mpi --target bench_mpi_bed
//   OMP_NUM_THREADS=1 mpirun -np 2 build-mpi/benchmarks/mpi/bench_mpi_bed --steps 500
// Command line: --particles N (default 100000), --steps S (500), --warmup W (100),
// --grid px py pz (default: least cut area), --rebalance T (1.2; 0 off).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "granule/granule.hpp"
#include "granule/parallel/mpi_domains.hpp"

using namespace granule;
using Vec = Dim3::Vec;
using Sim = Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList, integrators::VelocityVerlet,
                       parallel::MpiDomains>;

int main(int argc, char** argv) {
  parallel::MpiContext mpi(argc, argv);
  std::size_t n = 100000;
  std::uint64_t steps = 500, warmup = 100;
  parallel::RankGrid grid{{0, 0, 0}};
  double threshold = 1.2;
  for (int a = 1; a < argc; ++a) {
    const std::string k = argv[a];
    auto next = [&] { return a + 1 < argc ? std::string(argv[++a]) : std::string("0"); };
    if (k == "--particles") n = std::stoull(next());
    else if (k == "--steps") steps = std::stoull(next());
    else if (k == "--warmup") warmup = std::stoull(next());
    else if (k == "--rebalance") threshold = std::stod(next());
    else if (k == "--grid") for (int d = 0; d < 3; ++d) grid.parts[d] = std::stoi(next());
    else {
      if (mpi.root()) std::fprintf(stderr, "bench_mpi_bed: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  return mpi.run([&] {
    // A square box holding the bed ~ as deep as wide: spheres of radius 1 mm +-10 % on a
    // lattice of spacing 2.2 r, dropping a little onto the floor.
    const double r = 1e-3, s = 2.2 * r;
    const int side = std::max(2, static_cast<int>(std::cbrt(double(n))));
    const int layers = static_cast<int>((n + std::size_t(side) * side - 1) / (std::size_t(side) * side));
    SimulationConfig<Dim3> cfg;
    cfg.domain.lo = Vec::Zero();
    cfg.domain.hi = Vec(side * s, (layers + 2) * s, side * s);
    cfg.domain.periodic[0] = cfg.domain.periodic[2] = true;
    cfg.gravity = Vec(0.0, -9.81, 0.0);
    cfg.dt = 5e-6;
    cfg.skin = 0.2 * r;
    Sim sim(cfg, parallel::MpiDomains(mpi, grid).rebalance(threshold));
    Material m;
    m.youngs_modulus = 5e7;
    m.poisson_ratio = 0.3;
    m.density = 2500;
    m.restitution = 0.4;
    m.friction = 0.5;
    const auto mat = sim.add_material(m);
    const auto wmat = sim.add_wall_material(m);
    sim.add_wall(geometry::PlaneShape<Dim3>(cfg.domain.lo, Vec::UnitY()), wmat);
    sim.add_wall(geometry::PlaneShape<Dim3>(cfg.domain.hi, Vec(-Vec::UnitY())), wmat);
    std::uint64_t state = 0x2545F4914F6CDD1DULL;
    auto uniform = [&state] {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return double(state >> 11) * (1.0 / 9007199254740992.0);
    };
    for (std::size_t k = 0; k < n; ++k) {
      const int i = int(k % std::size_t(side)), j = int(k / (std::size_t(side) * side)),
                l = int((k / std::size_t(side)) % std::size_t(side));
      sim.add_particle(Vec((i + 0.5) * s, (j + 0.5) * s, (l + 0.5) * s), r * (0.9 + 0.2 * uniform()), mat,
                       Vec(0.0, -0.01 * uniform(), 0.0));
    }
    sim.run(warmup);
    const auto& E = sim.parallel_engine();
    const std::uint64_t bytes0 = E.sum(E.sent_bytes), msgs0 = E.sum(E.sent_messages);
    const std::size_t builds0 = sim.neighbour_list().builds;
    const double mig0 = E.migration_seconds, halo0 = E.halo_seconds, ref0 = E.refresh_seconds,
                 reb0 = E.rebalance_seconds;
    const std::uint64_t rebal0 = E.rebalances, moved0 = E.sum(E.migrated);
    MPI_Barrier(mpi.comm());
    const auto t0 = std::chrono::steady_clock::now();
    sim.run(steps);
    MPI_Barrier(mpi.comm());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double bytes = double(E.sum(E.sent_bytes) - bytes0), msgs = double(E.sum(E.sent_messages) - msgs0);
    const double builds = double(sim.neighbour_list().builds - builds0);
    const double mig = mpi.max(E.migration_seconds - mig0), halo = mpi.max(E.halo_seconds - halo0),
                 ref = mpi.max(E.refresh_seconds - ref0), reb = mpi.max(E.rebalance_seconds - reb0);
    const double moved = double(E.sum(E.migrated) - moved0);
    const double owned = double(sim.particles().owned()), ghosts = double(sim.particles().ghosts());
    const double owned_max = mpi.max(owned), ghosts_max = mpi.max(ghosts), ghosts_sum = mpi.sum(ghosts);
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    if (mpi.root()) {
      const double R = mpi.size();
      const auto parts = E.decomposition->grid().parts;
      std::printf("bench_mpi_bed: %zu spheres, %d ranks (grid %dx%dx%d) x %d threads, %lu steps after %lu\n", n,
                  mpi.size(), parts[0], parts[1], parts[2], threads, (unsigned long)steps, (unsigned long)warmup);
      std::printf("  time per particle-step      %.4g s (%.4g core-s: x ranks x threads)\n", wall / (double(n) * steps),
                  wall * R * threads / (double(n) * steps));
      std::printf("  sent per step (all ranks)   %.4g bytes in %.4g messages (halo refresh; rebuild steps add "
                  "migration and the halo build)\n", bytes / steps, msgs / steps);
      std::printf("  rebuilds                    %.0f (every %.1f steps); migrations %.0f particles\n", builds,
                  builds > 0 ? steps / builds : 0.0, moved);
      std::printf("  per rebuild (slowest rank)  migration %.4g s, halo build %.4g s\n",
                  builds > 0 ? mig / builds : 0.0, builds > 0 ? halo / builds : 0.0);
      std::printf("  per step (slowest rank)     ghost refresh %.4g s of %.4g s\n", ref / steps, wall / steps);
      std::printf("  rebalances                  %lu (%.4g s)\n", (unsigned long)(E.rebalances - rebal0), reb);
      std::printf("  particles per rank          max %.0f, mean %.0f; ghosts max %.0f, mean %.0f\n", owned_max,
                  double(n) / R, ghosts_max, ghosts_sum / R);
    }
    return 0;
  });
}
