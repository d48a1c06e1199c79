// Neighbour policies agree: BruteForce, LinkedCells and VerletList must find exactly the same
// touching pairs, and those must be the pairs a direct O(N^2) test of the positions with the
// minimum-image convention finds (the reference, as in Cabana's neighbour unit tests which
// check every list against an N^2 search).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "engine_helpers.hpp"

using namespace granule;
using granule::test::PairSet;

namespace {

// Geometry of the packings: radii in [1, 5] mm (ratio 5:1); boxes large enough for periodic
// images (L > 2 (2 r_max + skin)).
constexpr double kPolicyRmin = 1.0e-3;  // [m]
constexpr double kPolicyRmax = 5.0e-3;  // [m]

template <class D>
typename D::Vec packing_box() {
  using Vec = typename D::Vec;
  return Vec::Constant(D::dim == 2 ? 0.1 : 0.05);  // [m]
}

template <class D>
std::size_t packing_count() {
  return D::dim == 2 ? 400 : 450;
}

// One step of dt = 1e-9 s from rest: particles move by far less than the tolerance used to call
// a pair ambiguous, so the recorded contacts are those of the initial positions.
template <class D, class Search>
analysis::Frame<D> frame_after_one_step(const Domain<D>& dom,
                                        const std::vector<test::SphereSpec<D>>& pk) {
  SimulationConfig<D> cfg;
  cfg.domain = dom;
  cfg.dt = 1e-9;
  cfg.thickness = 1e-3;
  Simulation<D, contact::HertzFrictionless, Search> sim(cfg);
  const auto mat = sim.add_material(test::soft_material(0.9));
  for (const auto& s : pk) sim.add_particle(s.x, s.r, mat);
  // An observer that needs contacts records them at every step (the documented way).
  sim.every(1, [](auto&) {}, true);
  sim.step();
  return sim.frame();
}

template <class D>
void check_static_packing(int periodic_case) {
  const bool all = periodic_case == 2;
  const int axis = periodic_case == 1 ? 0 : -1;
  const auto dom = test::box_domain<D>(packing_box<D>(), all, axis);
  // Pairs overlapping by 0.2 r_min through each periodic face (and through the corner when all
  // axes are periodic), then random spheres.
  using Vec = typename D::Vec;
  std::vector<test::SphereSpec<D>> placed;
  const double gap = 0.5 * (kPolicyRmax + 0.8 * kPolicyRmin);  // half the centre distance
  const Vec mid = 0.5 * (dom.lo + dom.hi);
  for (int k = 0; k < D::dim; ++k) {
    if (!dom.periodic[k]) continue;
    Vec a = mid + 0.25 * dom.length()[(k + 1) % D::dim] * Vec::Unit((k + 1) % D::dim);
    Vec b = a;
    a[k] = dom.lo[k] + gap;
    b[k] = dom.hi[k] - gap;
    placed.push_back({a, kPolicyRmax});
    placed.push_back({b, kPolicyRmin});
  }
  if (all) {
    const double g = gap / std::sqrt(double(D::dim));
    placed.push_back({Vec(dom.lo + Vec::Constant(g)), kPolicyRmin});
    placed.push_back({Vec(dom.hi - Vec::Constant(g)), kPolicyRmax});
  }
  const auto pk = test::random_packing<D>(1234 + periodic_case, dom, packing_count<D>(), kPolicyRmin, kPolicyRmax, 0.3, placed);
  REQUIRE(pk.size() == packing_count<D>());

  const auto f_bf = frame_after_one_step<D, neighbours::BruteForce>(dom, pk);
  const auto f_lc = frame_after_one_step<D, neighbours::LinkedCells>(dom, pk);
  const auto f_vl = frame_after_one_step<D, neighbours::VerletList>(dom, pk);

  std::size_t ambiguous = 0, across = 0;
  const PairSet truth = test::pairs_from_positions(f_bf, dom, &ambiguous, &across);
  const PairSet bf = test::pairs_from_frame(f_bf);
  const PairSet lc = test::pairs_from_frame(f_lc);
  const PairSet vl = test::pairs_from_frame(f_vl);
  INFO("dim " << D::dim << ", periodic case " << periodic_case << ": " << truth.size()
              << " touching pairs, " << across << " across periodic faces");
  REQUIRE(ambiguous == 0);
  // The packing must be a real test: many overlapping pairs, some through periodic faces.
  REQUIRE(truth.size() >= 60);
  if (periodic_case > 0) REQUIRE(across >= 3);
  CHECK(bf == truth);
  CHECK(lc == truth);
  CHECK(vl == truth);
  // Each pair is recorded once (a half list).
  CHECK(f_bf.contacts.size() == truth.size());
  CHECK(f_lc.contacts.size() == truth.size());
  CHECK(f_vl.contacts.size() == truth.size());
  // The ground truth of the other runs' own positions agrees too (they moved by ~1e-16 m).
  CHECK(test::pairs_from_positions(f_lc, dom) == truth);
  CHECK(test::pairs_from_positions(f_vl, dom) == truth);
}

}  // namespace

TEMPLATE_TEST_CASE("Neighbour policies find the same touching pairs in polydisperse packings",
                   "[engine][neighbours]", Dim2, Dim3) {
  SECTION("non-periodic") { check_static_packing<TestType>(0); }
  SECTION("periodic along x") { check_static_packing<TestType>(1); }
  SECTION("periodic on all axes") { check_static_packing<TestType>(2); }
}

namespace {

// A dilute elastic gas in a box periodic along x (walls on the other axes): pair sets of
// BruteForce and VerletList (small skin: frequent rebuilds) compared at every step.
template <class D>
void check_gas(bool periodic_all) {
  using Vec = typename D::Vec;
  const Vec box = packing_box<D>();
  const auto dom = test::box_domain<D>(box, periodic_all, 0);
  const std::size_t n = D::dim == 2 ? 150 : 120;
  const auto pk = test::random_packing<D>(99, dom, n, kPolicyRmin, kPolicyRmax, 0.0);
  REQUIRE(pk.size() == n);
  std::mt19937_64 rng(7);
  std::vector<Vec> vel(n);
  for (auto& v : vel)
    for (int k = 0; k < D::dim; ++k) v[k] = test::uniform(rng, -1.0, 1.0);  // [m/s]

  auto run = [&](auto search_tag, double skin, std::vector<PairSet>& sets, std::vector<std::vector<Vec>>& xs,
                 std::size_t& builds) {
    using Search = decltype(search_tag);
    SimulationConfig<D> cfg;
    cfg.domain = dom;
    cfg.thickness = 1e-3;
    cfg.skin = skin;
    cfg.dt = 5e-6;
    Simulation<D, contact::HertzFrictionless, Search> sim(cfg);
    const auto mat = sim.add_material(test::soft_material(1.0));
    const auto wmat = sim.add_wall_material(test::soft_material(1.0));
    if (!periodic_all) {
      // Plane walls on the faces of the non-periodic axes.
      for (int k = 1; k < D::dim; ++k) {
        sim.add_wall(geometry::PlaneShape<D>(dom.lo, Vec::Unit(k)), wmat);
        sim.add_wall(geometry::PlaneShape<D>(dom.hi, Vec(-Vec::Unit(k))), wmat);
      }
    }
    for (std::size_t k = 0; k < n; ++k) sim.add_particle(pk[k].x, pk[k].r, mat, vel[k]);
    sim.every(1, [&](auto& s) {
      sets.push_back(test::pairs_from_frame(s.frame()));
      xs.push_back(test::positions_by_id(s));
    }, true);
    sim.run(1500);
    builds = sim.neighbour_list().builds;
    // The recorded set equals the set of the simulation's own positions.
    const auto fr = sim.frame();
    CHECK(test::pairs_from_frame(fr) == test::pairs_from_positions(fr, dom));
  };
  std::vector<PairSet> s_bf, s_vl;
  std::vector<std::vector<Vec>> x_bf, x_vl;
  std::size_t b_bf = 0, b_vl = 0;
  run(neighbours::BruteForce{}, 0.0, s_bf, x_bf, b_bf);
  run(neighbours::VerletList{}, 0.1 * kPolicyRmin, s_vl, x_vl, b_vl);
  REQUIRE(s_bf.size() == 1500);
  REQUIRE(s_vl.size() == 1500);
  std::size_t mismatched_steps = 0, total_contacts = 0, first_bad = 0;
  double max_dx = 0.0;
  for (std::size_t k = 0; k < s_bf.size(); ++k) {
    total_contacts += s_bf[k].size();
    if (s_bf[k] != s_vl[k]) {
      if (mismatched_steps == 0) first_bad = k + 1;
      ++mismatched_steps;
    }
    max_dx = std::max(max_dx, test::max_difference(x_bf[k], x_vl[k]));
  }
  INFO("dim " << D::dim << ": contacts summed over steps " << total_contacts << ", VerletList builds "
              << b_vl << ", max |x_BF - x_VL| = " << max_dx << " m, first mismatch at step " << first_bad);
  CHECK(total_contacts >= 200);  // the gas collides
  CHECK(b_vl >= 20);             // and the Verlet list is rebuilt many times
  CHECK(b_vl < 1500);            // but not every step
  CHECK(mismatched_steps == 0);
  // Without history the two runs differ only by the order of force sums (round-off).
  CHECK(max_dx < 1e-9 * kPolicyRmin);
}

}  // namespace

TEMPLATE_TEST_CASE("Neighbour policies agree at every step of a moving gas", "[engine][neighbours]",
                   Dim2, Dim3) {
  SECTION("periodic along x, walls elsewhere") { check_gas<TestType>(false); }
  SECTION("periodic on all axes") { check_gas<TestType>(true); }
}

// Regression test of a fixed engine bug ("request_contacts"): request_contacts()
// sets a flag that the *next force evaluation* consumes. Before the first step (and after
// set_dt, add_particle, ... which re-initialise) step() first calls initialise(), whose force
// evaluation at the old time records the contacts and clears the flag; the step's own force
// evaluation then records nothing and frame() after the step has no contacts.
// Expected (engine_api.md: "sim.request_contacts(); sim.step(); sim.frame() -> contacts"):
// the frame after the step holds that step's contacts.
TEMPLATE_TEST_CASE("request_contacts before the first step records that step's contacts",
                   "[engine][neighbours]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  SimulationConfig<TestType> cfg;
  cfg.domain.hi = Vec::Constant(0.02);
  cfg.dt = 1e-7;
  cfg.thickness = 1e-3;
  Simulation<TestType, contact::HertzFrictionless> sim(cfg);
  const auto mat = sim.add_material(test::soft_material());
  Vec x = Vec::Constant(0.01);
  sim.add_particle(x, kPolicyRmin, mat);
  x[0] += 1.9 * kPolicyRmin;
  sim.add_particle(x, kPolicyRmin, mat);
  sim.request_contacts();
  sim.step();
  CHECK(sim.contact_count() == 1);
  CHECK(sim.frame().contacts.size() == 1);
  sim.set_dt(2e-7);
  sim.request_contacts();
  sim.step();
  CHECK(sim.frame().contacts.size() == 1);
}

// Reference: the Verlet-list criterion (Verlet 1967; Allen & Tildesley, "Computer Simulation of
// Liquids", 2nd ed., section 5.3): a list built with skin s stays complete while no particle has
// moved more than s/2 since the build. The engine keeps the build positions in single precision
// (neighbours/pair_list.hpp) and subtracts their rounding from s/2, so a particle drifting at
// constant speed must trigger a rebuild at the first step where its true displacement might
// exceed s/2: never after it (that could miss a contact), and not earlier than s/2 less twice
// the rounding bound 2^-24 |x|_inf sqrt(dim). Far from the origin (|x| ~ 100 m) the rounding is
// 3.8 um (2D) and 5.0 um (3D), 4-5 % of s/2 = 100 um here, so the window is resolved by the
// ~1 um steps; near the origin it is below 1e-9 m. The drift is oblique, so that the rounding
// of every coordinate matters.
TEMPLATE_TEST_CASE("The Verlet list rebuilds before any particle has moved half the skin", "[engine][neighbours]",
                   Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  for (const double offset : {0.0, 100.0}) {
    SimulationConfig<D> cfg;
    cfg.domain.lo = Vec::Constant(offset);
    cfg.domain.hi = Vec::Constant(offset + 0.05);
    cfg.dt = 1e-6;
    cfg.skin = 2e-4;
    cfg.thickness = 1e-3;
    Simulation<D, contact::HertzFrictionless, neighbours::VerletList> sim(cfg);
    const auto mat = sim.add_material(test::soft_material());
    const Vec x0 = Vec::Constant(offset + 0.0123456789);
    Vec v = Vec::Zero();
    v[0] = 1.0;  // [m/s]: ~1 um per step
    v[D::dim - 1] = -0.5;
    sim.add_particle(x0, 1e-3, mat, v);
    const auto& list = sim.neighbour_list();
    // The first build is made before the first drift; from the next one on, the list is built
    // from the positions of the step that rebuilds, which is where the rounds below start.
    sim.step();
    const std::size_t first = list.builds;
    for (int k = 0; k < 1000 && list.builds == first; ++k) sim.step();
    REQUIRE(list.builds == first + 1);
    const double bound = std::ldexp(std::abs(offset + 0.05), -24) * std::sqrt(double(D::dim));
    INFO("offset " << offset << " m: rounding of the build positions " << list.build_rounding << " m (bound "
                   << bound << " m)");
    CHECK(list.build_rounding <= bound);
    if (offset > 0.0) CHECK(list.build_rounding > 0.01 * bound);
    for (int round = 0; round < 3; ++round) {
      const std::size_t builds = list.builds;
      const Vec x_build = sim.particles().x[0];
      double before = 0.0;  // true displacement since the build at the last step without a rebuild
      int k = 0;
      while (list.builds == builds && k < 1000) {
        before = (sim.particles().x[0] - x_build).norm();
        sim.step();
        ++k;
      }
      const double at = (sim.particles().x[0] - x_build).norm();
      INFO("round " << round << ": rebuilt after " << k << " steps, displacement " << before << " m before, " << at
                    << " m at the rebuild");
      REQUIRE(list.builds == builds + 1);
      CHECK(before <= 0.5 * cfg.skin);
      CHECK(at > 0.5 * cfg.skin - 2.0 * bound);
    }
  }
}
