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

// Both passes read and write the particle arrays through raw pointers copied into the loop's
// lambda, and each loop runs a local copy of that lambda: through the vectors (or through
// pointers whose address a parallel region had seen) GCC reloaded every array's data pointer
// after each store, since a store to a double might have changed it as far as it could tell.
// One thread (below kParallelMinParticles) runs the plain loop, without a parallel region.
template <class D, class Model, class Search, class Integrator, class Parallel>
inline typename Simulation<D, Model, Search, Integrator, Parallel>::Drift
Simulation<D, Model, Search, Integrator, Parallel>::kick_and_drift(double dt) {
  const double kick1 = Integrator::first_kick * dt;
  const std::size_t n = particles_.owned();
  auto& p = particles_;
  const double lim = list_.rebuild_distance(skin_used_), lim2 = lim * lim;
  const bool test_moves = !Search::rebuild_every_step && list_.x_at_build.size() == n;
  Vec* const x = p.x.data();
  Vec* const v = p.v.data();
  AngVec* const omega = p.omega.data();
  Vec* const f = p.f.data();
  AngVec* const torque = p.torque.data();
  const double* const mass = p.mass.data();
  const double* const inv_mass = p.inv_mass.data();
  const double* const inv_inertia = p.inv_inertia.data();
  const std::uint32_t* const material = p.material.data();
  const Motion* const motion = p.motion.data();
  const auto* const group = p.group.data();
  const Vec* const group_v = group_v_now_.data();
  const auto* const x_build = list_.x_at_build.data();
  const Vec gravity = config_.gravity;
  // Kicks and drifts particle i; its squared displacement since the list's build (0 without
  // the rebuild test).
  const auto particle = [=](std::size_t i) -> double {
    switch (motion[i]) {
      case Motion::Free:
        v[i] += kick1 * inv_mass[i] * f[i];
        omega[i] += (kick1 * inv_inertia[i]) * torque[i];
        x[i] += dt * v[i];
        if constexpr (kResetInDrift) f[i] = mass[i] * gravity;
        break;
      case Motion::Prescribed:
        v[i] = group_v[group[i]];
        x[i] += dt * v[i];
        if constexpr (kResetInDrift) f[i].setZero();
        break;
      case Motion::Frozen:
        if constexpr (kResetInDrift) f[i].setZero();
        break;
    }
    if constexpr (kResetInDrift) torque[i] = D::zero_ang();
    return test_moves ? (x[i] - x_build[i].template cast<double>()).squaredNorm() : 0.0;
  };
  int moved = 0;
  // The range of particle materials: with one material the packed loop need not look up
  // each pair's (ghosts carry their owners' material).
  std::uint32_t mat_lo = std::numeric_limits<std::uint32_t>::max(), mat_hi = 0;
  if (parallel_) {
#pragma omp parallel reduction(| : moved) reduction(min : mat_lo) reduction(max : mat_hi)
    {
      const auto local = particle;  // (a copy per thread: the shared one is read through memory)
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        mat_lo = std::min(mat_lo, material[i]);
        mat_hi = std::max(mat_hi, material[i]);
        moved |= static_cast<int>(local(i) > lim2);
      }
    }
  } else {
    // (The largest displacement, not an `or` of the tests: GCC kept that flag in memory, and
    // the `or` into it per particle chained the iterations. A NaN is passed over by both.)
    const auto local = particle;
    double worst = 0.0;
    std::uint32_t lo = mat_lo, hi = mat_hi;
    for (std::size_t i = 0; i < n; ++i) {
      lo = std::min(lo, material[i]);
      hi = std::max(hi, material[i]);
      worst = std::max(worst, local(i));
    }
    moved = static_cast<int>(worst > lim2);
    mat_lo = lo;
    mat_hi = hi;
  }
  return {!test_moves || moved != 0, n > 0 && mat_lo == mat_hi};
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::second_kick(double dt) {
  const double kick2 = Integrator::second_kick * dt;
  const std::size_t n = particles_.owned();
  auto& p = particles_;
  const Vec* const x = p.x.data();
  Vec* const v = p.v.data();
  AngVec* const omega = p.omega.data();
  const Vec* const f = p.f.data();
  const AngVec* const torque = p.torque.data();
  const double* const inv_mass = p.inv_mass.data();
  const double* const inv_inertia = p.inv_inertia.data();
  const Motion* const motion = p.motion.data();
  const auto* const group = p.group.data();
  const Vec* const group_v = group_v_now_.data();
  // compute_forces left the finiteness test to this pass: a particle that fails it keeps its
  // velocity and stops the run below (finite_state's test, on the hoisted pointers).
  const auto particle = [=](std::size_t i, std::size_t& bad) {
    // (Vectors summed before their components: fewer dependent additions than finite_state's
    // order, the same verdict, since a sum of zeros is zero in any order and inf - inf = NaN.)
    const Vec z = (f[i] - f[i]) + (x[i] - x[i]) + (v[i] - v[i]);
    double s;
    if constexpr (D::dim == 3) {
      s = (z + (torque[i] - torque[i])).sum();
    } else {
      s = z.sum() + (torque[i] - torque[i]);
    }
    if (s != 0.0) {
      bad = std::min(bad, i);
      return;
    }
    if (motion[i] == Motion::Free) {
      v[i] += kick2 * inv_mass[i] * f[i];
      omega[i] += (kick2 * inv_inertia[i]) * torque[i];
    } else if (motion[i] == Motion::Prescribed) {
      v[i] = group_v[group[i]];
    }
  };
  std::size_t bad = std::numeric_limits<std::size_t>::max();
  if (parallel_) {
#pragma omp parallel reduction(min : bad)
    {
      const auto local = particle;
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) local(i, bad);
    }
  } else {
    const auto local = particle;
    std::size_t b = bad;
    for (std::size_t i = 0; i < n; ++i) local(i, b);
    bad = b;
  }
  if (bad != std::numeric_limits<std::size_t>::max())
    throw_instability(bad, "its force, torque, position or velocity is not finite");
}

}  // namespace granule
