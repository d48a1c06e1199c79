#pragma once
// Packing fraction in bins and bed height per column.
//
// Packing fraction of bin B (paper 001 section 2.8.1, done exactly):
//   φ_B = Σ_i |P_i ∩ B| / |B|,
// P_i the sphere (3D) or disk (2D) of particle i, |·| the exact volume / area of
// intersection_volume.hpp; on periodic axes every periodic image of a particle that reaches the
// bin grid is counted. Particle overlaps are counted twice, as in 001 (negligible at DEM
// overlaps). In 2D the thickness cancels: φ is the area fraction.
//
// Bed height per column (paper 001 section 2.8.2): the columns are the bins of a BinGrid with a
// single bin along the vertical axis; the height of a column is the mean vertical coordinate of
// the centres of its N_h highest particles (centre inside the column). By default
//   N_h = max(1, round(column cross-section / particle cross-section)),
// 3D: (w_a w_b) / (π r̄²); 2D: w_a / (2 r̄), r̄ the mean radius of the column's particles — the
// number of particles that fit side by side on the column's top (001 writes the denominator as
// 2πR; we use the particle's cross-section as its text describes).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <limits>
#include <utility>
#include <vector>

#include "granule/analysis/bin_grid.hpp"
#include "granule/analysis/frame.hpp"
#include "granule/analysis/frame_checks.hpp"
#include "granule/analysis/intersection_volume.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

/// Exact packing fraction of every bin (flat bin index) [-].
template <class D>
std::vector<double> packing_fraction(const Frame<D>& frame, const BinGrid<D>& bins) {
  using Vec = typename D::Vec;
  using IVec = typename D::IVec;
  granule::detail::check_frame(frame, "packing_fraction");
  const std::size_t nbins = bins.size();
  std::vector<double> measure(nbins, 0.0);
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(frame.size());
#pragma omp parallel
  {
    std::vector<double> local(nbins, 0.0);
#pragma omp for schedule(dynamic, 64)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const double r = frame.radius[static_cast<std::size_t>(i)];
      // Periodic images: shifts of −L, 0, +L on periodic axes.
      int shifts[3] = {0, 0, 0};
      for (int a = 0; a < D::dim; ++a) shifts[a] = frame.periodic[a] ? 1 : 0;
      const int nz = D::dim == 3 ? 2 * shifts[2] + 1 : 1;
      for (int sz = 0; sz < nz; ++sz) {
        for (int sy = 0; sy < 2 * shifts[1] + 1; ++sy) {
          for (int sx = 0; sx < 2 * shifts[0] + 1; ++sx) {
            const int s[3] = {sx - shifts[0], sy - shifts[1], sz - (D::dim == 3 ? shifts[2] : 0)};
            Vec x = frame.x[static_cast<std::size_t>(i)];
            for (int a = 0; a < D::dim; ++a)
              x[a] += s[a] * (frame.box_hi[a] - frame.box_lo[a]);
            IVec k0;
            IVec k1;
            bool hit = true;
            for (int a = 0; a < D::dim; ++a) {
              const double f0 = std::floor((x[a] - r - bins.lo()[a]) / bins.width()[a]);
              const double f1 = std::floor((x[a] + r - bins.lo()[a]) / bins.width()[a]);
              k0[a] = static_cast<int>(std::max(f0, 0.0));
              k1[a] = static_cast<int>(std::min(f1, bins.count()[a] - 1.0));
              if (k1[a] < k0[a] || f1 < 0.0 || f0 > bins.count()[a] - 1.0) hit = false;
            }
            if (!hit) continue;
            IVec k = k0;
            for (;;) {
              local[bins.index(k)] += ball_box_measure<D>(x, r, bins.bin_lo(k), bins.bin_hi(k));
              int a = 0;
              while (a < D::dim && ++k[a] > k1[a]) {
                k[a] = k0[a];
                ++a;
              }
              if (a == D::dim) break;
            }
          }
        }
      }
    }
#pragma omp critical(granule_packing_fraction)
    for (std::size_t b = 0; b < nbins; ++b) measure[b] += local[b];
  }
  for (double& m : measure) m /= bins.bin_measure();
  return measure;
}

/// Bed height of one column.
struct ColumnHeight {
  double height = std::numeric_limits<double>::quiet_NaN();  ///< mean centre height of the top N_h [m]
  std::size_t used = 0;       ///< particles averaged (N_h, or fewer if the column has fewer)
  std::size_t particles = 0;  ///< particles whose centre lies in the column
};

/// Height of every column of `columns` (which must have one bin along `up_axis`): mean vertical
/// centre coordinate of the top `n_top` particles of the column (0: automatic N_h, see above).
template <class D>
std::vector<ColumnHeight> bed_height(const Frame<D>& frame, const BinGrid<D>& columns,
                                     int up_axis = D::dim - 1, std::size_t n_top = 0) {
  using Vec = typename D::Vec;
  granule::detail::check_frame(frame, "bed_height");
  require(up_axis >= 0 && up_axis < D::dim, "bed_height", "up_axis", up_axis, "[0, dim)");
  require(columns.count()[up_axis] == 1, "bed_height", "columns.count()[up_axis]",
          columns.count()[up_axis], "{1}: columns have a single bin vertically");
  std::vector<std::vector<std::pair<double, double>>> members(columns.size());  // (height, r)
  for (std::size_t i = 0; i < frame.size(); ++i) {
    Vec x = frame.x[i];
    for (int a = 0; a < D::dim; ++a) {
      if (!frame.periodic[a]) continue;
      const double length = frame.box_hi[a] - frame.box_lo[a];
      x[a] -= length * std::floor((x[a] - frame.box_lo[a]) / length);
    }
    const auto k = columns.locate(x);
    if (k) members[columns.index(*k)].emplace_back(x[up_axis], frame.radius[i]);
  }
  std::vector<ColumnHeight> out(columns.size());
  for (std::size_t c = 0; c < columns.size(); ++c) {
    auto& m = members[c];
    out[c].particles = m.size();
    if (m.empty()) continue;
    std::size_t nh = n_top;
    if (nh == 0) {
      double rbar = 0.0;
      for (const auto& p : m) rbar += p.second;
      rbar /= static_cast<double>(m.size());
      double section = 1.0;
      for (int a = 0; a < D::dim; ++a)
        if (a != up_axis) section *= columns.width()[a];
      const double particle_section =
          D::dim == 3 ? std::numbers::pi * rbar * rbar : 2.0 * rbar;
      nh = static_cast<std::size_t>(std::max(1.0, std::round(section / particle_section)));
    }
    nh = std::min(nh, m.size());
    std::partial_sort(m.begin(), m.begin() + static_cast<std::ptrdiff_t>(nh), m.end(),
                      [](const auto& p, const auto& q) { return p.first > q.first; });
    double s = 0.0;
    for (std::size_t k = 0; k < nh; ++k) s += m[k].first;
    out[c].height = s / static_cast<double>(nh);
    out[c].used = nh;
  }
  return out;
}

}  // namespace granule::analysis
