// Packed 2D contacts (Dim2Lanes in core/lanes.hpp, PairChunk<_, 2> in contact/packed.hpp, the
// 2D touch scan of contact/touch_scan.hpp): disks evaluated W contacts at a time must give what
// they give one contact at a time.
//
// Reference: the scalar evaluation (ContactModel<...>::evaluate over ContactGeometry<Dim2>),
// which the physics tests of tests/contact check against analytic results (contact time,
// restitution, Coulomb limit). The packed form runs the same law templates over Lane, so the
// two agree to rounding (FMA contractions): a relative 1e-12 on every force, torque and history
// double. A branch blended into the wrong lanes, a history double read from the padding of the
// stored 2D state (an Eigen::Vector2d and one double take 32 bytes) or a geometry term built
// differently shows up as an O(1) difference.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include <granule/boundaries/geometry/sphero_line.hpp>
#include <granule/granule.hpp>

using namespace granule;

namespace packed2d_test {

using Vec2 = Eigen::Vector2d;
constexpr std::size_t kLanes = lane_width;

double uniform(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

Vec2 random_unit(std::mt19937_64& rng) {
  const double a = uniform(rng, 0.0, 2.0 * 3.141592653589793);
  return Vec2(std::cos(a), std::sin(a));
}

/// Two disks in contact: i at d (moving at dv, spinning at wi) against j at rest at the origin.
struct Pair {
  Vec2 d, dv;
  double wi, wj, ri, rj, inv_mi, inv_mj;
};

Pair random_pair(std::mt19937_64& rng, double r, double speed) {
  Pair p;
  p.ri = r * uniform(rng, 0.5, 1.0);
  p.rj = r * uniform(rng, 0.5, 1.0);
  const double overlap = uniform(rng, 1e-4, 2e-2) * std::min(p.ri, p.rj);
  p.d = (p.ri + p.rj - overlap) * random_unit(rng);
  p.dv = speed * uniform(rng, 0.0, 1.0) * random_unit(rng);
  p.wi = (speed / r) * uniform(rng, -1.0, 1.0);
  p.wj = (speed / r) * uniform(rng, -1.0, 1.0);
  const double rho = 2500.0, t = 3e-3;  // [kg/m^3], disk thickness [m]
  p.inv_mi = 1.0 / (rho * Dim2::volume(p.ri, t));
  p.inv_mj = uniform(rng, 0, 1) < 0.2 ? 0.0 : 1.0 / (rho * Dim2::volume(p.rj, t));  // some frozen
  return p;
}

/// The scalar geometry, written out as Simulation::pair_geometry builds it for disks.
template <class Model>
contact::ContactGeometry<Dim2> scalar_geometry(const Pair& in, double dt) {
  contact::ContactGeometry<Dim2> g;
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
  g.v_rel = in.dv - (g.arm_i * Dim2::cross(in.wi, g.n) + g.arm_j * Dim2::cross(in.wj, g.n));
  g.vn = g.v_rel.dot(g.n);
  g.vt = g.v_rel - g.vn * g.n;
  g.omega_rel = in.wi - in.wj;
  g.damp_at_kinematic_velocity();
  const double k1 = Dim2::inertia_factor + 1.0;
  g.i_roll = Model::needs_rolling_inertia
                 ? 1.0 / (in.inv_mi / (k1 * g.r_i * g.r_i) + in.inv_mj / (k1 * g.r_j * g.r_j))
                 : 0.0;
  g.dt = dt;
  return g;
}

template <class Model>
using Stored = typename Model::template State<Dim2>;

/// A loaded contact's history: tangential force up to twice the Coulomb limit (some lanes slide,
/// some stick) and a rolling torque up to twice its limit; `fresh`: a new contact.
template <class Model>
Stored<Model> random_state(std::mt19937_64& rng, const contact::ContactGeometry<Dim2>& g,
                           const typename Model::Params& prm, bool fresh) {
  Stored<Model> s{};
  if (fresh) return s;
  const auto nr = Model::NormalLaw::eval(prm.normal, g);
  const double fn = std::abs(nr.fn) + 1e-3 * nr.fn_elastic;
  if constexpr (requires { s.tangential.ft; }) {
    s.tangential.ft = uniform(rng, 0.0, 2.0) * 0.5 * fn * Vec2(-g.n.y(), g.n.x()) * (rng() % 2 ? 1.0 : -1.0);
  }
  if constexpr (requires { s.tangential.fs; }) {
    s.tangential.fs = uniform(rng, 0.0, 2.0) * 0.5 * fn * Vec2(-g.n.y(), g.n.x());
    double gamma = 0.0;
    s.tangential.kt_old = Model::TangentialLaw::StiffnessLaw::eval(prm.tangential.stiffness, g, nr, gamma) *
                          uniform(rng, 0.8, 1.25);
  }
  if constexpr (requires { s.tangential.xi; }) {  // displacement history, up to twice the limit
    double gamma = 0.0;
    const double kt = Model::TangentialLaw::StiffnessLaw::eval(prm.tangential.stiffness, g, nr, gamma);
    s.tangential.xi = uniform(rng, -2.0, 2.0) * 0.5 * fn / kt * Vec2(-g.n.y(), g.n.x());
  }
  if constexpr (requires { s.rolling.m_roll; }) {
    s.rolling.m_roll = uniform(rng, -2.0, 2.0) * prm.rolling.mu_r * g.r_eff * fn;
  }
  if constexpr (requires { s.rolling.theta; }) {  // SDS rolling angle, up to twice the limit
    s.rolling.theta = uniform(rng, -2.0, 2.0) * prm.rolling.mu_r * g.r_eff * fn /
                      contact::SdsRolling::stiffness(prm.rolling, g.r_eff);
  }
  return s;
}

/// The history's doubles (its padding excluded: the packed store must not write it).
template <class Model>
std::vector<double> doubles_of(const Stored<Model>& s) {
  if constexpr (!Model::template has_state<Dim2>) {
    return {};
  } else {
    constexpr std::size_t n = sizeof(typename Model::template State<Dim2Lanes>) / sizeof(Lane);
    std::vector<double> v(n);
    std::memcpy(v.data(), static_cast<const void*>(&s), n * sizeof(double));
    return v;
  }
}

Material disk_material() {
  Material m;
  m.youngs_modulus = 2e7;  // [Pa]
  m.poisson_ratio = 0.25;
  m.density = 2500.0;  // [kg/m^3]
  m.restitution = 0.9;
  m.friction = 0.5;
  m.rolling_friction = 0.02;
  m.rolling_stiffness_factor = 40.0;
  m.rolling_damping = 0.3;
  m.rolling_stiffness = 20.0;  // [N/m] (SDS rolling)
  m.reference_length = 3e-3;  // [m] (linear laws: k_n = E d)
  m.tangential_stiffness_ratio = 0.5;
  return m;
}

// disk_records: the geometry reads v, omega and r from contact::DiskRecord copies (the engine's
// 2D pass) instead of the three arrays; the same bits either way.
template <class Model>
void check_packed_against_scalar(double dt, std::uint64_t seed, bool disk_records = false) {
  using Chunk = contact::PairChunk<64, 2>;
  using Packed = typename Model::template State<Dim2Lanes>;
  const Material m = disk_material();
  const auto prm = Model::make(mix(m, m), 3e-3);
  std::mt19937_64 rng(seed);
  auto chunk = std::make_unique<Chunk>();
  std::vector<Pair> pairs;
  std::vector<Stored<Model>> states;
  std::vector<Vec2> x, v;
  std::vector<double> w, radius, inv_mass;
  const double r = 2e-3;
  for (std::size_t c = 0; c < Chunk::capacity - 3; ++c) {  // the last pack is padded
    const Pair in = random_pair(rng, r, c % 3 == 0 ? 0.01 : 1.0);
    pairs.push_back(in);
    states.push_back(random_state<Model>(rng, scalar_geometry<Model>(in, dt), prm, c % 5 == 0));
    x.insert(x.end(), {in.d, Vec2::Zero()});
    v.insert(v.end(), {in.dv, Vec2::Zero()});
    w.insert(w.end(), {in.wi, in.wj});
    radius.insert(radius.end(), {in.ri, in.rj});
    inv_mass.insert(inv_mass.end(), {in.inv_mi, in.inv_mj});
    chunk->i[c] = static_cast<std::uint32_t>(2 * c);
    chunk->j[c] = static_cast<std::uint32_t>(2 * c + 1);
    chunk->history[c] = static_cast<std::uint32_t>(c);
    ++chunk->count;
  }
  std::vector<contact::DiskRecord> disks(w.size());
  contact::fill_disk_records(v.data()->data(), w.data(), radius.data(), w.size(), disks.data());
  const contact::PackedParticles particles{x.data()->data(), v.data()->data(), w.data(), radius.data(),
                                           inv_mass.data(), disk_records ? disks.data() : nullptr};
  chunk->pad();
  std::vector<Stored<Model>> packed_states = states;
  packed_states.resize(Chunk::capacity, Stored<Model>{});
  std::size_t sliding = 0, mobilised = 0;
  for (std::size_t k = 0; k < chunk->count; k += kLanes) {
    const std::size_t valid = std::min(kLanes, chunk->count - k);
    contact::ContactGeometry<Dim2Lanes> g;
    chunk->template geometry<Model::needs_rolling_inertia, Model::needs_twist>(k, particles, dt, g);
    Packed s{};
    Stored<Model>* slots[kLanes];
    for (std::size_t q = 0; q < kLanes; ++q) slots[q] = &packed_states[chunk->history[k + q]];
    if constexpr (Model::template has_state<Dim2>) contact::PackedState<Stored<Model>, Packed>::load(s, slots);
    const auto cf = Model::evaluate(prm, g, s);
    if constexpr (Model::template has_state<Dim2>) contact::PackedState<Stored<Model>, Packed>::store(s, slots, valid);
    chunk->store_force(k, cf);
    for (std::size_t q = 0; q < valid; ++q) {
      const std::size_t c = k + q;
      INFO("contact " << c);
      const auto gs = scalar_geometry<Model>(pairs[c], dt);
      Stored<Model> ss = states[c];
      if constexpr (requires { ss.rolling.theta; }) {  // the SDS slider holds |M| at its limit
        auto probe = ss.rolling;
        const auto nr = Model::NormalLaw::eval(prm.normal, gs);
        const double mmax = prm.rolling.mu_r * gs.r_eff * std::abs(nr.fn);
        if (std::abs(contact::SdsRolling::eval(prm.rolling, gs, nr, probe)) >= (1.0 - 1e-12) * mmax && mmax > 0.0)
          ++mobilised;
      }
      const auto cs = Model::evaluate(prm, gs, ss);
      if (cs.ft.norm() > (1.0 - 1e-12) * m.friction * std::abs(cs.fn) && cs.fn > 0.0) ++sliding;
      if constexpr (requires { ss.rolling.m_roll; }) {
        if (std::abs(ss.rolling.m_roll) >= (1.0 - 1e-12) * prm.rolling.mu_r * gs.r_eff * std::abs(cs.fn)) ++mobilised;
      }
      const double fscale = 1e-12 * (cs.force.norm() + 1e-30), tscale = fscale * r;
      CHECK(std::abs(chunk->out[Chunk::fx][c] - cs.force.x()) <= fscale);
      CHECK(std::abs(chunk->out[Chunk::fx + 1][c] - cs.force.y()) <= fscale);
      CHECK(std::abs(chunk->out[Chunk::tix][c] - cs.torque_i) <= 1e-12 * std::abs(cs.torque_i) + tscale);
      CHECK(std::abs(chunk->out[Chunk::tjx][c] - cs.torque_j) <= 1e-12 * std::abs(cs.torque_j) + tscale);
      const auto a = doubles_of<Model>(ss), b = doubles_of<Model>(packed_states[c]);
      // History: relative 1e-10 with an absolute floor of 1e-20 (m, rad, N or N m). With FMA the
      // two paths round differently and two updates cancel: a spring that stays exactly 0 in the
      // scalar law carries ~5e-23 m in the packed one (v_t ~1e-17 m/s where the scalar geometry
      // gives 0), and SDS's reset of a sliding rolling angle, -(M + C w)/K, lost a factor ~60 at
      // 20 us (measured 6.4e-12 relative, -march=native). A history double read from the padding
      // or blended into the wrong lane is off by order 1.
      for (std::size_t e = 0; e < a.size(); ++e) CHECK(std::abs(b[e] - a[e]) <= 1e-10 * std::abs(a[e]) + 1e-20);
    }
  }
  // The padded lanes were not written back.
  for (std::size_t c = chunk->count; c < Chunk::capacity; ++c)
    CHECK(doubles_of<Model>(packed_states[c]) == doubles_of<Model>(Stored<Model>{}));
  INFO("lanes " << kLanes << ": sliding " << sliding << ", rolling mobilised " << mobilised);
  if (dt > 0.0 && Model::template has_state<Dim2>) {
    // Both sides of each limit were exercised.
    CHECK(sliding >= 3);
    CHECK(sliding + 3 <= chunk->count);
    if constexpr (requires(Stored<Model> s) { s.rolling.m_roll; } || requires(Stored<Model> s) { s.rolling.theta; }) {
      CHECK(mobilised >= 3);
      CHECK(mobilised + 3 <= chunk->count);
    }
  }
}

struct BedRun {
  std::vector<Vec2> x, v;
  std::vector<double> omega;
  std::size_t contacts = 0;
  Vec2 intruder_force = Vec2::Zero();
  double intruder_torque = 0.0;
};

/// A 2D cell of ~700 disks (radii 0.98-1.06 mm) with random velocities under strong gravity, closed by a
/// floor plane and two sphero-line sides, with a tilted sphero-line intruder on a body that
/// rises and turns through them: 200 steps of the pull-out scene's law.
/// With `changes`, the run also freezes a fifth of the disks for 40 steps, releases them and
/// removes a few: the packed loop's per-pair constants (R*, m*, I_r per list entry) must follow.
template <class Model>
BedRun run_bed(bool packed, bool changes = false, bool two_materials = false) {
  SimulationConfig<Dim2> cfg;
  const double w = 0.06, h = 0.06;  // [m]
  cfg.domain.lo = Vec2(-0.01, -0.01);
  cfg.domain.hi = Vec2(w + 0.01, h + 0.01);
  cfg.gravity = Vec2(0.0, -1000.0);  // [m/s^2]: presses the bed together within the run
  cfg.thickness = 3e-3;
  cfg.dt = 2e-6;
  cfg.packed_contacts = packed;
  Simulation<Dim2, Model> sim(cfg);
  const auto mat = sim.add_material(disk_material());
  Material stiff = disk_material();
  stiff.name = "stiff";
  stiff.youngs_modulus *= 2.0;
  stiff.friction = 0.3;
  const auto mat2 = two_materials ? sim.add_material(stiff) : mat;
  const auto wmat = sim.add_wall_material(disk_material());
  sim.add_wall(geometry::PlaneShape<Dim2>(Vec2::Zero(), Vec2::UnitY()), wmat);
  sim.add_wall(geometry::SpheroLineShape(Vec2(-1e-3, 0.0), Vec2(-1e-3, h), 1e-3), wmat);
  sim.add_wall(geometry::SpheroLineShape(Vec2(w + 1e-3, 0.0), Vec2(w + 1e-3, h), 1e-3), wmat);
  Body<Dim2> intruder;
  intruder.name = "intruder";
  intruder.pose = geometry::Pose<Dim2>::translation(Vec2(0.5 * w, 0.01));
  intruder.velocity = [](double) { return Vec2(0.0, 0.5); };  // [m/s]
  intruder.angular_velocity = [](double) { return 30.0; };    // [rad/s]
  const std::uint32_t id = sim.add_body(intruder);
  sim.add_wall(geometry::SpheroLineShape(Vec2(-4e-3, -1e-3), Vec2(4e-3, 1e-3), 1e-3), wmat, id);
  std::mt19937_64 rng(9);
  for (int a = 0; a < 27; ++a)
    for (int b = 0; b < 27; ++b) {
      const Vec2 x(2e-3 + 2.05e-3 * a + uniform(rng, -5e-5, 5e-5), 2e-3 + 2.0e-3 * b);
      // No disk inside the intruder: its distance from the segment at least cap + radius.
      const Vec2 c = intruder.pose.translation(), a0 = c + Vec2(-4e-3, -1e-3), a1 = c + Vec2(4e-3, 1e-3);
      const double u = std::clamp((x - a0).dot(a1 - a0) / (a1 - a0).squaredNorm(), 0.0, 1.0);
      if ((x - (a0 + u * (a1 - a0))).norm() < 1e-3 + 1.06e-3 + 5e-5) continue;
      // Rows 2 mm apart, radii 0.98-1.06 mm: most neighbours overlap a little at the start.
      sim.add_particle(x, uniform(rng, 0.98e-3, 1.06e-3), (a * 27 + b) % 7 == 3 ? mat2 : mat,
                       Vec2(uniform(rng, -0.3, 0.3), uniform(rng, -0.3, 0.3)),
                       (a + b) % 5 == 0 ? 1u : 0u);
    }
  if (changes) {
    sim.run(60);
    sim.freeze_group(1);
    sim.run(40);
    sim.release_group(1);
    sim.run(40);
    sim.remove_particles([&](std::size_t i) { return sim.particles().x[i].x() < 4e-3; });
    sim.run(60);
  } else {
    sim.run(200);
  }
  BedRun out;
  const auto& p = sim.particles();
  out.x.assign(p.x.begin(), p.x.begin() + p.owned());
  out.v.assign(p.v.begin(), p.v.begin() + p.owned());
  out.omega.assign(p.omega.begin(), p.omega.begin() + p.owned());
  out.contacts = sim.contact_count();
  out.intruder_force = sim.body(id).force;
  out.intruder_torque = sim.body(id).torque;
  return out;
}

}  // namespace packed2d_test

TEMPLATE_TEST_CASE("Packed 2D contact evaluation equals the one-at-a-time evaluation", "[contact][packed][2d]",
                   contact::LinearCoulombRolling, contact::HertzMindlin, contact::LinearFrictionless,
                   contact::HertzMindlinEpsd, contact::HertzMindlinIncremental, contact::HertzMindlinSds) {
  STATIC_REQUIRE(TestType::lanes);
  STATIC_REQUIRE(Simulation<Dim2, TestType>::kPackable);
  SECTION("a step of 1 us") { packed2d_test::check_packed_against_scalar<TestType>(1e-6, 31); }
  SECTION("a step of 20 us (large increments)") { packed2d_test::check_packed_against_scalar<TestType>(2e-5, 32); }
  SECTION("the set-up evaluation (dt = 0)") { packed2d_test::check_packed_against_scalar<TestType>(0.0, 33); }
  SECTION("v, omega and r read from disk records") {
    packed2d_test::check_packed_against_scalar<TestType>(2e-5, 34, true);
  }
}

TEST_CASE("Disk records copy v, omega and r of every disk exactly", "[contact][packed][2d]") {
  using packed2d_test::Vec2;
  // Lengths around the four-disk blocks of the AVX2 copy, so that its tail runs too.
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t n = 0; n <= 13; ++n) {
    std::vector<Vec2> v(n);
    std::vector<double> w(n), radius(n);
    for (std::size_t i = 0; i < n; ++i) {
      v[i] = Vec2(u(rng), u(rng));
      w[i] = 100.0 * u(rng);
      radius[i] = 1e-3 * (2.0 + u(rng));
    }
    std::vector<contact::DiskRecord> out(n + 1);
    out[n].vx = 42.0;  // past the end: untouched
    contact::fill_disk_records(n > 0 ? v.data()->data() : nullptr, w.data(), radius.data(), n, out.data());
    for (std::size_t i = 0; i < n; ++i) {
      INFO("n " << n << ", disk " << i);
      CHECK(out[i].vx == v[i].x());
      CHECK(out[i].vy == v[i].y());
      CHECK(out[i].omega == w[i]);
      CHECK(out[i].radius == radius[i]);
    }
    CHECK(out[n].vx == 42.0);
  }
}

TEST_CASE("The 2D touch scan lists the touching entries as the definition does", "[contact][packed][2d]") {
  using packed2d_test::uniform;
  std::mt19937_64 rng(23);
  const std::size_t n = 300;
  std::vector<packed2d_test::Vec2> x(n);
  std::vector<double> r(n);
  for (std::size_t k = 0; k < n; ++k) {
    x[k] = packed2d_test::Vec2(uniform(rng, 0.0, 4e-3), uniform(rng, 0.0, 4e-3));  // about half touch
    r[k] = uniform(rng, 0.5e-3, 1e-3);
  }
  constexpr std::uint32_t none = 0xFFFFFFFFu;
  std::vector<std::uint32_t> row_begin{0}, nbr, slot;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = rng() % 20; k > 0; --k) {
      nbr.push_back(static_cast<std::uint32_t>(rng() % n));
      slot.push_back(rng() % 2 == 0 ? none : static_cast<std::uint32_t>(nbr.size()));
    }
    row_begin.push_back(static_cast<std::uint32_t>(nbr.size()));
  }
  const contact::TouchScanInput in{x.data()->data(), r.data(), row_begin.data(), nbr.data(), slot.data(), none};
  // The engine's 2D form: r_i + r_j and the row given per entry (8 of room after the last).
  std::vector<double> reach(nbr.size() + 8, 0.0);
  std::vector<std::uint32_t> entry_row(nbr.size() + 8, 0u);
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e) {
      reach[e] = r[i] + r[nbr[e]];
      entry_row[e] = i;
    }
  std::size_t listed = 0;
  for (const auto& [r0, r1] : {std::pair<std::uint32_t, std::uint32_t>{0, 300}, {5, 6}, {17, 211}, {150, 150}}) {
    INFO("rows " << r0 << " to " << r1);
    std::vector<std::uint32_t> t1(nbr.size() + 8), rows1(nbr.size() + 8), t2(nbr.size() + 8), rows2(nbr.size() + 8);
    std::vector<std::pair<std::uint32_t, bool>> c1, c2, expected_calls;
    // With the separation output (the engine's 2D form) and without it (3D).
    std::vector<double> s1x(nbr.size() + 8), s1y(nbr.size() + 8), s2x(nbr.size() + 8), s2y(nbr.size() + 8);
    contact::TouchScanInput in1 = in, in2 = in;
    in1.separation[0] = s1x.data(), in1.separation[1] = s1y.data();
    in2.separation[0] = s2x.data(), in2.separation[1] = s2y.data();
    const std::size_t n1 = contact::scan_rows_scalar<2>(in1, r0, r1, t1.data(), rows1.data(),
                                                        [&](std::uint32_t e, bool t) { c1.emplace_back(e, t); });
    const std::size_t n2 = contact::scan_rows<2>(in2, r0, r1, t2.data(), rows2.data(),
                                                 [&](std::uint32_t e, bool t) { c2.emplace_back(e, t); });
    std::vector<std::uint32_t> t3(nbr.size() + 8), rows3(nbr.size() + 8);
    const std::size_t n3 = contact::scan_rows<2>(in, r0, r1, t3.data(), rows3.data(), [](std::uint32_t, bool) {});
    CHECK(n3 == n2);
    CHECK(std::equal(t3.begin(), t3.begin() + static_cast<std::ptrdiff_t>(n3), t2.begin()));
    // x_i - x_j of each listed pair, exactly (the geometry reads it instead of the positions).
    for (std::size_t k = 0; k < n1; ++k) {
      const packed2d_test::Vec2 d = x[rows1[k]] - x[nbr[t1[k]]];
      REQUIRE(s1x[k] == d.x());
      REQUIRE(s1y[k] == d.y());
    }
    for (std::size_t k = 0; k < n2; ++k) {
      const packed2d_test::Vec2 d = x[rows2[k]] - x[nbr[t2[k]]];
      REQUIRE(s2x[k] == d.x());
      REQUIRE(s2y[k] == d.y());
    }
    contact::TouchScanInput in4 = in;
    in4.reach = reach.data();
    in4.entry_row = entry_row.data();
    std::vector<std::uint32_t> t4(nbr.size() + 8), rows4(nbr.size() + 8);
    std::vector<std::pair<std::uint32_t, bool>> c4;
    const std::size_t n4 = contact::scan_rows<2>(in4, r0, r1, t4.data(), rows4.data(),
                                                 [&](std::uint32_t e, bool t) { c4.emplace_back(e, t); });
    t4.resize(n4), rows4.resize(n4);
    t1.resize(n1), rows1.resize(n1), t2.resize(n2), rows2.resize(n2);
    std::vector<std::uint32_t> expected, expected_rows;
    for (std::uint32_t i = r0; i < r1; ++i)
      for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e) {
        const std::uint32_t j = nbr[e];
        const bool touch = (x[i] - x[j]).squaredNorm() < (r[i] + r[j]) * (r[i] + r[j]);
        if (touch) expected.push_back(e), expected_rows.push_back(i);
        if (touch == (slot[e] == none)) expected_calls.emplace_back(e, touch);
      }
    CHECK(t1 == expected);
    CHECK(rows1 == expected_rows);
    CHECK(c1 == expected_calls);
    CHECK(t2 == expected);
    CHECK(rows2 == expected_rows);
    CHECK(c2 == expected_calls);
    CHECK(t4 == expected);
    CHECK(rows4 == expected_rows);
    CHECK(c4 == expected_calls);
    listed += n1;
  }
  CHECK(listed > 1000);
}

TEMPLATE_TEST_CASE("A packed 2D run follows the one-at-a-time run", "[contact][packed][2d][engine]",
                   contact::LinearCoulombRolling, contact::HertzMindlin) {
  // The whole packed 2D path (touch scan, chunks with padding, history gather/scatter with the
  // stored state's padding, force scatter, wall contacts one at a time beside it, forces on a
  // moving, turning body) against the scalar loop. 200 steps of a colliding bed: trajectories
  // separate only by amplified rounding.
  // Also with every seventh disk of a second material (twice as stiff, less friction): the
  // packed loop then looks up each pair's parameters (step() finds more than one material).
  const bool two_materials = GENERATE(false, true);
  INFO("two materials: " << two_materials);
  const auto one = packed2d_test::run_bed<TestType>(false, false, two_materials);
  const auto packed = packed2d_test::run_bed<TestType>(true, false, two_materials);
  REQUIRE(one.contacts > 150);
  CHECK(packed.contacts == one.contacts);
  double dx = 0.0, dv = 0.0, dw = 0.0, vmax = 0.0, wmax = 0.0;
  for (std::size_t k = 0; k < one.x.size(); ++k) {
    dx = std::max(dx, (packed.x[k] - one.x[k]).norm());
    dv = std::max(dv, (packed.v[k] - one.v[k]).norm());
    dw = std::max(dw, std::abs(packed.omega[k] - one.omega[k]));
    vmax = std::max(vmax, one.v[k].norm());
    wmax = std::max(wmax, std::abs(one.omega[k]));
  }
  INFO("max differences: position " << dx << " m, velocity " << dv << " m/s (max " << vmax << "), spin " << dw
                                    << " rad/s (max " << wmax << "); intruder force " << one.intruder_force.transpose()
                                    << " N");
  CHECK(dx < 1e-13);  // 1e-10 of a radius
  CHECK(dv < 1e-9 * vmax);
  CHECK(dw < 1e-9 * wmax);
  REQUIRE(one.intruder_force.norm() > 0.0);  // the intruder is in the bed
  CHECK((packed.intruder_force - one.intruder_force).norm() < 1e-9 * one.intruder_force.norm());
  CHECK(std::abs(packed.intruder_torque - one.intruder_torque) < 1e-9 * std::abs(one.intruder_torque) + 1e-15);
}

TEST_CASE("A packed 2D run follows the one-at-a-time run through freezing, release and removal",
          "[contact][packed][2d][engine]") {
  // The packed 2D loop reads R*, m* and I_r from a record per list entry (contact::PairConstants),
  // computed at the list's build: a frozen disk's pairs must see m* = m of the free partner,
  // released ones the mean again, and a removal renumbers the slots. Stale records would put the
  // packed run far from the scalar one (which computes them per contact).
  using Model = contact::LinearCoulombRolling;
  const auto one = packed2d_test::run_bed<Model>(false, true);
  const auto packed = packed2d_test::run_bed<Model>(true, true);
  REQUIRE(one.x.size() == packed.x.size());
  REQUIRE(one.x.size() + 20 < 27 * 27);  // a column was removed
  REQUIRE(one.contacts > 150);
  CHECK(packed.contacts == one.contacts);
  double dx = 0.0, dv = 0.0, vmax = 0.0;
  for (std::size_t k = 0; k < one.x.size(); ++k) {
    dx = std::max(dx, (packed.x[k] - one.x[k]).norm());
    dv = std::max(dv, (packed.v[k] - one.v[k]).norm());
    vmax = std::max(vmax, one.v[k].norm());
  }
  INFO("max differences: position " << dx << " m, velocity " << dv << " m/s (max " << vmax << ")");
  CHECK(dx < 1e-13);
  CHECK(dv < 1e-9 * vmax);
}
