#pragma once
// Simulation, part: state I/O. save_state writes the dynamic state (particles, ghosts, the
// neighbour list with its history, bodies, wall switches, time and its origin) through a writer;
// load_state_format reads every checkpoint format still accepted, checks all of it, and only
// then replaces the simulation's state (io/checkpoint.hpp adds the file, its header and the
// scene's materials around it).
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class W>
inline void Simulation<D, Model, Search, Integrator, Parallel>::save_state(W& w) {
  if (!initialised_ || !list_valid_) initialise();
  if constexpr (Parallel::distributed) {
    save_state_distributed(w);  // simulation/distributed.hpp
    return;
  }
  const auto& p = particles_;
  w.template pod<double>(time_);
  w.template pod<std::uint64_t>(step_);
  w.template pod<std::uint64_t>(next_id_);
  w.template pod<double>(config_.dt);
  w.template pod<double>(skin_used_);
  w.template pod<std::uint64_t>(p.owned());
  w.vec(p.x); w.vec(p.v); w.vec(p.f); w.vec(p.omega); w.vec(p.torque); w.vec(p.radius);
  w.vec(p.mass); w.vec(p.inv_mass); w.vec(p.inv_inertia); w.vec(p.material); w.vec(p.group);
  w.vec(p.id); w.vec(p.motion); w.vec(p.image); w.vec(p.ghost_owner); w.vec(p.ghost_shift);
  list_.save(w);
  save_state_tail(w);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class W>
inline void Simulation<D, Model, Search, Integrator, Parallel>::save_state_tail(W& w) const {
  w.template pod<std::uint64_t>(bodies_.size());
  for (const auto& b : bodies_) {
    w.template pod<typename D::Mat>(b.pose.rotation());
    w.template pod<Vec>(b.pose.translation());
    w.template pod<Vec>(b.force);
    w.template pod<AngVec>(b.torque);
    w.template pod<double>(b.work);
    w.template pod<Vec>(b.displacement_since_build);
    w.template pod<double>(b.rotation_since_build);
  }
  w.template pod<std::uint64_t>(materials_.size());
  w.template pod<std::uint64_t>(walls_.size());
  for (const auto& wl : walls_) {
    w.template pod<std::uint8_t>(wl.active ? 1 : 0);
    w.template pod<Vec>(wl.force);
    w.template pod<AngVec>(wl.torque);
  }
  w.vec(group_motion_);
  w.template pod<double>(time_origin_);
  w.template pod<std::uint64_t>(step_origin_);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class R>
inline void Simulation<D, Model, Search, Integrator, Parallel>::load_state(R& r, bool wall_states) {
  load_state_format(r, wall_states ? kStateFormat : 3);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class R>
inline void Simulation<D, Model, Search, Integrator, Parallel>::load_state_format(R& r, std::uint32_t format, bool whole) {
  require(format >= 3 && format <= kStateFormat, "Simulation::load_state_format", "format", format,
          "[3, " + std::to_string(kStateFormat) + "]");
  const double time = r.template pod<double>();
  const auto step = r.template pod<std::uint64_t>();
  const auto next_id = r.template pod<std::uint64_t>();
  const double dt = r.template pod<double>();
  if (dt != config_.dt)
    r.fail("time step " + detail::to_text(dt) + " s differs from the scene's " + detail::to_text(config_.dt) + " s");
  const double skin = r.template pod<double>();
  const auto owned = r.template pod<std::uint64_t>();
  ParticleStore<D> p;
  r.vec(p.x); r.vec(p.v); r.vec(p.f); r.vec(p.omega); r.vec(p.torque); r.vec(p.radius);
  r.vec(p.mass); r.vec(p.inv_mass); r.vec(p.inv_inertia); r.vec(p.material); r.vec(p.group);
  r.vec(p.id); r.vec(p.motion); r.vec(p.image); r.vec(p.ghost_owner); r.vec(p.ghost_shift);
  List list;
  list.read_saved(r);
  const auto nb = r.template pod<std::uint64_t>();
  if (nb != bodies_.size())
    r.fail("it has " + std::to_string(nb) + " bodies, the scene " + std::to_string(bodies_.size()));
  struct BodyState {
    typename D::Mat rotation;
    Vec translation, force;
    AngVec torque;
    double work;
    Vec displacement;
    double rotation_since_build;
  };
  std::vector<BodyState> bs(bodies_.size());
  for (auto& b : bs) {
    b.rotation = r.template pod<typename D::Mat>();
    b.translation = r.template pod<Vec>();
    b.force = r.template pod<Vec>();
    b.torque = r.template pod<AngVec>();
    b.work = r.template pod<double>();
    b.displacement = r.template pod<Vec>();
    b.rotation_since_build = r.template pod<double>();
  }
  const auto nm = r.template pod<std::uint64_t>();
  const auto nw = r.template pod<std::uint64_t>();
  if (nm != materials_.size() || nw != walls_.size())
    r.fail("it has " + std::to_string(nm) + " materials and " + std::to_string(nw) +
           " walls, the scene " + std::to_string(materials_.size()) + " and " + std::to_string(walls_.size()));
  struct WallState {
    bool active = true;
    Vec force = Vec::Zero();
    AngVec torque = D::zero_ang();
  };
  std::vector<WallState> ws(walls_.size());
  if (format >= 4)
    for (auto& wl : ws) {
      wl.active = r.template pod<std::uint8_t>() != 0;
      wl.force = r.template pod<Vec>();
      wl.torque = r.template pod<AngVec>();
    }
  std::vector<Motion> modes;
  r.vec(modes);
  double time_origin = time;
  std::uint64_t step_origin = step;
  if (format >= 5) {
    time_origin = r.template pod<double>();
    step_origin = r.template pod<std::uint64_t>();
  }
  if constexpr (requires { r.size(); })
    if (whole && r.position() != r.size()) r.fail("unexpected trailing data");

  // ---- checks (nothing of this simulation has changed yet) ----
  const auto bad = [&](const std::string& why) { r.fail(why); };
  if (!std::isfinite(time) || !std::isfinite(time_origin) || step_origin > step)
    bad("its time " + detail::to_text(time) + " s (origin " + detail::to_text(time_origin) + " s at step " +
        std::to_string(step_origin) + " of " + std::to_string(step) + ") is not a finite time");
  if (!(std::isfinite(skin) && skin >= 0.0))
    bad("its neighbour skin " + detail::to_text(skin) + " m is not in [0, inf)");
  const std::size_t slots = p.x.size();
  if (owned > slots)
    bad("it declares " + std::to_string(owned) + " particles but holds arrays of " + std::to_string(slots));
  const auto same = [&](std::size_t got, const char* what, std::size_t want) {
    if (got != want)
      bad(std::string("its array '") + what + "' has " + std::to_string(got) + " values, not " +
          std::to_string(want));
  };
  same(p.v.size(), "v", slots); same(p.f.size(), "f", slots); same(p.omega.size(), "omega", slots);
  same(p.torque.size(), "torque", slots); same(p.radius.size(), "radius", slots);
  same(p.mass.size(), "mass", slots); same(p.inv_mass.size(), "inv_mass", slots);
  same(p.inv_inertia.size(), "inv_inertia", slots); same(p.material.size(), "material", slots);
  same(p.group.size(), "group", slots); same(p.id.size(), "id", slots); same(p.motion.size(), "motion", slots);
  same(p.image.size(), "image", slots); same(p.ghost_owner.size(), "ghost_owner", slots - owned);
  same(p.ghost_shift.size(), "ghost_shift", slots - owned);
  p.set_owned(static_cast<std::size_t>(owned));
  const std::size_t groups = std::max(group_motion_.size(), modes.size());
  for (std::size_t i = 0; i < slots; ++i) {
    const auto at = [&](const std::string& what, double value) {
      bad("particle slot " + std::to_string(i) + " (id " + std::to_string(p.id[i]) + "): " + what + " " +
          detail::to_text(value));
    };
    for (int k = 0; k < D::dim; ++k) {
      if (!std::isfinite(p.x[i][k])) at("x[" + std::to_string(k) + "] =", p.x[i][k]);
      if (!std::isfinite(p.v[i][k])) at("v[" + std::to_string(k) + "] =", p.v[i][k]);
      if (!std::isfinite(p.f[i][k])) at("f[" + std::to_string(k) + "] =", p.f[i][k]);
    }
    for (int k = 0; k < D::rot_dim; ++k) {
      const double w = D::component(p.omega[i], k), t = D::component(p.torque[i], k);
      if (!std::isfinite(w)) at("omega[" + std::to_string(k) + "] =", w);
      if (!std::isfinite(t)) at("torque[" + std::to_string(k) + "] =", t);
    }
    if (!(p.radius[i] > 0.0 && std::isfinite(p.radius[i]))) at("radius =", p.radius[i]);
    if (!(p.mass[i] > 0.0 && std::isfinite(p.mass[i]))) at("mass =", p.mass[i]);
    if (!(p.inv_mass[i] >= 0.0 && std::isfinite(p.inv_mass[i]))) at("inv_mass =", p.inv_mass[i]);
    if (!(p.inv_inertia[i] >= 0.0 && std::isfinite(p.inv_inertia[i]))) at("inv_inertia =", p.inv_inertia[i]);
    if (p.material[i] >= materials_.size() || wall_material_[p.material[i]])
      at("material index", p.material[i]);
    const auto mode = static_cast<std::uint8_t>(p.motion[i]);
    if (mode > static_cast<std::uint8_t>(Motion::Prescribed)) at("motion mode", mode);
    // (A prescribed particle takes its group's velocity: the group must exist.)
    if (p.motion[i] == Motion::Prescribed && p.group[i] >= groups) at("prescribed, in group", p.group[i]);
    if (i >= owned && p.ghost_owner[i - owned] >= owned) at("ghost of slot", p.ghost_owner[i - owned]);
  }
  for (std::size_t i = 0; i < owned; ++i)
    if (p.id[i] >= next_id)
      bad("particle slot " + std::to_string(i) + " has id " + std::to_string(p.id[i]) + ", not below the next id " +
          std::to_string(next_id));
  if (auto why = list.check_loaded(p.owned(), slots, walls_.size()); !why.empty()) bad(why);
  for (std::size_t k = 0; k < bs.size(); ++k) {
    const BodyState& b = bs[k];
    bool finite = b.rotation.allFinite() && b.translation.allFinite() && b.force.allFinite() &&
                  b.displacement.allFinite() && std::isfinite(b.work) && std::isfinite(b.rotation_since_build);
    for (int c = 0; c < D::rot_dim; ++c) finite = finite && std::isfinite(D::component(b.torque, c));
    if (!finite) bad("body " + std::to_string(k) + " has a value that is not finite");
  }
  for (std::size_t k = 0; k < ws.size(); ++k) {
    bool finite = ws[k].force.allFinite();
    for (int c = 0; c < D::rot_dim; ++c) finite = finite && std::isfinite(D::component(ws[k].torque, c));
    if (!finite) bad("wall " + std::to_string(k) + " has a force or torque that is not finite");
  }
  for (std::size_t g = 0; g < modes.size(); ++g) {
    const Motion scene = g < group_motion_.size() ? group_motion_[g] : Motion::Free;
    if (modes[g] != scene) bad("group " + std::to_string(g) + " has a different motion mode than in the scene");
  }

  // ---- commit ----
  time_ = time;
  step_ = step;
  next_id_ = next_id;
  skin_used_ = skin;
  time_origin_ = time_origin;
  step_origin_ = step_origin;
  particles_ = std::move(p);
  list_.take_loaded(list);
  for (std::size_t k = 0; k < bs.size(); ++k) {
    Body<D>& b = bodies_[k];
    b.pose = geometry::Pose<D>(bs[k].rotation, bs[k].translation);
    b.force = bs[k].force;
    b.torque = bs[k].torque;
    b.work = bs[k].work;
    b.displacement_since_build = bs[k].displacement;
    b.rotation_since_build = bs[k].rotation_since_build;
    b.set_velocities(time_);
  }
  // (The list read above lists the walls active when it was written; the scene's switches
  // follow the checkpoint.)
  for (std::size_t k = 0; k < ws.size(); ++k) {
    walls_[k].active = ws[k].active;
    walls_[k].force = ws[k].force;
    walls_[k].torque = ws[k].torque;
  }
  if (!modes.empty()) group_mode_resize(static_cast<std::uint32_t>(modes.size() - 1));
  wall_touched_.assign(list_.wall.size(), 0);
  parallel_ = particles_.owned() >= kParallelMinParticles;
  update_group_velocities(time_);
  list_valid_ = true;
  initialised_ = true;
  forces_ready_ = true;
  if constexpr (Parallel::distributed) {
    // Every rank holds the whole state now: the first step's rebuild (no build positions, so
    // the drift test asks for one) re-decomposes it for this rank count and each rank keeps its
    // own particles, their histories carried by key from the list just read (docs/mpi.md).
    list_.x_at_build.clear();
    dist_.decomposition.reset();
  }
}

}  // namespace granule
