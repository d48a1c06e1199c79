#pragma once
// Two parallel rods intruding vertically into a 3D bed of spheres (Pravin, Chang, Han, London,
// Goldman, Jaeger & Hsieh 2020, "Effect of two parallel intruders on net work during granular
// penetrations", paper 000 in shared/papers; section I.1, table I).
//
// Scene logic shared by main.cpp and tests/examples/test_two_rod_intrusion.cpp:
//  * prepare_bed: pour a bed once (jittered loose lattice falling under gravity, settled with
//    periodic velocity zeroing, trimmed to the fill height, settled again) and cache it in a
//    checkpoint whose file name is a hash of every bed parameter, so a changed bed is rebuilt;
//  * run_intrusion: load the bed, add one or two rods (square prisms or flat-capped cylinders,
//    axes along x, surface-to-surface gap s along y), each on its own Body driven down at U0
//    from just above the surface to the final depth z_f, and record the vertical force F(z);
//  * the net work W = integral_0^z_f F dz (000 section II), cross-checked with Body::work
//    (W = -integral F . V dt); at half depth: the PDF of f_n/<f_n> and the number of
//    "very strong" forces f_n > 6 <f_n> (000 section V, fig. 8), V_y and V_z binned along y
//    within 5d below the rods (000 fig. 5-6), and the shear strain-rate magnitude
//    |eps| = sqrt(eps_ij eps_ij), eps = (grad u + grad u^T)/2, of the coarse-grained velocity,
//    averaged along the rod length (000 section IV, fig. 7).
// Coordinates: x along the rods, y across them, z up; the bed fills the box [0, Lx] x [0, Ly]
// x [0, H]; depth z is measured from the mean bed surface down to the rods' lowest point.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <granule/analysis/coarse_graining.hpp>
#include <granule/analysis/force_network.hpp>
#include <granule/analysis/histogram.hpp>
#include <granule/analysis/profiles.hpp>
#include <granule/analysis/strain_rate.hpp>
#include <granule/boundaries/geometry/box_container.hpp>
#include <granule/boundaries/geometry/cylinder.hpp>
#include <granule/boundaries/geometry/display_mesh.hpp>
#include <granule/boundaries/geometry/prism.hpp>
#include <granule/granule.hpp>
#include <granule/io/checkpoint.hpp>
#include <granule/io/progress.hpp>
#include <granule/io/vtk.hpp>
#include <granule/analysis/bin_grid.hpp>
#include <granule/analysis/packing.hpp>
#include <granule/scene/settle.hpp>

namespace granule::examples::two_rod {

using Vec = Dim3::Vec;
// Hertz-Mindlin with the force history of the tangential spring (Thornton et al. 2013), the
// library's default until 2026-12-06: every result in results/ was computed with it, so the study
// keeps it until the ensembles are rerun with the potential form that is the default now
// (contact/tangential/spring.hpp; the two differ only in micro-slip, Chung & Ooi Test 4).
// A build may choose another law of contact/model.hpp with -DGRANULE_TWO_ROD_LAW=<name>: the
// target two_rod_intrusion_legacy (examples/CMakeLists.txt) is HertzMindlinLegacy, the
// LIGGGHTS 3.8 law paper 000 ran with (run_study.sh legacy9). The law's signature is part of the
// bed's key and of every study's results (law.txt), so results of two laws never mix.
#ifndef GRANULE_TWO_ROD_LAW
#define GRANULE_TWO_ROD_LAW HertzMindlinIncremental
#endif
using Law = contact::GRANULE_TWO_ROD_LAW;
using Sim = Simulation<Dim3, Law, neighbours::VerletList>;

/// Cross-section of the rods.
enum class RodShape {
  Square,    ///< square prism of width D
  Cylinder   ///< circular cylinder of diameter D with flat caps
};

inline const char* shape_name(RodShape s) { return s == RodShape::Square ? "square" : "cylinder"; }

/// Granular bed: particles, container and the pouring procedure (000 table I).
struct BedParams {
  double diameter = 4e-3;          ///< particle diameter d [m]
  double density = 1100.0;         ///< particle density rho [kg/m^3]
  double youngs_modulus = 5e6;     ///< E [Pa] (particles, rods and container alike)
  double poisson_ratio = 0.3;      ///< nu [-]
  double restitution = 0.2;        ///< e [-]
  double friction = 0.5;           ///< mu [-] (particle-particle and particle-wall)
  /// Friction while the grains fall and settle [-] (negative: `friction`). A lower value packs the
  /// bed denser (the standard way to reach a target packing, here 000's phi = 0.62); the
  /// settled bed is then an equilibrium for `friction` too (all forces normal, no sliding).
  double pour_friction = -1.0;
  double dt = 2.5e-5;              ///< time step [s]
  double pour_dt = -1.0;           ///< time step while pouring [s] (negative: dt); the settled
                                   ///< bed is static, so the intrusions' dt is restored after it
  double gravity = 9.81;           ///< g [m/s^2], along -z
  double length_x = 0.09;          ///< container length along the rods [m]
  double length_y = 0.10;          ///< container width across the rods [m]
  double fill_height = 0.06;       ///< bed height after trimming [m]
  double lattice_spacing = 1.08;   ///< initial lattice spacing / d [-]
  double jitter = 0.03;            ///< random lattice offset amplitude / d [-]
  double settle_ke = 1e-4;         ///< settled when mean KE per particle < settle_ke m g d [-]
  double zero_interval = 5e-3;     ///< velocities zeroed this often while settling [s]
  double max_settle_time = 1.5;    ///< give up settling after this long (each stage) [s]
  std::uint64_t seed = 1;          ///< lattice jitter seed
  bool allow_large_time_step = false;  ///< accept dt > 0.2 Rayleigh time (paper's own dt)
  double skin = -1.0;              ///< Verlet skin of the intrusions / d [-] (negative: the
                                   ///< library's 0.1 d); not part of the bed's key

  /// Particle mass m [kg].
  double particle_mass() const { return density * std::acos(-1.0) / 6.0 * diameter * diameter * diameter; }
  /// Friction used while pouring [-].
  double friction_while_pouring() const { return pour_friction < 0.0 ? friction : pour_friction; }
  /// Time step used while pouring [s].
  double dt_while_pouring() const { return pour_dt <= 0.0 ? dt : pour_dt; }
  /// Grains per lattice row along x and y, and lattice layers, of the initial loose column.
  std::array<int, 3> lattice_counts() const;
  /// Height of the container (and its lid) [m]: room for the loose column and for splashes.
  double container_height() const;
  /// Hash of every field that changes the bed (FNV-1a over their bytes).
  std::uint64_t key() const;
  /// "bed_<16 hex digits of key()>.ckpt".
  std::string checkpoint_name() const;
  /// Throws InvalidParameter for a bad field.
  void validate() const;
};

/// Intruders and their motion.
struct RodParams {
  RodShape shape = RodShape::Square;
  double width = 5e-3;       ///< D: square side or cylinder diameter [m]
  double length = 5e-2;      ///< L_r [m]
  double speed = 1.0;        ///< U0 [m/s], downwards
  double depth = 3e-2;       ///< z_f, final depth of the rods' bottom below the surface [m]
  double clearance = 0.5;    ///< start height of the rods' bottom above the surface / d [-]
  double offset_y = 0.0;     ///< shift of the rods' mid-plane from the container's mid-plane [m]
  void validate(const BedParams& bed) const;
};

/// What else a run does besides recording F(z).
struct RunOptions {
  bool analyse_half_depth = true;     ///< force PDF, velocity profiles, strain-rate map
  std::uint64_t vtk_every = 0;        ///< write VTK frames every n steps (0: never)
  std::filesystem::path vtk_dir;      ///< where the VTK series go
  io::ProgressMode progress = io::ProgressMode::Off;
  std::string label = "two_rod";      ///< progress label
};

/// The bed as cached: its surface and size.
struct BedInfo {
  double surface = 0.0;          ///< mean height of the free surface [m]
  std::size_t particles = 0;     ///< particle count
  bool built = false;            ///< true if this call poured it (false: read from the cache)
  double settle_time = 0.0;      ///< simulated pouring/settling time [s]
  double packing_fraction = 0.0; ///< N V_p / (Lx Ly surface) [-]
  std::filesystem::path checkpoint;
};

/// One sample of the force record.
struct ForceSample {
  double time = 0.0;      ///< since the start of the intrusion [s]
  double depth = 0.0;     ///< depth of the rods' bottom below the surface [m] (< 0: above)
  double force = 0.0;     ///< total vertical force of the grains on the rods (up > 0) [N]
  double force_a = 0.0;   ///< on rod a (y < centre, or the single rod) [N]
  double force_b = 0.0;   ///< on rod b [N] (0 for a single rod)
  double work = 0.0;      ///< integral_0^depth F dz so far (trapezoidal in depth) [J]
};

/// Shear strain-rate map row: one node of the y-z plane, averaged along x over the rods.
struct StrainRateNode {
  double y = 0.0;            ///< [m]
  double z = 0.0;            ///< [m]
  double strain_rate = 0.0;  ///< |eps| averaged along x [1/s] (NaN outside the bed)
  double v_y = 0.0;          ///< coarse-grained V_y averaged along x [m/s]
  double v_z = 0.0;          ///< coarse-grained V_z averaged along x [m/s]
};

/// Snapshot analysis at half depth (000 sections III-V).
struct HalfDepthAnalysis {
  bool done = false;
  double depth = 0.0;                ///< actual depth of the snapshot [m]
  double rod_bottom = 0.0;           ///< height of the rods' bottom [m]
  analysis::ForcePdf pdf;            ///< PDF of f_n / <f_n>, particle pairs
  std::size_t contacts = 0;          ///< particle-pair contacts
  std::size_t very_strong = 0;       ///< pair contacts with f_n > 6 <f_n>
  analysis::Profile v_y;             ///< V_y along y, 5d below the rods [m/s]
  analysis::Profile v_z;             ///< V_z along y, 5d below the rods [m/s]
  std::vector<StrainRateNode> strain;
};

/// Result of one intrusion.
struct RunResult {
  double gap = 0.0;                ///< s, surface-to-surface [m] (NaN for a single rod)
  int rods = 2;
  RodShape shape = RodShape::Square;
  std::vector<ForceSample> samples;
  double work = 0.0;               ///< integral_0^z_f F dz [J]
  double body_work = 0.0;          ///< sum of Body::work of the rods over the whole run [J]
  double peak_force = 0.0;         ///< max F [N]
  HalfDepthAnalysis half;
  std::size_t steps = 0;
  double wall_seconds = 0.0;
};

// ---- implementation ---------------------------------------------------------------------------

inline std::array<int, 3> BedParams::lattice_counts() const {
  // Grains for the fill height at a packing fraction of 0.64 (an upper bound of a random
  // pour), plus 8 % to trim, on a cubic lattice of spacing a inside the box.
  const double a = lattice_spacing * diameter;
  const double vp = std::acos(-1.0) / 6.0 * diameter * diameter * diameter;
  const double needed = 1.08 * 0.64 * length_x * length_y * fill_height / vp;
  const int nx = static_cast<int>(std::floor((length_x - diameter) / a)) + 1;
  const int ny = static_cast<int>(std::floor((length_y - diameter) / a)) + 1;
  const int layers = static_cast<int>(std::ceil(needed / (static_cast<double>(nx) * ny)));
  return {nx, ny, layers};
}

inline double BedParams::container_height() const {
  const double column = lattice_counts()[2] * lattice_spacing * diameter + diameter;
  return std::max(column + 2.0 * diameter, fill_height + 0.06);
}

inline void BedParams::validate() const {
  const std::string w = "two_rod::BedParams";
  require_positive(diameter, w, "diameter");
  require_positive(density, w, "density");
  require_positive(youngs_modulus, w, "youngs_modulus");
  require(poisson_ratio >= 0.0 && poisson_ratio < 0.5, w, "poisson_ratio", poisson_ratio, "[0, 0.5)");
  require(restitution > 0.0 && restitution <= 1.0, w, "restitution", restitution, "(0, 1]");
  require_non_negative(friction, w, "friction");
  require(std::isfinite(pour_friction), w, "pour_friction", pour_friction,
          "[0, inf), or negative for the same as friction");
  require_positive(dt, w, "dt");
  require_finite(pour_dt, w, "pour_dt");
  require_non_negative(gravity, w, "gravity");
  require(length_x >= 4.0 * diameter, w, "length_x", length_x, "[4 d, inf) m");
  require(length_y >= 4.0 * diameter, w, "length_y", length_y, "[4 d, inf) m");
  require(fill_height >= 3.0 * diameter, w, "fill_height", fill_height, "[3 d, inf) m");
  require(lattice_spacing > 1.0 && lattice_spacing < 3.0, w, "lattice_spacing", lattice_spacing, "(1, 3)");
  require(jitter >= 0.0 && 2.0 * jitter < lattice_spacing - 1.0, w, "jitter", jitter,
          "[0, (lattice_spacing - 1)/2)");
  require_positive(settle_ke, w, "settle_ke");
  require_non_negative(zero_interval, w, "zero_interval");
  require_positive(max_settle_time, w, "max_settle_time");
  require(std::isfinite(skin) && skin <= 2.0, w, "skin", skin, "[0, 2] (/ d), or negative for the default");
}

inline std::uint64_t BedParams::key() const {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      h ^= b[i];
      h *= 1099511628211ull;
    }
  };
  const char tag[] = "two_rod_bed_v2";
  mix(tag, sizeof(tag));
  const double v[] = {diameter, density, youngs_modulus, poisson_ratio, restitution, friction_while_pouring(), dt, gravity,
                      length_x, length_y, fill_height, lattice_spacing, jitter, settle_ke, zero_interval,
                      max_settle_time, dt_while_pouring()};
  mix(v, sizeof(v));
  mix(&seed, sizeof(seed));
  const std::uint8_t large = allow_large_time_step ? 1 : 0;
  mix(&large, 1);
  // The law, for any law but the one every cached bed so far was poured with (their names stay).
  if (const std::string law = Law::signature(); law != contact::HertzMindlinIncremental::signature())
    mix(law.data(), law.size());
  return h;
}

inline std::string BedParams::checkpoint_name() const {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "bed_%016llx.ckpt", static_cast<unsigned long long>(key()));
  return buf;
}

inline void RodParams::validate(const BedParams& bed) const {
  const std::string w = "two_rod::RodParams";
  require_positive(width, w, "width");
  require_positive(length, w, "length");
  require(length <= bed.length_x - 2.0 * bed.diameter, w, "length", length,
          "(0, container length_x - 2 d] m");
  require_positive(speed, w, "speed");
  require(depth > 0.0 && depth <= bed.fill_height - 2.0 * bed.diameter, w, "depth", depth,
          "(0, fill_height - 2 d] m");
  require_non_negative(clearance, w, "clearance");
}

/// Particle material of the bed (also used for the rods and the container); `pouring` gives it
/// the friction used while the bed is poured.
inline Material bed_material(const BedParams& p, bool pouring = false) {
  Material m;
  m.name = "grain";
  m.youngs_modulus = p.youngs_modulus;
  m.poisson_ratio = p.poisson_ratio;
  m.density = p.density;
  m.restitution = p.restitution;
  m.friction = pouring ? p.friction_while_pouring() : p.friction;
  return m;
}

/// Indices of the scene's two materials.
struct SceneMaterials {
  std::uint32_t grain = 0;
  std::uint32_t wall = 0;
};

/// A simulation with the bed's materials and container and no particles: the common start of
/// the pouring and of every intrusion (checkpoints need the same static set-up on both sides).
inline std::unique_ptr<Sim> make_bed_simulation(const BedParams& p, SceneMaterials* mats = nullptr,
                                                bool pouring = false) {
  p.validate();
  SimulationConfig<Dim3> cfg;
  const double h = p.container_height();
  const double pad = p.diameter;
  cfg.domain.lo = Vec(-pad, -pad, -pad);
  cfg.domain.hi = Vec(p.length_x + pad, p.length_y + pad, h + pad);
  cfg.gravity = Vec(0.0, 0.0, -p.gravity);
  cfg.dt = p.dt;
  cfg.allow_large_time_step = p.allow_large_time_step;
  if (!pouring && p.skin >= 0.0) cfg.skin = p.skin * p.diameter;
  auto sim = std::make_unique<Sim>(cfg);
  Material grain = bed_material(p, pouring);
  SceneMaterials m;
  m.grain = sim->add_material(grain);
  Material wall = grain;
  wall.name = "wall";
  m.wall = sim->add_wall_material(wall);
  sim->add_wall(geometry::BoxContainerShape<Dim3>(Vec::Zero(), Vec(p.length_x, p.length_y, h)), m.wall);
  if (mats) *mats = m;
  return sim;
}

/// Mean height of the free surface [m]: the top view is cut into square columns of side 2 d
/// away from the walls (a margin of 2 d); analysis::bed_height gives each column's height (the
/// mean centre height of as many top grains as fit side by side on the column); the surface is
/// the mean of the columns plus one radius.
inline double bed_surface(const Sim& sim, const BedParams& p) {
  const double w = 2.0 * p.diameter;
  const double margin = 2.0 * p.diameter;
  const int nx = std::max(1, static_cast<int>((p.length_x - 2.0 * margin) / w));
  const int ny = std::max(1, static_cast<int>((p.length_y - 2.0 * margin) / w));
  const analysis::BinGrid<Dim3> columns(Vec(margin, margin, -p.diameter),
                                        Vec(margin + nx * w, margin + ny * w, p.container_height()),
                                        Dim3::IVec(nx, ny, 1));
  double s = 0.0;
  int n = 0;
  for (const auto& c : analysis::bed_height(sim.frame(), columns))
    if (c.used > 0) {
      s += c.height;
      ++n;
    }
  return n > 0 ? s / n + 0.5 * p.diameter : std::numeric_limits<double>::quiet_NaN();
}

/// Packing fraction of the bed's interior [-]: exact sphere-box volumes (analysis::packing_
/// fraction) in the box 2 d from every wall, from 2 d above the floor to 2 d below the surface.
inline double interior_packing(const Sim& sim, const BedParams& p, double surface) {
  const double m = 2.0 * p.diameter;
  const analysis::BinGrid<Dim3> box(Vec(m, m, m), Vec(p.length_x - m, p.length_y - m, surface - m),
                                    Dim3::IVec(1, 1, 1));
  return analysis::packing_fraction(sim.frame(), box)[0];
}

namespace detail {
inline std::uint64_t bits(double v) {
  std::uint64_t u;
  std::memcpy(&u, &v, sizeof(u));
  return u;
}
inline double from_bits(std::uint64_t u) {
  double v;
  std::memcpy(&v, &u, sizeof(v));
  return v;
}
}  // namespace detail

/// Pours and settles a bed into `sim` (made by make_bed_simulation with pouring = true): a
/// jittered loose cubic lattice with small random velocities falls under gravity, is settled by
/// scene::settle (velocities zeroed every zero_interval until the mean kinetic energy per grain
/// is below settle_ke m g d), trimmed to the fill height (scene::remove_above) and settled
/// again. `log` receives one line per stage.
inline BedInfo pour_bed(Sim& sim, const BedParams& p, std::uint32_t grain,
                        const std::function<void(const std::string&)>& log = {}) {
  const double d = p.diameter;
  const double r = 0.5 * d;
  const double a = p.lattice_spacing * d;
  const auto [nx, ny, layers] = p.lattice_counts();
  const double x0 = 0.5 * (p.length_x - (nx - 1) * a);
  const double y0 = 0.5 * (p.length_y - (ny - 1) * a);
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double jit = p.jitter * d;
  const double vkick = 0.05 * std::sqrt(p.gravity * d);
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        Vec x(x0 + i * a + jit * u(rng), y0 + j * a + jit * u(rng), r + 0.5 * (a - d) + k * a + jit * u(rng));
        x.x() = std::clamp(x.x(), r, p.length_x - r);
        x.y() = std::clamp(x.y(), r, p.length_y - r);
        Vec v(vkick * u(rng), vkick * u(rng), vkick * u(rng));
        sim.add_particle(x, r, grain, v);
      }
  if (log) log("pouring " + std::to_string(sim.particles().owned()) + " particles (" + std::to_string(layers) +
               " layers of " + std::to_string(nx) + " x " + std::to_string(ny) + "), friction " +
               std::to_string(p.friction_while_pouring()));
  const double m = p.particle_mass();
  BedInfo info;
  const double t0 = sim.time();
  sim.set_dt(p.dt_while_pouring());
  // Progress of a long pour (a million grains take an hour): a line every 30 s of wall time,
  // with the simulated time, the kinetic energy against the settling target and, for the fall,
  // whose end is known, an ETA.
  using Clock = std::chrono::steady_clock;
  const auto wall0 = Clock::now();
  auto last = wall0;
  const auto reporter = [&](const char* stage, double t_end) {
    return [&, stage, t_end](double t, double ke) {
      const auto now = Clock::now();
      if (!log || now - last < std::chrono::seconds(30)) return;
      last = now;
      const double wall = std::chrono::duration<double>(now - wall0).count();
      std::ostringstream s;
      s.precision(3);
      s << "  pour: " << stage << ", t = " << t - t0 << " s, KE/(m g d) = " << ke / (m * p.gravity * d)
        << " (target " << p.settle_ke << "), " << wall << " s wall";
      if (t_end > 0.0 && t > t0) s << ", stage ETA " << wall * (t_end - t) / (t - t0) << " s";
      log(s.str());
    };
  };
  // Free fall of the column (no damping) for the time its top layer needs to land.
  scene::SettleOptions fall;
  fall.max_time = std::sqrt(2.0 * layers * a / std::max(p.gravity, 1e-9)) + 0.02;
  fall.kinetic_energy_per_particle = 0.0;
  fall.check_interval = 0.01 * fall.max_time;
  fall.on_check = reporter("free fall", t0 + fall.max_time);
  scene::settle(sim, fall);
  scene::SettleOptions calm;
  calm.max_time = p.max_settle_time;
  calm.zero_velocity_interval = p.zero_interval;
  calm.check_interval = p.zero_interval > 0.0 ? p.zero_interval : 5e-3;
  calm.kinetic_energy_per_particle = p.settle_ke * m * p.gravity * d;
  calm.on_check = reporter("settling", 0.0);
  auto res = scene::settle(sim, calm);
  if (log) log("settled (stage 1) after " + std::to_string(sim.time() - t0) + " s, mean KE/(m g d) = " +
               std::to_string(res.kinetic_energy_per_particle / (m * p.gravity * d)));
  const std::size_t removed = scene::remove_above(sim, 2, p.fill_height - r);
  res = scene::settle(sim, calm);
  if (!res.settled && log) log("warning: stage 2 did not reach the kinetic-energy criterion in max_settle_time");
  for (std::size_t i = 0; i < sim.particles().owned(); ++i) {
    sim.particles().v[i].setZero();
    sim.particles().omega[i].setZero();
  }
  info.settle_time = sim.time() - t0;
  sim.set_dt(p.dt);
  info.particles = sim.particles().owned();
  info.surface = bed_surface(sim, p);
  info.packing_fraction = interior_packing(sim, p, info.surface);
  if (log) log("trimmed " + std::to_string(removed) + " particles; settled (stage 2), " +
               std::to_string(info.particles) + " particles, surface at " + std::to_string(info.surface) +
               " m, interior packing fraction " + std::to_string(info.packing_fraction));
  return info;
}

/// A simulation holding the bed, ready for rods to be added.
struct LoadedBed {
  std::unique_ptr<Sim> sim;
  SceneMaterials materials;
  BedInfo info;
};

/// Loads the cached bed of `p` from `cache_dir`, or pours it (and writes the cache) when the
/// file is missing or unreadable. The bed is poured in a simulation whose grains have the
/// pouring friction and read back into one with `p.friction` (allow_other_materials: the
/// checkpoint records the pouring materials). The checkpoint's user section holds {key, surface bits, settle-time
/// bits, packing bits}; the file name already encodes the key, so a changed bed gets a new file.
inline LoadedBed load_or_prepare_bed(const BedParams& p, const std::filesystem::path& cache_dir,
                                     const std::function<void(const std::string&)>& log = {}) {
  LoadedBed out;
  const std::filesystem::path file = cache_dir / p.checkpoint_name();
  auto read = [&]() -> bool {
    out.sim = make_bed_simulation(p, &out.materials);
    const auto user = io::read_checkpoint(*out.sim, file.string(), {.allow_other_materials = true});
    if (user.size() != 4 || user[0] != p.key()) return false;
    out.info.surface = detail::from_bits(user[1]);
    out.info.settle_time = detail::from_bits(user[2]);
    out.info.packing_fraction = detail::from_bits(user[3]);
    out.info.particles = out.sim->particles().owned();
    out.info.checkpoint = file;
    return true;
  };
  if (std::filesystem::exists(file)) {
    try {
      if (read()) return out;
      if (log) log("cached bed " + file.string() + " has another key; rebuilding it");
    } catch (const IoError& e) {
      if (log) log(std::string("cannot use the cached bed (") + e.what() + "); rebuilding it");
    }
  }
  SceneMaterials pm;
  auto pour = make_bed_simulation(p, &pm, true);
  const BedInfo info = pour_bed(*pour, p, pm.grain, log);
  std::filesystem::create_directories(cache_dir);
  io::write_checkpoint(*pour, file.string(),
                       {p.key(), detail::bits(info.surface), detail::bits(info.settle_time),
                        detail::bits(info.packing_fraction)});
  pour.reset();
  if (!read()) throw IoError("two_rod: the bed just written to " + file.string() + " cannot be read back");
  out.info.built = true;
  return out;
}

/// y of the rod centre lines for a surface-to-surface gap `gap` [m], symmetric about the
/// container's mid-plane; one rod sits on the mid-plane.
inline std::vector<double> rod_centres_y(const BedParams& bed, const RodParams& rod, int rods, double gap) {
  const double yc = 0.5 * bed.length_y + rod.offset_y;
  if (rods == 1) return {yc};
  const double off = 0.5 * (gap + rod.width);
  return {yc - off, yc + off};
}

/// Display mesh of a rod in world coordinates (for VTK output).
inline geometry::DisplayMesh rod_mesh(const RodParams& rod, const geometry::Pose<Dim3>& pose) {
  geometry::DisplayMesh m;
  if (rod.shape == RodShape::Square) {
    m = geometry::tessellate(geometry::PrismShape<Dim3>(Vec::Zero(), Vec(0.5 * rod.length, 0.5 * rod.width, 0.5 * rod.width)));
  } else {
    m = geometry::tessellate(geometry::CylinderShape(Vec::Zero(), Vec::UnitX(), 0.5 * rod.width, 0.5 * rod.length));
  }
  m.transform(pose);
  return m;
}

/// Half-depth snapshot analysis of a frame with recorded contacts.
inline HalfDepthAnalysis analyse_snapshot(const analysis::Frame<Dim3>& frame, const BedParams& bed,
                                          const RodParams& rod, const std::vector<double>& rods_y,
                                          double rod_bottom, double surface) {
  HalfDepthAnalysis h;
  h.done = true;
  h.rod_bottom = rod_bottom;
  h.depth = surface - rod_bottom;
  const double d = bed.diameter;
  const double xc = 0.5 * bed.length_x;
  // Normal-force statistics over particle pairs (000 fig. 8).
  h.pdf = analysis::normal_force_pdf(frame, analysis::uniform_edges(0.0, 20.0, 80));
  h.contacts = h.pdf.histogram.samples;
  h.very_strong = analysis::count_strong_forces(frame, 6.0);
  // Velocity profiles along y in the slab 5 d below the rods, |x - xc| <= min(10 d, L/2)
  // (000 fig. 5: x/d in [-10, 10]); bins of d/2 across the container.
  const double hx = std::min(10.0 * d, 0.5 * rod.length);
  const Vec lo(xc - hx, d, rod_bottom - 5.0 * d);
  const Vec hi(xc + hx, bed.length_y - d, rod_bottom);
  const auto bins = static_cast<std::size_t>(std::max(1.0, std::round((hi.y() - lo.y()) / (0.5 * d))));
  h.v_y = analysis::velocity_profile(frame, lo, hi, 1, bins, 1);
  h.v_z = analysis::velocity_profile(frame, lo, hi, 1, bins, 2);
  // Strain rate of the coarse-grained velocity (Gaussian kernel of width d/2, grid d/2) in the
  // y-z plane around the rods, averaged along the rods' length (000 fig. 7).
  const double span = rods_y.back() - rods_y.front();
  const double ymid = 0.5 * (rods_y.back() + rods_y.front());
  const double half_y = std::min(0.5 * span + rod.width + 8.0 * d, 0.5 * bed.length_y - d);
  const Vec glo(xc - 0.5 * rod.length, ymid - half_y, std::max(d, rod_bottom - 10.0 * d));
  const Vec ghi(xc + 0.5 * rod.length, ymid + half_y, surface);
  const analysis::RegularGrid<Dim3> grid(glo, ghi, 0.5 * d);
  const analysis::GaussianCgKernel<Dim3> kernel(0.5 * d);
  analysis::CgOptions opt;
  opt.contact_stress = false;
  const auto fields = analysis::coarse_grain_direct(frame, grid, kernel, opt);
  const auto eps = analysis::strain_rate(fields, 0.2 * bed.density);
  const auto n = grid.count();
  for (int kz = 0; kz < n[2]; ++kz)
    for (int ky = 0; ky < n[1]; ++ky) {
      double s = 0.0, vy = 0.0, vz = 0.0;
      int cs = 0, cv = 0;
      for (int kx = 0; kx < n[0]; ++kx) {
        const std::size_t idx = grid.index(Dim3::IVec(kx, ky, kz));
        const double e = analysis::strain_rate_magnitude(eps[idx]);
        if (std::isfinite(e)) {
          s += e;
          ++cs;
        }
        if (fields.density[idx] >= 0.2 * bed.density) {
          vy += fields.velocity[idx].y();
          vz += fields.velocity[idx].z();
          ++cv;
        }
      }
      const double nan = std::numeric_limits<double>::quiet_NaN();
      const Vec node = grid.node(Dim3::IVec(0, ky, kz));
      h.strain.push_back({node.y(), node.z(), cs > 0 ? s / cs : nan, cv > 0 ? vy / cv : nan, cv > 0 ? vz / cv : nan});
    }
  return h;
}

/// Integral of F dz over depth in [0, z_f] by the trapezoidal rule on the samples, with the
/// segments that cross 0 or z_f cut by linear interpolation; fills ForceSample::work [J].
inline double integrate_work(std::vector<ForceSample>& s, double z_f) {
  double w = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (k > 0) {
      const double z1 = s[k - 1].depth, z2 = s[k].depth;
      const double a = std::max(z1, 0.0), b = std::min(z2, z_f);
      if (b > a && z2 > z1) {
        auto f_at = [&](double z) { return s[k - 1].force + (s[k].force - s[k - 1].force) * (z - z1) / (z2 - z1); };
        w += 0.5 * (f_at(a) + f_at(b)) * (b - a);
      }
    }
    s[k].work = w;
  }
  return w;
}

/// Least-squares slope dF/dz [N/m] of the samples with depth in [z_lo, z_hi].
inline double force_slope(const std::vector<ForceSample>& s, double z_lo, double z_hi) {
  double n = 0, sz = 0, sf = 0, szz = 0, szf = 0;
  for (const auto& q : s) {
    if (q.depth < z_lo || q.depth > z_hi) continue;
    n += 1;
    sz += q.depth;
    sf += q.force;
    szz += q.depth * q.depth;
    szf += q.depth * q.force;
  }
  const double den = n * szz - sz * sz;
  return den > 0.0 ? (n * szf - sz * sf) / den : std::numeric_limits<double>::quiet_NaN();
}

/// One intrusion of `rods` (1 or 2) rods with surface gap `gap` [m] into the cached bed.
inline RunResult run_intrusion(const BedParams& bed, const RodParams& rod, int rods, double gap,
                               const std::filesystem::path& cache_dir, const RunOptions& opt = {},
                               const std::function<void(const std::string&)>& log = {}) {
  require(rods == 1 || rods == 2, "two_rod::run_intrusion", "rods", rods, "{1, 2}");
  rod.validate(bed);
  const double d = bed.diameter;
  RunResult res;
  res.rods = rods;
  res.shape = rod.shape;
  res.gap = rods == 2 ? gap : std::numeric_limits<double>::quiet_NaN();
  const auto ys = rod_centres_y(bed, rod, rods, gap);
  if (rods == 2) require(gap >= 0.0, "two_rod::run_intrusion", "gap", gap, "[0, inf) m");
  require(ys.front() - 0.5 * rod.width >= 2.0 * d && ys.back() + 0.5 * rod.width <= bed.length_y - 2.0 * d,
          "two_rod::run_intrusion", "gap (with offset_y)", gap,
          "values that keep every rod at least 2 d from the side walls [m]");
  LoadedBed lb = load_or_prepare_bed(bed, cache_dir, log);
  Sim& sim = *lb.sim;
  const double surface = lb.info.surface;
  const double xc = 0.5 * bed.length_x;
  const double z_start = surface + rod.clearance * d + 0.5 * rod.width;  // rod axis height
  std::vector<std::uint32_t> bodies;
  const double u0 = rod.speed;
  for (double y : ys) {
    Body<Dim3> b;
    b.name = bodies.empty() ? "rod_a" : "rod_b";
    b.pose = geometry::Pose<Dim3>::translation(Vec(xc, y, z_start));
    b.velocity = [u0](double) { return Vec(0.0, 0.0, -u0); };
    const std::uint32_t idx = sim.add_body(b);
    if (rod.shape == RodShape::Square) {
      sim.add_wall(geometry::PrismShape<Dim3>(Vec::Zero(), Vec(0.5 * rod.length, 0.5 * rod.width, 0.5 * rod.width)),
                   lb.materials.wall, idx);
    } else {
      sim.add_wall(geometry::CylinderShape(Vec::Zero(), Vec::UnitX(), 0.5 * rod.width, 0.5 * rod.length),
                   lb.materials.wall, idx);
    }
    bodies.push_back(idx);
  }
  const double travel = rod.clearance * d + rod.depth;
  const auto steps = static_cast<std::uint64_t>(std::ceil(travel / (u0 * bed.dt) - 1e-9));
  const auto half_step = static_cast<std::uint64_t>(std::ceil((rod.clearance * d + 0.5 * rod.depth) / (u0 * bed.dt) - 1e-9));
  const double t0 = sim.time();
  auto bottom = [&]() { return sim.body(bodies[0]).pose.translation().z() - 0.5 * rod.width; };

  std::unique_ptr<io::VtkWriter<Dim3>> vtk_particles;
  std::unique_ptr<io::SurfaceVtkWriter> vtk_rods;
  auto write_vtk = [&]() {
    if (!vtk_particles) return;
    vtk_particles->write(sim.frame(), {}, sim.time() - t0);
    std::vector<geometry::DisplayMesh> parts;
    for (auto b : bodies) parts.push_back(rod_mesh(rod, sim.body(b).pose));
    vtk_rods->write(parts, sim.time() - t0);
  };
  if (opt.vtk_every > 0) {
    std::filesystem::create_directories(opt.vtk_dir);
    vtk_particles = std::make_unique<io::VtkWriter<Dim3>>(opt.vtk_dir, "particles");
    vtk_rods = std::make_unique<io::SurfaceVtkWriter>(opt.vtk_dir, "rods");
    io::SurfaceVtkWriter box(opt.vtk_dir, "container");
    const geometry::DisplayMesh c = geometry::tessellate(
        geometry::BoxContainerShape<Dim3>(Vec::Zero(), Vec(bed.length_x, bed.length_y, bed.container_height())));
    box.write(std::vector<geometry::DisplayMesh>{c}, 0.0);
    write_vtk();
  }

  io::ProgressOptions po;
  po.total_steps = steps;
  po.mode = opt.progress;
  po.label = opt.label;
  io::ProgressReporter progress(po);
  const auto wall_start = std::chrono::steady_clock::now();
  res.samples.reserve(steps + 1);
  res.samples.push_back({0.0, surface - bottom(), 0.0, 0.0, 0.0, 0.0});
  for (std::uint64_t k = 1; k <= steps; ++k) {
    const bool snapshot = opt.analyse_half_depth && k == half_step;
    if (snapshot) sim.request_contacts();
    sim.step();
    ForceSample q;
    q.time = sim.time() - t0;
    q.depth = surface - bottom();
    q.force_a = sim.body(bodies[0]).force.z();
    q.force_b = rods == 2 ? sim.body(bodies[1]).force.z() : 0.0;
    q.force = q.force_a + q.force_b;
    res.samples.push_back(q);
    res.peak_force = std::max(res.peak_force, q.force);
    if (snapshot) res.half = analyse_snapshot(sim.frame(), bed, rod, ys, bottom(), surface);
    if (opt.vtk_every > 0 && k % opt.vtk_every == 0) write_vtk();
    progress.update(k, q.time);
  }
  progress.finish(steps, sim.time() - t0);
  res.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  res.steps = steps;
  res.work = integrate_work(res.samples, rod.depth);
  for (auto b : bodies) res.body_work += sim.body(b).work;
  return res;
}

/// Peak of W(s/d) and its ratio to the value at the largest gap.
struct PeakSummary {
  double gap_over_d = 0.0;   ///< (s/d) at the largest W [-]
  double work = 0.0;         ///< W at the peak [J]
  double plateau_work = 0.0; ///< W at the largest gap swept [J]
  double ratio = 0.0;        ///< work / plateau_work [-]
};

inline PeakSummary find_peak(const std::vector<double>& gap_over_d, const std::vector<double>& work) {
  require(!work.empty() && gap_over_d.size() == work.size(), "two_rod::find_peak", "size", work.size(),
          "[1, inf), equal sizes");
  PeakSummary p;
  const auto k = static_cast<std::size_t>(std::max_element(work.begin(), work.end()) - work.begin());
  const auto last = static_cast<std::size_t>(std::max_element(gap_over_d.begin(), gap_over_d.end()) - gap_over_d.begin());
  p.gap_over_d = gap_over_d[k];
  p.work = work[k];
  p.plateau_work = work[last];
  p.ratio = p.work / p.plateau_work;
  return p;
}

}  // namespace granule::examples::two_rod
