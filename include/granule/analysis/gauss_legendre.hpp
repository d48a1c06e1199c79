#pragma once
// Gauss–Legendre quadrature nodes and weights on [-1, 1], used by the analysis toolkit for the
// coarse-graining line integrals and the sphere ∩ box volumes.
//
//   ∫_{-1}^{1} f(t) dt ≈ Σ_q w_q f(t_q),  exact for polynomials of degree ≤ 2n − 1.
//
// The nodes are the roots of the Legendre polynomial P_n, found by Newton iteration from the
// Tricomi initial guess t ≈ cos(π (q − 1/4)/(n + 1/2)); the weights are
// w_q = 2 / ((1 − t_q²) P_n'(t_q)²) (Abramowitz & Stegun 1964, 25.4.29).
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <vector>

#include "granule/core/error.hpp"

namespace granule::detail {

/// Nodes and weights of an n-point Gauss–Legendre rule on [-1, 1].
struct GaussLegendreRule {
  std::vector<double> node;    ///< abscissae in (-1, 1), ascending
  std::vector<double> weight;  ///< weights, summing to 2

  /// Builds the n-point rule (1 ≤ n ≤ 256).
  explicit GaussLegendreRule(int n) {
    require(n >= 1 && n <= 256, "GaussLegendreRule", "n", n, "[1, 256]");
    node.resize(static_cast<std::size_t>(n));
    weight.resize(static_cast<std::size_t>(n));
    const int half = (n + 1) / 2;
    for (int q = 0; q < half; ++q) {
      double t = std::cos(std::numbers::pi * (q + 0.75) / (n + 0.5));
      double dp = 0.0;
      for (int iter = 0; iter < 100; ++iter) {
        // Three-term recurrence for P_n(t) and its derivative.
        double p0 = 1.0;
        double p1 = t;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (t * p1 - p0) / (t * t - 1.0);  // P_n' from P_n = p1, P_{n-1} = p0
        const double step = p1 / dp;
        t -= step;
        if (std::abs(step) < 1e-16) break;
      }
      const double w = 2.0 / ((1.0 - t * t) * dp * dp);
      node[static_cast<std::size_t>(q)] = -t;
      node[static_cast<std::size_t>(n - 1 - q)] = t;
      weight[static_cast<std::size_t>(q)] = w;
      weight[static_cast<std::size_t>(n - 1 - q)] = w;
    }
    if (n % 2 == 1) node[static_cast<std::size_t>(n / 2)] = 0.0;
  }

  std::size_t size() const { return node.size(); }
};

}  // namespace granule::detail
