#pragma once
// Simulation, part: the force pass over pairs. compute_forces resets the forces, runs the layers
// of the cell list in three colours (one thread per contiguous range of a colour's layers), and
// sums the per-layer accumulators in layer order; process_layer is the one-at-a-time loop (and
// the recording one), process_layer_packed the SIMD one: touching entries gathered into chunks,
// each chunk's laws evaluated W pairs at a time (contact/packed.hpp), with prefetch of the next
// layer. Each calls the wall pass for its rows.
// Included by granule/simulation.hpp at its end: include that header, not this one.

namespace granule {

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::compute_forces(bool record, bool owned_reset, bool check_finite) {
  auto& p = particles_;
  const std::size_t n = p.owned();
  const std::size_t m = p.size();
  const std::size_t nb = bodies_.size();
  const std::size_t nw = walls_.size();
  if constexpr (kPredictDamping) predict_damping_velocities();
  const auto reset = [&](std::size_t i) {
    p.f[i] = (i < n && p.motion[i] == Motion::Free) ? Vec(p.mass[i] * config_.gravity) : Vec(Vec::Zero());
    p.torque[i] = D::zero_ang();
  };
  if (parallel_ && !owned_reset) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < m; ++i) reset(i);
  } else {
    // After step()'s first pass only the ghosts are left: too few to pay for a barrier. (Not a
    // parallel region switched off by an `if` clause: that still enters the OpenMP runtime,
    // ~4000 cycles a step, 2 % of the 1600-disk 2D step on a Zen 3.)
    for (std::size_t i = owned_reset ? n : 0; i < m; ++i) reset(i);
  }
  const std::size_t nl = list_.layers();
  layer_acc_.resize(nl);
#ifdef _OPENMP
  pair_work_.resize(static_cast<std::size_t>(omp_get_max_threads()));
#else
  pair_work_.resize(1);
#endif
  // Only the layers that hold rows are reset, processed and summed: a layer without rows has
  // no pair or wall entries. (A tall box has many: paper 002's 2D bed fills 33 of 175 layers,
  // and the others' upkeep cost 36 instructions per disk-step, 8 % of the step.) The reads below
  // skip the same layers, so an emptied layer's old sums are never seen.
  const auto& layer_begin = list_.layer_begin;
  const auto filled = [&](std::size_t l) { return layer_begin[l] != layer_begin[l + 1]; };
  for (std::size_t l = 0; l < nl; ++l) {
    if (!filled(l)) continue;
    auto& a = layer_acc_[l];
    a.contacts = 0;
    a.bad_row = std::numeric_limits<std::size_t>::max();
    a.missing_wall_features = 0;
    a.body_force.assign(nb, Vec::Zero());
    a.body_torque.assign(nb, D::zero_ang());
    a.wall_force.assign(nw, Vec::Zero());
    a.wall_torque.assign(nw, D::zero_ang());
    a.records.clear();
  }
  if constexpr (kPairConstants)
    if (!record && config_.packed_contacts) update_pair_constants();
  if constexpr (kPackable && D::dim == 2) {
    if (!record && config_.packed_contacts) {
      disk_records_.resize(m);
      // (Blocks of 1024 particles, a multiple of every lane width: copies, so no order matters.)
      const std::size_t blocks = (m + 1023) / 1024;
      const auto fill = [&](std::size_t b) {
        const std::size_t a = 1024 * b, e = std::min(m, a + 1024);
        contact::fill_disk_records(scalars(p.v) + 2 * a, p.omega.data() + a, p.radius.data() + a, e - a,
                                   disk_records_.data() + a);
      };
      if (parallel_) {
#pragma omp parallel for schedule(static)
        for (std::size_t b = 0; b < blocks; ++b) fill(b);
      } else {
        for (std::size_t b = 0; b < blocks; ++b) fill(b);
      }
    }
  }
  const bool parallel = Search::uses_cells;
  // Three colours: layers l and l + 3 never touch the same particle or ghost. Each thread
  // takes one contiguous range of a colour's layers (static schedule), so that it works on
  // the same particles in every colour and in the kick passes (particles are sorted by
  // layer): with layers handed out one at a time (dynamic) the particles' cache lines moved
  // between the cores at every phase, and two threads ran 1.1-1.4x one thread on a VM whose
  // cores are far apart (docs/performance.md, "Two threads").
  // The ranges hold about equal work (pair entries and rows), not equal numbers of layers:
  // the layers run along the domain's longest axis, and a bed in a tall box left the thread
  // that got the layers above it idle (the two-rod study ran its pair loop on one thread).
  // Which thread takes a layer does not change the result.
  const auto& row_begin = list_.row_begin;
  auto layer_work = [&](std::size_t l) -> std::uint64_t {
    return std::uint64_t(row_begin[layer_begin[l + 1]] - row_begin[layer_begin[l]]) +
           (layer_begin[l + 1] - layer_begin[l]);
  };
  const auto process = [&](std::size_t l) {
    if (record) {
      process_layer<true>(l);
    } else if (kPackable && config_.packed_contacts) {
      process_layer_packed(l);
    } else {
      process_layer<false>(l);
    }
  };
  // One thread: the same layers in the same order, without the parallel regions and the work
  // split (both cost 3-4 % of a 1600-disk 2D step).
  const bool threaded = parallel && parallel_;
  for (std::size_t colour = 0; colour < 3 && !threaded; ++colour)
    for (std::size_t l = colour; l < nl; l += 3)
      if (filled(l)) process(l);
  for (std::size_t colour = 0; colour < 3 && threaded; ++colour) {
    const std::size_t count = nl > colour ? (nl - colour + 2) / 3 : 0;
#pragma omp parallel
    {
#ifdef _OPENMP
      const std::uint64_t thread = static_cast<std::uint64_t>(omp_get_thread_num());
      const std::uint64_t threads = static_cast<std::uint64_t>(omp_get_num_threads());
#else
      const std::uint64_t thread = 0, threads = 1;
#endif
      std::uint64_t total = 0;
      for (std::size_t t = 0; t < count; ++t) total += layer_work(colour + 3 * t);
      // A layer goes to the thread whose share of the total holds the layer's midpoint.
      std::uint64_t before = 0;
      for (std::size_t t = 0; t < count; ++t) {
        const std::size_t l = colour + 3 * t;
        const std::uint64_t w = layer_work(l);
        const std::uint64_t owner =
            total == 0 ? 0 : std::min(threads - 1, (2 * before + w) * threads / (2 * total));
        before += w;
        if (owner == thread && filled(l)) process(l);
      }
    }
  }
  // Ghost forces go back to their owners, in ghost order.
  for (std::size_t g = 0; g < p.local_ghosts(); ++g) {
    const std::uint32_t o = p.ghost_owner[g];
    p.f[o] += p.f[n + g];
    p.torque[o] += p.torque[n + g];
  }
  contacts_ = 0;
  for (auto& b : bodies_) {
    b.force.setZero();
    b.torque = D::zero_ang();
  }
  for (auto& w : walls_) {
    w.force.setZero();
    w.torque = D::zero_ang();
  }
  std::size_t bad_layer = nl;
  for (std::size_t l = 0; l < nl; ++l) {
    if (!filled(l)) continue;
    const auto& a = layer_acc_[l];
    contacts_ += a.contacts;
    for (std::size_t b = 0; b < nb; ++b) {
      bodies_[b].force += a.body_force[b];
      bodies_[b].torque += a.body_torque[b];
    }
    for (std::size_t w = 0; w < nw; ++w) {
      walls_[w].force += a.wall_force[w];
      walls_[w].torque += a.wall_torque[w];
    }
    if (a.bad_row != std::numeric_limits<std::size_t>::max() && bad_layer == nl) bad_layer = l;
  }
  if (record) {
    records_.clear();
    for (std::size_t l = 0; l < nl; ++l)
      if (filled(l)) records_.insert(records_.end(), layer_acc_[l].records.begin(), layer_acc_[l].records.end());
    records_step_ = step_;
    record_next_ = false;
  }
  if (bad_layer != nl) {
    const auto& a = layer_acc_[bad_layer];
    std::ostringstream s;
    s.precision(6);
    s << "overlap " << a.bad_overlap << " m with "
      << (a.bad_wall ? "wall " + std::to_string(a.bad_partner)
                     : "particle id " + std::to_string(p.id[a.bad_partner]))
      << " exceeds max_overlap_ratio (" << config_.max_overlap_ratio << ") x the smaller radius";
    throw_instability(a.bad_row, s.str());
  }
  if (!check_finite) return;
  std::size_t bad = std::numeric_limits<std::size_t>::max();
#pragma omp parallel for schedule(static) reduction(min : bad) if (parallel_)
  for (std::size_t i = 0; i < n; ++i)
    if (!finite_state(i)) bad = std::min(bad, i);
  if (bad != std::numeric_limits<std::size_t>::max())
    throw_instability(bad, "its force, torque, position or velocity is not finite");
}

// The velocities the dashpots see (integrators::VelocityVerletPredictedDamping): the end-of-step
// velocity extrapolated with the force of the previous step, v + (a2 dt) F_old / m, which p.f
// still holds here (the reset comes after). Ghosts copy their owners. The set-up evaluation
// and non-free particles use v itself.
template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::predict_damping_velocities() {
  auto& p = particles_;
  const std::size_t n = p.owned();
  const double kick = setup_evaluation_ ? 0.0 : Integrator::second_kick * config_.dt;
  v_damp_.resize(p.size());
  omega_damp_.resize(p.size());
  const auto predict = [&](std::size_t i) {
    if (p.motion[i] == Motion::Free) {
      v_damp_[i] = p.v[i] + (kick * p.inv_mass[i]) * p.f[i];
      omega_damp_[i] = p.omega[i] + (kick * p.inv_inertia[i]) * p.torque[i];
    } else {
      v_damp_[i] = p.v[i];
      omega_damp_[i] = p.omega[i];
    }
  };
  // (Two loops, not an `if` clause: see compute_forces.)
  if (parallel_) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) predict(i);
  } else {
    for (std::size_t i = 0; i < n; ++i) predict(i);
  }
  for (std::size_t g = 0; g < p.ghosts(); ++g) {
    v_damp_[n + g] = v_damp_[p.ghost_owner[g]];
    omega_damp_[n + g] = omega_damp_[p.ghost_owner[g]];
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <bool Record>
GRANULE_FLATTEN inline void Simulation<D, Model, Search, Integrator, Parallel>::process_layer(std::size_t l) {
  auto& p = particles_;
  auto& acc = layer_acc_[l];
  const std::size_t n = p.owned();
  const std::size_t nm = materials_.size();
  const double max_ratio = config_.max_overlap_ratio;
  contact::ContactGeometry<D> g;
  State scratch{};
  for (std::size_t i = list_.layer_begin[l]; i < list_.layer_begin[l + 1]; ++i) {
    Vec fi = Vec::Zero();
    AngVec ti = D::zero_ang();
    const Params* prow = &params_[p.material[i] * nm];
    for (std::uint32_t e = list_.row_begin[i]; e < list_.row_begin[i + 1]; ++e) {
      const std::uint32_t j = list_.nbr[e];
      double reach = 0.0;
      if constexpr (Model::tensile) reach = tensile_reach(list_.history(l, e), prow[p.material[j]], i, j);
      if (!pair_geometry(i, j, g, reach)) {
        if constexpr (kHasState) list_.drop(l, e);
        continue;
      }
      if constexpr (kHasState) list_.acquire(l, e);
      State& s = kHasState ? *list_.history(l, e) : scratch;
      if (g.overlap > max_ratio * std::min(g.r_i, g.r_j) && acc.bad_row == std::numeric_limits<std::size_t>::max()) {
        acc.bad_row = i;
        acc.bad_partner = j < n ? j : p.source(j);
        acc.bad_overlap = g.overlap;
        acc.bad_wall = false;
      }
      const contact::ContactForce<D> cf = Model::evaluate(prow[p.material[j]], g, s);
      fi += cf.force;
      ti += cf.torque_i;
      p.f[j] -= cf.force;
      p.torque[j] += cf.torque_j;
      ++acc.contacts;
      if constexpr (Record) {
        analysis::ContactRecord<D> r;
        r.i = static_cast<std::uint32_t>(i);
        r.j = static_cast<std::uint32_t>(j < n ? j : p.source(j));
        r.normal = g.n;
        r.branch = -g.distance * g.n;
        r.contact_point = p.x[i] - g.arm_i * g.n;
        r.overlap = g.overlap;
        r.fn = cf.fn;
        r.ft = cf.ft;
        r.mu = materials_.pair(p.material[i], p.material[j]).mu_s;
        acc.records.push_back(r);
      }
    }
    wall_contacts<Record>(i, acc, fi, ti);
    p.f[i] += fi;
    p.torque[i] += ti;
  }
}

// Asks the caches for the particle data that layer l's packs gather and scatter (velocities,
// angular velocities, inverse masses, forces and torques of layers l and l + 1): 104 B per
// particle, 1 000-6 000 cache lines a layer in the 100k beds, about 3 prefetch instructions
// per particle-step. When the bed outgrows the L3 cache (100k particles, ~50 MB) these lines
// come from memory, and the packs' own loads, spread over many arrays, left the hardware
// prefetchers behind: +3-5 % on the 100k beds, no change at 20k (docs/performance.md, "Beds
// larger than the cache"). Positions and radii are left to the touch scan, which reads them
// first and in order. Beds below kPrefetchMinParticles (whose 104 B per particle fit in a
// core's L2 cache) skip it: there the lines are in the cache already, and the prefetch loops
// were 1-1.5 % of the 1600-disk 2D step.
template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::prefetch_layer_pair(std::size_t l) const {
  const auto& p = particles_;
  const std::size_t last = list_.layer_begin.size() - 1;
  const std::size_t a = list_.layer_begin[l], b = list_.layer_begin[std::min(l + 2, last)];
  if (a == b) return;
  // (64-byte lines; __builtin_prefetch(address, 1 = for a write, 2 = keep in L2 and L3).)
  const auto lines = [a, b](const auto* base, auto for_write) {
    const char* c = reinterpret_cast<const char*>(base + a);
    const char* const end = reinterpret_cast<const char*>(base + b);
    for (; c < end; c += 64) __builtin_prefetch(c, decltype(for_write)::value, 2);
  };
  lines(p.v.data(), std::false_type{});
  lines(p.omega.data(), std::false_type{});
  lines(p.inv_mass.data(), std::false_type{});
  lines(p.f.data(), std::true_type{});
  lines(p.torque.data(), std::true_type{});
}

// process_layer<false> with the particle pairs evaluated W at a time (contact/packed.hpp);
// the wall contacts are found one at a time and their law runs W at a time. Pass 1 lists the
// layer's touching entries without a branch
// (which pair touches is unpredictable: a third do not) and moves history slots (a pair that
// starts touching takes one, one that separates gives it back); then the touching pairs go
// through chunks. A chunk holds pairs of one parameter set: a change of material pair flushes
// it; the packs read the particles' data from the store themselves (core/lane_transpose.hpp).
// (When the chunk still held copies of that data, copying every entry in pass 1, so that only
// the count depended on the touch, was 5-12 % slower: the copy was bound by its stores.)
template <class D, class Model, class Search, class Integrator, class Parallel>
GRANULE_FLATTEN inline void Simulation<D, Model, Search, Integrator, Parallel>::process_layer_packed(std::size_t l) {
  if constexpr (kPackable) {
    // (2D: 256 contacts, so that most layers fill one chunk and end in one part-filled pack:
    // 1-2 % faster than 64 on a Zen 3, where paper 002's layers hold ~65 contacts.)
    using Chunk = contact::PairChunk<D::dim == 2 ? 256 : 64, D::dim>;
    auto& p = particles_;
    auto& acc = layer_acc_[l];
    const std::size_t r0 = list_.layer_begin[l], r1 = list_.layer_begin[l + 1];
    const std::size_t entries = list_.row_begin[r1] - list_.row_begin[r0];
    if (p.size() >= kPrefetchMinParticles) prefetch_layer_pair(l);
#ifdef _OPENMP
    PairWork& work = pair_work_[static_cast<std::size_t>(omp_get_thread_num())];
#else
    PairWork& work = pair_work_[0];
#endif
    // (8 entries of room for the packed scan's full-width stores.)
    work.entries.resize(entries + 8);
    work.rows.resize(entries + 8);
    std::uint32_t* const sorted = work.entries.data();
    std::uint32_t* const rows = work.rows.data();
    contact::TouchScanInput scan{scalars(p.x), p.radius.data(), list_.row_begin.data(),
                                 list_.nbr.data(), kHasState ? list_.slot.data() : nullptr, List::kNone,
                                 kPairConstants ? pair_reach_.data() : nullptr,
                                 kPairConstants ? entry_row_.data() : nullptr};
    // 2D: the scan hands the touching pairs' x_i - x_j to the geometry (one gather of both
    // positions per pair instead of two; 3D was left as measured).
    if constexpr (D::dim == 2) {
      for (auto& a : work.separation) a.resize(entries + 8);
      scan.separation[0] = work.separation[0].data();
      scan.separation[1] = work.separation[1].data();
    }
    // (Slots are taken and given back in entry order, so they do not depend on threads.)
    const std::size_t nt = contact::scan_rows<D::dim>(scan, static_cast<std::uint32_t>(r0), static_cast<std::uint32_t>(r1),
                                              sorted, rows, [&](std::uint32_t e, bool touch) {
                                                if constexpr (kHasState) {
                                                  if (touch) {
                                                    list_.acquire(l, e);
                                                  } else {
                                                    list_.drop(l, e);
                                                  }
                                                }
                                              });
    Chunk chunk;
    for (std::size_t k = 0; k < nt;) {
      if constexpr (D::dim == 2) {
        chunk.separation[0] = work.separation[0].data() + k;
        chunk.separation[1] = work.separation[1].data() + k;
      }
      k = fill_chunk(chunk, sorted, rows, k, nt);
      evaluate_chunk(chunk, acc, l);
    }
    if constexpr (D::dim == 3) {
      WallQueue walls;
      queue_wall_contacts(r0, r1, acc, walls);
      flush_wall_queue(walls, acc);
    } else {
      wall_contacts_by_entry(r0, r1, acc);
    }
  }
}

// Lists touching pairs k, k+1, ... of the layer (entries `touching`, their rows `rows`) in
// the chunk until it is full or the material pair changes; returns the first pair not listed.
// (A local count and plain stores: with chunk.count incremented in memory GCC reloaded it for
// every store.)
template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Chunk>
inline std::size_t Simulation<D, Model, Search, Integrator, Parallel>::fill_chunk(Chunk& chunk, const std::uint32_t* touching, const std::uint32_t* rows, std::size_t k, std::size_t nt) const {
  const auto& p = particles_;
  const std::size_t nm = materials_.size();
  const std::size_t prm = p.material[rows[k]] * nm + p.material[list_.nbr[touching[k]]];
  std::size_t c = 0;
  // With one particle material (step() knows) no pair's material need be read.
  const auto list = [&](auto check_material) {
    // (One bound: the pairs left or the chunk's room, whichever ends first.)
    const std::size_t last = std::min(nt, k + Chunk::capacity);
    for (; k < last; ++k, ++c) {
      const std::uint32_t e = touching[k], j = list_.nbr[e];
      const std::uint32_t i = rows[k];
      if constexpr (decltype(check_material)::value) {
        if (p.material[i] * nm + p.material[j] != prm) break;
      }
      chunk.i[c] = i;
      chunk.j[c] = j;
      chunk.history[c] = kHasState ? list_.slot[e] : 0u;  // (no slots without history)
      if constexpr (kPairConstants) chunk.entry[c] = e;
    }
  };
  if (one_material_) {
    list(std::false_type{});
  } else {
    list(std::true_type{});
  }
  chunk.count = c;
  chunk.params = prm;
  return k;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
template <class Chunk>
inline void Simulation<D, Model, Search, Integrator, Parallel>::evaluate_chunk(Chunk& chunk, LayerAccumulator& acc, std::size_t l) {
  using LD = LanesOf<D>;
  using PackedState = typename Model::template State<LD>;
  auto& p = particles_;
  const std::size_t n = p.owned();
  const Params& prm = params_[chunk.params];
  const double dt = setup_evaluation_ ? 0.0 : config_.dt;
  const double max_ratio = config_.max_overlap_ratio;
  chunk.pad();
  static_assert(sizeof(Vec) == D::dim * sizeof(double) && sizeof(AngVec) == D::rot_dim * sizeof(double));
  const contact::PackedParticles pp{scalars(p.x), scalars(p.v), scalars(p.omega), p.radius.data(),
                                    p.inv_mass.data(), D::dim == 2 ? disk_records_.data() : nullptr};
  // The geometry of the W contacts at k, with the overlap check.
  const auto geometry = [&](std::size_t k, contact::ContactGeometry<LD>& g) {
    const std::size_t valid = std::min(lane_width, chunk.count - k);
    chunk.template geometry<Model::needs_rolling_inertia, Model::needs_twist, kPairConstants>(
        k, pp, dt, g, pair_constants_.data());
    const LaneMask deep = g.overlap > max_ratio * stdx::min(g.r_i, g.r_j);
    if (stdx::any_of(deep) && acc.bad_row == std::numeric_limits<std::size_t>::max()) {
      const std::size_t b = static_cast<std::size_t>(stdx::find_first_set(deep));
      if (b < valid) {
        const std::uint32_t j = chunk.j[k + b];
        acc.bad_row = chunk.i[k + b];
        acc.bad_partner = j < n ? j : p.source(j);
        acc.bad_overlap = g.overlap[b];
        acc.bad_wall = false;
      }
    }
  };
  // The law of the W contacts at k: history in, forces out, history back.
  const auto law = [&](std::size_t k, const contact::ContactGeometry<LD>& g) {
    const std::size_t valid = std::min(lane_width, chunk.count - k);
    PackedState s{};
    State* slots[lane_width];
    if constexpr (kHasState) {
      State* const pool = list_.pools[l].states.data();
      for (std::size_t q = 0; q < lane_width; ++q) slots[q] = pool + chunk.history[k + q];
      contact::PackedState<State, PackedState>::load(s, slots);
    }
    const contact::ContactForce<LD> cf = Model::evaluate(prm, g, s);
    if constexpr (kHasState) contact::PackedState<State, PackedState>::store(s, slots, valid);
    chunk.store_force(k, cf);
  };
  // 2D with AVX-512: two packs at a time, both geometries before both laws. The law is one
  // chain of dependent steps through the history (the rotation's square root, the increment,
  // the Coulomb clamp), so the two laws' chains, close together in the instruction stream,
  // overlap in the core. The same operations per pack: the same bits. (Zen 4, 2026-12-07: one
  // pack at a time 29.1-30.8 ns against 26.7, three at a time 27.7-28.7 against 25.8-27.4.)
  // With AVX2's 16 registers the two geometries spill: one pack at a time was 2-3 % faster
  // on a Zen 3 (2026-12-07, the two loops alternated in one run).
  std::size_t k = 0;
  if constexpr (D::dim == 2 && lane_width == 8) {
    contact::ContactGeometry<LD> g0, g1;
    for (; k + lane_width < chunk.count; k += 2 * lane_width) {
      geometry(k, g0);
      geometry(k + lane_width, g1);
      law(k, g0);
      law(k + lane_width, g1);
    }
  }
  contact::ContactGeometry<LD> g;
  for (; k < chunk.count; k += lane_width) {
    geometry(k, g);
    law(k, g);
  }
  // Pass 3, in entry order. (Keeping a row's sum in a register and writing it once per run
  // of equal i was 5 % slower in scene B: the run ends are unpredictable branches.)
  // (Raw pointers: through the vectors GCC reloaded their data pointers after every store.)
  Vec* const force = p.f.data();
  AngVec* const torque = p.torque.data();
  const auto& out = chunk.out;
  constexpr std::size_t fx = Chunk::fx, tix = Chunk::tix, tjx = Chunk::tjx;
  for (std::size_t c = 0; c < chunk.count; ++c) {
    const std::uint32_t i = chunk.i[c], j = chunk.j[c];
    if constexpr (D::dim == 3) {
      const Vec f(out[fx][c], out[fx + 1][c], out[fx + 2][c]);
      force[i] += f;
      force[j] -= f;
      torque[i] += AngVec(out[tix][c], out[tix + 1][c], out[tix + 2][c]);
      torque[j] += AngVec(out[tjx][c], out[tjx + 1][c], out[tjx + 2][c]);
    } else {
      const Vec f(out[fx][c], out[fx + 1][c]);
      force[i] += f;
      force[j] -= f;
      torque[i] += out[tix][c];
      torque[j] += out[tjx][c];
    }
  }
  acc.contacts += chunk.count;
  chunk.count = 0;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::update_pair_constants() {
  if (pair_constants_generation_ == list_.generation()) return;
  const auto& p = particles_;
  const std::size_t n = list_.row_begin.empty() ? 0 : list_.row_begin.size() - 1;
  pair_constants_.assign(list_.nbr.size(), contact::PairConstants{});
  pair_reach_.assign(list_.nbr.size() + 8, 0.0);  // (8 of room for the scan's last block)
  entry_row_.assign(list_.nbr.size() + 8, 0u);
  contact::PairConstants* const out = pair_constants_.data();
  double* const reach = pair_reach_.data();
  std::uint32_t* const entry_row = entry_row_.data();
  const auto* const row_begin = list_.row_begin.data();
  const auto* const nbr = list_.nbr.data();
  const double* const radius = p.radius.data();
  const double* const inv_mass = p.inv_mass.data();
  // (The packed geometry's formulas, contact/packed.hpp: the same bits as computed per pack.)
#pragma omp parallel for schedule(static) if (parallel_)
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e) {
      const std::uint32_t j = nbr[e];
      const double r_i = radius[i], r_j = radius[j], im_i = inv_mass[i], im_j = inv_mass[j];
      entry_row[e] = static_cast<std::uint32_t>(i);
      reach[e] = r_i + r_j;
      contact::PairConstants& c = out[e];
      c.r_eff = contact::effective_radius(r_i, r_j, r_i + r_j);
      c.m_eff = contact::effective_mass(im_i, im_j);
      if constexpr (Model::needs_rolling_inertia)
        c.i_roll = contact::rolling_inertia(r_i, r_j, im_i, im_j, D::inertia_factor);
    }
  }
  pair_constants_generation_ = list_.generation();
}

// The doubles of a vector of small vectors, for the packed passes' raw-pointer inputs; null when
// there are no particles (a scene of walls and bodies alone), where data()->data() would be a
// member access through a null pointer.
template <class D, class Model, class Search, class Integrator, class Parallel>
template <class V>
inline const double* Simulation<D, Model, Search, Integrator, Parallel>::scalars(const std::vector<V>& v) {
  if constexpr (std::is_same_v<V, double>) {
    return v.empty() ? nullptr : v.data();
  } else {
    return v.empty() ? nullptr : v.front().data();
  }
}

}  // namespace granule
