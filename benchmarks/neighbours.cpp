// Neighbour search: cost of building the list, and the per-step cost as a function of the skin.
//
// Packing: a settled random bed read from the LAMMPS data file named by the environment variable
// GRANULE_BENCH_BED (e.g. the scene-B bed written by bench_scene_throughput --prepare; box and
// radii from the file). Without it: 19 652 spheres of d = 2 mm (17^3 face-centred cubic cells)
// with nearest-neighbour distance 1.0726 d, i.e. packing fraction 0.60, each centre jittered by
// +-0.018 d per coordinate (no initial overlap; its neighbour shells are sharp, so the list
// length jumps with the skin instead of growing smoothly as in a random bed). The counter `bed`
// is 1 for the data file, 0 for the lattice. Material and time step of scene B (paper 000:
// E = 5 MPa, nu = 0.3, rho = 1100 kg/m^3, e = 0.2, mu = 0.5, dt = 5e-6 s), contact model
// contact::HertzMindlin; skins are given in % of d = 2 mm.
//
//   rebuild/<search>/skin_pct_d:<s>/threads:<t>     (skin = s % of d)
//       one Simulation::rebuild() (spatial sort, ghosts, rows, history transfer, layer split) on
//       the packing at rest in a closed box without walls; items = particles, so
//       time_per_particle is the build cost per particle.
//   step_vs_skin/<search>/skin_pct_d:<s>/threads:1
//       a 400-step run of the same packing in a fully periodic box (no gravity, no walls), every
//       particle drifting at 0.2 m/s along (1,1,1)/sqrt(3) plus random velocities of 0.01 m/s
//       rms (a gently moving bed: the drift, 1e-6 m per step, sets how often the Verlet list
//       must be rebuilt).
//       items = particle-steps; counters: rebuilds in the run, list entries and contacts per
//       particle. The skin trades list length (pair-loop work every step) against rebuild
//       frequency; LinkedCells is the skin-0, rebuild-every-step end of that trade.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/granule.hpp>
#include <granule/io/lammps_data.hpp>

namespace {

using namespace granule;
using Vec = Dim3::Vec;

constexpr double kDiameter = 2.0e-3;  // [m]
constexpr int kCells = 17;            // FCC cells per side

Material bed_material() {
  Material m;
  m.name = "scene B";
  m.youngs_modulus = 5.0e6;  // [Pa]
  m.poisson_ratio = 0.3;     // [-]
  m.density = 1100.0;        // [kg/m^3]
  m.restitution = 0.2;       // [-]
  m.friction = 0.5;          // [-]
  return m;
}

struct Packing {
  std::vector<Vec> x;
  std::vector<double> radius;  // [m]
  Vec lo = Vec::Zero(), hi = Vec::Zero();  // [m] box
  bool from_file = false;
};

const Packing& packing() {
  static const Packing pk = [] {
    Packing p;
    if (const char* file = std::getenv("GRANULE_BENCH_BED"); file != nullptr && *file != '\0') {
      const io::LammpsData data = io::read_lammps_data(file);
      p.x = data.frame.x;
      p.radius = data.frame.radius;
      p.lo = data.frame.box_lo;
      p.hi = data.frame.box_hi;
      p.from_file = true;
      return p;
    }
    const double a_nn = kDiameter * std::cbrt(0.74048 / 0.60);  // [m] nearest-neighbour distance
    const double a = a_nn * std::sqrt(2.0);                     // [m] cubic cell
    p.hi = Vec::Constant(kCells * a);
    const Vec basis[4] = {Vec(0.25, 0.25, 0.25), Vec(0.75, 0.75, 0.25), Vec(0.75, 0.25, 0.75),
                          Vec(0.25, 0.75, 0.75)};
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < kCells; ++k)
      for (int j = 0; j < kCells; ++j)
        for (int i = 0; i < kCells; ++i)
          for (const Vec& b : basis) {
            Vec x = a * (Vec(i, j, k) + b);
            for (int c = 0; c < 3; ++c) x[c] += 0.018 * kDiameter * u(rng);
            p.x.push_back(x);
            p.radius.push_back(0.5 * kDiameter);
          }
    return p;
  }();
  return pk;
}

template <class Search>
std::unique_ptr<Simulation<Dim3, contact::HertzMindlin, Search>> make_bed(double skin, bool periodic,
                                                                          double drift) {
  const Packing& pk = packing();
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = pk.lo;
  cfg.domain.hi = pk.hi;
  cfg.domain.periodic.setConstant(periodic);
  cfg.dt = 5.0e-6;  // [s]
  cfg.skin = skin;
  auto sim = std::make_unique<Simulation<Dim3, contact::HertzMindlin, Search>>(cfg);
  const std::uint32_t mat = sim->add_material(bed_material());
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 0.01 / std::sqrt(3.0));
  const Vec v_drift = drift * Vec::Ones().normalized();
  for (std::size_t i = 0; i < pk.x.size(); ++i)
    sim->add_particle(pk.x[i], pk.radius[i], mat, Vec(v_drift + Vec(g(rng), g(rng), g(rng))));
  return sim;
}

void set_threads(int t) {
#ifdef _OPENMP
  omp_set_num_threads(t);
#else
  (void)t;
#endif
}

template <class Search>
void bm_rebuild(benchmark::State& st) {
  const double skin = static_cast<double>(st.range(0)) * 0.01 * kDiameter;  // arg: skin in % of d
  set_threads(static_cast<int>(st.range(1)));
  auto sim = make_bed<Search>(Search::rebuild_every_step ? 0.0 : skin, false, 0.0);
  sim->rebuild();
  for (auto _ : st) sim->rebuild();
  const double n = static_cast<double>(sim->particles().owned());
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * n));
  st.counters["time_per_particle"] =
      benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["entries_per_particle"] = static_cast<double>(sim->neighbour_list().entries()) / n;
  st.counters["bed"] = packing().from_file ? 1.0 : 0.0;
  set_threads(1);
}

template <class Search>
void bm_step_vs_skin(benchmark::State& st) {
  const double skin = static_cast<double>(st.range(0)) * 0.01 * kDiameter;
  set_threads(static_cast<int>(st.range(1)));
  constexpr std::uint64_t kSteps = 400;
  auto sim = make_bed<Search>(Search::rebuild_every_step ? 0.0 : skin, true, 0.2);
  sim->run(10);
  std::size_t builds = 0;
  for (auto _ : st) {
    const std::size_t b0 = sim->neighbour_list().builds;
    sim->run(kSteps);
    builds += sim->neighbour_list().builds - b0;
  }
  const double n = static_cast<double>(sim->particles().owned());
  const double per_iter = n * static_cast<double>(kSteps);
  st.SetItemsProcessed(static_cast<std::int64_t>(static_cast<double>(st.iterations()) * per_iter));
  st.counters["time_per_particle_step"] =
      benchmark::Counter(per_iter, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["rebuilds_per_400_steps"] = static_cast<double>(builds) / static_cast<double>(st.iterations());
  st.counters["entries_per_particle"] = static_cast<double>(sim->neighbour_list().entries()) / n;
  st.counters["contacts_per_particle"] = static_cast<double>(sim->contact_count()) / n;
  st.counters["bed"] = packing().from_file ? 1.0 : 0.0;
  set_threads(1);
}

const bool registered = [] {
  // Build cost. Args: skin in % of d, threads. CPU time for 1 thread, wall time for 2.
  benchmark::RegisterBenchmark("rebuild/LinkedCells", bm_rebuild<neighbours::LinkedCells>)
      ->ArgNames({"skin_pct_d", "threads"})
      ->Args({0, 1})
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("rebuild/LinkedCells", bm_rebuild<neighbours::LinkedCells>)
      ->ArgNames({"skin_pct_d", "threads"})
      ->Args({0, 2})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  for (const long skin : {5L, 10L, 20L, 40L}) {
    benchmark::RegisterBenchmark("rebuild/VerletList", bm_rebuild<neighbours::VerletList>)
        ->ArgNames({"skin_pct_d", "threads"})
        ->Args({skin, 1})
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("rebuild/VerletList", bm_rebuild<neighbours::VerletList>)
      ->ArgNames({"skin_pct_d", "threads"})
      ->Args({10, 2})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);

  // Per-step cost against the skin (single thread, one 400-step run per measurement).
  benchmark::RegisterBenchmark("step_vs_skin/LinkedCells", bm_step_vs_skin<neighbours::LinkedCells>)
      ->ArgNames({"skin_pct_d", "threads"})
      ->Args({0, 1})
      ->Iterations(1)
      ->Unit(benchmark::kMillisecond);
  for (const long skin : {2L, 5L, 10L, 20L, 40L}) {
    benchmark::RegisterBenchmark("step_vs_skin/VerletList", bm_step_vs_skin<neighbours::VerletList>)
        ->ArgNames({"skin_pct_d", "threads"})
        ->Args({skin, 1})
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
