#pragma once
// Simulation: particles, materials, walls on bodies, a contact model and a neighbour search,
// advanced in time by velocity Verlet (translation and rotation).
//
//   Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList> sim(config);
//
// One step (Allen & Tildesley 1987, velocity Verlet -- the default Integrator policy; the force
// uses the half-step velocity as in LAMMPS/LIGGGHTS nve/sphere):
//   v += dt/2 F/m,  omega += dt/2 T/I,  x += dt v        (prescribed particles: x += dt v(t+dt/2))
//   bodies move; the neighbour list is rebuilt if any particle or wall moved more than skin/2
//   F, T <- gravity + contacts (pair loop in three colours of cell layers, then walls)
//   v += dt/2 F/m,  omega += dt/2 T/I
// Determinism: every particle's force is summed in an order fixed by the list alone (its row,
// then rows of earlier colours, in row order), so results are bitwise identical for any number
// of threads. See docs/architecture.md.
//
// This header holds the class: its public API, step() (the outline above, in code) and the
// declarations of its parts; the parts' definitions are in granule/simulation/, one file each,
// included at the end (docs/architecture.md, "Simulation in parts").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "granule/analysis/frame.hpp"
#include "granule/boundaries/body.hpp"
#include "granule/boundaries/wall.hpp"
#include "granule/contact/model.hpp"
#include "granule/contact/packed.hpp"
#include "granule/contact/touch_scan.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"
#include "granule/core/vec2_lanes.hpp"
#include "granule/integrators/predicted_damping.hpp"
#include "granule/integrators/symplectic_euler.hpp"
#include "granule/integrators/velocity_verlet.hpp"
#include "granule/materials/material_table.hpp"
#include "granule/materials/time_step.hpp"
#include "granule/neighbours/domain.hpp"
#include "granule/neighbours/pair_list.hpp"
#include "granule/neighbours/policies.hpp"
#include "granule/parallel/single_process.hpp"
#include "granule/particles/particle_store.hpp"
#include "granule/simulation/config.hpp"
#include "granule/simulation/force_work.hpp"
#include "granule/simulation/gathered.hpp"

namespace granule {

// Parallel: parallel::SingleProcess (the default: one process, no MPI) or parallel::MpiDomains
// (parallel/mpi_domains.hpp: domain decomposition over MPI ranks, docs/mpi.md).
template <class D, class Model, class Search = neighbours::VerletList,
          class Integrator = integrators::VelocityVerlet, class Parallel = parallel::SingleProcess>
class Simulation {
 public:
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  using State = typename Model::template State<D>;
  using Params = typename Model::Params;
  using ContactModelType = Model;
  using SearchPolicy = Search;
  using IntegratorPolicy = Integrator;
  using Dimension = D;
  using ParallelPolicy = Parallel;
  static constexpr bool kHasState = Model::template has_state<D>;
  static constexpr bool kTangentialDashpot = Model::template tangential_dashpot<D>;
  static constexpr bool kRollingDashpot = Model::template rolling_dashpot<D>;
  /// Dashpots act on a predicted end-of-step velocity (integrators/predicted_damping.hpp).
  static constexpr bool kPredictDamping = integrators::predicts_damping_velocity<Integrator>();
  using List = neighbours::PairList<D, State, kHasState>;
  /// The pair loop can run packed (contact/packed.hpp): 3D, a model written over D::Real, and
  /// dashpots on the kinematic velocity.
  static constexpr bool kPackable = Model::lanes && !kPredictDamping;
  /// The packed 2D loop reads each pair's R*, m* and I_r from a record per list entry, computed
  /// when the list is built or loaded (update_pair_constants), instead of 5 divisions per pack.
  /// (2D only: the 3D path is left as it was measured; its lists are 3x longer per particle.)
  static constexpr bool kPairConstants = kPackable && D::dim == 2;
  /// Below this many particles every loop runs on one thread: a parallel region costs more
  /// than it saves, and badly so when cores are oversubscribed.
  static constexpr std::size_t kParallelMinParticles = 2048;
  /// Particles (ghosts included) from which the packed pair loop prefetches each layer's
  /// particle data (prefetch_layer_pair).
  static constexpr std::size_t kPrefetchMinParticles = 8192;

  /// `par`: the parallel policy's set-up (parallel::MpiDomains: the MPI context and rank grid;
  /// nothing for SingleProcess). Distributed: every rank builds the whole scene with the same
  /// calls; the first step keeps on each rank the particles of its region (docs/mpi.md).
  explicit Simulation(const SimulationConfig<D>& config, const Parallel& par = Parallel{})
      : config_(config), dist_(par) {
    if constexpr (Parallel::distributed) {
      static_assert(!kPredictDamping, "the distributed engine does not support predicted damping yet");
      static_assert(Search::uses_cells, "the distributed engine needs a cell-based search");
    }
    config_.validate();
    if (Search::rebuild_every_step) {
      require(config_.skin <= 0.0, "SimulationConfig", "skin", config_.skin,
              std::string("(-inf, 0] for ") + Search::name + " (rebuilt every step)");
    }
    bodies_.push_back(Body<D>{});
    bodies_[0].name = "world";
  }

  // ---- set-up --------------------------------------------------------------------------------

  /// Adds a particle material; returns its index.
  std::uint32_t add_material(const Material& m) { return add_material_impl(m, false); }
  /// Adds a wall material (density may be zero; Material::rigid for a rigid wall); returns its
  /// index.
  std::uint32_t add_wall_material(const Material& m) { return add_material_impl(m, true); }

  /// Sets pair properties of materials a and b explicitly (PairOverride: e, mu_s, mu_r, eta_r,
  /// k_c, gamma, linear k_n and k_t/k_n, SDS k_roll), replacing the mixed values of
  /// docs/physics.md. a and b are
  /// particle materials, or a particle and a wall material. Fields left empty keep their
  /// value (the mix, or an earlier set_pair); materials added later do not undo it. The
  /// contact parameters are precomputed per pair, so the pair loop does not change.
  void set_pair(std::uint32_t a, std::uint32_t b, const PairOverride& o);

  /// Adds a particle and returns its stable id. `omega`: initial angular velocity [rad/s]
  /// (2D: the scalar about z). Frozen and prescribed groups set v and omega themselves.
  /// Distributed (parallel::MpiDomains): every rank makes the same calls; after the first step
  /// only the rank whose region holds x keeps the particle (docs/mpi.md).
  std::uint64_t add_particle(const Vec& x, double radius, std::uint32_t material,
                             const Vec& v = Vec::Zero(), std::uint32_t group = 0,
                             const AngVec& omega = D::zero_ang());

  /// Adds a body with prescribed kinematics; returns its index (0 is the fixed world).
  std::uint32_t add_body(const Body<D>& b);

  /// Adds a wall of the given shape and (wall) material on a body; returns its index.
  template <class Shape>
  std::uint32_t add_wall(const Shape& shape, std::uint32_t material, std::uint32_t body = 0);

  /// Switches wall `w` on or off from the next step on (a gate that opens, a lid put on). The
  /// switch rebuilds the neighbour list, which lists active walls only: the wall pass has no
  /// test to pay, an inactive wall's contacts and their history are dropped, and a wall switched
  /// on again starts with fresh contacts. The forces of the step just done (with the wall) still
  /// give the next step's first half kick, as for any change between steps. Checkpoints keep the
  /// switch.
  void set_wall_active(std::uint32_t w, bool active);

  /// Particles of `group` never move (e.g. the rough frozen floor of paper 001).
  void freeze_group(std::uint32_t group) { set_group_motion(group, Motion::Frozen, nullptr); }

  /// Particles of `group` move with velocity v(t) whatever the forces (virtual piston, shaker).
  void prescribe_group_velocity(std::uint32_t group, std::function<Vec(double)> velocity);

  /// Particles of `group` move freely again.
  void release_group(std::uint32_t group) { set_group_motion(group, Motion::Free, nullptr); }

  /// Moves particles to another group (and motion mode) by predicate on (slot).
  template <class Pred>
  void assign_group(std::uint32_t group, Pred&& pred);

  /// Removes the particles for which pred(slot) is true (e.g. above a fill height). The contact
  /// records of the current step name slots that no longer hold the same particles, so they are
  /// dropped: frame() then has no contacts until the next recorded step. Returns how many
  /// were removed. Distributed, after the first step: pred sees each rank's own particles, the
  /// call is collective and returns the count over the ranks (docs/mpi.md).
  template <class Pred>
  std::size_t remove_particles(Pred&& pred);

  /// Registers f(sim) to run after every step whose count is a multiple of n (not before the
  /// first step: call f yourself for the initial state). With `needs_contacts` the contacts of
  /// those steps are recorded for frame().
  void every(std::uint64_t n, std::function<void(Simulation&)> f, bool needs_contacts = false);

  // ---- running -------------------------------------------------------------------------------

  /// Advances `n` steps.
  void run(std::uint64_t n) {
    for (std::uint64_t s = 0; s < n; ++s) step();
  }

  /// Advances until time >= t_end.
  void run_until(double t_end) {
    while (time_ < t_end - 0.5 * config_.dt) step();
  }

  /// One velocity-Verlet step. A distributed run (Parallel::distributed, simulation/
  /// distributed.hpp) takes the same outline: the rebuild decided by all ranks, the remote ghosts
  /// refreshed, the body and wall forces summed over the ranks and every check collective.
  void step() {
    if constexpr (Parallel::distributed) {
      start_distributed();  // start_if_needed with collective checks
    } else {
      start_if_needed();
    }
    const double dt = config_.dt;
    update_group_velocities(time_ + 0.5 * dt);
    const Drift drift = kick_and_drift(dt);
    for (auto& b : bodies_) b.advance(time_, dt);
    ++step_;
    // The product, not a running sum: no rounding accumulates (20 000 steps of 5e-6 s give
    // 0.1 s, where adding dt gave 0.10000000000002962 s). Rounded once (std::fma), so that every
    // build gives the same time: `origin + n * dt` was one rounding or two depending on whether
    // the compiler fused it (GCC with -march=native did, the baseline build could not).
    time_ = std::fma(static_cast<double>(step_ - step_origin_), dt, time_origin_);
    const bool record = contacts_wanted(step_);
    if (on_any_rank(drift.list_stale) || body_needs_rebuild()) {
      rebuild_everywhere();
    } else {
      refresh_ghosts();
      if constexpr (Parallel::distributed) refresh_remote_ghosts();
    }
    collective([&] {
      // (Cleared on the way out, also by an exception: other evaluations do not know.)
      struct Clear {
        bool& flag;
        ~Clear() { flag = false; }
      } clear{one_material_};
      one_material_ = drift.one_material;
      compute_forces(record, /*owned_reset=*/kResetInDrift, /*check_finite=*/false);
    });
    if constexpr (Parallel::distributed) reduce_wall_forces();
    update_group_velocities(time_);
    collective([&] { second_kick(dt); });
    for (auto& b : bodies_) {
      // Work of the drive against the particles over this step (rectangle rule at step end).
      b.work -= (b.force.dot(b.current_velocity) + D::dot(b.torque, b.current_angular_velocity)) * dt;
    }
    if (config_.check_rolling_stability && config_.stability_check_interval > 0 &&
        step_ % config_.stability_check_interval == 0)
      collective([&] { check_rolling_time_step(); });
    for (auto& o : observers_)
      if (step_ % o.every == 0) o.f(*this);
  }

  // ---- state ---------------------------------------------------------------------------------

  double time() const { return time_; }
  double dt() const { return config_.dt; }
  std::uint64_t step_count() const { return step_; }
  const SimulationConfig<D>& config() const { return config_; }
  ParticleStore<D>& particles() { return particles_; }
  const ParticleStore<D>& particles() const { return particles_; }
  const MaterialTable& materials() const { return materials_; }
  /// Whether material m was added with add_wall_material.
  bool is_wall_material(std::uint32_t m) const {
    require(m < materials_.size(), "Simulation::is_wall_material", "m", m,
            "[0, " + std::to_string(materials_.size()) + ")");
    return wall_material_[m];
  }
  Body<D>& body(std::uint32_t b) { return bodies_.at(b); }
  const Body<D>& body(std::uint32_t b) const { return bodies_.at(b); }
  std::size_t body_count() const { return bodies_.size(); }
  const std::vector<Wall<D>>& walls() const { return walls_; }
  /// Wall w: its shape, body, whether it is active, and the force and torque (about the body's
  /// pose origin) of the particles on it at the last force evaluation.
  const Wall<D>& wall(std::uint32_t w) const { return walls_.at(w); }
  /// The torque of the particles on wall w about the point q [N m]: T_q = T_o + (o - q) x F.
  AngVec wall_torque_about(std::uint32_t w, const Vec& q) const {
    const Wall<D>& wl = walls_.at(w);
    return wl.torque + D::cross(Vec(bodies_[wl.body].pose.translation() - q), wl.force);
  }
  /// The list of the last build; its rows are empty from adding or removing particles until
  /// the next step (PairList::detach).
  const List& neighbour_list() const { return list_; }
  /// Number of touching pairs and particle-wall contacts at the last force evaluation.
  /// Distributed: over all ranks, a pair across two ranks counted once (collective).
  std::size_t contact_count() const {
    if constexpr (Parallel::distributed) return contact_count_distributed();
    return contacts_;
  }
  /// Contacts recorded at the last force evaluation that recorded them (see every()).
  const std::vector<analysis::ContactRecord<D>>& recorded_contacts() const { return records_; }

  /// Current slot of the particle with stable id `id` (throws if absent).
  std::size_t index_of(std::uint64_t id) const;

  /// Sets the time-step; the stability check runs again before the next step. Time then counts
  /// on from the present: time() = t_change + (steps since the change) x dt.
  void set_dt(double dt) {
    require(dt > 0.0 && std::isfinite(dt), "Simulation::set_dt", "dt", dt, "(0, inf) s");
    if (dt != config_.dt) {
      time_origin_ = time_;
      step_origin_ = step_;
    }
    config_.dt = dt;
    initialised_ = false;
  }

  /// Makes the next force evaluation record its contacts (frame() then includes them).
  /// For every step, see record_contacts_every_step.
  void request_contacts() { record_next_ = true; }

  /// A standing request: every force evaluation records its contacts while `on` (frame() and
  /// recorded_contacts() then hold each step's contact forces without a request_contacts()
  /// before every step). Recorded steps use the scalar pair loop, whose results agree with the
  /// packed loop to rounding only (docs/architecture.md), and cost the records' copy.
  void record_contacts_every_step(bool on = true) { record_always_ = on; }
  bool records_contacts_every_step() const { return record_always_; }

  /// Translational + rotational kinetic energy of the real particles [J].
  double kinetic_energy() const;

  /// Gravitational potential energy -sum m g . x [J] (zero at the origin).
  double gravitational_energy() const;

  /// Energy stored in all contacts: normal, tangential and rolling springs, and the potential of
  /// the adhesion (cohesion laws: zero for a separated pair; contact/cohesion/*.hpp) [J].
  double elastic_energy();

  /// Critical time of the scene [s]: the smallest Rayleigh time (Hertz laws) or linear critical
  /// time (linear laws: the collision time, or pi/2 x the damped pair's stability limit where
  /// that is smaller; linear_critical_time) over the particles present.
  double critical_time_step() const;

  /// Largest time step the checks accept [s]: time_step_safety x critical_time_step(), and,
  /// once forces have been evaluated, no more than rolling_stability_limit().
  double suggested_time_step() const;

  /// Where the rotational spring-dashpots of the current contacts (EPSD rolling) limit dt.
  struct RollingLimit {
    double limit = std::numeric_limits<double>::infinity();  ///< largest stable dt [s]
    std::size_t particle = 0;   ///< store index of the particle that sets it
    std::size_t contacts = 0;   ///< its number of contacts
  };
  /// Stability limit of the rotations under the rolling spring-dashpots (EPSD) in the contacts
  /// of the last force evaluation (infinite for models without them, or before the first step).
  /// How: Gershgorin's bound on the rotation rows (simulation/time_step.hpp); docs/physics.md,
  /// "Time step", gives how far it is below the measured onsets of instability.
  RollingLimit rolling_stability_limit() const;

  /// The rotational limit before any contact exists (checked at the first step, when
  /// rolling_stability_limit() has no contacts yet): an upper bound of it for one contact per
  /// pair of materials, loaded by the particle's weight (simulation/time_step.hpp).
  struct RollingEstimate {
    double limit = std::numeric_limits<double>::infinity();  ///< [s]
    std::uint32_t material = 0, partner = 0;  ///< the pair of materials that sets it
    double overlap = 0.0;                     ///< the reference overlap [m]
    double rolling_damping = 0.0;             ///< that pair's eta_r [-]
  };
  RollingEstimate rolling_limit_estimate() const;

  /// A self-contained snapshot for analysis and output (contacts only if they were recorded at
  /// the current step: call request_contacts() before the step, record_contacts_every_step(),
  /// or register the observer with needs_contacts = true).
  analysis::Frame<D> frame() const;

  /// Memory held by particles, list and history, and the pair loop's work arrays [bytes].
  std::size_t memory_bytes() const;

  /// Writes the dynamic state (particles, ghosts, neighbour list with history, bodies, time and
  /// its origin) to `w`. The scene's static set-up (materials, walls, group motions, observers)
  /// is not part of it: the restarting program builds the same scene and then loads the state
  /// (io/checkpoint.hpp, which also records the materials to compare them).
  template <class W>
  void save_state(W& w);

  /// The layout save_state writes: checkpoint format 5 (io/checkpoint.hpp). 4 lacks the time
  /// origin (time and step at the last change of dt), 3 also the wall states.
  static constexpr std::uint32_t kStateFormat = 5;

  /// Restores what save_state wrote into a simulation set up with the same scene. Without
  /// `wall_states` the state is read as checkpoint format 3 wrote it (before walls could be
  /// switched off): every wall is active and the wall readouts are zero until the next step.
  template <class R>
  void load_state(R& r, bool wall_states = true);

  /// Restores a state in the layout of checkpoint format `format` (3, 4 or kStateFormat). All of
  /// it is read and checked first -- the scene's dt, body, wall and material counts and group
  /// modes, array sizes, every index (materials, ghost owners, list entries, history slots) and
  /// the finiteness of every value -- and only then taken over: when r.fail() throws, the
  /// simulation is as it was. With `whole`, data after the state (r.position() < r.size()) is an
  /// error too. Formats 3 and 4 start the time origin at the state's time and step.
  template <class R>
  void load_state_format(R& r, std::uint32_t format, bool whole = false);

  /// Rebuilds the neighbour list now (normally automatic). Distributed: collective.
  void rebuild();

  /// Every particle and recorded contact in one Frame, particles in global-id order: in a
  /// distributed run on rank 0 (others: no particles), a contact across two ranks once, as seen
  /// from its lower id; in one process, frame() sorted by id. Distributed: collective.
  analysis::Frame<D> gathered_frame() const;

  /// The owned particles of every rank on rank 0 in global-id order (other ranks: empty);
  /// one process: its particles in id order. Distributed: collective.
  GatheredParticles<D> gather() const;

  /// This process's rank and the number of ranks (0 and 1 for one process).
  int rank() const { return dist_.rank(); }
  int ranks() const { return dist_.ranks(); }
  /// The parallel policy's data (parallel::MpiDomains: decomposition, halo plan, counters).
  const typename Parallel::template Engine<D>& parallel_engine() const { return dist_; }

 private:
  // Observers, and the work of one force evaluation: per-layer accumulators, the packed pass's
  // per-thread arrays and its queue of wall contacts.
  struct Observer {
    std::uint64_t every;
    std::function<void(Simulation&)> f;
    bool needs_contacts;
  };

  // The work of one force evaluation (simulation/force_work.hpp).
  using LayerAccumulator = simulation_parts::LayerAccumulator<D>;
  using PairWork = simulation_parts::PairWork;
  using WallQueue = simulation_parts::WallQueue<D, State>;

  // ---- set-up (simulation/setup.hpp) ----
  // A particle wider than the domain along a bounded axis, or one that an active wall
  // overlaps by more than max_overlap_ratio x its radius (it pokes through the wall: the first
  // step would stop as unstable), is refused here, where the call that placed it is known.
  void check_insertion(const Vec& x, double radius, const std::string& where) const;

  std::uint32_t add_material_impl(const Material& m, bool is_wall);

  void refresh_params();

  void group_mode_resize(std::uint32_t group);

  // Every particle of `group` takes motion `mode` (velocity: v(t) of a prescribed group).
  void set_group_motion(std::uint32_t group, Motion mode, std::function<Vec(double)> velocity);

  void apply_group_motion(std::size_t i);

  void update_group_velocities(double t);

  // ---- the step's particle passes (simulation/integrate.hpp) ----
  // The first kick and drift reset the forces to gravity on the way (velocity Verlet-type
  // integrators; the predicted-damping one needs the old forces in compute_forces, which resets
  // them there).
  static constexpr bool kResetInDrift = !kPredictDamping;

  struct Drift {
    bool list_stale = false;    ///< a particle moved past the rebuild distance (or no test)
    bool one_material = false;  ///< every particle has the same material
  };

  // First kick and drift of every owned particle, with the force reset and the rebuild test.
  Drift kick_and_drift(double dt);

  // Second kick; stops the run at the first particle whose state is not finite.
  void second_kick(double dt);

  // The first step builds the list and forces; a step after set_dt checks the new step.
  void start_if_needed();

  // ---- the step's upkeep: first list and forces, rebuilds, ghosts, stops (simulation/upkeep.hpp) ----
  double effective_skin() const;

  // The distance the list is built to: the skin and a tensile model's pull-off separation.
  double skin_with_reach(double skin) const;

  // Rebuilds the list with the rebuild's extra steps `hooks` (neighbours::NoRebuildHooks; the
  // distributed engine's migration and halo).
  template <class Hooks>
  void rebuild_list(double skin, double listed, Hooks&& hooks);

  void initialise();

  // The set-up evaluation: the forces of the initial state, changing no contact history.
  void setup_forces();

  bool contacts_wanted(std::uint64_t step) const;

  /// Whether a moving body has moved more than half the skin since the last build (the
  /// particles' displacement is tested in step()'s first pass).
  bool body_needs_rebuild() const;

  void refresh_ghosts();

  void check_domain() const;

  // One comparison for all components: c - c is 0 for a finite c and NaN otherwise, and a sum
  // with a NaN is NaN. (Four allFinite() calls were a compare and branch each.)
  bool finite_state(std::size_t i) const;

  [[noreturn]] void throw_instability(std::size_t i, const std::string& why) const;

  // ---- time-step and stability checks (simulation/time_step.hpp) ----
  // Every pair of materials that can touch (not two wall materials) against the laws' own
  // requirements (ContactModel::validate), naming the pair.
  void check_pair_parameters() const;

  void check_time_step() const;

  // dt against rolling_stability_limit(): a bad step stops the run with the particle that
  // sets the limit (the excess shows as spin that the dashpots pump up to the mobilisation
  // limit, not as a blow-up, so no later test would catch it).
  void check_rolling_time_step() const;

  // ---- contact geometry (simulation/contact_geometry.hpp) ----
  // Builds the contact geometry of pair (i, j); returns false if not touching. A tensile
  // model's formed contact touches to a separation of `reach` (overlap > -reach).
  bool pair_geometry(std::size_t i, std::size_t j, contact::ContactGeometry<D>& g, double reach = 0.0) const;

  // Builds the contact geometry of particle i against a wall surface point.
  bool wall_geometry(std::size_t i, const geometry::SurfacePoint<D>& sp, const Body<D>& b,
                     contact::ContactGeometry<D>& g, double reach = 0.0) const;

  // How far apart pair (i, j) with history h still touches: the pull-off separation once the
  // contact has formed (tensile models), else 0.
  double tensile_reach(const State* h, const Params& prm, std::size_t i, std::size_t j) const;

  // As tensile_reach for particle i and a wall (R* = r_i).
  double tensile_wall_reach(const State* h, const Params& prm, std::size_t i) const;

  // The largest pull-off separation of any contact (R* <= r_max, a wall's), for the list's cut-off.
  double max_tensile_reach() const;

  const Params& pair_params(std::size_t i, std::size_t j) const;

  // Visits every touching pair and wall contact with its geometry, without changing history.
  template <class F>
  void for_each_contact_geometry(F&& f) const;

  // ---- the force pass over pairs (simulation/pair_pass.hpp) ----
  /// `owned_reset`: the owned particles' forces and torques are already reset (step() does it
  /// in its first pass); `check_finite`: test the result here (step() does it in its last).
  void compute_forces(bool record, bool owned_reset = false, bool check_finite = true);

  // The velocities the dashpots see (integrators::VelocityVerletPredictedDamping).
  void predict_damping_velocities();

  template <bool Record>
  GRANULE_FLATTEN void process_layer(std::size_t l);

  // The doubles of a vector of small vectors (null when it is empty).
  template <class V>
  static const double* scalars(const std::vector<V>& v);

  // Prefetches the particle data that the packs of layers l and l + 1 gather and scatter.
  void prefetch_layer_pair(std::size_t l) const;

  // process_layer<false> with the particle pairs, and the wall contacts' law, evaluated W at a
  // time (contact/packed.hpp).
  GRANULE_FLATTEN void process_layer_packed(std::size_t l);

  // Lists touching pairs k, k+1, ... in the chunk until it is full or the material pair changes;
  // returns the first pair not listed.
  template <class Chunk>
  std::size_t fill_chunk(Chunk& chunk, const std::uint32_t* touching, const std::uint32_t* rows,
                         std::size_t k, std::size_t nt) const;

  // Passes 2 and 3 of the packed pair loop (contact/packed.hpp) for one chunk; empties it.
  template <class Chunk>
  void evaluate_chunk(Chunk& chunk, LayerAccumulator& acc, std::size_t l);

  // R*, m* and I_r of every list entry (kPairConstants), if the list changed since they were
  // computed (PairList::generation: every rebuild and load, so every change of a radius, mass,
  // motion mode, particle count or the list's slots, which all go through one).
  void update_pair_constants();

  // ---- the wall pass (simulation/wall_pass.hpp) ----
  // The walls of row i, one contact at a time, each handed to `use(g, state, params, wall, sp)`
  // to evaluate or queue.
  template <class Use>
  void for_each_wall_contact(std::size_t i, LayerAccumulator& acc, Use&& use);

  // The contacts of wall entry e of row i: a plane's at once, other shapes' with the first of
  // the wall's entries (features) in the row.
  template <class Use>
  void wall_entry_contacts(std::size_t i, std::uint32_t e, LayerAccumulator& acc, Use& use);

  // The contacts of row i with the wall of entry e, the first of that wall's entries in the row.
  template <class Use>
  void wall_group_contacts(std::size_t i, std::uint32_t e, LayerAccumulator& acc, Use& use);

  // The contact of row i with plane wall entry e, bitwise as wall_group_contacts would give it.
  template <class Use>
  void plane_contact(std::size_t i, std::uint32_t e, const geometry::PlaneShape<D>& plane, const Wall<D>& w,
                     LayerAccumulator& acc, Use& use);

  // The first overlap of a layer beyond max_overlap_ratio of the radius, for the step's check.
  void note_wall_overlap(std::size_t i, std::uint32_t wall, const contact::ContactGeometry<D>& g,
                         double max_ratio, LayerAccumulator& acc) const;

  // The walls of row i: forces and torques on i go to fi and ti, those on the bodies to acc.
  template <bool Record>
  void wall_contacts(std::size_t i, LayerAccumulator& acc, Vec& fi, AngVec& ti);

  // The wall contacts of rows r0..r1 into the queue, in entry order.
  void queue_wall_contacts(std::size_t r0, std::size_t r1, LayerAccumulator& acc, WallQueue& q);

  // The packed law for the queued wall contacts; out of line on purpose (see the definition).
  [[gnu::noinline]] GRANULE_FLATTEN void flush_wall_queue(WallQueue& q, LayerAccumulator& acc);

  // The wall contacts of rows r0..r1 one at a time, in entry order.
  void wall_contacts_by_entry(std::size_t r0, std::size_t r1, LayerAccumulator& acc);

  // Touch marks for wall history entries (one bit per entry, owned by the entry's row).
  void touched_mark(std::uint32_t k) { wall_touched_[k] = 1; }
  bool touched_take(std::uint32_t k);

  // ---- the distributed engine (simulation/distributed.hpp; used only when Parallel::distributed) ----
  struct HaloHooks;
  void start_distributed();
  void rebuild_distributed();
  void refresh_remote_ghosts();
  // save_state of a distributed run: every rank's particles and histories gathered to rank 0,
  // which writes them as a one-process state would be (other ranks write nothing).
  template <class W>
  void save_state_distributed(W& w);
  // A sum over the ranks in rank order (the same bits on every rank); collective.
  double over_ranks(double x) const;
  // Whether the pair (owned i, slot j) is a pair across ranks counted by the other rank (the
  // lower id's): energies, counts and frames take each such pair once.
  bool counted_elsewhere(std::size_t i, std::size_t j) const {
    return j >= particles_.owned() + particles_.local_ghosts() && particles_.id[j] < particles_.id[i];
  }
  std::size_t contact_count_distributed() const;
  // What save_state writes after the neighbour list: bodies, walls, group modes, time origin.
  template <class W>
  void save_state_tail(W& w) const;
  // Body and wall forces and torques summed over the ranks in rank order.
  void reduce_wall_forces();
  // f() on every rank; an exception on any rank is thrown on every rank (MpiContext::collective).
  // In one process simply f(), at no cost.
  template <class F>
  void collective(F&& f) {
    if constexpr (Parallel::distributed) {
      dist_.context().collective(std::forward<F>(f));
    } else {
      f();
    }
  }
  // Whether b holds on any rank (in one process: b).
  bool on_any_rank(bool b) const {
    if constexpr (Parallel::distributed) {
      return dist_.any(b);
    } else {
      return b;
    }
  }
  // The list rebuild: rebuild(), or with migration and halo exchange in a distributed run.
  void rebuild_everywhere() {
    if constexpr (Parallel::distributed) {
      rebuild_distributed();
    } else {
      rebuild();
    }
  }

  // ---- data (every part works on these members directly) ----
  SimulationConfig<D> config_;
  MaterialTable materials_;
  std::vector<bool> wall_material_;
  std::vector<Params> params_;
  ParticleStore<D> particles_;
  std::vector<Body<D>> bodies_;
  std::vector<Wall<D>> walls_;
  List list_;
  std::vector<LayerAccumulator> layer_acc_;
  std::vector<PairWork> pair_work_;
  std::vector<contact::PairConstants> pair_constants_;  ///< per list entry (kPairConstants only)
  std::vector<double> pair_reach_;  ///< r_i + r_j per list entry, for the touch scan (kPairConstants only)
  std::vector<std::uint32_t> entry_row_;  ///< the row of each list entry, for the touch scan (kPairConstants only)
  /// 2D packed pass: v, omega and r of every particle slot, copied at the pass's start.
  std::vector<contact::DiskRecord> disk_records_;
  /// The list's generation pair_constants_ were computed for (none yet: the maximum).
  std::uint64_t pair_constants_generation_ = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::uint8_t> wall_touched_;
  std::vector<Motion> group_motion_;
  std::vector<std::function<Vec(double)>> group_velocity_;
  std::vector<Vec> group_v_now_;
  std::vector<Vec> v_damp_;         ///< velocities the dashpots see (kPredictDamping only)
  std::vector<AngVec> omega_damp_;  ///< angular velocities the dashpots see (kPredictDamping only)
  std::vector<Observer> observers_;
  std::vector<analysis::ContactRecord<D>> records_;
  std::uint64_t records_step_ = std::numeric_limits<std::uint64_t>::max();
  bool record_next_ = false;
  bool record_always_ = false;  ///< record_contacts_every_step
  std::size_t contacts_ = 0;
  double time_ = 0.0;
  std::uint64_t step_ = 0;
  double time_origin_ = 0.0;       ///< time at the last change of dt (time() counts from it)
  std::uint64_t step_origin_ = 0;  ///< step count at the last change of dt
  std::uint64_t next_id_ = 0;
  double skin_used_ = 0.0;
  bool list_valid_ = false;
  bool initialised_ = false;
  bool forces_ready_ = false;
  bool setup_evaluation_ = false;  ///< the set-up force evaluation runs: contacts see dt = 0
  bool one_material_ = false;      ///< all particles share one material (set by step() for its pair loop)
  bool parallel_ = false;
  [[no_unique_address]] typename Parallel::template Engine<D> dist_;  ///< the policy's data
};

}  // namespace granule

// The parts' member definitions (docs/architecture.md, "Simulation in parts").
#include "granule/simulation/time_step.hpp"         // critical time, rolling stability limit, dt checks
#include "granule/simulation/state_io.hpp"          // save_state, load_state_format
#include "granule/simulation/contact_geometry.hpp"  // pair and wall geometry, tensile reach, read-only walk
#include "granule/simulation/wall_pass.hpp"         // particle-wall contacts: by entries, planes, packs
#include "granule/simulation/pair_pass.hpp"         // compute_forces: colours, scalar and packed layer loops
#include "granule/simulation/setup.hpp"             // materials, particles, bodies, walls, groups, observers
#include "granule/simulation/observables.hpp"       // energies, frame, memory
#include "granule/simulation/upkeep.hpp"            // first list and forces, rebuilds, ghosts, stops
#include "granule/simulation/integrate.hpp"         // the step's particle passes: kicks and drift
#include "granule/simulation/distributed.hpp"       // MPI domains: migration, halo, reductions, gather
