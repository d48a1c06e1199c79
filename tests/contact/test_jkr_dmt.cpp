// JKR and DMT adhesion (contact/cohesion/jkr.hpp, dmt.hpp): the closed-form JKR relations
// (Johnson, Kendall & Roberts 1971; Johnson, Contact Mechanics 1985, sec. 5.5), with w = 2 gamma,
//   F(a) = 4 E* a^3 / (3 R*) - sqrt(8 pi w E* a^3),   delta(a) = a^2 / R* - sqrt(2 pi w a / E*),
// the hysteresis of the engine (a contact forms at touch and breaks at -delta_c), and DMT's
// constant pull 2 pi w R*. Material: E = 1 MPa, nu = 0.3, gamma = 0.05 J/m^2, r = 1 mm, so that
// delta0 ~ 5 um and delta_c ~ 4 um, a few hundred time steps of 1 us at 0.1 m/s.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "contact_test_support.hpp"

using namespace granule;
using namespace granule::contact_test;

namespace {

constexpr double kPiJkr = std::numbers::pi;
constexpr double kRJkr = 1.0e-3;             // particle radius [m]
constexpr double kRstar = 0.5 * kRJkr;       // R* of two equal spheres [m]
constexpr double kGamma = 0.05;           // surface energy [J/m^2]
constexpr double kW = 2.0 * kGamma;       // work of adhesion [J/m^2]

Material adhesive_material() {
  Material m;
  m.youngs_modulus = 1.0e6;  // [Pa]
  m.poisson_ratio = 0.3;
  m.density = 2500.0;        // [kg/m^3]
  m.restitution = 1.0;
  m.friction = 0.0;
  m.surface_energy = kGamma;
  return m;
}

double e_star() {
  const Material m = adhesive_material();
  return m.youngs_modulus / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio));
}

contact::JkrCohesion::Params jkr_params() { return {kW, e_star()}; }

// delta(a) of JKR, written out independently of the law.
double jkr_delta(double a) { return a * a / kRstar - std::sqrt(2.0 * kPiJkr * kW * a / e_star()); }
double jkr_force(double a) {
  return 4.0 * e_star() * a * a * a / (3.0 * kRstar) - std::sqrt(8.0 * kPiJkr * kW * e_star() * a * a * a);
}
// Zero-load radius a0^3 = 9 pi w R*^2 / (2 E*), break radius a_c^3 = pi w R*^2 / (8 E*).
double jkr_a0() { return std::cbrt(9.0 * kPiJkr * kW * kRstar * kRstar / (2.0 * e_star())); }
double jkr_ac() { return std::cbrt(kPiJkr * kW * kRstar * kRstar / (8.0 * e_star())); }

// Work done by the contact force from a1 to a2, int F(a) delta'(a) da, in closed form: with
// F = A a^3 - B a^3/2 and delta' = 2 a / R* - C a^-1/2 / 2 (A = 4 E*/(3 R*), B = sqrt(8 pi w E*),
// C = sqrt(2 pi w / E*)), the antiderivative is
//   2A/(5R*) a^5 - (2/7)(A C / 2 + 2 B / R*) a^7/2 + B C / 4 a^2.
double jkr_work(double a) {
  const double A = 4.0 * e_star() / (3.0 * kRstar), B = std::sqrt(8.0 * kPiJkr * kW * e_star()),
               C = std::sqrt(2.0 * kPiJkr * kW / e_star());
  return 2.0 * A / (5.0 * kRstar) * std::pow(a, 5) - 2.0 / 7.0 * (0.5 * A * C + 2.0 * B / kRstar) * std::pow(a, 3.5) +
         0.25 * B * C * a * a;
}

template <class Model>
struct Pair {
  Simulation<Dim3, Model> sim;
  std::size_t i = 0, j = 1;
  Pair(double overlap0, double v_sep, double skin, double restitution = 1.0) : sim(config(skin)) {
    Material m = adhesive_material();
    m.restitution = restitution;
    const auto pm = sim.add_material(m);
    const double h = kRJkr - 0.5 * overlap0;
    sim.add_particle(Eigen::Vector3d(h, 0.0, 0.0), kRJkr, pm, Eigen::Vector3d(0.5 * v_sep, 0.0, 0.0));
    sim.add_particle(Eigen::Vector3d(-h, 0.0, 0.0), kRJkr, pm, Eigen::Vector3d(-0.5 * v_sep, 0.0, 0.0));
  }
  static SimulationConfig<Dim3> config(double skin) {
    SimulationConfig<Dim3> cfg;
    cfg.domain.lo = Eigen::Vector3d::Constant(-0.01);
    cfg.domain.hi = Eigen::Vector3d::Constant(0.01);
    cfg.dt = 1.0e-6;
    cfg.skin = skin;
    return cfg;
  }
  double overlap() const {
    const auto& p = sim.particles();
    return 2.0 * kRJkr - (p.x[sim.index_of(0)] - p.x[sim.index_of(1)]).norm();
  }
  /// Normal force on particle 0 (repulsive > 0) [N].
  double fn() const {
    const auto& p = sim.particles();
    const Eigen::Vector3d d = p.x[sim.index_of(0)] - p.x[sim.index_of(1)];
    return p.f[sim.index_of(0)].dot(d.normalized());
  }
};

}  // namespace

// Reference: delta_c = 3/4 (pi^2 w^2 R* / E*^2)^(1/3) is delta(a_c), a_c^3 = pi w R*^2 / (8 E*),
// where d delta / da = 0; there F = -5/6 pi w R*. Zero load: a0^3 = 9 pi w R*^2 / (2 E*),
// delta0 = a0^2 / (3 R*). Pull-off (largest pull) -3/2 pi w R* at a^3 = a0^3 / 4,
// delta = -a^2 / (3 R*). A wrong R* (R instead of R/2) or w = gamma moves each by 26-100 %.
TEST_CASE("JKR law: pull-off force, break separation, zero-load overlap", "[contact][cohesion][jkr]") {
  const auto p = jkr_params();
  const double ac = jkr_ac(), a0 = jkr_a0();
  const double dc = 0.75 * std::cbrt(kPiJkr * kPiJkr * kW * kW * kRstar / (e_star() * e_star()));
  CHECK(contact::JkrCohesion::separation(p, kRstar) == Approx(dc).epsilon(1e-14));
  CHECK(jkr_delta(ac) == Approx(-dc).epsilon(1e-12));
  CHECK(jkr_force(ac) == Approx(-5.0 / 6.0 * kPiJkr * kW * kRstar).epsilon(1e-12));
  CHECK(contact::JkrCohesion::force(p, a0, kRstar) == Approx(0.0).margin(1e-12 * kPiJkr * kW * kRstar));
  CHECK(jkr_delta(a0) == Approx(a0 * a0 / (3.0 * kRstar)).epsilon(1e-12));
  // Zero load through the law: the inverted radius at delta0 is a0 and the pull cancels Hertz.
  const double delta0 = a0 * a0 / (3.0 * kRstar);
  CHECK(contact::JkrCohesion::contact_radius(p, delta0, kRstar) == Approx(a0).epsilon(1e-12));
  // Largest pull, scanning delta from -delta_c to delta0 with the law's inversion.
  double f_min = 0.0, d_at = 0.0;
  const int n = 200000;
  for (int k = 0; k <= n; ++k) {
    const double d = -dc + (delta0 + dc) * k / n;
    const double f = contact::JkrCohesion::force(p, contact::JkrCohesion::contact_radius(p, d, kRstar), kRstar);
    if (f < f_min) {
      f_min = f;
      d_at = d;
    }
  }
  const double a_pf = a0 / std::cbrt(4.0);
  INFO("pull-off " << f_min << " N at delta = " << d_at << " m; delta_c = " << dc << ", delta0 = " << delta0);
  CHECK(f_min == Approx(-1.5 * kPiJkr * kW * kRstar).epsilon(1e-9));
  CHECK(d_at == Approx(-a_pf * a_pf / (3.0 * kRstar)).epsilon(1e-3));
}

// Reference: contact_radius inverts delta(a) on the stable branch a >= a_c; checked against
// a grid a_c..3 a0 put through delta(a) above. Relative 1e-10, 1e-6 within 1 % of a_c, where
// d delta / da -> 0 makes a(delta) ill-conditioned (sqrt of the distance to delta_c).
TEST_CASE("JKR law: delta -> a inversion", "[contact][cohesion][jkr]") {
  const auto p = jkr_params();
  const double ac = jkr_ac(), a0 = jkr_a0();
  for (int k = 0; k <= 400; ++k) {
    const double a = ac + (3.0 * a0 - ac) * k / 400.0;
    const double got = contact::JkrCohesion::contact_radius(p, jkr_delta(a), kRstar);
    INFO("a = " << a << " (a_c " << ac << ")");
    CHECK(got == Approx(a).epsilon(a < 1.01 * ac ? 1e-6 : 1e-10));
  }
  // Beyond the break: a_c. Without adhesion: Hertz, a = sqrt(R* delta).
  CHECK(contact::JkrCohesion::contact_radius(p, 2.0 * jkr_delta(ac), kRstar) == Approx(ac).epsilon(1e-12));
  const contact::JkrCohesion::Params dry{0.0, e_star()};
  CHECK(contact::JkrCohesion::contact_radius(dry, 1e-6, kRstar) == Approx(std::sqrt(kRstar * 1e-6)).epsilon(1e-14));
}

// Reference (hysteresis): approaching from apart, no force until the overlap turns positive,
// then at once F(a(delta)) (JKR's jump-in, ~ -4/3 pi w R*); separating from delta0 at 0.1 m/s,
// the contact holds F(a(delta)) at negative overlap to delta = -delta_c and is gone beyond it
// (last contact within one step, v dt = 1e-7 m, of -delta_c). With skin 0 the list holds the
// pair only through the pull-off reach added to its cut-off.
TEST_CASE("JKR engine: contact forms at touch and breaks at -delta_c", "[contact][cohesion][jkr]") {
  const auto p = jkr_params();
  const double dc = contact::JkrCohesion::separation(p, kRstar), delta0 = jkr_delta(jkr_a0());
  const double v = 0.1, dt = 1.0e-6;
  for (const double skin : {-1.0, 0.0}) {
    INFO("skin " << skin);
    {  // approach
      Pair<contact::HertzMindlinJkr> pr(-2.0e-6, -v, skin);
      bool touched = false;
      for (int s = 0; s < 100 && !touched; ++s) {
        pr.sim.step();
        if (pr.overlap() <= 0.0) {
          REQUIRE(pr.sim.contact_count() == 0);
          CHECK(pr.fn() == 0.0);
        } else {
          touched = true;
          REQUIRE(pr.sim.contact_count() == 1);
          const double f = contact::JkrCohesion::force(p, contact::JkrCohesion::contact_radius(p, pr.overlap(), kRstar), kRstar);
          CHECK(pr.fn() == Approx(f).epsilon(1e-9));
          CHECK(pr.fn() == Approx(-4.0 / 3.0 * kPiJkr * kW * kRstar).epsilon(0.05));
        }
      }
      CHECK(touched);
    }
    {  // separation
      Pair<contact::HertzMindlinJkr> pr(delta0, v, skin);
      double last_contact = 1.0, first_apart = 1.0, most_negative = 0.0;
      for (int s = 0; s < 400; ++s) {
        pr.sim.step();
        const double d = pr.overlap();
        if (pr.sim.contact_count() == 1) {
          REQUIRE(first_apart == 1.0);  // no contact again once broken
          last_contact = d;
          most_negative = std::min(most_negative, d);
          const double f = contact::JkrCohesion::force(p, contact::JkrCohesion::contact_radius(p, d, kRstar), kRstar);
          CHECK(pr.fn() == Approx(f).epsilon(1e-9));
        } else if (first_apart == 1.0) {
          first_apart = d;
          CHECK(pr.fn() == 0.0);
        }
      }
      INFO("last in contact at " << last_contact << " m, first apart at " << first_apart << " m, -delta_c = " << -dc);
      CHECK(last_contact > -dc);
      CHECK(last_contact < -dc + 1.5 * v * dt);
      CHECK(first_apart <= -dc);
      CHECK(first_apart > -dc - 1.5 * v * dt);
    }
  }
}

// Reference (walls): a sphere (R* = r) leaving a plane or a box face at 0.1 m/s from its zero-load
// overlap holds F(a(delta)) to delta = -delta_c(R* = r) = -3/4 (pi^2 w^2 r / E*^2)^(1/3) (2^1/3 of the
// pair's) and is gone beyond it. E* of a sphere on a rigid wall is E/(1 - nu^2), twice the pair's.
TEST_CASE("JKR engine: a sphere pulled off a wall breaks at -delta_c", "[contact][cohesion][jkr]") {
  const Material m = adhesive_material();
  const contact::JkrCohesion::Params p{kW, m.youngs_modulus / (1.0 - m.poisson_ratio * m.poisson_ratio)};
  const double dc = 0.75 * std::cbrt(kPiJkr * kPiJkr * kW * kW * kRJkr / (p.E_eff * p.E_eff));
  const double a0 = std::cbrt(9.0 * kPiJkr * kW * kRJkr * kRJkr / (2.0 * p.E_eff)), delta0 = a0 * a0 / (3.0 * kRJkr);
  const double v = 0.1, dt = 1.0e-6;
  for (const bool plane : {true, false}) {
    INFO((plane ? "plane" : "box"));
    SimulationConfig<Dim3> cfg;
    cfg.domain.lo = Eigen::Vector3d::Constant(-0.01);
    cfg.domain.hi = Eigen::Vector3d::Constant(0.01);
    cfg.dt = dt;
    Simulation<Dim3, contact::HertzMindlinJkr> sim(cfg);
    const auto pm = sim.add_material(m);
    const auto wm = sim.add_wall_material(Material::rigid_wall());
    if (plane) {
      sim.add_wall(geometry::PlaneShape<Dim3>(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1)), wm);
    } else {
      sim.add_wall(geometry::BoxShape<Dim3>(Eigen::Vector3d(-0.005, -0.005, -0.005), Eigen::Vector3d(0.005, 0.005, 0.0)), wm);
    }
    sim.add_particle(Eigen::Vector3d(0.0, 0.0, kRJkr - delta0), kRJkr, pm, Eigen::Vector3d(0.0, 0.0, v));
    double last_contact = 1.0, first_apart = 1.0;
    for (int s = 0; s < 400; ++s) {
      sim.step();
      const auto& pp = sim.particles();
      const double d = kRJkr - pp.x[0].z();
      if (sim.contact_count() == 1) {
        REQUIRE(first_apart == 1.0);
        last_contact = d;
        const double f = contact::JkrCohesion::force(p, contact::JkrCohesion::contact_radius(p, d, kRJkr), kRJkr);
        CHECK(pp.f[0].z() == Approx(f).epsilon(1e-9));
      } else if (first_apart == 1.0) {
        first_apart = d;
      }
    }
    INFO("last in contact at " << last_contact << " m, first apart at " << first_apart << " m, -delta_c = " << -dc);
    CHECK(last_contact > -dc);
    CHECK(last_contact < -dc + 1.5 * v * dt);
    CHECK(first_apart <= -dc);
  }
}

// Reference (energy): two spheres released at rest with a small overlap delta_s = 0.05 delta0,
// e = 1, oscillate between delta_s and delta_max, where the work of the JKR force vanishes,
// W(a(delta_max)) = W(a(delta_s)) with the closed-form W above (delta_max ~ 1.9 delta0): the
// turning points of the first and the last of ~25 periods agree with it to 1e-3 (dt^2 error of
// velocity Verlet), and with each other to 1e-4 (no drift).
TEST_CASE("JKR engine: an elastic pair oscillates about delta0 without drift", "[contact][cohesion][jkr]") {
  const auto p = jkr_params();
  const double a0 = jkr_a0(), delta0 = jkr_delta(a0), ds = 0.05 * delta0;
  const double as = contact::JkrCohesion::contact_radius(p, ds, kRstar);
  double lo = a0, hi = 4.0 * a0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (jkr_work(mid) - jkr_work(as) < 0.0 ? lo : hi) = mid;
  }
  const double dmax = jkr_delta(0.5 * (lo + hi));
  Pair<contact::HertzMindlinJkr> pr(ds, 0.0, -1.0);
  std::vector<double> maxima, minima;
  double prev2 = pr.overlap(), prev = prev2;
  for (int s = 0; s < 40000; ++s) {
    pr.sim.step();
    REQUIRE(pr.sim.contact_count() == 1);
    const double d = pr.overlap();
    if (prev > prev2 && prev >= d) maxima.push_back(prev);
    if (prev < prev2 && prev <= d) minima.push_back(prev);
    prev2 = prev;
    prev = d;
  }
  INFO("delta_s " << ds << ", delta0 " << delta0 << ", delta_max (theory) " << dmax << "; " << maxima.size()
                  << " maxima, first " << maxima.front() << " last " << maxima.back() << "; minima first "
                  << minima.front() << " last " << minima.back());
  REQUIRE(maxima.size() > 10);
  CHECK(dmax > delta0);
  CHECK(maxima.front() == Approx(dmax).epsilon(1e-3));
  CHECK(maxima.back() == Approx(maxima.front()).epsilon(1e-4));
  CHECK(minima.back() == Approx(ds).epsilon(1e-3));
  CHECK(minima.back() == Approx(minima.front()).epsilon(1e-4));
}

// Reference (DMT): F = 4/3 E* sqrt(R*) delta^3/2 - 2 pi w R*: the pull just after touch is
// 2 pi w R* (tolerance 1e-6: a factor 2, R for R* or w = gamma shows); no contact at negative overlap (no hysteresis); a damped pair settles where Hertz balances the
// pull, delta_eq = (3 pi w sqrt(R*) / (2 E*))^(2/3).
TEST_CASE("DMT: constant pull-off 2 pi w R*, equilibrium overlap", "[contact][cohesion][dmt]") {
  static_assert(!contact::HertzMindlinDmt::tensile);
  const PairMaterial pm = mix(adhesive_material(), adhesive_material());
  CHECK(pm.surface_energy == kGamma);
  const auto prm = contact::HertzMindlinDmt::make(pm);
  const auto g = make_pair_geometry<Dim3>(Eigen::Vector3d(2.0 * kRJkr - 1e-15, 0, 0), Eigen::Vector3d::Zero(), kRJkr, kRJkr,
                                          1e-5, 1e-5, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                          Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1e-6);
  contact::HertzMindlinDmt::State<Dim3> s{};
  CHECK(contact::HertzMindlinDmt::evaluate(prm, g, s).fn == Approx(-2.0 * kPiJkr * kW * kRstar).epsilon(1e-6));
  {  // approach: nothing before touch
    Pair<contact::HertzMindlinDmt> pr(-2.0e-6, 0.0, -1.0);
    for (int k = 0; k < 10; ++k) pr.sim.step();
    CHECK(pr.sim.contact_count() == 0);
  }
  const double d_eq = std::pow(3.0 * kPiJkr * kW * std::sqrt(kRstar) / (2.0 * e_star()), 2.0 / 3.0);
  Pair<contact::HertzMindlinDmt> pr(0.5 * d_eq, 0.0, -1.0, 0.3);
  pr.sim.run_until(0.03);
  INFO("DMT delta_eq " << pr.overlap() << " m, theory " << d_eq);
  CHECK(pr.overlap() == Approx(d_eq).epsilon(1e-4));
}

// Reference (existing laws unchanged): a law without `tensile` leaves the model non-tensile,
// its pull-off separation 0 and its history exactly the tangential/rolling history (so the
// neighbour list, checkpoints and the packed path see the same State as before).
TEST_CASE("JKR/DMT: existing models are not tensile and keep their history layout", "[contact][cohesion][jkr]") {
  using namespace contact;
  static_assert(!HertzMindlin::tensile && !HertzMindlinEpsdSjkr::tensile && !LinearCoulombRolling::tensile);
  static_assert(HertzMindlinJkr::tensile);
  static_assert(sizeof(HertzMindlin::State<Dim3>) == sizeof(MindlinTangential::State<Dim3>));
  static_assert(!HertzFrictionless::has_state<Dim3> && !LinearFrictionless::has_state<Dim2>);
  static_assert(ContactModel<HertzNormal, NoTangential, NoRolling, JkrCohesion>::has_state<Dim3>);
  static_assert(HertzMindlin::lanes && HertzMindlinDmt::lanes && !HertzMindlinJkr::lanes);
  const auto prm = HertzMindlin::make(mix(adhesive_material(), adhesive_material()));
  CHECK(HertzMindlin::pull_off_separation(prm, kRstar) == 0.0);
}

// Reference: surface_energy is validated like the other material fields (named error).
TEST_CASE("JKR/DMT: surface energy validation", "[contact][cohesion][materials]") {
  Material m = adhesive_material();
  m.surface_energy = -1.0;
  CHECK_THROWS_WITH(m.validate(), Catch::Contains("surface_energy"));
  PairOverride o;
  o.surface_energy = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(o.validate("set_pair"), Catch::Contains("surface_energy"));
  o.surface_energy = 0.2;
  CHECK(o.apply(PairMaterial{}).surface_energy == 0.2);
}
