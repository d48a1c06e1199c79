// Size distributions: sample mean and standard deviation within a few standard errors of
// the exact values (uniform; truncated normal and log-normal moments from Johnson, Kotz &
// Balakrishnan 1994, as implemented in mean()/stddev(), checked here also against direct
// numerical integration), bounds always respected, discrete fractions, parameter checks.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "granule/scene/size_distribution.hpp"

using namespace granule;
using namespace granule::scene;

namespace {

struct Stats {
  double mean = 0.0, sd = 0.0, lo = 1e300, hi = -1e300;
};

template <class S>
Stats sample_stats(const S& s, int n, std::uint64_t seed) {
  RandomGenerator g(seed);
  Stats st;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double r = s.sample(g);
    sum += r;
    sum2 += r * r;
    st.lo = std::min(st.lo, r);
    st.hi = std::max(st.hi, r);
  }
  st.mean = sum / n;
  st.sd = std::sqrt(std::max(0.0, sum2 / n - st.mean * st.mean));
  return st;
}

template <class S>
void check_statistics(const S& s, int n = 40000) {
  const Stats st = sample_stats(s, n, 31);
  INFO("sample mean " << st.mean << " vs " << s.mean() << ", sd " << st.sd << " vs " << s.stddev());
  CHECK(st.lo >= s.r_min());
  CHECK(st.hi <= s.r_max());
  CHECK(std::abs(st.mean - s.mean()) < 4.0 * s.stddev() / std::sqrt(double(n)));
  CHECK(std::abs(st.sd - s.stddev()) < 0.03 * s.stddev());
}

// Midpoint-rule moments of a density f on [a, b].
template <class F>
std::pair<double, double> integrate_moments(F f, double a, double b) {
  const int n = 200000;
  double z = 0.0, m1 = 0.0, m2 = 0.0;
  const double h = (b - a) / n;
  for (int k = 0; k < n; ++k) {
    const double r = a + (k + 0.5) * h;
    const double w = f(r) * h;
    z += w;
    m1 += w * r;
    m2 += w * r * r;
  }
  const double mean = m1 / z;
  return {mean, std::sqrt(m2 / z - mean * mean)};
}

}  // namespace

TEST_CASE("MonodisperseSizes and UniformSizes", "[scene][size_distribution]") {
  RandomGenerator g(1);
  const MonodisperseSizes mono(1e-3);
  CHECK(mono.sample(g) == 1e-3);
  CHECK(mono.stddev() == 0.0);
  const UniformSizes u(1e-3, 2e-3);
  CHECK(u.mean() == Approx(1.5e-3));
  CHECK(u.stddev() == Approx(1e-3 / std::sqrt(12.0)));
  check_statistics(u);
  CHECK_THROWS_AS(UniformSizes(2e-3, 1e-3), InvalidParameter);
  CHECK_THROWS_AS(UniformSizes(0.0, 1e-3), InvalidParameter);
  CHECK_THROWS_AS(MonodisperseSizes(-1.0), InvalidParameter);
}

TEST_CASE("NormalSizes truncated moments", "[scene][size_distribution]") {
  const NormalSizes s(1.0e-3, 0.2e-3, 0.8e-3, 1.5e-3);  // asymmetric window
  const auto [m, sd] = integrate_moments(
      [](double r) { return std::exp(-0.5 * std::pow((r - 1.0e-3) / 0.2e-3, 2)); }, 0.8e-3, 1.5e-3);
  CHECK(s.mean() == Approx(m).epsilon(1e-8));
  CHECK(s.stddev() == Approx(sd).epsilon(1e-6));
  check_statistics(s);
  CHECK_THROWS_AS(NormalSizes(1e-3, 0.0, 0.5e-3, 2e-3), InvalidParameter);
  CHECK_THROWS_AS(NormalSizes(1e-3, 1e-4, 2e-3, 1e-3), InvalidParameter);
  // A window 20 sigma away from the mean holds no probability.
  CHECK_THROWS_WITH(NormalSizes(1e-3, 1e-5, 1.2e-3, 1.3e-3), Catch::Contains("probability"));
}

TEST_CASE("LogNormalSizes truncated moments", "[scene][size_distribution]") {
  const LogNormalSizes s(std::log(1e-3), 0.25, 0.7e-3, 1.6e-3);
  const auto [m, sd] = integrate_moments(
      [](double r) { return std::exp(-0.5 * std::pow((std::log(r) - std::log(1e-3)) / 0.25, 2)) / r; }, 0.7e-3,
      1.6e-3);
  CHECK(s.mean() == Approx(m).epsilon(1e-8));
  CHECK(s.stddev() == Approx(sd).epsilon(1e-6));
  check_statistics(s);
  // Wide window: the untruncated mean and sd given to from_mean_sd come back.
  const LogNormalSizes w = LogNormalSizes::from_mean_sd(2e-3, 0.3e-3, 1e-5, 1e-1);
  CHECK(w.mean() == Approx(2e-3).epsilon(1e-9));
  CHECK(w.stddev() == Approx(0.3e-3).epsilon(1e-9));
  check_statistics(w);
  CHECK_THROWS_AS(LogNormalSizes(0.0, -1.0, 1e-3, 2e-3), InvalidParameter);
}

TEST_CASE("DiscreteSizes number fractions", "[scene][size_distribution]") {
  const DiscreteSizes s({1e-3, 2e-3, 3e-3}, {2.0, 1.0, 1.0});  // normalised to 1/2, 1/4, 1/4
  CHECK(s.fractions()[0] == 0.5);
  CHECK(s.mean() == Approx(0.5e-3 + 0.5e-3 + 0.75e-3));
  RandomGenerator g(5);
  const int n = 40000;
  std::vector<int> count(3, 0);
  for (int k = 0; k < n; ++k) {
    const double r = s.sample(g);
    ++count[static_cast<int>(std::lround(r * 1e3)) - 1];
  }
  for (int k = 0; k < 3; ++k) {
    const double p = s.fractions()[k];
    CHECK(std::abs(count[k] / double(n) - p) < 4.0 * std::sqrt(p * (1 - p) / n));
  }
  check_statistics(s);
  // Equal volume fractions in 3D: number fractions ~ 1/r^3.
  const DiscreteSizes v = DiscreteSizes::from_volume_fractions({1e-3, 2e-3}, {0.5, 0.5}, 3);
  CHECK(v.fractions()[0] == Approx(8.0 / 9.0));
  // A zero fraction leaves its radius out of [r_min, r_max].
  const DiscreteSizes z({1e-3, 5e-3}, {1.0, 0.0});
  CHECK(z.r_max() == 1e-3);
  CHECK_THROWS_AS(DiscreteSizes({1e-3}, {1.0, 2.0}), InvalidParameter);
  CHECK_THROWS_AS(DiscreteSizes({1e-3, 2e-3}, {0.0, 0.0}), InvalidParameter);
  CHECK_THROWS_AS(DiscreteSizes({-1e-3}, {1.0}), InvalidParameter);
}

TEST_CASE("SizeDistribution wraps any distribution", "[scene][size_distribution]") {
  const SizeDistribution a = UniformSizes(1e-3, 3e-3);
  CHECK(a.mean() == Approx(2e-3));
  CHECK(a.r_max() == 3e-3);
  RandomGenerator g1(3), g2(3);
  const UniformSizes direct(1e-3, 3e-3);
  for (int k = 0; k < 10; ++k) CHECK(a.sample(g1) == direct.sample(g2));
  check_statistics(a);
}
