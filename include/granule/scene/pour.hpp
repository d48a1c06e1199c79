#pragma once
// Pouring: particles enter a region of a running simulation at a given rate (particles per
// second), like LIGGGHTS' insert/stream used by paper 001 section 2.4 (table 3: the insertion
// rate sets the packing fraction: fast = loose, slow = compact). Each update() places the
// particles that the StreamSchedule says are due, at random non-overlapping positions in the
// region (scene::insert_random), with a given initial velocity.
// The generator state travels with checkpoints: rng_state()/set_rng_state() and inserted().
// Distributed (parallel::MpiDomains): construct and update it on every rank; the particles near
// the region are gathered from every rank, so all place the same ones (docs/mpi.md).
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/scene/insertion.hpp"
#include "granule/scene/random.hpp"
#include "granule/scene/size_distribution.hpp"

namespace granule::scene {

template <class Sim>
class Pour {
 public:
  using D = typename Sim::Dimension;
  using Vec = typename D::Vec;

  Pour(Sim& sim, const geometry::Aabb<D>& region, SizeDistribution sizes, StreamSchedule schedule,
       std::uint32_t material, const Vec& velocity = Vec::Zero(), std::uint32_t group = 0,
       std::uint64_t seed = 1, InsertionOptions<D> options = {})
      : sim_(sim), region_(region), sizes_(std::move(sizes)), schedule_(schedule),
        material_(material), velocity_(velocity), group_(group), rng_(seed), options_(std::move(options)) {}

  /// Inserts the particles due at the simulation's current time; returns how many it placed.
  /// Particles that found no room are retried at the next update (the region may have cleared).
  std::size_t update() {
    const std::size_t due = schedule_.due(sim_.time(), inserted_);
    if (due == 0) return 0;
    const auto& p = sim_.particles();
    std::span<const Vec> xs(p.x.data(), p.owned());
    std::span<const double> rs(p.radius.data(), p.owned());
    std::vector<Vec> gathered_x;
    std::vector<double> gathered_r;
    if constexpr (Sim::ParallelPolicy::distributed) {
      // Each rank holds its own particles only (after the first step): the obstacles near the
      // region are gathered from every rank in id order, so every rank draws the same
      // positions and makes the same add_particle calls (docs/mpi.md).
      if (sim_.parallel_engine().decomposition) {
        gather_obstacles(gathered_x, gathered_r);
        xs = std::span<const Vec>(gathered_x);
        rs = std::span<const double>(gathered_r);
      }
    }
    const InsertionResult<D> res = insert_random<D>(region_, sizes_, rng_, due, xs, rs, options_);
    for (std::size_t k = 0; k < res.count(); ++k)
      sim_.add_particle(res.positions[k], res.radii[k], material_, velocity_, group_);
    inserted_ += res.count();
    failed_last_ = res.failed;
    return res.count();
  }

  bool finished() const { return schedule_.finished(inserted_); }
  std::size_t inserted() const { return inserted_; }
  /// Particles that found no room at the last update.
  std::size_t failed_last() const { return failed_last_; }
  RandomState rng_state() const { return rng_.state(); }
  void set_rng_state(const RandomState& s) { rng_.set_state(s); }
  void set_inserted(std::size_t n) { inserted_ = n; }

 private:
  // A distributed run: the owned particles of every rank that insert_random would find
  // relevant (those that can reach the region: |x - region| < r + r_max + min_gap), ordered by
  // id, on every rank. insert_random's decisions depend on that set only.
  void gather_obstacles(std::vector<Vec>& xs, std::vector<double>& rs) const {
    const auto& p = sim_.particles();
    const double r_new = sizes_.r_max();
    std::vector<double> mine;
    for (std::size_t i = 0; i < p.owned(); ++i) {
      const double reach = p.radius[i] + r_new + options_.min_gap;
      if (!(region_.squared_distance(p.x[i]) < reach * reach)) continue;
      mine.push_back(static_cast<double>(p.id[i]));  // (exact below 2^53)
      for (int k = 0; k < D::dim; ++k) mine.push_back(p.x[i][k]);
      mine.push_back(p.radius[i]);
    }
    const std::vector<double> all = sim_.parallel_engine().all_gather(mine);
    constexpr std::size_t per = D::dim + 2;
    std::vector<std::size_t> order(all.size() / per);
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[a * per] < all[b * per]; });
    xs.resize(order.size());
    rs.resize(order.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
      const double* rec = &all[order[k] * per];
      for (int c = 0; c < D::dim; ++c) xs[k][c] = rec[1 + c];
      rs[k] = rec[1 + D::dim];
    }
  }

  Sim& sim_;
  geometry::Aabb<D> region_;
  SizeDistribution sizes_;
  StreamSchedule schedule_;
  std::uint32_t material_;
  Vec velocity_;
  std::uint32_t group_;
  RandomGenerator rng_;
  InsertionOptions<D> options_;
  std::size_t inserted_ = 0;
  std::size_t failed_last_ = 0;
};

}  // namespace granule::scene
