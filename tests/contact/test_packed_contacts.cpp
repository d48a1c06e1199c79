// Packed contacts (core/lanes.hpp, contact/packed.hpp): the laws evaluated W contacts at a time
// must give what they give one contact at a time.
//
// Reference: the scalar evaluation itself (ContactModel<...>::evaluate with ContactGeometry<Dim3>),
// which the physics tests of tests/contact check against analytic results. The packed form runs
// the same law templates over Lane instead of double, so the two agree to rounding: the only
// differences allowed are FMA contractions and the order of a few additions, i.e. a relative
// 1e-12 on every force, torque and history component. A wrong blend (a branch taken in the
// wrong lanes), a lane mix-up in the history gather/scatter or a geometry term built
// differently shows up as an O(1) difference.
#include <catch2/catch.hpp>

#include <array>
#include <cstring>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <granule/granule.hpp>

using namespace granule;

namespace {

using Vec = Eigen::Vector3d;
constexpr std::size_t W = lane_width;

double uniform(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

Vec random_unit(std::mt19937_64& rng) {
  Vec v;
  do {
    v = Vec(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
  } while (v.squaredNorm() > 1.0 || v.squaredNorm() < 1e-4);
  return v.normalized();
}

/// Relative difference with a floor: |a - b| / max(|a|, |b|, scale).
double rel(double a, double b, double scale) { return std::abs(a - b) / std::max({std::abs(a), std::abs(b), scale}); }

/// A pair of spheres in contact: centre distance, relative velocity, spins, radii, 1/m.
struct PairInput {
  Vec d, dv, wi, wj;
  double ri, rj, inv_mi, inv_mj;
};

PairInput random_pair(std::mt19937_64& rng, double r, double speed) {
  PairInput in;
  in.ri = r * uniform(rng, 0.7, 1.3);
  in.rj = r * uniform(rng, 0.7, 1.3);
  const double overlap = uniform(rng, 1e-4, 2e-2) * std::min(in.ri, in.rj);
  in.d = (in.ri + in.rj - overlap) * random_unit(rng);
  in.dv = speed * uniform(rng, 0.0, 1.0) * random_unit(rng);
  in.wi = (speed / r) * uniform(rng, 0.0, 1.0) * random_unit(rng);
  in.wj = (speed / r) * uniform(rng, 0.0, 1.0) * random_unit(rng);
  const double rho = 2500.0;  // [kg/m^3]
  in.inv_mi = 1.0 / (rho * Dim3::volume(in.ri, 1.0));
  in.inv_mj = uniform(rng, 0, 1) < 0.2 ? 0.0 : 1.0 / (rho * Dim3::volume(in.rj, 1.0));  // some frozen
  return in;
}

/// The scalar geometry of one pair, written out as Simulation::pair_geometry builds it.
template <class Model>
contact::ContactGeometry<Dim3> scalar_geometry(const PairInput& in, double dt) {
  contact::ContactGeometry<Dim3> g;
  const double rs = in.ri + in.rj;
  const double dist = in.d.norm();
  g.distance = dist;
  g.n = in.d / dist;
  g.overlap = rs - dist;
  g.r_i = in.ri;
  g.r_j = in.rj;
  g.arm_i = g.r_i - 0.5 * g.overlap;
  g.arm_j = g.r_j - 0.5 * g.overlap;
  g.r_eff = g.r_i * g.r_j / rs;
  g.m_eff = 1.0 / (in.inv_mi + in.inv_mj);
  g.v_rel = in.dv - (g.arm_i * in.wi.cross(g.n) + g.arm_j * in.wj.cross(g.n));
  g.vn = g.v_rel.dot(g.n);
  g.vt = g.v_rel - g.vn * g.n;
  g.omega_rel = in.wi - in.wj;
  g.damp_at_kinematic_velocity();
  const double k1 = Dim3::inertia_factor + 1.0;
  g.i_roll = Model::needs_rolling_inertia
                 ? 1.0 / (in.inv_mi / (k1 * g.r_i * g.r_i) + in.inv_mj / (k1 * g.r_j * g.r_j))
                 : 0.0;
  g.dt = dt;
  g.twist = Model::needs_twist ? 0.5 * (in.wi + in.wj).dot(g.n) * dt : 0.0;
  return g;
}

template <class Model>
using StoredState = typename Model::template State<Dim3>;

/// A history as a contact that has been loaded for a while would carry: random, with a spring
/// force up to twice the Coulomb limit (so some lanes slide, some stick), a previous stiffness
/// above or below the current one (unloading or not) and a rolling spring up to twice its limit.
/// `fresh` leaves it empty (a new contact).
template <class Model>
StoredState<Model> random_state(std::mt19937_64& rng, const contact::ContactGeometry<Dim3>& g,
                                const typename Model::Params& prm, bool fresh) {
  StoredState<Model> s{};
  if (fresh) return s;
  const auto nr = Model::NormalLaw::eval(prm.normal, g);
  const double fn = std::abs(nr.fn) + 1e-3 * nr.fn_elastic;
  if constexpr (requires { s.tangential.fs; }) {
    s.tangential.fs = uniform(rng, 0.0, 2.0) * 0.5 * fn * random_unit(rng);
    double gamma = 0.0;
    const double kt = Model::TangentialLaw::StiffnessLaw::eval(prm.tangential.stiffness, g, nr, gamma);
    s.tangential.kt_old = kt * uniform(rng, 0.8, 1.25);
  }
  if constexpr (requires { s.tangential.xi; }) {  // displacement history, up to twice the limit
    double gamma = 0.0;
    const double kt = Model::TangentialLaw::StiffnessLaw::eval(prm.tangential.stiffness, g, nr, gamma);
    s.tangential.xi = uniform(rng, 0.0, 2.0) * 0.5 * fn / kt * random_unit(rng);
  }
  if constexpr (requires { s.rolling.m_roll; }) {
    // Up to twice the limit, split into its tangent-plane and normal parts.
    const Eigen::Vector3d m = uniform(rng, 0.0, 2.0) * 0.5 * g.r_eff * fn * random_unit(rng);
    s.rolling.m_twist = m.dot(g.n);
    s.rolling.m_roll = m - s.rolling.m_twist * g.n;
  }
  if constexpr (requires { s.rolling.theta; }) {  // SDS rolling angle, up to twice the limit
    const Eigen::Vector3d t = random_unit(rng);
    const double kr = contact::SdsRolling::stiffness(prm.rolling, g.r_eff);
    s.rolling.theta = uniform(rng, 0.0, 2.0) * prm.rolling.mu_r * g.r_eff * fn / kr * (t - t.dot(g.n) * g.n).normalized();
  }
  return s;
}

template <class Model>
std::vector<double> state_doubles(const StoredState<Model>& s) {
  if constexpr (!Model::template has_state<Dim3>) return {};
  std::vector<double> v(sizeof(s) / sizeof(double));
  std::memcpy(v.data(), static_cast<const void*>(&s), sizeof(s));
  return v;
}

/// Friction, rolling resistance and cohesion switched on, so that every slot of every packed
/// model does real work.
Material test_material(double youngs_modulus, double rolling_friction, double cohesion) {
  Material m;
  m.youngs_modulus = youngs_modulus;  // [Pa]
  m.poisson_ratio = 0.3;
  m.density = 2500.0;  // [kg/m^3]
  m.restitution = 0.5;
  m.friction = 0.5;
  m.rolling_friction = rolling_friction;
  m.rolling_damping = 0.3;
  m.cohesion_energy_density = cohesion;  // [J/m^3]
  m.normal_stiffness = 1e4;              // [N/m] (linear laws)
  m.rolling_stiffness = 50.0;            // [N/m] (SDS rolling)
  return m;
}

template <class Model>
void check_packed_against_scalar(double dt, std::uint64_t seed) {
  using Chunk = contact::PairChunk<64>;
  using PackedState = typename Model::template State<Dim3Lanes>;
  const Material m = test_material(5e6, 0.4, 1000.0);
  const auto prm = Model::make(mix(m, m));
  std::mt19937_64 rng(seed);
  auto chunk = std::make_unique<Chunk>();
  std::vector<PairInput> inputs;
  std::vector<StoredState<Model>> states;
  // Particle arrays as the engine's store holds them: pair c is particle 2c (i, at x = d,
  // moving at dv) against particle 2c + 1 (j, at rest at the origin), so x_i - x_j = d exactly.
  std::vector<Vec> x, v, w;
  std::vector<double> radius, inv_mass;
  const double r = 1e-3;
  for (std::size_t c = 0; c < Chunk::capacity - 3; ++c) {  // the last pack is padded
    const PairInput in = random_pair(rng, r, c % 3 == 0 ? 0.01 : 1.0);
    inputs.push_back(in);
    const auto g = scalar_geometry<Model>(in, dt);
    states.push_back(random_state<Model>(rng, g, prm, c % 5 == 0));
    x.insert(x.end(), {in.d, Vec::Zero()});
    v.insert(v.end(), {in.dv, Vec::Zero()});
    w.insert(w.end(), {in.wi, in.wj});
    radius.insert(radius.end(), {in.ri, in.rj});
    inv_mass.insert(inv_mass.end(), {in.inv_mi, in.inv_mj});
    chunk->i[c] = static_cast<std::uint32_t>(2 * c);
    chunk->j[c] = static_cast<std::uint32_t>(2 * c + 1);
    chunk->history[c] = static_cast<std::uint32_t>(c);
    ++chunk->count;
  }
  const contact::PackedParticles particles{x.data()->data(), v.data()->data(), w.data()->data(),
                                           radius.data(), inv_mass.data()};
  chunk->pad();
  std::vector<StoredState<Model>> packed_states = states;
  packed_states.resize(Chunk::capacity, StoredState<Model>{});
  std::size_t sliding = 0, unloading = 0, fresh = 0, mobilised = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < chunk->count; k += W) {
    const std::size_t valid = std::min(W, chunk->count - k);
    contact::ContactGeometry<Dim3Lanes> g;
    chunk->template geometry<Model::needs_rolling_inertia, Model::needs_twist>(k, particles, dt, g);
    PackedState s{};
    StoredState<Model>* slots[W];
    for (std::size_t q = 0; q < W; ++q) slots[q] = &packed_states[chunk->history[k + q]];
    if constexpr (Model::template has_state<Dim3>) contact::PackedState<StoredState<Model>, PackedState>::load(s, slots);
    const auto cf = Model::evaluate(prm, g, s);
    if constexpr (Model::template has_state<Dim3>)
      contact::PackedState<StoredState<Model>, PackedState>::store(s, slots, valid);
    for (std::size_t q = 0; q < valid; ++q) {
      const std::size_t c = k + q;
      const auto gs = scalar_geometry<Model>(inputs[c], dt);
      StoredState<Model> ss = states[c];
      const auto before = state_doubles<Model>(ss);
      if constexpr (requires { ss.rolling.theta; }) {  // the SDS slider holds |M| at its limit
        auto probe = ss.rolling;
        const auto nr = Model::NormalLaw::eval(prm.normal, gs);
        const double mmax = prm.rolling.mu_r * gs.r_eff * std::abs(nr.fn);
        if (contact::SdsRolling::eval(prm.rolling, gs, nr, probe).norm() >= (1.0 - 1e-12) * mmax && mmax > 0.0)
          ++mobilised;
      }
      const auto cs = Model::evaluate(prm, gs, ss);
      // Which branches this contact took (so the test proves it covered them).
      if constexpr (requires { ss.tangential.fs; }) {
        if (before[3] == 0.0) ++fresh;
        const double limit = prm.tangential.mu_s * std::abs(cs.fn);
        if (cs.ft.norm() > (1.0 - 1e-12) * limit && limit > 0.0) ++sliding;
        double gamma = 0.0;
        if (Model::TangentialLaw::StiffnessLaw::eval(prm.tangential.stiffness, gs, contact::NormalResult{}, gamma) < before[3]) ++unloading;
      }
      if constexpr (requires { ss.tangential.xi; }) {
        if (before[0] == 0.0 && before[1] == 0.0 && before[2] == 0.0) ++fresh;
        const double limit = prm.tangential.mu_s * std::abs(cs.fn);
        if (cs.ft.norm() > (1.0 - 1e-12) * limit && limit > 0.0) ++sliding;
      }
      if constexpr (requires { ss.rolling.m_roll; }) {
        const double mmax = prm.rolling.mu_r * gs.r_eff * std::abs(cs.fn);
        const double m = std::sqrt(contact::EpsdRolling::squared_norm<Dim3>(ss.rolling));
        if (m >= (1.0 - 1e-12) * mmax && mmax > 0.0) ++mobilised;
      }
      const double fscale = 1e-12 * std::max(std::abs(cs.fn), 1e-30);
      const double tscale = fscale * r;
      const double packed_f[3] = {cf.force.x[q], cf.force.y[q], cf.force.z[q]};
      const double packed_ti[3] = {cf.torque_i.x[q], cf.torque_i.y[q], cf.torque_i.z[q]};
      const double packed_tj[3] = {cf.torque_j.x[q], cf.torque_j.y[q], cf.torque_j.z[q]};
      for (int a = 0; a < 3; ++a) {
        worst = std::max(worst, rel(packed_f[a], cs.force[a], std::abs(cs.fn) * 1e-9));
        CHECK(std::abs(packed_f[a] - cs.force[a]) <= 1e-12 * cs.force.norm() + fscale);
        CHECK(std::abs(packed_ti[a] - cs.torque_i[a]) <= 1e-12 * cs.torque_i.norm() + tscale);
        CHECK(std::abs(packed_tj[a] - cs.torque_j[a]) <= 1e-12 * cs.torque_j.norm() + tscale);
      }
      CHECK(std::abs(cf.fn[q] - cs.fn) <= 1e-12 * std::abs(cs.fn));
      const auto after_scalar = state_doubles<Model>(ss);
      const auto after_packed = state_doubles<Model>(packed_states[c]);
      // Absolute floor 1e-20 (m, N or N m): with FMA the packed geometry gives a v_t of ~1e-17 m/s
      // where the scalar one gives exactly 0, so a spring displacement that stays exactly 0 in the
      // scalar law carries ~5e-23 m in the packed one (measured; 2D test alike).
      for (std::size_t a = 0; a < after_scalar.size(); ++a) {
        INFO("contact " << c << ", history double " << a);
        CHECK(std::abs(after_packed[a] - after_scalar[a]) <=
              1e-12 * std::abs(after_scalar[a]) + 1e-12 * std::abs(before[a]) + 1e-20);
      }
    }
  }
  // The padded lanes of the last pack must not have been written back.
  for (std::size_t c = chunk->count; c < Chunk::capacity; ++c)
    CHECK(state_doubles<Model>(packed_states[c]) == state_doubles<Model>(StoredState<Model>{}));
  INFO("lanes " << W << ": " << chunk->count << " contacts, sliding " << sliding << ", unloading "
                << unloading << ", fresh " << fresh << ", rolling mobilised " << mobilised
                << ", worst relative force difference " << worst);
  if constexpr (requires(StoredState<Model> s) { s.tangential.fs; }) {
    if (dt > 0.0) {
      CHECK(sliding >= 3);
      CHECK(sliding + 3 <= chunk->count);
      CHECK(unloading >= 3);
    }
    CHECK(fresh >= 3);
  }
  if constexpr (requires(StoredState<Model> s) { s.tangential.xi; }) {
    if (dt > 0.0) {
      CHECK(sliding >= 3);
      CHECK(sliding + 3 <= chunk->count);
    }
    CHECK(fresh >= 3);
  }
  if constexpr (requires(StoredState<Model> s) { s.rolling.m_roll; } ||
                requires(StoredState<Model> s) { s.rolling.theta; }) {
    if (dt > 0.0) {
      CHECK(mobilised >= 3);
      CHECK(mobilised + 3 <= chunk->count);
    }
  }
}

struct ColumnResult {
  std::vector<Vec> x, v;
  std::size_t contacts = 0;
  Vec lid_force = Vec::Zero(), lid_torque = Vec::Zero();  ///< on the moving lid, last step [N], [N m]
};

constexpr double kPackedR = 1.0e-3;  // [m]

/// ~1000 spheres (radii 0.8-1.2 kPackedR) on a jittered lattice 2.1 kPackedR apart, random velocities up to
/// 0.3 m/s, gravity, walls on every face; `steps` steps of 1e-5 s.
/// `two_materials`: every other sphere of a second, stiffer material, so that chunks mix
/// material pairs and flush on every change (with one material they never do).
/// `box_container`: the four sides and the floor are the faces of one BoxContainerShape (its
/// top face far above the lid) instead of five planes: the general wall walk (shape dispatch,
/// a history slot per face, touch marks) instead of the planes' own path, in the same order.
template <class Model>
ColumnResult run_column(bool packed, std::size_t steps, bool two_materials = false, bool box_container = false) {
  SimulationConfig<Dim3> cfg;
  const Vec len(8 * 2.1e-3, 8 * 2.1e-3, 16 * 2.1e-3);
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = len;
  cfg.dt = 1e-5;
  // 1.15x the EPSD rotational limit of this column (8.7e-6 s, rolling_stability_limit): the
  // test compares two evaluations of the same 150 steps, not their stability.
  cfg.check_rolling_stability = false;
  cfg.gravity = Vec(0.0, 0.0, -100.0);  // [m/s^2]
  cfg.packed_contacts = packed;
  Simulation<Dim3, Model> sim(cfg);
  const Material m = test_material(1e7, 0.3, 2e4);
  const auto mat = sim.add_material(m);
  const auto mat2 = two_materials ? sim.add_material(test_material(1.5e7, 0.3, 2e4)) : mat;
  const auto wmat = sim.add_wall_material(m);
  if (box_container) {
    sim.add_wall(geometry::BoxContainerShape<Dim3>(Vec::Zero(), Vec(len.x(), len.y(), 3.0 * len.z())), wmat);
  } else {
    for (int k = 0; k < 2; ++k) {
      sim.add_wall(geometry::PlaneShape<Dim3>(Vec::Zero(), Vec::Unit(k)), wmat);
      sim.add_wall(geometry::PlaneShape<Dim3>(len, Vec(-Vec::Unit(k))), wmat);
    }
    sim.add_wall(geometry::PlaneShape<Dim3>(Vec::Zero(), Vec::UnitZ()), wmat);
  }
  // The lid is a body that sinks and spins about the column's axis: wall velocities at the
  // contact points, and the force and torque on a body, go through the packed path too.
  Body<Dim3> lid;
  lid.name = "lid";
  lid.pose = geometry::Pose<Dim3>::translation(Vec(0.5 * len.x(), 0.5 * len.y(), len.z()));
  lid.velocity = [](double) { return Vec(0.0, 0.0, -0.05); };       // [m/s]
  lid.angular_velocity = [](double) { return Vec(0.0, 0.0, 20.0); };  // [rad/s]
  const std::uint32_t lid_id = sim.add_body(lid);
  sim.add_wall(geometry::PlaneShape<Dim3>(Vec::Zero(), Vec(-Vec::UnitZ())), wmat, lid_id);
  std::mt19937_64 rng(5);
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b)
      for (int c = 0; c < 16; ++c) {
        Vec x = (Vec(a, b, c) + Vec::Constant(0.5)) * 2.1e-3;
        for (int q = 0; q < 3; ++q) x[q] += uniform(rng, -0.03, 0.03) * kPackedR;
        const double r = uniform(rng, 0.8, 1.2) * kPackedR;
        sim.add_particle(x, r, (a + b + c) % 2 == 0 ? mat : mat2,
                         Vec(uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3)));
      }
  sim.run(steps);
  ColumnResult out;
  const auto& p = sim.particles();
  out.x.assign(p.x.begin(), p.x.begin() + p.owned());
  out.v.assign(p.v.begin(), p.v.begin() + p.owned());
  out.contacts = sim.contact_count();
  out.lid_force = sim.body(lid_id).force;
  out.lid_torque = sim.body(lid_id).torque;
  return out;
}

/// Two runs of the column agree to amplified rounding: contact count, positions to 1e-6 kPackedR,
/// velocities to 1e-5 of the largest speed. Rounding is amplified in jumps, not smoothly: with
/// Truncation::Total a contact that starts to slide has its spring relaxed towards the dashpot's
/// share (tangential/spring.hpp), so a rounding-level difference at the stick/slip threshold
/// moves the spring by a finite step. Measured for the default Hertz-Mindlin (e = 0.5): velocity
/// differences of 1e-13 of the speed up to step 55, then jumps at steps 60 and 90 to 1.5e-8
/// (2.4e-7 in the -march=native build, whose FMA contractions differ between the two paths);
/// with e = 1 (no dashpot) 1.2e-12 after 150 steps; the force history with the unloading
/// rescale happened to meet no such switch (5e-13). A real difference between the packed and the scalar
/// law (a term missing in one of them, a history slot scattered wrongly) is of the order of the
/// contact forces' share of the motion, 1e-3 and more.
void check_same_run(const ColumnResult& a, const ColumnResult& b) {
  CHECK(b.contacts == a.contacts);
  double dx = 0.0, dv = 0.0, vmax = 0.0;
  for (std::size_t k = 0; k < a.x.size(); ++k) {
    dx = std::max(dx, (b.x[k] - a.x[k]).norm());
    dv = std::max(dv, (b.v[k] - a.v[k]).norm());
    vmax = std::max(vmax, a.v[k].norm());
  }
  INFO("max position difference " << dx << " m, velocity " << dv << " m/s (max speed " << vmax << ")");
  CHECK(dx < 1e-6 * kPackedR);
  CHECK(dv < 1e-5 * vmax);
}

}  // namespace

namespace {

/// Records of N doubles, 0-terminated between each other by a sentinel double, read by the
/// transposes in the lane order `order` (repeats allowed for reads) and written back.
template <std::size_t N>
void check_transposes(const std::vector<std::size_t>& order) {
  const std::size_t stride = N + 1;  // one sentinel after every record
  const std::size_t records = 2 * W + 1;
  std::vector<double> data(records * stride);
  for (std::size_t k = 0; k < data.size(); ++k) data[k] = 1000.0 + static_cast<double>(k);
  const double* in[W];
  for (std::size_t l = 0; l < W; ++l) in[l] = &data[order[l] * stride];
  Lane lanes[N];
  transpose_in<N>(in, lanes);
  for (std::size_t k = 0; k < N; ++k)
    for (std::size_t l = 0; l < W; ++l) {
      INFO("N " << N << ", double " << k << ", lane " << l);
      CHECK(lanes[k][l] == in[l][k]);
    }
  // Writing back: lanes first `valid` records only, the sentinels and the others untouched.
  for (std::size_t valid = 1; valid <= W; ++valid) {
    std::vector<double> out = data;
    double* rec[W];
    for (std::size_t l = 0; l < W; ++l) rec[l] = &out[(records - 1 - l) * stride];  // distinct, reversed
    Lane values[N];
    for (std::size_t k = 0; k < N; ++k)
      for (std::size_t l = 0; l < W; ++l) values[k][l] = -1.0 - static_cast<double>(10 * k + l);
    transpose_out<N>(values, rec, valid);
    for (std::size_t q = 0; q < out.size(); ++q) {
      const std::size_t record = q / stride, k = q % stride;
      const std::size_t l = records - 1 - record;  // the lane that owns this record, if any
      const bool written = k < N && l < valid;
      INFO("N " << N << ", valid " << valid << ", record " << record << ", double " << k);
      CHECK(out[q] == (written ? -1.0 - static_cast<double>(10 * k + l) : data[q]));
    }
  }
}

template <std::size_t... Ns>
void check_transposes_all(const std::vector<std::size_t>& order, std::index_sequence<Ns...>) {
  (check_transposes<Ns + 1>(order), ...);
}

}  // namespace

TEST_CASE("Lane transposes move each record's doubles to its own lane", "[contact][packed]") {
  // core/lane_transpose.hpp: with AVX-512 or AVX2 (a -march=native build, granule_native_tests)
  // in registers, block by block of four doubles (three as two plus one with AVX2, masks for the
  // rest); otherwise through a buffer. Records of 1-9 doubles cover full blocks, partial ones
  // and two blocks (histories of 4 and 8 doubles, 3-vectors).
  INFO("lane width " << W << (detail::kTransposeInRegisters ? " (in registers)" : " (through a buffer)"));
  std::vector<std::size_t> reversed(W), repeated(W), spread(W);
  for (std::size_t l = 0; l < W; ++l) {
    reversed[l] = W - 1 - l;
    repeated[l] = l / 2;
    spread[l] = (5 * l + 3) % (2 * W + 1);
  }
  for (const auto& order : {reversed, repeated, spread}) check_transposes_all(order, std::make_index_sequence<9>{});
  // The 3-vector helper reads x, y, z of a store's array of vectors, including its last element.
  std::vector<Vec> x(W + 3);
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = Vec(1.0 * k, 100.0 + k, 200.0 + k);
  std::uint32_t idx[W];
  for (std::size_t l = 0; l < W; ++l) idx[l] = static_cast<std::uint32_t>(x.size() - 1 - 2 * (l % 2) - l / 2);
  const LaneVec3 g = gather_vec3_lanes(x.data()->data(), idx);
  for (std::size_t l = 0; l < W; ++l) {
    CHECK(g.x[l] == x[idx[l]][0]);
    CHECK(g.y[l] == x[idx[l]][1]);
    CHECK(g.z[l] == x[idx[l]][2]);
  }
  // One double per lane (radii, 1/m), through a buffer and (with AVX-512) by loads into halves
  // and quarters of the pack.
  std::vector<double> s(x.size());
  for (std::size_t k = 0; k < s.size(); ++k) s[k] = 0.5 + static_cast<double>(k);
  const Lane by_buffer = gather_lanes<GatherBy::buffer>(s.data(), idx);
  const Lane by_registers = gather_lanes<GatherBy::registers>(s.data(), idx);
  for (std::size_t l = 0; l < W; ++l) {
    CHECK(by_buffer[l] == s[idx[l]]);
    CHECK(by_registers[l] == s[idx[l]]);
  }
}

TEST_CASE("The touch scan lists a layer's touching entries and moves slots in entry order", "[contact][packed]") {
  // contact/touch_scan.hpp: with AVX-512 or AVX2 (granule_native_tests, granule_avx2_tests) 8 or
  // 4 entries at a time across the ends of rows; the reference is the one-at-a-time scan and,
  // for the touches, the definition |x_i - x_j|^2 < (r_i + r_j)^2. Rows of 0 to 19 entries
  // (empty ones, ones longer than a pack), layers starting and ending anywhere, and slots given
  // to about half the entries, so that slots move both ways.
  INFO("packed scan: " << (contact::kPackedTouchScan ? "yes" : "no"));
#if defined(__AVX2__)
  // In the wide flavours the stream scan must be the one compared (else this compares the
  // one-at-a-time scan with itself).
  CHECK(contact::kPackedTouchScan == (lane_width == 4 || lane_width == 8));
#endif
  std::mt19937_64 rng(21);
  const std::size_t n = 400;
  std::vector<Vec> x(n);
  std::vector<double> r(n);
  for (std::size_t k = 0; k < n; ++k) {
    // A 3 mm cube and radii 0.5-1 mm: about half the entries touch.
    x[k] = Vec(uniform(rng, 0.0, 3e-3), uniform(rng, 0.0, 3e-3), uniform(rng, 0.0, 3e-3));
    r[k] = uniform(rng, 0.5e-3, 1e-3);
  }
  constexpr std::uint32_t none = 0xFFFFFFFFu;
  std::vector<std::uint32_t> row_begin{0}, nbr, slot;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t len = rng() % 20;
    for (std::size_t k = 0; k < len; ++k) {
      nbr.push_back(static_cast<std::uint32_t>(rng() % n));
      slot.push_back(rng() % 2 == 0 ? none : static_cast<std::uint32_t>(nbr.size()));
    }
    row_begin.push_back(static_cast<std::uint32_t>(nbr.size()));
  }
  using Calls = std::vector<std::pair<std::uint32_t, bool>>;
  const auto scan = [&](bool packed, bool history, std::uint32_t r0, std::uint32_t r1, Calls& calls) {
    const contact::TouchScanInput in{x.data()->data(), r.data(), row_begin.data(), nbr.data(),
                                     history ? slot.data() : nullptr, none};
    std::vector<std::uint32_t> touching(nbr.size() + 8), rows(nbr.size() + 8);
    const auto move = [&](std::uint32_t e, bool touch) { calls.emplace_back(e, touch); };
    const std::size_t nt = packed ? contact::scan_rows(in, r0, r1, touching.data(), rows.data(), move)
                                  : contact::scan_rows_scalar(in, r0, r1, touching.data(), rows.data(), move);
    touching.resize(nt);
    rows.resize(nt);
    return std::pair{touching, rows};
  };
  std::size_t listed = 0, taken = 0, given = 0;
  const std::pair<std::uint32_t, std::uint32_t> layers[] = {{0, 400}, {0, 1}, {3, 4}, {7, 150}, {151, 152},
                                                            {152, 389}, {390, 400}, {200, 200}};
  for (const auto& [r0, r1] : layers) {
    for (const bool history : {true, false}) {
      INFO("rows " << r0 << " to " << r1 << (history ? ", with history slots" : ", without history"));
      Calls calls_one, calls_packed;
      const auto [touching, rows] = scan(false, history, r0, r1, calls_one);
      const auto [touching_p, rows_p] = scan(true, history, r0, r1, calls_packed);
      CHECK(touching_p == touching);
      CHECK(rows_p == rows);
      CHECK(calls_packed == calls_one);
      // The reference against the definition.
      std::vector<std::uint32_t> expected, expected_rows;
      Calls expected_calls;
      for (std::uint32_t i = r0; i < r1; ++i) {
        for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e) {
          const std::uint32_t j = nbr[e];
          const bool touch = (x[i] - x[j]).squaredNorm() < (r[i] + r[j]) * (r[i] + r[j]);
          if (touch) {
            expected.push_back(e);
            expected_rows.push_back(i);
          }
          if (history && touch == (slot[e] == none)) expected_calls.emplace_back(e, touch);
        }
      }
      CHECK(touching == expected);
      CHECK(rows == expected_rows);
      CHECK(calls_one == expected_calls);
      listed += touching.size();
      for (const auto& c : calls_packed) (c.second ? taken : given) += 1;
    }
  }
  // The scene is not trivial: many touches, and slots moving both ways.
  CHECK(listed > 3000);
  CHECK(taken > 500);
  CHECK(given > 500);
}

TEMPLATE_TEST_CASE("Packed contact evaluation equals the one-at-a-time evaluation", "[contact][packed]",
                   contact::LinearFrictionless, contact::HertzFrictionless, contact::HertzMindlin,
                   contact::HertzMindlinIncremental, contact::HertzMindlinNonTensile, contact::HertzMindlinEpsd,
                   contact::HertzMindlinEpsdSjkr, contact::HertzMindlinSds) {
  STATIC_REQUIRE(TestType::lanes);
  SECTION("a step of 1 us") { check_packed_against_scalar<TestType>(1e-6, 11); }
  SECTION("a step of 20 us (large increments)") { check_packed_against_scalar<TestType>(2e-5, 12); }
  SECTION("the set-up evaluation (dt = 0)") { check_packed_against_scalar<TestType>(0.0, 13); }
}

TEST_CASE("Models with a scalar-only slot are not packed", "[contact][packed]") {
  STATIC_REQUIRE_FALSE(contact::HertzMindlinLegacy::lanes);      // displacement history, SpringOnly
  STATIC_REQUIRE_FALSE(contact::LinearSpringDashpot::lanes);     // displacement history
  STATIC_REQUIRE(contact::LinearCoulombRolling::lanes);           // incremental Coulomb is packed
  STATIC_REQUIRE(Simulation<Dim2, contact::HertzMindlin>::kPackable);  // 2D too (test_packed_contacts_2d.cpp)
  STATIC_REQUIRE(Simulation<Dim3, contact::HertzMindlin>::kPackable);
  STATIC_REQUIRE_FALSE(Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList,
                                  integrators::VelocityVerletPredictedDamping>::kPackable);
}

TEMPLATE_TEST_CASE("A packed run follows the one-at-a-time run", "[contact][packed][engine]",
                   contact::HertzMindlin, contact::HertzMindlinEpsdSjkr) {
  // A 3D column of ~1000 polydisperse spheres with random velocities under gravity, between
  // walls, under a sinking, spinning lid: the whole packed path (touch sorting, chunks with
  // padding, history gather/scatter, force scatter, wall contacts queued for the packed law,
  // forces on a moving body) against the scalar loop, with one particle material and with two
  // (chunks flushed at every change of material pair). The trajectories separate only by
  // amplified rounding over 150 steps.
  const bool two_materials = GENERATE(false, true);
  INFO((two_materials ? "two particle materials" : "one particle material"));
  const auto one = run_column<TestType>(false, 150, two_materials);
  const auto packed = run_column<TestType>(true, 150, two_materials);
  REQUIRE(one.contacts > 600);
  check_same_run(one, packed);
  INFO("lid force " << one.lid_force.transpose() << " N (packed " << packed.lid_force.transpose() << "), torque "
                    << one.lid_torque.transpose() << " N m (packed " << packed.lid_torque.transpose() << ")");
  REQUIRE(one.lid_force.z() > 0.0);  // the sinking lid presses on the column
  CHECK((packed.lid_force - one.lid_force).norm() < 1e-5 * one.lid_force.norm());
  CHECK((packed.lid_torque - one.lid_torque).norm() < 1e-5 * one.lid_torque.norm());
}

TEMPLATE_TEST_CASE("Plane walls and a box container of the same faces give the same run",
                   "[contact][packed][engine]", contact::HertzMindlin, contact::HertzMindlinEpsdSjkr) {
  // Planes have a path of their own in the wall walk (Simulation::plane_contact: one entry per
  // row, its history slot is the entry, reset when the contact opens), the box container's
  // faces go through the general one (slot search among the row's features, touch marks).
  // A face's distance, point and normal are the same numbers either way, and the contacts come
  // in the same order, so the two runs must agree to rounding: a plane history kept over a
  // contact that opened, or taken from the wrong entry, would part them. (Built on this
  // machine the runs agree exactly; with the plane path's reset left out, the velocities
  // differed by 0.3-3 % of the largest speed.)
  const bool packed = GENERATE(false, true);
  INFO((packed ? "packed contacts" : "one contact at a time"));
  const auto planes = run_column<TestType>(packed, 150, false, false);
  const auto box = run_column<TestType>(packed, 150, false, true);
  REQUIRE(planes.contacts > 600);
  check_same_run(planes, box);
  CHECK((box.lid_force - planes.lid_force).norm() < 1e-9 * planes.lid_force.norm());
}
