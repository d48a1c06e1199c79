#pragma once
// Pouring: particles enter a region of a running simulation at a given rate (particles per
// second), like LIGGGHTS' insert/stream used by paper 001 section 2.4 (table 3: the insertion
// rate sets the packing fraction: fast = loose, slow = compact). Each update() places the
// particles that the StreamSchedule says are due, at random non-overlapping positions in the
// region (scene::insert_random), with a given initial velocity.
// The generator state travels with checkpoints: rng_state()/set_rng_state() and inserted().
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
    const std::span<const Vec> xs(p.x.data(), p.owned());
    const std::span<const double> rs(p.radius.data(), p.owned());
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
