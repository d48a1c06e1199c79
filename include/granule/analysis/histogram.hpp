#pragma once
// Histogram normalised as a probability density: with N samples in total and n_k of them in
// bin [e_k, e_{k+1}),
//   p_k = n_k / (N (e_{k+1} − e_k)),
// so Σ p_k Δe_k is the fraction of samples inside the bins — 1 when the edges cover every sample.
// The last bin is closed on the right. Samples outside the edges are counted in `below` /
// `above` (non-finite ones in `non_finite`), never dropped silently.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "granule/core/error.hpp"

namespace granule::analysis {

/// Probability-density histogram.
struct Histogram {
  std::vector<double> edges;         ///< bin edges, strictly increasing (bins + 1 values)
  std::vector<std::size_t> counts;   ///< samples per bin
  std::vector<double> density;       ///< n_k / (N Δe_k)
  std::size_t samples = 0;           ///< N, all samples offered (inside or outside the edges)
  std::size_t below = 0;             ///< samples < edges.front()
  std::size_t above = 0;             ///< samples > edges.back()
  std::size_t non_finite = 0;        ///< NaN or infinite samples (in no bin)

  std::size_t bins() const { return counts.size(); }
  /// Centre of bin k.
  double centre(std::size_t k) const { return 0.5 * (edges[k] + edges[k + 1]); }
  /// Σ p_k Δe_k: the fraction of the samples inside the edges.
  double integral() const {
    double s = 0.0;
    for (std::size_t k = 0; k < bins(); ++k) s += density[k] * (edges[k + 1] - edges[k]);
    return s;
  }
};

/// `bins` equal bins spanning [lo, hi].
inline std::vector<double> uniform_edges(double lo, double hi, std::size_t bins) {
  require(bins >= 1, "uniform_edges", "bins", static_cast<double>(bins), "[1, inf)");
  require(std::isfinite(lo) && std::isfinite(hi) && hi > lo, "uniform_edges", "hi - lo", hi - lo,
          "(0, inf)");
  std::vector<double> e(bins + 1);
  for (std::size_t k = 0; k <= bins; ++k)
    e[k] = lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(bins);
  return e;
}

/// Histogram of `values` on `edges` (strictly increasing, at least two).
inline Histogram make_histogram(const std::vector<double>& values, const std::vector<double>& edges) {
  require(edges.size() >= 2, "make_histogram", "edges.size()", static_cast<double>(edges.size()),
          "[2, inf)");
  for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
    require(edges[k + 1] > edges[k], "make_histogram", "edges[" + std::to_string(k + 1) + "]",
            edges[k + 1], "(edges[k], inf): strictly increasing");
  }
  Histogram h;
  h.edges = edges;
  h.counts.assign(edges.size() - 1, 0);
  h.density.assign(edges.size() - 1, 0.0);
  h.samples = values.size();
  for (double v : values) {
    if (!std::isfinite(v)) {
      ++h.non_finite;
    } else if (v < edges.front()) {
      ++h.below;
    } else if (v > edges.back()) {
      ++h.above;
    } else {
      auto it = std::upper_bound(edges.begin(), edges.end(), v);
      std::size_t k = static_cast<std::size_t>(it - edges.begin()) - 1;
      if (k >= h.counts.size()) k = h.counts.size() - 1;  // v == edges.back()
      ++h.counts[k];
    }
  }
  if (h.samples > 0) {
    for (std::size_t k = 0; k < h.counts.size(); ++k) {
      h.density[k] = static_cast<double>(h.counts[k]) /
                     (static_cast<double>(h.samples) * (edges[k + 1] - edges[k]));
    }
  }
  return h;
}

}  // namespace granule::analysis
