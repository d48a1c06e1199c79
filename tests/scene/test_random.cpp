// RandomGenerator: published reference outputs of splitmix64 (seed 1234567: Vigna's
// splitmix64.c, also Rosetta Code "Pseudo-random numbers/Splitmix64") and xoshiro256**
// (state {1, 2, 3, 4}: reference outputs of Vigna's xoshiro256starstar.c), uniform and
// normal moments within a few standard errors, state save/restore mid Box-Muller pair.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "granule/scene/random.hpp"

using namespace granule;
using scene::RandomGenerator;

TEST_CASE("splitmix64 reference outputs", "[scene][random]") {
  std::uint64_t s = 1234567;
  CHECK(scene::splitmix64(s) == 6457827717110365317ull);
  CHECK(scene::splitmix64(s) == 3203168211198807973ull);
  CHECK(scene::splitmix64(s) == 9817491932198370423ull);
  CHECK(scene::splitmix64(s) == 4593380528125082431ull);
  CHECK(scene::splitmix64(s) == 16408922859458223821ull);
}

TEST_CASE("xoshiro256** reference outputs", "[scene][random]") {
  RandomGenerator g;
  g.set_state({1, 2, 3, 4, 0, 0});
  const std::uint64_t ref[] = {11520ull,
                               0ull,
                               1509978240ull,
                               1215971899390074240ull,
                               1216172134540287360ull,
                               607988272756665600ull,
                               16172922978634559625ull,
                               8476171486693032832ull,
                               10595114339597558777ull,
                               2904607092377533576ull};
  for (std::uint64_t r : ref) CHECK(g() == r);
}

TEST_CASE("RandomGenerator seeding is splitmix64 and reproducible", "[scene][random]") {
  RandomGenerator a(1234567);
  const auto st = a.state();
  CHECK(st[0] == 6457827717110365317ull);
  CHECK(st[3] == 4593380528125082431ull);
  RandomGenerator b(1234567);
  for (int k = 0; k < 1000; ++k) CHECK(a() == b());
  RandomGenerator c(1234568);
  CHECK(RandomGenerator(1234567)() != c());
  // uniform() is the top 53 bits scaled by 2^-53.
  RandomGenerator d(99), e(99);
  CHECK(d.uniform() == static_cast<double>(e() >> 11) * 0x1.0p-53);
}

TEST_CASE("RandomGenerator uniform and normal moments", "[scene][random]") {
  RandomGenerator g(2024);
  const int n = 200000;
  double s = 0.0, s2 = 0.0, lo = 1.0, hi = 0.0;
  for (int k = 0; k < n; ++k) {
    const double u = g.uniform();
    s += u;
    s2 += u * u;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  CHECK(lo >= 0.0);
  CHECK(hi < 1.0);
  // Mean 1/2 (SE sqrt(1/12/n)), variance 1/12.
  CHECK(std::abs(s / n - 0.5) < 4.0 * std::sqrt(1.0 / 12.0 / n));
  CHECK(std::abs(s2 / n - (s / n) * (s / n) - 1.0 / 12.0) < 0.002);
  double m = 0.0, v = 0.0, m4 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double z = g.normal();
    m += z;
    v += z * z;
    m4 += z * z * z * z;
  }
  m /= n;
  v = v / n - m * m;
  CHECK(std::abs(m) < 4.0 / std::sqrt(double(n)));
  CHECK(std::abs(v - 1.0) < 4.0 * std::sqrt(2.0 / n));
  CHECK(std::abs(m4 / n - 3.0) < 4.0 * std::sqrt(96.0 / n));  // Var(z^4) = 105 - 9
  // below(n): every value appears with frequency 1/7 (SE sqrt(p(1-p)/n)).
  std::vector<int> count(7, 0);
  for (int k = 0; k < 70000; ++k) ++count[g.below(7)];
  for (int c : count) CHECK(std::abs(c / 70000.0 - 1.0 / 7.0) < 4.0 * std::sqrt(1.0 / 7.0 * 6.0 / 7.0 / 70000.0));
}

TEST_CASE("RandomGenerator state save and restore", "[scene][random]") {
  RandomGenerator g(7);
  for (int k = 0; k < 10; ++k) g();
  (void)g.normal();  // leaves the second Box-Muller value pending
  const scene::RandomState saved = g.state();
  CHECK(saved[4] == 1u);
  std::vector<double> first;
  for (int k = 0; k < 5; ++k) first.push_back(g.normal());
  first.push_back(g.uniform());
  RandomGenerator h(12345);
  h.set_state(saved);
  for (int k = 0; k < 5; ++k) CHECK(h.normal() == first[k]);
  CHECK(h.uniform() == first[5]);
  CHECK_THROWS_AS(h.set_state({0, 0, 0, 0, 0, 0}), InvalidParameter);
  CHECK_THROWS_AS(h.set_state({1, 0, 0, 0, 2, 0}), InvalidParameter);
}
