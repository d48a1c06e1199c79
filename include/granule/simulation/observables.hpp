#pragma once
// Simulation, part: observables. Energies (kinetic, gravitational, elastic in the contacts),
// the analysis frame, the memory held, and the lookup of a particle by its id.
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
inline std::size_t Simulation<D, Model, Search, Integrator, Parallel>::index_of(std::uint64_t id) const {
  for (std::size_t i = 0; i < particles_.owned(); ++i)
    if (particles_.id[i] == id) return i;
  throw InvalidParameter("Simulation::index_of: id = " + std::to_string(id) + " is not a particle");
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < particles_.owned(); ++i) {
    const double m = particles_.mass[i];
    const double inertia = D::inertia_factor * m * particles_.radius[i] * particles_.radius[i];
    e += 0.5 * m * particles_.v[i].squaredNorm() + 0.5 * inertia * D::squared_norm(particles_.omega[i]);
  }
  if constexpr (Parallel::distributed) e = over_ranks(e);
  return e;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::gravitational_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < particles_.owned(); ++i) e -= particles_.mass[i] * config_.gravity.dot(particles_.x[i]);
  if constexpr (Parallel::distributed) e = over_ranks(e);
  return e;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::elastic_energy() {
  if (!initialised_ || !list_valid_) initialise();
  double e = 0.0;
  for_each_contact_geometry([&](const contact::ContactGeometry<D>& g, const Params& prm, const State& s,
                                std::size_t i, std::uint32_t j, std::uint32_t wall) {
    if constexpr (Parallel::distributed)
      if (wall == 0 && counted_elsewhere(i, j)) return;
    e += Model::stored_energy(prm, g, s);
  });
  if constexpr (Parallel::distributed) e = over_ranks(e);
  return e;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline analysis::Frame<D> Simulation<D, Model, Search, Integrator, Parallel>::frame() const {
  analysis::Frame<D> fr;
  const std::size_t n = particles_.owned();
  fr.time = time_;
  fr.thickness = config_.thickness;
  fr.x.assign(particles_.x.begin(), particles_.x.begin() + n);
  fr.v.assign(particles_.v.begin(), particles_.v.begin() + n);
  fr.omega.assign(particles_.omega.begin(), particles_.omega.begin() + n);
  fr.radius.assign(particles_.radius.begin(), particles_.radius.begin() + n);
  fr.mass.assign(particles_.mass.begin(), particles_.mass.begin() + n);
  fr.id.assign(particles_.id.begin(), particles_.id.begin() + n);
  fr.group.assign(particles_.group.begin(), particles_.group.begin() + n);
  fr.force.assign(particles_.f.begin(), particles_.f.begin() + n);
  fr.torque.assign(particles_.torque.begin(), particles_.torque.begin() + n);
  if (records_step_ == step_) fr.contacts = records_;
  fr.box_lo = config_.domain.lo;
  fr.box_hi = config_.domain.hi;
  fr.periodic = config_.domain.periodic;
  return fr;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline std::size_t Simulation<D, Model, Search, Integrator, Parallel>::memory_bytes() const {
  const auto& p = particles_;
  const std::size_t per = 5 * sizeof(Vec) + 2 * sizeof(AngVec) + 4 * sizeof(double) + 2 * 4 + 8 + 1 +
                          sizeof(typename ParticleStore<D>::Image);
  std::size_t work = v_damp_.capacity() * sizeof(Vec) + omega_damp_.capacity() * sizeof(AngVec);
  for (const auto& w : pair_work_) {
    work += (w.entries.capacity() + w.rows.capacity()) * sizeof(std::uint32_t);
    work += (w.separation[0].capacity() + w.separation[1].capacity()) * sizeof(double);
  }
  work += pair_constants_.capacity() * sizeof(contact::PairConstants) + pair_reach_.capacity() * sizeof(double) +
          entry_row_.capacity() * sizeof(std::uint32_t) + disk_records_.capacity() * sizeof(contact::DiskRecord);
  return p.x.capacity() * per + list_.memory_bytes() + work;
}

}  // namespace granule
