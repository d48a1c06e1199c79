#pragma once
// Random sequential insertion of non-overlapping particles into a box-shaped region, and the
// schedule of a particle stream.
//
// insert_random(): for each of `count` new particles a radius is drawn from the size
// distribution, then up to `max_attempts` centres are drawn uniformly in [lo + r, hi - r]
// (the particle stays inside the region); a centre is accepted when the optional `accept`
// test passes and the particle overlaps no existing particle and no particle placed before
// it: |x - x_j| >= r + r_j + min_gap. Overlap tests use a uniform cell grid of edge
// >= r_max + r_j,max + min_gap over the region grown by that edge, so only the 3^dim
// neighbouring cells are searched. A particle that finds no place after max_attempts is
// skipped (counted in `failed`); larger particles fail more often in a crowded region.
//
// StreamSchedule: how many particles a stream of `rate` particles/s should have inserted by
// time t, out of `total`. Continuous: floor(rate (t - t0)). Batched (LIGGGHTS fix
// insert/stream as described in paper 001, section 2.4: "one tenth of the requested
// particles every 0.1 s", i.e. rate * interval particles per batch): floor((k + 1) rate
// interval) with k = floor((t - t0)/interval) the batch index, the first batch at t0.
// Both are capped at `total`.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/core/error.hpp"
#include "granule/scene/random.hpp"

namespace granule::scene {

template <class D>
struct InsertionOptions {
  std::size_t max_attempts = 1000;  ///< trial positions per particle
  double min_gap = 0.0;             ///< minimum surface gap between particles [m]
  /// Optional extra test of a trial (centre [m], radius [m]), e.g. "inside the silo".
  std::function<bool(const typename D::Vec&, double)> accept;
};

template <class D>
struct InsertionResult {
  std::vector<typename D::Vec> positions;  ///< centres of the placed particles [m]
  std::vector<double> radii;               ///< their radii [m]
  std::size_t failed = 0;                  ///< particles given up after max_attempts
  std::size_t attempts = 0;                ///< trial positions drawn in total
  std::size_t count() const { return positions.size(); }
};

namespace detail {

/// Linked-cell grid for overlap queries (dense over a box, head/next lists).
template <class D>
class InsertionGrid {
 public:
  using Vec = typename D::Vec;

  InsertionGrid(const geometry::Aabb<D>& box, double cell) : lo_(box.lo) {
    const double max_cells = 1 << 22;
    double h = cell;
    while (true) {
      double total = 1.0;
      for (int a = 0; a < D::dim; ++a) total *= std::max(1.0, std::ceil(box.extent()[a] / h));
      if (total <= max_cells) break;
      h *= 1.5;
    }
    h_ = h;
    std::size_t total = 1;
    for (int a = 0; a < D::dim; ++a) {
      n_[a] = std::max<long>(1, static_cast<long>(std::ceil(box.extent()[a] / h_)));
      total *= static_cast<std::size_t>(n_[a]);
    }
    head_.assign(total, -1);
  }

  void add(const Vec& x, double r) {
    const std::size_t c = cell_of(x);
    xs_.push_back(x);
    rs_.push_back(r);
    next_.push_back(head_[c]);
    head_[c] = static_cast<std::int64_t>(xs_.size() - 1);
  }

  /// True when a particle (x, r) keeps a gap >= `gap` to every stored particle.
  bool free(const Vec& x, double r, double gap) const {
    std::array<long, 3> c{0, 0, 0};
    for (int a = 0; a < D::dim; ++a) c[a] = index(x, a);
    std::array<long, 3> lo{0, 0, 0}, hi{0, 0, 0};
    for (int a = 0; a < D::dim; ++a) {
      lo[a] = std::max(0L, c[a] - 1);
      hi[a] = std::min(n_[a] - 1, c[a] + 1);
    }
    for (long k = lo[2]; k <= hi[2]; ++k) {
      for (long j = lo[1]; j <= hi[1]; ++j) {
        for (long i = lo[0]; i <= hi[0]; ++i) {
          const std::size_t cell = static_cast<std::size_t>((k * n_[1] + j) * n_[0] + i);
          for (std::int64_t p = head_[cell]; p >= 0; p = next_[static_cast<std::size_t>(p)]) {
            const double reach = r + rs_[static_cast<std::size_t>(p)] + gap;
            if ((xs_[static_cast<std::size_t>(p)] - x).squaredNorm() < reach * reach) return false;
          }
        }
      }
    }
    return true;
  }

 private:
  long index(const Vec& x, int a) const {
    const long i = static_cast<long>(std::floor((x[a] - lo_[a]) / h_));
    return std::clamp(i, 0L, n_[a] - 1);
  }
  std::size_t cell_of(const Vec& x) const {
    std::array<long, 3> c{0, 0, 0};
    for (int a = 0; a < D::dim; ++a) c[a] = index(x, a);
    return static_cast<std::size_t>((c[2] * n_[1] + c[1]) * n_[0] + c[0]);
  }

  Vec lo_;
  double h_ = 1.0;
  std::array<long, 3> n_{1, 1, 1};
  std::vector<std::int64_t> head_;
  std::vector<std::int64_t> next_;
  std::vector<Vec> xs_;
  std::vector<double> rs_;
};

}  // namespace detail

/// Places up to `count` non-overlapping particles in `region`; see the file comment.
/// `sizes` provides sample(RandomGenerator&), r_min() and r_max() (size_distribution.hpp).
/// Existing particles (centres [m], radii [m]) may lie anywhere; only those that can reach the
/// region matter.
template <class D, class Sizes>
InsertionResult<D> insert_random(const geometry::Aabb<D>& region, const Sizes& sizes, RandomGenerator& rng,
                                 std::size_t count, std::span<const typename D::Vec> existing_x = {},
                                 std::span<const double> existing_r = {}, const InsertionOptions<D>& options = {}) {
  using Vec = typename D::Vec;
  const char* where = "scene::insert_random";
  require(region.is_finite() && !region.is_empty(), where, "region extent (min)", region.extent().minCoeff(),
          "a finite, non-empty box");
  require(existing_r.size() == existing_x.size(), where, "number of existing radii",
          static_cast<double>(existing_r.size()), std::to_string(existing_x.size()) + " (one per existing centre)");
  require_non_negative(options.min_gap, where, "min_gap");
  require(options.max_attempts >= 1, where, "max_attempts", static_cast<double>(options.max_attempts), "[1, inf)");
  const double r_max = sizes.r_max();
  require(2.0 * sizes.r_min() <= region.extent().minCoeff(), where, "smallest region extent",
          region.extent().minCoeff(), "[2 r_min, inf) = [" + granule::detail::to_text(2.0 * sizes.r_min()) + ", inf) m");

  // Existing particles that can touch a new one.
  std::vector<std::size_t> relevant;
  double r_old_max = 0.0;
  for (std::size_t i = 0; i < existing_x.size(); ++i) {
    const double reach = existing_r[i] + r_max + options.min_gap;
    if (region.squared_distance(existing_x[i]) < reach * reach) {
      relevant.push_back(i);
      r_old_max = std::max(r_old_max, existing_r[i]);
    }
  }
  const double cell = r_max + std::max(r_max, r_old_max) + options.min_gap;
  detail::InsertionGrid<D> grid(region.expanded(cell), cell);
  for (std::size_t i : relevant) grid.add(existing_x[i], existing_r[i]);

  InsertionResult<D> out;
  out.positions.reserve(count);
  out.radii.reserve(count);
  for (std::size_t n = 0; n < count; ++n) {
    const double r = sizes.sample(rng);
    bool placed = false;
    if ((region.extent().array() >= 2.0 * r).all()) {
      for (std::size_t attempt = 0; attempt < options.max_attempts && !placed; ++attempt) {
        ++out.attempts;
        Vec x;
        for (int a = 0; a < D::dim; ++a) x[a] = rng.uniform(region.lo[a] + r, region.hi[a] - r);
        if (options.accept && !options.accept(x, r)) continue;
        if (!grid.free(x, r, options.min_gap)) continue;
        grid.add(x, r);
        out.positions.push_back(x);
        out.radii.push_back(r);
        placed = true;
      }
    }
    if (!placed) ++out.failed;
  }
  return out;
}

/// Continuous stream or LIGGGHTS-style batches.
enum class StreamMode { Continuous, Batched };

/// Number of particles a stream should have inserted by a given time; see the file comment.
class StreamSchedule {
 public:
  /// `rate` [1/s] > 0, `total` particles, start `start_time` [s]; Batched: one batch of
  /// rate * interval particles every `interval` [s] (0.1 s in LIGGGHTS ins/stream per 001).
  StreamSchedule(double rate, std::size_t total, double start_time = 0.0, StreamMode mode = StreamMode::Continuous,
                 double interval = 0.1)
      : rate_(rate), total_(total), t0_(start_time), mode_(mode), interval_(interval) {
    require_positive(rate, "scene::StreamSchedule", "rate");
    require_finite(start_time, "scene::StreamSchedule", "start_time");
    if (mode == StreamMode::Batched) require_positive(interval, "scene::StreamSchedule", "interval");
  }

  /// Cumulative number of particles due by time t [s].
  std::size_t target(double t) const {
    if (t < t0_) return 0;
    const double eps = 1e-9;
    double n = 0.0;
    if (mode_ == StreamMode::Continuous) {
      n = std::floor(rate_ * (t - t0_) + eps);
    } else {
      const double k = std::floor((t - t0_) / interval_ + eps);
      n = std::floor((k + 1.0) * rate_ * interval_ + eps);
    }
    return n >= static_cast<double>(total_) ? total_ : static_cast<std::size_t>(n);
  }

  /// Particles to insert now, given how many were inserted already.
  std::size_t due(double t, std::size_t inserted) const {
    const std::size_t want = target(t);
    return want > inserted ? want - inserted : 0;
  }

  /// First time at which target() reaches total [s].
  double end_time() const {
    if (total_ == 0) return t0_;
    if (mode_ == StreamMode::Continuous) return t0_ + static_cast<double>(total_) / rate_;
    const double batches = std::ceil(static_cast<double>(total_) / (rate_ * interval_) - 1e-9);
    return t0_ + (std::max(batches, 1.0) - 1.0) * interval_;
  }

  bool finished(std::size_t inserted) const { return inserted >= total_; }
  double rate() const { return rate_; }
  std::size_t total() const { return total_; }

 private:
  double rate_;       // [1/s]
  std::size_t total_;
  double t0_;         // [s]
  StreamMode mode_;
  double interval_;   // [s]
};

}  // namespace granule::scene
