#pragma once
// parallel::MpiDomains: the distributed policy of Simulation (its fifth template parameter):
// each MPI rank owns the particles in its region of the box (parallel/decomposition.hpp),
// holds copies (ghosts) of the other ranks' particles within the halo width, and moves
// particles that leave its region, with their contact history, at every neighbour-list rebuild.
// The engine side is simulation/distributed.hpp; the design is docs/mpi.md.
//
//   granule::parallel::MpiContext mpi(argc, argv);
//   using Sim = Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList,
//                          integrators::VelocityVerlet, parallel::MpiDomains>;
//   Sim sim(config, parallel::MpiDomains(mpi));          // rank grid chosen (least cut area)
//   ... the whole scene, the same calls on every rank ...
//   sim.run(n);  auto all = sim.gather();                   // rank 0: every particle, id order
//
// This header holds the policy's data and its messages (the C API of MPI, through the
// context's communicator); nothing here knows the particles' layout.
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "granule/parallel/decomposition.hpp"
#include "granule/parallel/mpi_context.hpp"

namespace granule::parallel {

struct MpiDomains {
  static constexpr bool distributed = true;
  static constexpr const char* name = "mpi";

  /// `grid`: parts per axis (their product must be the number of ranks); all zero: the grid of
  /// least cut area (choose_grid) for the halo width.
  explicit MpiDomains(const MpiContext& context, RankGrid grid = RankGrid{{0, 0, 0}})
      : context_(&context), grid_(grid) {}

  const MpiContext& context() const { return *context_; }
  const RankGrid& grid() const { return grid_; }

  /// Runtime load balance: at a rebuild, when the particle counts' max/mean over the ranks
  /// exceeds `threshold` (>= 1; 0 turns it off), new cuts are made from every particle's
  /// position (Decomposition::balanced on the same rank grid) and the particles migrate.
  MpiDomains& rebalance(double threshold) {
    require(threshold == 0.0 || (threshold >= 1.0 && std::isfinite(threshold)), "MpiDomains", "rebalance threshold",
            threshold, "0 (off) or [1, inf)");
    threshold_ = threshold;
    return *this;
  }
  double rebalance_threshold() const { return threshold_; }
  /// The first build cuts the box uniformly instead of balancing on the particles (tests, and
  /// a scene that fills the box later).
  MpiDomains& uniform_start(bool on = true) {
    uniform_start_ = on;
    return *this;
  }
  bool starts_uniform() const { return uniform_start_; }

  /// The per-simulation data: the decomposition, the halo plan and the messages.
  template <class D>
  class Engine {
   public:
    using Shift = Eigen::Matrix<int, D::dim, 1>;
    struct Send {
      std::uint32_t slot = 0;  ///< owned slot sent
      Shift shift = Shift::Zero();  ///< periodic image it is sent in
    };

    explicit Engine(const MpiDomains& p)
        : threshold(p.threshold_), uniform_start(p.uniform_start_), context_(p.context_), grid_(p.grid_) {}

    /// Load balance (MpiDomains::rebalance): the threshold, whether the first cuts are uniform,
    /// how often the cuts were remade, and the imbalance of the particle counts at the last
    /// rebuild (after any rebalance) and before the last rebalance.
    double threshold = 1.2;
    bool uniform_start = false;
    std::uint64_t rebalances = 0;
    double imbalance = 1.0, imbalance_before_rebalance = 1.0;
    /// Seconds spent remaking cuts (the gather of positions and the new cuts; the migration
    /// that follows is part of the rebuild).
    double rebalance_seconds = 0.0;
    /// Cost counters of this rank (benchmarks/mpi/bed.cpp): payload bytes and non-empty
    /// messages it sent through exchange() (migration, halo build, ghost refresh), and seconds
    /// in migration (after the wrap), the halo build and the ghost refresh.
    mutable std::uint64_t sent_bytes = 0, sent_messages = 0;
    double migration_seconds = 0.0, halo_seconds = 0.0, refresh_seconds = 0.0;

    int rank() const { return context_->rank(); }
    int ranks() const { return context_->size(); }
    const MpiContext& context() const { return *context_; }
    MPI_Comm comm() const { return context_->comm(); }
    const RankGrid& requested_grid() const { return grid_; }

    /// The decomposition, made at the first build from every particle (all ranks hold the
    /// whole scene then, so all make the same without a message).
    std::optional<Decomposition<D>> decomposition;
    /// Halo plan of the last build: what goes to each rank, how many come from each, where
    /// the remote ghosts start in the store.
    std::vector<std::vector<Send>> send;
    std::vector<std::size_t> receive;
    std::size_t remote_begin = 0;
    /// Counters for tests and logs: particles sent away, contact histories they carried.
    std::uint64_t migrated = 0, carried_histories = 0;
    /// Particles over all ranks at the last build.
    std::uint64_t total = 0;
    /// Insertion and removal between builds (docs/mpi.md, "Insertion and removal"): the
    /// Simulation's next id at the last build (every rank's add_particle calls since then
    /// advance it alike; a new particle is kept by the rank that owns its position only), and
    /// the particles this rank removed since then.
    std::uint64_t next_id_at_build = 0;
    std::uint64_t removed_since_build = 0;

    bool any(bool b) const {
      int in = b ? 1 : 0, out = 0;
      MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, comm());
      return out != 0;
    }
    double max(double x) const { return context().max(x); }
    std::uint64_t sum(std::uint64_t x) const {
      std::uint64_t out = 0;
      MPI_Allreduce(&x, &out, 1, MPI_UINT64_T, MPI_SUM, comm());
      return out;
    }

    /// Element-wise maximum and sum over the ranks, in place (one collective for several
    /// values).
    void max(std::vector<double>& a) const {
      MPI_Allreduce(MPI_IN_PLACE, a.data(), static_cast<int>(a.size()), MPI_DOUBLE, MPI_MAX, comm());
    }
    void sum(std::vector<std::uint64_t>& a) const {
      MPI_Allreduce(MPI_IN_PLACE, a.data(), static_cast<int>(a.size()), MPI_UINT64_T, MPI_SUM, comm());
    }

    /// Element-wise sum of equal-length arrays added in rank order, ((a_0 + a_1) + a_2) + ...,
    /// the same bits on every rank (body and wall forces, docs/mpi.md).
    void sum_in_rank_order(std::vector<double>& a) const {
      const int n = static_cast<int>(a.size());
      if (n == 0) return;
      std::vector<double> all(context().root() ? a.size() * static_cast<std::size_t>(ranks()) : 0);
      MPI_Gather(a.data(), n, MPI_DOUBLE, all.data(), n, MPI_DOUBLE, 0, comm());
      if (context().root())
        for (int r = 1; r < ranks(); ++r)
          for (int k = 0; k < n; ++k) a[k] += all[static_cast<std::size_t>(r) * a.size() + k];
      MPI_Bcast(a.data(), n, MPI_DOUBLE, 0, comm());
    }

    /// Rank 0's bytes on every rank (checkpoints: the file read, the outcome of the write).
    void broadcast(std::string& s) const {
      std::uint64_t n = s.size();
      MPI_Bcast(&n, 1, MPI_UINT64_T, 0, comm());
      s.resize(static_cast<std::size_t>(n));
      // (Chunks below 2^31 bytes: MPI counts are ints.)
      for (std::uint64_t at = 0; at < n; at += (std::uint64_t(1) << 30)) {
        const int len = static_cast<int>(std::min<std::uint64_t>(n - at, std::uint64_t(1) << 30));
        MPI_Bcast(s.data() + at, len, MPI_CHAR, 0, comm());
      }
    }

    /// Sends out[r] to rank r, returns what every rank sent here, by source rank (sizes are
    /// exchanged first).
    std::vector<std::vector<char>> exchange(const std::vector<std::vector<char>>& out) const {
      const int R = ranks();
      std::vector<int> scount(R), rcount(R);
      for (int r = 0; r < R; ++r) scount[r] = static_cast<int>(out[r].size());
      MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, comm());
      std::vector<std::vector<char>> in(R);
      for (int r = 0; r < R; ++r) in[r].resize(static_cast<std::size_t>(rcount[r]));
      exchange_known(out, in);
      return in;
    }

    /// As exchange(), with the sizes of in[] already set (a fixed plan: the ghost refresh).
    /// Point to point with the ranks that have something to send or receive (both sides know
    /// the sizes), so a step's refresh costs messages to the halo's neighbours only, not a
    /// collective over all ranks (MPI_Alltoallv visits every rank: at 1000 ranks that is ~1000
    /// latencies per step; docs/performance.md, "Distributed runs").
    void exchange_known(const std::vector<std::vector<char>>& out, std::vector<std::vector<char>>& in) const {
      const int R = ranks(), me = rank();
      constexpr int tag = 28;  // one exchange at a time: every request completes below
      std::vector<MPI_Request> requests;
      requests.reserve(2 * static_cast<std::size_t>(R));
      for (int r = 0; r < R; ++r)
        if (r != me && !in[r].empty())
          MPI_Irecv(in[r].data(), static_cast<int>(in[r].size()), MPI_BYTE, r, tag, comm(),
                    &requests.emplace_back());
      for (int r = 0; r < R; ++r) {
        if (r == me || out[r].empty()) continue;
        sent_bytes += out[r].size();
        ++sent_messages;
        MPI_Isend(out[r].data(), static_cast<int>(out[r].size()), MPI_BYTE, r, tag, comm(), &requests.emplace_back());
      }
      if (!in[me].empty()) std::memcpy(in[me].data(), out[me].data(), in[me].size());
      MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    }

    /// Every rank's values on every rank, in rank order.
    std::vector<double> all_gather(const std::vector<double>& mine) const {
      const int R = ranks();
      int n = static_cast<int>(mine.size());
      std::vector<int> counts(R), displ(R);
      MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm());
      int total = 0;
      for (int r = 0; r < R; ++r) { displ[r] = total; total += counts[r]; }
      std::vector<double> all(static_cast<std::size_t>(total));
      MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displ.data(), MPI_DOUBLE, comm());
      return all;
    }

    /// Every rank's bytes on rank 0, in rank order (other ranks: empty).
    std::vector<char> gather_to_root(const std::vector<char>& mine) const {
      const int R = ranks();
      int n = static_cast<int>(mine.size());
      std::vector<int> counts(context().root() ? R : 0), displ(context().root() ? R : 0);
      MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm());
      std::vector<char> all;
      if (context().root()) {
        int total = 0;
        for (int r = 0; r < R; ++r) { displ[r] = total; total += counts[r]; }
        all.resize(static_cast<std::size_t>(total));
      }
      MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), displ.data(), MPI_BYTE, 0, comm());
      return all;
    }

   private:
    const MpiContext* context_;
    RankGrid grid_;
  };

 private:
  const MpiContext* context_;
  RankGrid grid_;
  double threshold_ = 1.2;
  bool uniform_start_ = false;
};

}  // namespace granule::parallel
