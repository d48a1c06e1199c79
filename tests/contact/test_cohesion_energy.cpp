// The energy of the cohesion laws (energy(params, g) of contact/cohesion/*.hpp) and its place in
// ContactModel::stored_energy: the potential of the elastic normal force, zero for a separated
// pair, so that d(stored energy)/d(overlap) = F_n.
//
// References:
//  * derivative: the central difference of the energy in the overlap against the force the
//    same law returns, at h = 1e-4 of the overlap (truncation ~1e-8 relative);
//  * SJKR (001 eq. A6-A7): F_c = k_c pi a^2, a the radius of the intersection circle;
//  * DMT: -2 pi w R* delta (a constant pull while overlapping);
//  * JKR: Johnson's total energy U_T = U_E - w pi a^2 (Johnson, Kendall & Roberts 1971;
//    Johnson, Contact Mechanics 1985, sec. 5.5; Maugis 2000, ch. 5), whose elastic energy U_E is
//    built by loading a Hertz contact to the radius a (P1 = 4 E* a^3 / (3 R*), energy
//    8 E* a^5 / (15 R*^2)) and unloading it at constant radius with the flat-punch stiffness
//    2 a E* to the JKR load P: U_E = 8 E* a^5 / (15 R*^2) - (P1^2 - P^2) / (4 a E*). It is
//    written out here independently of the law's closed form. At the zero-load radius a0 it gives
//    -3/5 pi w a0^2, at the load-controlled pull-off (a^3 = a0^3 / 4) -2/5 pi w a^2, at the break
//    radius a_c +2/5 pi w a_c^2, at touch (delta = 0 on the stable branch, a_t^3 = 2 pi w R*^2 / E*)
//    -3/5 pi w a_t^2 (these four by hand from U_T).
// Material as tests/contact/test_jkr_dmt.cpp: E = 1 MPa, nu = 0.3, gamma = 0.05 J/m^2, r = 1 mm.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>

#include "contact_test_support.hpp"

using namespace granule;
using namespace granule::contact_test;

namespace {

constexpr double kPiCe = std::numbers::pi;
constexpr double kRCe = 1.0e-3;          // particle radius [m]
constexpr double kRstarCe = 0.5 * kRCe;  // R* of two equal spheres [m]
constexpr double kWCe = 2.0 * 0.05;      // work of adhesion 2 gamma [J/m^2]

Material cohesion_energy_material() {
  Material m;
  m.youngs_modulus = 1.0e6;  // [Pa]
  m.poisson_ratio = 0.3;
  m.density = 2500.0;  // [kg/m^3]
  m.restitution = 1.0;
  m.friction = 0.0;
  m.surface_energy = 0.05;
  m.cohesion_energy_density = 2.0e4;  // [J/m^3] (SJKR)
  return m;
}

double ce_e_star() { return 1.0e6 / (2.0 * (1.0 - 0.09)); }

/// A pair geometry at rest with centre distance d along x [m].
template <class D>
contact::ContactGeometry<D> ce_pair_at(double d, double ri, double rj) {
  typename D::Vec xi = D::Vec::Zero(), xj = D::Vec::Zero();
  xi[0] = d;
  const double m = 1e-5;
  return make_pair_geometry<D>(xi, xj, ri, rj, m, m, D::Vec::Zero(), D::Vec::Zero(), D::zero_ang(), D::zero_ang(), 1e-6);
}

/// A particle-wall geometry at rest with overlap delta [m] (distance +inf: flat-contact limit).
template <class D>
contact::ContactGeometry<D> ce_wall_at(double delta, double r) {
  contact::ContactGeometry<D> g = ce_pair_at<D>(2.0 * r - delta, r, r);
  g.distance = std::numeric_limits<double>::infinity();
  g.r_eff = r;
  g.m_eff = 1e-5;
  return g;
}

/// Central difference of f(delta) at delta, step h.
template <class F>
double ce_derivative(F&& f, double delta, double h) {
  return (f(delta + h) - f(delta - h)) / (2.0 * h);
}

// JKR closed forms of the law (F(a), delta(a)) and U_T from the Hertz-load, flat-punch-unload
// construction (file header).
double ce_jkr_force(double a) {
  return 4.0 * ce_e_star() * a * a * a / (3.0 * kRstarCe) - std::sqrt(8.0 * kPiCe * kWCe * ce_e_star() * a * a * a);
}
double ce_jkr_total_energy(double a) {
  const double es = ce_e_star(), p1 = 4.0 * es * a * a * a / (3.0 * kRstarCe), p = ce_jkr_force(a);
  const double ue = 8.0 * es * std::pow(a, 5) / (15.0 * kRstarCe * kRstarCe) - (p1 * p1 - p * p) / (4.0 * a * es);
  return ue - kWCe * kPiCe * a * a;
}

}  // namespace

// SJKR: d/d delta of energy = -k_c A, pair (equal and unequal radii) and wall, 3D and 2D; the
// model's stored energy differentiates to its elastic F_n (Hertz, or linear in 2D, minus k_c A).
// A wrong closed form (e.g. R* delta^2 without the curvature terms) is off by ~delta/r = 1e-3.
TEST_CASE("Cohesion energy: SJKR energy differentiates to its force", "[contact][cohesion][energy]") {
  const Material mat = cohesion_energy_material();
  const PairMaterial pm = mix(mat, mat);
  const double thickness = 2.0e-3;
  const contact::SjkrCohesion::Params p = contact::SjkrCohesion::make(pm, thickness);
  using Model3 = contact::ContactModel<contact::HertzNormal, contact::NoTangential, contact::NoRolling, contact::SjkrCohesion>;
  using Model2 = contact::ContactModel<contact::LinearNormal, contact::NoTangential, contact::NoRolling, contact::SjkrCohesion>;
  const auto prm3 = Model3::make(pm, thickness);
  const auto prm2 = Model2::make(pm, thickness);
  for (const double rj : {kRCe, 0.6 * kRCe}) {
    for (const double frac : {1e-4, 1e-3, 1e-2, 0.1, 0.3}) {
      const double delta = frac * std::min(kRCe, rj), h = 1e-4 * delta;
      INFO("r_j " << rj << ", delta " << delta);
      // 3D pair
      auto e3 = [&](double d) { return contact::SjkrCohesion::energy(p, ce_pair_at<Dim3>(kRCe + rj - d, kRCe, rj)); };
      const auto g3 = ce_pair_at<Dim3>(kRCe + rj - delta, kRCe, rj);
      CHECK(ce_derivative(e3, delta, h) == Approx(-contact::SjkrCohesion::eval(p, g3)).epsilon(1e-7));
      auto s3 = [&](double d) { return Model3::stored_energy(prm3, ce_pair_at<Dim3>(kRCe + rj - d, kRCe, rj), Model3::State<Dim3>{}); };
      Model3::State<Dim3> st3{};
      CHECK(ce_derivative(s3, delta, h) == Approx(Model3::evaluate(prm3, g3, st3).fn).epsilon(1e-7));
      // 2D pair (disks of thickness t)
      auto e2 = [&](double d) { return contact::SjkrCohesion::energy(p, ce_pair_at<Dim2>(kRCe + rj - d, kRCe, rj)); };
      const auto g2 = ce_pair_at<Dim2>(kRCe + rj - delta, kRCe, rj);
      CHECK(ce_derivative(e2, delta, h) == Approx(-contact::SjkrCohesion::eval(p, g2)).epsilon(1e-7));
      auto s2 = [&](double d) { return Model2::stored_energy(prm2, ce_pair_at<Dim2>(kRCe + rj - d, kRCe, rj), Model2::State<Dim2>{}); };
      Model2::State<Dim2> st2{};
      CHECK(ce_derivative(s2, delta, h) == Approx(Model2::evaluate(prm2, g2, st2).fn).epsilon(1e-7));
    }
  }
  for (const double frac : {1e-4, 1e-2, 0.3}) {  // walls
    const double delta = frac * kRCe, h = 1e-4 * delta;
    INFO("wall, delta " << delta);
    auto e3 = [&](double d) { return contact::SjkrCohesion::energy(p, ce_wall_at<Dim3>(d, kRCe)); };
    CHECK(ce_derivative(e3, delta, h) == Approx(-contact::SjkrCohesion::eval(p, ce_wall_at<Dim3>(delta, kRCe))).epsilon(1e-7));
    auto e2 = [&](double d) { return contact::SjkrCohesion::energy(p, ce_wall_at<Dim2>(d, kRCe)); };
    CHECK(ce_derivative(e2, delta, h) == Approx(-contact::SjkrCohesion::eval(p, ce_wall_at<Dim2>(delta, kRCe))).epsilon(1e-7));
  }
  // Zero apart; small overlap: -k_c pi R* delta^2 (3D pair, a^2 -> 2 R* delta).
  CHECK(contact::SjkrCohesion::energy(p, ce_pair_at<Dim3>(2.0 * kRCe + 1e-6, kRCe, kRCe)) == 0.0);
  const double ds = 1e-9;
  CHECK(contact::SjkrCohesion::energy(p, ce_pair_at<Dim3>(2.0 * kRCe - ds, kRCe, kRCe)) ==
        Approx(-p.k_c * kPiCe * kRstarCe * ds * ds).epsilon(1e-5));
}

// DMT: energy -2 pi w R* delta while overlapping, 0 apart; the model's stored energy
// differentiates to Hertz minus the pull.
TEST_CASE("Cohesion energy: DMT energy differentiates to its force", "[contact][cohesion][energy][dmt]") {
  const PairMaterial pm = mix(cohesion_energy_material(), cohesion_energy_material());
  const auto prm = contact::HertzMindlinDmt::make(pm);
  CHECK(contact::DmtCohesion::energy(prm.cohesion, ce_pair_at<Dim3>(2.0 * kRCe + 1e-7, kRCe, kRCe)) == 0.0);
  for (const double delta : {1e-7, 1e-6, 1e-5, 1e-4}) {
    const double h = 1e-4 * delta;
    INFO("delta " << delta);
    const auto g = ce_pair_at<Dim3>(2.0 * kRCe - delta, kRCe, kRCe);
    // (1e-9: the overlap of a pair built from its centres carries ~1e-16 x 2r / delta)
    CHECK(contact::DmtCohesion::energy(prm.cohesion, g) == Approx(-2.0 * kPiCe * kWCe * kRstarCe * g.overlap).epsilon(1e-14));
    CHECK(g.overlap == Approx(delta).epsilon(1e-9));
    auto s = [&](double d) {
      return contact::HertzMindlinDmt::stored_energy(prm, ce_pair_at<Dim3>(2.0 * kRCe - d, kRCe, kRCe),
                                                     contact::HertzMindlinDmt::State<Dim3>{});
    };
    contact::HertzMindlinDmt::State<Dim3> st{};
    CHECK(ce_derivative(s, delta, h) == Approx(contact::HertzMindlinDmt::evaluate(prm, g, st).fn).epsilon(1e-7));
  }
}

// JKR: the slot's energy against U_T (header) at radii from a_c/2 (unstable branch) to 3 a0, the
// three closed values, and d(stored energy)/d delta = F(a(delta)) through the model, from the
// load-controlled pull-off point (F = -3/2 pi w R*, delta = -0.48 |delta_c|) and nearer the
// break (-0.9 |delta_c|) to 5 delta0. The Hertz part counted twice would add 8 E* a^5/(15 R*^2),
// ~4 pi w a^2 at a0: far outside every tolerance here.
TEST_CASE("Cohesion energy: JKR energy is Johnson's total energy and differentiates to F",
          "[contact][cohesion][energy][jkr]") {
  const PairMaterial pm = mix(cohesion_energy_material(), cohesion_energy_material());
  const auto prm = contact::HertzMindlinJkr::make(pm);
  const auto& p = prm.cohesion;
  REQUIRE(p.E_eff == Approx(ce_e_star()).epsilon(1e-14));
  const double es = ce_e_star();
  const double a0 = std::cbrt(9.0 * kPiCe * kWCe * kRstarCe * kRstarCe / (2.0 * es));
  const double ac = std::cbrt(kPiCe * kWCe * kRstarCe * kRstarCe / (8.0 * es));
  const double at = std::cbrt(2.0 * kPiCe * kWCe * kRstarCe * kRstarCe / es);
  // The slot's energy at radius a: its geometry is the elastic one, overlap a^2 / R*.
  auto slot_energy = [&](double a) {
    contact::ContactGeometry<Dim3> g = ce_pair_at<Dim3>(2.0 * kRCe, kRCe, kRCe);
    g.overlap = a * a / kRstarCe;
    return contact::JkrCohesion::energy(p, g);
  };
  for (int k = 0; k <= 60; ++k) {
    const double a = 0.5 * ac + (3.0 * a0 - 0.5 * ac) * k / 60.0;
    INFO("a = " << a);
    CHECK(slot_energy(a) == Approx(ce_jkr_total_energy(a)).margin(1e-12 * kPiCe * kWCe * a0 * a0));
  }
  CHECK(slot_energy(0.0) == 0.0);
  CHECK(slot_energy(a0) == Approx(-0.6 * kPiCe * kWCe * a0 * a0).epsilon(1e-12));
  CHECK(slot_energy(ac) == Approx(0.4 * kPiCe * kWCe * ac * ac).epsilon(1e-12));
  CHECK(slot_energy(at) == Approx(-0.6 * kPiCe * kWCe * at * at).epsilon(1e-12));
  const double a_pf0 = a0 / std::cbrt(4.0);  // the load-controlled pull-off, F = -3/2 pi w R*
  CHECK(slot_energy(a_pf0) == Approx(-0.4 * kPiCe * kWCe * a_pf0 * a_pf0).epsilon(1e-12));
  CHECK(ce_jkr_force(a0) == Approx(0.0).margin(1e-12 * kPiCe * kWCe * kRstarCe));

  // Through the model, in the real overlap.
  const double dc = contact::JkrCohesion::separation(p, kRstarCe), delta0 = a0 * a0 / (3.0 * kRstarCe);
  const double a_pf = a0 / std::cbrt(4.0), delta_pf = -a_pf * a_pf / (3.0 * kRstarCe);
  using M = contact::HertzMindlinJkr;
  auto stored = [&](double d) { return M::stored_energy(prm, ce_pair_at<Dim3>(2.0 * kRCe - d, kRCe, kRCe), M::State<Dim3>{}); };
  for (const double delta : {-0.9 * dc, delta_pf, -0.2 * dc, 0.0, 0.5 * delta0, delta0, 2.0 * delta0, 5.0 * delta0}) {
    const double h = 1e-4 * delta0;
    const double f = contact::JkrCohesion::force(p, contact::JkrCohesion::contact_radius(p, delta, kRstarCe), kRstarCe);
    M::State<Dim3> st{};
    const double fn = M::evaluate(prm, ce_pair_at<Dim3>(2.0 * kRCe - delta, kRCe, kRCe), st).fn;
    INFO("delta " << delta << " (delta0 " << delta0 << ", -delta_c " << -dc << "), F " << f);
    CHECK(fn == Approx(f).margin(1e-12 * 1.5 * kPiCe * kWCe * kRstarCe));
    CHECK(ce_derivative(stored, delta, h) == Approx(f).margin(1e-7 * 1.5 * kPiCe * kWCe * kRstarCe));
  }
  CHECK(contact::JkrCohesion::force(p, a_pf, kRstarCe) == Approx(-1.5 * kPiCe * kWCe * kRstarCe).epsilon(1e-12));
  CHECK(stored(0.0) == Approx(-0.6 * kPiCe * kWCe * at * at).epsilon(1e-9));
}

namespace {

/// Two equal adhesive spheres on the x axis, centres +-(r - overlap0 / 2), moving apart at
/// v_sep (negative: approaching); e = 1 (no damping), no friction, no gravity.
struct CeJkrPair {
  Simulation<Dim3, contact::HertzMindlinJkr> sim;
  CeJkrPair(double overlap0, double v_sep, double dt = 1.0e-6) : sim(config(dt)) {
    const auto pm = sim.add_material(cohesion_energy_material());
    const double h = kRCe - 0.5 * overlap0;
    sim.add_particle(Eigen::Vector3d(h, 0.0, 0.0), kRCe, pm, Eigen::Vector3d(0.5 * v_sep, 0.0, 0.0));
    sim.add_particle(Eigen::Vector3d(-h, 0.0, 0.0), kRCe, pm, Eigen::Vector3d(-0.5 * v_sep, 0.0, 0.0));
  }
  static SimulationConfig<Dim3> config(double dt) {
    SimulationConfig<Dim3> cfg;
    cfg.domain.lo = Eigen::Vector3d::Constant(-0.01);
    cfg.domain.hi = Eigen::Vector3d::Constant(0.01);
    cfg.dt = dt;
    return cfg;
  }
  double overlap() const {
    const auto& p = sim.particles();
    return 2.0 * kRCe - (p.x[sim.index_of(0)] - p.x[sim.index_of(1)]).norm();
  }
  double energy() { return sim.kinetic_energy() + sim.elastic_energy(); }
};

}  // namespace

// An undamped JKR pair released at rest at delta_s = 0.05 delta0 oscillates in its well
// (between delta_s and ~1.9 delta0, ~25 periods of ~1.6e3 steps): kinetic + stored energy is
// constant to velocity Verlet's error, O(dt^2) and bounded (a symplectic integrator). Measured
// (2026-12-07): largest |E - E0| = 9.4e-7 of the well depth |U(a0)| = 3/5 pi w a0^2 over 40000
// steps, the same in both halves (no trend). Tolerance 1e-5 of the depth; the stored energy
// without the JKR surface term (the Hertz energy alone, as before) swings by ~7 depths.
TEST_CASE("Cohesion energy: an undamped JKR pair conserves kinetic + stored energy",
          "[contact][cohesion][energy][jkr]") {
  const double es = ce_e_star();
  const double a0 = std::cbrt(9.0 * kPiCe * kWCe * kRstarCe * kRstarCe / (2.0 * es)), delta0 = a0 * a0 / (3.0 * kRstarCe);
  const double depth = 0.6 * kPiCe * kWCe * a0 * a0;
  CeJkrPair pr(0.05 * delta0, 0.0);
  const double e0 = pr.energy();
  double worst = 0.0, first_half = 0.0, second_half = 0.0, dmax = 0.0;
  const int n = 40000;
  for (int s = 0; s < n; ++s) {
    pr.sim.step();
    REQUIRE(pr.sim.contact_count() == 1);
    const double dev = std::abs(pr.energy() - e0) / depth;
    worst = std::max(worst, dev);
    (s < n / 2 ? first_half : second_half) = std::max(s < n / 2 ? first_half : second_half, dev);
    dmax = std::max(dmax, pr.overlap());
  }
  INFO("E0 " << e0 << " J (depth " << depth << " J); largest |E - E0| / depth " << worst << " (first half " << first_half
             << ", second " << second_half << "); largest overlap " << dmax / delta0 << " delta0");
  CHECK(e0 < 0.0);
  CHECK(dmax > 1.5 * delta0);
  CHECK(worst < 1e-5);
  CHECK(second_half < 2.0 * first_half + 1e-6);
}

// Approach at v, touch, rebound and break (e = 1, so the contact dissipates only its hysteresis):
// kinetic + stored energy drops at touch by 3/5 pi w a_t^2 and at the break by 2/5 pi w a_c^2
// (the jumps of the stored energy at constant overlap, cohesion/jkr.hpp) and is constant
// between; so the pair leaves with 1/2 m* v_out^2 = 1/2 m* v^2 - (3/5 pi w a_t^2 + 2/5 pi w a_c^2),
// the area of the JKR hysteresis loop (3.5 % of the impact energy at 0.1 m/s). Touch and break
// fall inside a step (dt = 0.2 us here, v dt = 2e-8 m of overlap), which moves the energy by
// up to |F| v dt at each, 0.5 % of the loss. Measured (2026-12-07): loss 0.25 % above the
// loop's area, the drop at touch 0.25 % above 3/5 pi w a_t^2, energy in contact constant to
// 2e-5 of the loss over 4391 steps. Tolerances 1 %, 1 %, 2e-4.
TEST_CASE("Cohesion energy: a JKR collision loses the hysteresis loop's area", "[contact][cohesion][energy][jkr]") {
  const double es = ce_e_star();
  const double ac = std::cbrt(kPiCe * kWCe * kRstarCe * kRstarCe / (8.0 * es));
  const double at = std::cbrt(2.0 * kPiCe * kWCe * kRstarCe * kRstarCe / es);
  const double loss = kPiCe * kWCe * (0.6 * at * at + 0.4 * ac * ac);
  const double v = 0.1;
  CeJkrPair pr(-1.0e-7, -v, 2.0e-7);
  const double e_in = pr.energy();
  bool touched = false, broken = false;
  double e_touch_min = 0.0, e_touch_max = -1.0;  // kinetic + stored while in contact (after the touch step)
  int in_contact = 0;
  for (int s = 0; s < 200000 && !broken; ++s) {
    pr.sim.step();
    if (pr.sim.contact_count() == 1) {
      const double e = pr.energy();
      if (touched) {
        e_touch_min = std::min(e_touch_min, e);
        e_touch_max = std::max(e_touch_max, e);
      } else {
        touched = true;
        e_touch_min = e_touch_max = e;
      }
      ++in_contact;
    } else if (touched) {
      broken = true;
    }
  }
  REQUIRE(broken);
  const double e_out = pr.energy();
  const double ke_out = pr.sim.kinetic_energy();
  INFO("impact energy " << e_in << " J, loss (theory) " << loss << " J, measured " << e_in - e_out << " J ("
                        << (e_in - e_out) / loss - 1.0 << " relative); in contact " << in_contact
                        << " steps, energy in contact spread " << e_touch_max - e_touch_min << " J, below impact "
                        << e_in - e_touch_max << " J (theory " << 0.6 * kPiCe * kWCe * at * at << " J)");
  CHECK(e_out == Approx(ke_out).margin(0.0));
  CHECK(e_in - e_out == Approx(loss).epsilon(0.01));
  // In contact the energy is constant (no jump inside the contact).
  CHECK(e_touch_max - e_touch_min < 2e-4 * loss);
  // and it sits 3/5 pi w a_t^2 below the impact energy.
  CHECK(e_in - e_touch_max == Approx(0.6 * kPiCe * kWCe * at * at).epsilon(0.01));
}

// d delta_H / d delta of the JKR law (JkrCohesion::elastic_overlap_slope) against the central
// difference of elastic_overlap in the real overlap (h = 1e-5 of delta0), from near the break
// to 5 delta0; 6/5 at the zero-load radius a0 and 3/2 at the load-controlled pull-off a0/4^1/3
// (by hand from delta(a), Johnson 1985 sec. 5.5: 1 / (1 - (a_c/a)^3/2), (a_c/a0)^3 = 1/36); the
// cap at and beyond the break.
TEST_CASE("Cohesion energy: JKR elastic overlap slope is d delta_H / d delta", "[contact][cohesion][energy][jkr]") {
  const PairMaterial pm = mix(cohesion_energy_material(), cohesion_energy_material());
  const auto& p = contact::HertzMindlinJkr::make(pm).cohesion;
  using J = contact::JkrCohesion;
  const double es = ce_e_star();
  const double a0 = std::cbrt(9.0 * kPiCe * kWCe * kRstarCe * kRstarCe / (2.0 * es)), delta0 = a0 * a0 / (3.0 * kRstarCe);
  const double dc = J::separation(p, kRstarCe);
  CHECK(J::elastic_overlap_slope(p, a0 * a0 / kRstarCe, kRstarCe) == Approx(1.2).epsilon(1e-12));
  const double a_pf = a0 / std::cbrt(4.0);
  CHECK(J::elastic_overlap_slope(p, a_pf * a_pf / kRstarCe, kRstarCe) == Approx(1.5).epsilon(1e-12));
  for (const double delta : {-0.99 * dc, -0.9 * dc, -0.5 * dc, 0.0, delta0, 5.0 * delta0}) {
    const double h = 1e-5 * delta0;
    const double fd = ce_derivative([&](double d) { return J::elastic_overlap(p, d, kRstarCe); }, delta, h);
    const double slope = J::elastic_overlap_slope(p, J::elastic_overlap(p, delta, kRstarCe), kRstarCe);
    INFO("delta " << delta << " (-delta_c " << -dc << "): slope " << slope << ", difference " << fd);
    CHECK(slope == Approx(fd).epsilon(1e-6));
  }
  CHECK(J::elastic_overlap_slope(p, J::elastic_overlap(p, -dc, kRstarCe), kRstarCe) == J::max_elastic_overlap_slope);
  CHECK(J::elastic_overlap_slope(p, J::elastic_overlap(p, -2.0 * dc, kRstarCe), kRstarCe) == J::max_elastic_overlap_slope);
}

// A sphere hanging from a ceiling by JKR adhesion (sphere-wall: R* = r, E* = E/(1 - nu^2)) under
// a gravity that pulls with m g = pi w r, released with its contact at F = -0.8 pi w r and a
// sideways velocity: the overlap oscillates with F between ~-0.8 and ~-1.2 pi w r (the pull
// never comes near zero, so mu |F_n| stays large), the contact radius between ~0.8 and ~0.9 a0
// (d delta_H / d delta ~ 1.3), and the tangential spring (mu = 1) swings to ~0.7 of the Coulomb
// limit and sticks, at its own period (tangential + rolling), so the contact's (delta, xi)
// encloses area every cycle. e = 1: no damping. Kinetic (translation + rotation) + stored +
// gravitational energy is then constant to velocity Verlet's error only if the normal force
// carries the tangential spring's coupling d/d delta [k_t(delta_H) |xi|^2 / 2] =
// k_t'(delta_H) (d delta_H / d delta) |xi|^2 / 2 with the JKR factor d delta_H / d delta (the
// chain rule through a(delta): delta(a) of Johnson, Kendall & Roberts 1971 and Johnson 1985
// sec. 5.5; k_t = 8 G* a of Mindlin 1949).
// Measured (2026-12-07, dt = 1 us, 30000 steps, ~20 normal periods): largest |E - E0| = 1.0e-2 of
// the spring's largest energy with the coupling differentiated in delta_H only (the factor
// missing, as before the fix), 1.5e-5 with it (4.0e-6 at dt = 0.5 us: O(dt^2), velocity Verlet's).
// Tolerance 1e-4.
TEST_CASE("Cohesion energy: a sticking frictional JKR contact conserves energy", "[contact][cohesion][energy][jkr]") {
  Material m = cohesion_energy_material();
  m.friction = 1.0;
  const double es = 1.0e6 / (1.0 - 0.09), r = kRCe;  // E* and R* against a rigid wall
  const double mass = 2500.0 * 4.0 / 3.0 * kPiCe * r * r * r;
  const double pull = kPiCe * kWCe * r;
  const contact::JkrCohesion::Params p{kWCe, es};
  const double a0 = std::cbrt(9.0 * kPiCe * kWCe * r * r / (2.0 * es)), a_pf = a0 / std::cbrt(4.0);
  // a_s on the branch a_pf < a < a0 (F increasing) with F(a_s) = -0.8 pi w r.
  double lo = a_pf, hi = a0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (contact::JkrCohesion::force(p, mid, r) < -0.8 * pull ? lo : hi) = mid;
  }
  const double a_s = 0.5 * (lo + hi);
  const double delta_s = a_s * a_s / r - std::sqrt(2.0 * kPiCe * kWCe * a_s / es);
  // The sideways speed that loads the spring to ~0.7 of mu |F_n|: k_t xi_max ~ v sqrt(k_t m_t),
  // m_t = m / 3.5 (the contact point of a free solid sphere, 1/m + r^2/I).
  const double kt = 8.0 * (1.0e6 / (2.0 * 1.7 * 1.3)) * a_s;  // k_t = 8 G* a, G* = E / (2 (2 - nu)(1 + nu))
  const double v_x = 0.7 * 0.8 * pull / std::sqrt(kt * mass / 3.5);

  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Eigen::Vector3d::Constant(-0.01);
  cfg.domain.hi = Eigen::Vector3d::Constant(0.01);
  cfg.dt = 1.0e-6;
  cfg.gravity = Eigen::Vector3d(0.0, 0.0, -pull / mass);
  Simulation<Dim3, contact::HertzMindlinJkr> sim(cfg);
  const auto pm = sim.add_material(m);
  const auto wm = sim.add_wall_material(Material::rigid_wall());
  sim.add_wall(geometry::PlaneShape<Dim3>(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -1)), wm);
  sim.add_particle(Eigen::Vector3d(0.0, 0.0, -(r - delta_s)), r, pm, Eigen::Vector3d(v_x, 0.0, 0.0));
  sim.record_contacts_every_step();
  auto energy = [&] { return sim.kinetic_energy() + sim.elastic_energy() + sim.gravitational_energy(); };
  const double e0 = energy();
  double worst = 0.0, stick = 0.0, fmin = 0.0, fmax = -1e300, spring = 0.0;
  const int n = 30000;
  for (int s = 0; s < n; ++s) {
    sim.step();
    REQUIRE(sim.contact_count() == 1);
    REQUIRE(sim.recorded_contacts().size() == 1);
    const auto& c = sim.recorded_contacts()[0];
    stick = std::max(stick, c.ft.norm() / (c.mu * std::abs(c.fn)));
    fmin = std::min(fmin, c.fn);
    fmax = std::max(fmax, c.fn);
    spring = std::max(spring, 0.5 * c.ft.squaredNorm() / kt);
    worst = std::max(worst, std::abs(energy() - e0));
  }
  INFO("F_n in [" << fmin / pull << ", " << fmax / pull << "] pi w r; largest |F_t| / (mu |F_n|) " << stick
                  << "; spring energy up to " << spring << " J; largest |E - E0| " << worst << " J = " << worst / spring
                  << " of it");
  CHECK(fmax < -0.7 * pull);
  CHECK(fmin > -1.4 * pull);
  CHECK(stick < 0.9);
  CHECK(stick > 0.3);
  CHECK(worst < 1e-4 * spring);
}
