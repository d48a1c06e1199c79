#pragma once
// Simulation, the step's particle passes: the first kick and drift (with the force reset and the
// rebuild test, in one pass over the particles) and the second kick (with the finiteness stop).
// Part of the Simulation class (granule/simulation.hpp includes this file at its end).

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::start_if_needed() {
  if (!list_valid_) {
    initialise();
  } else if (!initialised_) {
    // Only the time step changed (set_dt): check it, keep the list and forces as they are so
    // the trajectory is not perturbed by an extra rebuild.
    check_time_step();
    check_rolling_time_step();
    initialised_ = true;
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline typename Simulation<D, Model, Search, Integrator, Parallel>::Drift
Simulation<D, Model, Search, Integrator, Parallel>::kick_and_drift(double dt) {
  const double kick1 = Integrator::first_kick * dt;
  const std::size_t n = particles_.owned();
  auto& p = particles_;
  const double lim = list_.rebuild_distance(skin_used_), lim2 = lim * lim;
  const bool test_moves = !Search::rebuild_every_step && list_.x_at_build.size() == n;
  int moved = 0;
  // The range of particle materials: with one material the packed loop need not look up
  // each pair's (ghosts carry their owners' material).
  std::uint32_t mat_lo = std::numeric_limits<std::uint32_t>::max(), mat_hi = 0;
#pragma omp parallel for schedule(static) reduction(| : moved) reduction(min : mat_lo) reduction(max : mat_hi) if (parallel_)
  for (std::size_t i = 0; i < n; ++i) {
    mat_lo = std::min(mat_lo, p.material[i]);
    mat_hi = std::max(mat_hi, p.material[i]);
    switch (p.motion[i]) {
      case Motion::Free:
        p.v[i] += kick1 * p.inv_mass[i] * p.f[i];
        p.omega[i] += (kick1 * p.inv_inertia[i]) * p.torque[i];
        p.x[i] += dt * p.v[i];
        if constexpr (kResetInDrift) p.f[i] = p.mass[i] * config_.gravity;
        break;
      case Motion::Prescribed:
        p.v[i] = group_v_now_[p.group[i]];
        p.x[i] += dt * p.v[i];
        if constexpr (kResetInDrift) p.f[i].setZero();
        break;
      case Motion::Frozen:
        if constexpr (kResetInDrift) p.f[i].setZero();
        break;
    }
    if constexpr (kResetInDrift) p.torque[i] = D::zero_ang();
    if (test_moves) moved |= (p.x[i] - list_.x_at_build[i].template cast<double>()).squaredNorm() > lim2;
  }
  return {!test_moves || moved != 0, n > 0 && mat_lo == mat_hi};
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::second_kick(double dt) {
  const double kick2 = Integrator::second_kick * dt;
  const std::size_t n = particles_.owned();
  auto& p = particles_;
  // compute_forces left the finiteness test to this pass: a particle that fails it keeps its
  // velocity and stops the run below.
  std::size_t bad = std::numeric_limits<std::size_t>::max();
#pragma omp parallel for schedule(static) reduction(min : bad) if (parallel_)
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite_state(i)) {
      bad = std::min(bad, i);
      continue;
    }
    if (p.motion[i] == Motion::Free) {
      p.v[i] += kick2 * p.inv_mass[i] * p.f[i];
      p.omega[i] += (kick2 * p.inv_inertia[i]) * p.torque[i];
    } else if (p.motion[i] == Motion::Prescribed) {
      p.v[i] = group_v_now_[p.group[i]];
    }
  }
  if (bad != std::numeric_limits<std::size_t>::max())
    throw_instability(bad, "its force, torque, position or velocity is not finite");
}

}  // namespace granule
