// Oblique and grazing impacts with friction, particle on a plane wall and particle on particle,
// 2D and 3D: energy bookkeeping at every step (kinetic + rotational + elastic energy stored in
// the contact, Simulation::elastic_energy), the two Coulomb truncations, and the rebound in the
// gross-sliding regime against rigid-body impulse theory.
//
// A LAMMPS wall law once gained 34 % of the impact energy at grazing incidence; the checks
// below would catch such a gain both at the end of the contact and during it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include "contact_test_support.hpp"

using namespace granule;
using namespace granule::contact_test;

namespace {

constexpr double kPi = std::numbers::pi;

Material impact_material(double e, double mu) {
  Material m;
  m.youngs_modulus = 1.0e7;  // [Pa]
  m.poisson_ratio = 0.3;     // [-]
  m.density = 2500.0;        // [kg/m^3]
  m.restitution = e;
  m.friction = mu;
  m.normal_stiffness = 2.0e3;  // [N/m], used by the linear laws only
  return m;
}

struct ObliqueResult {
  double max_excess = -1.0;  ///< max over steps of (E_kin + E_rot + E_elastic - E0) / E0
  double final_ratio = 0.0;  ///< (E_kin + E_rot) after the contact / E0
  double vt_after = 0.0;     ///< particle i: tangential centre velocity after [m/s]
  double spin_after = 0.0;   ///< particle i: spin about the rolling axis x lever arm [m/s]
  double vc_after = 0.0;     ///< wall: tangential contact-point velocity after [m/s]
  double coulomb_max = 0.0;  ///< max |F_t| / (mu |F_n|) over the contact (contacts recorded)
  double coulomb_min_sliding = 1.0;  ///< min of the same while |v_t(contact)| > 5 % of v_t0
};

// Impact at speed v and angle `theta` [rad] from the normal. Wall: the particle falls on the
// plane (normal "up") moving in +x. Pair: particle i moves along -up towards a resting equal
// particle j placed so that the normal at first touch makes the angle theta with -v.
// dt = (Hertz time of the normal impact) / steps for both laws (the linear law's period is
// longer, so it is resolved more finely).
template <class D, class Model>
ObliqueResult run_oblique(double e, double mu, double theta, bool wall, bool record = false,
                          int steps = 2000) {
  using Vec = typename D::Vec;
  const Material mat = impact_material(e, mu);
  const double r = 2.0e-3, v = 1.0, t = 1.0e-3;  // [m], [m/s], [m]
  const double m = mass_of<D>(mat.density, r, t);
  const double E_eff = mat.youngs_modulus / (2.0 * (1.0 - mat.poisson_ratio * mat.poisson_ratio));
  const double vn = v * std::cos(theta);
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.dt = hertz_duration_exact(wall ? m : 0.5 * m, E_eff, wall ? r : 0.5 * r, vn) / steps;
  cfg.thickness = t;
  Simulation<D, Model> sim(cfg);
  const auto pm = sim.add_material(mat);
  const Vec n = up<D>(), tx = unit<D>(0);
  const double gap = 3.3 * vn * cfg.dt;
  std::uint64_t id = 0;
  if (wall) {
    sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), n), sim.add_wall_material(mat));
    id = sim.add_particle(Vec((r + gap) * n), r, pm, Vec(v * (std::sin(theta) * tx - std::cos(theta) * n)));
  } else {
    const Vec n0 = std::cos(theta) * n + std::sin(theta) * tx;
    id = sim.add_particle(Vec(2.0 * r * n0 + gap * n), r, pm, Vec(-v * n));
    sim.add_particle(Vec::Zero(), r, pm);
  }
  auto& p = sim.particles();
  const double E0 = sim.kinetic_energy();
  ObliqueResult out;
  bool touched = false;
  int after = 0;
  for (int k = 0; k < 50 * steps; ++k) {
    if (record) sim.request_contacts();
    sim.step();
    out.max_excess = std::max(out.max_excess, (sim.kinetic_energy() + sim.elastic_energy() - E0) / E0);
    if (record) {
      for (const auto& c : sim.frame().contacts) {
        const double lim = mu * std::abs(c.fn);
        if (lim <= 0.0) continue;
        const double ratio = c.ft.norm() / lim;
        out.coulomb_max = std::max(out.coulomb_max, ratio);
        const std::size_t i = c.i;
        Vec vc = p.v[i] - (r - c.overlap) * D::cross(p.omega[i], Vec(c.normal));
        if (!wall) {
          const std::size_t j = c.j;
          vc -= p.v[j] + (r - c.overlap) * D::cross(p.omega[j], Vec(c.normal));
        }
        vc -= vc.dot(c.normal) * c.normal;
        if (vc.norm() > 0.05 * v * std::sin(theta)) out.coulomb_min_sliding = std::min(out.coulomb_min_sliding, ratio);
      }
    }
    if (sim.contact_count() > 0) touched = true;
    if (touched && sim.contact_count() == 0 && ++after > 3) break;
  }
  const std::size_t i = sim.index_of(id);
  out.final_ratio = sim.kinetic_energy() / E0;
  out.vt_after = p.v[i][0];
  out.spin_after = spin_about_rolling_axis(p.omega[i]) * r;
  out.vc_after = (p.v[i] - r * D::cross(p.omega[i], n))[0];
  return out;
}

// Energy tolerance at 2000 steps per contact (justified at the linear e = 1 test below).
constexpr double kEnergyTolerance = 3e-6;
// The same for the Hertz-Mindlin potential form (the default): its excess is the first-order
// error of the stick/slip switches too, about twice the linear law's. Measured max excess over
// 10, 15, 20 deg (3D wall, e = 1, mu = 0.5): 1.4e-5, 7.1e-6, 3.6e-6, 1.8e-6 with 1000, 2000,
// 4000, 8000 steps per contact (halving with dt: no energy source), where the LIGGGHTS 3.8
// displacement form without the normal coupling gains 1.9 % at every step size.
constexpr double kEnergyToleranceHertz = 1e-5;

const double kAnglesDeg[] = {5.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 88.0, 89.5};

}  // namespace

// Hertz-Mindlin force-form spring with the legacy truncation (limit on the spring force only):
// the same history as HertzMindlin, so without damping the two truncations must coincide.
using HertzMindlinSpringOnly =
    contact::ContactModel<contact::HertzNormal,
                          contact::SpringTangential<contact::MindlinStiffness, contact::Truncation::SpringOnly>>;

// Reference: energy balance of a passive contact (no source of energy in a spring-dashpot-slider
// law): the kinetic energy after separation cannot exceed the impact energy. Tolerance 1e-9
// relative (velocity Verlet conserves the energy of a purely elastic impact to ~1e-10 here).
// The elastic (e = 1) laws have no damping at all, so both truncations must then coincide; they
// are compared on the same (force-form) spring history. The LIGGGHTS 3.8 law
// (HertzMindlinLegacy: displacement history and the spring-only limit) is checked for the net
// balance only: its spring gains energy while the contact loads, but returns it on unloading
// (see the per-step test below). Until the force form existed this test compared HertzMindlin
// with HertzMindlinLegacy directly, which then differed in the truncation only.
TEMPLATE_TEST_CASE("Oblique impacts: no energy is gained over the contact (Hertz-Mindlin, both truncations)",
                   "[contact][energy][oblique]", Dim2, Dim3) {
  using D = TestType;
  for (const bool wall : {true, false}) {
    for (const double e : {1.0, 0.5}) {
      for (const double deg : kAnglesDeg) {
        const double th = deg * kPi / 180.0;
        const auto total = run_oblique<D, contact::HertzMindlin>(e, 0.5, th, wall);
        const auto spring_only = run_oblique<D, HertzMindlinSpringOnly>(e, 0.5, th, wall);
        const auto legacy = run_oblique<D, contact::HertzMindlinLegacy>(e, 0.5, th, wall);
        INFO("dim " << D::dim << (wall ? " wall" : " pair") << " e = " << e << " angle " << deg
                    << ": E_after/E0 Total " << total.final_ratio << ", SpringOnly " << spring_only.final_ratio
                    << ", LIGGGHTS 3.8 legacy " << legacy.final_ratio);
        CHECK(total.final_ratio <= 1.0 + 1e-9);
        CHECK(spring_only.final_ratio <= 1.0 + 1e-9);
        CHECK(legacy.final_ratio <= 1.0 + 1e-9);
        if (e == 1.0) CHECK(total.final_ratio == Approx(spring_only.final_ratio).epsilon(1e-12));
      }
    }
  }
}

// Reference: a constant-stiffness spring with a Coulomb slider and no dashpot (Cundall & Strack
// 1979 with e = 1) is conservative while it sticks and dissipative while it slides, so
// E_kin + E_rot + k_n delta^2/2 + k_t |xi|^2/2 can never exceed E0. Tolerance 3e-6 relative:
// 1e-6 for round-off and the O((omega dt)^2) velocity-Verlet error of the smooth parts (measured
// 3e-8 frictionless), plus the first-order error of the non-smooth slider, each stick/slip switch
// being resolved to within one step: measured max excess 3.3e-6, 1.6e-6, 7.6e-7, 3.7e-7 with
// 1000, 2000, 4000, 8000 steps per contact (2000 here).
TEMPLATE_TEST_CASE("Oblique impacts, linear spring-dashpot with e = 1: energy never grows at any step",
                   "[contact][energy][oblique]", Dim2, Dim3) {
  using D = TestType;
  for (const bool wall : {true, false}) {
    for (const double deg : kAnglesDeg) {
      const auto res = run_oblique<D, contact::LinearSpringDashpot>(1.0, 0.5, deg * kPi / 180.0, wall);
      INFO("dim " << D::dim << (wall ? " wall" : " pair") << " angle " << deg << ": max (E - E0)/E0 = "
                  << res.max_excess);
      CHECK(res.max_excess <= kEnergyTolerance);
    }
  }
}

// Reference: energy balance as above, now for the Mindlin spring, whose stiffness
// k_t = 8 G* sqrt(R* delta) changes during the contact. Formerly (docs/physics.md, "Tangential
// laws", "Displacement history") the spring was F_t = -k_t(delta) xi with xi the total
// tangential displacement; then d/dt (k_t |xi|^2 / 2) - F_t . v_t = (dk_t/dt) |xi|^2 / 2 > 0 while
// the contact loads: the stored energy rose without work (a closed load-shear-unload cycle gains
// (k_2 - k_1) xi^2 / 2; the path-independent-law problem of Elata & Berryman 1996). Measured
// (e = 1, mu = 0.5): up to +2.6 % of the impact energy at 25 deg on a wall (3D), +1.3 % for a
// pair; the excess disappeared again on unloading (E_after < E0), which is why the net balance
// above did not see it. The spring now keeps its force as history and increments it,
// F_s <- F_s - k_t v_t dt (Thornton et al. 2013, Powder Technol. 233, eq. 18), scaled by
// k_t / k_t,old when the stiffness falls, with stored energy |F_s|^2 / (2 k_t)
// (contact/tangential/spring.hpp, SpringHistory::IncrementalForce): passive, so the per-step
// excess is bounded by the same integration tolerance as for the constant-stiffness law.
TEMPLATE_TEST_CASE("Oblique impacts, Hertz-Mindlin with e = 1: energy never grows at any step",
                   "[contact][energy][oblique]", Dim2, Dim3) {
  using D = TestType;
  for (const bool wall : {true, false}) {
    for (const double deg : kAnglesDeg) {
      const auto res = run_oblique<D, contact::HertzMindlin>(1.0, 0.5, deg * kPi / 180.0, wall);
      const auto inc = run_oblique<D, contact::HertzMindlinIncremental>(1.0, 0.5, deg * kPi / 180.0, wall);
      INFO("dim " << D::dim << (wall ? " wall" : " pair") << " angle " << deg << ": max (E - E0)/E0 = "
                  << res.max_excess << ", force history with rescale " << inc.max_excess);
      CHECK(res.max_excess <= kEnergyToleranceHertz);
      CHECK(inc.max_excess <= kEnergyTolerance);
    }
  }
}

// Reference: Coulomb's law of sliding friction (|F_t| = mu |F_n| while the contact slides) and
// the energy balance. Formerly (docs/physics.md, "Tangential laws", `Truncation::Total`)
// Truncation::Total reset the spring to the limited force MINUS the dashpot force, F_s = F_lim +
// gamma_t v_t (Luding 2008 eq. 17 / LAMMPS convention). While the dashpot force gamma_t |v_t|
// exceeds mu |F_n| (early and late in a sliding contact: gamma_t ~ delta^1/4, mu F_n ~ delta^3/2)
// that loaded the spring forwards with energy (mu F_n + gamma_t v_t)^2/(2 k_t) that no work had
// put in, and on a later step the force fell below the Coulomb value although the contact still
// slid fast. Measured (HertzMindlin, e = 0.5, mu = 0.5, 3D wall): the stored energy exceeded E0
// by up to 23 % (60 deg); while sliding |F_t| dropped to 1-2 % of mu |F_n| (85-88 deg) and the
// friction impulse was 9 % below mu int |F_n| dt. The spring-dashpot element is now relaxed
// implicitly to the limited force, -k_t xi_new - gamma_t (xi_new - xi_old)/dt = F_lim with xi_old
// the projected history before this step's increment (spring.hpp): the dashpot sees the rate of
// the element, not the slip. Checked for both spring histories (Mindlin force form, linear
// displacement form): no energy gain at any step and |F_t| never above mu |F_n| at every angle;
// |F_t| = mu |F_n| while sliding where the contact slides throughout (85, 88 deg).
// "Sliding" is detected as a contact-point velocity above 5 % of the initial one, which is only
// valid there. At 45 and 60 deg the contact sticks part of the time while the contact points
// still move: with tangential compliance the spring takes up the motion, and sliding stops once
// |v_c| < mu dF_n/dt / k_t (= mu E* / (4 G*) |v_n| = 0.61 |v_n| for Hertz-Mindlin here;
// measured: stick starts at 45 deg when |v_c| = 0.37 v_t0 = 0.61 |v_n|), after which the spring
// even reverses v_c (Maw, Barber & Fawcett 1976; the reversal test below). The first version of
// this test applied the 5 % criterion at every angle; it failed at 45 and 60 deg in these elastic
// stick phases, not in sliding. Gross sliding throughout: tan(theta) > mu (1 + e)(1 + 1/k).
TEMPLATE_TEST_CASE("Oblique impacts with damping, Truncation::Total: energy never grows, Coulomb force while sliding",
                   "[contact][energy][oblique]", Dim2, Dim3) {
  using D = TestType;
  const double mu = 0.5, e = 0.5;
  for (const bool wall : {true, false}) {
    for (const double deg : {45.0, 60.0, 85.0, 88.0}) {
      const double th = deg * kPi / 180.0;
      const bool gross_sliding = std::tan(th) > mu * (1.0 + e) * (1.0 + 1.0 / D::inertia_factor);
      REQUIRE(gross_sliding == (deg > 80.0));
      const auto h = run_oblique<D, contact::HertzMindlin>(e, mu, th, wall, true);
      const auto l = run_oblique<D, contact::LinearSpringDashpot>(e, mu, th, wall, true);
      INFO("dim " << D::dim << (wall ? " wall" : " pair") << " angle " << deg << ": HertzMindlin max excess "
                  << h.max_excess << ", min |F_t|/mu|F_n| while |v_c| > 5 % " << h.coulomb_min_sliding
                  << ", max " << h.coulomb_max << "; LinearSpringDashpot " << l.max_excess << ", "
                  << l.coulomb_min_sliding << ", " << l.coulomb_max);
      CHECK(h.max_excess <= kEnergyToleranceHertz);
      CHECK(l.max_excess <= kEnergyTolerance);
      CHECK(h.coulomb_max <= 1.0 + 1e-9);
      CHECK(l.coulomb_max <= 1.0 + 1e-9);
      if (gross_sliding) {
        CHECK(h.coulomb_min_sliding >= 1.0 - 1e-9);
        CHECK(l.coulomb_min_sliding >= 1.0 - 1e-9);
      }
    }
  }
}

// Reference: rigid-body impulse theory of an impact with gross sliding throughout (e.g.
// Brilliantov & Poeschel 2004 ch. 1; Maw, Barber & Fawcett 1976, the gross-slip branch): the
// friction impulse is mu times the normal impulse m (1 + e) v_n, so
//   v_t' = v_t - mu (1 + e) v_n,    omega' r = mu (1 + e) v_n / k     (k = I / (m r^2)),
// valid when tan(theta) > mu (1 + e)(1 + 1/k). Elastic case (e = 1, no dashpot, both truncations
// identical) at 85 and 88 deg. Tolerances: v_t' to 0.3 % of the change (measured 1e-6); the spin
// to 1.5 %, because the friction acts at the contact point, r - delta(t) from the centre, and
// delta_max / r = 1.1 % at 85 deg (measured spin 0.9 % and 0.4 % below the rigid value at 85 and
// 88 deg). A missing 1/k, a lever arm 2 r or a sign error fails by > 40 %.
// Qualitative check after Maw, Barber & Fawcett (1976, Fig. 1-4): with tangential compliance the
// tangential velocity of the contact point is reversed (Psi2 < 0) over a range of intermediate
// incidence below gross slip, where rigid theory predicts it stops (Psi2 = 0); the normalised
// angles are Psi = 2 (1 - nu) / (mu (2 - nu)) v_t,contact / v_n.
TEMPLATE_TEST_CASE("Oblique impact on a wall: gross-sliding rebound and spin (impulse theory), Maw reversal",
                   "[contact][friction][oblique]", Dim2, Dim3) {
  using D = TestType;
  const double mu = 0.5, e = 1.0, k = D::inertia_factor;
  for (const double deg : {85.0, 88.0}) {
    const double th = deg * kPi / 180.0;
    const double vn = std::cos(th), vt = std::sin(th);
    REQUIRE(std::tan(th) > mu * (1.0 + e) * (1.0 + 1.0 / k));
    const auto res = run_oblique<D, contact::HertzMindlin>(e, mu, th, true);
    const double dv = mu * (1.0 + e) * vn;
    INFO("dim " << D::dim << " angle " << deg << ": v_t' = " << res.vt_after << " (theory " << vt - dv
                << "), omega' r = " << res.spin_after << " (theory " << dv / k << ")");
    CHECK(vt - res.vt_after == Approx(dv).epsilon(3e-3));
    CHECK(res.spin_after == Approx(dv / k).epsilon(0.015));
    CHECK(res.spin_after < dv / k);  // lever arm r - delta < r
  }
  // Reversal of the contact-point velocity at intermediate incidence (qualitative).
  const double psi_scale = 2.0 * (1.0 - 0.3) / (mu * (2.0 - 0.3));
  double psi2_min = 0.0;
  for (const double deg : {40.0, 50.0, 60.0}) {
    const double th = deg * kPi / 180.0;
    const auto res = run_oblique<D, contact::HertzMindlin>(e, mu, th, true);
    const double psi1 = psi_scale * std::tan(th);
    const double psi2 = psi_scale * res.vc_after / std::cos(th);
    WARN("dim " << D::dim << " Maw et al. angles: Psi1 = " << psi1 << " -> Psi2 = " << psi2);
    psi2_min = std::min(psi2_min, psi2);
  }
  CHECK(psi2_min < -0.3);
}

// ---- Chung & Ooi (2011), Test 4 -------------------------------------------------------------
// Reference: Y. C. Chung & J. Y. Ooi, "Benchmark tests for verifying discrete element modelling
// codes at particle impact level", Granular Matter 13 (2011) 643-656, Test 4: oblique impact of a
// sphere on a rigid plane at a constant speed of 3.9 m/s and incidence angles 5-85 deg
// (from the normal), aluminium oxide: R = 2.5 mm, rho = 4000 kg/m^3, E = 380 GPa, nu = 0.23,
// mu = 0.092, e = 0.98; the published curves are the tangential restitution v_t'/v_t, the
// rebound angular velocity and the rebound angle of the contact patch, atan(v_c'/v_n'), against
// the incidence angle. (Issue 29 calls this "Test 6"; in the paper Test 6 is the impact at a
// constant normal speed with varying spin.) The points below are the paper's curves as digitised
// for the Kratos DEM application's benchmark data (DEMApplication/tests/DEM3D_chung_ooi_tests/
// test4_data/paper_data, read there, not copied from code): the incidence angle of each point
// is the digitised abscissa (it scatters by up to 0.2 deg around the nominal 5, 10, ... deg) and
// is used as given. The paper gives the spin as negative (its axis); here it is the forward
// rolling spin, so the sign is flipped.
// The rigid plane is a wall of 1e6 E (its 1/E* and 1/G* terms are 1e-6 of the sphere's), with the
// sphere's e and mu, so the mixed pair values are the sphere's.
// Tolerances: e_t within 0.02, the spin within 15 rad/s (2.4 % of the peak 617 rad/s), the
// rebound angle within 1.5 deg: the scatter of the published DEM codes and of the digitisation
// (the default law is at most 0.012, 10 rad/s and 1.0 deg off, at 10-15 deg where the curves
// are steepest). The force history with the unloading rescale (HertzMindlinIncremental, the
// default until 2026-12) is off by 0.09 in e_t and 30 rad/s (2.5x) at 5 deg: checked below, so
// that the test would see that form come back.
namespace {

struct ChungOoiPoint {
  double angle_deg, e_t, spin, rebound_deg;
};
// e_t, spin and rebound angle were digitised from three figures with their own abscissae; the
// three agree within 0.2 deg and the first is used for all three.
constexpr ChungOoiPoint kChungOoiTest4[] = {
    {5.17, 0.948, 19.3, 3.76},     {10.16, 0.687, 213.0, -1.56},  {14.99, 0.624, 377.8, -5.54},
    {20.06, 0.616, 510.6, -7.54},  {25.05, 0.634, 599.4, -7.54},  {30.12, 0.684, 616.5, -3.55},
    {40.02, 0.781, 544.8, 11.57},  {50.0, 0.845, 457.0, 29.35},   {59.98, 0.893, 357.5, 47.79},
    {69.96, 0.932, 246.2, 64.58},  {80.02, 0.966, 126.3, 78.70},  {85.01, 0.983, 63.1, 84.52}};

struct Test4Result {
  double e_t = 0.0, spin = 0.0, rebound_deg = 0.0, max_excess = -1.0;
};

// Sphere of Chung & Ooi's aluminium oxide on a plane, 2000 steps per (elastic, normal) contact.
template <class Model>
Test4Result run_chung_ooi_test4(double angle_deg, double e = 0.98) {
  using D = Dim3;
  using Vec = D::Vec;
  Material al2o3;
  al2o3.youngs_modulus = 3.8e11;  // [Pa]
  al2o3.poisson_ratio = 0.23;
  al2o3.density = 4000.0;  // [kg/m^3]
  al2o3.restitution = e;
  al2o3.friction = 0.092;
  Material rigid = al2o3;
  rigid.youngs_modulus = 1.0e6 * al2o3.youngs_modulus;
  const double r = 2.5e-3, v = 3.9, th = angle_deg * kPi / 180.0;  // [m], [m/s]
  const double m = mass_of<D>(al2o3.density, r, 1.0);
  const double E_eff = al2o3.youngs_modulus / (1.0 - 0.23 * 0.23);
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.dt = hertz_duration_exact(m, E_eff, r, v * std::cos(th)) / 2000;
  Simulation<D, Model> sim(cfg);
  const auto pm = sim.add_material(al2o3);
  sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), Vec::UnitZ()), sim.add_wall_material(rigid));
  const double gap = 3.3 * v * std::cos(th) * cfg.dt;
  const auto id = sim.add_particle(Vec(0.0, 0.0, r + gap), r, pm, Vec(v * std::sin(th), 0.0, -v * std::cos(th)));
  const double E0 = sim.kinetic_energy();
  Test4Result out;
  bool touched = false;
  int after = 0;
  for (int k = 0; k < 100000; ++k) {
    sim.step();
    out.max_excess = std::max(out.max_excess, (sim.kinetic_energy() + sim.elastic_energy() - E0) / E0);
    if (sim.contact_count() > 0) touched = true;
    if (touched && sim.contact_count() == 0 && ++after > 3) break;
  }
  const auto& p = sim.particles();
  const std::size_t i = sim.index_of(id);
  out.e_t = p.v[i].x() / (v * std::sin(th));
  out.spin = p.omega[i].y();
  const double vc = p.v[i].x() - r * p.omega[i].y();  // contact-patch tangential velocity after
  out.rebound_deg = std::atan(vc / p.v[i].z()) * 180.0 / kPi;
  return out;
}

}  // namespace

// The three laws at every angle also go to chung_ooi_test4.csv in the working directory
// (<build>/tests), which benchmarks/plot_chung_ooi.py draws against the published points
// (the figure of docs/physics.md, "Tangential laws").
TEST_CASE("Chung & Ooi (2011) Test 4: oblique impacts on a rigid plane at every angle (default Hertz-Mindlin)",
          "[contact][oblique][benchmark]") {
  std::ofstream csv("chung_ooi_test4.csv");
  csv << "angle_deg,law,e_t,spin,rebound_deg\n";
  for (double deg = 1.0; deg <= 89.0; deg += deg < 20.0 ? 1.0 : 5.0) {
    const auto a = run_chung_ooi_test4<contact::HertzMindlin>(deg);
    const auto b = run_chung_ooi_test4<contact::HertzMindlinIncremental>(deg);
    const auto c = run_chung_ooi_test4<contact::HertzMindlinLegacy>(deg);
    csv << deg << ",potential," << a.e_t << ',' << a.spin << ',' << a.rebound_deg << '\n' << deg
        << ",incremental," << b.e_t << ',' << b.spin << ',' << b.rebound_deg << '\n' << deg << ",liggghts38,"
        << c.e_t << ',' << c.spin << ',' << c.rebound_deg << '\n';
  }
  for (const auto& ref : kChungOoiTest4) {
    const auto res = run_chung_ooi_test4<contact::HertzMindlin>(ref.angle_deg);
    INFO("angle " << ref.angle_deg << " deg: e_t " << res.e_t << " (paper " << ref.e_t << "), spin " << res.spin
                  << " rad/s (" << ref.spin << "), rebound angle " << res.rebound_deg << " deg ("
                  << ref.rebound_deg << ")");
    CHECK(std::abs(res.e_t - ref.e_t) <= 0.02);
    CHECK(std::abs(res.spin - ref.spin) <= 15.0);
    CHECK(std::abs(res.rebound_deg - ref.rebound_deg) <= 1.5);
  }
  // The force history with the unloading rescale departs in the micro-slip regime.
  const auto& five = kChungOoiTest4[0];
  const auto inc = run_chung_ooi_test4<contact::HertzMindlinIncremental>(five.angle_deg);
  INFO("HertzMindlinIncremental at " << five.angle_deg << " deg: e_t " << inc.e_t << ", spin " << inc.spin);
  CHECK(inc.e_t < five.e_t - 0.05);
  CHECK(inc.spin > 2.0 * five.spin);
}

// Reference: energy balance (as above) for Chung & Ooi's sphere with e = 1: the potential form
// stores k_t |xi|^2 / 2 and puts k_t' |xi|^2 / 2 into the normal force, so while the contact
// sticks (5 deg: micro-slip regime; 30 deg: stick, then slip) energy is conserved up to the
// integration error, and slip dissipates. Without the coupling term (the LIGGGHTS 3.8
// displacement form) impacts gain up to 2.3 % of E0 during the contact (mu = 0.5, 25 deg;
// measured in a one-contact model of this test). Tolerance as kEnergyToleranceHertz.
TEST_CASE("Chung & Ooi (2011) Test 4 with e = 1: the default Hertz-Mindlin never gains energy",
          "[contact][energy][oblique][benchmark]") {
  for (const double deg : {2.0, 5.0, 10.0, 30.0, 60.0}) {
    const auto res = run_chung_ooi_test4<contact::HertzMindlin>(deg, 1.0);
    INFO("angle " << deg << ": max (E - E0)/E0 = " << res.max_excess);
    CHECK(res.max_excess <= kEnergyToleranceHertz);
  }
}
