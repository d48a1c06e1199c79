// Contact-law kernels: time of one ContactModel<...>::evaluate for every blessed alias of
// include/granule/contact/model.hpp, in 2D and 3D.
//
// Each benchmark owns a batch of pre-built ContactGeometry objects (what Simulation::pair_geometry
// hands to the model) and one history State per contact. Geometries are drawn like contacts in a
// settled bed: radii 1 mm +- 10 %, overlaps 0.5e-3..1.5e-3 of the smaller radius, random unit
// normals, particle velocities up to 1 mm/s and spins up to 1 rad/s per component, dt = 1e-6 s.
// The batch is evaluated twice per iteration: once with the velocities as drawn and once with
// them reversed, so every spring winds forward and back and the mix of sticking and sliding
// contacts stays stationary however long Google Benchmark runs. Before timing, every contact is
// loaded for a random number (0..499) of forward steps so that some springs sit at their Coulomb
// or rolling limit; the counter `sliding` reports the fraction of contacts whose tangential force
// is at mu_s |F_n| after that warm-up.
//
// Reported: items_per_second = contact evaluations per second (CPU time); time_per_contact =
// its inverse.
// evaluate_packed/3D/<alias> (models with ContactModel::lanes): the same batch evaluated W
// contacts per call over Dim3Lanes (core/lanes.hpp), geometries and histories held packed, i.e.
// the law arithmetic of the engine's packed pair loop without its gather and scatter.
// Argument: evaluations per iteration (half as many distinct contacts, each evaluated forward
// and reversed); 4096 means about 0.8 MB of geometries and history, 65536 about 13 MB.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <granule/granule.hpp>

namespace {

using namespace granule;

/// One material for all laws: scene-B-like elastic constants with friction, rolling and cohesion
/// switched on so that every slot of every alias does real work.
Material kernel_material() {
  Material m;
  m.name = "kernel";
  m.youngs_modulus = 5.0e6;       // [Pa]
  m.poisson_ratio = 0.3;          // [-]
  m.density = 2500.0;             // [kg/m^3]
  m.restitution = 0.5;            // [-]
  m.friction = 0.5;               // [-]
  m.rolling_friction = 0.3;       // [-]
  m.rolling_damping = 0.5;        // [-]
  m.cohesion_energy_density = 1000.0;  // [J/m^3]
  m.normal_stiffness = 1.0e4;     // [N/m] (linear laws: E d for d = 2 mm)
  return m;
}

template <class D>
struct Batch {
  std::vector<contact::ContactGeometry<D>> forward, backward;
};

template <class D>
Batch<D> make_batch(std::size_t n, double thickness, std::uint64_t seed) {
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  const Material mat = kernel_material();
  Batch<D> b;
  b.forward.resize(n);
  b.backward.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    contact::ContactGeometry<D>& g = b.forward[k];
    Vec nrm;
    do {
      for (int c = 0; c < D::dim; ++c) nrm[c] = u(rng);
    } while (nrm.squaredNorm() < 1e-2 || nrm.squaredNorm() > 1.0);
    nrm.normalize();
    const double r_i = 1.0e-3 * (1.0 + 0.1 * u(rng));  // [m]
    const double r_j = 1.0e-3 * (1.0 + 0.1 * u(rng));  // [m]
    const double overlap = (0.5 + u01(rng)) * 1.0e-3 * std::min(r_i, r_j);  // [m]
    const double m_i = mat.density * D::volume(r_i, thickness);
    const double m_j = mat.density * D::volume(r_j, thickness);
    Vec v_i, v_j;
    for (int c = 0; c < D::dim; ++c) {
      v_i[c] = 1.0e-3 * u(rng);
      v_j[c] = 1.0e-3 * u(rng);
    }
    AngVec w_i, w_j;
    if constexpr (D::dim == 2) {
      w_i = 1.0 * u(rng);
      w_j = 1.0 * u(rng);
    } else {
      for (int c = 0; c < 3; ++c) {
        w_i[c] = 1.0 * u(rng);
        w_j[c] = 1.0 * u(rng);
      }
    }
    g.n = nrm;
    g.overlap = overlap;
    g.distance = r_i + r_j - overlap;
    g.r_i = r_i;
    g.r_j = r_j;
    g.arm_i = r_i - 0.5 * overlap;
    g.arm_j = r_j - 0.5 * overlap;
    g.r_eff = r_i * r_j / (r_i + r_j);
    g.m_eff = m_i * m_j / (m_i + m_j);
    g.v_rel = v_i - v_j - (g.arm_i * D::cross(w_i, nrm) + g.arm_j * D::cross(w_j, nrm));
    g.vn = g.v_rel.dot(nrm);
    g.vt = g.v_rel - g.vn * nrm;
    g.omega_rel = w_i - w_j;
    g.damp_at_kinematic_velocity();
    const double k1 = D::inertia_factor + 1.0;
    g.i_roll = 1.0 / (1.0 / (k1 * m_i * r_i * r_i) + 1.0 / (k1 * m_j * r_j * r_j));
    g.dt = 1.0e-6;  // [s]

    contact::ContactGeometry<D>& h = b.backward[k];
    h = g;
    h.v_rel = -g.v_rel;
    h.vn = -g.vn;
    h.vt = -g.vt;
    h.omega_rel = -g.omega_rel;
    h.damp_at_kinematic_velocity();
  }
  return b;
}

// One pass over a batch. `flatten` inlines the whole law into the loop, as it is inlined into the
// engine's pair loop; without it GCC keeps evaluate() and its slots out of line in this large
// translation unit (16 instantiations) and the timing would include call overhead.
template <class D, class Model>
[[gnu::flatten]] void sweep(const typename Model::Params& prm,
                            const std::vector<contact::ContactGeometry<D>>& geometry,
                            std::vector<typename Model::template State<D>>& states,
                            typename D::Vec& force_sum, typename D::AngVec& torque_sum) {
  for (std::size_t k = 0; k < geometry.size(); ++k) {
    const contact::ContactForce<D> f = Model::evaluate(prm, geometry[k], states[k]);
    force_sum += f.force;
    torque_sum += f.torque_i;
  }
}

/// Histories after loading the springs: contact k sees 0..499 forward steps before timing.
template <class D, class Model>
std::vector<typename Model::template State<D>> loaded_states(const typename Model::Params& prm, const Batch<D>& batch) {
  std::vector<typename Model::template State<D>> states(batch.forward.size());
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> loads(0, 499);
  for (std::size_t k = 0; k < states.size(); ++k) {
    const int nload = loads(rng);
    for (int s = 0; s < nload; ++s) benchmark::DoNotOptimize(Model::evaluate(prm, batch.forward[k], states[k]));
  }
  return states;
}

template <class D, class Model>
void bm_evaluate(benchmark::State& st) {
  using State = typename Model::template State<D>;
  const std::size_t half = static_cast<std::size_t>(st.range(0)) / 2;
  const double thickness = 2.0e-3;  // [m] 2D disk thickness
  const Material mat = kernel_material();
  const typename Model::Params prm = Model::make(mix(mat, mat), thickness);
  const Batch<D> batch = make_batch<D>(half, thickness, 20240611);
  std::vector<State> states = loaded_states<D, Model>(prm, batch);
  std::size_t sliding = 0;
  {
    std::vector<State> probe = states;
    for (std::size_t k = 0; k < half; ++k) {
      const auto f = Model::evaluate(prm, batch.forward[k], probe[k]);
      const double limit = mix(mat, mat).mu_s * std::abs(f.fn);
      if (f.ft.norm() >= (1.0 - 1e-9) * limit && f.ft.norm() > 0.0) ++sliding;
    }
  }

  for (auto _ : st) {
    typename D::Vec force_sum = D::zero();
    typename D::AngVec torque_sum = D::zero_ang();
    sweep<D, Model>(prm, batch.forward, states, force_sum, torque_sum);
    sweep<D, Model>(prm, batch.backward, states, force_sum, torque_sum);
    benchmark::DoNotOptimize(force_sum);
    benchmark::DoNotOptimize(torque_sum);
    benchmark::ClobberMemory();
  }
  const double per_iter = static_cast<double>(2 * half);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations()) * static_cast<std::int64_t>(2 * half));
  st.counters["time_per_contact"] = benchmark::Counter(
      per_iter, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["sliding"] = static_cast<double>(sliding) / static_cast<double>(half);
  st.counters["state_bytes"] = static_cast<double>(Model::template has_state<D> ? sizeof(State) : 0);
}

/// Packs W scalar geometries (lanes k..k+W-1 of `g`) into one Dim3Lanes geometry.
contact::ContactGeometry<Dim3Lanes> pack(const std::vector<contact::ContactGeometry<Dim3>>& g, std::size_t k) {
  contact::GeometryLanes lanes;
  for (std::size_t l = 0; l < lane_width; ++l) lanes.set(l, g[k + l]);
  return lanes.packed();
}

template <class Model>
[[gnu::flatten]] void sweep_packed(const typename Model::Params& prm,
                                   const std::vector<contact::ContactGeometry<Dim3Lanes>>& geometry,
                                   std::vector<typename Model::template State<Dim3Lanes>>& states,
                                   LaneVec3& force_sum, LaneVec3& torque_sum) {
  for (std::size_t k = 0; k < geometry.size(); ++k) {
    const contact::ContactForce<Dim3Lanes> f = Model::evaluate(prm, geometry[k], states[k]);
    force_sum += f.force;
    torque_sum += f.torque_i;
  }
}

template <class Model>
void bm_evaluate_packed(benchmark::State& st) {
  using State = typename Model::template State<Dim3>;
  using PackedState = typename Model::template State<Dim3Lanes>;
  const std::size_t half = static_cast<std::size_t>(st.range(0)) / 2;
  const Material mat = kernel_material();
  const typename Model::Params prm = Model::make(mix(mat, mat), 1.0);
  const Batch<Dim3> batch = make_batch<Dim3>(half, 1.0, 20240611);
  // The same warm-up as the scalar benchmark, then the loaded histories are packed.
  const std::vector<State> states = loaded_states<Dim3, Model>(prm, batch);
  std::vector<contact::ContactGeometry<Dim3Lanes>> forward, backward;
  std::vector<PackedState> packed(half / lane_width);
  for (std::size_t k = 0; k + lane_width <= half; k += lane_width) {
    forward.push_back(pack(batch.forward, k));
    backward.push_back(pack(batch.backward, k));
    if constexpr (Model::template has_state<Dim3>) {
      const State* slots[lane_width];
      for (std::size_t l = 0; l < lane_width; ++l) slots[l] = &states[k + l];
      contact::PackedState<State, PackedState>::load(packed[k / lane_width], slots);
    }
  }
  for (auto _ : st) {
    LaneVec3 force_sum = Dim3Lanes::zero(), torque_sum = Dim3Lanes::zero();
    sweep_packed<Model>(prm, forward, packed, force_sum, torque_sum);
    sweep_packed<Model>(prm, backward, packed, force_sum, torque_sum);
    benchmark::DoNotOptimize(force_sum);
    benchmark::DoNotOptimize(torque_sum);
    benchmark::ClobberMemory();
  }
  const double per_iter = static_cast<double>(2 * forward.size() * lane_width);
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations()) * static_cast<std::int64_t>(per_iter));
  st.counters["time_per_contact"] = benchmark::Counter(
      per_iter, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  st.counters["lanes"] = static_cast<double>(lane_width);
}

template <class Model>
void register_model(const std::string& name) {
  for (const long batch : {4096L, 65536L}) {
    benchmark::RegisterBenchmark(("evaluate/2D/" + name).c_str(), bm_evaluate<Dim2, Model>)->Arg(batch);
    benchmark::RegisterBenchmark(("evaluate/3D/" + name).c_str(), bm_evaluate<Dim3, Model>)->Arg(batch);
    if constexpr (Model::lanes)
      benchmark::RegisterBenchmark(("evaluate_packed/3D/" + name).c_str(), bm_evaluate_packed<Model>)->Arg(batch);
  }
}

const bool registered = [] {
  register_model<contact::LinearFrictionless>("LinearFrictionless");
  register_model<contact::LinearSpringDashpot>("LinearSpringDashpot");
  register_model<contact::HertzFrictionless>("HertzFrictionless");
  register_model<contact::HertzMindlin>("HertzMindlin");
  register_model<contact::HertzMindlinIncremental>("HertzMindlinIncremental");
  register_model<contact::HertzMindlinNonTensile>("HertzMindlinNonTensile");
  register_model<contact::HertzMindlinLegacy>("HertzMindlinLegacy");
  register_model<contact::HertzMindlinEpsd>("HertzMindlinEpsd");
  register_model<contact::HertzMindlinEpsdSjkr>("HertzMindlinEpsdSjkr");
  register_model<contact::LinearCoulombRolling>("LinearCoulombRolling");
  return true;
}();

}  // namespace
