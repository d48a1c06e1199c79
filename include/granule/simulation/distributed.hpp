#pragma once
// Simulation, part: the distributed engine (Parallel = parallel::MpiDomains; docs/mpi.md). Every
// member here is used only behind `if constexpr (Parallel::distributed)`, so a one-process
// program never instantiates it and needs no MPI header.
//
// A rank's store holds its owned particles, then the periodic images of its own particles along
// an axis it spans alone (local ghosts), then copies of other ranks' particles within the halo
// width w = 2 r_max + skin (+ pull-off reach) of its region (remote ghosts), periodic images
// across ranks included. At every rebuild, decided by all ranks together (the largest
// displacement test is OR-reduced), particles that left the region go to their new owner with
// their whole state and the history of every contact they hold, keyed by the partner's global id
// and the relative periodic image (PairList::detached_histories / add_detached_row); then the
// halo is rebuilt. Between rebuilds only x, v and omega of the ghosts travel, in the order of the
// last build (a fixed plan). A pair of an owned particle and a remote ghost is evaluated on both
// ranks, each keeping the force on its own particle. Body and wall forces are summed over the
// ranks in rank order. Local work that can throw runs in MpiContext::collective, so an error on
// one rank is thrown on every rank with that rank's message.
//
// Set-up: every rank builds the whole scene with the same calls; the first build makes the
// decomposition from all particles (the same on every rank, no message) and keeps each rank's own.
// Later every rank still makes the same add_particle calls (the owner of the position keeps the
// particle) and removes of its own; each rebuild checks the ranks added alike and the count over
// the ranks (HaloHooks::after_wrap; docs/mpi.md, "Insertion and removal").
// Included by granule/simulation.hpp at its end: include that header, not this one.
#include <array>
#include <chrono>
#include <cstring>
#include <limits>
#include <map>
#include <tuple>
#include <type_traits>

#include "granule/parallel/decomposition.hpp"  // no MPI: the cuts are pure functions

namespace granule {

namespace simulation_parts {

// Bytes for the messages: scalars, enums and Eigen vectors (component by component), and the
// contact histories as they lie in memory (plain structs of doubles and fixed-size vectors).
struct Packer {
  std::vector<char>& b;
  template <class T>
  void put(const T& v) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      const char* p = reinterpret_cast<const char*>(&v);
      b.insert(b.end(), p, p + sizeof(T));
    } else if constexpr (requires { v.size(); v[0]; }) {
      for (Eigen::Index k = 0; k < v.size(); ++k) put(v[k]);
    } else {
      // (A contact history: plain data, Eigen vectors of fixed size included.)
      const char* p = reinterpret_cast<const char*>(&v);
      b.insert(b.end(), p, p + sizeof(T));
    }
  }
};

struct Unpacker {
  const char* p;
  const char* end;
  template <class T>
  void get(T& v) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      std::memcpy(&v, p, sizeof(T));
      p += sizeof(T);
    } else if constexpr (requires { v.size(); v[0]; }) {
      for (Eigen::Index k = 0; k < v.size(); ++k) get(v[k]);
    } else {
      std::memcpy(static_cast<void*>(&v), p, sizeof(T));
      p += sizeof(T);
    }
  }
  template <class T>
  T take() {
    T v{};
    get(v);
    return v;
  }
  bool done() const { return p >= end; }
};

}  // namespace simulation_parts

// The rebuild's extra steps: migration after the wrap, the halo after the sort.
template <class D, class Model, class Search, class Integrator, class Parallel>
struct Simulation<D, Model, Search, Integrator, Parallel>::HaloHooks {
  Simulation& sim;
  double w;  // halo width
  static constexpr bool local_images = false;  // the decomposition says which images stay local

  void after_wrap(ParticleStore<D>& p) {
    auto& E = sim.dist_;
    sim.collective([&] { sim.check_domain(); });
    const int me = E.rank(), R = E.ranks();
    if (!E.decomposition) {
      // First build: every rank holds the whole scene.
      const std::uint64_t total = p.owned();
      sim.collective([&] {
        std::vector<Vec> xs(p.x.begin(), p.x.begin() + static_cast<std::ptrdiff_t>(p.owned()));
        parallel::RankGrid grid = E.requested_grid();
        if (grid.parts[0] == 0) grid = parallel::choose_grid(sim.config_.domain, R, w);
        require(grid.ranks() == R, "MpiDomains", "rank grid parts", grid.ranks(),
                "= the number of ranks (" + std::to_string(R) + ")");
        if (E.uniform_start)
          E.decomposition.emplace(sim.config_.domain, grid, w);
        else
          E.decomposition.emplace(parallel::Decomposition<D>::balanced(sim.config_.domain, grid, xs, {}, w));
        std::vector<bool> keep(p.owned());
        for (std::size_t i = 0; i < p.owned(); ++i) keep[i] = E.decomposition->owner(p.x[i]) == me;
        p.remove_if_not(keep);
      });
      const std::uint64_t kept = E.sum(p.owned());
      std::vector<double> spread{static_cast<double>(total), static_cast<double>(sim.next_id_),
                                 -static_cast<double>(sim.next_id_)};
      E.max(spread);
      const std::uint64_t most = static_cast<std::uint64_t>(spread[0]);
      if (kept != total || most != total || spread[1] != -spread[2])
        throw InvalidParameter("MpiDomains: the ranks did not set up the same scene (" + std::to_string(total) +
                               " particles here, " + std::to_string(kept) + " kept over all ranks" +
                               (spread[1] != -spread[2] ? ", different numbers of add_particle calls" : "") + ")");
      E.total = total;
      E.next_id_at_build = sim.next_id_;
      E.removed_since_build = 0;
      E.imbalance = parallel::Load{E.all_gather({static_cast<double>(p.owned())})}.imbalance();
      return;
    }
    // Insertion and removal since the last build (docs/mpi.md, "Insertion and removal"): every
    // rank made the same add_particle calls (the same ids; each kept those whose position it
    // owns, Simulation::add_particle), and each counted the particles it removed of its own.
    {
      const std::uint64_t added = sim.next_id_ - E.next_id_at_build;
      std::vector<double> spread{static_cast<double>(added), -static_cast<double>(added)};
      E.max(spread);
      if (spread[0] != -spread[1])
        throw InvalidParameter("MpiDomains: the ranks added different numbers of particles since the last rebuild (" +
                               std::to_string(static_cast<std::uint64_t>(-spread[1])) + " to " +
                               std::to_string(static_cast<std::uint64_t>(spread[0])) +
                               "); every rank must make the same add_particle calls (docs/mpi.md)");
      std::vector<std::uint64_t> counts{E.removed_since_build, p.owned()};
      E.sum(counts);
      const std::uint64_t removed = counts[0], now = counts[1], expected = E.total + added - removed;
      if (now != expected)
        throw InvalidParameter("MpiDomains: " + std::to_string(now) + " particles over the ranks where " +
                               std::to_string(expected) + " were expected (" + std::to_string(E.total) +
                               " at the last rebuild, " + std::to_string(added) + " added, " +
                               std::to_string(removed) + " removed); add and remove particles only through "
                               "add_particle and remove_particles, with the same calls on every rank (docs/mpi.md)");
      E.total = expected;
      E.next_id_at_build = sim.next_id_;
      E.removed_since_build = 0;
    }
    // Load balance: the particle counts' max/mean; above the threshold, new cuts from every
    // particle's position (gathered in rank order, so every rank makes the same cuts).
    {
      const std::vector<double> counts = E.all_gather({static_cast<double>(p.owned())});
      E.imbalance = parallel::Load{counts}.imbalance();
      if (E.threshold >= 1.0 && E.imbalance > E.threshold) {
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<double> mine;
        mine.reserve(p.owned() * D::dim);
        for (std::size_t i = 0; i < p.owned(); ++i)
          for (int k = 0; k < D::dim; ++k) mine.push_back(p.x[i][k]);
        const std::vector<double> all = E.all_gather(mine);
        std::vector<Vec> xs(all.size() / D::dim);
        for (std::size_t i = 0; i < xs.size(); ++i)
          for (int k = 0; k < D::dim; ++k) xs[i][k] = all[i * D::dim + k];
        const parallel::RankGrid grid = E.decomposition->grid();
        sim.collective([&] {
          E.decomposition.emplace(parallel::Decomposition<D>::balanced(sim.config_.domain, grid, xs, {}, w));
        });
        parallel::Load after{std::vector<double>(static_cast<std::size_t>(R), 0.0)};
        for (const Vec& x : xs) after.per_rank[static_cast<std::size_t>(E.decomposition->owner(x))] += 1.0;
        E.imbalance_before_rebalance = E.imbalance;
        E.imbalance = after.imbalance();
        ++E.rebalances;
        E.rebalance_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
    }
    // Migration: who leaves, with what history.
    const auto t_migration = std::chrono::steady_clock::now();
    struct Clock {  // (the migration's seconds, however it ends)
      double& total;
      std::chrono::steady_clock::time_point t0;
      ~Clock() { total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
    } clock{E.migration_seconds, t_migration};
    const auto& dec = *E.decomposition;
    std::vector<int> dest(p.owned(), me);
    std::vector<std::uint64_t> ids;
    for (std::size_t i = 0; i < p.owned(); ++i) {
      dest[i] = dec.owner(p.x[i]);
      if (dest[i] != me) ids.push_back(p.id[i]);
    }
    std::sort(ids.begin(), ids.end());
    struct Carried {
      std::vector<std::uint64_t> keys;
      std::vector<State> states;
      std::vector<neighbours::WallEntry> walls;
      std::vector<State> wall_states;
    };
    std::vector<Carried> carried(ids.size());
    if constexpr (kHasState) {
      sim.list_.detached_histories(
          ids, [](State& s) { Model::reverse(s); },
          [&](std::size_t k, std::uint64_t key, const State& s) {
            carried[k].keys.push_back(key);
            carried[k].states.push_back(s);
          },
          [&](std::size_t k, const neighbours::WallEntry& e, const State& s) {
            carried[k].walls.push_back(e);
            carried[k].wall_states.push_back(s);
          });
    }
    std::vector<std::vector<char>> out(static_cast<std::size_t>(R));
    std::vector<bool> keep(p.owned(), true);
    for (std::size_t i = 0; i < p.owned(); ++i) {
      if (dest[i] == me) continue;
      keep[i] = false;
      const std::size_t k = static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), p.id[i]) - ids.begin());
      simulation_parts::Packer b{out[static_cast<std::size_t>(dest[i])]};
      b.put(p.x[i]); b.put(p.v[i]); b.put(p.f[i]); b.put(p.omega[i]); b.put(p.torque[i]);
      b.put(p.radius[i]); b.put(p.mass[i]); b.put(p.inv_mass[i]); b.put(p.inv_inertia[i]);
      b.put(p.material[i]); b.put(p.group[i]); b.put(p.id[i]); b.put(p.motion[i]); b.put(p.image[i]);
      const Carried& c = carried[k];
      b.put(static_cast<std::uint64_t>(c.keys.size()));
      for (std::size_t h = 0; h < c.keys.size(); ++h) { b.put(c.keys[h]); b.put(c.states[h]); }
      b.put(static_cast<std::uint64_t>(c.walls.size()));
      for (std::size_t h = 0; h < c.walls.size(); ++h) {
        b.put(c.walls[h].wall); b.put(c.walls[h].feature); b.put(c.wall_states[h]);
      }
    }
    p.remove_if_not(keep);
    E.migrated += ids.size();
    for (const auto& c : carried) E.carried_histories += c.keys.size() + c.walls.size();
    const auto in = E.exchange(out);
    for (int r = 0; r < R; ++r) {
      simulation_parts::Unpacker u{in[r].data(), in[r].data() + in[r].size()};
      while (!u.done()) {
        const Vec x = u.take<Vec>(), v = u.take<Vec>(), f = u.take<Vec>();
        const AngVec om = u.take<AngVec>(), tq = u.take<AngVec>();
        const double rad = u.take<double>(), m = u.take<double>(), im = u.take<double>(), iI = u.take<double>();
        const auto mat = u.take<std::uint32_t>(), grp = u.take<std::uint32_t>();
        const auto pid = u.take<std::uint64_t>();
        const auto mo = u.take<Motion>();
        const auto img = u.take<typename ParticleStore<D>::Image>();
        const std::size_t i = p.add(x, v, rad, m, mat, grp, pid);
        p.f[i] = f; p.omega[i] = om; p.torque[i] = tq; p.inv_mass[i] = im; p.inv_inertia[i] = iI;
        p.motion[i] = mo; p.image[i] = img;
        Carried c;
        c.keys.resize(u.take<std::uint64_t>());
        c.states.resize(c.keys.size());
        for (std::size_t h = 0; h < c.keys.size(); ++h) { u.get(c.keys[h]); u.get(c.states[h]); }
        c.walls.resize(u.take<std::uint64_t>());
        c.wall_states.resize(c.walls.size());
        for (std::size_t h = 0; h < c.walls.size(); ++h) {
          u.get(c.walls[h].wall); u.get(c.walls[h].feature); u.get(c.wall_states[h]);
        }
        sim.list_.add_detached_row(pid, c.keys, c.states, c.walls, c.wall_states);
      }
    }
  }

  void after_ghosts(ParticleStore<D>& p) {
    auto& E = sim.dist_;
    struct Clock {
      double& total;
      std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
      ~Clock() { total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
    } clock{E.halo_seconds};
    const auto& dec = *E.decomposition;
    const int me = E.rank(), R = E.ranks();
    const Vec L = sim.config_.domain.length();
    Vec lo, hi;
    dec.region(me, lo, hi);
    E.send.assign(static_cast<std::size_t>(R), {});
    for (std::size_t i = 0; i < p.owned(); ++i) {
      const Vec xi = p.x[i];
      bool near = false;
      for (int k = 0; k < D::dim; ++k) near = near || xi[k] - lo[k] < w || hi[k] - xi[k] < w;
      if (!near) continue;  // deeper than w inside the region: nobody needs it
      for (const auto& t : dec.halo_targets(xi, w)) {
        if (t.rank == me) {
          // Own periodic image, along an axis this rank spans alone: as make_ghosts, only the
          // shifts in the positive half (first non-zero component +1), so that each periodic
          // pair is listed once.
          int first = 0;
          for (int k = 0; k < D::dim && first == 0; ++k) first = t.shift[k];
          if (first > 0) p.add_ghost(static_cast<std::uint32_t>(i), t.shift, L);
        } else {
          E.send[static_cast<std::size_t>(t.rank)].push_back({static_cast<std::uint32_t>(i), t.shift});
        }
      }
    }
    std::vector<std::vector<char>> out(static_cast<std::size_t>(R));
    for (int r = 0; r < R; ++r) {
      simulation_parts::Packer b{out[static_cast<std::size_t>(r)]};
      for (const auto& s : E.send[static_cast<std::size_t>(r)]) {
        const std::size_t i = s.slot;
        b.put(Vec(p.x[i] + (s.shift.template cast<double>().array() * L.array()).matrix()));
        b.put(p.v[i]); b.put(p.omega[i]); b.put(p.radius[i]); b.put(p.mass[i]); b.put(p.inv_mass[i]);
        b.put(p.inv_inertia[i]); b.put(p.material[i]); b.put(p.group[i]); b.put(p.id[i]); b.put(p.motion[i]);
        b.put(typename ParticleStore<D>::Image(p.image[i] - s.shift));
      }
    }
    const auto in = E.exchange(out);
    E.remote_begin = p.size();
    E.receive.assign(static_cast<std::size_t>(R), 0);
    for (int r = 0; r < R; ++r) {
      simulation_parts::Unpacker u{in[r].data(), in[r].data() + in[r].size()};
      while (!u.done()) {
        const Vec x = u.take<Vec>(), v = u.take<Vec>();
        const AngVec om = u.take<AngVec>();
        const double rad = u.take<double>(), m = u.take<double>(), im = u.take<double>(), iI = u.take<double>();
        const auto mat = u.take<std::uint32_t>(), grp = u.take<std::uint32_t>();
        const auto pid = u.take<std::uint64_t>();
        const auto mo = u.take<Motion>();
        const auto img = u.take<typename ParticleStore<D>::Image>();
        p.add_remote_ghost(x, v, om, rad, m, im, iI, mat, grp, pid, mo, img);
        ++E.receive[static_cast<std::size_t>(r)];
      }
    }
  }
};

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::rebuild_distributed() {
  double r_local = 0.0;
  for (std::size_t i = 0; i < particles_.owned(); ++i) r_local = std::max(r_local, particles_.radius[i]);
  const double r_max = dist_.max(r_local);
  const double skin = Search::rebuild_every_step ? 0.0 : (config_.skin >= 0.0 ? config_.skin : 0.2 * r_max);
  const double listed = dist_.max(skin_with_reach(skin));
  const double w = 2.0 * r_max + listed;
  HaloHooks hooks{*this, w};
  rebuild_list(skin, listed, hooks);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::refresh_remote_ghosts() {
  auto& E = dist_;
  struct Clock {
    double& total;
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
    ~Clock() { total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
  } clock{E.refresh_seconds};
  auto& p = particles_;
  const int R = E.ranks();
  const Vec L = config_.domain.length();
  constexpr std::size_t per = sizeof(double) * (2 * D::dim + (D::dim == 3 ? 3 : 1));
  std::vector<std::vector<char>> out(static_cast<std::size_t>(R)), in(static_cast<std::size_t>(R));
  for (int r = 0; r < R; ++r) {
    auto& b = out[static_cast<std::size_t>(r)];
    b.reserve(per * E.send[static_cast<std::size_t>(r)].size());
    simulation_parts::Packer pk{b};
    for (const auto& s : E.send[static_cast<std::size_t>(r)]) {
      pk.put(Vec(p.x[s.slot] + (s.shift.template cast<double>().array() * L.array()).matrix()));
      pk.put(p.v[s.slot]);
      pk.put(p.omega[s.slot]);
    }
    in[static_cast<std::size_t>(r)].resize(per * E.receive[static_cast<std::size_t>(r)]);
  }
  E.exchange_known(out, in);
  std::size_t g = E.remote_begin;
  for (int r = 0; r < R; ++r) {
    simulation_parts::Unpacker u{in[r].data(), in[r].data() + in[r].size()};
    while (!u.done()) {
      u.get(p.x[g]);
      u.get(p.v[g]);
      u.get(p.omega[g]);
      ++g;
    }
  }
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::reduce_wall_forces() {
  std::vector<double> a;
  auto put = [&](const auto& v) {
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(v)>>) {
      a.push_back(v);
    } else {
      for (Eigen::Index k = 0; k < v.size(); ++k) a.push_back(v[k]);
    }
  };
  for (const auto& b : bodies_) { put(b.force); put(b.torque); }
  for (const auto& w : walls_) { put(w.force); put(w.torque); }
  dist_.sum_in_rank_order(a);
  std::size_t k = 0;
  auto get = [&](auto& v) {
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(v)>>) {
      v = a[k++];
    } else {
      for (Eigen::Index c = 0; c < v.size(); ++c) v[c] = a[k++];
    }
  };
  for (auto& b : bodies_) { get(b.force); get(b.torque); }
  for (auto& w : walls_) { get(w.force); get(w.torque); }
}

// The start of step() in a distributed run: start_if_needed (simulation/integrate.hpp) with the
// time-step checks collective.
template <class D, class Model, class Search, class Integrator, class Parallel>
inline void Simulation<D, Model, Search, Integrator, Parallel>::start_distributed() {
  // (Decided together: a rank whose scene script added or removed particles rebuilds, so all
  // do; a rank that made no call while others did is then found by the rebuild's checks
  // instead of waiting in a different collective.)
  if (on_any_rank(!list_valid_)) {
    initialise();
  } else if (!initialised_) {
    collective([&] {
      check_time_step();
      check_rolling_time_step();
    });
    initialised_ = true;
  }
}

// save_state of a distributed run (docs/mpi.md, "Checkpoints"). Each rank sends its owned
// particles, the histories its rows hold (keyed by partner id and relative image; a pair with
// another rank's particle is held by both ranks and sent by the lower id's) and its wall
// entries. Rank 0 writes the state a one-process run would: the particles in id order, a
// periodic image wherever a history's partner is seen across a periodic face, one row per
// particle listing the pairs that hold history, one cell layer, and no build positions, so any
// reader rebuilds its list on its first step and carries the histories over by key, as
// every rebuild does. The other ranks write nothing.
template <class D, class Model, class Search, class Integrator, class Parallel>
template <class W>
inline void Simulation<D, Model, Search, Integrator, Parallel>::save_state_distributed(W& w) {
  const auto& p = particles_;
  const std::size_t remote = p.owned() + p.local_ghosts();
  std::vector<std::vector<std::pair<std::uint64_t, State>>> hist(p.owned());
  struct WallRecord {
    neighbours::WallEntry entry;
    State state;
  };
  std::vector<std::vector<WallRecord>> walls(p.owned());
  list_.for_each_history(
      p,
      [&](std::size_t i, std::size_t j, std::uint64_t key, const State& st) {
        if (j >= remote && p.id[j] < p.id[i]) return;  // the other rank sends this pair
        hist[i].push_back({key, st});
      },
      [&](std::size_t i, const neighbours::WallEntry& e, std::uint32_t k) {
        WallRecord rec{e, State{}};
        if constexpr (kHasState) rec.state = list_.wall_state[k];
        walls[i].push_back(rec);
      });
  std::vector<char> mine;
  simulation_parts::Packer b{mine};
  // (Right after a checkpoint was read every rank holds every particle: rank 0 sends them.)
  const std::size_t n_sent = dist_.decomposition || dist_.context().root() ? p.owned() : 0;
  for (std::size_t i = 0; i < n_sent; ++i) {
    b.put(p.id[i]); b.put(p.x[i]); b.put(p.v[i]); b.put(p.f[i]); b.put(p.omega[i]); b.put(p.torque[i]);
    b.put(p.radius[i]); b.put(p.mass[i]); b.put(p.inv_mass[i]); b.put(p.inv_inertia[i]);
    b.put(p.material[i]); b.put(p.group[i]); b.put(p.motion[i]); b.put(p.image[i]);
    b.put(static_cast<std::uint64_t>(hist[i].size()));
    for (const auto& [key, st] : hist[i]) { b.put(key); b.put(st); }
    b.put(static_cast<std::uint64_t>(walls[i].size()));
    for (const auto& rec : walls[i]) { b.put(rec.entry.wall); b.put(rec.entry.feature); b.put(rec.state); }
  }
  const double rounding = dist_.max(list_.build_rounding);
  const std::vector<char> all = dist_.gather_to_root(mine);
  if (!dist_.context().root()) return;

  struct Record {
    std::uint64_t id;
    Vec x, v, f;
    AngVec omega, torque;
    double radius, mass, inv_mass, inv_inertia;
    std::uint32_t material, group;
    Motion motion;
    typename ParticleStore<D>::Image image;
    std::vector<std::pair<std::uint64_t, State>> hist;
    std::vector<WallRecord> walls;
  };
  std::vector<Record> recs;
  simulation_parts::Unpacker u{all.data(), all.data() + all.size()};
  while (!u.done()) {
    Record r;
    u.get(r.id); u.get(r.x); u.get(r.v); u.get(r.f); u.get(r.omega); u.get(r.torque);
    u.get(r.radius); u.get(r.mass); u.get(r.inv_mass); u.get(r.inv_inertia);
    u.get(r.material); u.get(r.group); u.get(r.motion); u.get(r.image);
    r.hist.resize(u.take<std::uint64_t>());
    for (auto& [key, st] : r.hist) { u.get(key); u.get(st); }
    r.walls.resize(u.take<std::uint64_t>());
    for (auto& rec : r.walls) { u.get(rec.entry.wall); u.get(rec.entry.feature); u.get(rec.state); }
    recs.push_back(std::move(r));
  }
  std::sort(recs.begin(), recs.end(), [](const Record& a, const Record& c) { return a.id < c.id; });
  const std::size_t n = recs.size();
  ParticleStore<D> q;
  for (const Record& r : recs) {
    const std::size_t i = q.add(r.x, r.v, r.radius, r.mass, r.material, r.group, r.id);
    q.f[i] = r.f; q.omega[i] = r.omega; q.torque[i] = r.torque; q.inv_mass[i] = r.inv_mass;
    q.inv_inertia[i] = r.inv_inertia; q.motion[i] = r.motion; q.image[i] = r.image;
  }
  auto slot_of = [&](std::uint64_t id) -> std::size_t {
    const auto it = std::lower_bound(recs.begin(), recs.end(), id, [](const Record& a, std::uint64_t v) { return a.id < v; });
    if (it == recs.end() || it->id != id)
      throw InvalidParameter("save_state: a contact history names particle " + std::to_string(id) +
                             ", which no rank owns");
    return static_cast<std::size_t>(it - recs.begin());
  };
  using Image = typename ParticleStore<D>::Image;
  constexpr std::uint64_t K = List::image_codes();
  const auto fold = [](int c) { return ((c % 5) + 5 + 2) % 5 - 2; };  // into [-2, 2]
  const Vec L = config_.domain.length();
  std::map<std::pair<std::size_t, std::array<int, D::dim>>, std::uint32_t> ghost_of;
  std::vector<std::uint32_t> row_begin{0}, nbr, slot, wall_begin{0}, row_of_id, layer_begin{0, std::uint32_t(n)};
  std::vector<neighbours::WallEntry> wall;
  std::vector<State> states, wall_state;
  for (std::size_t i = 0; i < n; ++i) {
    for (const auto& [key, st] : recs[i].hist) {
      const std::size_t j = slot_of(key / K);
      const Image rel = List::image_of_code(key % K);
      bool direct = true;
      for (int k = 0; k < D::dim; ++k) direct = direct && fold(q.image[i][k] - q.image[j][k]) == rel[k];
      std::size_t partner = j;
      if (!direct) {
        // A periodic image of j with shift s such that s - image[j] + image[i] = rel.
        std::array<int, D::dim> s{};
        Image shift;
        for (int k = 0; k < D::dim; ++k) shift[k] = s[k] = fold(rel[k] + q.image[j][k] - q.image[i][k]);
        auto [it, fresh] = ghost_of.try_emplace({j, s}, std::uint32_t(q.ghosts()));
        if (fresh) q.add_ghost(static_cast<std::uint32_t>(j), shift, L);
        partner = n + it->second;
      }
      nbr.push_back(static_cast<std::uint32_t>(partner));
      if constexpr (kHasState) {
        slot.push_back(static_cast<std::uint32_t>(states.size()));
        states.push_back(st);
      }
    }
    row_begin.push_back(static_cast<std::uint32_t>(nbr.size()));
    for (const auto& rec : recs[i].walls) {
      wall.push_back(rec.entry);
      if constexpr (kHasState) wall_state.push_back(rec.state);
    }
    wall_begin.push_back(static_cast<std::uint32_t>(wall.size()));
  }
  if (n > 0) {
    row_of_id.assign(recs.back().id + 1, List::kNone);
    for (std::size_t i = 0; i < n; ++i) row_of_id[recs[i].id] = static_cast<std::uint32_t>(i);
  }
  w.template pod<double>(time_);
  w.template pod<std::uint64_t>(step_);
  w.template pod<std::uint64_t>(next_id_);
  w.template pod<double>(config_.dt);
  w.template pod<double>(skin_used_);
  w.template pod<std::uint64_t>(q.owned());
  w.vec(q.x); w.vec(q.v); w.vec(q.f); w.vec(q.omega); w.vec(q.torque); w.vec(q.radius);
  w.vec(q.mass); w.vec(q.inv_mass); w.vec(q.inv_inertia); w.vec(q.material); w.vec(q.group);
  w.vec(q.id); w.vec(q.motion); w.vec(q.image); w.vec(q.ghost_owner); w.vec(q.ghost_shift);
  // The list, in PairList::save's layout.
  w.vec(row_begin); w.vec(nbr); w.vec(slot); w.vec(wall_begin); w.vec(wall); w.vec(wall_state);
  w.vec(layer_begin);
  w.vec(std::vector<typename List::BuildPosition>{});  // no build positions: rebuild first
  w.template pod<double>(rounding);
  w.vec(row_of_id);
  w.template pod<std::uint64_t>(kHasState ? 1 : 0);
  if constexpr (kHasState) {
    w.vec(states);
    w.vec(std::vector<std::uint32_t>{});
  }
  w.template pod<std::uint64_t>(list_.builds);
  save_state_tail(w);
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline double Simulation<D, Model, Search, Integrator, Parallel>::over_ranks(double x) const {
  // (Before the first build, and after a checkpoint was read, every rank holds every particle.)
  std::vector<double> a{dist_.decomposition || dist_.context().root() ? x : 0.0};
  dist_.sum_in_rank_order(a);
  return a[0];
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline std::size_t Simulation<D, Model, Search, Integrator, Parallel>::contact_count_distributed() const {
  // This rank's count less the pairs across ranks the other rank counts (same test as the pair
  // pass: the list's pairs whose geometry touches).
  std::uint64_t twice = 0;
  for_each_contact_geometry([&](const contact::ContactGeometry<D>&, const Params&, const State&, std::size_t i,
                                std::uint32_t j, std::uint32_t wall) {
    if (wall == 0 && counted_elsewhere(i, j)) ++twice;
  });
  const bool mine = dist_.decomposition || dist_.context().root();  // (as in over_ranks)
  return static_cast<std::size_t>(dist_.sum(mine ? static_cast<std::uint64_t>(contacts_) - twice : 0));
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline analysis::Frame<D> Simulation<D, Model, Search, Integrator, Parallel>::gathered_frame() const {
  using Record = analysis::ContactRecord<D>;
  const auto& p = particles_;
  bool all_here = true;  // (before the first build every rank holds every particle: rank 0's count)
  if constexpr (Parallel::distributed) all_here = dist_.decomposition || dist_.context().root();
  const std::size_t n = all_here ? p.owned() : 0;
  std::vector<char> mine;
  simulation_parts::Packer b{mine};
  b.put(static_cast<std::uint64_t>(n));
  for (std::size_t i = 0; i < n; ++i) {
    b.put(p.id[i]); b.put(p.x[i]); b.put(p.v[i]); b.put(p.omega[i]); b.put(p.radius[i]); b.put(p.mass[i]);
    b.put(p.group[i]); b.put(p.f[i]); b.put(p.torque[i]);
  }
  constexpr std::uint64_t kWallId = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t kept = 0;
  std::vector<char> contacts;
  simulation_parts::Packer c{contacts};
  if (records_step_ == step_ && all_here)
    for (const Record& r : records_) {
      const bool wall = r.j == Record::kWall;
      if (!wall && counted_elsewhere(r.i, r.j)) continue;
      ++kept;
      c.put(p.id[r.i]); c.put(wall ? kWallId : p.id[r.j]); c.put(r.wall); c.put(r.normal); c.put(r.branch);
      c.put(r.contact_point); c.put(r.overlap); c.put(r.fn); c.put(r.ft); c.put(r.mu);
    }
  b.put(kept);
  mine.insert(mine.end(), contacts.begin(), contacts.end());
  std::vector<char> all;
  if constexpr (Parallel::distributed) all = dist_.gather_to_root(mine);
  else all.swap(mine);

  analysis::Frame<D> fr;
  fr.time = time_;
  fr.thickness = config_.thickness;
  fr.box_lo = config_.domain.lo;
  fr.box_hi = config_.domain.hi;
  fr.periodic = config_.domain.periodic;
  struct Particle {
    std::uint64_t id;
    Vec x, v, f;
    AngVec omega, torque;
    double radius, mass;
    std::uint32_t group;
  };
  struct Contact {
    std::uint64_t id_i, id_j;
    Record r;
  };
  std::vector<Particle> ps;
  std::vector<Contact> cs;
  simulation_parts::Unpacker u{all.data(), all.data() + all.size()};
  while (!u.done()) {
    const auto np = u.take<std::uint64_t>();
    for (std::uint64_t k = 0; k < np; ++k) {
      Particle q;
      u.get(q.id); u.get(q.x); u.get(q.v); u.get(q.omega); u.get(q.radius); u.get(q.mass); u.get(q.group);
      u.get(q.f); u.get(q.torque);
      ps.push_back(q);
    }
    const auto nc = u.take<std::uint64_t>();
    for (std::uint64_t k = 0; k < nc; ++k) {
      Contact q;
      u.get(q.id_i); u.get(q.id_j); u.get(q.r.wall); u.get(q.r.normal); u.get(q.r.branch);
      u.get(q.r.contact_point); u.get(q.r.overlap); u.get(q.r.fn); u.get(q.r.ft); u.get(q.r.mu);
      cs.push_back(q);
    }
  }
  std::sort(ps.begin(), ps.end(), [](const Particle& a, const Particle& q) { return a.id < q.id; });
  std::sort(cs.begin(), cs.end(), [](const Contact& a, const Contact& q) {
    return std::tie(a.id_i, a.id_j, a.r.wall) < std::tie(q.id_i, q.id_j, q.r.wall);
  });
  for (const Particle& q : ps) {
    fr.id.push_back(q.id); fr.x.push_back(q.x); fr.v.push_back(q.v); fr.omega.push_back(q.omega);
    fr.radius.push_back(q.radius); fr.mass.push_back(q.mass); fr.group.push_back(q.group);
    fr.force.push_back(q.f); fr.torque.push_back(q.torque);
  }
  auto index = [&](std::uint64_t id) {
    return static_cast<std::uint32_t>(
        std::lower_bound(fr.id.begin(), fr.id.end(), id) - fr.id.begin());
  };
  for (Contact& q : cs) {
    q.r.i = index(q.id_i);
    q.r.j = q.id_j == kWallId ? Record::kWall : index(q.id_j);
    fr.contacts.push_back(q.r);
  }
  return fr;
}

template <class D, class Model, class Search, class Integrator, class Parallel>
inline GatheredParticles<D> Simulation<D, Model, Search, Integrator, Parallel>::gather() const {
  GatheredParticles<D> g;
  if constexpr (!Parallel::distributed) {
    g.append(particles_);
  } else {
    const auto& p = particles_;
    std::vector<char> mine;
    simulation_parts::Packer b{mine};
    // (Before the first build, and after a checkpoint was read, every rank holds every particle.)
    const std::size_t n = dist_.decomposition || dist_.context().root() ? p.owned() : 0;
    for (std::size_t i = 0; i < n; ++i) {
      b.put(p.id[i]); b.put(p.x[i]); b.put(p.v[i]); b.put(p.f[i]); b.put(p.omega[i]); b.put(p.torque[i]);
      b.put(p.radius[i]); b.put(p.mass[i]); b.put(p.material[i]); b.put(p.group[i]); b.put(p.motion[i]);
      b.put(p.image[i]);
    }
    const std::vector<char> all = dist_.gather_to_root(mine);
    simulation_parts::Unpacker u{all.data(), all.data() + all.size()};
    while (!u.done()) {
      g.id.push_back(u.take<std::uint64_t>()); g.x.push_back(u.take<Vec>()); g.v.push_back(u.take<Vec>());
      g.f.push_back(u.take<Vec>()); g.omega.push_back(u.take<AngVec>()); g.torque.push_back(u.take<AngVec>());
      g.radius.push_back(u.take<double>()); g.mass.push_back(u.take<double>());
      g.material.push_back(u.take<std::uint32_t>()); g.group.push_back(u.take<std::uint32_t>());
      g.motion.push_back(u.take<Motion>()); g.image.push_back(u.take<typename ParticleStore<D>::Image>());
    }
  }
  g.sort_by_id();
  return g;
}

}  // namespace granule
