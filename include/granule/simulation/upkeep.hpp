#pragma once
// Simulation, part: the step's upkeep. The set-up before the first step (checks, the first
// list and the set-up force evaluation that changes no history), the neighbour list rebuild and
// its triggers, ghost refresh, and the checks that stop a run as unstable.
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::rebuild() {
  if constexpr (Parallel::distributed) {
    rebuild_distributed();  // simulation/distributed.hpp
    return;
  }
  rebuild_list(effective_skin(), skin_with_reach(effective_skin()), neighbours::NoRebuildHooks{});
  check_domain();
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::skin_with_reach(double skin) const {
  return skin + max_tensile_reach();
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Hooks>
inline void Simulation<D, Model, Search, Integrator, Parallel>::rebuild_list(double skin, double listed, Hooks&& hooks) {
  // A tensile model lists pairs to the pull-off separation beyond the skin (the rebuild test
  // stays at half the skin, so a pair that can still touch is always listed).
  list_.template rebuild<Search>(
      particles_, config_.domain, listed, [](State& s) { Model::reverse(s); },
      [&](std::size_t, const Vec& x, double reach, auto&& emit) {
        for (std::uint32_t w = 0; w < walls_.size(); ++w) {
          if (!walls_[w].active) continue;
          walls_[w].for_each_contact(bodies_[walls_[w].body], x, reach,
                                     [&](const geometry::SurfacePoint<D>& sp) { emit(w, sp.feature); });
        }
      },
      hooks);
  for (auto& b : bodies_) {
    b.displacement_since_build.setZero();
    b.rotation_since_build = 0.0;
  }
  wall_touched_.assign(list_.wall.size(), 0);
  parallel_ = particles_.owned() >= kParallelMinParticles;
  skin_used_ = skin;
  list_valid_ = true;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::effective_skin() const {
  if (Search::rebuild_every_step) return 0.0;
  if (config_.skin >= 0.0) return config_.skin;
  double r_max = 0.0;
  for (std::size_t i = 0; i < particles_.owned(); ++i) r_max = std::max(r_max, particles_.radius[i]);
  return 0.2 * r_max;  // 0.1 x the largest diameter
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::initialise() {
  // In a distributed run (simulation/distributed.hpp) every check is collective (a failure on
  // one rank is thrown on every rank), the rebuild migrates and exchanges halos and the body and
  // wall forces of the set-up evaluation are summed over the ranks.
  if (!initialised_) collective([&] {
      check_pair_parameters();
      check_time_step();
    });
  rebuild_everywhere();
  update_group_velocities(time_);
  for (auto& b : bodies_) b.set_velocities(time_);
  if (forces_ready_) {
    // Mid-run change (particles or walls added or removed): the list is rebuilt but forces
    // are not evaluated twice, which would advance every tangential spring a second time.
    // New particles start with zero force for their first half kick.
    initialised_ = true;
    return;
  }
  forces_ready_ = true;
  // A pending request_contacts() is for the coming step, not this set-up evaluation.
  const bool pending = record_next_;
  collective([&] { setup_forces(); });
  if constexpr (Parallel::distributed) reduce_wall_forces();
  record_next_ = pending;
  initialised_ = true;
  collective([&] { check_rolling_time_step(); });
}

// The set-up evaluation: the forces of the initial state for the first half kick. No time has
// passed, so no contact history may change (LAMMPS does the same: no history update during
// set-up). The laws see dt = 0 -- no increment, no twist, the force of the history as it is --
// and whatever they still write (e.g. the stiffness the Mindlin force form remembers) is
// discarded: the history arrays are put back afterwards, so this holds for every law.
template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::setup_forces() {
  struct Restore {
    Simulation& sim;
    ~Restore() { sim.setup_evaluation_ = false; }
  } restore{*this};
  std::vector<std::uint32_t> saved_slots;
  std::vector<typename List::HistoryPool> saved_pools;
  std::vector<State> saved_walls;
  if constexpr (kHasState) {
    saved_slots = list_.slot;
    saved_pools = list_.pools;
    saved_walls = list_.wall_state;
  }
  setup_evaluation_ = true;
  compute_forces(contacts_wanted(step_) || record_next_);
  if constexpr (kHasState) {
    list_.slot.swap(saved_slots);
    // Assigned, not swapped: the copies have no spare room (PairList::transfer reserved it).
    for (std::size_t l = 0; l < saved_pools.size(); ++l) {
      list_.pools[l].states.assign(saved_pools[l].states.begin(), saved_pools[l].states.end());
      list_.pools[l].free.assign(saved_pools[l].free.begin(), saved_pools[l].free.end());
    }
    list_.wall_state.swap(saved_walls);
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline bool Simulation<D, Model, Search, Integrator, Parallel>::contacts_wanted(std::uint64_t step) const {
  if (record_next_ || record_always_) return true;
  for (const auto& o : observers_)
    if (o.needs_contacts && step % o.every == 0) return true;
  return false;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline bool Simulation<D, Model, Search, Integrator, Parallel>::body_needs_rebuild() const {
  const double half = 0.5 * skin_used_;
  for (const auto& b : bodies_) {
    if (!b.moving()) continue;
    double moved = b.displacement_since_build.norm();
    if (b.rotation_since_build > 0.0) {
      double ext = 0.0;
      for (const auto& w : walls_)
        if (&bodies_[w.body] == &b) ext = std::max(ext, w.extent());
      moved += b.rotation_since_build * ext;
    }
    if (moved > half) return true;
  }
  return false;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::refresh_ghosts() {
  auto& p = particles_;
  const std::size_t n = p.owned();
  const Vec L = config_.domain.length();
  for (std::size_t g = 0; g < p.local_ghosts(); ++g) {
    const std::uint32_t o = p.ghost_owner[g];
    p.x[n + g] = p.x[o] + (p.ghost_shift[g].template cast<double>().array() * L.array()).matrix();
    p.v[n + g] = p.v[o];
    p.omega[n + g] = p.omega[o];
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::check_domain() const {
  for (std::size_t i = 0; i < particles_.owned(); ++i) {
    if (!particles_.x[i].allFinite()) throw_instability(i, "its position is not finite");
    if (!config_.domain.contains(particles_.x[i])) throw_instability(i, "it left the non-periodic domain");
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline bool Simulation<D, Model, Search, Integrator, Parallel>::finite_state(std::size_t i) const {
  const auto& p = particles_;
  const auto zeros = [](const auto& a) { return (a - a).sum(); };
  double s = zeros(p.f[i]) + zeros(p.x[i]) + zeros(p.v[i]);
  if constexpr (D::dim == 3) {
    s += zeros(p.torque[i]);
  } else {
    s += p.torque[i] - p.torque[i];
  }
  return s == 0.0;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
[[noreturn]] inline void Simulation<D, Model, Search, Integrator, Parallel>::throw_instability(std::size_t i, const std::string& why) const {
  std::ostringstream s;
  s.precision(9);
  s << "Simulation unstable at step " << step_ << " (t = " << time_ << " s): particle id "
    << particles_.id[i] << " at (";
  for (int k = 0; k < D::dim; ++k) s << (k ? ", " : "") << particles_.x[i][k];
  s << ") m: " << why << ". Reduce dt or check the set-up (overlaps, stiffness, walls).";
  throw InstabilityError(s.str());
}

}  // namespace granule
