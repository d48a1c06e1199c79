#pragma once
// Spatial decomposition of the simulation box among ranks, without MPI: the choice of the rank
// grid, balanced cut positions, the owner of a point and the halo test. The distributed policy
// (docs/mpi.md) calls these on every rank with the same input and gets the same answer, so no
// message is needed to agree on who owns what.
//
//   auto grid = parallel::choose_grid(box, ranks, halo_width);    // px x py (x pz)
//   auto dec  = parallel::Decomposition<Dim3>::balanced(box, grid, x, weights, halo_width);
//   int r     = dec.owner(x[i]);
//   for (auto& t : dec.halo_targets(x[i], halo_width)) ...         // ghost copies: rank, shift
//
// Grid: among all px*py*pz = ranks, the one with the least total area of internal cuts. On a
// periodic axis split into p > 1 parts the wrap is a cut as well (p cuts, not p - 1); an axis
// with one part keeps its periodic images on the rank. Every part must be at least
// `min_width` (the halo width, cut-off + skin) wide: then a rank never needs its own periodic
// image from across another rank, and a ghost comes from an adjacent region only.
// Ties (equal area to 1e-12) go to the grid with more parts on the lower axis.
//
// Cuts: recursive coordinate multisection, staggered. The x cuts split all particles into px
// slabs of equal weight; within each slab the y cuts split its particles into py parts; within
// each (x, y) column the z cuts split into pz. Cut j of p along an axis goes into the gap
// between two distinct coordinates whose weight below is nearest to j/p of the node's weight
// (ties: the lower gap), midway between the two coordinates, gaps strictly increasing with j;
// then cuts are moved apart to keep every part min_width wide. A point on a cut belongs to
// the upper part. Rank numbering: rank = (ix * py + iy) * pz + iz.
//
// Errors are InvalidParameter (core/error.hpp) naming "Decomposition", the parameter, the value
// and the valid range: zero ranks, more ranks than the box can be cut into, a non-positive box
// length, a weight that is NaN, negative or infinite, a position that is not finite.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"
#include "granule/neighbours/domain.hpp"

namespace granule::parallel {

/// Parts per axis; axes beyond the dimension have one part.
struct RankGrid {
  std::array<int, 3> parts{1, 1, 1};
  int ranks() const { return parts[0] * parts[1] * parts[2]; }
  bool operator==(const RankGrid&) const = default;
};

namespace detail {

inline const char* axis_name(int k) { return k == 0 ? "x" : (k == 1 ? "y" : "z"); }

template <class D>
void check_box(const Domain<D>& box) {
  for (int k = 0; k < D::dim; ++k) {
    require_finite(box.lo[k], "Decomposition", std::string("box lo[") + axis_name(k) + "]");
    const double len = box.hi[k] - box.lo[k];
    require(len > 0.0 && std::isfinite(len), "Decomposition",
            std::string("box length along ") + axis_name(k), len, "(0, inf)");
  }
}

/// Number of cut planes across axis k with p parts.
inline int cut_count(int p, bool periodic) { return (p > 1 && periodic) ? p : p - 1; }

}  // namespace detail

/// Total area (3D; length in 2D) of the faces between ranks for this grid.
template <class D>
double cut_area(const Domain<D>& box, const RankGrid& grid) {
  const typename D::Vec L = box.length();
  double area = 0.0;
  for (int k = 0; k < D::dim; ++k) {
    double face = 1.0;
    for (int j = 0; j < D::dim; ++j)
      if (j != k) face *= L[j];
    area += detail::cut_count(grid.parts[k], box.periodic[k]) * face;
  }
  return area;
}

/// The rank grid with the least cut area among those whose parts are all at least min_width
/// wide (uniform cuts). Throws InvalidParameter if ranks < 1 or no grid fits.
template <class D>
RankGrid choose_grid(const Domain<D>& box, int ranks, double min_width = 0.0) {
  require(ranks >= 1, "Decomposition", "ranks", ranks, "[1, inf)");
  require_non_negative(min_width, "Decomposition", "min_width");
  detail::check_box(box);
  const typename D::Vec L = box.length();
  auto fits = [&](int k, int p) { return p == 1 || L[k] >= p * min_width; };  // no cut, no width
  RankGrid best;
  double best_area = 0.0;
  bool found = false;
  // Enumerated with more parts on the lower axes first, so that ties go to them.
  for (int p0 = ranks; p0 >= 1; --p0) {
    if (ranks % p0 != 0 || !fits(0, p0)) continue;
    const int rest = ranks / p0;
    for (int p1 = rest; p1 >= 1; --p1) {
      if (rest % p1 != 0) continue;
      const int p2 = rest / p1;
      if (D::dim == 2 && p2 != 1) continue;
      if (!fits(1, p1) || (D::dim == 3 && !fits(2, p2))) continue;
      RankGrid g{{p0, p1, p2}};
      const double a = cut_area(box, g);
      if (!found || a < best_area * (1.0 - 1e-12)) {
        best = g;
        best_area = a;
        found = true;
      }
    }
  }
  if (!found) {
    std::string most;
    for (int k = 0; k < D::dim; ++k) {
      const double m = std::max(1.0, std::floor(L[k] / min_width));
      most += (k ? ", " : "") + std::string(detail::axis_name(k)) + " " + granule::detail::to_text(m);
    }
    throw InvalidParameter("Decomposition: ranks = " + std::to_string(ranks) +
                           " cannot be arranged as a grid of parts at least " +
                           granule::detail::to_text(min_width) + " m wide (at most " + most +
                           " parts along the axes)");
  }
  return best;
}

/// One ghost copy of a point: the rank that needs it and the periodic image (in box lengths)
/// in which it appears there: position x + shift * L.
template <class D>
struct HaloTarget {
  int rank = 0;
  Eigen::Matrix<int, D::dim, 1> shift = Eigen::Matrix<int, D::dim, 1>::Zero();
};

/// Weights per rank and their imbalance.
struct Load {
  std::vector<double> per_rank;
  double total() const { return std::accumulate(per_rank.begin(), per_rank.end(), 0.0); }
  /// max / mean over the ranks; 1 when there is no weight at all.
  double imbalance() const {
    const double t = total();
    if (per_rank.empty() || !(t > 0.0)) return 1.0;
    const double mx = *std::max_element(per_rank.begin(), per_rank.end());
    return mx / (t / static_cast<double>(per_rank.size()));
  }
  /// A rebalance is due when the imbalance exceeds threshold (>= 1).
  bool needs_rebalance(double threshold) const {
    require(threshold >= 1.0 && std::isfinite(threshold), "Decomposition", "rebalance threshold",
            threshold, "[1, inf)");
    return imbalance() > threshold;
  }
};

template <class D>
class Decomposition {
 public:
  using Vec = typename D::Vec;
  using Shift = Eigen::Matrix<int, D::dim, 1>;
  static constexpr int dim = D::dim;

  /// Uniform cuts: every part of an axis the same width.
  Decomposition(const Domain<D>& box, const RankGrid& grid, double min_width = 0.0)
      : box_(box), grid_(grid), min_width_(min_width) {
    check_grid();
    for (int k = 0; k < dim; ++k) {
      const int p = grid_.parts[k];
      bounds_[k].assign(nodes(k) * std::size_t(p + 1), 0.0);
      for (std::size_t n = 0; n < nodes(k); ++n)
        for (int j = 0; j <= p; ++j)
          bounds_[k][n * (p + 1) + j] = j == p ? box_.hi[k] : box_.lo[k] + length(k) * j / p;
    }
  }

  /// Cuts balanced on per-particle weights (empty `weights`: every particle weighs 1).
  template <class Points>
  static Decomposition balanced(const Domain<D>& box, const RankGrid& grid, const Points& x,
                                const std::vector<double>& weights = {}, double min_width = 0.0) {
    Decomposition d(box, grid, min_width);
    const std::size_t n = x.size();
    if (!weights.empty())
      require(weights.size() == n, "Decomposition", "number of weights",
              static_cast<double>(weights.size()), "= number of positions (" + std::to_string(n) + ")");
    std::vector<Vec> c(n);
    std::vector<double> w(n, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
      for (int k = 0; k < dim; ++k)
        require_finite(x[i][k], "Decomposition", "position[" + std::to_string(i) + "]." + detail::axis_name(k));
      if (!weights.empty()) {
        require(weights[i] >= 0.0 && std::isfinite(weights[i]), "Decomposition",
                "weight[" + std::to_string(i) + "]", weights[i], "[0, inf)");
        w[i] = weights[i];
      }
      c[i] = d.wrapped(x[i]);
    }
    std::vector<std::size_t> items(n);
    std::iota(items.begin(), items.end(), std::size_t{0});
    d.split(0, 0, items, c, w);
    return d;
  }

  const RankGrid& grid() const { return grid_; }
  int ranks() const { return grid_.ranks(); }
  const Domain<D>& box() const { return box_; }
  double min_width() const { return min_width_; }

  /// Part index of each axis of a rank.
  std::array<int, 3> coordinates(int rank) const {
    const int iz = rank % grid_.parts[2];
    const int iy = (rank / grid_.parts[2]) % grid_.parts[1];
    const int ix = rank / (grid_.parts[2] * grid_.parts[1]);
    return {ix, iy, iz};
  }

  /// The boundaries [lo, hi] of a rank's region, per axis.
  void region(int rank, Vec& lo, Vec& hi) const {
    require(rank >= 0 && rank < ranks(), "Decomposition", "rank", rank,
            "[0, " + std::to_string(ranks() - 1) + "]");
    const auto ic = coordinates(rank);
    std::size_t node = 0;
    for (int k = 0; k < dim; ++k) {
      const int p = grid_.parts[k];
      lo[k] = bounds_[k][node * (p + 1) + ic[k]];
      hi[k] = bounds_[k][node * (p + 1) + ic[k] + 1];
      node = node * p + ic[k];
    }
  }

  /// The cut positions along axis k within node `node` of that level (the x slab for y cuts,
  /// the column ix * py + iy for z cuts), lo and hi included.
  std::vector<double> cuts(int k, std::size_t node = 0) const {
    const int p = grid_.parts[k];
    auto b = bounds_[k].begin() + static_cast<std::ptrdiff_t>(node * (p + 1));
    return std::vector<double>(b, b + p + 1);
  }

  /// The rank whose region holds x (periodic axes wrapped; a point beyond a non-periodic face
  /// goes to the part on that face).
  int owner(const Vec& x) const {
    const Vec c = wrapped(x);
    std::size_t node = 0;
    for (int k = 0; k < dim; ++k) node = node * grid_.parts[k] + part_of(k, node, c[k]);
    return static_cast<int>(node);
  }

  /// Every (rank, shift) whose region lies closer than w (Euclidean) to the image x + shift*L,
  /// except the owner with shift 0: the ghost copies of a particle at x for a halo of width w.
  /// Shifts are -1, 0, 1 on periodic axes and 0 on the others; the owner appears with a
  /// non-zero shift only along a periodic axis that it spans alone.
  std::vector<HaloTarget<D>> halo_targets(const Vec& x, double w) const {
    check_width(w);
    const Vec c = wrapped(x);
    const int me = owner(c);
    const Vec L = box_.length();
    std::vector<HaloTarget<D>> out;
    const int images = dim == 2 ? 9 : 27;
    Vec lo, hi;
    for (int r = 0; r < ranks(); ++r) {
      region(r, lo, hi);
      for (int code = 0; code < images; ++code) {
        Shift s;
        int rest = code;
        bool ok = true;
        for (int k = 0; k < dim; ++k) {
          s[k] = rest % 3 - 1;
          rest /= 3;
          if (s[k] != 0 && !box_.periodic[k]) ok = false;
        }
        if (!ok || (r == me && s.isZero())) continue;
        double d2 = 0.0;
        for (int k = 0; k < dim; ++k) {
          const double y = c[k] + s[k] * L[k];
          const double out_by = std::max({lo[k] - y, 0.0, y - hi[k]});
          d2 += out_by * out_by;
        }
        if (d2 < w * w) out.push_back(HaloTarget<D>{r, s});
      }
    }
    return out;
  }

  /// The other ranks (sorted, each once) that need a ghost of a particle at x.
  std::vector<int> ghost_ranks(const Vec& x, double w) const {
    const int me = owner(x);
    std::vector<int> r;
    for (const auto& t : halo_targets(x, w))
      if (t.rank != me) r.push_back(t.rank);
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    return r;
  }

  /// The weight each rank owns (empty `weights`: counts).
  template <class Points>
  Load load(const Points& x, const std::vector<double>& weights = {}) const {
    Load l;
    l.per_rank.assign(static_cast<std::size_t>(ranks()), 0.0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double w = weights.empty() ? 1.0 : weights[i];
      require(w >= 0.0 && std::isfinite(w), "Decomposition", "weight[" + std::to_string(i) + "]", w, "[0, inf)");
      l.per_rank[static_cast<std::size_t>(owner(x[i]))] += w;
    }
    return l;
  }

  /// x with periodic coordinates wrapped into [lo, hi).
  Vec wrapped(const Vec& x) const {
    Vec c = x;
    for (int k = 0; k < dim; ++k) {
      if (!box_.periodic[k]) continue;
      const double L = length(k);
      c[k] -= L * std::floor((c[k] - box_.lo[k]) / L);
      if (c[k] >= box_.hi[k]) c[k] = box_.lo[k];
    }
    return c;
  }

 private:
  double length(int k) const { return box_.hi[k] - box_.lo[k]; }

  /// Nodes at the level of axis k: the product of the parts of the axes before it.
  std::size_t nodes(int k) const {
    std::size_t n = 1;
    for (int j = 0; j < k; ++j) n *= static_cast<std::size_t>(grid_.parts[j]);
    return n;
  }

  int part_of(int k, std::size_t node, double c) const {
    const int p = grid_.parts[k];
    auto first = bounds_[k].begin() + static_cast<std::ptrdiff_t>(node * (p + 1) + 1);
    return static_cast<int>(std::upper_bound(first, first + (p - 1), c) - first);
  }

  void check_grid() const {
    detail::check_box(box_);
    require_non_negative(min_width_, "Decomposition", "min_width");
    for (int k = 0; k < 3; ++k) {
      const int p = grid_.parts[k];
      require(p >= 1 && (k < dim || p == 1), "Decomposition",
              std::string("parts along ") + detail::axis_name(k), p, k < dim ? "[1, inf)" : "{1}");
      if (k < dim && p > 1 && length(k) < p * min_width_)
        throw InvalidParameter("Decomposition: " + std::to_string(p) + " parts along " +
                               detail::axis_name(k) + " cannot each be min_width = " +
                               granule::detail::to_text(min_width_) + " m wide in a box " +
                               granule::detail::to_text(length(k)) + " m long");
    }
  }

  void check_width(double w) const {
    require_non_negative(w, "Decomposition", "halo width");
    for (int k = 0; k < dim; ++k)
      if (box_.periodic[k])
        require(w < length(k), "Decomposition", "halo width", w,
                std::string("[0, box length along ") + detail::axis_name(k) + " = " +
                    granule::detail::to_text(length(k)) + ")");
  }

  /// Cuts of axis k for one node and its items, then the next axis in each part.
  void split(int k, std::size_t node, std::vector<std::size_t>& items, const std::vector<Vec>& c,
             const std::vector<double>& w) {
    const int p = grid_.parts[k];
    if (p > 1) {
      std::sort(items.begin(), items.end(), [&](std::size_t a, std::size_t b) {
        return c[a][k] < c[b][k] || (c[a][k] == c[b][k] && a < b);
      });
      std::vector<double> cut = multisection(k, items, c, w, p);
      for (int j = 1; j < p; ++j) bounds_[k][node * (p + 1) + j] = cut[static_cast<std::size_t>(j)];
    }
    if (k + 1 == dim) return;
    std::vector<std::vector<std::size_t>> child(static_cast<std::size_t>(p));
    for (std::size_t i : items) child[static_cast<std::size_t>(part_of(k, node, c[i][k]))].push_back(i);
    for (int j = 0; j < p; ++j) split(k + 1, node * p + j, child[static_cast<std::size_t>(j)], c, w);
  }

  /// p + 1 boundaries along axis k for items sorted by that coordinate.
  std::vector<double> multisection(int k, const std::vector<std::size_t>& items,
                                   const std::vector<Vec>& c, const std::vector<double>& w,
                                   int p) const {
    const double a = box_.lo[k], b = box_.hi[k];
    std::vector<double> cut(static_cast<std::size_t>(p + 1));
    for (int j = 0; j <= p; ++j) cut[static_cast<std::size_t>(j)] = j == p ? b : a + (b - a) * j / p;
    // Gaps between distinct coordinates: the weight below each and the position midway.
    std::vector<double> below, at;
    double sum = 0.0;
    for (std::size_t i = 0; i < items.size(); ++i) {
      sum += w[items[i]];
      if (i + 1 < items.size() && c[items[i + 1]][k] > c[items[i]][k]) {
        below.push_back(sum);
        at.push_back(0.5 * (c[items[i]][k] + c[items[i + 1]][k]));
      }
    }
    const double total = sum;
    const std::size_t gaps = below.size();
    if (total > 0.0 && gaps >= static_cast<std::size_t>(p - 1)) {
      std::size_t next = 0;  // first gap cut j may use: gaps strictly increase with j
      for (int j = 1; j < p; ++j) {
        const double target = total * j / p;
        const std::size_t last = gaps - static_cast<std::size_t>(p - 1 - j);  // leave gaps for later cuts
        std::size_t best = next;
        for (std::size_t g = next; g < last; ++g)
          if (std::abs(below[g] - target) < std::abs(below[best] - target)) best = g;
        cut[static_cast<std::size_t>(j)] = at[best];
        next = best + 1;
      }
    }
    // Keep every part at least min_width wide (possible: checked when the grid was made).
    const double m = min_width_;
    for (int j = 1; j < p; ++j)
      cut[static_cast<std::size_t>(j)] = std::max(cut[static_cast<std::size_t>(j)], cut[static_cast<std::size_t>(j - 1)] + m);
    for (int j = p - 1; j >= 1; --j)
      cut[static_cast<std::size_t>(j)] = std::min(cut[static_cast<std::size_t>(j)], cut[static_cast<std::size_t>(j + 1)] - m);
    return cut;
  }

  Domain<D> box_;
  RankGrid grid_;
  double min_width_ = 0.0;
  /// Per axis k: for each node of its level, the p_k + 1 boundaries (lo, cuts, hi).
  std::array<std::vector<double>, 3> bounds_;
};

}  // namespace granule::parallel
