// Constant-stiffness SDS rolling resistance (contact/rolling/sds.hpp, LAMMPS `rolling sds`) on
// a sphere (disk) resting on a plane wall, against analytic references:
//  * the small-angle rolling oscillation under the rolling spring alone,
//  * its decay rate under the rolling dashpot,
//  * the mobilised (plastic) limit torque mu_r R* F_n on a slope steeper than the rolling
//    friction angle, and rest on a gentler one,
//  * the named error for a pair with rolling friction and no rolling spring.
//
// Rolling oscillation. The particle (mass m, moment of inertia I = k m r^2, k = 2/5 sphere, 1/2
// disk) rests with overlap delta on the wall, lever arm a = r - delta (simulation.hpp
// wall_geometry). Rolling without slip about the contact point, theta the rolling angle:
//   (I + m a^2) theta'' + C theta' + K theta = 0,   K = k_roll R*^2, R* = r (a wall),
// so w0 = sqrt(K / (I + m a^2)) -- the inertia about the contact point -- and the amplitude
// decays as exp(-sigma t), sigma = C / (2 (I + m a^2)) with C = eta_r 2 sqrt(I_r K) and the
// engine's I_r = I + m r^2 (Ai et al. 2011 eq. 14). The tangential spring k_t at the contact is
// in series with the rolling constraint: with the centre x and the rotation phi as coordinates,
//   m x'' = -k_t (x - a phi),   I phi'' = k_t a (x - a phi) - K phi,
// whose slow root m I w^4 - (m (k_t a^2 + K) + I k_t) w^2 + k_t K = 0 is the reference (it is
// w0 to 1 - O(K / (k_t a^2))).
//
// Mobilised limit. On a slope alpha (gravity tilted), with enough sliding friction to roll
// without slip, the rolling torque is held at M_m = mu_r R* F_n, F_n = m g cos alpha, once
// m g sin alpha a > M_m, i.e. tan alpha > mu_r r / a:
//   (I + m a^2) omega' = m g sin alpha a - mu_r r m g cos alpha.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "granule/granule.hpp"

using namespace granule;

namespace {

constexpr double kSdsR = 1.25e-3, kSdsRho = 2500.0, kSdsE = 5.0e6, kSdsNu = 0.2, kSdsG = 100.0;

template <class D>
struct OnPlane {
  using Vec = typename D::Vec;
  using Sim = Simulation<D, contact::HertzMindlinSds>;
  std::unique_ptr<Sim> sim;

  OnPlane(double k_roll, double mu_r, double eta_r, double slope, double dt) {
    SimulationConfig<D> cfg;
    cfg.domain.lo = Vec::Constant(-0.02);
    cfg.domain.hi = Vec::Constant(0.02);
    cfg.gravity = Vec::Zero();
    cfg.gravity[0] = kSdsG * std::sin(slope);
    cfg.gravity[D::dim - 1] = -kSdsG * std::cos(slope);
    cfg.dt = dt;
    cfg.thickness = 2.0 * kSdsR;
    sim = std::make_unique<Sim>(cfg);
    Material m{.youngs_modulus = kSdsE, .poisson_ratio = kSdsNu, .density = kSdsRho, .restitution = 0.5, .friction = 1.0};
    m.rolling_friction = mu_r;
    m.rolling_damping = eta_r;
    m.rolling_stiffness = k_roll;
    const auto mat = sim->add_material(m), wall = sim->add_wall_material(m);
    Vec up = Vec::Zero();
    up[D::dim - 1] = 1.0;
    sim->add_wall(geometry::PlaneShape<D>(Vec::Zero(), up), wall);
    // Near the 3D Hertz rest overlap; the normal dashpot (e = 0.5) settles the rest.
    const double mass = kSdsRho * 4.0 / 3.0 * std::numbers::pi * kSdsR * kSdsR * kSdsR;
    const double e_eff = kSdsE / (2.0 * (1.0 - kSdsNu * kSdsNu));
    const double overlap = std::pow(mass * kSdsG * std::cos(slope) / (4.0 / 3.0 * e_eff * std::sqrt(kSdsR)), 2.0 / 3.0);
    sim->add_particle(up * (kSdsR - overlap), kSdsR, mat);
  }
  double& spin() {
    if constexpr (D::dim == 3) {
      return sim->particles().omega[0][1];
    } else {
      return sim->particles().omega[0];
    }
  }
  double lever_arm() const { return sim->particles().x[0][D::dim - 1]; }
  /// Starts rolling without slip at spin w (3D about y, 2D about z; both roll along x).
  void launch(double w) {
    // v_contact = v - a omega x n = 0 with n = z: 3D v_x = a omega_y, 2D v_x = -a omega_z.
    spin() = w;
    sim->particles().v[0][0] = (D::dim == 3 ? 1.0 : -1.0) * lever_arm() * w;
  }
};

// Times of the upward zero crossings and the peaks of the spin over `steps` steps.
template <class D>
void record(OnPlane<D>& op, int steps, std::vector<double>& ups, std::vector<double>& peaks) {
  double prev = op.spin(), prev2 = prev;
  const double dt = op.sim->config().dt;
  for (int s = 0; s < steps; ++s) {
    op.sim->step();
    const double w = op.spin();
    if (prev <= 0.0 && w > 0.0) ups.push_back(op.sim->time() - dt * w / (w - prev));
    if (prev > prev2 && prev >= w && prev > 0.0) peaks.push_back(prev);
    prev2 = prev;
    prev = w;
  }
}

}  // namespace

TEMPLATE_TEST_CASE("SDS rolling: small-angle oscillation period and dashpot decay on a plane",
                   "[contact][rolling][sds]", Dim2, Dim3) {
  using D = TestType;
  const double k_roll = 0.5, dt = 5e-6, w0 = 0.01;
  for (const double eta : {0.0, 0.05}) {
    OnPlane<D> op(k_roll, 0.8, eta, 0.0, dt);
    op.sim->run(4000);  // settle the normal bounce (20 ms)
    const auto& p = op.sim->particles();
    const double m = p.mass[0], inertia = 1.0 / p.inv_inertia[0], a = op.lever_arm(), delta = kSdsR - a;
    REQUIRE(inertia == Approx(D::inertia_factor * m * kSdsR * kSdsR).epsilon(1e-9));
    op.launch(w0);
    std::vector<double> ups, peaks;
    record(op, 50000, ups, peaks);
    REQUIRE(ups.size() >= 3);
    const double period = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
    const double kr = k_roll * kSdsR * kSdsR, i_contact = inertia + m * a * a;
    const double w_simple = std::sqrt(kr / i_contact);
    // The tangential spring: Mindlin k_t = 8 G* sqrt(R* delta) in 3D; in 2D read from the law.
    const double g_eff = kSdsE / (4.0 * (2.0 - kSdsNu) * (1.0 + kSdsNu));
    contact::ContactGeometry<D> g{};
    g.r_eff = kSdsR;
    g.overlap = delta;
    g.m_eff = m;
    g.vn = g.vn_damp = 0.0;
    const auto prm = contact::HertzMindlinSds::make(op.sim->materials().pair(0, 1), 2.0 * kSdsR);
    const contact::NormalResult nr = contact::HertzNormal::eval(prm.normal, g);
    const double kt = contact::MindlinTangential::spring_dashpot(prm.tangential, g, nr).stiffness;
    if constexpr (D::dim == 3) CHECK(kt == Approx(8.0 * g_eff * std::sqrt(kSdsR * delta)).epsilon(1e-9));
    const double b = m * (kt * a * a + kr) + inertia * kt;
    const double w_slow = std::sqrt((b - std::sqrt(b * b - 4.0 * m * inertia * kt * kr)) / (2.0 * m * inertia));
    const double sigma = eta * 2.0 * std::sqrt((inertia + m * kSdsR * kSdsR) * kr) / (2.0 * i_contact);
    const double w_damped = std::sqrt(w_slow * w_slow - sigma * sigma);
    INFO("dim " << D::dim << " eta_r " << eta << ": period " << period << " s, 2 pi / w " << 2.0 * std::numbers::pi / w_damped
                << " s (no k_t: " << 2.0 * std::numbers::pi / w_simple << " s), delta " << delta << " m, k_t " << kt);
    CHECK(period == Approx(2.0 * std::numbers::pi / w_damped).epsilon(1e-4));
    // The rolling angle stays far below mobilisation (K theta << mu_r r m g): the law is elastic.
    CHECK(kr * w0 / w_simple < 1e-3 * 0.8 * kSdsR * m * kSdsG);
    if (eta > 0.0) {
      REQUIRE(peaks.size() >= 4);
      const double measured = std::log(peaks[0] / peaks[3]) / (3.0 * period);
      INFO("decay rate " << measured << " 1/s, C / (2 (I + m a^2)) = " << sigma << " 1/s");
      CHECK(measured == Approx(sigma).epsilon(5e-3));
    } else {
      REQUIRE(peaks.size() >= 2);
      CHECK(peaks.back() == Approx(peaks.front()).epsilon(0.01));
    }
  }
}

TEST_CASE("SDS rolling: the mobilised torque mu_r R* F_n on a slope", "[contact][rolling][sds]") {
  using D = Dim3;
  const double mu_r = 0.1, dt = 5e-6;
  // Above the rolling friction angle: constant angular acceleration once the slider holds.
  {
    const double slope = std::atan(2.0 * mu_r);
    OnPlane<D> op(100.0, mu_r, 0.5, slope, dt);
    op.sim->run(1000);
    const double w1 = op.spin(), t1 = op.sim->time();
    op.sim->run(3000);
    const double w2 = op.spin(), t2 = op.sim->time();
    const auto& p = op.sim->particles();
    const double m = p.mass[0], inertia = 1.0 / p.inv_inertia[0], a = op.lever_arm();
    const double expected = m * kSdsG * (std::sin(slope) * a - mu_r * kSdsR * std::cos(slope)) / (inertia + m * a * a);
    // Without the limit the same slope would roll freely: m g sin a / (I + m a^2) a.
    const double free_rolling = m * kSdsG * std::sin(slope) * a / (inertia + m * a * a);
    INFO("omega' " << (w2 - w1) / (t2 - t1) << " rad/s^2, expected " << expected << ", free " << free_rolling);
    CHECK((w2 - w1) / (t2 - t1) == Approx(expected).epsilon(1e-4));
  }
  // Below it: the spring holds the sphere, the dashpot brings it to rest.
  {
    const double slope = std::atan(0.5 * mu_r);
    OnPlane<D> op(100.0, mu_r, 0.5, slope, dt);
    op.sim->run(4000);
    const double x1 = op.sim->particles().x[0][0];
    op.sim->run(4000);
    INFO("omega " << op.spin() << " rad/s, drift " << op.sim->particles().x[0][0] - x1 << " m");
    CHECK(std::abs(op.spin()) < 1e-3);
    CHECK(std::abs(op.sim->particles().x[0][0] - x1) < 1e-9);
  }
}

TEST_CASE("SDS rolling: parameters, mixing and the time-step limit", "[contact][rolling][sds][errors]") {
  Material a{.youngs_modulus = kSdsE, .poisson_ratio = kSdsNu, .density = kSdsRho};
  a.rolling_friction = 0.1;
  a.rolling_stiffness = 2.0;
  Material b = a;
  b.rolling_stiffness = 6.0;
  CHECK(mix(a, b).k_roll == Approx(3.0));  // springs in series: 2 * 2 * 6 / 8
  CHECK(mix(a, a).k_roll == Approx(2.0));
  CHECK(mix(a, Material::rigid_wall()).k_roll == Approx(2.0));
  PairOverride o;
  o.rolling_stiffness = 7.0;
  CHECK(o.apply(mix(a, b)).k_roll == 7.0);
  o.rolling_stiffness = -1.0;
  CHECK_THROWS_WITH(o.validate("set_pair"), Catch::Contains("rolling_stiffness = -1"));
  Material bad = a;
  bad.rolling_stiffness = -1.0;
  CHECK_THROWS_WITH(bad.validate(), Catch::Contains("rolling_stiffness"));
  // Rolling friction without a rolling spring: refused when the run starts, naming the pair
  // (not when the material is added: set_pair may still give the pair its k_roll).
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Dim3::Vec::Constant(-0.01);
  cfg.domain.hi = Dim3::Vec::Constant(0.01);
  cfg.dt = 1e-6;
  Material none = a;
  none.name = "grain";
  none.rolling_stiffness = 0.0;
  {
    Simulation<Dim3, contact::HertzMindlinSds> sim(cfg);
    const auto mat = sim.add_material(none);
    sim.add_particle(Dim3::Vec::Zero(), 1e-3, mat);
    CHECK_THROWS_WITH(sim.step(), Catch::Contains("material pair ('grain', 'grain'): rolling_stiffness = 0") &&
                                      Catch::Contains("k_roll"));
  }
  {
    Simulation<Dim3, contact::HertzMindlinSds> sim(cfg);
    const auto mat = sim.add_material(none);
    PairOverride o;
    o.rolling_stiffness = 10.0;
    sim.set_pair(mat, mat, o);
    sim.add_particle(Dim3::Vec::Zero(), 1e-3, mat);
    CHECK_NOTHROW(sim.step());
  }
  {
    // No rolling friction between the grains: k_roll may stay 0 there (the law does nothing);
    // against the walls the grain's k_roll (one side 0: the other's); two wall materials never
    // touch and are not checked (mu_r 0.1, k_roll 0).
    Simulation<Dim3, contact::HertzMindlinSds> sim(cfg);
    none.rolling_friction = 0.0;
    none.rolling_stiffness = 5.0;
    const auto mat = sim.add_material(none);
    Material wall = a;
    wall.rolling_stiffness = 0.0;
    sim.add_wall_material(wall);
    sim.add_wall_material(wall);
    sim.add_particle(Dim3::Vec::Zero(), 1e-3, mat);
    CHECK_NOTHROW(sim.step());
  }
  // The rolling spring-dashpot enters the engine's rotational limits. Before the first step
  // (no contact yet): one wall contact's pure rolling mode, w^2 = K / I, zeta = C / (2 I w) with
  // K = k_roll r^2, C = eta_r 2 sqrt(I_r K), I_r = I + m r^2, independent of the overlap; with
  // the contact the tangential terms lower it.
  OnPlane<Dim3> op(100.0, 0.1, 0.5, 0.0, 1e-6);
  const double m = kSdsRho * 4.0 / 3.0 * std::numbers::pi * kSdsR * kSdsR * kSdsR, inertia = 0.4 * m * kSdsR * kSdsR;
  const double kr = 100.0 * kSdsR * kSdsR, cr = 0.5 * 2.0 * std::sqrt(1.4 * m * kSdsR * kSdsR * kr);
  const double w = std::sqrt(kr / inertia), zeta = cr / (2.0 * inertia * w);
  CHECK(op.sim->rolling_limit_estimate().limit == Approx(2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta) / w).epsilon(1e-9));
  op.sim->step();
  const double limit = op.sim->rolling_stability_limit().limit;
  // (Here the tangential spring, k_t a^2 = 4x K, dominates the contact's row: 0.43x the estimate.)
  CHECK(limit < op.sim->rolling_limit_estimate().limit);
  CHECK(limit > 0.3 * op.sim->rolling_limit_estimate().limit);
}
