#pragma once
// Binned averages of a per-particle quantity along one axis, within an axis-aligned region —
// e.g. the V_y and V_z profiles across y below the two intruders of paper 000 (fig. 5–6: average
// velocity of the particles in a slab x/d ∈ [−10, 10], 5d below the intruders, binned along y).
//
// For bin k, with the particles whose centres lie in the region and in the bin,
//   mean_k = Σ w_i q_i / Σ w_i,   stddev_k = √(Σ w_i (q_i − mean_k)² / Σ w_i)
// with w_i = 1 (number average, as 000) or w_i = m_i (mass average). Empty bins have
// count 0 and NaN mean and stddev.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "granule/analysis/frame.hpp"
#include "granule/analysis/frame_checks.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

/// Weights of a binned profile.
enum class ProfileWeight {
  Number,  ///< every particle counts once
  Mass     ///< particles weighted by their mass
};

/// A binned profile along one axis.
struct Profile {
  std::vector<double> edges;       ///< bin edges along the axis [m]
  std::vector<double> centre;      ///< bin centres [m]
  std::vector<double> mean;        ///< weighted mean of the quantity (NaN if empty)
  std::vector<double> stddev;      ///< weighted population standard deviation (NaN if empty)
  std::vector<std::size_t> count;  ///< particles in each bin
  std::size_t bins() const { return count.size(); }
};

/// Profile of quantity(i) (any callable std::size_t → double) along `axis`, over the particles
/// whose centre lies in the box [region_lo, region_hi]; `bins` equal bins span the region along
/// the axis (half-open, the last one closed).
template <class D, class Quantity>
Profile binned_profile(const Frame<D>& frame, const typename D::Vec& region_lo,  // [m]
                       const typename D::Vec& region_hi,                        // [m]
                       int axis, std::size_t bins, Quantity&& quantity,
                       ProfileWeight weight = ProfileWeight::Number) {
  granule::detail::check_frame(frame, "binned_profile");
  require(axis >= 0 && axis < D::dim, "binned_profile", "axis", axis, "[0, dim)");
  require(bins >= 1, "binned_profile", "bins", static_cast<double>(bins), "[1, inf)");
  for (int a = 0; a < D::dim; ++a) {
    require(region_hi[a] > region_lo[a], "binned_profile",
            "region_hi[" + std::to_string(a) + "] - region_lo", region_hi[a] - region_lo[a],
            "(0, inf)");
  }
  const double lo = region_lo[axis];
  const double width = (region_hi[axis] - lo) / static_cast<double>(bins);
  Profile p;
  p.edges.resize(bins + 1);
  for (std::size_t k = 0; k <= bins; ++k) p.edges[k] = lo + width * static_cast<double>(k);
  p.edges[bins] = region_hi[axis];
  p.centre.resize(bins);
  for (std::size_t k = 0; k < bins; ++k) p.centre[k] = 0.5 * (p.edges[k] + p.edges[k + 1]);
  p.count.assign(bins, 0);
  std::vector<double> sw(bins, 0.0);
  std::vector<double> swq(bins, 0.0);
  std::vector<std::size_t> bin_of(frame.size(), bins);
  std::vector<double> value(frame.size(), 0.0);
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const auto& x = frame.x[i];
    if ((x.array() < region_lo.array()).any() || (x.array() > region_hi.array()).any()) continue;
    const auto k = std::min(static_cast<std::size_t>((x[axis] - lo) / width), bins - 1);
    const double w = weight == ProfileWeight::Mass ? frame.mass[i] : 1.0;
    const double q = static_cast<double>(quantity(i));
    bin_of[i] = k;
    value[i] = q;
    ++p.count[k];
    sw[k] += w;
    swq[k] += w * q;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  p.mean.assign(bins, nan);
  p.stddev.assign(bins, nan);
  for (std::size_t k = 0; k < bins; ++k)
    if (p.count[k] > 0) p.mean[k] = swq[k] / sw[k];
  std::vector<double> sdev(bins, 0.0);
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const std::size_t k = bin_of[i];
    if (k == bins) continue;
    const double w = weight == ProfileWeight::Mass ? frame.mass[i] : 1.0;
    sdev[k] += w * (value[i] - p.mean[k]) * (value[i] - p.mean[k]);
  }
  for (std::size_t k = 0; k < bins; ++k)
    if (p.count[k] > 0) p.stddev[k] = std::sqrt(sdev[k] / sw[k]);
  return p;
}

/// Profile of one velocity component (component c of frame.v) [m/s].
template <class D>
Profile velocity_profile(const Frame<D>& frame, const typename D::Vec& region_lo,  // [m]
                         const typename D::Vec& region_hi,                        // [m]
                         int axis, std::size_t bins, int component,
                         ProfileWeight weight = ProfileWeight::Number) {
  require(component >= 0 && component < D::dim, "velocity_profile", "component", component,
          "[0, dim)");
  return binned_profile(
      frame, region_lo, region_hi, axis, bins,
      [&](std::size_t i) { return frame.v[i][component]; }, weight);
}

}  // namespace granule::analysis
