#pragma once
// Lateral shock in a lunar-gravity granular channel (paper 001 in shared/papers: Hofheins et
// al., impulse-induced surface dilation of a granular bed at low gravity), two parts:
//
// 1. Validation (001 section 2.2, table 1, fig. 1): the struck 5 x 5 grid, in grid.hpp.
// 2. Channel (001 sections 2.3-2.9, table 2): spheres of R = 1.25 mm (Hertz-Mindlin + EPSD
//    rolling + SJKR cohesion) poured at a controlled rate into a channel periodic across its
//    width (x), closed by end planes at y = 0 and y = L and a floor plane, under lunar gravity.
//    Pour with e -> 0 and no rolling damping (001 section 2.4) in a first simulation, copy the
//    bed into a second simulation with the table-2 material, delete particles above the fill
//    height, settle (velocities zeroed every 25 ms), save a checkpoint. Shock: the sheet
//    z < 2R is frozen as the rough floor, the sheet y < 2R is the virtual piston moving at v_p
//    along +y (P wave) or the virtual bender z = A sin(2 pi f t) for one period (S wave,
//    A = v_p / (2 pi f)). A 0.5 cm x 0.5 cm sensor grid in y-z records the mean per-particle
//    contact-force magnitude and mean overlap per bin; arrival time = first peak above 10 x the
//    initial level (analysis/wave_front.hpp); straight-line fits over y in [0, 15 cm] -> c_w
//    and over [30, 50 cm] -> c_p per depth with 2-sigma rejection (001 section 2.8.3);
//    delta_m / delta_0 per column (001 fig. 16) and the bed-height change per 0.5 cm column
//    from the top particles (001 section 2.8.2, analysis/packing.hpp).
#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <granule/analysis/bin_grid.hpp>
#include <granule/analysis/packing.hpp>
#include <granule/analysis/wave_front.hpp>
#include <granule/granule.hpp>
#include <granule/io/checkpoint.hpp>
#include <granule/io/progress.hpp>
#include <granule/scene/pour.hpp>
#include <granule/scene/settle.hpp>

#include "grid.hpp"

namespace granule::examples::lunar_shock {

using Vec = Dim3::Vec;

// =============================================================================================
// Part 2: the channel
// =============================================================================================

using ChannelSim = Simulation<Dim3, contact::HertzMindlinEpsdSjkr, neighbours::VerletList>;

/// Packing levels of 001 table 3, set by the insertion rate.
enum class Packing { Loose, Medium, Compact };

inline const char* packing_name(Packing p) {
  return p == Packing::Loose ? "loose" : p == Packing::Medium ? "medium" : "compact";
}

/// Insertion flux of 001 table 3 for the 2 m x 2 cm channel, per unit floor area
/// [particles / (s m^2)]: 600 000, 200 000 and 18 900 particles/s over 0.04 m^2.
inline double paper_insertion_flux(Packing p) {
  const double rate = p == Packing::Loose ? 600000.0 : p == Packing::Medium ? 200000.0 : 18900.0;
  return rate / (2.0 * 0.02);
}

/// Sound speed c_0 of 001 table 6 [m/s].
inline double paper_sound_speed(Packing p) {
  return p == Packing::Loose ? 6.55 : p == Packing::Medium ? 7.01 : 7.51;
}

/// Mean initial particle-particle overlap delta_0 of 001 table 8 / fig. 3 (2 m x 20 cm beds) [m].
inline double paper_mean_overlap(Packing p) {
  return p == Packing::Loose ? 4.82e-6 : p == Packing::Medium ? 4.81e-6 : 4.23e-6;
}

/// 001 eq. 7 (Nesterenko 2001 eq. 1.7, strongly compressed 1D chain) times the sqrt(3)/2 that
/// 001 fig. 7 applies: c_0 from the mean static overlap delta_0 [m] of spheres of radius R [m],
/// mass m [kg], Young's modulus E [Pa] and Poisson ratio nu [-] -> [m/s].
inline double eq7_sound_speed(double delta_0, double radius, double mass, double youngs, double nu) {
  const double c2 = youngs * std::sqrt(2.0 * radius) / (3.0 * (1.0 - nu * nu) * mass) * std::sqrt(delta_0) * 6.0 *
                    radius * radius;
  return std::sqrt(3.0) / 2.0 * std::sqrt(c2);
}

struct ChannelOptions {
  // geometry
  double length = 0.25;          ///< channel length along y (wave direction) [m]
  double depth = 0.035;          ///< fill height [m]
  double width = 0.02;           ///< periodic width along x [m]
  double radius = 1.25e-3;       ///< particle radius [m]
  // preparation
  Packing packing = Packing::Loose;
  double insertion_flux = 0.0;   ///< [1/(s m^2)]; 0 = table 3 for `packing`
  double drop_height = 0.02;     ///< insertion region starts this far above the fill height [m] (001: 0.10)
  double region_height = 0.03;   ///< height of the insertion region [m] (001: 0.20)
  double pour_speed = 0.65;      ///< downward speed of inserted particles [m/s] (001: 0)
  double dt_prepare = 0.0;       ///< pour/settle time step [s]; 0 = min(largest allowed, dt_max)
  /// Pour step [s]; 0 = dt_prepare's step. The pour material has no rolling damping, so the
  /// rolling limit that sets dt_max does not apply to it (README, "Pour protocol").
  double dt_pour = 0.0;
  /// Rolling viscous damping ratio eta_r of the settle and shock material [-]. 001 table 2 and
  /// section 2.4 give 2 (calibrated on a spinning particle, switched off for pouring and back on
  /// after it); section 2.1 says the damping torque is neglected (0). README, "Rolling damping".
  double rolling_damping = 2.0;
  /// Cap on the channel time steps chosen automatically (pour, settle, shock) [s]. At the
  /// engine's limit (0.2 Rayleigh times = 3.0e-5 s) a static bed never comes to rest: its mean
  /// net force stays at 5-8 particle weights with particles spinning at ~150 rad/s, whatever the
  /// settling (measured: 3 weights at 2e-5 s, 0.6 at 1.5e-5 s, 0.3-0.5 at 1e-5 and 5e-6 s). The
  /// cause is the explicit EPSD rolling damping (eta_r = 2), whose rate 2 C_r / I per contact is
  /// 0.72 per step of 3.0e-5 s; with eta_r = 0 the bed stays quiet at 3.0e-5 s (README).
  double dt_max = 1e-5;
  /// Longest settling after the top is removed [s]; settling stops earlier once the bed is
  /// quiet (settle_force).
  double settle_time = 1.0;
  /// Quiet: mean net force per particle below this many particle weights m g [-]
  /// (001: mean force 1e-11 N = 3e-7 weights); 0 = settle for the whole settle_time.
  double settle_force = 1e-3;
  /// ... and no particle faster than this [m/s] (0 = no condition): perched surface particles
  /// that roll off later land with force peaks that the wave detection takes for arrivals.
  double settle_speed = 1e-3;
  /// Background damping while settling: every free velocity and spin decays as exp(-rate t)
  /// [1/s] (0 = none, 001 uses none).
  double settle_damping = 0.0;
  double settle_check = 0.005;   ///< quietness measured this often while settling [s]
  double zero_interval = 0.025;  ///< velocities zeroed this often while settling [s] (001: 25 ms; 0 = never)
  double gravity = 1.625;        ///< lunar gravity along -z [m/s^2]
  std::uint64_t seed = 1;
  std::filesystem::path bed_dir = ".";  ///< where the settled-bed checkpoint is cached
  // shock
  bool bender = false;           ///< S wave by the virtual bender instead of the P-wave piston
  double bender_frequency = 50e3;  ///< [Hz] (001 section 2.6)
  double dt_shock = 0.0;         ///< [s]; 0 = min(largest allowed, dt_max, tau_c(v_p)/20, bender period/20)
  double run_time = 0.0;         ///< simulated time after the shock [s]; 0 = 2.5 L / 7 m/s
  double sample_interval = 2e-5; ///< sensor sampling interval [s]
  /// The sensors record this long before the impulse; the mean over it is each bin's initial
  /// level (001: "initial average particle force") [s].
  double pre_record = 1e-3;
  /// Force series are stored for this long after the impulse (0: the whole run); overlaps are
  /// tracked over the whole run [s].
  double sensor_time = 0.0;
  /// After this long after the impulse the shock run continues at tail_dt [s] (0: never): the
  /// fronts have crossed the channel, what is left is lofted particles landing and the bed
  /// coming to rest (the at-rest height change), which needs no 1e-6 s step.
  double tail_from = 0.0;
  double tail_dt = 1e-5;         ///< [s], at most tau_c(fastest particle)/20
  double bin = 5e-3;             ///< sensor grid spacing in y and z [m] (001: 0.5 cm)
  double cw_from = 0.0, cw_to = 0.08;   ///< fit window for c_w along y [m] (001: 0-15 cm)
  double cp_from = 0.12, cp_to = 0.20;  ///< fit window for c_p along y [m] (001: 30-50 cm)
  bool progress = true;          ///< progress lines on stderr

  /// The paper's geometry and analysis windows (001 sections 2.3-2.8).
  static ChannelOptions paper() {
    ChannelOptions o;
    o.length = 2.0;
    o.depth = 0.20;
    o.drop_height = 0.10;
    o.region_height = 0.20;
    o.pour_speed = 0.0;
    o.dt_prepare = 1e-6;
    o.dt_shock = 1e-6;
    o.settle_time = 5.0;       // a cap: 001 settles until the mean force is 1e-11 N
    o.settle_force = 1e-11 / (o.gravity * 2500.0 * o.particle_volume());  // 3.0e-7 weights
    o.run_time = 1.5;
    o.sample_interval = 1e-4;
    o.sensor_time = 0.25;  // 001 writes 1 ms frames over the first 0.25 s
    o.cw_from = 0.0;
    o.cw_to = 0.15;
    o.cp_from = 0.30;
    o.cp_to = 0.50;
    return o;
  }

  double flux() const { return insertion_flux > 0.0 ? insertion_flux : paper_insertion_flux(packing); }
  double particle_volume() const { return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius; }
  /// Particles poured: 1.1 x a random close packing (0.64) of the fill volume, so that every
  /// packing overfills and the top can be cut off.
  std::size_t pour_count() const {
    return static_cast<std::size_t>(1.1 * 0.64 * length * width * depth / particle_volume());
  }
  void validate() const {
    const std::string w = "lunar_shock::ChannelOptions";
    require(length > 10.0 * radius, w, "length", length, "(10 R, inf) m");
    require(depth > 4.0 * radius, w, "depth", depth, "(4 R, inf) m");
    require(width >= 4.0 * radius, w, "width", width, "[4 R, inf) m");
    require_positive(radius, w, "radius");
    require_positive(region_height, w, "region_height");
    require_non_negative(drop_height, w, "drop_height");
    require_non_negative(pour_speed, w, "pour_speed");
    require_positive(settle_time, w, "settle_time");
    require_non_negative(dt_prepare, w, "dt_prepare");
    require_non_negative(dt_max, w, "dt_max");
    require_non_negative(dt_pour, w, "dt_pour");
    require(rolling_damping >= 0.0 && rolling_damping <= 10.0, w, "rolling_damping", rolling_damping, "[0, 10]");
    require_non_negative(tail_from, w, "tail_from");
    require_positive(tail_dt, w, "tail_dt");
    require_non_negative(settle_force, w, "settle_force");
    require_non_negative(settle_speed, w, "settle_speed");
    require_non_negative(settle_damping, w, "settle_damping");
    require_positive(settle_check, w, "settle_check");
    require_non_negative(zero_interval, w, "zero_interval");
    require_positive(sample_interval, w, "sample_interval");
    require(bin >= 2.0 * radius, w, "bin", bin, "[2 R, inf) m");
    require(cw_to > cw_from && cp_to > cp_from, w, "fit windows (to - from)", std::min(cw_to - cw_from, cp_to - cp_from),
            "(0, inf) m");
  }
};

/// Table-2 material with rolling damping ratio eta_r; `pouring` gives the pouring variant
/// (e -> 0, no rolling damping, 001 sec. 2.4).
inline Material channel_material(bool pouring, double rolling_damping = 2.0) {
  Material m;
  m.name = pouring ? "regolith (pouring)" : "regolith";
  m.youngs_modulus = 5e6;           // [Pa]
  m.poisson_ratio = 0.2;
  m.density = 2500.0;               // [kg/m^3]
  m.friction = 1.0;
  m.rolling_friction = 0.8;
  m.rolling_damping = pouring ? 0.0 : rolling_damping;
  m.restitution = pouring ? 0.01 : 0.5;  // 001 pours with e = 0; the Hertz damping needs e > 0
  m.cohesion_energy_density = 1000.0;    // [J/m^3]
  return m;
}

/// A channel simulation with materials and walls (floor, end walls) but no particles.
inline std::unique_ptr<ChannelSim> make_channel(const ChannelOptions& o, double dt, bool pouring) {
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Vec(0.0, 0.0, 0.0);
  cfg.domain.hi = Vec(o.width, o.length, o.depth + o.drop_height + o.region_height + 0.05);
  cfg.domain.periodic = Eigen::Matrix<bool, 3, 1>(true, false, false);
  cfg.gravity = Vec(0.0, 0.0, -o.gravity);
  cfg.dt = dt;
  // The engine's rotational limit (rolling_stability_limit, eta_r = 2) is conservative: on a
  // settled bed it lies at 0.5-0.6 of the step where spinning sets in, so it would ask for
  // ~6e-6 s here, while dt_max = 1e-5 s was measured quiet (see dt_max). The channel keeps the
  // measured step and leaves that check off; the Rayleigh check stays on.
  cfg.check_rolling_stability = false;
  auto sim = std::make_unique<ChannelSim>(cfg);
  const Material m = channel_material(pouring, o.rolling_damping);
  sim->add_material(m);
  const auto wall = sim->add_wall_material(m);
  sim->add_wall(geometry::PlaneShape<Dim3>(Vec(0, 0, 0), Vec(0, 0, 1)), wall);         // floor
  sim->add_wall(geometry::PlaneShape<Dim3>(Vec(0, 0, 0), Vec(0, 1, 0)), wall);         // y = 0
  sim->add_wall(geometry::PlaneShape<Dim3>(Vec(0, o.length, 0), Vec(0, -1, 0)), wall); // y = L
  return sim;
}

/// Largest step the engine accepts for the channel particles (0.2 Rayleigh times) [s].
inline double channel_max_dt(const ChannelOptions& o) {
  const Material m = channel_material(false);
  return 0.2 * rayleigh_time(o.radius, m.density, m.shear_modulus(), m.poisson_ratio);
}

/// Step of pouring and settling: dt_prepare, or the engine's limit capped at dt_max [s].
inline double prepare_dt(const ChannelOptions& o) {
  if (o.dt_prepare > 0.0) return o.dt_prepare;
  return o.dt_max > 0.0 ? std::min(channel_max_dt(o), o.dt_max) : channel_max_dt(o);
}

/// Step of pouring: dt_pour, or prepare_dt [s].
inline double pour_dt(const ChannelOptions& o) { return o.dt_pour > 0.0 ? o.dt_pour : prepare_dt(o); }

namespace detail {
/// FNV-1a hash of the bytes of some doubles.
inline std::uint64_t hash_values(const std::vector<double>& vals) {
  std::uint64_t h = 1469598103934665603ull;
  for (double v : vals) {
    unsigned char b[sizeof(double)];
    std::memcpy(b, &v, sizeof v);
    for (unsigned char c : b) {
      h ^= c;
      h *= 1099511628211ull;
    }
  }
  return h;
}

inline std::filesystem::path cache_name(const ChannelOptions& o, const char* kind, std::uint64_t h) {
  char name[80];
  std::snprintf(name, sizeof name, "%s_%s_%016llx.ckpt", kind, packing_name(o.packing), static_cast<unsigned long long>(h));
  return o.bed_dir / name;
}
}  // namespace detail

/// Cache file of the poured and trimmed bed before settling (table-2 material, at rest): the
/// name carries a hash of every pouring parameter, so settling variants reuse one pour.
inline std::filesystem::path poured_path(const ChannelOptions& o) {
  return detail::cache_name(o, "poured",
                            detail::hash_values({o.length, o.depth, o.width, o.radius, o.flux(), o.drop_height,
                                                 o.region_height, o.pour_speed, pour_dt(o), o.gravity,
                                                 static_cast<double>(o.seed), 1.0 /* pour recipe version */}));
}

/// Cache file of the settled bed: the name carries a hash of every bed parameter.
inline std::filesystem::path bed_path(const ChannelOptions& o) {
  std::vector<double> key{o.length, o.depth, o.width, o.radius, o.flux(), o.drop_height, o.region_height, o.pour_speed,
                          prepare_dt(o), o.settle_time, o.zero_interval, o.gravity, static_cast<double>(o.seed),
                          o.settle_force, o.settle_speed, o.settle_damping, o.settle_check,
                          3.0 /* bed recipe version */};
  // Appended only when they differ from their first defaults, so that beds cached before
  // these options existed keep their names.
  if (o.dt_pour > 0.0 && o.dt_pour != prepare_dt(o)) key.push_back(o.dt_pour);
  if (o.rolling_damping != 2.0) key.push_back(1000.0 + o.rolling_damping);
  return detail::cache_name(o, "bed", detail::hash_values(key));
}

/// How quiet a bed is (001 section 2.4 settles until the mean force is 1e-11 N): net force
/// |f| of each free particle (gravity included, so zero in equilibrium) in units of its weight.
struct Quietness {
  double time = 0.0;             ///< simulated time [s]
  double ke_per_particle = 0.0;  ///< translational + rotational, mean over all particles [J]
  double force_mean = 0.0;       ///< mean |f| / (m g) over the free particles [-]
  double force_median = 0.0;     ///< median |f| / (m g) [-]
  double force_p99 = 0.0;        ///< 99th percentile of |f| / (m g) [-]
  double max_speed = 0.0;        ///< largest |v| [m/s]
  double max_spin = 0.0;         ///< largest |omega| [rad/s]
};

/// Quietness of the current state of sim under gravity g [m/s^2] (forces of the last step).
inline Quietness measure_quietness(const ChannelSim& sim, double g) {
  const auto& p = sim.particles();
  Quietness q;
  q.time = sim.time();
  std::vector<double> f;
  f.reserve(p.owned());
  double s = 0.0;
  for (std::size_t i = 0; i < p.owned(); ++i) {
    q.max_speed = std::max(q.max_speed, p.v[i].norm());
    q.max_spin = std::max(q.max_spin, p.omega[i].norm());
    if (p.motion[i] != Motion::Free) continue;
    f.push_back(p.f[i].norm() / (p.mass[i] * g));
    s += f.back();
  }
  q.ke_per_particle = sim.kinetic_energy() / static_cast<double>(std::max<std::size_t>(1, p.owned()));
  if (!f.empty()) {
    q.force_mean = s / static_cast<double>(f.size());
    const auto pick = [&](double fraction) {
      auto it = f.begin() + static_cast<long>(std::floor(fraction * static_cast<double>(f.size() - 1)));
      std::nth_element(f.begin(), it, f.end());
      return *it;
    };
    q.force_median = pick(0.5);
    q.force_p99 = pick(0.99);
  }
  return q;
}

/// What bed preparation did.
struct BedReport {
  bool from_cache = false;       ///< the settled bed was loaded from bed_path
  bool pour_from_cache = false;  ///< the poured bed was loaded from poured_path
  std::size_t poured = 0;        ///< particles inserted [-]
  std::size_t removed = 0;       ///< deleted above the fill height [-]
  std::size_t particles = 0;     ///< in the bed [-]
  double pour_time = 0.0;        ///< simulated pouring time [s]
  double settle_time = 0.0;      ///< simulated settling time [s]
  bool settled = false;          ///< the settle_force criterion was met within settle_time
  double ke_per_particle = 0.0;  ///< at the end of settling [J]
  double packing_fraction = 0.0; ///< particle volume / (L W H) below the fill height [-]
  double mean_overlap = 0.0;     ///< mean particle-particle overlap delta_0 [m]
  /// Particle volume over the volume of the interior, centres 2R from the floor and end walls
  /// and 3R below the fill height: the packing fraction without the boundary layers [-].
  double packing_interior = 0.0;
  double coordination = 0.0;     ///< particle-particle contacts per particle, x 2 [-]
  Quietness quiet;               ///< of the bed as the shocks start from it
  std::vector<Quietness> settle_history;  ///< every settle_check while settling, time counted from its start
                                          ///< (empty for a cached bed)
  double pour_wall_seconds = 0.0;    ///< [s]
  double pour_particle_steps = 0.0;  ///< sum over the pour's steps of the particles present [-]
  double settle_wall_seconds = 0.0;  ///< [s]
  double wall_seconds = 0.0;     ///< [s]
};

namespace detail {
inline double elapsed_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Mean particle-particle overlap of the last recorded contacts [m].
inline double mean_overlap(const ChannelSim& sim) {
  double s = 0.0;
  std::size_t n = 0;
  for (const auto& c : sim.recorded_contacts())
    if (c.j != analysis::ContactRecord<Dim3>::kWall) {
      s += c.overlap;
      ++n;
    }
  return n ? s / static_cast<double>(n) : 0.0;
}

/// Particle-particle contacts per particle of the last recorded contacts, counted at both ends [-].
inline double coordination(const ChannelSim& sim) {
  std::size_t n = 0;
  for (const auto& c : sim.recorded_contacts())
    if (c.j != analysis::ContactRecord<Dim3>::kWall) ++n;
  return 2.0 * static_cast<double>(n) / static_cast<double>(std::max<std::size_t>(1, sim.particles().owned()));
}

/// Packing fraction of the interior (BedReport::packing_interior) [-].
inline double packing_interior(const ChannelSim& sim, const ChannelOptions& o) {
  const double r = o.radius, y0 = 2.0 * r, y1 = o.length - 2.0 * r, z0 = 2.0 * r, z1 = o.depth - 3.0 * r;
  if (!(y1 > y0 && z1 > z0)) return 0.0;
  const auto& p = sim.particles();
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.owned(); ++i)
    if (p.x[i].y() >= y0 && p.x[i].y() < y1 && p.x[i].z() >= z0 && p.x[i].z() < z1) ++n;
  return static_cast<double>(n) * o.particle_volume() / ((y1 - y0) * (z1 - z0) * o.width);
}

/// Pours with e -> 0 and no rolling damping, copies the bed at rest into `bed` (table-2
/// material) and deletes what is above the fill height.
/// `stop_after` > 0: stop pouring at that simulated time [s] (a cost segment).
inline void pour_bed(const ChannelOptions& o, double dt, ChannelSim& bed, BedReport& rep, double stop_after = 0.0) {
  auto pour_sim = make_channel(o, dt, true);
  const double r = o.radius;
  geometry::Aabb<Dim3> region{Vec(r, r, o.depth + o.drop_height),
                              Vec(o.width - r, o.length - r, o.depth + o.drop_height + o.region_height)};
  const std::size_t total = o.pour_count();
  const double rate = o.flux() * o.length * o.width;  // [particles/s]
  scene::Pour<ChannelSim> pour(*pour_sim, region, scene::MonodisperseSizes(r), scene::StreamSchedule(rate, total), 0,
                               Vec(0, 0, -o.pour_speed), 0, o.seed);
  // ETA from the expected pour time: the insertion, the fall from the top of the region, 0.2 s.
  const double expected = static_cast<double>(total) / rate +
                          std::sqrt(2.0 * (o.depth + o.drop_height + o.region_height) / o.gravity) + 0.2;
  io::ProgressReporter progress({.end_time = expected, .mode = o.progress ? io::ProgressMode::On : io::ProgressMode::Off,
                                 .interval = 5.0, .label = "pour"});
  const auto every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(1e-3 / dt)));
  // Pour, then let the last particles land: stop when the mean kinetic energy per particle
  // is below that of a particle moving at 1 cm/s (or 3 s after the last insertion is due).
  const double m = channel_material(false).density * o.particle_volume();
  const double quiet = 0.5 * m * 1e-4;
  const double t_limit = static_cast<double>(total) / rate + 3.0;
  while (pour_sim->time() < t_limit && (stop_after <= 0.0 || pour_sim->time() < stop_after)) {
    pour.update();
    rep.pour_particle_steps += static_cast<double>(pour_sim->particles().owned()) * static_cast<double>(every);
    pour_sim->run(every);
    progress.update(pour_sim->step_count(), pour_sim->time());
    if (pour.finished()) {
      const double n = static_cast<double>(std::max<std::size_t>(1, pour_sim->particles().owned()));
      if (pour_sim->kinetic_energy() / n < quiet) break;
    }
  }
  progress.finish(pour_sim->step_count(), pour_sim->time());
  rep.poured = pour.inserted();
  rep.pour_time = pour_sim->time();
  const auto& p = pour_sim->particles();
  for (std::size_t i = 0; i < p.owned(); ++i)
    if (p.x[i].z() <= o.depth - r) bed.add_particle(p.x[i], p.radius[i], 0);
  rep.removed = p.owned() - bed.particles().owned();
}

/// Settles `bed` (001 section 2.4): velocities zeroed every zero_interval, optional background
/// damping, quietness measured every settle_check (before a zeroing that falls on the same
/// step); stops once the mean net force is below settle_force weights or after settle_time.
inline void settle_bed(const ChannelOptions& o, ChannelSim& bed, BedReport& rep) {
  const auto t_wall = std::chrono::steady_clock::now();
  const double dt = bed.dt();
  const double t0 = bed.time();
  const auto steps_of = [&](double interval) {
    return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(interval / dt)));
  };
  const std::uint64_t per_check = steps_of(o.settle_check);
  const std::uint64_t per_zero = o.zero_interval > 0.0 ? steps_of(o.zero_interval) : 0;
  const double decay = std::exp(-o.settle_damping * dt);
  const auto total = static_cast<std::uint64_t>(std::llround(o.settle_time / dt));
  double last_line = -1e300;
  for (std::uint64_t k = 1; k <= total; ++k) {
    bed.step();
    auto& p = bed.particles();
    if (o.settle_damping > 0.0)
      for (std::size_t i = 0; i < p.owned(); ++i) {
        p.v[i] *= decay;
        p.omega[i] *= decay;
      }
    if (k % per_check == 0 || k == total) {
      Quietness q = measure_quietness(bed, o.gravity);
      q.time -= t0;  // since the start of settling
      rep.settle_history.push_back(q);
      const bool quiet = o.settle_force > 0.0 && q.force_mean < o.settle_force &&
                         (o.settle_speed <= 0.0 || q.max_speed < o.settle_speed);
      const double wall = elapsed_since(t_wall);
      if (o.progress && (wall - last_line >= 5.0 || quiet || k == total)) {
        last_line = wall;
        std::fprintf(stderr,
                     "settle: t = %.3f s, net force / weight: mean %.3g, median %.3g, p99 %.3g; KE/particle %.3g J, "
                     "max |v| %.3g m/s, max |omega| %.3g rad/s (%.0f s wall)\n",
                     q.time, q.force_mean, q.force_median, q.force_p99, q.ke_per_particle, q.max_speed,
                     q.max_spin, wall);
      }
      if (quiet) {
        rep.settled = true;
        break;
      }
    }
    if (per_zero && k % per_zero == 0)
      for (std::size_t i = 0; i < p.owned(); ++i) {
        p.v[i].setZero();
        p.omega[i].setZero();
      }
  }
  rep.settle_time = bed.time() - t0;
  rep.settle_wall_seconds = elapsed_since(t_wall);
}
}  // namespace detail

/// Pours, trims and settles a bed (001 section 2.4) unless a cached one exists; writes the
/// checkpoints poured_path(o) (before settling) and bed_path(o). The bed simulation uses the
/// table-2 material and dt_prepare.
inline BedReport prepare_bed(const ChannelOptions& o) {
  o.validate();
  const auto t_wall = std::chrono::steady_clock::now();
  BedReport rep;
  const double dt = prepare_dt(o);
  const auto path = bed_path(o);
  auto bed = make_channel(o, dt, false);
  if (std::filesystem::exists(path)) {
    const auto user = io::read_checkpoint(*bed, path.string());
    rep.from_cache = true;
    if (user.size() >= 5) {
      rep.poured = user[0];
      rep.removed = user[1];
      rep.pour_time = std::bit_cast<double>(user[2]);
      rep.settled = user[3] != 0;
      rep.settle_time = std::bit_cast<double>(user[4]);
    }
  } else {
    std::filesystem::create_directories(o.bed_dir);
    const auto poured = poured_path(o);
    const auto t_pour = std::chrono::steady_clock::now();
    if (std::filesystem::exists(poured)) {
      const auto user = io::read_checkpoint(*bed, poured.string());
      rep.pour_from_cache = true;
      if (user.size() >= 3) {
        rep.poured = user[0];
        rep.removed = user[1];
        rep.pour_time = std::bit_cast<double>(user[2]);
      }
    } else {
      detail::pour_bed(o, pour_dt(o), *bed, rep);
      io::write_checkpoint(*bed, poured.string(), {rep.poured, rep.removed, std::bit_cast<std::uint64_t>(rep.pour_time)});
    }
    rep.pour_wall_seconds = detail::elapsed_since(t_pour);
    detail::settle_bed(o, *bed, rep);
    io::write_checkpoint(*bed, path.string(),
                         {rep.poured, rep.removed, std::bit_cast<std::uint64_t>(rep.pour_time), rep.settled ? 1u : 0u,
                          std::bit_cast<std::uint64_t>(rep.settle_time)});
  }
  const auto& p = bed->particles();
  rep.particles = p.owned();
  const std::size_t n = std::max<std::size_t>(1, p.owned());
  rep.ke_per_particle = bed->kinetic_energy() / static_cast<double>(n);
  rep.packing_fraction = static_cast<double>(p.owned()) * o.particle_volume() / (o.length * o.width * o.depth);
  bed->request_contacts();
  bed->step();
  rep.mean_overlap = detail::mean_overlap(*bed);
  rep.coordination = detail::coordination(*bed);
  rep.packing_interior = detail::packing_interior(*bed, o);
  rep.quiet = measure_quietness(*bed, o.gravity);
  rep.wall_seconds = detail::elapsed_since(t_wall);
  return rep;
}

/// Results of one shock.
struct ShockResult {
  double v_p = 0.0;              ///< piston (or bender peak) speed [m/s]
  double dt = 0.0;               ///< [s]
  std::vector<double> depth;     ///< depth of each sensor row (centre) [m]
  std::vector<double> y;         ///< centre of each sensor column [m]
  std::vector<double> arrival;   ///< [row * ny + column] arrival time, NaN if none [s]
  std::vector<double> c_w, c_w_u, c_p, c_p_u;  ///< per depth, NaN if the fit failed [m/s]
  double c_w_mean = 0.0, c_w_sd = 0.0;  ///< depth average and spread [m/s]
  double c_p_mean = 0.0, c_p_sd = 0.0;  ///< [m/s]
  std::vector<double> delta_ratio;      ///< delta_m / delta_0 per column [-]
  std::vector<double> dz;               ///< bed-height change per column [m]
  double delta_0 = 0.0;                 ///< mean initial overlap of the sensor bins [m]
  double delta_ratio_mean = 0.0;        ///< delta_m / delta_0 averaged over the c_p window [-]
  double dz_mean = 0.0, dz_sd = 0.0;    ///< over the c_p window [m]
  double max_particle_speed = 0.0;      ///< largest |v| outside the piston after 2 ms [m/s]
  std::size_t ejected = 0;              ///< particles removed above the ceiling [-]
  double wall_seconds = 0.0;            ///< [s]
  std::uint64_t steps = 0;
  std::size_t particles = 0;
  double dt_tail = 0.0;                 ///< step after tail_from, 0 if none [s]
};

namespace detail {
inline void mean_sd(const std::vector<double>& v, double& mean, double& sd) {
  double s = 0.0, s2 = 0.0;
  std::size_t n = 0;
  for (double x : v)
    if (std::isfinite(x)) {
      s += x;
      s2 += x * x;
      ++n;
    }
  mean = n ? s / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
  sd = n > 1 ? std::sqrt(std::max(0.0, (s2 - s * s / static_cast<double>(n)) / static_cast<double>(n - 1))) : 0.0;
}

/// Front speed over the sensors of one row inside [from, to], NaN when fewer than 3 arrivals.
inline std::pair<double, double> row_speed(const std::vector<double>& y, const std::vector<double>& t, double from,
                                           double to) {
  std::vector<double> yy, tt;
  for (std::size_t k = 0; k < y.size(); ++k)
    if (y[k] >= from && y[k] <= to) {
      yy.push_back(y[k]);
      tt.push_back(t[k]);
    }
  std::size_t finite = 0;
  for (double v : tt) finite += std::isfinite(v);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (finite < 4) return {nan, nan};
  try {
    const auto fs = analysis::front_speed_from_arrivals(yy, tt, 2.0);
    return {fs.speed, fs.speed_uncertainty};
  } catch (const InvalidParameter&) {
    return {nan, nan};
  }
}
}  // namespace detail

/// Loads the settled bed and sends one P wave (piston) or S wave (bender) of speed v_p.
/// `bed`: the settled bed's checkpoint (default bed_path(o)).
inline ShockResult run_shock(const ChannelOptions& o, double v_p, const std::filesystem::path& bed = {}) {
  o.validate();
  require(v_p > 0.0 && std::isfinite(v_p), "lunar_shock::run_shock", "v_p", v_p, "(0, inf) m/s");
  const auto t_wall = std::chrono::steady_clock::now();
  const double r = o.radius;
  const double dt_bed = prepare_dt(o);
  auto sim_ptr = make_channel(o, dt_bed, false);
  ChannelSim& sim = *sim_ptr;
  io::read_checkpoint(sim, (bed.empty() ? bed_path(o) : bed).string());
  const std::uint64_t steps0 = sim.step_count();
  // Rough floor: the sheet z < 2R, frozen (001 section 2.6). Piston/bender: the sheet y < 2R.
  const std::uint32_t floor_group = 1, piston_group = 2;
  {
    const auto& p = sim.particles();
    sim.assign_group(floor_group, [&](std::size_t i) { return p.x[i].z() < 2.0 * r; });
    sim.assign_group(piston_group, [&](std::size_t i) { return p.x[i].y() < 2.0 * r && p.group[i] != floor_group; });
  }
  sim.freeze_group(floor_group);
  ShockResult res;
  res.v_p = v_p;
  // Time step: the engine's limit, at most 1/20 of the Hertz collision time of a particle pair
  // meeting at v_p, and 1/20 of the bender period (001: 20 steps per period).
  double dt = o.dt_shock;
  if (dt <= 0.0) {
    const PairMaterial pm = sim.materials().pair(0, 0);
    const double m = channel_material(false).density * o.particle_volume();
    dt = std::min(channel_max_dt(o), hertz_collision_time(0.5 * m, pm.E_eff, 0.5 * r, v_p) / 20.0);
    if (o.dt_max > 0.0) dt = std::min(dt, o.dt_max);
    if (o.bender) dt = std::min(dt, 1.0 / (20.0 * o.bender_frequency));
  }
  sim.set_dt(dt);
  res.dt = dt;
  const double t0 = sim.time() + o.pre_record;  // time of the impulse
  const double run_time = o.run_time > 0.0 ? o.run_time : 2.5 * o.length / 7.0;

  // Sensor grid in y-z.
  const int ny = std::max(1, static_cast<int>(std::floor(o.length / o.bin)));
  const int nz = std::max(1, static_cast<int>(std::floor(o.depth / o.bin)));
  const std::size_t nb = static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz);
  for (int k = 0; k < nz; ++k) res.depth.push_back(o.depth - (k + 0.5) * o.bin);
  for (int j = 0; j < ny; ++j) res.y.push_back((j + 0.5) * o.bin);
  std::vector<analysis::SensorSeries> force(nb);
  std::vector<double> delta0(nb, 0.0), delta_max(nb, 0.0);
  std::size_t pre_samples = 0;
  std::vector<double> overlap_sum, per_particle_f;
  std::vector<int> contact_n;
  const auto bin_of = [&](const Vec& x) -> long {
    const int j = static_cast<int>(std::floor(x.y() / o.bin));
    const int k = static_cast<int>(std::floor(x.z() / o.bin));
    if (j < 0 || j >= ny || k < 0 || k >= nz) return -1;
    return static_cast<long>(k) * ny + j;
  };
  std::vector<double> bin_f(nb), bin_d(nb);
  std::vector<int> bin_n(nb);
  const auto sample = [&](ChannelSim& s) {
    const auto& p = s.particles();
    const std::size_t n = p.owned();
    overlap_sum.assign(n, 0.0);
    contact_n.assign(n, 0);
    for (const auto& c : s.recorded_contacts()) {
      if (c.j == analysis::ContactRecord<Dim3>::kWall) continue;
      if (c.i < n) {
        overlap_sum[c.i] += c.overlap;
        ++contact_n[c.i];
      }
      if (c.j < n) {
        overlap_sum[c.j] += c.overlap;
        ++contact_n[c.j];
      }
    }
    std::fill(bin_f.begin(), bin_f.end(), 0.0);
    std::fill(bin_d.begin(), bin_d.end(), 0.0);
    std::fill(bin_n.begin(), bin_n.end(), 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (p.group[i] != 0) continue;
      const long b = bin_of(p.x[i]);
      if (b < 0) continue;
      bin_f[b] += p.f[i].norm();
      bin_d[b] += contact_n[i] ? overlap_sum[i] / contact_n[i] : 0.0;
      ++bin_n[b];
    }
    for (std::size_t b = 0; b < nb; ++b) {
      const double f = bin_n[b] ? bin_f[b] / bin_n[b] : 0.0;
      const double d = bin_n[b] ? bin_d[b] / bin_n[b] : 0.0;
      if (o.sensor_time <= 0.0 || s.time() - t0 <= o.sensor_time) {
        force[b].time.push_back(s.time() - t0);
        force[b].signal.push_back(f);
      }
      if (s.time() < t0 - 0.5 * dt) {
        delta0[b] += d;  // summed over the pre-record, averaged below
      } else {
        delta_max[b] = std::max(delta_max[b], d);
      }
    }
    if (s.time() < t0 - 0.5 * dt) ++pre_samples;
  };
  const auto every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(o.sample_interval / dt)));
  // Columns for the bed height (001 section 2.8.2): 0.5 cm along y, the whole width in x.
  const analysis::BinGrid<Dim3> columns(Vec(0, 0, 0), Vec(o.width, ny * o.bin, sim.config().domain.hi.z()),
                                        Dim3::IVec(1, ny, 1));
  const auto heights = [&]() {
    std::vector<double> h(static_cast<std::size_t>(ny));
    // Without the contacts: after remove_above on a recording step, the frame's contact
    // records still name the removed particles (engine: remove_particles keeps them).
    auto fr = sim.frame();
    fr.contacts.clear();
    const auto ch = analysis::bed_height(fr, columns, 2);
    for (int j = 0; j < ny; ++j) h[static_cast<std::size_t>(j)] = ch[static_cast<std::size_t>(j)].height;
    return h;
  };
  std::vector<double> h_end(static_cast<std::size_t>(ny), 0.0);
  int h_count = 0;
  sim.request_contacts();
  sim.step();
  sample(sim);
  sim.every(every, sample, true);
  sim.run_until(t0);  // pre-record: the initial level of every sensor
  const std::vector<double> h0 = heights();
  if (o.bender) {
    const double w = 2.0 * std::numbers::pi * o.bender_frequency;
    sim.prescribe_group_velocity(piston_group, [=](double t) { return Vec(0, 0, v_p * std::cos(w * (t - t0))); });
  } else {
    auto& p = sim.particles();
    for (std::size_t i = 0; i < p.owned(); ++i)
      if (p.group[i] == piston_group) p.v[i] = Vec(0, v_p, 0);
  }
  io::ProgressReporter progress({.end_time = run_time, .mode = o.progress ? io::ProgressMode::On : io::ProgressMode::Off,
                                 .interval = 5.0, .label = o.bender ? "bender" : "piston"});
  bool released = !o.bender;
  const auto steps_per = [](double interval, double step) {
    return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(interval / step)));
  };
  std::uint64_t height_every = steps_per(2e-3, dt);
  // Ceiling: particles lofted 3 cm below the top of the domain are removed (checked every
  // 1 ms, which is safe below 30 m/s); 001 lets its domain grow instead (shrink-wrap ceiling).
  const double ceiling = sim.config().domain.hi.z() - 0.03;
  std::uint64_t ceiling_every = steps_per(1e-3, dt);
  bool tail = false;
  while (sim.time() - t0 < run_time) {
    if (!tail && o.tail_from > 0.0 && sim.time() - t0 >= o.tail_from && o.tail_dt > dt) {
      // The tail: a longer step, capped at 1/20 of the collision time of the fastest particle
      // (at least 0.1 m/s, the elastic limit of 001 section 4). The sensors' sampling stays
      // every `every` steps, so it becomes coarser in time by the same factor.
      const PairMaterial pm = sim.materials().pair(0, 0);
      const double m = channel_material(false).density * o.particle_volume();
      double vmax = 0.1;
      const auto& p = sim.particles();
      for (std::size_t i = 0; i < p.owned(); ++i) vmax = std::max(vmax, p.v[i].norm());
      const double dt_tail = std::min(o.tail_dt, hertz_collision_time(0.5 * m, pm.E_eff, 0.5 * r, vmax) / 20.0);
      if (dt_tail > dt) {
        sim.set_dt(dt_tail);
        height_every = steps_per(2e-3, dt_tail);
        ceiling_every = steps_per(1e-3, dt_tail);
        res.dt_tail = dt_tail;
      }
      tail = true;
    }
    sim.step();
    if (sim.step_count() % ceiling_every == 0) res.ejected += scene::remove_above(sim, 2, ceiling);
    if (!released && sim.time() - t0 >= 1.0 / o.bender_frequency - 0.5 * dt) {
      sim.release_group(piston_group);  // one period of the bender
      released = true;
    }
    progress.update(sim.step_count(), sim.time() - t0);
    const double t = sim.time() - t0;
    if (t > 2e-3) {
      const auto& p = sim.particles();
      for (std::size_t i = 0; i < p.owned(); ++i)
        if (p.group[i] == 0) res.max_particle_speed = std::max(res.max_particle_speed, p.v[i].norm());
    }
    // Final height: the mean over the last 0.2 s (001 section 2.8.2), or the last 20 % of a short run.
    if (t > std::max(0.8 * run_time, run_time - 0.2) && sim.step_count() % height_every == 0) {
      const auto h = heights();
      for (int j = 0; j < ny; ++j) h_end[static_cast<std::size_t>(j)] += h[static_cast<std::size_t>(j)];
      ++h_count;
    }
  }
  progress.finish(sim.step_count(), sim.time() - t0);
  res.steps = sim.step_count() - steps0;
  res.particles = sim.particles().owned();

  // Arrivals and front speeds per depth (001 section 2.8.3).
  // Threshold: 10 x the bin's mean level over the pre-record (001 section 2.8.3).
  res.arrival.assign(nb, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t b = 0; b < nb; ++b) {
    delta0[b] /= static_cast<double>(std::max<std::size_t>(1, pre_samples));
    analysis::SensorSeries after;
    double base = 0.0;
    std::size_t nbase = 0;
    for (std::size_t k = 0; k < force[b].time.size(); ++k) {
      if (force[b].time[k] < -0.5 * dt) {
        base += force[b].signal[k];
        ++nbase;
      } else {
        after.time.push_back(force[b].time[k]);
        after.signal.push_back(force[b].signal[k]);
      }
    }
    if (nbase == 0 || base <= 0.0) continue;
    analysis::ArrivalSettings as;
    as.absolute_threshold = 10.0 * base / static_cast<double>(nbase);
    if (const auto ta = analysis::arrival_time(after, as)) res.arrival[b] = *ta;
  }
  for (int k = 0; k < nz; ++k) {
    std::vector<double> tt(res.arrival.begin() + static_cast<long>(k) * ny,
                           res.arrival.begin() + static_cast<long>(k + 1) * ny);
    const auto [cw, cwu] = detail::row_speed(res.y, tt, o.cw_from, o.cw_to);
    const auto [cp, cpu] = detail::row_speed(res.y, tt, o.cp_from, o.cp_to);
    res.c_w.push_back(cw);
    res.c_w_u.push_back(cwu);
    res.c_p.push_back(cp);
    res.c_p_u.push_back(cpu);
  }
  detail::mean_sd(res.c_w, res.c_w_mean, res.c_w_sd);
  detail::mean_sd(res.c_p, res.c_p_mean, res.c_p_sd);
  // delta_m / delta_0 per column and the bed-height change.
  std::vector<double> ratio_window, dz_window, d0_all;
  for (int j = 0; j < ny; ++j) {
    double dm = 0.0, d0 = 0.0;
    int n = 0;
    for (int k = 0; k < nz; ++k) {
      const std::size_t b = static_cast<std::size_t>(k) * ny + j;
      if (delta0[b] <= 0.0) continue;
      dm += delta_max[b];
      d0 += delta0[b];
      d0_all.push_back(delta0[b]);
      ++n;
    }
    res.delta_ratio.push_back(n ? dm / d0 : std::numeric_limits<double>::quiet_NaN());
    const double hz = h_count ? h_end[static_cast<std::size_t>(j)] / h_count : std::numeric_limits<double>::quiet_NaN();
    res.dz.push_back(hz - h0[static_cast<std::size_t>(j)]);
    if (res.y[static_cast<std::size_t>(j)] >= o.cp_from && res.y[static_cast<std::size_t>(j)] <= o.cp_to) {
      ratio_window.push_back(res.delta_ratio.back());
      dz_window.push_back(res.dz.back());
    }
  }
  double sd = 0.0;
  detail::mean_sd(d0_all, res.delta_0, sd);
  detail::mean_sd(ratio_window, res.delta_ratio_mean, sd);
  detail::mean_sd(dz_window, res.dz_mean, res.dz_sd);
  res.wall_seconds = detail::elapsed_since(t_wall);
  return res;
}

}  // namespace granule::examples::lunar_shock
