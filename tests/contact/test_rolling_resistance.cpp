// Rolling resistance: a particle rolling without slip on a plane wall under gravity decelerates
// under the constant-torque model (Ai et al. 2011 model A) and under the EPSD model (model C,
// paper 001 eq. A13-A15) once its spring is fully mobilised; the EPSD spring stiffness k_r is
// checked directly through ContactModel::evaluate.
#include <catch2/catch.hpp>

#include <cmath>

#include "contact_test_support.hpp"

using namespace granule;
using namespace granule::contact_test;

namespace {

Material rolling_material() {
  Material m;
  m.youngs_modulus = 1.0e7;  // [Pa]
  m.poisson_ratio = 0.3;     // [-]
  m.density = 2500.0;        // [kg/m^3]
  m.restitution = 0.5;       // damps normal and tangential vibrations
  m.friction = 0.5;          // mu_s: enough to roll without slip
  m.rolling_friction = 0.1;  // mu_r [-]
  m.rolling_damping = 0.3;   // eta_r [-] (EPSD only)
  return m;
}

using ConstantTorqueModel =
    contact::ContactModel<contact::HertzNormal, contact::MindlinTangential, contact::ConstantTorqueRolling>;

struct RollResult {
  double stop_distance = 0.0;   ///< distance travelled until v_x first reaches 0 [m]
  double deceleration = 0.0;    ///< mean -dv/dt between 20 % and 70 % of the stop time [m/s^2]
  double torque_ratio_min = 1e9;  ///< min of |M_r| / (mu_r R* |F_n|) in steady rolling
  double torque_ratio_max = 0.0;  ///< max of the same
  double max_slip = 0.0;        ///< max |contact-point velocity| / v0 in steady rolling
  double torque_ratio_peak = 0.0;  ///< max of |M_r| / (mu_r R* |F_n|) over the whole run
};

// Rolls a particle of radius r (starting at rest overlap `overlap0`, v0 along +x, rolling without
// slip) until it stops. The rolling torque is M_r = torque - (-(r - delta) n x F_t).
template <class D, class Model>
RollResult roll(const Material& mat, double r, double thickness, double v0, double g, double overlap0,
                double dt, double t_stop_estimate) {
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.05);
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.gravity = -g * up<D>();
  cfg.dt = dt;
  cfg.thickness = thickness;
  Simulation<D, Model> sim(cfg);
  const auto pm = sim.add_material(mat);
  sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), up<D>()), sim.add_wall_material(mat));
  const double h0 = r - overlap0;
  const auto id = sim.add_particle(Vec(h0 * up<D>()), r, pm, Vec(v0 * unit<D>(0)));
  auto& p = sim.particles();
  p.omega[sim.index_of(id)] = rolling_omega<D>(v0, h0);
  RollResult out;
  double t20 = -1.0, v20 = 0.0, t70 = -1.0, v70 = 0.0;
  double prev_x = 0.0, prev_v = v0;
  const long max_steps = static_cast<long>(3.0 * t_stop_estimate / dt);
  for (long k = 0; k < max_steps; ++k) {
    sim.request_contacts();
    sim.step();
    const std::size_t i = sim.index_of(id);
    const double x = p.x[i][0], v = p.v[i][0], t = sim.time();
    if (t20 < 0.0 && t >= 0.2 * t_stop_estimate) { t20 = t; v20 = v; }
    if (t70 < 0.0 && t >= 0.7 * t_stop_estimate) { t70 = t; v70 = v; }
    // The first step records nothing (the request is consumed by the initial force evaluation;
    // see test_contact_recording.cpp); every later step has the one wall contact.
    const auto fr = sim.frame();
    if (k > 0 && fr.contacts.size() != 1) FAIL("expected one wall contact at step " << k);
    if (fr.contacts.empty()) continue;
    const auto& c = fr.contacts[0];
    const Vec n = c.normal;
    const typename D::AngVec m_r = p.torque[i] - (-(r - c.overlap)) * D::cross(n, Vec(c.ft));
    const double ratio = D::norm(m_r) / (mat.rolling_friction * r * std::abs(c.fn));
    out.torque_ratio_peak = std::max(out.torque_ratio_peak, ratio);
    if (t > 0.1 * t_stop_estimate && t < 0.9 * t_stop_estimate) {
      out.torque_ratio_min = std::min(out.torque_ratio_min, ratio);
      out.torque_ratio_max = std::max(out.torque_ratio_max, ratio);
      const Vec vc = p.v[i] - (r - c.overlap) * D::cross(p.omega[i], n);
      out.max_slip = std::max(out.max_slip, vc.norm() / v0);
    }
    if (v <= 0.0) {
      out.stop_distance = prev_x + (x - prev_x) * prev_v / (prev_v - v);
      break;
    }
    prev_x = x;
    prev_v = v;
  }
  out.deceleration = (v20 - v70) / (t70 - t20);
  return out;
}

}  // namespace

// Reference: Ai, Chen, Rotter & Ooi (2011), Powder Technol. 206, 269, model A (constant
// directional torque M = mu_r R* F_n, R* = r on a wall), and rigid-body mechanics of rolling
// without slip, derived here: with friction f at the contact point and the centre at h = r - delta
//   m dv/dt = f,   I domega/dt = -M - f h,   v = omega h
//   =>  (m h + I / h) a = M,   a = mu_r r m g / (m h + k m r^2 / h)  ~  mu_r g / (1 + k),
//   stopping distance s = v0^2 / (2 a)     (sphere k = 2/5: a = mu_r g / 1.4; disk k = 1/2: / 1.5).
// Tolerances: deceleration and stopping distance 1 % (measured 1e-6 and 2e-5); the torque must be
// the full mu_r R* F_n while rolling (1e-9). Using R* = r/2, forgetting the I/h^2 term or the sign of
// the torque fails by > 30 %.
TEMPLATE_TEST_CASE("Constant-torque rolling resistance: deceleration and stopping distance (Ai et al. 2011 A)",
                   "[contact][rolling]", Dim2, Dim3) {
  using D = TestType;
  const Material mat = rolling_material();
  const double r = 5.0e-3, t = 2.0e-3, v0 = 0.1, g = 9.81;  // [m], [m], [m/s], [m/s^2]
  const double k = D::inertia_factor;
  const double m = mass_of<D>(mat.density, r, t);
  const double E_eff = mat.youngs_modulus / (2.0 * (1.0 - mat.poisson_ratio * mat.poisson_ratio));
  const double overlap0 = std::pow(m * g / (4.0 / 3.0 * E_eff * std::sqrt(r)), 2.0 / 3.0);
  const double h = r - overlap0;
  const double a = mat.rolling_friction * r * m * g / (m * h + k * m * r * r / h);
  const double s = v0 * v0 / (2.0 * a);
  const auto res = roll<D, ConstantTorqueModel>(mat, r, t, v0, g, overlap0, 1.0e-5, v0 / a);
  INFO("dim " << D::dim << ": a = " << res.deceleration << " m/s^2 (theory " << a << ", rigid mu_r g/(1+k) = "
              << mat.rolling_friction * g / (1.0 + k) << "), stop distance " << res.stop_distance << " m (theory "
              << s << "), |M_r|/(mu_r R* F_n) in [" << res.torque_ratio_min << ", " << res.torque_ratio_max
              << "], max slip/v0 " << res.max_slip);
  CHECK(res.deceleration == Approx(a).epsilon(0.01));
  CHECK(res.stop_distance == Approx(s).epsilon(0.01));
  CHECK(res.torque_ratio_min == Approx(1.0).epsilon(1e-9));
  CHECK(res.torque_ratio_max == Approx(1.0).epsilon(1e-9));
  CHECK(res.max_slip < 1e-3);  // rolls without slip
}

// Reference: paper 001 eq. A13-A15 / Ai et al. (2011) model C (EPSD): in steady rolling the
// spring torque is fully mobilised, |M_r| = mu_r R* |F_n|, and the damping is off (001 eq. A15),
// so the deceleration is that of model A above (tolerance 1 %, measured 1e-6). Without rolling
// damping the stopping distance matches v0^2 / (2 a) to 2 %: the spring first needs a rotation
// M_m / k_r = delta / (2.25 mu_r R*) ~ 8e-3 rad to mobilise (0.5 % of the distance) and rocks at
// the end. With eta_r = 0.3 the particle, which starts rolling on an unloaded spring, is braked
// by the dashpot torque C_r omega during that mobilisation, which model C does not cap: it reaches
// 12-18 x mu_r R* F_n here and shortens the run by 4-6 % (reported, not a defect of the published
// model; see the report).
TEMPLATE_TEST_CASE("EPSD rolling resistance: fully mobilised torque and stopping distance (001 eq. A13-A15)",
                   "[contact][rolling]", Dim2, Dim3) {
  using D = TestType;
  Material mat = rolling_material();
  const double r = 5.0e-3, t = 2.0e-3, v0 = 0.1, g = 9.81;
  const double k = D::inertia_factor;
  const double m = mass_of<D>(mat.density, r, t);
  const double E_eff = mat.youngs_modulus / (2.0 * (1.0 - mat.poisson_ratio * mat.poisson_ratio));
  const double overlap0 = std::pow(m * g / (4.0 / 3.0 * E_eff * std::sqrt(r)), 2.0 / 3.0);
  const double h = r - overlap0;
  const double a = mat.rolling_friction * r * m * g / (m * h + k * m * r * r / h);
  const double s = v0 * v0 / (2.0 * a);
  for (const double eta_r : {0.0, 0.3}) {
    mat.rolling_damping = eta_r;
    const auto res = roll<D, contact::HertzMindlinEpsd>(mat, r, t, v0, g, overlap0, 1.0e-5, v0 / a);
    INFO("dim " << D::dim << " eta_r = " << eta_r << ": a = " << res.deceleration << " m/s^2 (theory " << a
                << "), stop distance " << res.stop_distance << " m (theory " << s << "), |M_r|/(mu_r R* F_n) in ["
                << res.torque_ratio_min << ", " << res.torque_ratio_max << "], peak " << res.torque_ratio_peak);
    CHECK(res.torque_ratio_min == Approx(1.0).epsilon(1e-9));
    CHECK(res.torque_ratio_max == Approx(1.0).epsilon(1e-9));
    CHECK(res.deceleration == Approx(a).epsilon(0.01));
    if (eta_r == 0.0) {
      CHECK(res.stop_distance == Approx(s).epsilon(0.02));
      CHECK(res.torque_ratio_peak <= 1.0 + 1e-9);
    } else {
      WARN("EPSD with eta_r = 0.3, dim " << D::dim << ": stop distance / theory = " << res.stop_distance / s
                                         << ", peak rolling torque / (mu_r R* F_n) = " << res.torque_ratio_peak);
      CHECK(res.stop_distance < s);
    }
  }
}

// Reference: Ai et al. (2011) eq. 13 (k_r = 2.25 k_n mu_r^2 R*^2; paper 001 eq. A14 prints 2.55)
// with k_n the normal law's secant stiffness (4/3 E* sqrt(R* delta) for Hertz, k_n for the linear
// law), eq. 14 (C_r = eta_r 2 sqrt(I_r k_r)), and the plastic limit mu_r R* |F_n|. Direct calls of
// ContactModel<...>::evaluate on a hand-built pair geometry, no normal or tangential motion, so the
// torque on i is the rolling torque alone: after n steps of relative rotation w dt,
// M = -k_r n w dt (elastic, eta_r = 0), exact to round-off.
TEMPLATE_TEST_CASE("EPSD rolling spring: k_r = 2.25 k_n mu_r^2 R*^2, damping and plastic limit",
                   "[contact][rolling][epsd]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  Material mat = rolling_material();
  mat.rolling_damping = 0.0;
  const double r = 5.0e-3, m = 1.0e-3, overlap = 1.0e-5, dt = 1.0e-6;
  const Vec xi = (2.0 * r - overlap) * unit<D>(0), xj = Vec::Zero();
  AngVec w;
  if constexpr (D::dim == 2) {
    w = 0.3;  // [rad/s]
  } else {
    w = Eigen::Vector3d(0.0, 0.2, 0.1);  // rolling part only (perpendicular to n = x)
  }
  const double r_eff = 0.5 * r;
  const double E_eff = mat.youngs_modulus / (2.0 * (1.0 - mat.poisson_ratio * mat.poisson_ratio));
  const double kn_hertz = 4.0 / 3.0 * E_eff * std::sqrt(r_eff * overlap);
  const double mu_r = mat.rolling_friction;
  // Pure relative rolling: omega_i = w/2, omega_j = -w/2 give omega_rel = w and no slip at the
  // contact point (equal lever arms), so the tangential spring stays unloaded.
  const auto g = make_pair_geometry<D>(xi, xj, r, r, m, m, Vec::Zero(), Vec::Zero(), AngVec(0.5 * w),
                                       AngVec(-0.5 * w), dt);
  REQUIRE(g.vt.norm() <= 1e-15);
  {
    using Model = contact::HertzMindlinEpsd;
    const auto prm = Model::make(mix(mat, mat));
    typename Model::template State<D> st{};
    const double kr = 2.25 * kn_hertz * mu_r * mu_r * r_eff * r_eff;
    contact::ContactForce<D> f;
    for (int n = 1; n <= 5; ++n) {
      f = Model::evaluate(prm, g, st);
      const AngVec expected = -kr * n * dt * w;
      CHECK(D::norm(f.torque_i - expected) <= 1e-12 * D::norm(expected));
      CHECK(D::norm(f.torque_j + expected) <= 1e-12 * D::norm(expected));  // equal and opposite
      CHECK(f.ft.norm() <= 1e-15);
    }
    // Energy stored in the rolling spring, |M|^2 / (2 k_r) = k_r theta^2 / 2.
    const auto nr = contact::HertzNormal::eval(prm.normal, g);
    const double e_roll = contact::EpsdRolling::energy(prm.rolling, g, nr, st.rolling);
    CHECK(e_roll == Approx(0.5 * kr * std::pow(5 * dt * D::norm(w), 2)).epsilon(1e-9));
    // Large rotation: the torque saturates at mu_r R* F_n (F_n = 4/3 E* sqrt(R*) delta^1.5 here).
    const auto g_big = make_pair_geometry<D>(xi, xj, r, r, m, m, Vec::Zero(), Vec::Zero(), AngVec(0.5e6 * w),
                                             AngVec(-0.5e6 * w), dt);
    f = Model::evaluate(prm, g_big, st);
    const double fn = kn_hertz * overlap;
    // (1e-10: at these spins the lever arms' products arm_i w_i + arm_j w_j cancel only to
    // rounding when the compiler fuses them into a multiply-add (-march=native), ~4e-14 m/s of
    // slip whose tangential force adds ~4e-11 of the torque.)
    CHECK(D::norm(f.torque_i) == Approx(mu_r * r_eff * fn).epsilon(1e-10));
    CHECK(D::norm(f.torque_i + D::norm(f.torque_i) / D::norm(w) * w) <= 1e-10 * D::norm(f.torque_i));
  }
  {
    // Linear normal law: k_n is the material's normal stiffness.
    Material lin = mat;
    lin.normal_stiffness = 3.0e3;  // [N/m]
    using Model = contact::LinearCoulombRolling;
    const auto prm = Model::make(mix(lin, lin));
    typename Model::template State<D> st{};
    const auto f = Model::evaluate(prm, g, st);
    const double kr = 2.25 * lin.normal_stiffness * mu_r * mu_r * r_eff * r_eff;
    CHECK(D::norm(f.torque_i - AngVec(-kr * dt * w)) <= 1e-12 * kr * dt * D::norm(w));
  }
  {
    // Damping while not mobilised: M = M_k - C_r w, C_r = eta_r 2 sqrt(I_r k_r).
    Material damped = mat;
    damped.rolling_damping = 0.3;
    using Model = contact::HertzMindlinEpsd;
    const auto prm = Model::make(mix(damped, damped));
    typename Model::template State<D> st{};
    const auto f = Model::evaluate(prm, g, st);
    const double kr = 2.25 * kn_hertz * mu_r * mu_r * r_eff * r_eff;
    const double i_roll = 1.0 / (2.0 / ((D::inertia_factor + 1.0) * m * r * r));
    const double cr = 0.3 * 2.0 * std::sqrt(i_roll * kr);
    const AngVec expected = -kr * dt * w - cr * w;
    CHECK(D::norm(f.torque_i - expected) <= 1e-12 * D::norm(expected));
  }
}
