#pragma once
// Simulation, part: contact geometry. The geometry of a particle pair or of a particle and a
// wall surface point (overlap, normal, lever arms, relative and damping velocities) as the
// contact laws see it, how far a formed tensile contact still reaches, and a walk over every
// contact that changes no history (for energies and the stability limit).
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
inline bool Simulation<D, Model, Search, Integrator, Parallel>::pair_geometry(std::size_t i, std::size_t j, contact::ContactGeometry<D>& g, double reach) const {
  const auto& p = particles_;
  const Vec d = p.x[i] - p.x[j];
  const double rs = p.radius[i] + p.radius[j];
  const double d2 = d.squaredNorm();
  if constexpr (Model::tensile) {
    if (d2 >= (rs + reach) * (rs + reach)) return false;
  } else {
    if (d2 >= rs * rs) return false;
  }
  const double dist = std::sqrt(d2);
  g.distance = dist;
  g.n = dist > 0.0 ? Vec(d / dist) : Vec(Vec::Unit(D::dim - 1));
  g.overlap = rs - dist;
  g.r_i = p.radius[i];
  g.r_j = p.radius[j];
  g.arm_i = g.r_i - 0.5 * g.overlap;
  g.arm_j = g.r_j - 0.5 * g.overlap;
  g.r_eff = g.r_i * g.r_j / rs;
  g.m_eff = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
  g.v_rel = p.v[i] - p.v[j] - (g.arm_i * D::cross(p.omega[i], g.n) + g.arm_j * D::cross(p.omega[j], g.n));
  g.vn = g.v_rel.dot(g.n);
  g.vt = g.v_rel - g.vn * g.n;
  g.omega_rel = p.omega[i] - p.omega[j];
  if constexpr (kPredictDamping) {
    const Vec vd = v_damp_[i] - v_damp_[j] -
                   (g.arm_i * D::cross(omega_damp_[i], g.n) + g.arm_j * D::cross(omega_damp_[j], g.n));
    g.vn_damp = vd.dot(g.n);
    g.vt_damp = vd - g.vn_damp * g.n;
    g.omega_rel_damp = omega_damp_[i] - omega_damp_[j];
  } else {
    g.damp_at_kinematic_velocity();
  }
  if constexpr (Model::needs_rolling_inertia) {
    const double k1 = D::inertia_factor + 1.0;
    g.i_roll = 1.0 / (p.inv_mass[i] / (k1 * g.r_i * g.r_i) + p.inv_mass[j] / (k1 * g.r_j * g.r_j));
  } else {
    g.i_roll = 0.0;
  }
  g.dt = setup_evaluation_ ? 0.0 : config_.dt;
  // Mean twist angle of the step about n (3D only; a disk pair has no twist).
  if constexpr (D::dim == 3 && Model::needs_twist) g.twist = 0.5 * (p.omega[i] + p.omega[j]).dot(g.n) * g.dt;
  return true;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline bool Simulation<D, Model, Search, Integrator, Parallel>::wall_geometry(std::size_t i, const geometry::SurfacePoint<D>& sp, const Body<D>& b, contact::ContactGeometry<D>& g, double reach) const {
  const auto& p = particles_;
  const double overlap = p.radius[i] - sp.distance;
  if constexpr (Model::tensile) {
    if (overlap <= -reach) return false;
  } else {
    if (overlap <= 0.0) return false;
  }
  g.n = sp.normal;
  g.overlap = overlap;
  g.distance = std::numeric_limits<double>::infinity();
  g.r_i = p.radius[i];
  g.r_j = std::numeric_limits<double>::infinity();
  g.arm_i = sp.distance;  // centre to the contact point on the wall surface
  g.arm_j = 0.0;
  g.r_eff = g.r_i;
  g.m_eff = p.mass[i];
  const Vec vw = b.point_velocity(sp.point);
  g.v_rel = p.v[i] - g.arm_i * D::cross(p.omega[i], g.n) - vw;
  g.vn = g.v_rel.dot(g.n);
  g.vt = g.v_rel - g.vn * g.n;
  g.omega_rel = p.omega[i] - b.current_angular_velocity;
  if constexpr (kPredictDamping) {
    const Vec vd = v_damp_[i] - g.arm_i * D::cross(omega_damp_[i], g.n) - vw;
    g.vn_damp = vd.dot(g.n);
    g.vt_damp = vd - g.vn_damp * g.n;
    g.omega_rel_damp = omega_damp_[i] - b.current_angular_velocity;
  } else {
    g.damp_at_kinematic_velocity();
  }
  if constexpr (Model::needs_rolling_inertia) {
    g.i_roll = (D::inertia_factor + 1.0) * p.mass[i] * g.r_i * g.r_i;
  } else {
    g.i_roll = 0.0;
  }
  g.dt = setup_evaluation_ ? 0.0 : config_.dt;
  if constexpr (D::dim == 3 && Model::needs_twist)
    g.twist = 0.5 * (p.omega[i] + b.current_angular_velocity).dot(g.n) * g.dt;
  return true;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::tensile_reach(const State* h, const Params& prm, std::size_t i, std::size_t j) const {
  if constexpr (Model::tensile) {
    if (h == nullptr || !h->contact.formed) return 0.0;
    const double ri = particles_.radius[i], rj = particles_.radius[j];
    return Model::pull_off_separation(prm, ri * rj / (ri + rj));
  } else {
    return 0.0;
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::tensile_wall_reach(const State* h, const Params& prm, std::size_t i) const {
  if constexpr (Model::tensile) {
    return h == nullptr || !h->contact.formed ? 0.0 : Model::pull_off_separation(prm, particles_.radius[i]);
  } else {
    return 0.0;
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::max_tensile_reach() const {
  double reach = 0.0;
  if constexpr (Model::tensile) {
    double r_max = 0.0;
    for (std::size_t i = 0; i < particles_.owned(); ++i) r_max = std::max(r_max, particles_.radius[i]);
    for (const Params& prm : params_) reach = std::max(reach, Model::pull_off_separation(prm, r_max));
  }
  return reach;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline auto Simulation<D, Model, Search, Integrator, Parallel>::pair_params(std::size_t i, std::size_t j) const -> const Params& {
  return params_[particles_.material[i] * materials_.size() + particles_.material[j]];
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class F>
inline void Simulation<D, Model, Search, Integrator, Parallel>::for_each_contact_geometry(F&& f) const {
  const auto& p = particles_;
  contact::ContactGeometry<D> g;
  static const State kEmpty{};
  // Row by row within each layer: an entry's history lives in its layer's pool.
  for (std::size_t l = 0; l < list_.layers(); ++l) {
    for (std::size_t i = list_.layer_begin[l]; i < list_.layer_begin[l + 1]; ++i) {
      for (std::uint32_t e = list_.row_begin[i]; e < list_.row_begin[i + 1]; ++e) {
        const std::uint32_t j = list_.nbr[e];
        const State* h = kHasState ? list_.history(l, e) : nullptr;
        if (!pair_geometry(i, j, g, tensile_reach(h, pair_params(i, j), i, j))) continue;
        f(g, pair_params(i, j), h ? *h : kEmpty, i, j, 0u);
      }
      for (std::uint32_t e = list_.wall_begin[i]; e < list_.wall_begin[i + 1]; ++e) {
        const auto we = list_.wall[e];
        const Wall<D>& w = walls_[we.wall];
        const Body<D>& b = bodies_[w.body];
        const Params& prm = params_[p.material[i] * materials_.size() + w.material];
        const double reach = tensile_wall_reach(list_.wall_state.empty() ? nullptr : &list_.wall_state[e], prm, i);
        w.for_each_contact(b, p.x[i], Model::tensile ? p.radius[i] + reach : p.radius[i], [&](const geometry::SurfacePoint<D>& sp) {
          if (sp.feature != we.feature || !wall_geometry(i, sp, b, g, reach)) return;
          const State& s = kHasState ? list_.wall_state[e] : kEmpty;
          f(g, prm, s, i, we.wall, 1u);
        });
      }
    }
  }
}

}  // namespace granule
