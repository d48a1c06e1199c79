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
      INFO("dim " << D::dim << (wall ? " wall" : " pair") << " angle " << deg << ": max (E - E0)/E0 = "
                  << res.max_excess);
      CHECK(res.max_excess <= kEnergyTolerance);
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
      CHECK(h.max_excess <= kEnergyTolerance);
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
