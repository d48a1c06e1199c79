#pragma once
// Simulation, part: the time-step and stability checks. The critical time of the scene's
// materials (Rayleigh or linear collision time), the stability limit of the rolling
// spring-dashpots over the current contacts and its estimate before any contact, and the checks
// that refuse a dt above them (docs/physics.md, "Time step").
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::critical_time_step() const {
  double tc = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles_.owned(); ++i) {
    const Material& m = materials_[particles_.material[i]];
    const double r = particles_.radius[i];
    if constexpr (Model::NormalLaw::hertzian) {
      tc = std::min(tc, rayleigh_time(r, m.density, m.shear_modulus(), m.poisson_ratio));
    } else {
      for (std::uint32_t b = 0; b < materials_.size(); ++b) {
        const PairMaterial& pm = materials_.pair(particles_.material[i], b);
        if (pm.k_n_linear <= 0.0) continue;
        // Two equal particles: m* = m/2; a wall: m* = m (a rigid one has 2 k: the same period).
        const double m_eff = (wall_material_[b] ? 1.0 : 0.5) * particles_.mass[i];
        tc = std::min(tc, linear_critical_time(pm.k_n_linear, m_eff, pm.restitution, kPredictDamping ? 2.0 : 1.0));
      }
    }
  }
  return tc;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::suggested_time_step() const {
  return std::min(config_.time_step_safety * critical_time_step(), rolling_stability_limit().limit);
}

// rolling_stability_limit: rotations obey I theta'' = -K theta - C theta' - (coupling to
// translation through the tangential spring); K and C are assembled from the contacts' k_r, C_r
// on the relative rotation and k_t, gamma_t on the slip at the contact point. For every free
// particle i, Gershgorin's theorem on M^-1/2 K M^-1/2 (and C) bounds the largest rate of its
// rotation rows:
//   w_i^2 = sum_c [ k_r (a_i + sqrt(a_i a_j)) + k_t l_i (l_i a_i + l_j sqrt(a_i a_j)
//                   + sqrt(a_i b_i) + sqrt(a_i b_j)) ]
// with a = 1/I, b = 1/m (0 for a wall or a partner that is not free) and l the lever arms;
// 2 zeta_i w_i the same sum with C_r, gamma_t. The limit is the smallest
// damped_oscillator_stability_limit(w_i, zeta_i): dt^2 w^2 / 4 + dt zeta w <= 1, sufficient for
// K and C that are not proportional.
template <class D, class Model, class Search, class Integrator, class Parallel>
inline auto Simulation<D, Model, Search, Integrator, Parallel>::rolling_stability_limit() const -> RollingLimit {
  RollingLimit out;
  if constexpr (kRollingDashpot) {
    if (!list_valid_ || !forces_ready_) return out;
    const auto& p = particles_;
    const std::size_t n = p.owned();
    // Per free particle: the row sums of K and C, and the number of contacts.
    std::vector<double> k_sum(n, 0.0), c_sum(n, 0.0);
    std::vector<std::uint32_t> count(n, 0);
    const auto free_or_zero = [&](std::size_t i, double value) {
      return p.motion[i] == Motion::Free ? value : 0.0;
    };
    for_each_contact_geometry([&](const contact::ContactGeometry<D>& g, const Params& prm, const State&,
                                  std::size_t i, std::uint32_t j, std::uint32_t is_wall) {
      const contact::NormalResult nr = Model::NormalLaw::eval(prm.normal, g);
      const contact::SpringDashpot roll = Model::RollingLaw::spring_dashpot(prm.rolling, g, nr);
      contact::SpringDashpot slip;
      if constexpr (kTangentialDashpot) slip = Model::TangentialLaw::spring_dashpot(prm.tangential, g, nr);
      const std::size_t o = is_wall != 0u ? i : p.source(j);
      const double ai = free_or_zero(i, p.inv_inertia[i]), bi = free_or_zero(i, p.inv_mass[i]);
      const double aj = is_wall != 0u ? 0.0 : free_or_zero(o, p.inv_inertia[o]);
      const double bj = is_wall != 0u ? 0.0 : free_or_zero(o, p.inv_mass[o]);
      const double lj = is_wall != 0u ? 0.0 : static_cast<double>(g.arm_j);
      const double li = g.arm_i, cross = std::sqrt(ai * aj);
      // Row of particle `self` (inverse inertia a, mass b, arm l) against the other's (a2, b2, l2).
      const auto add = [&](std::size_t self, double a, double b, double l, double b2, double l2) {
        const double r = a + cross, t = l * (l * a + l2 * cross + std::sqrt(a * b) + std::sqrt(a * b2));
        k_sum[self] += roll.stiffness * r + slip.stiffness * t;
        c_sum[self] += roll.damping * r + slip.damping * t;
        ++count[self];
      };
      add(i, ai, bi, li, bj, lj);
      if (is_wall == 0u && o < n) add(o, aj, bj, lj, bi, li);  // (a remote ghost's row is its rank's)
    });
    // The predicted-damping integrator hands the dashpots v + dt/2 F_old/m, which doubles
    // their effective rate per step: a pure dashpot is stable for c dt <= 1 instead of 2.
    constexpr double rate_factor = kPredictDamping ? 2.0 : 1.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!(k_sum[i] > 0.0)) continue;
      const double w = std::sqrt(k_sum[i]);
      const double t = damped_oscillator_stability_limit(w, rate_factor * c_sum[i] / (2.0 * w));
      if (t < out.limit) out = {t, i, count[i]};
    }
  }
  return out;
}

// rolling_limit_estimate: for models with a rolling spring-dashpot under gravity, one contact of
// the smallest particle of each particle material against every material it can touch (a wall,
// or the smallest particle of another particle material), at the overlap where its normal law
// carries the particle's weight m |g|, with the rolling terms of rolling_stability_limit()'s row
// alone (w^2 = K (a_i + sqrt(a_i a_j)), 2 zeta w the same with C). Leaving out the tangential
// terms and the other contacts makes it an upper bound of rolling_stability_limit() at that
// contact: a step above it is refused surely (a particle at rest on anything carries at least
// its weight), one below it is checked again once the contacts exist.
template <class D, class Model, class Search, class Integrator, class Parallel>
inline auto Simulation<D, Model, Search, Integrator, Parallel>::rolling_limit_estimate() const -> RollingEstimate {
  RollingEstimate out;
  if constexpr (kRollingDashpot) {
    const auto& p = particles_;
    const double grav = config_.gravity.norm();
    if (!(grav > 0.0)) return out;
    const std::uint32_t nm = static_cast<std::uint32_t>(materials_.size());
    constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
    std::vector<std::size_t> smallest(nm, none);
    for (std::size_t i = 0; i < p.owned(); ++i) {
      if (p.motion[i] != Motion::Free) continue;
      std::size_t& s = smallest[p.material[i]];
      if (s == none || p.radius[i] < p.radius[s]) s = i;
    }
    const double k1 = D::inertia_factor + 1.0;
    constexpr double rate_factor = kPredictDamping ? 2.0 : 1.0;
    for (std::uint32_t a = 0; a < nm; ++a) {
      if (smallest[a] == none) continue;
      const std::size_t i = smallest[a];
      for (std::uint32_t b = 0; b < nm; ++b) {
        const bool wall = wall_material_[b];
        if (!wall && smallest[b] == none) continue;
        const std::size_t j = wall ? i : smallest[b];
        contact::ContactGeometry<D> g{};
        g.n = D::zero();
        g.n[D::dim - 1] = 1.0;
        g.r_i = p.radius[i];
        g.r_j = wall ? std::numeric_limits<double>::infinity() : p.radius[j];
        g.r_eff = wall ? g.r_i : g.r_i * g.r_j / (g.r_i + g.r_j);
        g.m_eff = wall ? p.mass[i] : 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
        g.i_roll = wall ? k1 * p.mass[i] * g.r_i * g.r_i
                        : 1.0 / (p.inv_mass[i] / (k1 * g.r_i * g.r_i) + p.inv_mass[j] / (k1 * g.r_j * g.r_j));
        g.vn = g.vn_damp = 0.0;
        g.dt = config_.dt;
        const Params& prm = params_[a * nm + b];
        // The overlap that carries the weight (the elastic force rises with it): bisection.
        double lo = 0.0, hi = g.r_i;
        for (int it = 0; it < 100; ++it) {
          g.overlap = 0.5 * (lo + hi);
          (Model::NormalLaw::eval(prm.normal, g).fn_elastic < p.mass[i] * grav ? lo : hi) = g.overlap;
        }
        g.overlap = hi;
        const contact::NormalResult nr = Model::NormalLaw::eval(prm.normal, g);
        const contact::SpringDashpot roll = Model::RollingLaw::spring_dashpot(prm.rolling, g, nr);
        const double ai = p.inv_inertia[i], aj = wall ? 0.0 : p.inv_inertia[j], row = ai + std::sqrt(ai * aj);
        if (!(roll.stiffness * row > 0.0)) continue;
        const double w = std::sqrt(roll.stiffness * row);
        const double t = damped_oscillator_stability_limit(w, rate_factor * roll.damping * row / (2.0 * w));
        if (t < out.limit) out = {t, a, b, g.overlap, materials_.pair(a, b).rolling_damping};
      }
    }
  }
  return out;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::check_pair_parameters() const {
  for (std::uint32_t a = 0; a < materials_.size(); ++a)
    for (std::uint32_t b = a; b < materials_.size(); ++b)
      if (!(wall_material_[a] && wall_material_[b]))
        Model::validate(materials_.pair(a, b),
                        "material pair ('" + materials_[a].name + "', '" + materials_[b].name + "')");
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::check_time_step() const {
  if (config_.allow_large_time_step || particles_.owned() == 0) return;
  const double tc = critical_time_step();
  if (!std::isfinite(tc)) return;
  const double limit = config_.time_step_safety * tc;
  if (config_.dt > limit) {
    std::ostringstream s;
    s.precision(6);
    s << "SimulationConfig: dt = " << config_.dt << " s is outside the valid range (0, " << limit
      << "] s: it exceeds time_step_safety (" << config_.time_step_safety << ") x the critical time "
      << tc << " s ("
      << (Model::NormalLaw::hertzian ? "Rayleigh time of the smallest particle"
                                     : "linear critical time of the lightest particle, linear_critical_time()")
      << "). Reduce dt, or set allow_large_time_step = true to override.";
    throw InvalidParameter(s.str());
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::check_rolling_time_step() const {
  if constexpr (kRollingDashpot) {
    if (config_.allow_large_time_step || !config_.check_rolling_stability) return;
    const RollingLimit r = rolling_stability_limit();
    std::ostringstream s;
    s.precision(6);
    if (r.contacts == 0 && step_ == 0) {
      // No contact yet: the a-priori bound of the materials and the smallest particles.
      const RollingEstimate e = rolling_limit_estimate();
      if (config_.dt <= e.limit) return;
      s << "SimulationConfig: dt = " << config_.dt << " s is outside the valid range (0, " << e.limit
        << "] s before the first step: the rolling spring-dashpot of material '" << materials_[e.material].name
        << "' against '" << materials_[e.partner].name << "' (rolling_damping eta_r = " << e.rolling_damping
        << ", smallest particle at the overlap " << e.overlap
        << " m that carries its weight) is stable only up to " << e.limit
        << " s even with this one contact (rolling_limit_estimate; a bed of contacts needs less). Reduce dt or "
           "rolling_damping (or the rolling stiffness), or set check_rolling_stability = false (or "
           "allow_large_time_step = true) to override.";
      throw InvalidParameter(s.str());
    }
    if (config_.dt <= r.limit) return;
    const auto& p = particles_;
    s << "SimulationConfig: dt = " << config_.dt << " s is outside the valid range (0, " << r.limit
      << "] s at step " << step_ << ": the rolling spring-dashpots of particle id " << p.id[r.particle]
      << " (" << r.contacts << " contacts, at (";
    for (int k = 0; k < D::dim; ++k) s << (k ? ", " : "") << p.x[r.particle][k];
    s << ") m, material '" << materials_[p.material[r.particle]].name << "', rolling_damping eta_r = "
      << materials_[p.material[r.particle]].rolling_damping << ") are guaranteed stable only up to " << r.limit
      << " s (rolling_stability_limit, a conservative bound). Reduce dt or rolling_damping, or set "
         "check_rolling_stability = false (or allow_large_time_step = true) to override.";
    throw InvalidParameter(s.str());
  }
}

}  // namespace granule
