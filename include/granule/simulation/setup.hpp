#pragma once
// Simulation, part: set-up. Materials and pair overrides, particles (with the checks that
// refuse one that cannot fit or pokes through a wall), bodies, walls and their switches, groups
// and their motion modes, removal, and observers.
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::set_pair(std::uint32_t a, std::uint32_t b, const PairOverride& o) {
  const std::string where = "Simulation::set_pair";
  const std::string range = "[0, " + std::to_string(materials_.size()) + ") (add_material first)";
  require(a < materials_.size(), where, "a", a, range);
  require(b < materials_.size(), where, "b", b, range);
  require(!(wall_material_[a] && wall_material_[b]), where, "b", b,
          "a particle material (a and b are both wall materials, which never touch)");
  materials_.set_pair(a, b, o, where);
  refresh_params();
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline std::uint64_t Simulation<D, Model, Search, Integrator, Parallel>::add_particle(const Vec& x, double radius, std::uint32_t material, const Vec& v, std::uint32_t group, const AngVec& omega) {
  const std::string where = "Simulation::add_particle";
  require(radius > 0.0 && std::isfinite(radius), where, "radius", radius, "(0, inf) m");
  require(material < materials_.size(), where, "material", material,
          "[0, " + std::to_string(materials_.size()) + ") (add_material first)");
  require(!wall_material_[material], where, "material", material, "a particle material (this one is a wall material)");
  for (int k = 0; k < D::dim; ++k) {
    require(std::isfinite(x[k]), where, "x[" + std::to_string(k) + "]", x[k], "finite");
    require(std::isfinite(v[k]), where, "v[" + std::to_string(k) + "]", v[k], "finite");
    if (!config_.domain.periodic[k])
      require(x[k] >= config_.domain.lo[k] && x[k] <= config_.domain.hi[k], where,
              "x[" + std::to_string(k) + "]", x[k],
              "[" + detail::to_text(config_.domain.lo[k]) + ", " + detail::to_text(config_.domain.hi[k]) +
                  "] m (inside the non-periodic domain)");
  }
  for (int k = 0; k < D::rot_dim; ++k) {
    const double w = D::component(omega, k);
    require(std::isfinite(w), where, "omega[" + std::to_string(k) + "]", w, "finite");
  }
  check_insertion(x, radius, where);
  list_.detach(particles_);  // the slots the rows name change here
  particles_.clear_ghosts();
  const double m = materials_[material].density * D::volume(radius, config_.thickness);
  const std::uint64_t id = next_id_++;
  if constexpr (Parallel::distributed) {
    // After the first build every rank makes this call (the same scene script) and only the
    // rank whose region holds x keeps the particle; the next rebuild checks that the ranks
    // added alike (simulation/distributed.hpp, docs/mpi.md).
    if (dist_.decomposition && dist_.decomposition->owner(x) != dist_.rank()) {
      list_valid_ = false;
      return id;
    }
  }
  const std::size_t slot = particles_.add(x, v, radius, m, material, group, id);
  particles_.omega[slot] = omega;
  apply_group_motion(slot);
  list_valid_ = false;
  return id;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline std::uint32_t Simulation<D, Model, Search, Integrator, Parallel>::add_body(const Body<D>& b) {
  bodies_.push_back(b);
  bodies_.back().set_velocities(time_);
  list_valid_ = false;
  return static_cast<std::uint32_t>(bodies_.size() - 1);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Shape>
inline std::uint32_t Simulation<D, Model, Search, Integrator, Parallel>::add_wall(const Shape& shape, std::uint32_t material, std::uint32_t body) {
  require(material < materials_.size(), "Simulation::add_wall", "material", material,
          "[0, " + std::to_string(materials_.size()) + ")");
  require(body < bodies_.size(), "Simulation::add_wall", "body", body,
          "[0, " + std::to_string(bodies_.size()) + ")");
  walls_.push_back(Wall<D>{typename WallShapes<D>::type(shape), material, body});
  list_valid_ = false;
  return static_cast<std::uint32_t>(walls_.size() - 1);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::set_wall_active(std::uint32_t w, bool active) {
  require(w < walls_.size(), "Simulation::set_wall_active", "wall", w,
          "[0, " + std::to_string(walls_.size()) + ")");
  if (walls_[w].active == active) return;  // no rebuild: the run stays as it was
  walls_[w].active = active;
  list_valid_ = false;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::prescribe_group_velocity(std::uint32_t group, std::function<Vec(double)> velocity) {
  require(static_cast<bool>(velocity), "Simulation::prescribe_group_velocity", "velocity", 0.0,
          "a callable of time");
  set_group_motion(group, Motion::Prescribed, std::move(velocity));
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::set_group_motion(std::uint32_t group, Motion mode,
                                                                        std::function<Vec(double)> velocity) {
  list_valid_ = false;  // which pairs exist depends on the motion modes
  group_mode_resize(group);
  group_motion_[group] = mode;
  group_velocity_[group] = std::move(velocity);
  for (std::size_t i = 0; i < particles_.owned(); ++i)
    if (particles_.group[i] == group) apply_group_motion(i);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Pred>
inline void Simulation<D, Model, Search, Integrator, Parallel>::assign_group(std::uint32_t group, Pred&& pred) {
  group_mode_resize(group);
  list_valid_ = false;
  for (std::size_t i = 0; i < particles_.owned(); ++i)
    if (pred(i)) {
      particles_.group[i] = group;
      apply_group_motion(i);
    }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Pred>
inline std::size_t Simulation<D, Model, Search, Integrator, Parallel>::remove_particles(Pred&& pred) {
  list_.detach(particles_);  // the slots the rows name change here
  particles_.clear_ghosts();
  std::vector<bool> keep(particles_.owned());
  std::size_t removed = 0;
  for (std::size_t i = 0; i < particles_.owned(); ++i) {
    keep[i] = !pred(i);
    removed += !keep[i];
  }
  particles_.remove_if_not(keep);
  list_valid_ = false;
  if (removed > 0) {
    records_.clear();
    records_step_ = std::numeric_limits<std::uint64_t>::max();
  }
  if constexpr (Parallel::distributed) {
    // After the first build each rank removes of its own particles: counted for the next
    // rebuild's check, and the count over the ranks returned (collective).
    if (dist_.decomposition) {
      dist_.removed_since_build += removed;
      return static_cast<std::size_t>(dist_.sum(static_cast<std::uint64_t>(removed)));
    }
  }
  return removed;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::every(std::uint64_t n, std::function<void(Simulation&)> f, bool needs_contacts) {
  require(n > 0, "Simulation::every", "n", static_cast<double>(n), "[1, inf)");
  observers_.push_back({n, std::move(f), needs_contacts});
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::check_insertion(const Vec& x, double radius, const std::string& where) const {
  for (int k = 0; k < D::dim; ++k) {
    if (config_.domain.periodic[k]) continue;  // (the list refuses a period shorter than the range)
    const double half = 0.5 * (config_.domain.hi[k] - config_.domain.lo[k]);
    require(radius <= half, where, "radius", radius,
            "(0, " + detail::to_text(half) + "] m (half the domain's width along axis " + std::to_string(k) +
                ": a larger particle does not fit in the box)");
  }
  const double allowed = config_.max_overlap_ratio * radius;
  for (std::uint32_t w = 0; w < walls_.size(); ++w) {
    if (!walls_[w].active) continue;
    double deepest = 0.0;
    walls_[w].for_each_contact(bodies_[walls_[w].body], x, radius, [&](const geometry::SurfacePoint<D>& sp) {
      deepest = std::max(deepest, sp.overlap(radius));
    });
    if (deepest > allowed) {
      std::ostringstream m;
      m.precision(17);
      m << where << ": the particle at x = (";
      for (int k = 0; k < D::dim; ++k) m << (k ? ", " : "") << x[k];
      m << ") m of radius " << radius << " m overlaps wall " << w << " by " << deepest
        << " m, more than max_overlap_ratio (" << config_.max_overlap_ratio << ") x radius = " << allowed
        << " m: it pokes through the wall";
      throw InvalidParameter(m.str());
    }
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline std::uint32_t Simulation<D, Model, Search, Integrator, Parallel>::add_material_impl(const Material& m, bool is_wall) {
  const std::uint32_t idx = materials_.add(m, is_wall);
  wall_material_.push_back(is_wall);
  refresh_params();
  return idx;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::refresh_params() {
  const std::size_t nm = materials_.size();
  params_.resize(nm * nm);
  for (std::uint32_t a = 0; a < nm; ++a)
    for (std::uint32_t b = 0; b < nm; ++b) params_[a * nm + b] = Model::make(materials_.pair(a, b), config_.thickness);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::group_mode_resize(std::uint32_t group) {
  if (group >= group_motion_.size()) {
    group_motion_.resize(group + 1, Motion::Free);
    group_velocity_.resize(group + 1);
    group_v_now_.resize(group + 1, Vec::Zero());
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::apply_group_motion(std::size_t i) {
  const std::uint32_t g = particles_.group[i];
  const Motion m = g < group_motion_.size() ? group_motion_[g] : Motion::Free;
  particles_.set_motion(i, m);
  if (m == Motion::Frozen) {
    particles_.v[i].setZero();
    particles_.omega[i] = D::zero_ang();
  }
  if (m == Motion::Prescribed) {
    particles_.v[i] = group_velocity_[g](time_);
    particles_.omega[i] = D::zero_ang();
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::update_group_velocities(double t) {
  for (std::size_t g = 0; g < group_velocity_.size(); ++g)
    if (group_velocity_[g]) group_v_now_[g] = group_velocity_[g](t);
}

}  // namespace granule
