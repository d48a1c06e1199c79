// Tests of granule/analysis/gauss_legendre.hpp. Reference: an n-point Gauss–Legendre rule
// integrates x^p over [-1, 1] exactly, 2/(p + 1) for even p and 0 for odd p, for p ≤ 2n − 1
// (Abramowitz & Stegun 1964, 25.4.29); for p = 2n the remainder is
// 2^{2n+1} (n!)^4 / ((2n + 1) ((2n)!)²) (A&S 25.4.30 with f^{(2n)} = (2n)!).
#include <catch2/catch.hpp>

#include <cmath>

#include "granule/analysis/gauss_legendre.hpp"

TEST_CASE("gauss-legendre rules are exact up to degree 2n-1", "[analysis][gauss_legendre]") {
  for (int n : {1, 2, 3, 5, 7, 12, 24, 64}) {
    const granule::detail::GaussLegendreRule rule(n);
    REQUIRE(rule.size() == static_cast<std::size_t>(n));
    for (int p = 0; p <= 2 * n; ++p) {
      double s = 0.0;
      for (std::size_t q = 0; q < rule.size(); ++q) s += rule.weight[q] * std::pow(rule.node[q], p);
      const double exact = (p % 2 == 1) ? 0.0 : 2.0 / (p + 1);
      INFO("n = " << n << ", p = " << p);
      if (p < 2 * n) {
        CHECK(std::abs(s - exact) < 1e-14);
      } else {
        const double remainder = std::exp((2 * n + 1) * std::log(2.0) + 4 * std::lgamma(n + 1.0) -
                                          std::log(2.0 * n + 1) - 2 * std::lgamma(2 * n + 1.0));
        CHECK(std::abs((exact - s) - remainder) < 1e-14);
        if (n <= 5) CHECK(remainder > 1e-3);
      }
    }
    for (std::size_t q = 1; q < rule.size(); ++q) CHECK(rule.node[q] > rule.node[q - 1]);
  }
  CHECK_THROWS_AS(granule::detail::GaussLegendreRule(0), granule::InvalidParameter);
}
