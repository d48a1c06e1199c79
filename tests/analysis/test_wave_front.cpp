// Tests of granule/analysis/wave_front.hpp. References: a synthetic Gaussian pulse travelling at a
// known speed (arrival = x / c + t0 by construction); the least-squares line and its standard
// uncertainty worked by hand (Taylor 1997, eq. 8.10–8.17) for three points.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "granule/analysis/wave_front.hpp"

using namespace granule::analysis;

namespace {

// Sensors at x_k = k · dx sampled every dt: baseline 1 plus a Gaussian pulse of amplitude 50
// and width tau arriving at t0 + x / c. Sensors listed in `spikes` get an extra early spike of
// amplitude 80, `lead` seconds before the pulse (outliers that the 2σ rejection must remove).
std::vector<SensorSeries> travelling_pulse(double c, int sensors, double dx, double dt,
                                           double duration, const std::vector<int>& spikes,
                                           double lead) {
  const double t0 = 1e-3;
  const double tau = 2e-4;
  std::vector<SensorSeries> out;
  const int samples = static_cast<int>(duration / dt) + 1;
  for (int k = 0; k < sensors; ++k) {
    SensorSeries s;
    s.position = k * dx;
    const bool spiky = std::find(spikes.begin(), spikes.end(), k) != spikes.end();
    for (int q = 0; q < samples; ++q) {
      const double t = q * dt;
      const double arg = (t - t0 - s.position / c) / tau;
      double y = 1.0 + 50.0 * std::exp(-arg * arg);
      if (spiky) {
        const double a2 = (t - t0 - s.position / c + lead) / (0.5 * tau);
        y += 80.0 * std::exp(-a2 * a2);
      }
      s.time.push_back(t);
      s.signal.push_back(y);
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

TEST_CASE("least-squares line and its uncertainty by hand", "[analysis][wave_front]") {
  // (0,0), (1,1), (2,3): slope 3/2, intercept −1/6, residuals (1/6, −1/3, 1/6),
  // s² = (1/6)/1, u(slope) = s/√2, u(intercept) = s √(1/3 + 1/2).
  const LineFit f = fit_line({0.0, 1.0, 2.0}, {0.0, 1.0, 3.0});
  CHECK(f.slope == Approx(1.5).epsilon(1e-15));
  CHECK(f.intercept == Approx(-1.0 / 6.0).epsilon(1e-14));
  CHECK(f.residual_sigma == Approx(std::sqrt(1.0 / 6.0)).epsilon(1e-14));
  CHECK(f.slope_uncertainty == Approx(std::sqrt(1.0 / 12.0)).epsilon(1e-14));
  CHECK(f.intercept_uncertainty == Approx(std::sqrt(1.0 / 6.0 * 5.0 / 6.0)).epsilon(1e-14));
  CHECK_THROWS_AS(fit_line({1.0, 1.0, 1.0}, {0.0, 1.0, 2.0}), granule::InvalidParameter);
  CHECK_THROWS_AS(fit_line({1.0, 2.0}, {0.0, 1.0}), granule::InvalidParameter);
}

TEST_CASE("arrival time: first local maximum above the threshold", "[analysis][wave_front]") {
  SensorSeries s;
  // Initial level 2; a bump to 15 (< 10 × 2) at t = 2, the real peak 40 at t = 5.
  s.time = {0, 1, 2, 3, 4, 5, 6, 7};
  s.signal = {2, 5, 15, 6, 20, 40, 30, 50};
  CHECK(*arrival_time(s) == 5.0);
  ArrivalSettings abs;
  abs.absolute_threshold = 10.0;
  CHECK(*arrival_time(s, abs) == 2.0);
  ArrivalSettings base;
  base.baseline_samples = 2;  // level 3.5 → threshold 35
  CHECK(*arrival_time(s, base) == 5.0);
  base.relative_threshold = 20.0;  // threshold 70: no maximum above it (50 is the last sample)
  CHECK_FALSE(arrival_time(s, base).has_value());
  // Parabolic refinement recovers the vertex of a sampled parabola exactly.
  SensorSeries p;
  for (int q = 0; q < 10; ++q) {
    const double t = 0.1 * q;
    p.time.push_back(t);
    p.signal.push_back(100.0 - 400.0 * (t - 0.437) * (t - 0.437));
  }
  ArrivalSettings refine;
  refine.absolute_threshold = 0.0;
  refine.refine_parabolic = true;
  CHECK(*arrival_time(p, refine) == Approx(0.437).epsilon(1e-13));
}

TEST_CASE("speed of a synthetic travelling pulse with injected outliers",
          "[analysis][wave_front]") {
  const double c = 120.0;  // [m/s]
  const double dt = 1e-5;
  auto sensors = travelling_pulse(c, 31, 0.01, dt, 5e-3, {7, 19}, 0.6e-3);
  // Refined arrivals: errors far below dt; the spikes of sensors 7 and 19, 0.6 ms early (7 cm of
  // front travel), come first and are rejected by the 2σ rule.
  ArrivalSettings refine;
  refine.refine_parabolic = true;
  const FrontSpeed fr = front_speed(sensors, refine);
  CHECK(fr.arrivals == 31);
  CHECK(fr.kept_points == 29);
  CHECK_FALSE(fr.kept[7]);
  CHECK_FALSE(fr.kept[19]);
  CHECK(std::abs(fr.speed - c) <= 2.0 * fr.speed_uncertainty);
  CHECK(fr.speed_uncertainty < 1e-5 * c);
  // The outliers bias the first fit by metres per second; the refit removes that.
  CHECK(std::abs(fr.first_fit.slope - c) > 1.0);
  // Sample-time arrivals (as paper 001): quantisation error ≤ dt/2, still within the regression
  // uncertainty.
  const FrontSpeed raw = front_speed(sensors);
  CHECK(raw.kept_points == 29);
  CHECK(std::abs(raw.speed - c) <= 2.0 * raw.speed_uncertainty);
  CHECK(raw.speed_uncertainty < 2e-3 * c);
  // Collinear arrivals: nothing rejected, zero uncertainty.
  const FrontSpeed exact = front_speed_from_arrivals({0.0, 1.0, 2.0, 3.0}, {0.0, 0.5, 1.0, 1.5});
  CHECK(exact.kept_points == 4);
  CHECK(exact.speed == Approx(2.0).epsilon(1e-14));
  CHECK(exact.speed_uncertainty < 1e-13);
}
