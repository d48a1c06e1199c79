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

namespace simulation_parts {
// Whether the W particles from `motion` on are all free (Motion::Free is 0): one load of their
// modes instead of W tests (the 2D passes' blocks below).
template <std::size_t W>
inline bool all_free(const Motion* motion) {
  std::uint64_t modes = 0;
  static_assert(W <= sizeof(modes) && sizeof(Motion) == 1);
  std::memcpy(&modes, motion, W);
  return modes == 0;
}
}  // namespace simulation_parts

// Both passes read and write the particle arrays through raw pointers copied into the loop's
// lambda, and each loop runs a local copy of that lambda: through the vectors (or through
// pointers whose address a parallel region had seen) GCC reloaded every array's data pointer
// after each store, since a store to a double might have changed it as far as it could tell.
// One thread (below kParallelMinParticles) runs the plain loop, without a parallel region.
// In 2D with AVX2 or AVX-512 both passes take W free particles at a time (core/vec2_lanes.hpp),
// with the same arithmetic per component as one at a time: the same bits.
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
  // 2D with AVX2 or AVX-512: W particles at a time when all are free (core/vec2_lanes.hpp:
  // each lane computes what `particle` computes for its component, so the results are the
  // same bits); `worst` takes the block's largest squared displacement (a NaN passed over, as
  // by std::max below). A block with a frozen or prescribed particle returns false untouched.
  // (One particle at a time the passes were 15 % of a 1600-disk step.)
  constexpr bool blocks = kVec2Lanes && D::dim == 2 && kResetInDrift;
  constexpr std::size_t W = lane_width;
  // (Built here, not in the block: a pack assembled from stores of its lanes and loaded at
  // once waits for the stores, which a load of several cannot forward: 40 % of the pass.)
  const Lane g([&](auto l) { return gravity[l % 2]; });
  const auto block = [=](std::size_t b, Lane& worst) GRANULE_ALWAYS_INLINE -> bool {
    if constexpr (blocks) {
      if (!simulation_parts::all_free<W>(motion + b)) return false;
      using namespace vec2_lanes;
      constexpr auto aligned = stdx::element_aligned;
      double* const xb = x[b].data();
      double* const vb = v[b].data();
      double* const fb = f[b].data();
      const Lane k = kick1 * Lane(inv_mass + b, aligned);
      const Lane m(mass + b, aligned);
      Lane om(&omega[b], aligned);
      om = om + (kick1 * Lane(inv_inertia + b, aligned)) * Lane(&torque[b], aligned);
      om.copy_to(&omega[b], aligned);
      Lane(0.0).copy_to(&torque[b], aligned);
      const auto half = [&](auto h) {
        constexpr int H = decltype(h)::value;
        const std::size_t o = H * W;
        Lane vh(vb + o, aligned);
        vh = vh + spread<H>(k) * Lane(fb + o, aligned);
        Lane xh(xb + o, aligned);
        xh = xh + dt * vh;
        vh.copy_to(vb + o, aligned);
        xh.copy_to(xb + o, aligned);
        (spread<H>(m) * g).copy_to(fb + o, aligned);
        if (test_moves) {
          const Lane d = xh - load_floats(x_build[b].data() + o);
          const Lane e = swap_pairs(d);
          // (Even lanes: dx dx + dy dy in the order of squaredNorm; the odd lanes are dropped.)
          const Lane d2 = even_lanes(d * d + e * e);
          assign_lanes(d2 > worst, worst, d2);
        }
      };
      half(std::integral_constant<int, 0>{});
      half(std::integral_constant<int, 1>{});
      return true;
    } else {
      (void)b;
      (void)worst;
      return false;
    }
  };
  // Unit c: block c of W particles (c < nb), then single particles. Takes the largest squared
  // displacement (one-at-a-time particles in `worst`) and whether a material differs from the
  // first particle's: with one material the packed loop need not look up each pair's (ghosts
  // carry their owners' material). A block's W materials in one vector operation: their
  // scalar min and max were 1-1.4 % of the 2D step (Zen 3, 2026-12-07).
  using MaterialLanes = stdx::fixed_size_simd<std::uint32_t, W>;
  const std::uint32_t m0 = n > 0 ? material[0] : 0;
  const std::size_t nb = blocks ? n / W : 0;
  const std::size_t units = nb + (n - nb * W);
  const auto unit = [=](std::size_t c, Lane& worst_lanes, double& worst, MaterialLanes& other_lanes,
                        std::uint32_t& other) GRANULE_ALWAYS_INLINE {
    const std::size_t b = c < nb ? c * W : nb * W + (c - nb);
    const std::size_t e = c < nb ? b + W : b + 1;
    if (c < nb) {
      other_lanes |= MaterialLanes(material + b, stdx::element_aligned) ^ m0;
    } else {
      other |= material[b] ^ m0;
    }
    if (c < nb && block(b, worst_lanes)) return;
    for (std::size_t i = b; i < e; ++i) worst = std::max(worst, particle(i));
  };
  const auto lanes_max = [](const Lane& w) {
    double m = 0.0;
    for (std::size_t l = 0; l < W; ++l) m = std::max(m, w[l]);
    return m;
  };
  const auto lanes_or = [](const MaterialLanes& v) {
    std::uint32_t r = 0;
    for (std::size_t l = 0; l < W; ++l) r |= v[l];
    return r;
  };
  int moved = 0;
  std::uint32_t other_material = 0;
  if (parallel_) {
#pragma omp parallel reduction(| : moved, other_material)
    {
      const auto local = unit;  // (a copy per thread: the shared one is read through memory)
      Lane worst_lanes(0.0);
      double worst = 0.0;
      MaterialLanes other_lanes(0u);
      std::uint32_t other = 0;
#pragma omp for schedule(static)
      for (std::size_t c = 0; c < units; ++c) local(c, worst_lanes, worst, other_lanes, other);
      moved |= static_cast<int>(std::max(worst, lanes_max(worst_lanes)) > lim2);
      other_material |= other | lanes_or(other_lanes);
    }
  } else {
    // (The largest displacement, not an `or` of the tests: GCC kept that flag in memory, and
    // the `or` into it per particle chained the iterations. A NaN is passed over by both.)
    const auto local = unit;
    Lane worst_lanes(0.0);
    double worst = 0.0;
    MaterialLanes other_lanes(0u);
    std::uint32_t other = 0;
    for (std::size_t c = 0; c < units; ++c) local(c, worst_lanes, worst, other_lanes, other);
    moved = static_cast<int>(std::max(worst, lanes_max(worst_lanes)) > lim2);
    other_material = other | lanes_or(other_lanes);
  }
  return {!test_moves || moved != 0, n > 0 && other_material == 0};
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
  // 2D with AVX2 or AVX-512: W particles at a time when all are free and finite (as in
  // kick_and_drift); otherwise one at a time.
  constexpr bool blocks = kVec2Lanes && D::dim == 2;
  constexpr std::size_t W = lane_width;
  const auto block = [=](std::size_t b) GRANULE_ALWAYS_INLINE -> bool {
    if constexpr (blocks) {
      if (!simulation_parts::all_free<W>(motion + b)) return false;
      using namespace vec2_lanes;
      constexpr auto aligned = stdx::element_aligned;
      const double* const xb = x[b].data();
      double* const vb = v[b].data();
      const double* const fb = f[b].data();
      const Lane tq(&torque[b], aligned);
      const Lane f0(fb, aligned), f1(fb + W, aligned), x0(xb, aligned), x1(xb + W, aligned);
      Lane v0(vb, aligned), v1(vb + W, aligned);
      // (x - x is 0 for a finite x and NaN otherwise: the test of `particle`.)
      const Lane z = ((f0 - f0) + (x0 - x0) + (v0 - v0)) + ((f1 - f1) + (x1 - x1) + (v1 - v1)) + (tq - tq);
      if (stdx::any_of(z != 0.0)) return false;
      const Lane k = kick2 * Lane(inv_mass + b, aligned);
      v0 = v0 + spread<0>(k) * f0;
      v1 = v1 + spread<1>(k) * f1;
      v0.copy_to(vb, aligned);
      v1.copy_to(vb + W, aligned);
      Lane om(&omega[b], aligned);
      om = om + (kick2 * Lane(inv_inertia + b, aligned)) * tq;
      om.copy_to(&omega[b], aligned);
      return true;
    } else {
      (void)b;
      return false;
    }
  };
  const std::size_t nb = blocks ? n / W : 0;
  const std::size_t units = nb + (n - nb * W);
  const auto unit = [=](std::size_t c, std::size_t& bad) GRANULE_ALWAYS_INLINE {
    const std::size_t b = c < nb ? c * W : nb * W + (c - nb);
    if (c < nb && block(b)) return;
    const std::size_t e = c < nb ? b + W : b + 1;
    for (std::size_t i = b; i < e; ++i) particle(i, bad);
  };
  std::size_t bad = std::numeric_limits<std::size_t>::max();
  if (parallel_) {
#pragma omp parallel reduction(min : bad)
    {
      const auto local = unit;
#pragma omp for schedule(static)
      for (std::size_t c = 0; c < units; ++c) local(c, bad);
    }
  } else {
    const auto local = unit;
    std::size_t b = bad;
    for (std::size_t c = 0; c < units; ++c) local(c, b);
    bad = b;
  }
  if (bad != std::numeric_limits<std::size_t>::max())
    throw_instability(bad, "its force, torque, position or velocity is not finite");
}

}  // namespace granule
