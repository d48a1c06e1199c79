#pragma once
// Settling helpers (paper 001 section 2.4): let a poured bed come to rest, optionally removing
// kinetic energy by zeroing every velocity at a fixed interval, and stop when the bed is quiet:
// mean kinetic energy per particle below a threshold, or mean |contact force| change small.
// Also: delete particles above a height (smooth surface) and the height of the bed's surface.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "granule/core/error.hpp"

namespace granule::scene {

struct SettleOptions {
  double max_time = 1.0;                 ///< give up after this much simulated time [s]
  double zero_velocity_interval = 0.0;   ///< zero all velocities this often [s]; 0 = never
  double kinetic_energy_per_particle = 1e-12;  ///< quiet when mean KE per particle is below [J]
  double check_interval = 1e-3;          ///< how often the criterion is evaluated [s] (with
                                         ///< zeroing: at the end of each zeroing interval)
  std::function<void(double time, double ke_per_particle)> on_check;  ///< progress hook
};

struct SettleResult {
  bool settled = false;                  ///< criterion met before max_time
  double time = 0.0;                     ///< simulated time spent [s]
  double kinetic_energy_per_particle = 0.0;  ///< at the end [J]
};

/// Runs sim until it is quiet (see SettleOptions); returns what happened.
template <class Sim>
SettleResult settle(Sim& sim, const SettleOptions& o) {
  require(o.max_time > 0.0, "scene::settle", "max_time", o.max_time, "(0, inf) s");
  require(o.check_interval > 0.0, "scene::settle", "check_interval", o.check_interval, "(0, inf) s");
  require(o.zero_velocity_interval >= 0.0, "scene::settle", "zero_velocity_interval",
          o.zero_velocity_interval, "[0, inf) s");
  SettleResult res;
  const double t0 = sim.time();
  const auto steps_per_check = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(o.check_interval / sim.dt())));
  const auto steps_per_zero = o.zero_velocity_interval > 0.0
      ? std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(o.zero_velocity_interval / sim.dt())))
      : std::numeric_limits<std::uint64_t>::max();
  std::uint64_t k = 0;
  while (sim.time() - t0 < o.max_time) {
    sim.step();
    ++k;
    // With zeroing, judge only at the end of a zeroing interval: right after a reset the
    // kinetic energy is artificially small.
    const bool zeroing = steps_per_zero != std::numeric_limits<std::uint64_t>::max();
    if (zeroing ? k % steps_per_zero == 0 : k % steps_per_check == 0) {
      std::size_t n = sim.particles().owned();
      if constexpr (Sim::ParallelPolicy::distributed) {
        // (kinetic_energy() is over every rank: so is the count, so every rank decides alike.)
        if (sim.parallel_engine().decomposition) n = static_cast<std::size_t>(sim.parallel_engine().sum(std::uint64_t(n)));
      }
      n = std::max<std::size_t>(1, n);
      res.kinetic_energy_per_particle = sim.kinetic_energy() / static_cast<double>(n);
      if (o.on_check) o.on_check(sim.time(), res.kinetic_energy_per_particle);
      if (res.kinetic_energy_per_particle < o.kinetic_energy_per_particle) {
        res.settled = true;
        break;
      }
    }
    if (k % steps_per_zero == 0) {
      auto& p = sim.particles();
      for (std::size_t i = 0; i < p.owned(); ++i) {
        p.v[i].setZero();
        p.omega[i] = Sim::Dimension::zero_ang();
      }
    }
  }
  res.time = sim.time() - t0;
  return res;
}

/// Deletes the particles whose centre lies above `height` along `axis` [m]; returns how many
/// (distributed: over every rank, collective).
template <class Sim>
std::size_t remove_above(Sim& sim, int axis, double height) {
  const auto& p = sim.particles();
  return sim.remove_particles([&](std::size_t i) { return p.x[i][axis] > height; });
}

/// Height of the free surface along `axis`: the mean top (x + r) of the `top_count` highest
/// particles [m] (a robust stand-in for the highest particle).
template <class Sim>
double surface_height(const Sim& sim, int axis, std::size_t top_count = 20) {
  const auto& p = sim.particles();
  std::vector<double> tops(p.owned());
  for (std::size_t i = 0; i < p.owned(); ++i) tops[i] = p.x[i][axis] + p.radius[i];
  if constexpr (Sim::ParallelPolicy::distributed) {
    // Each rank's highest top_count, gathered (collective): the same tops on every rank, in
    // the same order as one process would sum them (descending).
    if (sim.parallel_engine().decomposition) {
      const std::size_t k = std::min(top_count, tops.size());
      std::partial_sort(tops.begin(), tops.begin() + static_cast<std::ptrdiff_t>(k), tops.end(), std::greater<>());
      tops.resize(k);
      tops = sim.parallel_engine().all_gather(tops);
    }
  }
  if (tops.empty()) return std::numeric_limits<double>::quiet_NaN();
  top_count = std::min(top_count, tops.size());
  std::partial_sort(tops.begin(), tops.begin() + top_count, tops.end(), std::greater<>());
  double s = 0.0;
  for (std::size_t i = 0; i < top_count; ++i) s += tops[i];
  return s / static_cast<double>(top_count);
}

}  // namespace granule::scene
