#pragma once
// A regular grid of nodes on which coarse-grained fields are sampled:
//   node(k) = lo + k ⊙ spacing,  k_a = 0 … n_a − 1  (⊙: component-wise product).
// Node k has the flat index k_0 + n_0 (k_1 + n_1 k_2) (x fastest). An axis flagged periodic
// tiles its period exactly: n_a · spacing_a is the period and node n_a coincides with node 0.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "granule/analysis/frame.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

template <class D>
class RegularGrid {
 public:
  using Vec = typename D::Vec;
  using IVec = typename D::IVec;
  using BVec = Eigen::Matrix<bool, D::dim, 1>;

  RegularGrid() = default;

  /// Nodes from lo towards hi with the same spacing on every axis; the last node on axis a is the
  /// largest lo_a + k h not beyond hi_a (a 1e-9 relative slack absorbs round-off). No axis is
  /// periodic.
  RegularGrid(const Vec& lo,      // [m]
              const Vec& hi,      // [m]
              double spacing)     // [m]
      : RegularGrid(lo, hi, Vec::Constant(spacing)) {}

  /// As above with one spacing per axis.
  RegularGrid(const Vec& lo,        // [m]
              const Vec& hi,        // [m]
              const Vec& spacing)   // [m]
      : lo_(lo), spacing_(spacing), periodic_(BVec::Constant(false)) {
    for (int a = 0; a < D::dim; ++a) {
      require_finite(lo[a], "RegularGrid", "lo[" + std::to_string(a) + "]");
      require_positive(spacing[a], "RegularGrid", "spacing[" + std::to_string(a) + "]");
      require(hi[a] >= lo[a] && std::isfinite(hi[a]), "RegularGrid",
              "hi[" + std::to_string(a) + "]", hi[a], "[lo, inf)");
      const double steps = (hi[a] - lo[a]) / spacing[a];
      require(steps < 1e8, "RegularGrid", "(hi - lo) / spacing on axis " + std::to_string(a),
              steps, "[0, 1e8)");
      n_[a] = static_cast<int>(std::floor(steps * (1.0 + 1e-9) + 1e-9)) + 1;
    }
  }

  /// A grid suited to a frame: on periodic axes it tiles the box exactly (lo = box_lo,
  /// n = round(L / spacing) nodes, spacing adjusted to L / n); on other axes it spans the
  /// particle centres extended by `margin` on both sides with the requested spacing.
  static RegularGrid covering(const Frame<D>& frame,
                              double spacing,   // [m]
                              double margin) {  // [m]
    require_positive(spacing, "RegularGrid::covering", "spacing");
    require_non_negative(margin, "RegularGrid::covering", "margin");
    require(frame.size() > 0, "RegularGrid::covering", "frame.size()", 0.0, "[1, inf)");
    Vec lo = Vec::Constant(std::numeric_limits<double>::infinity());
    Vec hi = -lo;
    for (const Vec& x : frame.x) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    lo.array() -= margin;
    hi.array() += margin;
    Vec h = Vec::Constant(spacing);
    BVec per = BVec::Constant(false);
    for (int a = 0; a < D::dim; ++a) {
      if (!frame.periodic[a]) continue;
      const double length = frame.box_hi[a] - frame.box_lo[a];
      require_positive(length, "RegularGrid::covering", "periodic box length on axis " +
                                                            std::to_string(a));
      const double nodes = std::max(1.0, std::round(length / spacing));
      lo[a] = frame.box_lo[a];
      h[a] = length / nodes;
      hi[a] = frame.box_lo[a] + (nodes - 1.0) * h[a];
      per[a] = true;
    }
    RegularGrid g(lo, hi, h);
    for (int a = 0; a < D::dim; ++a) {
      if (per[a]) {
        g.n_[a] = static_cast<int>(std::round((frame.box_hi[a] - frame.box_lo[a]) / h[a]));
        g.periodic_[a] = true;
      }
    }
    return g;
  }

  /// Marks axis a as periodic with period n_a · spacing_a (the caller guarantees that the grid
  /// tiles the period: node n_a would coincide with node 0).
  void set_periodic(int axis, bool on) {
    require(axis >= 0 && axis < D::dim, "RegularGrid::set_periodic", "axis", axis,
            "[0, dim)");
    periodic_[axis] = on;
  }

  const Vec& lo() const { return lo_; }                ///< first node [m]
  const Vec& spacing() const { return spacing_; }      ///< node spacing per axis [m]
  const IVec& count() const { return n_; }             ///< nodes per axis
  const BVec& periodic() const { return periodic_; }   ///< periodic axes
  /// Last node [m].
  Vec hi() const { return lo_ + (n_.template cast<double>() - Vec::Ones()).cwiseProduct(spacing_); }
  /// Period of axis a (n_a · spacing_a) [m].
  double period(int a) const { return n_[a] * spacing_[a]; }
  /// Number of nodes.
  std::size_t size() const {
    std::size_t s = 1;
    for (int a = 0; a < D::dim; ++a) s *= static_cast<std::size_t>(n_[a]);
    return s;
  }
  /// Volume (area in 2D) represented by one node, Π spacing_a [m^D].
  double cell_volume() const { return spacing_.prod(); }

  /// Flat index of node k.
  std::size_t index(const IVec& k) const {
    std::size_t idx = 0;
    for (int a = D::dim - 1; a >= 0; --a) idx = idx * static_cast<std::size_t>(n_[a]) + k[a];
    return idx;
  }
  /// Integer coordinates of the node with flat index idx.
  IVec coords(std::size_t idx) const {
    IVec k;
    for (int a = 0; a < D::dim; ++a) {
      k[a] = static_cast<int>(idx % static_cast<std::size_t>(n_[a]));
      idx /= static_cast<std::size_t>(n_[a]);
    }
    return k;
  }
  /// Position of node k [m].
  Vec node(const IVec& k) const { return lo_ + k.template cast<double>().cwiseProduct(spacing_); }
  /// Position of the node with flat index idx [m].
  Vec node(std::size_t idx) const { return node(coords(idx)); }

 private:
  Vec lo_ = Vec::Zero();
  Vec spacing_ = Vec::Ones();
  IVec n_ = IVec::Ones();
  BVec periodic_ = BVec::Constant(false);
};

/// Σ_nodes value · cell_volume: the integral of a field sampled on the grid (the trapezoidal
/// rule when the field vanishes on the grid boundary or the axis is periodic).
template <class D>
double integrate(const RegularGrid<D>& grid, const std::vector<double>& values) {
  require(values.size() == grid.size(), "integrate", "values.size()",
          static_cast<double>(values.size()), "grid.size()");
  double s = 0.0;
  for (double v : values) s += v;
  return s * grid.cell_volume();
}

}  // namespace granule::analysis
