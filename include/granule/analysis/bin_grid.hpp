#pragma once
// A regular grid of rectangular bins (cells) covering the box [lo, hi]: count_a equal bins on
// axis a, bin k spans [lo + k ⊙ width, lo + (k + 1) ⊙ width]. Flat index k_0 + n_0 (k_1 + n_1 k_2)
// (x fastest). Used for packing fractions, bed-height columns and binned averages.
// Example: the y-z sensor grid of paper 001 section 2.8 is a BinGrid with one bin across the
// channel width (x) and 0.5 cm bins in y and z.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>

#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

template <class D>
class BinGrid {
 public:
  using Vec = typename D::Vec;
  using IVec = typename D::IVec;

  BinGrid() = default;
  /// count[a] ≥ 1 equal bins on each axis between lo and hi (hi > lo).
  BinGrid(const Vec& lo,       // [m]
          const Vec& hi,       // [m]
          const IVec& count)
      : lo_(lo), hi_(hi), n_(count) {
    for (int a = 0; a < D::dim; ++a) {
      // Appended rather than "[" + to_string(a): GCC 12 warns (-Wrestrict, a false positive) on
      // operator+(const char*, string&&) once this is inlined.
      std::string ax = std::to_string(a);
      ax.insert(ax.begin(), '[');
      ax.push_back(']');
      require_finite(lo[a], "BinGrid", "lo" + ax);
      require(std::isfinite(hi[a]) && hi[a] > lo[a], "BinGrid", "hi" + ax, hi[a], "(lo, inf)");
      require(count[a] >= 1 && count[a] <= 100000000, "BinGrid", "count" + ax, count[a],
              "[1, 1e8]");
    }
    width_ = (hi_ - lo_).cwiseQuotient(n_.template cast<double>());
  }

  const Vec& lo() const { return lo_; }        ///< [m]
  const Vec& hi() const { return hi_; }        ///< [m]
  const IVec& count() const { return n_; }     ///< bins per axis
  const Vec& width() const { return width_; }  ///< bin size per axis [m]
  /// Number of bins.
  std::size_t size() const {
    std::size_t s = 1;
    for (int a = 0; a < D::dim; ++a) s *= static_cast<std::size_t>(n_[a]);
    return s;
  }
  /// Measure of one bin, Π width_a [m^D].
  double bin_measure() const { return width_.prod(); }
  std::size_t index(const IVec& k) const {
    std::size_t idx = 0;
    for (int a = D::dim - 1; a >= 0; --a) idx = idx * static_cast<std::size_t>(n_[a]) + k[a];
    return idx;
  }
  IVec coords(std::size_t idx) const {
    IVec k;
    for (int a = 0; a < D::dim; ++a) {
      k[a] = static_cast<int>(idx % static_cast<std::size_t>(n_[a]));
      idx /= static_cast<std::size_t>(n_[a]);
    }
    return k;
  }
  Vec bin_lo(const IVec& k) const { return lo_ + k.template cast<double>().cwiseProduct(width_); }
  Vec bin_hi(const IVec& k) const { return bin_lo(k) + width_; }
  Vec centre(const IVec& k) const { return bin_lo(k) + 0.5 * width_; }
  /// The bin holding x (bins are half-open [lo, hi) except the last one, closed at hi), if any.
  std::optional<IVec> locate(const Vec& x) const {
    IVec k;
    for (int a = 0; a < D::dim; ++a) {
      if (!(x[a] >= lo_[a] && x[a] <= hi_[a])) return std::nullopt;
      k[a] = std::min(static_cast<int>(std::floor((x[a] - lo_[a]) / width_[a])), n_[a] - 1);
    }
    return k;
  }

 private:
  Vec lo_ = Vec::Zero();
  Vec hi_ = Vec::Ones();
  IVec n_ = IVec::Ones();
  Vec width_ = Vec::Ones();
};

}  // namespace granule::analysis
