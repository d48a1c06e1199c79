#pragma once
// Simulation, part: the wall pass. Particle-wall contacts of the list's wall entries: entry by
// entry for the scalar pass (plane entries in closed form, other shapes through their surface
// points, grouped by feature), and queued W at a time for the packed law in the packed pass.
// Forces and torques go to the particle and, per layer, to the wall and its body.
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

// The walls of row i, one contact at a time: surface point, geometry, history slot, the
// overlap check, and the history of features no longer touched. `use(g, state, params, wall, sp)`
// evaluates each contact or queues it; state is null for a contact without a history slot (a
// feature the list has no entry for) and for models without history.
template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Use>
inline void Simulation<D, Model, Search, Integrator, Parallel>::for_each_wall_contact(std::size_t i, LayerAccumulator& acc, Use&& use) {
  for (std::uint32_t e = list_.wall_begin[i]; e < list_.wall_begin[i + 1]; ++e)
    wall_entry_contacts(i, e, acc, use);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Use>
inline void Simulation<D, Model, Search, Integrator, Parallel>::wall_entry_contacts(std::size_t i, std::uint32_t e, LayerAccumulator& acc, Use& use) {
  const std::uint32_t wall = list_.wall[e].wall;
  const Wall<D>& w = walls_[wall];
  if (const auto* plane = std::get_if<geometry::PlaneShape<D>>(&w.shape)) {
    plane_contact(i, e, *plane, w, acc, use);
  } else if (e == list_.wall_begin[i] || list_.wall[e - 1].wall != wall) {
    wall_group_contacts(i, e, acc, use);
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Use>
inline void Simulation<D, Model, Search, Integrator, Parallel>::wall_group_contacts(std::size_t i, std::uint32_t e, LayerAccumulator& acc, Use& use) {
  auto& p = particles_;
  const double max_ratio = config_.max_overlap_ratio;
  const std::uint32_t wall = list_.wall[e].wall;
  const std::uint32_t row_end = list_.wall_begin[i + 1];
  const Wall<D>& w = walls_[wall];
  const Body<D>& b = bodies_[w.body];
  const std::size_t prm = p.material[i] * materials_.size() + w.material;
  contact::ContactGeometry<D> g;
  // A tensile model looks for features to the pull-off separation (formed contacts hold there).
  double search = p.radius[i];
  if constexpr (Model::tensile) search += Model::pull_off_separation(params_[prm], p.radius[i]);
  w.for_each_contact(b, p.x[i], search, [&](const geometry::SurfacePoint<D>& sp) {
    // History slot of this feature among the row's entries for this wall.
    const auto find_slot = [&] {
      for (std::uint32_t k = e; k < row_end && list_.wall[k].wall == wall; ++k)
        if (list_.wall[k].feature == sp.feature) return k;
      return std::numeric_limits<std::uint32_t>::max();
    };
    std::uint32_t slot = std::numeric_limits<std::uint32_t>::max();
    if constexpr (Model::tensile) {
      slot = find_slot();
      const State* h = slot != std::numeric_limits<std::uint32_t>::max() ? &list_.wall_state[slot] : nullptr;
      if (!wall_geometry(i, sp, b, g, tensile_wall_reach(h, params_[prm], i))) return;
    } else {
      if (!wall_geometry(i, sp, b, g)) return;
      slot = find_slot();
    }
    if (slot == std::numeric_limits<std::uint32_t>::max()) ++acc.missing_wall_features;
    note_wall_overlap(i, wall, g, max_ratio, acc);
    State* state = nullptr;
    if (slot != std::numeric_limits<std::uint32_t>::max()) {
      if constexpr (kHasState) state = &list_.wall_state[slot];
      touched_mark(slot);
    }
    use(g, state, prm, wall, sp);
  });
  // Features of this wall not in contact this step lose their history.
  if constexpr (kHasState) {
    for (std::uint32_t k = e; k < row_end && list_.wall[k].wall == wall; ++k) {
      if (!touched_take(k)) list_.wall_state[k] = State{};
    }
  }
}

// The contact of row i with plane wall entry e (a plane has one feature, so one entry per
// row and its slot is e): wall_group_contacts without the shape dispatch, the slot search
// and the touch marks, in the same arithmetic (Wall::for_each_contact's pose transforms
// and PlaneShape::closest), so results are bitwise the same.
template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Use>
inline void Simulation<D, Model, Search, Integrator, Parallel>::plane_contact(std::size_t i, std::uint32_t e, const geometry::PlaneShape<D>& plane, const Wall<D>& w, LayerAccumulator& acc, Use& use) {
  auto& p = particles_;
  const Body<D>& b = bodies_[w.body];
  const geometry::SurfacePoint<D> sp = b.pose.to_world(plane.closest(b.pose.to_body(p.x[i])));
  contact::ContactGeometry<D> g;
  double reach = 0.0;
  if constexpr (Model::tensile) {
    reach = tensile_wall_reach(&list_.wall_state[e], params_[p.material[i] * materials_.size() + w.material], i);
  }
  if (!(sp.distance < (Model::tensile ? p.radius[i] + reach : p.radius[i])) || !wall_geometry(i, sp, b, g, reach)) {
    if constexpr (kHasState) list_.wall_state[e] = State{};
    return;
  }
  const std::uint32_t wall = list_.wall[e].wall;
  note_wall_overlap(i, wall, g, config_.max_overlap_ratio, acc);
  State* state = nullptr;
  if constexpr (kHasState) state = &list_.wall_state[e];
  use(g, state, p.material[i] * materials_.size() + w.material, wall, sp);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::note_wall_overlap(std::size_t i, std::uint32_t wall, const contact::ContactGeometry<D>& g, double max_ratio, LayerAccumulator& acc) const {
  if (g.overlap > max_ratio * g.r_i && acc.bad_row == std::numeric_limits<std::size_t>::max()) {
    acc.bad_row = i;
    acc.bad_partner = wall;
    acc.bad_overlap = g.overlap;
    acc.bad_wall = true;
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <bool Record>
inline void Simulation<D, Model, Search, Integrator, Parallel>::wall_contacts(std::size_t i, LayerAccumulator& acc, Vec& fi, AngVec& ti) {
  for_each_wall_contact(i, acc, [&](const contact::ContactGeometry<D>& g, State* state, std::size_t prm,
                                    std::uint32_t wall, const geometry::SurfacePoint<D>& sp) {
    const Wall<D>& w = walls_[wall];
    State tmp{};
    const contact::ContactForce<D> cf = Model::evaluate(params_[prm], g, state != nullptr ? *state : tmp);
    fi += cf.force;
    ti += cf.torque_i;
    acc.body_force[w.body] -= cf.force;
    const Vec arm = sp.point - bodies_[w.body].pose.translation();
    const AngVec t = D::cross(arm, cf.force);
    acc.body_torque[w.body] -= t;
    acc.wall_force[wall] -= cf.force;
    acc.wall_torque[wall] -= t;
    ++acc.contacts;
    if constexpr (Record) {
      const auto& p = particles_;
      analysis::ContactRecord<D> r;
      r.i = static_cast<std::uint32_t>(i);
      r.wall = wall;
      r.normal = g.n;
      r.branch = sp.point - p.x[i];
      r.contact_point = sp.point;
      r.overlap = g.overlap;
      r.fn = cf.fn;
      r.ft = cf.ft;
      r.mu = materials_.pair(p.material[i], w.material).mu_s;
      acc.records.push_back(r);
    }
  });
}

// The wall contacts of rows r0..r1 into the queue, in entry order: entry by entry through
// the list's wall_row (most rows have no wall entries, and looking for those that do cost
// about 1 % of scene B).
template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::queue_wall_contacts(std::size_t r0, std::size_t r1, LayerAccumulator& acc, WallQueue& q) {
  std::uint32_t row = 0;
  const auto queue = [&](const contact::ContactGeometry<D>& g, State* state, std::size_t prm,
                         std::uint32_t wall, const geometry::SurfacePoint<D>& sp) {
    const std::uint32_t body = walls_[wall].body;
    if (q.count > 0 && prm != q.params) flush_wall_queue(q, acc);
    const std::size_t l = q.count++;
    q.params = prm;
    q.lanes.set(l, g);
    if (state == nullptr) {
      q.scratch[l] = State{};
      state = &q.scratch[l];
    }
    q.state[l] = state;
    q.i[l] = row;
    q.wall[l] = wall;
    q.arm[l] = sp.point - bodies_[body].pose.translation();
    if (q.count == lane_width) flush_wall_queue(q, acc);
  };
  const std::uint32_t e1 = list_.wall_begin[r1];
  for (std::uint32_t e = list_.wall_begin[r0]; e < e1; ++e) {
    row = list_.wall_row[e];
    wall_entry_contacts(row, e, acc, queue);
  }
}

// The packed law for the queued wall contacts; forces and torques to the particles and bodies
// in queue order. (One out-of-line copy: inlined at its three calls into the flattened pair
// loop it made scene A 5 % slower.)
template <class D, class Model, class Search, class Integrator, class Parallel>
[[gnu::noinline]] GRANULE_FLATTEN void Simulation<D, Model, Search, Integrator, Parallel>::flush_wall_queue(WallQueue& q, LayerAccumulator& acc) {
  if constexpr (kPackable && D::dim == 3) {
    using LD = Dim3Lanes;
    using PackedState = typename Model::template State<LD>;
    const std::size_t n = q.count;
    if (n == 0) return;
    for (std::size_t l = n; l < lane_width; ++l) {  // padding: copies of the last contact
      q.lanes.copy_lane(n - 1, l);
      q.state[l] = q.state[n - 1];
    }
    const contact::ContactGeometry<LD> g = q.lanes.packed();
    PackedState s{};
    if constexpr (kHasState) contact::PackedState<State, PackedState>::load(s, q.state);
    const contact::ContactForce<LD> cf = Model::evaluate(params_[q.params], g, s);
    if constexpr (kHasState) contact::PackedState<State, PackedState>::store(s, q.state, n);
    alignas(64) double out[6][lane_width];
    const Lane* parts[6] = {&cf.force.x, &cf.force.y, &cf.force.z, &cf.torque_i.x, &cf.torque_i.y, &cf.torque_i.z};
    for (std::size_t k = 0; k < 6; ++k) parts[k]->copy_to(out[k], stdx::vector_aligned);
    auto& p = particles_;
    for (std::size_t l = 0; l < n; ++l) {
      const Vec f(out[0][l], out[1][l], out[2][l]);
      p.f[q.i[l]] += f;
      p.torque[q.i[l]] += AngVec(out[3][l], out[4][l], out[5][l]);
      const std::uint32_t body = walls_[q.wall[l]].body;
      const AngVec t = D::cross(q.arm[l], f);
      acc.body_force[body] -= f;
      acc.body_torque[body] -= t;
      acc.wall_force[q.wall[l]] -= f;
      acc.wall_torque[q.wall[l]] -= t;
    }
    acc.contacts += n;
    q.count = 0;
  }
}

// The wall contacts of rows r0..r1 one at a time, in entry order (2D: a disk bed has few wall
// contacts, and the packed wall law is written for 3D geometries, contact::GeometryLanes).
template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::wall_contacts_by_entry(std::size_t r0, std::size_t r1, LayerAccumulator& acc) {
  auto& p = particles_;
  std::uint32_t row = 0;
  const auto use = [&](const contact::ContactGeometry<D>& g, State* state, std::size_t prm, std::uint32_t wall,
                       const geometry::SurfacePoint<D>& sp) {
    const std::uint32_t body = walls_[wall].body;
    State tmp{};
    const contact::ContactForce<D> cf = Model::evaluate(params_[prm], g, state != nullptr ? *state : tmp);
    p.f[row] += cf.force;
    p.torque[row] += cf.torque_i;
    const AngVec t = D::cross(Vec(sp.point - bodies_[body].pose.translation()), cf.force);
    acc.body_force[body] -= cf.force;
    acc.body_torque[body] -= t;
    acc.wall_force[wall] -= cf.force;
    acc.wall_torque[wall] -= t;
    ++acc.contacts;
  };
  const std::uint32_t e1 = list_.wall_begin[r1];
  for (std::uint32_t e = list_.wall_begin[r0]; e < e1; ++e) {
    row = list_.wall_row[e];
    wall_entry_contacts(row, e, acc, use);
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline bool Simulation<D, Model, Search, Integrator, Parallel>::touched_take(std::uint32_t k) {
  if (k >= wall_touched_.size()) return false;
  const bool t = wall_touched_[k] != 0;
  wall_touched_[k] = 0;
  return t;
}

}  // namespace granule
