// Per-pair properties (issue 29, item 3): explicit pair values over the mixing rules
// (PairOverride, Simulation::set_pair), rigid wall materials (Material::rigid), the effective
// mass against a frozen or prescribed partner, an initial angular velocity in add_particle and
// the standing contact request (record_contacts_every_step).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include "../contact/contact_test_support.hpp"
#include "granule/io/checkpoint.hpp"
#include "../support/message_of.hpp"

using namespace granule;
using namespace granule::contact_test;
using Catch::Matchers::Contains;
using granule::test::message_of;

namespace {

// Aluminium oxide of Chung & Ooi (2011): R = 2.5 mm, E = 380 GPa, nu = 0.23, rho = 4000 kg/m^3.
Material alumina(double e) {
  Material m;
  m.name = "alumina";
  m.youngs_modulus = 3.8e11;  // [Pa]
  m.poisson_ratio = 0.23;     // [-]
  m.density = 4000.0;         // [kg/m^3]
  m.restitution = e;
  return m;
}

// A soft grain for the slow tests (sliding, rolling, linear springs).
Material soft_grain(double e, double mu) {
  Material m;
  m.name = "grain";
  m.youngs_modulus = 1.0e7;  // [Pa]
  m.poisson_ratio = 0.3;     // [-]
  m.density = 2500.0;        // [kg/m^3]
  m.restitution = e;
  m.friction = mu;
  return m;
}

struct Impact {
  double restitution = 0.0;  ///< separation speed / impact speed [-]
  double duration = 0.0;     ///< contact time [s]
  double max_overlap = 0.0;  ///< [m]
};

// Follows one normal impact that starts at 0.3 of the 4th step (gap 3.3 v dt): `overlap()` and
// `speed()` (relative normal separation speed) of the two bodies; ends 3 steps after separation.
template <class Sim, class Overlap, class Speed>
Impact follow_impact(Sim& sim, double v, double gap, Overlap&& overlap, Speed&& speed) {
  Impact out;
  const double dt = sim.dt();
  double prev = overlap();
  bool touched = false;
  for (long k = 0; k < 1000000; ++k) {
    sim.step();
    const double o = overlap();
    out.max_overlap = std::max(out.max_overlap, o);
    if (o > 0.0) touched = true;
    if (touched && o <= 0.0) {
      out.duration = zero_crossing(sim.time() - dt, prev, sim.time(), o) - gap / v;
      break;
    }
    prev = o;
  }
  sim.run(3);
  out.restitution = speed() / v;
  return out;
}

// A particle of `grain` falling at v onto a plane of `wall` (normal +z), no gravity; `o` is set
// on the pair.
template <class Model>
Impact drop_on_plane(const Material& grain, const Material& wall, double r, double v, double dt,
                     const PairOverride& o = {}) {
  using D = Dim3;
  using Vec = D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.dt = dt;
  Simulation<D, Model> sim(cfg);
  const auto pm = sim.add_material(grain);
  const auto wm = sim.add_wall_material(wall);
  sim.set_pair(pm, wm, o);
  sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), Vec::UnitZ()), wm);
  const double gap = 3.3 * v * dt;
  const auto id = sim.add_particle(Vec(0.0, 0.0, r + gap), r, pm, Vec(0.0, 0.0, -v));
  const auto& p = sim.particles();
  return follow_impact(
      sim, v, gap, [&] { return r - p.x[sim.index_of(id)].z(); }, [&] { return p.v[sim.index_of(id)].z(); });
}

// A free particle hitting an equal one of the same material along x at relative speed v; the
// partner (group 1) is frozen, or prescribed to move at u towards it. No gravity.
template <class Model>
Impact hit_partner(const Material& mat, double r, double v, bool prescribed, double u, double dt) {
  using D = Dim3;
  using Vec = D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.dt = dt;
  Simulation<D, Model> sim(cfg);
  const auto pm = sim.add_material(mat);
  if (prescribed) {
    sim.prescribe_group_velocity(1, [u](double) { return Vec(u, 0.0, 0.0); });
  } else {
    sim.freeze_group(1);
  }
  const double gap = 3.3 * v * dt;
  const auto b = sim.add_particle(Vec::Zero(), r, pm, Vec::Zero(), 1);
  const auto a = sim.add_particle(Vec(2.0 * r + gap, 0.0, 0.0), r, pm, Vec(-(v - u), 0.0, 0.0));
  const auto& p = sim.particles();
  return follow_impact(
      sim, v, gap, [&] { return 2.0 * r - (p.x[sim.index_of(a)] - p.x[sim.index_of(b)]).norm(); },
      [&] { return (p.v[sim.index_of(a)] - p.v[sim.index_of(b)]).x(); });
}

// Linear spring-dashpot: half period pi / omega_d, omega_d = sqrt(k/m*) sqrt(1 - xi^2).
double linear_duration(double k, double m_eff, double e) {
  const double l = std::log(e);
  const double xi = -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
  return std::numbers::pi / (std::sqrt(k / m_eff) * std::sqrt(1.0 - xi * xi));
}

}  // namespace

// ---- Rigid wall materials ------------------------------------------------------------------
// Reference: the limit E_wall -> inf of the Hertz/Mindlin mixing rules (docs/physics.md):
// 1/E* = (1 - nu^2)/E, 1/G* = 2 (2 - nu)(1 + nu)/E of the particle alone; the linear laws'
// half-contacts in series, 2 k_a k_b / (k_a + k_b) -> 2 k_a. The pair takes the particle's e,
// mu, mu_r, eta_r, k_c (not the mean with the wall's, which are set to other values here).
// Exact up to rounding (1e-15); against a wall of 1e6 E the moduli agree to the 1e-6 that such a
// wall still adds.
TEST_CASE("Rigid wall material: pair values are the particle's and the E_wall -> inf limit",
          "[materials][pair][rigid]") {
  Material grain = alumina(0.5);
  grain.friction = 0.3;
  grain.rolling_friction = 0.05;
  grain.rolling_damping = 0.2;
  grain.cohesion_energy_density = 1.0e3;
  grain.normal_stiffness = 1.0e3;
  grain.tangential_stiffness_ratio = 0.4;
  grain.rolling_stiffness_factor = 2.0;
  Material wall = Material::rigid_wall("steel plate");
  wall.restitution = 0.9;
  wall.friction = 0.7;
  wall.rolling_friction = 0.3;
  wall.rolling_damping = 0.9;
  wall.cohesion_energy_density = 7.0e3;
  wall.normal_stiffness = 5.0e3;
  wall.validate(true);  // E = 0 is fine for a rigid wall
  for (const PairMaterial& p : {mix(grain, wall), mix(wall, grain)}) {
    CHECK(p.E_eff == Approx(3.8e11 / (1.0 - 0.23 * 0.23)).epsilon(1e-15));
    CHECK(p.G_eff == Approx(3.8e11 / (2.0 * (2.0 - 0.23) * (1.0 + 0.23))).epsilon(1e-15));
    CHECK(p.restitution == 0.5);
    CHECK(p.mu_s == 0.3);
    CHECK(p.mu_r == 0.05);
    CHECK(p.rolling_damping == 0.2);
    CHECK(p.k_c == 1.0e3);
    CHECK(p.k_n_linear == 2.0e3);
    CHECK(p.kt_ratio == 0.4);
    CHECK(p.rolling_stiffness_factor == 2.0);
  }
  Material stiff = grain;
  stiff.youngs_modulus *= 1.0e6;
  stiff.normal_stiffness *= 1.0e6;
  const PairMaterial limit = mix(grain, stiff);
  CHECK(mix(grain, wall).E_eff == Approx(limit.E_eff).epsilon(2e-6));
  CHECK(mix(grain, wall).G_eff == Approx(limit.G_eff).epsilon(2e-6));
  CHECK(mix(grain, wall).k_n_linear == Approx(limit.k_n_linear).epsilon(2e-6));

  // A rigid particle material is refused by name.
  SimulationConfig<Dim3> cfg;
  cfg.domain.hi = Dim3::Vec::Constant(0.05);
  cfg.dt = 1e-7;
  Simulation<Dim3, contact::HertzFrictionless> sim(cfg);
  Material rigid_grain = grain;
  rigid_grain.rigid = true;
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(rigid_grain); }),
             Contains("Material 'alumina'") && Contains("rigid = 1") && Contains("add_wall_material"));
  CHECK(sim.add_wall_material(wall) == 0u);
}

// Reference: Chung & Ooi (2011), Granular Matter 13:643, Tests 1 and 3: a sphere (aluminium
// oxide) on a rigid plane at 3.9 m/s. Test 1 (elastic): delta_max = (15 m v^2 / (16 E* R^1/2))^2/5
// and the Hertz duration with E* = E/(1 - nu^2), m* = m, R* = R (Johnson 1985); the engine at 2000
// steps per contact is within 0.5 % of both (the tolerance of tests/contact/test_restitution.cpp).
// Test 3: e_out = e_in for the damped law (Antypov & Elliott 2011), to 1e-3 as there; the rigid
// wall's own e (0.2) must not enter. And the rigid plane reproduces the 1e6-E plane that stood
// for it: restitution, duration and maximum overlap to 1e-5 relative (measured: see INFO). An
// averaged e would give 0.35 instead of 0.5; a wall compliance counted twice moves delta_max by 32 %.
TEST_CASE("Rigid plane: Chung & Ooi Tests 1 and 3, and the 1e6-E plane to < 1e-5",
          "[materials][pair][rigid][restitution]") {
  const double r = 2.5e-3, v = 3.9;  // [m], [m/s]
  for (const double e : {0.5, 0.9, 1.0}) {
    const Material grain = alumina(e);
    Material rigid = Material::rigid_wall();
    rigid.restitution = 0.2;
    Material stiff = grain;
    stiff.youngs_modulus *= 1.0e6;
    const double m = mass_of<Dim3>(grain.density, r, 1.0);
    const double E_eff = grain.youngs_modulus / (1.0 - grain.poisson_ratio * grain.poisson_ratio);
    const double tc = hertz_duration_exact(m, E_eff, r, v);
    const Impact a = drop_on_plane<contact::HertzFrictionless>(grain, rigid, r, v, tc / 2000);
    const Impact b = drop_on_plane<contact::HertzFrictionless>(grain, stiff, r, v, tc / 2000);
    INFO("e = " << e << ": rigid e_out " << a.restitution << ", t_c " << a.duration << " s, delta_max "
                << a.max_overlap << " m; 1e6 E: " << b.restitution << ", " << b.duration << ", " << b.max_overlap
                << "; relative differences " << (a.restitution - b.restitution) / b.restitution << ", "
                << (a.duration - b.duration) / b.duration << ", " << (a.max_overlap - b.max_overlap) / b.max_overlap);
    CHECK(a.restitution == Approx(e).margin(1e-3));
    CHECK(a.restitution == Approx(b.restitution).epsilon(1e-5));
    CHECK(a.duration == Approx(b.duration).epsilon(1e-5));
    CHECK(a.max_overlap == Approx(b.max_overlap).epsilon(1e-5));
    if (e == 1.0) {
      CHECK(a.max_overlap == Approx(hertz_max_overlap_exact(m, E_eff, r, v)).epsilon(5e-3));
      CHECK(a.duration == Approx(tc).epsilon(5e-3));
    }
  }
}

// Reference: linear spring-dashpot (Schwager & Poeschel 2007; tests/contact/test_restitution.cpp):
// the contact lasts pi / omega_d, omega_d = sqrt(k/m*) sqrt(1 - xi^2), and returns e exactly.
// A rigid plane: k = 2 k_particle (the half-contacts' limit), m* = m, the particle's e. With
// linear_normal_stiffness and restitution overridden on that pair: the override's k and e.
// Tolerances as there: e to 1e-3, duration to 0.1 % (k or 2k differ by 41 % in duration).
// The time-step check sees the same: the rigid pair (2 k, m* = m) has the period of the
// particle pair (k, m/2), so critical_time_step() stays linear_critical_time(k, m/2, e).
TEST_CASE("Linear law on a rigid plane, and stiffness and restitution set per pair",
          "[materials][pair][rigid][linear]") {
  const double r = 2.0e-3, v = 0.5, k = 2.0e3;  // [m], [m/s], [N/m]
  Material grain = soft_grain(0.5, 0.0);
  grain.normal_stiffness = k;
  const double m = mass_of<Dim3>(grain.density, r, 1.0);
  Material wall = Material::rigid_wall();
  wall.restitution = 0.9;
  {
    SimulationConfig<Dim3> cfg;
    cfg.domain.hi = Dim3::Vec::Constant(0.05);
    cfg.dt = 1e-7;
    Simulation<Dim3, contact::LinearFrictionless> sim(cfg);
    const auto pm = sim.add_material(grain);
    sim.add_wall_material(wall);
    sim.add_particle(Dim3::Vec::Constant(0.01), r, pm);
    CHECK(sim.critical_time_step() == Approx(linear_critical_time(k, 0.5 * m, 0.5)).epsilon(1e-12));
  }
  {
    const double tc = linear_duration(2.0 * k, m, 0.5);
    const Impact a = drop_on_plane<contact::LinearFrictionless>(grain, wall, r, v, tc / 4000);
    INFO("rigid plane: e_out " << a.restitution << ", t_c " << a.duration << " s (pi/omega_d " << tc << ")");
    CHECK(a.restitution == Approx(0.5).margin(1e-3));
    CHECK(a.duration == Approx(tc).epsilon(1e-3));
  }
  {
    PairOverride o;
    o.linear_normal_stiffness = 1.0e3;  // [N/m]
    o.restitution = 0.8;
    const double tc = linear_duration(1.0e3, m, 0.8);
    const Impact a = drop_on_plane<contact::LinearFrictionless>(grain, wall, r, v, tc / 4000, o);
    INFO("override k = 1e3 N/m, e = 0.8: e_out " << a.restitution << ", t_c " << a.duration << " s (pi/omega_d "
                                                  << tc << ")");
    CHECK(a.restitution == Approx(0.8).margin(1e-3));
    CHECK(a.duration == Approx(tc).epsilon(1e-3));
  }
}

// ---- Frozen and prescribed partners --------------------------------------------------------
// Reference: a partner that does not respond to forces (inv_mass 0) acts like a wall, so
// m* = m_free (1/m* = 1/m_i + 0), without a density hack. Linear spring-dashpot: e exactly and
// duration pi / omega_d with m* = m (with the pair's m/2 it would be 29 % shorter, and a
// dashpot built on m/2 would return e = 0.59 instead of 0.5). A prescribed partner moving at
// constant speed u towards the free one is the same impact in its frame (Galilean invariance):
// the relative separation speed is e times the relative impact speed. Damped Hertz: the
// one-contact ODE with m* = m (RK4, tests/contact/contact_test_support.hpp). Tolerances those of
// tests/contact/test_restitution.cpp: linear e 1e-3 and duration 0.1 %; Hertz e 5e-4 and duration
// 0.5 % of the ODE.
TEST_CASE("Frozen or prescribed partner: m* is the free particle's mass, e is the material's",
          "[materials][pair][restitution][motion]") {
  const double r = 2.0e-3, v = 0.5, k = 2.0e3;  // [m], [m/s], [N/m]
  Material lin = soft_grain(0.5, 0.0);
  lin.normal_stiffness = k;
  const double m = mass_of<Dim3>(lin.density, r, 1.0);
  const double tc = linear_duration(k, m, 0.5);
  for (const bool prescribed : {false, true}) {
    const double u = prescribed ? 0.2 : 0.0;  // [m/s]
    const Impact a = hit_partner<contact::LinearFrictionless>(lin, r, v, prescribed, u, tc / 4000);
    INFO((prescribed ? "prescribed" : "frozen") << " partner, linear: e_out " << a.restitution << ", t_c "
                                                << a.duration << " s (pi/omega_d with m* = m: " << tc << ")");
    CHECK(a.restitution == Approx(0.5).margin(1e-3));
    CHECK(a.duration == Approx(tc).epsilon(1e-3));
  }
  const Material hz = soft_grain(0.5, 0.0);
  const double E_eff = hz.youngs_modulus / (2.0 * (1.0 - hz.poisson_ratio * hz.poisson_ratio));
  const double th = hertz_duration_exact(m, E_eff, 0.5 * r, 1.0);
  const auto ode = integrate_hertz_ode(m, E_eff, 0.5 * r, beta_of(0.5), 1.0, 200000);
  const Impact a = hit_partner<contact::HertzFrictionless>(hz, r, 1.0, false, 0.0, th / 2000);
  INFO("frozen partner, Hertz: e_out " << a.restitution << " (ODE " << ode.restitution << "), t_c " << a.duration
                                       << " s (ODE with m* = m: " << ode.duration << ")");
  CHECK(a.restitution == Approx(ode.restitution).margin(5e-4));
  CHECK(a.duration == Approx(ode.duration).epsilon(5e-3));
}

// ---- Friction set per pair: the Coulomb ratio ----------------------------------------------
// Reference: Coulomb's law. A sphere sliding under gravity carries |F_t| = mu |F_n| at every
// step while it slides (the Total truncation scales the force to the limit exactly), with the mu
// of the pair: here the override, not the mean. On a plane wall (grain mu 0.2, wall 0.6: the
// mix would give 0.4; override 0.3) and on a frozen sphere (grains of mu 0.2 and 0.6; override
// 0.1). The recorded mu of the contacts is the override too. Every step's contacts come from the
// standing request (record_contacts_every_step). Tolerance 1e-9 relative: the ratio is exact up
// to rounding; 0.4 against 0.3 is off by 33 %.
TEST_CASE("Friction set per pair: |F_t| / F_n is the override's mu while sliding (wall and particle pairs)",
          "[materials][pair][friction][contacts]") {
  using D = Dim3;
  using Vec = D::Vec;
  const double r = 5.0e-3, g = 9.81;  // [m], [m/s^2]
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.gravity = Vec(0.0, 0.0, -g);
  cfg.dt = 1.0e-5;  // [s]; Rayleigh time 2.2e-4 s
  for (const bool on_wall : {true, false}) {
    for (const bool override_mu : {true, false}) {
      Simulation<D, contact::HertzMindlin> sim(cfg);
      const auto a = sim.add_material(soft_grain(0.5, 0.2));
      const double mu_mix = 0.4, mu_set = on_wall ? 0.3 : 0.1;
      const double mu = override_mu ? mu_set : mu_mix;
      const double m = mass_of<D>(2500.0, r, 1.0);
      std::uint64_t id = 0;
      double v0 = 0.0;
      if (on_wall) {
        Material wall = soft_grain(0.5, 0.6);
        wall.name = "wall";
        const auto w = sim.add_wall_material(wall);
        PairOverride o;
        if (override_mu) o.friction = mu_set;
        sim.set_pair(a, w, o);
        sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), Vec::UnitZ()), w);
        const double E = sim.materials().pair(a, w).E_eff;
        const double overlap0 = std::pow(m * g / (4.0 / 3.0 * E * std::sqrt(r)), 2.0 / 3.0);
        v0 = 1.0;
        id = sim.add_particle(Vec(0.0, 0.0, r - overlap0), r, a, Vec(v0, 0.0, 0.0));
      } else {
        const auto b = sim.add_material(soft_grain(0.5, 0.6));
        PairOverride o;
        if (override_mu) o.friction = mu_set;
        sim.set_pair(a, b, o);
        sim.freeze_group(1);
        sim.add_particle(Vec::Zero(), r, b, Vec::Zero(), 1);
        const double E = sim.materials().pair(a, b).E_eff;
        const double overlap0 = std::pow(m * g / (4.0 / 3.0 * E * std::sqrt(0.5 * r)), 2.0 / 3.0);
        v0 = 0.1;  // centripetal v^2 / 2r = 1 m/s^2 < g: it stays on top
        id = sim.add_particle(Vec(0.0, 0.0, 2.0 * r - overlap0), r, a, Vec(v0, 0.0, 0.0));
      }
      sim.record_contacts_every_step(true);
      double worst = 0.0;
      std::size_t recorded = 0;
      for (int k = 1; k <= 300; ++k) {
        sim.step();
        const auto fr = sim.frame();
        REQUIRE(fr.contacts.size() == 1);
        const auto& c = fr.contacts[0];
        REQUIRE(c.fn > 0.0);
        CHECK(c.mu == Approx(mu).epsilon(1e-15));
        if (k >= 5) {
          worst = std::max(worst, std::abs(c.ft.norm() / c.fn - mu) / mu);
          ++recorded;
        }
      }
      // Still sliding: the contact point moves forward.
      const auto& p = sim.particles();
      const std::size_t i = sim.index_of(id);
      const double slip = p.v[i].x() - r * p.omega[i].y();
      INFO((on_wall ? "plane wall" : "frozen sphere") << (override_mu ? ", override mu " : ", mixed mu ") << mu
                                                      << ": worst relative |F_t|/F_n - mu " << worst
                                                      << " over " << recorded << " steps; slip " << slip << " m/s");
      CHECK(slip > 0.2 * v0);
      CHECK(worst < 1e-9);
    }
  }
}

// ---- Standing contact request --------------------------------------------------------------
// Reference: statics. A sphere resting on a plane at its Hertz equilibrium overlap
// delta_0 = (m g / (4/3 E* sqrt(R)))^(2/3) carries F_n = m g; with record_contacts_every_step
// every step's frame holds that contact (no request_contacts() before each step), to 1e-9
// relative (the sphere starts at rest in equilibrium: only rounding moves it). Switched off, the
// next step records nothing; request_contacts() still records the one step after it.
TEST_CASE("record_contacts_every_step: each step's contact forces without a request per step",
          "[engine][contacts]") {
  using D = Dim3;
  using Vec = D::Vec;
  const double r = 5.0e-3, g = 9.81;  // [m], [m/s^2]
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.gravity = Vec(0.0, 0.0, -g);
  cfg.dt = 1.0e-5;
  Simulation<D, contact::HertzMindlin> sim(cfg);
  const auto a = sim.add_material(soft_grain(0.5, 0.5));
  const auto w = sim.add_wall_material(Material::rigid_wall());
  sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), Vec::UnitZ()), w);
  const double m = mass_of<D>(2500.0, r, 1.0);
  const double E = sim.materials().pair(a, w).E_eff;
  const double overlap0 = std::pow(m * g / (4.0 / 3.0 * E * std::sqrt(r)), 2.0 / 3.0);
  sim.add_particle(Vec(0.0, 0.0, r - overlap0), r, a);
  CHECK_FALSE(sim.records_contacts_every_step());
  sim.record_contacts_every_step(true);
  CHECK(sim.records_contacts_every_step());
  for (int k = 0; k < 50; ++k) {
    sim.step();
    const auto fr = sim.frame();
    REQUIRE(fr.contacts.size() == 1);
    CHECK(fr.contacts[0].fn == Approx(m * g).epsilon(1e-9));
  }
  sim.record_contacts_every_step(false);
  sim.step();
  CHECK(sim.frame().contacts.empty());
  sim.request_contacts();
  sim.step();
  CHECK(sim.frame().contacts.size() == 1);
  sim.step();
  CHECK(sim.frame().contacts.empty());
}

// ---- Initial angular velocity --------------------------------------------------------------
// Reference: rigid-body mechanics of a ball set down spinning (omega_0, no velocity) on a rough
// plane: friction accelerates it until it rolls; angular momentum about the contact point,
// I omega_0 = I v/h + m v h (h = r - delta_0 the height of the centre over the contact point),
// gives v_final = k r^2 omega_0 h / (k r^2 + h^2), which is k/(1 + k) omega_0 r for h = r (sphere
// k = 2/5: 2/7 omega_0 r; disk k = 1/2: 1/3). Tolerances as in tests/contact/
// test_sliding_to_rolling.cpp: 0.5 % of the textbook value, 2e-4 of the lever-arm value. A spin
// that add_particle dropped leaves v = 0. In free flight the spin stays as given (bitwise);
// frozen particles have none; a non-finite component is refused by name.
TEMPLATE_TEST_CASE("add_particle with an initial angular velocity: a spinning ball set down rolls at k/(1+k) omega_0 r",
                   "[engine][rolling][friction]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  const double r = 5.0e-3, t = 2.0e-3, g = 9.81, w0 = 200.0;  // [m], [m], [m/s^2], [rad/s]
  const double kI = D::inertia_factor;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.domain.hi[0] = 0.5;
  cfg.gravity = -g * up<D>();
  cfg.dt = 1.0e-5;
  cfg.thickness = t;
  Simulation<D, contact::HertzMindlin> sim(cfg);
  const Material mat = soft_grain(0.5, 0.3);
  const auto pm = sim.add_material(mat);
  const auto wm = sim.add_wall_material(mat);
  sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), up<D>()), wm);
  const double m = mass_of<D>(mat.density, r, t);
  const double E = sim.materials().pair(pm, wm).E_eff;
  const double overlap0 = std::pow(m * g / (4.0 / 3.0 * E * std::sqrt(r)), 2.0 / 3.0);
  // omega_0 turning the ball as if it rolled along +x: the contact point slips backwards.
  const auto omega0 = rolling_omega<D>(w0 * r, r);
  const auto id = sim.add_particle(Vec((r - overlap0) * up<D>()), r, pm, Vec::Zero(), 0, omega0);
  // A second ball, high up, spinning in free flight (checked after 10 steps, long before it lands).
  const auto free_id = sim.add_particle(Vec(0.2 * unit<D>(0) + 0.04 * up<D>()), r, pm, Vec::Zero(), 0, omega0);
  const double t_roll = w0 * r / (mat.friction * g * (1.0 + 1.0 / kI));
  const long steps = static_cast<long>(1.6 * t_roll / cfg.dt);
  const auto& p = sim.particles();
  sim.run(10);
  CHECK(p.omega[sim.index_of(free_id)] == omega0);
  double sum_v = 0.0;
  long n_avg = 0;
  for (long k = 11; k <= steps; ++k) {
    sim.step();
    if (k > 0.7 * steps) {
      sum_v += p.v[sim.index_of(id)][0];
      ++n_avg;
    }
  }
  const double v_final = sum_v / n_avg;
  const double h = r - overlap0;
  INFO("dim " << D::dim << ": v_final = " << v_final << " m/s; k/(1+k) omega_0 r = " << kI / (1.0 + kI) * w0 * r
              << ", with the lever arm " << kI * r * r * w0 * h / (kI * r * r + h * h));
  CHECK(v_final == Approx(kI / (1.0 + kI) * w0 * r).epsilon(5e-3));
  CHECK(v_final == Approx(kI * r * r * w0 * h / (kI * r * r + h * h)).epsilon(2e-4));

  sim.freeze_group(2);
  const auto frozen = sim.add_particle(Vec(0.3 * unit<D>(0) + 0.02 * up<D>()), r, pm, Vec::Zero(), 2, omega0);
  CHECK(D::squared_norm(p.omega[sim.index_of(frozen)]) == 0.0);
  auto bad = omega0;
  if constexpr (D::dim == 2) {
    bad = std::numeric_limits<double>::infinity();
  } else {
    bad[2] = std::numeric_limits<double>::quiet_NaN();
  }
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(Vec(0.4 * unit<D>(0) + 0.02 * up<D>()), r, pm, Vec::Zero(), 0, bad); }),
             Contains("Simulation::add_particle") && Contains(D::dim == 2 ? "omega[0] = inf" : "omega[2] = nan"));
}

// ---- The set-up path: overrides survive later materials, named errors, restarts ------------
// Reference: the pair table itself. An override replaces only the fields it sets (the others
// keep the mix: pair_material.hpp), a second override on the same pair adds to the first, both
// orders (a, b) and (b, a) agree, and add_material afterwards mixes only the new pairs. Out-of-
// range values name the field and range.
TEST_CASE("set_pair: overrides merge, survive later add_material calls and are validated",
          "[materials][pair][errors]") {
  SimulationConfig<Dim3> cfg;
  cfg.domain.hi = Dim3::Vec::Constant(0.05);
  cfg.dt = 1e-7;
  Simulation<Dim3, contact::HertzMindlin> sim(cfg);
  Material ma = soft_grain(0.5, 0.2), mb = soft_grain(0.7, 0.6), mw = soft_grain(0.9, 0.4);
  ma.rolling_friction = 0.02;
  mb.rolling_friction = 0.06;
  mb.cohesion_energy_density = 2.0e3;
  const auto a = sim.add_material(ma);
  const auto b = sim.add_material(mb);
  const auto w = sim.add_wall_material(mw);
  PairOverride ab;
  ab.cohesion_energy_density = 500.0;
  ab.rolling_friction = 0.07;
  ab.rolling_damping = 0.3;
  sim.set_pair(a, b, ab);
  PairOverride aw;
  aw.friction = 0.35;
  aw.restitution = 0.45;
  sim.set_pair(w, a, aw);  // a wall material first: the same pair
  PairOverride aw2;
  aw2.rolling_friction = 0.01;
  sim.set_pair(a, w, aw2);
  const auto c = sim.add_material(soft_grain(0.3, 0.8));
  const auto w2 = sim.add_wall_material(Material::rigid_wall());
  const MaterialTable& t = sim.materials();
  for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, a}}) {
    CHECK(t.pair(x, y).k_c == 500.0);
    CHECK(t.pair(x, y).mu_r == 0.07);
    CHECK(t.pair(x, y).rolling_damping == 0.3);
    CHECK(t.pair(x, y).mu_s == Approx(0.4));        // not overridden: the mean
    CHECK(t.pair(x, y).restitution == Approx(0.6));  // the mean
  }
  for (const auto& [x, y] : {std::pair{a, w}, std::pair{w, a}}) {
    CHECK(t.pair(x, y).mu_s == 0.35);
    CHECK(t.pair(x, y).restitution == 0.45);
    CHECK(t.pair(x, y).mu_r == 0.01);
    CHECK(t.pair(x, y).E_eff == mix(ma, mw).E_eff);
  }
  CHECK(t.pair(a, c).mu_s == mix(ma, soft_grain(0.3, 0.8)).mu_s);
  CHECK(t.pair(a, w2).restitution == 0.5);  // rigid: the particle's own
  CHECK(t.pair(b, w).mu_s == Approx(0.5));  // other pairs untouched

  const auto msg = [&](std::uint32_t x, std::uint32_t y, void (*edit)(PairOverride&)) {
    PairOverride o;
    edit(o);
    return message_of<InvalidParameter>([&] { sim.set_pair(x, y, o); });
  };
  CHECK_THAT(msg(a, w, [](PairOverride& o) { o.restitution = 1.5; }),
             Contains("Simulation::set_pair") && Contains("restitution = 1.5") && Contains("(0, 1]"));
  CHECK_THAT(msg(a, w, [](PairOverride& o) { o.restitution = 0.0; }), Contains("restitution = 0"));
  CHECK_THAT(msg(a, b, [](PairOverride& o) { o.friction = -0.1; }), Contains("friction = -0.1") && Contains("[0, inf)"));
  CHECK_THAT(msg(a, b, [](PairOverride& o) { o.rolling_friction = std::nan(""); }), Contains("rolling_friction = nan"));
  CHECK_THAT(msg(a, b, [](PairOverride& o) { o.rolling_damping = -1.0; }), Contains("rolling_damping = -1"));
  CHECK_THAT(msg(a, b, [](PairOverride& o) { o.cohesion_energy_density = -1.0; }),
             Contains("cohesion_energy_density = -1") && Contains("J/m^3"));
  CHECK_THAT(msg(a, b, [](PairOverride& o) { o.linear_normal_stiffness = 0.0; }),
             Contains("linear_normal_stiffness = 0") && Contains("(0, inf) N/m"));
  CHECK_THAT(msg(a, b, [](PairOverride& o) { o.tangential_stiffness_ratio = std::numeric_limits<double>::infinity(); }),
             Contains("tangential_stiffness_ratio = inf"));
  CHECK_THAT(msg(a, 9, [](PairOverride&) {}), Contains("b = 9") && Contains("add_material first"));
  CHECK_THAT(msg(w, w2, [](PairOverride&) {}), Contains("both wall materials"));
  // A refused override leaves the pair as it was.
  CHECK(t.pair(a, w).restitution == 0.45);
}

// Reference: checkpoints store the dynamic state only; materials and pair tables are the scene's
// static set-up, which the restarting program builds again (io/checkpoint.hpp). A scene with pair
// overrides and a rigid floor set up by the same code restarts bitwise: 2N steps equal N, write,
// read into a fresh scene, N more. The overrides matter: the same scene without them ends
// elsewhere.
TEST_CASE("Checkpoint restart with pair overrides and a rigid wall is bitwise exact",
          "[materials][pair][restart]") {
  using D = Dim3;
  using Vec = D::Vec;
  using Sim = Simulation<D, contact::HertzMindlin>;
  const auto build = [](bool overrides) {
    SimulationConfig<D> cfg;
    cfg.domain.lo = Vec::Zero();
    cfg.domain.hi = Vec::Constant(0.02);
    cfg.domain.periodic[0] = cfg.domain.periodic[1] = true;
    cfg.gravity = Vec(0.0, 0.0, -9.81);
    cfg.dt = 2e-6;
    cfg.skin = 1e-4;
    auto sim = std::make_unique<Sim>(cfg);
    Material ma = soft_grain(0.5, 0.5), mb = soft_grain(0.8, 0.2);
    ma.youngs_modulus = mb.youngs_modulus = 5e6;
    const auto a = sim->add_material(ma);
    const auto b = sim->add_material(mb);
    const auto w = sim->add_wall_material(Material::rigid_wall());
    if (overrides) {
      PairOverride o;
      o.friction = 0.9;
      o.restitution = 0.3;
      sim->set_pair(a, b, o);
      PairOverride f;
      f.friction = 0.05;
      sim->set_pair(b, w, f);
    }
    sim->add_wall(geometry::PlaneShape<D>(Vec::Zero(), Vec::UnitZ()), w);
    int n = 0;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        for (int k = 0; k < 3; ++k, ++n)
          sim->add_particle(Vec(2e-3 + 3.5e-3 * i + 2e-4 * k, 2e-3 + 3.5e-3 * j, 1e-3 + 1.2e-3 * k), 5e-4,
                            n % 2 == 0 ? a : b, Vec(0.05 * (j - 2), 0.03 * (i - 2), -0.5));
    return sim;
  };
  const std::uint64_t n = 1500;
  auto straight = build(true);
  std::size_t contacts = 0;  // contact-steps of the run
  straight->every(1, [&](Sim& s) { contacts += s.contact_count(); });
  straight->run(2 * n);
  auto first = build(true);
  first->run(n);
  const std::string path = (std::filesystem::temp_directory_path() / "granule_ckpt_pair_overrides").string();
  io::write_checkpoint(*first, path);
  auto resumed = build(true);
  io::read_checkpoint(*resumed, path);
  resumed->run(n);
  std::filesystem::remove(path);
  auto plain = build(false);
  plain->run(2 * n);
  const auto& ps = straight->particles();
  const auto& pr = resumed->particles();
  const auto& pp = plain->particles();
  REQUIRE(ps.owned() == pr.owned());
  INFO(contacts << " contact-steps");
  REQUIRE(contacts > 1000);
  bool same = true, differs = false;
  for (std::size_t i = 0; i < ps.owned(); ++i) {
    same = same && ps.id[i] == pr.id[i] && ps.x[i] == pr.x[i] && ps.v[i] == pr.v[i] && ps.omega[i] == pr.omega[i];
    differs = differs || (ps.x[i] - pp.x[plain->index_of(ps.id[i])]).norm() > 1e-6;
  }
  CHECK(same);
  CHECK(differs);
}
