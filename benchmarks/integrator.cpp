// Cost of a step without contacts: the velocity-Verlet kicks and drift, force reset (gravity),
// the rebuild test, the empty pair and wall loops, and the finite-value check -- the floor under
// every scene's time per particle-step.
//
// Particles of d = 2 mm sit on a simple-cubic lattice of spacing 4 d (no pair within the
// interaction range 2 r + skin), at rest, without gravity, so the list is never rebuilt after the
// first step. Arguments: particle count, OpenMP threads. Items = particle-steps;
// time_per_particle_step is its inverse. One thread: CPU time; two threads: wall time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/granule.hpp>

namespace {

using namespace granule;

template <class D, class Model>
void bm_free_step(benchmark::State& st) {
  using Vec = typename D::Vec;
  const auto n = static_cast<std::size_t>(st.range(0));
#ifdef _OPENMP
  omp_set_num_threads(static_cast<int>(st.range(1)));
#endif
  const double d = 2.0e-3;    // [m]
  const double spacing = 4.0 * d;
  const auto side = static_cast<std::size_t>(std::ceil(std::pow(static_cast<double>(n), 1.0 / D::dim)));
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(static_cast<double>(side) * spacing);
  cfg.dt = 5.0e-6;  // [s]
  cfg.thickness = d;
  Material m;
  m.youngs_modulus = 5.0e6;  // [Pa]
  m.poisson_ratio = 0.3;     // [-]
  m.density = 1100.0;        // [kg/m^3]
  m.restitution = 0.2;       // [-]
  m.friction = 0.5;          // [-]
  m.rolling_friction = 0.1;  // [-]
  m.reference_length = d;    // [m] linear laws: k_n = E d
  Simulation<D, Model> sim(cfg);
  const std::uint32_t mat = sim.add_material(m);
  for (std::size_t i = 0; i < n; ++i) {
    Vec x;
    std::size_t rest = i;
    for (int k = 0; k < D::dim; ++k) {
      x[k] = (static_cast<double>(rest % side) + 0.5) * spacing;
      rest /= side;
    }
    sim.add_particle(x, 0.5 * d, mat);
  }
  sim.run(2);
  for (auto _ : st) sim.step();
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations()) * static_cast<std::int64_t>(n));
  st.counters["time_per_particle_step"] = benchmark::Counter(
      static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["rebuilds"] = static_cast<double>(sim.neighbour_list().builds);
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
}

const bool registered = [] {
  for (const long n : {1000L, 20000L, 100000L}) {
    benchmark::RegisterBenchmark("free_step/3D/HertzMindlin", bm_free_step<Dim3, contact::HertzMindlin>)
        ->ArgNames({"n", "threads"})
        ->Args({n, 1})
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("free_step/3D/HertzMindlin", bm_free_step<Dim3, contact::HertzMindlin>)
        ->ArgNames({"n", "threads"})
        ->Args({n, 2})
        ->UseRealTime()
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("free_step/2D/LinearCoulombRolling",
                                 bm_free_step<Dim2, contact::LinearCoulombRolling>)
        ->ArgNames({"n", "threads"})
        ->Args({n, 1})
        ->Unit(benchmark::kMicrosecond);
  }
  return true;
}();

}  // namespace
