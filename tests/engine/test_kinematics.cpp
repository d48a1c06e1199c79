// Prescribed kinematics (boundaries/kinematics.hpp):
//  - every factory returns the value of its formula at chosen times;
//  - the engine drifts with the midpoint velocity, x += dt V(t + dt/2), which is the exact
//    integral over a step inside one linear piece: a body driven through a ramp sits on the area
//    under the velocity curve to round-off, and a spun body turns by omega t to round-off;
//  - for a sinusoid each step's displacement is too large by (w dt/2) / sin(w dt/2): a tapped
//    group comes back to its start and peaks at A (1 + (w dt)^2 / 24), second order in dt;
//  - invalid input throws InvalidParameter naming the parameter.
// Time steps are powers of two and knots integer multiples of them, so the engine's time
// (t += dt) is exact and step boundaries fall exactly on the knots.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>

#include "engine_helpers.hpp"

using namespace granule;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDt = 0x1.0p-18;  // [s], 3.8 us

template <class D>
SimulationConfig<D> kinematics_config(double dt) {
  SimulationConfig<D> cfg;
  cfg.domain.lo = D::Vec::Zero();
  cfg.domain.hi = D::Vec::Constant(0.04);
  cfg.dt = dt;
  cfg.thickness = 1e-3;
  return cfg;  // no gravity: a lone prescribed particle feels nothing anyway
}

template <class D>
typename D::Vec vec3(double a, double b, double c) {
  typename D::Vec v;
  if constexpr (D::dim == 2) {
    v << a, c;
  } else {
    v << a, b, c;
  }
  return v;
}

}  // namespace

TEST_CASE("Kinematics factories return their formulas", "[kinematics]") {
  using Vec = Eigen::Vector3d;
  const Vec u(0.25, -0.5, 2.0);
  SECTION("constant and starting_at") {
    const auto c = kinematics::constant(u);
    CHECK(c(-1.0) == u);
    CHECK(c(1e9) == u);
    const auto s = kinematics::starting_at(0.5, kinematics::constant(2.0 * u));  // an expression
    CHECK(s(std::nextafter(0.5, 0.0)) == Vec::Zero());
    CHECK(s(0.5) == 2.0 * u);  // closed at t0: the velocity of the motion that follows
    CHECK(s(3.0) == 2.0 * u);
    const auto w = kinematics::starting_at(1.0, [](double t) { return 3.0 * t; });  // 2D angular
    CHECK(w(0.75) == 0.0);
    CHECK(w(2.0) == 6.0);
  }
  SECTION("piecewise_linear") {
    // Knots and values are binary fractions, so interpolation at quarter points is exact.
    const auto v = kinematics::piecewise_linear({1.0, 2.0, 4.0}, {Vec(0, 0, 0), u, Vec(-u)});
    CHECK(v(-5.0) == Vec::Zero());  // constant before the first knot
    CHECK(v(1.0) == Vec::Zero());
    CHECK(v(1.25) == 0.25 * u);
    CHECK(v(2.0) == u);             // a knot returns its value exactly
    CHECK(v(3.0) == Vec::Zero());   // half way from u to -u
    CHECK(v(3.5) == -0.5 * u);
    CHECK(v(4.0) == -u);
    CHECK(v(100.0) == -u);          // constant after the last knot
    const auto one = kinematics::piecewise_linear({2.0}, {1.5});  // one point: a constant
    CHECK(one(0.0) == 1.5);
    CHECK(one(9.0) == 1.5);
  }
  SECTION("sinusoidal_displacement") {
    const double f = 50.0, w = 2.0 * std::numbers::pi * f, t0 = 0.01, phase = 0.3;
    const auto v = kinematics::sinusoidal_displacement(u, f, phase, t0, 2.0);
    CHECK(v(t0 - 1e-6) == Vec::Zero());
    CHECK(v(t0) == (w * std::cos(phase)) * u);  // the argument is exactly `phase` at t0
    // Inside: V = w A cos(w (t - t0) + phase); the reference evaluates the same expression in
    // another order, so agreement to a few ulp of the peak speed w |A| (here 1e-13 relative).
    for (double t : {0.0137, 0.0251, 0.0499}) {
      const Vec ref = u * (w * std::cos(w * (t - t0) + phase));
      CHECK((v(t) - ref).norm() < 1e-13 * w * u.norm());
    }
    CHECK(v(t0 + 2.0 / f) == Vec::Zero());  // two periods, then at rest: [t0, t0 + 2/f)
    CHECK(v(1.0) == Vec::Zero());
    const auto forever = kinematics::sinusoidal_displacement(1e-3, f);  // scalar, periods = inf
    CHECK(forever(0.0) == w * 1e-3);
    // Still shaking after 5e4 periods; w t = 1e5 pi is rounded by ~1e-11 rad, so cos = 1 - 1e-22.
    CHECK(forever(1e3) == Approx(w * 1e-3).epsilon(1e-12));
    CHECK(forever(-1e-9) == 0.0);
  }
  SECTION("spin") {
    CHECK(kinematics::spin(Vec(0, 0, 2), 3.0)(0.0) == Vec(0, 0, 3));
    const Vec w = kinematics::spin(Vec(1, 2, 2), 6.0)(7.0);  // |axis| = 3
    CHECK((w - Vec(2, 4, 4)).norm() < 4 * kEps * 6.0);       // axis / 3 rounds each component once
    CHECK(kinematics::spin(-2.5)(1.0) == -2.5);               // 2D: a scalar about z
    const auto ramp = kinematics::spin(Vec(0, 0, 1), kinematics::piecewise_linear({0.0, 1.0}, {0.0, 4.0}));
    CHECK(ramp(0.5) == Vec(0, 0, 2));
  }
}

TEMPLATE_TEST_CASE("A body driven through a velocity ramp sits on the area under the curve", "[kinematics]",
                   Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  Simulation<D, contact::HertzMindlin> sim(kinematics_config<D>(kDt));
  // Accelerate to U, cruise, then decelerate through zero to -U/2 (an intrusion stopping and
  // backing off). Knots on step boundaries: steps 64, 192, 448, 512.
  const Vec U = vec3<D>(0.05, -0.02, 0.01);  // [m/s]
  const std::vector<double> t = {64 * kDt, 192 * kDt, 448 * kDt, 512 * kDt};
  const std::vector<Vec> V = {Vec::Zero(), U, U, Vec(-0.5 * U)};
  Body<D> b;
  b.name = "ramp";
  const Vec x0 = vec3<D>(0.01, 0.02, 0.005);
  b.pose = geometry::Pose<D>::translation(x0);
  b.velocity = kinematics::piecewise_linear(t, V);
  const auto id = sim.add_body(b);
  // Analytic position: x0 + the area under the curve, trapezoids between knots.
  auto area = [&](double tt) {
    Vec a = Vec::Zero();
    for (std::size_t k = 0; k + 1 < t.size(); ++k) {
      if (tt <= t[k]) break;
      const double te = std::min(tt, t[k + 1]);
      const Vec ve = V[k] + (te - t[k]) / (t[k + 1] - t[k]) * (V[k + 1] - V[k]);
      a += 0.5 * (V[k] + ve) * (te - t[k]);
    }
    if (tt > t.back()) a += V.back() * (tt - t.back());
    return a;
  };
  const int steps = 640;
  double worst = 0.0, worst_knot = 0.0, scale = 0.0;
  for (int s = 1; s <= steps; ++s) {
    sim.step();
    const Vec x = sim.body(id).pose.translation();
    const double err = (x - (x0 + area(sim.time()))).cwiseAbs().maxCoeff();
    worst = std::max(worst, err);
    if (s == 64 || s == 192 || s == 448 || s == 512) worst_knot = std::max(worst_knot, err);
    scale = std::max(scale, x.cwiseAbs().maxCoeff());
    REQUIRE(sim.body(id).current_velocity == b.velocity(sim.time()));
  }
  // Round-off only: each step adds dt V to a coordinate of size <= scale, rounding by at most
  // eps/2 scale; the interpolated V itself is off by a few eps relatively (~1e-20 m per step).
  const double tol = steps * kEps * scale;
  const Vec total = area(steps * kDt);
  INFO("dim " << D::dim << ": displacement " << total.transpose() << " m; worst |x - x0 - area| = " << worst
              << " m (at knots " << worst_knot << " m), tolerance " << tol << " m");
  CHECK(total.norm() > 1e-5);  // the body really moved (|U| x 1.1 ms)
  CHECK(worst <= tol);
}

TEMPLATE_TEST_CASE("A spun body turns by omega t", "[kinematics]", Dim2, Dim3) {
  using D = TestType;
  using Mat = typename D::Mat;
  Simulation<D, contact::HertzMindlin> sim(kinematics_config<D>(kDt));
  const double omega = 500.0;  // [rad/s]: 1000 steps turn it by 1.9 rad
  Body<D> b;
  b.name = "turntable";
  Eigen::Vector3d axis(1.0, -2.0, 2.0);
  if constexpr (D::dim == 2) {
    b.angular_velocity = kinematics::spin(omega);
  } else {
    b.angular_velocity = kinematics::spin(axis, omega);
  }
  const auto id = sim.add_body(b);
  const int steps = 1000;
  double worst = 0.0;
  for (int s = 1; s <= steps; ++s) {
    sim.step();
    Mat exact;
    if constexpr (D::dim == 2) {
      exact = Eigen::Rotation2Dd(omega * sim.time()).toRotationMatrix();
    } else {
      exact = Eigen::AngleAxisd(omega * sim.time(), axis.normalized()).toRotationMatrix();
    }
    worst = std::max(worst, (sim.body(id).pose.rotation() - exact).cwiseAbs().maxCoeff());
  }
  // Every step composes one rotation (2D: adds to an angle of size <= pi) and re-normalises,
  // each contributing a few eps to the entries of R: after n steps at most ~ 10 n eps.
  const double tol = 10.0 * steps * kEps;
  INFO("dim " << D::dim << ": angle " << omega * sim.time() << " rad, worst |R - R(omega t)| = " << worst
              << ", tolerance " << tol);
  CHECK(worst <= tol);
  CHECK(sim.body(id).pose.translation() == D::Vec::Zero());  // pure rotation about the origin
}

namespace {

struct TapResult {
  double peak_error = 0.0;    ///< max over steps of the displacement along A, minus |A| [m]
  double return_error = 0.0;  ///< |x - x0| one period after t0 [m]
  double tolerance = 0.0;     ///< round-off bound of the return [m]
  double w_dt = 0.0;          ///< 2 pi f dt [-]
  double amplitude = 0.0;     ///< |A| [m]
};

// One period of a sinusoidal displacement of a lone prescribed particle, `n` steps per period,
// starting 16 steps in; 32 steps of rest follow.
template <class D>
TapResult run_tap(int n) {
  using Vec = typename D::Vec;
  const double dt = 64.0 / n * kDt;  // n a power of two: dt stays a power of two
  Simulation<D, contact::HertzMindlin> sim(kinematics_config<D>(dt));
  const auto mat = sim.add_material(test::soft_material());
  const Vec x0 = Vec::Constant(0.02);
  const auto pid = sim.add_particle(x0, 1e-3, mat, Vec::Zero(), 1);
  const Vec A = vec3<D>(3e-4, 1.2e-4, -4e-4);  // [m]
  const double f = 1.0 / (n * dt);              // [Hz]: 4096 Hz for n = 64 at kDt
  const double t0 = 16 * dt;
  sim.prescribe_group_velocity(1, kinematics::sinusoidal_displacement(A, f, 0.0, t0, 1.0));
  const Vec dir = A.normalized();
  TapResult r;
  r.w_dt = 2.0 * std::numbers::pi * f * dt;
  r.amplitude = A.norm();
  double peak = 0.0;
  for (int s = 1; s <= 16 + n + 32; ++s) {
    sim.step();
    const Vec x = sim.particles().x[sim.index_of(pid)];
    if (s <= 16) REQUIRE(x == x0);  // before t0: at rest, bitwise
    peak = std::max(peak, (x - x0).dot(dir));
    if (s == 16 + n) r.return_error = (x - x0).norm();
    if (s > 16 + n) REQUIRE((x - x0).norm() == r.return_error);  // after the tap: at rest
  }
  r.peak_error = peak - r.amplitude;
  // The n increments dt V cancel over the period; each addition to a coordinate of size |x0|
  // rounds by at most eps/2 |x0|, and w = 2 pi f is rounded (relative eps of A).
  r.tolerance = n * kEps * (x0.norm() + r.amplitude);
  return r;
}

}  // namespace

TEMPLATE_TEST_CASE("A tapped group returns to its start and peaks at A to second order", "[kinematics]", Dim2,
                   Dim3) {
  using D = TestType;
  const TapResult coarse = run_tap<D>(64);
  const TapResult fine = run_tap<D>(128);
  // Midpoint rule on a sinusoid: every step's displacement is scaled by x / sin x, x = w dt / 2,
  // so the peak (reached on a step boundary: n / 4 steps after t0) is |A| x / sin x, i.e.
  // |A| (w dt)^2 / 24 (1 + 7 (w dt)^2 / 240 + ...) above |A|. Bounds: the leading term below,
  // and above with 1/20 for the series' 7/240 (w dt ~ 0.1, higher terms are ~1e-5 smaller).
  for (const TapResult& r : {coarse, fine}) {
    const double lead = r.amplitude * r.w_dt * r.w_dt / 24.0;
    INFO("dim " << D::dim << ": w dt = " << r.w_dt << ", peak error " << r.peak_error << " m, leading term "
                << lead << " m; return error " << r.return_error << " m (tolerance " << r.tolerance << " m)");
    CHECK(r.return_error <= r.tolerance);
    CHECK(r.peak_error >= lead);
    CHECK(r.peak_error <= lead * (1.0 + r.w_dt * r.w_dt / 20.0));
  }
  // Second order: halving dt divides the error by 4 (1 + 7 (w dt)^2 / 320) ~ 4.001 here; 1 %
  // leaves room for nothing but the neglected (w dt)^4 terms (1e-4) and round-off (1e-9).
  const double ratio = coarse.peak_error / fine.peak_error;
  INFO("error ratio dt / (dt/2): " << ratio);
  CHECK(ratio == Approx(4.0).epsilon(0.01));
}

TEST_CASE("Invalid kinematics throw InvalidParameter naming the parameter", "[kinematics]") {
  using Vec = Eigen::Vector3d;
  using Catch::Contains;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto pl = [](std::vector<double> t, std::vector<Vec> v) { return kinematics::piecewise_linear(t, v); };
  CHECK_THROWS_AS(pl({}, {}), InvalidParameter);
  CHECK_THROWS_WITH(pl({}, {}), Contains("times.size()") && Contains("[1, inf)"));
  CHECK_THROWS_WITH(pl({0.0, 1.0}, {Vec::Zero()}), Contains("values.size()") && Contains("{2}"));
  CHECK_THROWS_WITH(pl({0.0, 2.0, 1.0}, {Vec::Zero(), Vec::Zero(), Vec::Zero()}),
                    Contains("times[2]") && Contains("strictly increasing"));
  CHECK_THROWS_WITH(pl({0.0, 0.0}, {Vec::Zero(), Vec::Zero()}), Contains("times[1]"));
  CHECK_THROWS_WITH(pl({0.0, inf}, {Vec::Zero(), Vec::Zero()}), Contains("times[1]") && Contains("finite"));
  CHECK_THROWS_WITH(pl({0.0, 1.0}, {Vec::Zero(), Vec(0, nan, 0)}), Contains("values[1]"));
  CHECK_THROWS_AS(kinematics::constant(Vec(inf, 0, 0)), InvalidParameter);
  CHECK_THROWS_WITH(kinematics::constant(nan), Contains("value"));
  CHECK_THROWS_WITH(kinematics::starting_at(nan, kinematics::constant(1.0)), Contains("t0"));
  CHECK_THROWS_WITH(kinematics::starting_at(0.0, std::function<double(double)>()), Contains("f ="));
  CHECK_THROWS_WITH(kinematics::sinusoidal_displacement(1.0, 0.0), Contains("frequency") && Contains("(0, inf)"));
  CHECK_THROWS_WITH(kinematics::sinusoidal_displacement(1.0, -5.0), Contains("frequency"));
  CHECK_THROWS_WITH(kinematics::sinusoidal_displacement(1.0, 5.0, 0.0, 0.0, 0.0),
                    Contains("periods") && Contains("(0, inf]"));
  CHECK_THROWS_WITH(kinematics::sinusoidal_displacement(1.0, 5.0, nan), Contains("phase"));
  CHECK_THROWS_WITH(kinematics::sinusoidal_displacement(Vec(nan, 0, 0), 5.0), Contains("amplitude"));
  CHECK_THROWS_WITH(kinematics::spin(Vec::Zero(), 1.0), Contains("|axis|") && Contains("(0, inf)"));
  CHECK_THROWS_WITH(kinematics::spin(Vec::UnitZ(), nan), Contains("omega"));
  CHECK_THROWS_WITH(kinematics::spin(inf), Contains("omega"));
}
