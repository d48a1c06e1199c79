#pragma once
// The half neighbour list shared by every search policy, with per-contact history stored next
// to it, periodic ghosts, the spatial sort and the history transfer across rebuilds.
//
// Layout (CSR): row i (a real particle slot) lists slots j of particles within r_i + r_j + skin,
// each pair once: for two real particles the one with the larger slot is in the row of the
// smaller; a ghost (periodic image) is always in the row of the real particle. Wall candidates
// (wall index, surface feature) within r_i + skin are listed per row the same way.
//
// History: only pairs in contact hold one. Entry e of a row in cell layer l has its history in
// pools[l].states[slot[e]], or none (slot kNone: zero history, as for a pair that never
// touched). A pool belongs to one layer, which one thread processes at a time, so the pair loop
// takes and gives back slots without locks; a slot freed when its pair separates is reused.
// About 60 % of the list's entries touch in a settled bed: a slot per entry would hold the
// history of the whole skin (docs/performance.md, "Memory").
//
// Transfer across a rebuild: a pair is keyed by (id of the partner, code of the relative
// periodic image), so that history survives re-sorting, wrapping through a periodic face and the
// pair moving to the other particle's row (then it is reversed: ContactModel::reverse). The keys
// are computed when the list is detached from the particle store (detach(): at the start of a
// rebuild, or before particles are added or removed), not stored per entry.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "granule/core/error.hpp"
#include "granule/neighbours/domain.hpp"
#include "granule/particles/particle_store.hpp"

namespace granule::neighbours {

/// A wall surface feature a particle may touch before the next rebuild.
struct WallEntry {
  std::uint32_t wall = 0;
  std::uint32_t feature = 0;
  std::uint64_t key() const { return (std::uint64_t(wall) << 32) | feature; }
};

/// What a rebuild does beyond the local list: nothing (one process). The distributed engine
/// (simulation/distributed.hpp) passes its own: migration after the wrap, the halo after the sort.
struct NoRebuildHooks {
  static constexpr bool local_images = true;  ///< make the periodic images here (make_ghosts)
  template <class Store> void after_wrap(Store&) {}
  template <class Store> void after_ghosts(Store&) {}
};

template <class D, class State, bool HasState>
class PairList {
 public:
  using Vec = typename D::Vec;
  using Image = typename ParticleStore<D>::Image;
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  std::vector<std::uint32_t> row_begin;   ///< size owned + 1
  std::vector<std::uint32_t> nbr;         ///< partner slot per entry
  std::vector<std::uint32_t> slot;        ///< history slot per entry, kNone if none (empty when !HasState)
  struct HistoryPool {
    std::vector<State> states;
    std::vector<std::uint32_t> free;  ///< slots of states given back, reused first
  };
  std::vector<HistoryPool> pools;         ///< per cell layer (empty when !HasState)
  std::vector<std::uint32_t> wall_begin;  ///< size owned + 1
  std::vector<WallEntry> wall;            ///< wall candidates per row
  std::vector<std::uint32_t> wall_row;    ///< row of each wall entry (derived from wall_begin)
  std::vector<State> wall_state;          ///< history per wall entry (empty when !HasState)
  std::vector<std::uint32_t> layer_begin; ///< row ranges of the cell layers (size layers + 1)
  /// Positions of the real particles at the last build, in single precision: the rebuild test
  /// needs them only to a small fraction of the skin, and they are 12 of the ~490 bytes a 3D
  /// particle costs (docs/performance.md, "Memory"). build_rounding bounds the error.
  using BuildPosition = Eigen::Matrix<float, D::dim, 1>;
  std::vector<BuildPosition> x_at_build;
  double build_rounding = 0.0;            ///< max over particles of |x - x_at_build| at the build [m]
  std::size_t builds = 0;

  /// Changes whenever the rows, or the particles their slots name, may have changed (a rebuild,
  /// a load): data derived from the rows and the particles' radii and masses (the engine's
  /// per-pair constants) is stale when this differs from its value at the derivation. Not saved.
  std::uint64_t generation() const { return generation_; }

  std::size_t layers() const { return layer_begin.empty() ? 0 : layer_begin.size() - 1; }
  std::size_t entries() const { return nbr.size(); }

  /// History of entry e (its row in layer l), nullptr if it has none (zero history).
  State* history(std::size_t l, std::uint32_t e) {
    return slot[e] == kNone ? nullptr : &pools[l].states[slot[e]];
  }
  const State* history(std::size_t l, std::uint32_t e) const {
    return slot[e] == kNone ? nullptr : &pools[l].states[slot[e]];
  }
  /// Gives entry e (its row in layer l) a zero history slot if it has none.
  void acquire(std::size_t l, std::uint32_t e) {
    if (slot[e] != kNone) return;
    HistoryPool& pool = pools[l];
    if (!pool.free.empty()) {
      slot[e] = pool.free.back();
      pool.free.pop_back();
      pool.states[slot[e]] = State{};
      return;
    }
    // Grow by a quarter, not the doubling of push_back: pools hold most of the list's memory.
    if (pool.states.size() == pool.states.capacity())
      pool.states.reserve(pool.states.size() + pool.states.size() / 4 + 8);
    slot[e] = static_cast<std::uint32_t>(pool.states.size());
    pool.states.emplace_back();
  }
  /// Entry e (its row in layer l) separated: its history, if any, is forgotten.
  void drop(std::size_t l, std::uint32_t e) {
    if (slot[e] == kNone) return;
    pools[l].free.push_back(slot[e]);
    slot[e] = kNone;
  }
  /// Entries holding a history slot.
  std::size_t histories() const {
    std::size_t c = 0;
    for (const auto& pool : pools) c += pool.states.size() - pool.free.size();
    return c;
  }

  /// Computes the transfer keys of every pair that holds history from the store as it is, and
  /// lets go of the rows: call it before the store's slots change (particles added or removed);
  /// rebuild() calls it itself. Until the next rebuild the list must not be used.
  void detach(const ParticleStore<D>& p) {
    if (detached_ || row_begin.empty()) return;
    detached_ = true;
    ++generation_;
    const std::size_t n = row_begin.size() - 1;
    old_row_of_id_.swap(row_of_id_);
    old_wall_begin_.swap(wall_begin);
    old_wall_.swap(wall);
    old_wall_state_.swap(wall_state);
    if constexpr (HasState) {
      old_row_begin_.assign(n + 1, 0);
      old_key_.clear();
      old_state_.clear();
      const std::size_t held = histories();
      old_key_.reserve(held);
      old_state_.reserve(held);
      for (std::size_t l = 0; l < layers(); ++l) {
        for (std::size_t i = layer_begin[l]; i < layer_begin[l + 1]; ++i) {
          for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e) {
            if (slot[e] == kNone) continue;
            old_key_.push_back(pair_key(p, i, nbr[e]));
            old_state_.push_back(pools[l].states[slot[e]]);
          }
          old_row_begin_[i + 1] = static_cast<std::uint32_t>(old_key_.size());
        }
      }
    }
    release(row_begin, nbr, slot, pools);
  }

  /// Rebuilds the list. `reversed(State&)` turns a pair's history into its mirror image;
  /// `collect_walls(slot, x, reach, emit)` must call emit(wall, feature) for every wall feature
  /// within `reach` of x.
  /// `hooks` (NoRebuildHooks): after_wrap(p) may remove and add real particles (the detached
  /// history can be extended with add_detached_row), after_ghosts(p) may append ghosts; with
  /// local_images false no periodic images are made here.
  template <class Policy, class Reverse, class CollectWalls, class Hooks = NoRebuildHooks>
  void rebuild(ParticleStore<D>& p, const Domain<D>& dom, double skin, Reverse&& reversed,
               CollectWalls&& collect_walls, Hooks&& hooks = Hooks{}) {
    detach(p);
    domain_cache_ = dom;
    p.clear_ghosts();
    wrap(p, dom);
    hooks.after_wrap(p);
    const std::size_t n = p.owned();
    double r_max = 0.0;
    for (std::size_t i = 0; i < n; ++i) r_max = std::max(r_max, p.radius[i]);
    const double range = 2.0 * r_max + skin;
    const Vec L = dom.length();
    for (int k = 0; k < D::dim; ++k)
      if (dom.periodic[k] && L[k] <= 2.0 * range)
        throw InvalidParameter("Domain: periodic length along axis " + std::to_string(k) + " = " +
                               detail::to_text(L[k]) + " m must exceed twice the interaction "
                               "range 2 (2 r_max + skin) = " + detail::to_text(2.0 * range) + " m");

    if constexpr (Policy::uses_cells) {
      setup_grid(dom, range);
      sort_by_cell(p, dom);
    }
    if constexpr (std::remove_cvref_t<Hooks>::local_images) make_ghosts(p, dom, range);
    hooks.after_ghosts(p);
    p.trim_capacity();
    if constexpr (Policy::uses_cells) bin_all(p, dom);

    build_rows<Policy>(p, skin);
    build_walls(p, skin, collect_walls);
    build_layers<Policy>(p);
    if constexpr (HasState) transfer(p, reversed);
    // The old rows are needed only for the transfer: holding them until the next rebuild would
    // double the list's memory (a rebuild every few hundred steps allocates them afresh).
    release(old_row_begin_, old_key_, old_state_, old_wall_begin_, old_wall_, old_wall_state_, old_row_of_id_);
    // Likewise the cell grid: only the rows are used between builds (about 25 B per particle).
    release(cell_of_, cell_start_, cell_items_, cell_coords_);
    record_build_positions(p, n);
    detached_ = false;
    ++builds;
    ++generation_;
  }

  /// Half the skin less the rounding of the build positions: a particle whose distance from
  /// its single-precision build position stays within this has moved at most half the skin.
  /// (0 when positions are so large that rounding eats the half skin -- then every step
  /// rebuilds; that needs |x| of about 2^23 half skins, kilometres for millimetre grains.)
  double rebuild_distance(double skin) const { return std::max(0.5 * skin - build_rounding, 0.0); }

  /// Between detach() and the rebuild (a rebuild hook's after_wrap): for each particle named in
  /// `ids` (sorted), calls f(k, key, state) for every pair history it holds -- its own row's and,
  /// reversed, those in its partners' rows -- keyed as seen from ids[k], and w(k, entry, state)
  /// for its wall histories. What a migrating particle carries (docs/mpi.md).
  template <class Reverse, class F, class W>
  void detached_histories(const std::vector<std::uint64_t>& ids, Reverse&& reversed, F&& f, W&& w) const {
    if constexpr (HasState) {
      if (!detached_ || old_row_begin_.empty()) return;
      const std::size_t rows = old_row_begin_.size() - 1;
      std::vector<std::uint64_t> row_id(rows, std::numeric_limits<std::uint64_t>::max());
      for (std::size_t id = 0; id < old_row_of_id_.size(); ++id)
        if (old_row_of_id_[id] != kNone && old_row_of_id_[id] < rows) row_id[old_row_of_id_[id]] = id;
      auto index = [&](std::uint64_t id) -> std::size_t {
        auto it = std::lower_bound(ids.begin(), ids.end(), id);
        return it != ids.end() && *it == id ? std::size_t(it - ids.begin()) : ids.size();
      };
      for (std::size_t r = 0; r < rows; ++r) {
        const std::size_t ki = index(row_id[r]);
        for (std::uint32_t o = old_row_begin_[r]; o < old_row_begin_[r + 1]; ++o) {
          if (ki < ids.size()) f(ki, old_key_[o], old_state_[o]);
          const std::size_t kj = index(old_key_[o] / kImageCodes);
          if (kj < ids.size() && row_id[r] != std::numeric_limits<std::uint64_t>::max()) {
            State s = old_state_[o];
            reversed(s);
            f(kj, row_id[r] * kImageCodes + negated_code(old_key_[o] % kImageCodes), s);
          }
        }
        if (ki < ids.size())
          for (std::uint32_t o = old_wall_begin_[r]; o < old_wall_begin_[r + 1]; ++o) w(ki, old_wall_[o], old_wall_state_[o]);
      }
    }
  }

  /// Adds the histories a particle brought from another rank (detached_histories there) as an
  /// old row of its own, for the rebuild's transfer; call from a rebuild hook's after_wrap.
  void add_detached_row(std::uint64_t id, const std::vector<std::uint64_t>& keys, const std::vector<State>& states,
                        const std::vector<WallEntry>& walls, const std::vector<State>& wall_states) {
    if constexpr (HasState) {
      if (old_row_begin_.empty()) old_row_begin_.assign(1, 0);
      if (old_wall_begin_.empty()) old_wall_begin_.assign(1, 0);
      const auto row = static_cast<std::uint32_t>(old_row_begin_.size() - 1);
      if (old_row_of_id_.size() <= id) old_row_of_id_.resize(id + 1, kNone);
      old_row_of_id_[id] = row;
      old_key_.insert(old_key_.end(), keys.begin(), keys.end());
      old_state_.insert(old_state_.end(), states.begin(), states.end());
      old_row_begin_.push_back(static_cast<std::uint32_t>(old_key_.size()));
      old_wall_.insert(old_wall_.end(), walls.begin(), walls.end());
      old_wall_state_.insert(old_wall_state_.end(), wall_states.begin(), wall_states.end());
      old_wall_begin_.push_back(static_cast<std::uint32_t>(old_wall_.size()));
    }
  }

  /// Every pair history of the real particles' rows as f(row i, partner slot j, key, state), the
  /// key as detach() makes it (partner id, relative image), and every wall entry of those rows as
  /// w(row i, entry, state, has_state). A distributed checkpoint is gathered from these.
  template <class F, class W>
  void for_each_history(const ParticleStore<D>& p, F&& f, W&& w) const {
    if (row_begin.empty()) return;
    if constexpr (HasState)
      for (std::size_t l = 0; l < layers(); ++l)
        for (std::size_t i = layer_begin[l]; i < layer_begin[l + 1]; ++i)
          for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e)
            if (slot[e] != kNone) f(i, std::size_t(nbr[e]), pair_key(p, i, nbr[e]), pools[l].states[slot[e]]);
    for (std::size_t i = 0; i + 1 < wall_begin.size(); ++i)
      for (std::uint32_t e = wall_begin[i]; e < wall_begin[i + 1]; ++e) w(i, wall[e], e);
  }
  /// The relative image a key's code names, each component in [-2, 2].
  static Image image_of_code(std::uint64_t code) {
    Image rel;
    for (int k = 0; k < D::dim; ++k, code /= 5) rel[k] = int(code % 5) <= 2 ? int(code % 5) : int(code % 5) - 5;
    return rel;
  }
  static constexpr std::uint64_t image_codes() { return kImageCodes; }

  /// Slot of the row holding particle `id` (kNone if absent); valid until the next rebuild.
  std::uint32_t row_of_id(std::uint64_t id) const {
    return id < row_of_id_.size() ? row_of_id_[id] : kNone;
  }

  /// Writes everything a later step depends on (rows, history, layers, build positions),
  /// so that a restart continues bitwise identically without an extra rebuild.
  template <class W>
  void save(W& w) const {
    w.vec(row_begin); w.vec(nbr); w.vec(slot); w.vec(wall_begin); w.vec(wall); w.vec(wall_state);
    w.vec(layer_begin); w.vec(x_at_build); w.template pod<double>(build_rounding); w.vec(row_of_id_);
    w.template pod<std::uint64_t>(pools.size());
    for (const auto& pool : pools) { w.vec(pool.states); w.vec(pool.free); }
    w.template pod<std::uint64_t>(builds);
  }
  template <class R>
  void load(R& r) {
    read_saved(r);
    index_wall_rows();
    detached_ = false;
    ++generation_;
  }

  /// Reads what save() wrote, without using it (check_loaded, then take_loaded).
  template <class R>
  void read_saved(R& r) {
    r.vec(row_begin); r.vec(nbr); r.vec(slot); r.vec(wall_begin); r.vec(wall); r.vec(wall_state);
    r.vec(layer_begin); r.vec(x_at_build); build_rounding = r.template pod<double>(); r.vec(row_of_id_);
    const auto np = r.template pod<std::uint64_t>();
    // (A pool costs at least 16 bytes of the file: a crafted count cannot allocate more than it holds.)
    if constexpr (requires { r.size(); })
      if (np > r.size() / 16) r.fail("the neighbour list names " + std::to_string(np) + " history pools");
    pools.resize(np);
    for (auto& pool : pools) { r.vec(pool.states); r.vec(pool.free); }
    builds = r.template pod<std::uint64_t>();
  }

  /// Why a list read by read_saved cannot serve a store of `owned` particles in `slots` slots
  /// (ghosts included) and `walls` walls: an index out of range, sizes that disagree, a
  /// non-finite build rounding. Empty if it can.
  std::string check_loaded(std::size_t owned, std::size_t slots, std::size_t walls) const {
    const auto csr = [&](const std::vector<std::uint32_t>& begin, std::size_t entries,
                         const std::string& what) -> std::string {
      if (begin.empty() && owned == 0 && entries == 0) return {};
      if (begin.size() != owned + 1)
        return what + " has " + std::to_string(begin.size()) + " row starts for " + std::to_string(owned) +
               " particles (needs " + std::to_string(owned + 1) + ")";
      if (begin.front() != 0 || begin.back() != entries)
        return what + " rows span [" + std::to_string(begin.front()) + ", " + std::to_string(begin.back()) +
               "), not the " + std::to_string(entries) + " entries";
      for (std::size_t i = 0; i + 1 < begin.size(); ++i)
        if (begin[i + 1] < begin[i]) return what + " row " + std::to_string(i) + " ends before it starts";
      return {};
    };
    if (auto why = csr(row_begin, nbr.size(), "the neighbour list"); !why.empty()) return why;
    if (auto why = csr(wall_begin, wall.size(), "the wall list"); !why.empty()) return why;
    for (std::size_t e = 0; e < nbr.size(); ++e)
      if (nbr[e] >= slots)
        return "neighbour entry " + std::to_string(e) + " names slot " + std::to_string(nbr[e]) + " of " +
               std::to_string(slots);
    for (std::size_t e = 0; e < wall.size(); ++e)
      if (wall[e].wall >= walls)
        return "wall entry " + std::to_string(e) + " names wall " + std::to_string(wall[e].wall) + " of " +
               std::to_string(walls);
    if (!layer_begin.empty()) {
      if (layer_begin.front() != 0 || layer_begin.back() != owned)
        return "the cell layers span rows [" + std::to_string(layer_begin.front()) + ", " +
               std::to_string(layer_begin.back()) + "), not the " + std::to_string(owned) + " particles";
      for (std::size_t l = 0; l + 1 < layer_begin.size(); ++l)
        if (layer_begin[l + 1] < layer_begin[l]) return "cell layer " + std::to_string(l) + " ends before it starts";
    }
    for (std::uint32_t r : row_of_id_)
      if (r != kNone && r >= owned) return "the id index names row " + std::to_string(r) + " of " + std::to_string(owned);
    if (!(std::isfinite(build_rounding) && build_rounding >= 0.0))
      return "the build rounding " + granule::detail::to_text(build_rounding) + " m is not a finite distance";
    if constexpr (HasState) {
      if (slot.size() != nbr.size())
        return "the list has " + std::to_string(slot.size()) + " history slots for " + std::to_string(nbr.size()) +
               " entries";
      if (wall_state.size() != wall.size())
        return "the list has " + std::to_string(wall_state.size()) + " wall histories for " +
               std::to_string(wall.size()) + " wall entries";
      if (pools.size() != layers())
        return "the list has " + std::to_string(pools.size()) + " history pools for " + std::to_string(layers()) +
               " cell layers";
      for (std::size_t l = 0; l < layers(); ++l) {
        const std::size_t held = pools[l].states.size();
        for (std::uint32_t f : pools[l].free)
          if (f >= held) return "history pool " + std::to_string(l) + " frees slot " + std::to_string(f) + " of " + std::to_string(held);
        if (row_begin.empty()) continue;
        for (std::uint32_t e = row_begin[layer_begin[l]]; e < row_begin[layer_begin[l + 1]]; ++e)
          if (slot[e] != kNone && slot[e] >= held)
            return "neighbour entry " + std::to_string(e) + " names history slot " + std::to_string(slot[e]) +
                   " of " + std::to_string(held) + " in pool " + std::to_string(l);
      }
    }
    return {};
  }

  /// Takes over what `loaded` read (read_saved), once check_loaded found nothing wrong.
  void take_loaded(PairList& loaded) {
    row_begin.swap(loaded.row_begin); nbr.swap(loaded.nbr); slot.swap(loaded.slot);
    wall_begin.swap(loaded.wall_begin); wall.swap(loaded.wall); wall_state.swap(loaded.wall_state);
    layer_begin.swap(loaded.layer_begin); x_at_build.swap(loaded.x_at_build);
    build_rounding = loaded.build_rounding;
    row_of_id_.swap(loaded.row_of_id_);
    pools.swap(loaded.pools);
    builds = loaded.builds;
    index_wall_rows();
    detached_ = false;
    ++generation_;
  }

  /// Memory held by the list, its history and the search's work arrays [bytes].
  std::size_t memory_bytes() const {
    std::size_t pooled = 0;
    for (const auto& pool : pools) pooled += pool.states.capacity() * sizeof(State) + pool.free.capacity() * 4;
    return row_begin.capacity() * 4 + nbr.capacity() * 4 + slot.capacity() * 4 + pooled +
           pools.capacity() * sizeof(HistoryPool) + wall_begin.capacity() * 4 +
           wall.capacity() * sizeof(WallEntry) + wall_row.capacity() * 4 +
           wall_state.capacity() * sizeof(State) * HasState +
           x_at_build.capacity() * sizeof(BuildPosition) + cell_start_.capacity() * 4 +
           cell_items_.capacity() * 4 + row_of_id_.capacity() * 4 + layer_begin.capacity() * 4 +
           cell_of_.capacity() * 4 + cell_coords_.capacity() * sizeof(cell_coords_[0]) +
           order_.capacity() * sizeof(int);
  }

 private:
  template <class... V>
  static void release(V&... v) {
    (std::remove_reference_t<V>().swap(v), ...);
  }

  void record_build_positions(const ParticleStore<D>& p, std::size_t n) {
    x_at_build.resize(n);
    double worst2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      x_at_build[i] = p.x[i].template cast<float>();
      worst2 = std::max(worst2, (p.x[i] - x_at_build[i].template cast<double>()).squaredNorm());
    }
    build_rounding = std::sqrt(worst2);
  }

  // Row ranges of the cell layers (the rows are in cell order, the layer axis slowest).
  template <class Policy>
  void build_layers(const ParticleStore<D>& p) {
    const std::size_t n = p.owned();
    layer_begin.clear();
    if constexpr (Policy::uses_cells) {
      const int a = layer_axis_;
      const int nl = ncell_[a];
      layer_begin.assign(static_cast<std::size_t>(nl) + 1, 0);
      std::size_t i = 0;
      for (int l = 0; l < nl; ++l) {
        layer_begin[l] = static_cast<std::uint32_t>(i);
        while (i < n && cell_coord(p.x[i], domain_cache_, a) <= l) ++i;
      }
      layer_begin[nl] = static_cast<std::uint32_t>(n);
    } else {
      layer_begin = {0u, static_cast<std::uint32_t>(n)};
    }
  }

  // ---- periodic wrapping --------------------------------------------------------------------
  static void wrap(ParticleStore<D>& p, const Domain<D>& dom) {
    const Vec L = dom.length();
    for (std::size_t i = 0; i < p.owned(); ++i) {
      for (int k = 0; k < D::dim; ++k) {
        if (!dom.periodic[k]) continue;
        if (p.x[i][k] < dom.lo[k] || p.x[i][k] >= dom.hi[k]) {
          const double s = std::floor((p.x[i][k] - dom.lo[k]) / L[k]);
          p.x[i][k] -= s * L[k];
          if (p.x[i][k] >= dom.hi[k]) p.x[i][k] = dom.lo[k];  // round-off at the face
          p.image[i][k] += static_cast<int>(s);
        }
      }
    }
  }

  // ---- cells ---------------------------------------------------------------------------------
  void setup_grid(const Domain<D>& dom, double range) {
    const Vec L = dom.length();
    int best = 0;
    for (int k = 0; k < D::dim; ++k) {
      ncell_[k] = std::max(1, static_cast<int>(std::floor(L[k] / range)));
      // Bound the grid so a sparse box cannot exhaust memory.
      ncell_[k] = std::min(ncell_[k], 1 << 20);
      cell_size_[k] = L[k] / ncell_[k];
      margin_[k] = dom.periodic[k] ? 1 : 0;
      ext_[k] = ncell_[k] + 2 * margin_[k];
      if (ncell_[k] > ncell_[best]) best = k;
    }
    layer_axis_ = best;
    // Linear cell index with the layer axis slowest.
    order_.clear();
    order_.push_back(layer_axis_);
    for (int k = 0; k < D::dim; ++k)
      if (k != layer_axis_) order_.push_back(k);
    std::size_t total = 1;
    for (int k = 0; k < D::dim; ++k) total *= static_cast<std::size_t>(ext_[k]);
    if (total > (std::size_t(1) << 28))
      throw InvalidParameter("PairList: the cell grid would have " + std::to_string(total) +
                             " cells; the domain is too large for the particle size (reduce the "
                             "domain or increase the skin)");
    ncells_total_ = total;
  }

  int cell_coord(const Vec& x, const Domain<D>& dom, int k) const {
    int c = static_cast<int>(std::floor((x[k] - dom.lo[k]) / cell_size_[k]));
    return std::clamp(c, -margin_[k], ncell_[k] - 1 + margin_[k]);
  }

  std::size_t cell_index(const Vec& x, const Domain<D>& dom) const {
    std::size_t idx = 0;
    for (int k : order_) idx = idx * ext_[k] + static_cast<std::size_t>(cell_coord(x, dom, k) + margin_[k]);
    return idx;
  }

  void sort_by_cell(ParticleStore<D>& p, const Domain<D>& dom) {
    const std::size_t n = p.owned();
    cell_of_.resize(n);
    std::vector<std::uint32_t> count(ncells_total_ + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      cell_of_[i] = static_cast<std::uint32_t>(cell_index(p.x[i], dom));
      ++count[cell_of_[i] + 1];
    }
    for (std::size_t c = 0; c < ncells_total_; ++c) count[c + 1] += count[c];
    std::vector<std::uint32_t> perm(n);
    for (std::size_t i = 0; i < n; ++i) perm[count[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
    p.permute(perm);
  }

  void bin_all(const ParticleStore<D>& p, const Domain<D>& dom) {
    const std::size_t m = p.size();
    cell_of_.resize(m);
    cell_start_.assign(ncells_total_ + 1, 0);
    for (std::size_t i = 0; i < m; ++i) {
      cell_of_[i] = static_cast<std::uint32_t>(cell_index(p.x[i], dom));
      ++cell_start_[cell_of_[i] + 1];
    }
    for (std::size_t c = 0; c < ncells_total_; ++c) cell_start_[c + 1] += cell_start_[c];
    cell_items_.resize(m);
    std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < m; ++i) cell_items_[fill[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  }

  // ---- ghosts --------------------------------------------------------------------------------
  void make_ghosts(ParticleStore<D>& p, const Domain<D>& dom, double range) {
    if (!dom.periodic.any()) return;
    // Shifts in the positive half of {-1,0,1}^d (first non-zero component +1), restricted to
    // periodic axes: each periodic pair then appears exactly once.
    std::vector<Image> shifts;
    const int total = D::dim == 2 ? 9 : 27;
    for (int code = 0; code < total; ++code) {
      Image s;
      int c = code;
      bool ok = true;
      for (int k = 0; k < D::dim; ++k) {
        s[k] = c % 3 - 1;
        c /= 3;
        if (s[k] != 0 && !dom.periodic[k]) ok = false;
      }
      if (!ok || s.isZero()) continue;
      int first = 0;
      for (int k = 0; k < D::dim; ++k)
        if (s[k] != 0) { first = s[k]; break; }
      if (first > 0) shifts.push_back(s);
    }
    const std::size_t n = p.owned();
    for (std::size_t i = 0; i < n; ++i) {
      for (const Image& s : shifts) {
        bool near = true;
        for (int k = 0; k < D::dim && near; ++k) {
          if (s[k] > 0) near = p.x[i][k] < dom.lo[k] + range;
          if (s[k] < 0) near = p.x[i][k] > dom.hi[k] - range;
        }
        if (near) p.add_ghost(static_cast<std::uint32_t>(i), s, dom.length());
      }
    }
  }

  // ---- rows ----------------------------------------------------------------------------------
  template <class Policy>
  void build_rows(const ParticleStore<D>& p, double skin) {
    const std::size_t n = p.owned();
    row_begin.assign(n + 1, 0);
    auto pair_ok = [&](std::size_t i, std::size_t j) {
      // Two particles that contacts cannot move (frozen or prescribed) exert nothing on
      // each other that matters; their effective mass would be infinite.
      if (p.inv_mass[i] + p.inv_mass[j] == 0.0) return false;
      const double rc = p.radius[i] + p.radius[j] + skin;
      return (p.x[i] - p.x[j]).squaredNorm() < rc * rc;
    };
    auto visit = [&](std::size_t i, auto&& emit) {
      if constexpr (Policy::uses_cells) {
        Eigen::Matrix<int, D::dim, 1> c;
        for (int k = 0; k < D::dim; ++k) c[k] = cell_coord_cached(i, k);
        const int total = D::dim == 2 ? 9 : 27;
        for (int code = 0; code < total; ++code) {
          int cc = code;
          std::size_t idx = 0;
          bool inside = true;
          Eigen::Matrix<int, D::dim, 1> q;
          for (int k = 0; k < D::dim; ++k) {
            q[k] = c[k] + cc % 3 - 1;
            cc /= 3;
            if (q[k] < -margin_[k] || q[k] > ncell_[k] - 1 + margin_[k]) inside = false;
          }
          if (!inside) continue;
          for (int k : order_) idx = idx * ext_[k] + static_cast<std::size_t>(q[k] + margin_[k]);
          for (std::uint32_t t = cell_start_[idx]; t < cell_start_[idx + 1]; ++t) {
            const std::uint32_t j = cell_items_[t];
            if (j < n && j <= i) continue;
            if (pair_ok(i, j)) emit(j);
          }
        }
      } else {
        for (std::size_t j = i + 1; j < p.size(); ++j)
          if (pair_ok(i, j)) emit(static_cast<std::uint32_t>(j));
      }
    };
    cell_coords_.resize(n);
    if constexpr (Policy::uses_cells) {
      for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < D::dim; ++k) cell_coords_[i][k] = cell_coord(p.x[i], domain_cache_, k);
    }
    if (n < kParallelRows) {
      // One thread: the rows appended in one pass (the two passes below, counting and then
      // filling, visit every candidate twice: 2 % of a 1600-disk 2D step).
      nbr.clear();
      for (std::size_t i = 0; i < n; ++i) {
        visit(i, [&](std::uint32_t j) { nbr.push_back(j); });
        std::sort(nbr.begin() + row_begin[i], nbr.end());
        row_begin[i + 1] = static_cast<std::uint32_t>(nbr.size());
      }
    } else {
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t cnt = 0;
        visit(i, [&](std::uint32_t) { ++cnt; });
        row_begin[i + 1] = cnt;
      }
      for (std::size_t i = 0; i < n; ++i) row_begin[i + 1] += row_begin[i];
      nbr.resize(row_begin[n]);
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t pos = row_begin[i];
        visit(i, [&](std::uint32_t j) { nbr[pos++] = j; });
        std::sort(nbr.begin() + row_begin[i], nbr.begin() + row_begin[i + 1]);
      }
    }
    row_of_id_.assign(max_id(p) + 1, kNone);
    for (std::size_t i = 0; i < n; ++i) row_of_id_[p.id[i]] = static_cast<std::uint32_t>(i);
    if constexpr (HasState) slot.assign(nbr.size(), kNone);
  }

  static constexpr std::size_t kParallelRows = 2048;  ///< rows from which build_rows uses threads

  int cell_coord_cached(std::size_t i, int k) const { return cell_coords_[i][k]; }

  template <class CollectWalls>
  void build_walls(const ParticleStore<D>& p, double skin, CollectWalls&& collect_walls) {
    const std::size_t n = p.owned();
    wall_begin.assign(n + 1, 0);
    wall.clear();
    for (std::size_t i = 0; i < n; ++i) {
      collect_walls(i, p.x[i], p.radius[i] + skin, [&](std::uint32_t w, std::uint32_t feature) {
        wall.push_back({w, feature});
      });
      wall_begin[i + 1] = static_cast<std::uint32_t>(wall.size());
    }
    if constexpr (HasState) wall_state.assign(wall.size(), State{});
    index_wall_rows();
  }

  // The packed loop walks a layer's wall entries, not its rows: most rows have none.
  void index_wall_rows() {
    wall_row.resize(wall.size());
    for (std::size_t i = 0; i + 1 < wall_begin.size(); ++i)
      for (std::uint32_t e = wall_begin[i]; e < wall_begin[i + 1]; ++e) wall_row[e] = static_cast<std::uint32_t>(i);
  }

  static std::size_t max_id(const ParticleStore<D>& p) {
    std::uint64_t m = 0;
    for (std::size_t i = 0; i < p.owned(); ++i) m = std::max(m, p.id[i]);
    return static_cast<std::size_t>(m);
  }

  /// Relative periodic image of j as seen from row i, folded into [0, 5^d).
  static std::uint64_t image_code(const Image& rel) {
    std::uint64_t code = 0;
    for (int k = D::dim - 1; k >= 0; --k) code = code * 5 + static_cast<std::uint64_t>(((rel[k] % 5) + 5) % 5);
    return code;
  }
  static constexpr std::uint64_t kImageCodes = D::dim == 2 ? 25 : 125;
  /// The code of -rel from the code of rel.
  static std::uint64_t negated_code(std::uint64_t code) {
    std::uint64_t out = 0, scale = 1;
    for (int k = 0; k < D::dim; ++k, code /= 5, scale *= 5) out += ((5 - code % 5) % 5) * scale;
    return out;
  }

  static Image relative_image(const ParticleStore<D>& p, std::size_t i, std::size_t j) {
    // (A remote ghost's image counter already has its shift taken off.)
    if (j < p.owned() || j - p.owned() >= p.local_ghosts()) return Image(p.image[i] - p.image[j]);
    const std::size_t g = j - p.owned();
    const std::uint32_t o = p.ghost_owner[g];
    return Image(p.ghost_shift[g] - p.image[o] + p.image[i]);
  }

  static std::uint64_t pair_key(const ParticleStore<D>& p, std::size_t i, std::size_t j) {
    return p.id[j] * kImageCodes + image_code(relative_image(p, i, j));
  }

  // Capacity of a pool that holds `held` histories after a rebuild: room for the contacts that
  // form before the next one (more grow the pool by a quarter, see acquire).
  static std::size_t spare_room(std::size_t held) { return held + held / 16 + 8; }

  // Gives each new entry the history its pair held in the old rows (detach()), in the same row
  // or, reversed, in the partner's; layer by layer, as each layer fills its own pool, sized for the
  // pairs that touch now.
  template <class Reverse>
  void transfer(const ParticleStore<D>& p, Reverse&& reversed) {
    const std::size_t nl = layers();
    pools.assign(nl, HistoryPool{});
    const bool has_old = !old_row_begin_.empty();
    auto old_history = [&](std::uint32_t old_row, std::uint64_t key) -> const State* {
      for (std::uint32_t o = old_row_begin_[old_row]; o < old_row_begin_[old_row + 1]; ++o)
        if (old_key_[o] == key) return &old_state_[o];
      return nullptr;
    };
    auto old_row = [&](std::uint64_t id) { return id < old_row_of_id_.size() ? old_row_of_id_[id] : kNone; };
#pragma omp parallel for schedule(dynamic, 1) if (p.owned() >= 2048)
    for (std::size_t l = 0; l < nl; ++l) {
      auto& states = pools[l].states;
      // The pairs that touch now take slots at the next step, whether they held history or not.
      std::size_t touching = 0;
      for (std::size_t i = layer_begin[l]; i < layer_begin[l + 1]; ++i)
        for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e) {
          const double rs = p.radius[i] + p.radius[nbr[e]];
          touching += (p.x[i] - p.x[nbr[e]]).squaredNorm() < rs * rs;
        }
      states.reserve(spare_room(touching));
      for (std::size_t i = layer_begin[l]; i < layer_begin[l + 1] && has_old; ++i) {
        const std::uint64_t id_i = p.id[i];
        const std::uint32_t old_i = old_row(id_i);
        for (std::uint32_t e = row_begin[i]; e < row_begin[i + 1]; ++e) {
          const std::uint32_t j = nbr[e];
          const Image rel = relative_image(p, i, j);
          const std::uint64_t id_j = p.id[j];  // a ghost carries its owner's id
          const State* h = old_i != kNone ? old_history(old_i, id_j * kImageCodes + image_code(rel)) : nullptr;
          bool reverse = false;
          if (!h) {
            // The pair may have been stored in the partner's row, seen from the other side.
            const std::uint32_t old_j = old_row(id_j);
            if (old_j != kNone) h = old_history(old_j, id_i * kImageCodes + image_code(Image(-rel)));
            reverse = h != nullptr;
          }
          if (!h) continue;
          slot[e] = static_cast<std::uint32_t>(states.size());
          states.push_back(*h);
          if (reverse) reversed(states.back());
        }
      }
      // No more room than spare_room: push_back may have doubled the capacity.
      const std::size_t room = spare_room(std::max(states.size(), touching));
      if (states.capacity() > room) {
        std::vector<State> fitted;
        fitted.reserve(room);
        fitted.assign(states.begin(), states.end());
        states.swap(fitted);
      } else {
        states.reserve(room);
      }
    }
    for (std::size_t i = 0; i < p.owned() && has_old; ++i) {
      const std::uint32_t old_i = old_row(p.id[i]);
      if (old_i == kNone) continue;
      for (std::uint32_t e = wall_begin[i]; e < wall_begin[i + 1]; ++e)
        for (std::uint32_t o = old_wall_begin_[old_i]; o < old_wall_begin_[old_i + 1]; ++o)
          if (old_wall_[o].key() == wall[e].key()) { wall_state[e] = old_wall_state_[o]; break; }
    }
  }

  Domain<D> domain_cache_;
  int ncell_[D::dim] = {};
  int ext_[D::dim] = {};
  int margin_[D::dim] = {};
  double cell_size_[D::dim] = {};
  int layer_axis_ = 0;
  std::vector<int> order_;
  std::size_t ncells_total_ = 0;
  std::vector<std::uint32_t> cell_of_, cell_start_, cell_items_;
  std::vector<Eigen::Matrix<int, D::dim, 1>> cell_coords_;
  std::vector<std::uint32_t> row_of_id_;
  bool detached_ = false;
  std::uint64_t generation_ = 0;
  std::vector<std::uint32_t> old_row_begin_, old_row_of_id_, old_wall_begin_;
  std::vector<std::uint64_t> old_key_;
  std::vector<State> old_state_, old_wall_state_;
  std::vector<WallEntry> old_wall_;
};

}  // namespace granule::neighbours
