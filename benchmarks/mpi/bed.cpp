// Costs of a distributed run (issue 28; docs/mpi.md, docs/performance.md "Distributed runs"):
// the benchmark beds A and B of bench_scene_throughput (benchmarks/beds.hpp; settled beds in
// LAMMPS data files, made with `bench_scene_throughput --scene A|B --particles N --prepare FILE`)
// run on the ranks mpirun gives, with OpenMP inside each rank as usual. After a warm-up it
// times `--steps` steps `--repeat` times and prints, for the best run:
//   time per particle-step: wall time / (N x steps), and x ranks x threads (core-seconds),
//   per step: halo and migration bytes and non-empty messages sent (summed over the ranks),
//   per rebuild: migration seconds, halo-build seconds; per step: ghost-refresh seconds;
//   rebalances and their seconds; particles and ghosts per rank (max/mean),
// and one summary line of key=value pairs (benchmarks/mpi/scaling.sh reads it).
// --single runs the same scene in one process with parallel::SingleProcess (no MPI in the
// engine; mpirun -np 1 or no mpirun), the reference for the cost of the MPI policy itself.
// Built only with -DGRANULE_MPI=ON, as bench_mpi_bed (not part of the default build):
//   cmake --build build-mpi --target bench_mpi_bed
//   OMP_NUM_THREADS=1 mpirun -np 2 build-mpi/benchmarks/mpi/bench_mpi_bed --scene B --data out/bench/B100k.data
// Command line: --scene A|B (B), --data FILE (required), --steps S (500), --warmup W (100),
// --repeat R (2), --grid px py pz (default: least cut area), --rebalance T (1.2; 0 off),
// --skin M (engine default 0.1 d; a small skin makes the resting bed's creep rebuild the list,
// which measures the per-rebuild costs: migration, halo build, rebalance), --single.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "granule/granule.hpp"
#include "granule/io/lammps_data.hpp"
#include "granule/parallel/mpi_domains.hpp"

#include "../beds.hpp"

using namespace granule;
using granule_bench::SceneSpec;

namespace {

struct Options {
  char scene = 'B';
  std::string data;
  std::uint64_t steps = 500, warmup = 100;
  int repeat = 2;
  parallel::RankGrid grid{{0, 0, 0}};
  double threshold = 1.2;
  bool single = false;
  double skin = -1.0;  // [m]; < 0: engine default (0.1 d)
};

std::string loadavg() {
  std::ifstream f("/proc/loadavg");
  std::string line;
  std::getline(f, line);
  return line;
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

int threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

template <class Model, class Parallel>
using Sim = Simulation<Dim3, Model, neighbours::VerletList, integrators::VelocityVerlet, Parallel>;

// The scene of `s` from the data file, built by `make(config)`.
template <class S, class Make>
std::unique_ptr<S> load(const SceneSpec& s, const io::LammpsData& data, double skin, Make make) {
  granule_bench::Box box;
  box.lo = data.frame.box_lo;
  box.hi = data.frame.box_hi;
  auto config = granule_bench::config_of(s, box);
  config.skin = skin;
  auto sim = make(config);
  const std::uint32_t mat = granule_bench::add_container(*sim, s, s.material, box);
  const auto& f = data.frame;
  for (std::size_t i = 0; i < f.x.size(); ++i) sim->add_particle(f.x[i], f.radius[i], mat, f.v[i]);
  return sim;
}

// Times o.repeat runs of o.steps steps; `barrier` separates the runs on every rank, `max` is the
// slowest rank's value. Returns the best run's wall seconds and the CPU seconds of this process.
template <class S, class Barrier>
std::pair<double, double> time_runs(S& sim, const Options& o, Barrier barrier, bool root) {
  double best = 1e300, best_cpu = 0.0;
  for (int rep = 0; rep < o.repeat; ++rep) {
    barrier();
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    sim.run(o.steps);
    barrier();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpu_seconds() - c0;
    if (root) std::printf("  run %d: %.4f s wall, loadavg \"%s\"\n", rep + 1, wall, loadavg().c_str());
    if (wall < best) best = wall, best_cpu = cpu;
  }
  return {best, best_cpu};
}

template <class Model>
int run_single(const SceneSpec& s, const Options& o, const io::LammpsData& data) {
  using S = Sim<Model, parallel::SingleProcess>;
  auto sim = load<S>(s, data, o.skin, [](const SimulationConfig<Dim3>& c) { return std::make_unique<S>(c); });
  const double n = double(sim->particles().owned());
  sim->run(o.warmup);
  const std::size_t builds0 = sim->neighbour_list().builds;
  std::printf("bench_mpi_bed: scene %c, %.0f spheres, one process (SingleProcess) x %d threads, %d x %lu steps "
              "after %lu\n", s.name, n, threads(), o.repeat, (unsigned long)o.steps, (unsigned long)o.warmup);
  const auto [wall, cpu] = time_runs(*sim, o, [] {}, true);
  const double builds = double(sim->neighbour_list().builds - builds0) / o.repeat;
  std::printf("  time per particle-step      %.4g s (%.4g core-s)\n", wall / (n * o.steps),
              wall * threads() / (n * o.steps));
  std::printf("summary scene=%c particles=%.0f ranks=1 threads=%d policy=single steps=%lu wall_s=%.5g cpu_s=%.5g "
              "s_per_particle_step=%.5g contacts=%zu rebuilds_per_run=%.1f bytes_per_step=0 messages_per_step=0 "
              "loadavg=\"%s\"\n", s.name, n, threads(), (unsigned long)o.steps, wall, cpu, wall / (n * o.steps),
              sim->contact_count(), builds, loadavg().c_str());
  return 0;
}

template <class Model>
int run_distributed(const SceneSpec& s, const Options& o, const io::LammpsData& data, parallel::MpiContext& mpi) {
  using S = Sim<Model, parallel::MpiDomains>;
  auto sim = load<S>(s, data, o.skin, [&](const SimulationConfig<Dim3>& c) {
    return std::make_unique<S>(c, parallel::MpiDomains(mpi, o.grid).rebalance(o.threshold));
  });
  sim->run(o.warmup);
  const double n = mpi.sum(double(sim->particles().owned()));
  const auto& E = sim->parallel_engine();
  const std::uint64_t bytes0 = E.sum(E.sent_bytes), msgs0 = E.sum(E.sent_messages);
  const std::size_t builds0 = sim->neighbour_list().builds;
  const double mig0 = E.migration_seconds, halo0 = E.halo_seconds, ref0 = E.refresh_seconds,
               reb0 = E.rebalance_seconds;
  const std::uint64_t rebal0 = E.rebalances, moved0 = E.sum(E.migrated);
  if (mpi.root())
    std::printf("bench_mpi_bed: scene %c, %.0f spheres, %d ranks x %d threads, %d x %lu steps after %lu\n", s.name,
                n, mpi.size(), threads(), o.repeat, (unsigned long)o.steps, (unsigned long)o.warmup);
  const auto [wall, cpu] = time_runs(*sim, o, [&] { MPI_Barrier(mpi.comm()); }, mpi.root());
  const double steps = double(o.steps) * o.repeat;  // the counters cover every run
  const double bytes = double(E.sum(E.sent_bytes) - bytes0), msgs = double(E.sum(E.sent_messages) - msgs0);
  const double builds = double(sim->neighbour_list().builds - builds0);
  const double mig = mpi.max(E.migration_seconds - mig0), halo = mpi.max(E.halo_seconds - halo0),
               ref = mpi.max(E.refresh_seconds - ref0), reb = mpi.max(E.rebalance_seconds - reb0);
  const double moved = double(E.sum(E.migrated) - moved0);
  const double owned = double(sim->particles().owned()), ghosts = double(sim->particles().ghosts());
  const double owned_max = mpi.max(owned), ghosts_max = mpi.max(ghosts), ghosts_sum = mpi.sum(ghosts);
  const double cpu_all = mpi.sum(cpu);
  const std::size_t contacts = sim->contact_count();
  const std::uint64_t rebalances = E.rebalances - rebal0;
  if (mpi.root()) {
    const double R = mpi.size();
    const auto parts = E.decomposition->grid().parts;
    std::printf("  rank grid                   %dx%dx%d\n", parts[0], parts[1], parts[2]);
    std::printf("  time per particle-step      %.4g s (%.4g core-s: x ranks x threads)\n", wall / (n * o.steps),
                wall * R * threads() / (n * o.steps));
    std::printf("  sent per step (all ranks)   %.4g bytes in %.4g messages (halo refresh; rebuild steps add "
                "migration and the halo build)\n", bytes / steps, msgs / steps);
    std::printf("  rebuilds                    %.0f (every %.1f steps); migrations %.0f particles\n", builds,
                builds > 0 ? steps / builds : 0.0, moved);
    std::printf("  per rebuild (slowest rank)  migration %.4g s, halo build %.4g s\n", builds > 0 ? mig / builds : 0.0,
                builds > 0 ? halo / builds : 0.0);
    std::printf("  per step (slowest rank)     ghost refresh %.4g s of %.4g s\n", ref / steps, wall / o.steps);
    std::printf("  rebalances                  %lu (%.4g s)\n", (unsigned long)rebalances, reb);
    std::printf("  particles per rank          max %.0f, mean %.0f; ghosts max %.0f, mean %.0f\n", owned_max, n / R,
                ghosts_max, ghosts_sum / R);
    std::printf("summary scene=%c particles=%.0f ranks=%d threads=%d policy=mpi grid=%dx%dx%d steps=%lu wall_s=%.5g "
                "cpu_s=%.5g s_per_particle_step=%.5g contacts=%zu rebuilds_per_run=%.1f bytes_per_step=%.5g "
                "messages_per_step=%.4g migration_s_per_rebuild=%.4g halo_build_s_per_rebuild=%.4g "
                "refresh_s_per_step=%.4g rebalances=%lu rebalance_s=%.4g owned_max=%.0f ghosts_max=%.0f "
                "ghosts_mean=%.1f loadavg=\"%s\"\n",
                s.name, n, mpi.size(), threads(), parts[0], parts[1], parts[2], (unsigned long)o.steps, wall, cpu_all,
                wall / (n * o.steps), contacts, builds / o.repeat, bytes / steps, msgs / steps,
                builds > 0 ? mig / builds : 0.0, builds > 0 ? halo / builds : 0.0, ref / steps,
                (unsigned long)rebalances, reb, owned_max, ghosts_max, ghosts_sum / R, loadavg().c_str());
  }
  return 0;
}

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "bench_mpi_bed: %s\nusage: bench_mpi_bed --data FILE [--scene A|B] [--steps S] [--warmup W] "
               "[--repeat R] [--grid px py pz] [--rebalance T] [--skin M] [--single]\n", why.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string k = argv[a];
    auto next = [&]() -> std::string {
      if (a + 1 >= argc) usage("missing value after " + k);
      return argv[++a];
    };
    try {
      if (k == "--scene") {
        const std::string v = next();
        if (v != "A" && v != "B") usage("--scene must be A or B, got " + v);
        o.scene = v[0];
      } else if (k == "--data") o.data = next();
      else if (k == "--steps") o.steps = std::stoull(next());
      else if (k == "--warmup") o.warmup = std::stoull(next());
      else if (k == "--repeat") o.repeat = std::stoi(next());
      else if (k == "--rebalance") o.threshold = std::stod(next());
      else if (k == "--grid") for (int d = 0; d < 3; ++d) o.grid.parts[d] = std::stoi(next());
      else if (k == "--single") o.single = true;
      else if (k == "--skin") o.skin = std::stod(next());
      else usage("unknown option " + k);
    } catch (const std::logic_error&) {
      usage("bad value for " + k);
    }
  }
  if (o.data.empty()) usage("--data FILE is required (a bed from bench_scene_throughput --prepare)");
  if (o.steps < 1) usage("--steps must be at least 1");
  if (o.repeat < 1) usage("--repeat must be at least 1");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  parallel::MpiContext mpi(argc, argv);
  const Options o = parse(argc, argv);
  return mpi.run([&] {
    const SceneSpec s = granule_bench::make_spec(o.scene);
    const io::LammpsData data = io::read_lammps_data(o.data);
    if (o.single) {
      if (mpi.size() != 1) throw InvalidParameter("bench_mpi_bed: --single runs in one process (mpirun -np 1)");
      return o.scene == 'A' ? run_single<contact::HertzMindlinEpsdSjkr>(s, o, data)
                            : run_single<contact::HertzMindlin>(s, o, data);
    }
    return o.scene == 'A' ? run_distributed<contact::HertzMindlinEpsdSjkr>(s, o, data, mpi)
                          : run_distributed<contact::HertzMindlin>(s, o, data, mpi);
  });
}
