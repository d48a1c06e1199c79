// Tests of granule/analysis/spectrum.hpp. References: the DFT of a sine with a whole number k0
// of periods is A N / 2 at bin k0 and zero elsewhere; Parseval's theorem Σ|X_k|² = N Σ x_n².
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "granule/analysis/spectrum.hpp"

using namespace granule::analysis;

namespace {
std::vector<double> sine(std::size_t n, double dt, double f0, double amplitude, double offset) {
  std::vector<double> x(n);
  for (std::size_t k = 0; k < n; ++k)
    x[k] = offset + amplitude * std::sin(2.0 * std::numbers::pi * f0 * k * dt + 0.3);
  return x;
}
}  // namespace

TEST_CASE("psd of a bin-centred sine: single peak holding the variance", "[analysis][spectrum]") {
  const std::size_t n = 1000;
  const double dt = 1e-3;  // f_s = 1 kHz, Δf = 1 Hz
  const double amplitude = 3.0;
  const auto x = sine(n, dt, 50.0, amplitude, 7.0);
  const PowerSpectrum s = power_spectrum(x, dt);
  REQUIRE(s.psd.size() == n / 2 + 1);
  CHECK(s.df == Approx(1.0).epsilon(1e-15));
  CHECK(s.frequency[50] == Approx(50.0).epsilon(1e-15));
  // P_50 Δf = A²/2, the variance of the sine; every other bin (the mean included) is round-off.
  CHECK(s.psd[50] * s.df == Approx(amplitude * amplitude / 2).epsilon(1e-12));
  double rest = 0.0;
  for (std::size_t k = 0; k < s.psd.size(); ++k)
    if (k != 50) rest += s.psd[k];
  CHECK(rest * s.df < 1e-20);
  CHECK(peak_frequency(s) == 50.0);
  CHECK(s.integral() == Approx(s.variance).epsilon(1e-12));
  // Hann window: the peak spreads over bins 49–51, the integral still equals the variance for a
  // whole number (≥ 2) of periods.
  const PowerSpectrum h = power_spectrum(x, dt, SpectralWindow::Hann);
  CHECK(h.integral() == Approx(amplitude * amplitude / 2).epsilon(1e-12));
  CHECK(peak_frequency(h) == 50.0);
}

TEST_CASE("psd satisfies Parseval for noise, even and odd lengths", "[analysis][spectrum]") {
  std::mt19937_64 gen(11);
  std::normal_distribution<double> g(2.0, 0.5);
  for (std::size_t n : {1024u, 999u}) {
    std::vector<double> x(n);
    for (double& v : x) v = g(gen);
    double mean = 0.0;
    for (double v : x) mean += v;
    mean /= n;
    double var = 0.0;
    for (double v : x) var += (v - mean) * (v - mean);
    var /= n;
    const PowerSpectrum s = power_spectrum(x, 0.01);
    CHECK(s.variance == Approx(var).epsilon(1e-13));
    CHECK(s.integral() == Approx(var).epsilon(1e-12));
    CHECK(s.psd[0] < 1e-20);  // mean removed
    CHECK(s.frequency.back() <= 50.0);
  }
  CHECK_THROWS_AS(power_spectrum({1.0, 2.0, 3.0}, 0.0), granule::InvalidParameter);
  CHECK_THROWS_AS(power_spectrum({1.0}, 0.1), granule::InvalidParameter);
}

TEST_CASE("peak frequency of an off-bin sine with interpolation", "[analysis][spectrum]") {
  const double dt = 1e-3;
  const double f0 = 50.3;
  const auto x = sine(1000, dt, f0, 1.0, 0.0);
  const PowerSpectrum h = power_spectrum(x, dt, SpectralWindow::Hann);
  CHECK(peak_frequency(h) == 50.0);  // nearest bin
  const double refined = peak_frequency(h, true);
  CHECK(std::abs(refined - f0) < 0.03 * h.df);
  CHECK(std::abs(refined - f0) < std::abs(50.0 - f0));
}
