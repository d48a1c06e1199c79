#pragma once
// A thin intruder pulled up out of a 2D bed of disks at constant speed (Mandato, Cuq, Ruiz,
// Dirrenberger & Fakih et al., "intruder pull-out ... coarse-graining", paper 002 in
// shared/papers; sections 2.3-2.5, 3 and 4).
//
// Scene logic shared by main.cpp, study.hpp and tests/examples/test_intruder_pull_out_2d.cpp:
//  * build: a cell of width W closed by sphero-line walls (floor and two sides, 002 section 2.3
//    "Walls and intruder"), the intruder as a horizontal sphero-line of length L on its own Body,
//    lying just above the floor (gap < d_min, so no disk gets under it);
//  * fill: a faster stand-in for 002's hopper (section 2.4: hours of computation). What it keeps
//    of the hopper is its outlet: the disks leave an 11 mm wide outlet centred above the cell
//    (002's D_o) at a controlled rate (the aperture "allows to control the filling rate"), from
//    3 bed heights above the floor (002's outlet at H_o = 447 mm over a 150 mm bed), and pile up
//    in a heap that spreads by surface avalanches; they are inserted at rest at random,
//    non-overlapping positions of the release region (scene::Pour, continuous stream), which
//    replaces the flow inside the hopper. Once all have landed the bed is settled
//    (scene::settle with periodic velocity zeroing). Optional: all disks at once (fill_rate = 0,
//    the former filling, looser) and a reduced friction during the filling (fill_friction: the
//    scene is rebuilt with the same disks and mu before the final settling). The number of
//    disks is 002's, 1600 per 100 mm x 150 mm of bed; the packing fraction is measured after
//    settling (measure_packing: analysis/packing.hpp, exact disk-bin areas). A settled bed can
//    be cached in a checkpoint (save_bed / load_bed), so that pulls at several speeds start
//    from the same bed;
//  * pull: the intruder moves up at V; every sample the vertical force of the disks on it,
//    averaged over the sample's steps, is recorded as the drag F = -F_y (positive when the bed
//    resists the rise), with the mean friction mobilisation mu* = |ft|/(mu fn) of the bulk and
//    of the cell walls (002 section 4, force_network.hpp). Every sample the velocity field is
//    coarse-grained with 002's kernel (section 2.5: Gaussian of width w = 1.5 d, cutoff 4 w,
//    eq. 4-9; coarse_graining.hpp), divided by V, and split into 002's flow zones with the
//    opening of the mobile cone measured (section 3.2, analysis/flow_zones.hpp). Velocity maps
//    are kept at chosen heights, each at the loading peak nearest to it (the sample of largest
//    drag within d/2 of the height): 002 shows its fields "during loading phases just before
//    the rupture of force chains" (section 3.2, fig. 8), instantaneous, not time-averaged.
// Contact law (002 section 2.3): linear normal spring k_n = E d (Material::reference_length =
// mean diameter), restitution e, incremental Coulomb friction with k_t = k_n / 2, and a rolling
// resistance standing in for 002's law |M| <= mu d 1e-2 F_n, k_r = d^2 k_n 1e-3. granule's EPSD
// law has |M| <= mu_r R* F_n and k_r = c k_n mu_r^2 R*^2; for two disks of the mean diameter
// R* = d/4, which gives mu_r = 4 mu 1e-2 and c = 1e-3 * 16 / (4 mu 1e-2)^2 (exact for equal
// mean-size pairs only: both EPSD quantities scale with R* of the actual pair).
// Disk thickness t (masses m = rho pi r^2 t): every force of the scene (contacts, their dashpots,
// gravity) is proportional to t at a fixed E/t, and every mass too, so the motion depends on E
// and t only through E/t: the stiffness number kappa (stiffness_number) is the physical
// parameter, and the drag scales with t. 002 does not state t; its step (section 2.4: dt = 1e-8
// s = dt_c / 60 with dt_c = sqrt(m_min / k_n), k_n = 1.92e8 N/m) implies m_min = 6.9e-5 kg,
// i.e. t = 8.8 mm for its lightest disk (d_min = 2 mm): 3 d to the precision of its "1/60"
// (README, "Time step and disk thickness"). The default is t = 3 d.
// Coordinates: x across the cell [0, W], y up; the floor surface is y = 0.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <granule/analysis/coarse_graining.hpp>
#include <granule/analysis/flow_zones.hpp>
#include <granule/analysis/force_network.hpp>
#include <granule/analysis/packing.hpp>
#include <granule/io/checkpoint.hpp>
#include <granule/boundaries/geometry/sphero_line.hpp>
#include <granule/granule.hpp>
#include <granule/scene/pour.hpp>
#include <granule/scene/settle.hpp>

namespace granule::examples::pull_out {

using Vec = Dim2::Vec;
using Sim = Simulation<Dim2, contact::LinearCoulombRolling, neighbours::VerletList>;

/// Time step of the pull.
enum class TimeStepRule {
  Engine,  ///< 0.2 x linear_critical_time of the two lightest disks: the largest the engine accepts
  Paper    ///< 002 section 2.4: dt_c / 60 with dt_c = sqrt(m_min / k_n)
};

/// Every parameter of the scene (defaults: the quick mode; paper_params() gives 002's values).
struct PullParams {
  double cell_width = 0.040;       ///< W [m]
  double bed_height = 0.050;       ///< target bed height [m]
  double mean_diameter = 3e-3;     ///< d [m]
  double size_ratio = 2.0;         ///< d_max / d_min, radii uniform [-]
  double density = 2500.0;         ///< rho [kg/m^3]
  double thickness = 9e-3;         ///< disk thickness t [m]: 3 d, what 002's step implies (file comment)
  double youngs_modulus = 6e7;     ///< E, k_n = E d [Pa]; at t = 3 d the former quick value 2e7 Pa at t = d
  double friction = 0.5;           ///< mu [-]
  double restitution = 0.9;        ///< e [-]
  double intruder_length = 0.010;  ///< L [m]
  double intruder_radius = 1e-3;   ///< cap radius of the intruder sphero-line (half thickness) [m]
  double wall_radius = 1e-3;       ///< cap radius of the cell walls [m]
  double pull_velocity = 0.02;     ///< V [m/s]
  double sample_travel = 2e-4;     ///< intruder travel between two drag samples [m]
  double fill_time = 1.0;          ///< max settling time after the filling [s]
  TimeStepRule dt_rule = TimeStepRule::Engine;  ///< step of the pull (the filling always uses Engine)
  double dt = 0.0;                 ///< explicit step of the pull [s]; 0: from dt_rule
  double cg_width = 1.5;           ///< coarse-graining kernel width w / d (002 section 2.5: 1.5) [-]
  double cg_spacing = 0.5;         ///< node spacing of the coarse-grained fields / d [-]
  // Filling (file comment): disks released per second from a region of width fill_source_width
  // centred above the cell, its bottom fill_release_height above the floor, with the friction
  // fill_friction (mu_r in proportion) until the bed has formed; then mu is restored and the bed
  // settled.
  double fill_rate = 100.0;          ///< disks released per second; 0: all at once, one batch [1/s]
  double fill_source_width = 0.011;  ///< width of the release region [m] (002's hopper outlet); 0: the whole cell
  double fill_release_height = 0.0;  ///< bottom of the release region above the floor [m]; 0: 3 x bed height
  double fill_friction = -1.0;       ///< mu while filling [-]; < 0: mu itself
  std::uint64_t seed = 1;          ///< insertion seed
};

/// 002's values: 100 mm cell, 150 mm bed, E = 64 GPa, V = 1.2 mm/s, its step dt_c / 60.
inline PullParams paper_params() {
  PullParams p;
  p.cell_width = 0.100;
  p.bed_height = 0.150;
  p.youngs_modulus = 64e9;
  p.pull_velocity = 1.2e-3;
  p.sample_travel = 1e-4;
  p.dt_rule = TimeStepRule::Paper;
  p.fill_rate = 250.0;  // the quick mode's rate per cell width, i.e. the same surface rise speed
  return p;
}

/// Packing fraction 002 reports (section 2.4), used for the pressure scale.
inline constexpr double kPaperPacking = 0.82;
/// Opening angle of the mobile cone in 002 (section 3.2 c) [deg].
inline constexpr double kPaperConeAngle = 60.0;
inline constexpr double kGravity = 9.81;  ///< [m/s^2]

inline double r_min(const PullParams& p) { return p.mean_diameter / (1.0 + p.size_ratio); }
/// Mass of a disk of radius r [kg].
inline double disk_mass(const PullParams& p, double r) { return p.density * std::numbers::pi * r * r * p.thickness; }
/// k_n = E d [N/m] (002 section 2.3).
inline double normal_stiffness(const PullParams& p) { return p.youngs_modulus * p.mean_diameter; }
/// The engine's largest step: 0.2 x the linear critical time of the two lightest disks (m* =
/// m_min / 2). At e = 0.9 it is 3 % below 0.2 x the undamped pi sqrt(m*/k_n): the dashpot lowers
/// the stability limit (linear_critical_time) [s].
inline double engine_dt(const PullParams& p) {
  return 0.2 * linear_critical_time(normal_stiffness(p), 0.5 * disk_mass(p, r_min(p)), p.restitution);
}
/// 002's dt_c = sqrt(m_min / k_n), m_min the mass of the lightest disk (section 2.4) [s].
inline double paper_critical_time(const PullParams& p) {
  return std::sqrt(disk_mass(p, r_min(p)) / normal_stiffness(p));
}
/// Step of the pull [s].
inline double pull_dt(const PullParams& p) {
  if (p.dt > 0.0) return p.dt;
  return p.dt_rule == TimeStepRule::Paper ? paper_critical_time(p) / 60.0 : engine_dt(p);
}
/// Pressure scale p = rho phi g H at the floor of a bed of height H at 002's packing [Pa].
inline double pressure_scale(const PullParams& p) { return p.density * kPaperPacking * kGravity * p.bed_height; }
/// Stiffness number kappa = k_n / (p t): the 2D contact force on a disk of the bed's floor is of
/// order p d t, its overlap delta = p d t / k_n, so delta / d = 1 / kappa (the 2D kappa = k_n / P
/// of da Cruz et al. 2005, Phys. Rev. E 72 021309, with the 2D pressure P = p t in N/m) [-].
inline double stiffness_number(const PullParams& p) { return normal_stiffness(p) / (pressure_scale(p) * p.thickness); }
/// Inertial number of the pull I = (V / d) d sqrt(rho / p) = V / sqrt(phi g H): the shear rate
/// V / d over the confinement rate sqrt(p / rho) / d (GDR MiDi 2004); independent of t [-].
inline double inertial_number(const PullParams& p) {
  return p.pull_velocity / std::sqrt(kPaperPacking * kGravity * p.bed_height);
}
/// 002's H1 = (W - L) / 2 tan(beta) (section 3.2 c): the rise over which edges of inclination beta
/// from the intruder's tips reach the side walls. 002 uses it as an intruder height: below it the
/// cone is truncated by the walls; above it the mobility near the walls is lost and mu* falls
/// towards 0.24 (section 4, fig. 13). 78 mm for W = 100 mm, L = 10 mm, beta = 60 deg [m].
inline double h1_height(const PullParams& p, double beta_deg = kPaperConeAngle) {
  return 0.5 * (p.cell_width - p.intruder_length) * std::tan(beta_deg * std::numbers::pi / 180.0);
}
/// Number of disks: 002's count per cell area, 1600 disks for a 100 mm x 150 mm bed (section 2.4).
inline std::size_t disk_count(const PullParams& p) {
  return static_cast<std::size_t>(std::lround(1600.0 * p.cell_width * p.bed_height / (0.100 * 0.150)));
}
/// Top of the region that is closed by walls and holds the release region [m].
inline double cell_top(const PullParams& p) {
  const double release = p.fill_release_height > 0.0 ? p.fill_release_height : 3.0 * p.bed_height;
  return p.fill_rate > 0.0 ? release + 20.0 * p.mean_diameter : 5.0 * p.bed_height;
}

/// Estimated steps of a run, before it runs.
struct CostEstimate {
  std::size_t particles = 0;
  double fill_time = 0.0;        ///< simulated time of filling and settling [s]
  double pull_travel = 0.0;      ///< [m]
  double fill_dt = 0.0, pull_dt = 0.0;  ///< [s]
  double fill_steps = 0.0, pull_steps = 0.0;
  /// Wall time at `ns` nanoseconds per particle-step [s] (without the fill when `cached`).
  double seconds(double ns, bool cached = false) const {
    return ns * 1e-9 * static_cast<double>(particles) * ((cached ? 0.0 : fill_steps) + pull_steps);
  }
};

/// Steps of filling (n / rate + the fall of the last disk + 0.2 s of landing + ~0.2 s of settling:
/// 7.1 s simulated for 1600 disks at 250 /s, measured) and of the pull (from the rest height to the
/// top of the bed, about 0.96 H, plus d).
inline CostEstimate estimate_cost(const PullParams& p) {
  CostEstimate c;
  c.particles = disk_count(p);
  const double fall = std::sqrt(2.0 * cell_top(p) / kGravity) + 0.2;
  c.fill_time = (p.fill_rate > 0.0 ? static_cast<double>(c.particles) / p.fill_rate : 0.0) + fall + 0.2;
  c.pull_travel = 0.96 * p.bed_height + p.mean_diameter - (0.5 * r_min(p) + p.intruder_radius);
  c.fill_dt = engine_dt(p);
  c.pull_dt = pull_dt(p);
  c.fill_steps = c.fill_time / c.fill_dt;
  c.pull_steps = c.pull_travel / (p.pull_velocity * c.pull_dt);
  return c;
}

/// Rolling parameters of the EPSD law matching 002's rolling law at the mean size (file comment).
struct RollingConversion {
  double mu_r;    ///< [-]
  double factor;  ///< c [-]
};
inline RollingConversion rolling_conversion(double mu) {
  const double mu_r = 4.0 * mu * 1e-2;
  return {mu_r, 1e-3 * 16.0 / (mu_r * mu_r)};
}

/// Packing of the settled bed, measured exactly (analysis/packing.hpp) in bins of the frame.
struct PackingReport {
  double surface = 0.0;        ///< mean surface height: mean over columns ~4 d wide of the
                               ///< centre height of their top disks (analysis::bed_height), plus
                               ///< the mean radius [m]
  double interior = 0.0;       ///< packing fraction of x in [2d, W - 2d], y in [2d, surface - 3d] [-]
  double interior_min = 0.0;   ///< lowest of the interior's horizontal slabs (~3 d high) [-]
  double interior_max = 0.0;   ///< highest of them [-]
  std::size_t slabs = 0;       ///< number of those slabs
  double whole = 0.0;          ///< packing fraction of the whole bed [0, W] x [0, surface] [-]
};

/// The assembled scene.
struct PullScene {
  PullParams params;
  std::unique_ptr<Sim> sim;
  std::uint32_t intruder_body = 0;
  std::vector<std::uint32_t> cell_walls;  ///< floor and sides
  std::uint32_t intruder_wall = 0;
  double intruder_y0 = 0.0;   ///< initial height of the intruder axis [m]
  double bed_height = 0.0;    ///< surface height after settling: mean top of the 5 highest disks [m]
  std::size_t particles = 0;
  bool settled = false;
  double fill_sim_time = 0.0; ///< simulated time of the filling and settling [s]
  double bed_mass = 0.0;      ///< mass of all disks [kg]
  std::uint64_t fill_steps = 0;  ///< steps of the filling and settling
  double fill_wall_seconds = 0.0;  ///< wall time of the filling and settling (0 when read from a cache) [s]
  bool from_cache = false;    ///< the bed was read from a checkpoint
  PackingReport packing;      ///< measured after settling
  /// Height of the intruder axis [m].
  double intruder_height() const { return sim->body(intruder_body).pose.translation().y(); }
  /// Weight of the bed above the intruder's length, M g L / W: the scale of the drag [N].
  double column_weight() const { return bed_mass * kGravity * params.intruder_length / params.cell_width; }
};

/// Packing fractions and mean surface of the bed in `sim` (see PackingReport).
inline PackingReport measure_packing(const Sim& sim, const PullParams& p) {
  using IVec = Dim2::IVec;
  const auto frame = sim.frame();
  const double d = p.mean_diameter, w = p.cell_width;
  PackingReport r;
  double top = 0.0, rbar = 0.0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    top = std::max(top, frame.x[i].y() + frame.radius[i]);
    rbar += frame.radius[i];
  }
  rbar /= std::max<double>(1.0, static_cast<double>(frame.size()));
  const int ncol = std::max(1, static_cast<int>(std::floor(w / (4.0 * d))));
  const analysis::BinGrid<Dim2> columns(Vec(0.0, 0.0), Vec(w, top + d), IVec(ncol, 1));
  double sum = 0.0;
  int used = 0;
  for (const auto& c : analysis::bed_height(frame, columns, 1))
    if (std::isfinite(c.height)) { sum += c.height; ++used; }
  r.surface = (used > 0 ? sum / used : 0.0) + rbar;
  const double y0 = 2.0 * d, y1 = r.surface - 3.0 * d;
  if (y1 > y0 + d && w > 5.0 * d) {
    const int nslab = std::max(1, static_cast<int>(std::lround((y1 - y0) / (3.0 * d))));
    const analysis::BinGrid<Dim2> slabs(Vec(2.0 * d, y0), Vec(w - 2.0 * d, y1), IVec(1, nslab));
    const auto phi = analysis::packing_fraction(frame, slabs);
    r.slabs = phi.size();
    r.interior_min = *std::min_element(phi.begin(), phi.end());
    r.interior_max = *std::max_element(phi.begin(), phi.end());
    for (double x : phi) r.interior += x / static_cast<double>(phi.size());  // equal slabs
  }
  const analysis::BinGrid<Dim2> all(Vec(0.0, 0.0), Vec(w, r.surface), IVec(1, 1));
  r.whole = analysis::packing_fraction(frame, all)[0];
  return r;
}

namespace detail {
/// Cell walls, intruder and disk material in a new simulation with friction mu (mu_r in
/// proportion); the region y < top is closed by walls, the domain reaches `domain_top`.
inline std::unique_ptr<Sim> make_cell(const PullParams& p, double mu, double top, double domain_top, PullScene& s,
                                      std::uint32_t& mat) {
  const double rmin = r_min(p);
  const double w = p.cell_width;
  SimulationConfig<Dim2> cfg;
  cfg.domain.lo = Vec(-0.01, -0.01);
  cfg.domain.hi = Vec(w + 0.01, domain_top + 0.01);
  cfg.gravity = Vec(0.0, -kGravity);
  cfg.thickness = p.thickness;
  // The filling runs at the engine's largest step (engine_dt); pull() sets the pull's step.
  cfg.dt = engine_dt(p);
  auto sim = std::make_unique<Sim>(cfg);

  Material glass;
  glass.name = "glass";
  glass.youngs_modulus = p.youngs_modulus;
  glass.poisson_ratio = 0.25;
  glass.density = p.density;
  glass.restitution = p.restitution;
  glass.friction = mu;
  glass.reference_length = p.mean_diameter;
  glass.tangential_stiffness_ratio = 0.5;
  // Rolling law from the scene's mu (rolling_conversion), scaled by mu / p.friction while the
  // friction is reduced, so that a frictionless fill also has no rolling resistance.
  const auto roll = rolling_conversion(p.friction);
  glass.rolling_friction = p.friction > 0.0 ? roll.mu_r * mu / p.friction : 0.0;
  glass.rolling_stiffness_factor = roll.factor;
  mat = sim->add_material(glass);
  const auto wall_mat = sim->add_wall_material(glass);

  const double rw = p.wall_radius;
  // Floor surface at y = 0, side surfaces at x = 0 and x = W.
  s.cell_walls.clear();
  s.cell_walls.push_back(sim->add_wall(geometry::SpheroLineShape(Vec(-rw, -rw), Vec(w + rw, -rw), rw), wall_mat));
  s.cell_walls.push_back(sim->add_wall(geometry::SpheroLineShape(Vec(-rw, -rw), Vec(-rw, top), rw), wall_mat));
  s.cell_walls.push_back(sim->add_wall(geometry::SpheroLineShape(Vec(w + rw, -rw), Vec(w + rw, top), rw), wall_mat));

  // Intruder: horizontal segment of length L centred in the cell, its lower surface d_min / 2
  // above the floor. Body frame: the segment's mid-point.
  s.intruder_y0 = 0.5 * rmin + p.intruder_radius;
  Body<Dim2> b;
  b.name = "intruder";
  b.pose = geometry::Pose<Dim2>::translation(Vec(0.5 * w, s.intruder_y0));
  s.intruder_body = sim->add_body(b);
  const double half = 0.5 * p.intruder_length - p.intruder_radius;  // caps included in L
  s.intruder_wall = sim->add_wall(geometry::SpheroLineShape(Vec(-half, 0.0), Vec(half, 0.0), p.intruder_radius),
                                  wall_mat, s.intruder_body);
  return sim;
}
}  // namespace detail

/// Builds the cell, fills and settles the bed; the intruder is at rest until start of the pull.
/// `on_progress(step, time)` is called during the filling.
inline PullScene build(const PullParams& p,
                       const std::function<void(std::uint64_t, double)>& on_progress = {}) {
  require_positive(p.cell_width, "pull_out::build", "cell_width");
  require(p.cell_width > p.intruder_length + 4.0 * p.mean_diameter, "pull_out::build", "cell_width",
          p.cell_width, "(intruder_length + 4 d, inf) m");
  require_positive(p.bed_height, "pull_out::build", "bed_height");
  require(p.size_ratio >= 1.0, "pull_out::build", "size_ratio", p.size_ratio, "[1, inf)");
  require_positive(p.pull_velocity, "pull_out::build", "pull_velocity");
  require_positive(p.sample_travel, "pull_out::build", "sample_travel");
  require(p.fill_rate >= 0.0, "pull_out::build", "fill_rate", p.fill_rate, "[0, inf) 1/s");
  require(p.fill_source_width >= 0.0, "pull_out::build", "fill_source_width", p.fill_source_width, "[0, inf) m");
  require(p.fill_release_height >= 0.0, "pull_out::build", "fill_release_height", p.fill_release_height, "[0, inf) m");
  require_positive(p.thickness, "pull_out::build", "thickness");
  require_positive(p.youngs_modulus, "pull_out::build", "youngs_modulus");
  require_positive(p.density, "pull_out::build", "density");
  require_positive(p.cg_width, "pull_out::build", "cg_width");
  require_positive(p.cg_spacing, "pull_out::build", "cg_spacing");
  require(p.dt >= 0.0 && std::isfinite(p.dt), "pull_out::build", "dt", p.dt, "[0, inf) s");
  const auto wall_start = std::chrono::steady_clock::now();
  PullScene s;
  s.params = p;
  const double rmin = r_min(p), rmax = p.size_ratio * rmin;
  const double w = p.cell_width;
  const bool stream = p.fill_rate > 0.0;
  // Batch: the insertion region [bed height, 5 x bed height] holds all disks at once. Stream:
  // a release region 20 d high (room for the disks still falling through it) whose bottom is
  // fill_release_height above the floor.
  const double release = p.fill_release_height > 0.0 ? p.fill_release_height : 3.0 * p.bed_height;
  const double slab = 20.0 * p.mean_diameter;
  const double top = cell_top(p);
  const double mu_fill = p.fill_friction >= 0.0 ? p.fill_friction : p.friction;
  const bool restore = mu_fill != p.friction;

  std::uint32_t mat = 0;
  s.sim = detail::make_cell(p, mu_fill, top, top, s, mat);
  Sim* sim = s.sim.get();

  const std::size_t n = disk_count(p);
  auto report = [&] { if (on_progress) on_progress(sim->step_count(), sim->time()); };
  if (!stream) {
    geometry::Aabb<Dim2> region{Vec(rmax, 1.0 * p.bed_height), Vec(w - rmax, top - rmax)};
    scene::Pour<Sim> pour(*sim, region, scene::UniformSizes(rmin, rmax),
                          scene::StreamSchedule(10.0 * n, n, 0.0, scene::StreamMode::Batched, 0.1), mat, Vec::Zero(), 0,
                          p.seed);
    pour.update();
    require(pour.finished(), "pull_out::build", "disks inserted", static_cast<double>(pour.inserted()),
            std::to_string(n) + " (insertion region too small)");
  } else {
    // The hopper's outlet: disks appear at rest, fill_rate per second, at random positions in a
    // region of width fill_source_width centred on the cell; they fall about release - bed height.
    const double ws = p.fill_source_width > 0.0 ? std::min(p.fill_source_width, w) : w;
    const double x0 = std::max(0.0, 0.5 * (w - ws)), x1 = std::min(w, 0.5 * (w + ws));
    require(x1 - x0 > 2.0 * rmax, "pull_out::build", "fill_source_width", ws, "(d_max, inf) m");
    geometry::Aabb<Dim2> region{Vec(x0, release), Vec(x1, release + slab)};
    scene::Pour<Sim> pour(*sim, region, scene::UniformSizes(rmin, rmax),
                          scene::StreamSchedule(p.fill_rate, n, 0.0, scene::StreamMode::Continuous), mat, Vec::Zero(), 0,
                          p.seed);
    const auto per_update = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(2e-3 / sim->dt())));
    std::uint64_t k = 0;
    while (!pour.finished()) {
      pour.update();
      sim->run(per_update);
      if (++k % 50 == 0) report();
    }
  }
  s.particles = n;

  // Fall (and, for a stream, the last disks' fall), then settle with periodic velocity zeroing.
  const double fall = std::sqrt(2.0 * top / kGravity) + 0.2;  // [s]
  const auto steps = static_cast<std::uint64_t>(fall / sim->dt());
  for (std::uint64_t k = 0; k < steps; k += 1000) {
    sim->run(1000);
    report();
  }
  scene::SettleOptions so;
  so.max_time = p.fill_time;
  so.zero_velocity_interval = 0.05;
  // Quiet below 6.2e-7 m g d per disk (m: the mean disk mass): 1e-12 J for disks 3 mm thick (the
  // former fixed threshold). In proportion to the mass so that a scene with E and t scaled
  // together settles at the same instant and moves the same way (file comment).
  const double mean_r2 = (rmin * rmin + rmin * rmax + rmax * rmax) / 3.0;  // radii uniform in [rmin, rmax]
  so.kinetic_energy_per_particle = 6.2e-7 * p.density * std::numbers::pi * mean_r2 * p.thickness * kGravity *
                                   p.mean_diameter;
  so.check_interval = 0.01;
  so.on_check = [&](double, double) { report(); };
  if (restore) {
    // Let the reduced-friction bed come to rest, then rebuild the scene with mu and the same
    // disks (no contact history to carry over: the springs start from zero, as on first
    // contact), and settle again under mu.
    scene::settle(*sim, so);
    const double t_fill = sim->time();
    const auto& q = sim->particles();
    std::vector<Vec> xs(q.x.begin(), q.x.begin() + q.owned());
    std::vector<double> rs(q.radius.begin(), q.radius.begin() + q.owned());
    s.fill_steps = sim->step_count();
    s.sim = detail::make_cell(p, p.friction, top, top, s, mat);
    sim = s.sim.get();
    for (std::size_t i = 0; i < xs.size(); ++i) sim->add_particle(xs[i], rs[i], mat);
    s.fill_sim_time = t_fill;
  }
  s.settled = scene::settle(*sim, so).settled;
  s.fill_sim_time += sim->time();
  s.fill_steps += sim->step_count();
  s.bed_height = scene::surface_height(*sim, 1, 5);
  s.packing = measure_packing(*sim, p);
  for (std::size_t i = 0; i < sim->particles().owned(); ++i) s.bed_mass += sim->particles().mass[i];
  s.fill_wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return s;
}

namespace detail {
inline std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}
inline std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }
inline double from_bits(std::uint64_t v) { return std::bit_cast<double>(v); }
}  // namespace detail

/// Key of everything that shapes the settled bed (not V, the pull's step, the sampling or the
/// coarse-graining): two parameter sets with the same key build the same bed.
inline std::uint64_t bed_key(const PullParams& p) {
  char buf[1024];
  std::snprintf(buf, sizeof(buf),
                "pull_out bed v1;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;"
                "%.17g;%.17g;%.17g;%llu",
                p.cell_width, p.bed_height, p.mean_diameter, p.size_ratio, p.density, p.thickness, p.youngs_modulus,
                p.friction, p.restitution, p.intruder_length, p.intruder_radius, p.wall_radius, p.fill_time,
                p.fill_rate, p.fill_source_width, p.fill_release_height, p.fill_friction,
                static_cast<unsigned long long>(p.seed));
  return detail::fnv1a(buf);
}

/// Writes the settled bed of `s` (before its pull) to a checkpoint with what build() measured.
inline void save_bed(PullScene& s, const std::filesystem::path& file) {
  std::filesystem::create_directories(file.parent_path());
  const PackingReport& k = s.packing;
  io::write_checkpoint(*s.sim, file.string(),
                       {bed_key(s.params), detail::bits(s.bed_height), static_cast<std::uint64_t>(s.particles),
                        s.settled ? 1u : 0u, detail::bits(s.fill_sim_time), detail::bits(s.bed_mass), s.fill_steps,
                        detail::bits(k.surface), detail::bits(k.interior), detail::bits(k.interior_min),
                        detail::bits(k.interior_max), static_cast<std::uint64_t>(k.slabs), detail::bits(k.whole)});
}

/// The bed written by save_bed for the same bed_key(p), or nothing (no file, another key, or a
/// file this build cannot read: IoError is caught, the caller builds the bed again).
inline std::optional<PullScene> load_bed(const PullParams& p, const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return std::nullopt;
  PullScene s;
  s.params = p;
  std::uint32_t mat = 0;
  const double top = cell_top(p);
  s.sim = detail::make_cell(p, p.friction, top, top, s, mat);
  std::vector<std::uint64_t> u;
  try {
    u = io::read_checkpoint(*s.sim, file.string());
  } catch (const IoError&) {
    return std::nullopt;
  }
  if (u.size() != 13 || u[0] != bed_key(p)) return std::nullopt;
  s.bed_height = detail::from_bits(u[1]);
  s.particles = static_cast<std::size_t>(u[2]);
  s.settled = u[3] != 0;
  s.fill_sim_time = detail::from_bits(u[4]);
  s.bed_mass = detail::from_bits(u[5]);
  s.fill_steps = u[6];
  s.packing.surface = detail::from_bits(u[7]);
  s.packing.interior = detail::from_bits(u[8]);
  s.packing.interior_min = detail::from_bits(u[9]);
  s.packing.interior_max = detail::from_bits(u[10]);
  s.packing.slabs = static_cast<std::size_t>(u[11]);
  s.packing.whole = detail::from_bits(u[12]);
  s.from_cache = true;
  return s;
}

/// One drag sample.
struct DragSample {
  double time;                 ///< since the start of the pull [s]
  double height;               ///< intruder axis height above the floor [m]
  double drag;                 ///< -F_y of the disks on the intruder, averaged over the sample [N]
  double mu_star_bulk;         ///< mean mu* of particle-particle contacts at the sample's end [-]
  double mu_star_wall;         ///< mean mu* of particle-cell wall contacts [-]
  double sliding_bulk;         ///< fraction of the bulk contacts at the Coulomb threshold [-]
  std::size_t contacts_intruder;  ///< disks touching the intruder at the sample's end
  // Flow zones of the coarse-grained field at the sample's end, above the intruder's axis
  // (NaN when the fields are off): see FieldProbe.
  double dragged_area;         ///< v* > 0.75 [m^2]
  double cone_area;            ///< 0.25 <= v* <= 0.75 [m^2]
  double wall_mobility;        ///< fraction of the wall bands' nodes with v* >= 0.25 [-]
  double cone_angle;           ///< mean inclination of the mobile zone's edges [deg] (NaN: none)
  double cone_left, cone_right;  ///< each side's [deg]
};

/// Coarse-grained velocity map at one intruder height.
struct VelocityMap {
  double target = 0.0;   ///< requested intruder height [m]
  double height = 0.0;   ///< intruder height of the snapshot: the loading peak nearest the target [m]
  double drag = 0.0;     ///< drag of that sample [N]
  analysis::CgFields<Dim2> fields;
  std::vector<double> speed;  ///< v* = |V| / V_pull per node [-]
  analysis::ConeFit cone;
};

/// Vertical velocity / V along the cell's vertical mid-line (002 fig. 9) at one intruder height.
struct CentreLine {
  double height = 0.0;        ///< [m]
  std::vector<double> y;      ///< node heights [m]
  std::vector<double> vy;     ///< V_y / V_pull [-]
};

/// What pull() records besides the drag.
struct PullOptions {
  double final_height = 0.0;          ///< intruder axis height at which the pull stops [m]; 0: top of the bed + d
  std::vector<double> map_heights;    ///< intruder heights of the velocity maps [m]
  bool fields = true;                 ///< coarse-grain every sample (flow zones and cone angle)
  double centre_line_travel = 0.0;    ///< record the mid-line profile every this much travel [m]; 0: never
};

/// Result of the pull.
struct PullResult {
  std::vector<DragSample> samples;
  std::vector<VelocityMap> maps;
  std::vector<CentreLine> centre_line;
  double dt = 0.0;                 ///< step of the pull [s]
  std::uint64_t steps = 0;         ///< steps of the pull
  double wall_seconds = 0.0;       ///< wall time of the pull, analysis included [s]
  double analysis_seconds = 0.0;   ///< of which coarse-graining and zones [s]
};

/// The flow-zone measurement of one frame (002 section 3.2; analysis/flow_zones.hpp): the
/// velocity coarse-grained with 002's kernel (Gaussian, width w = cg_width d, cutoff 4 w, section
/// 2.5) on a grid of spacing about cg_spacing d over the cell (spacing()), divided by V. Zones and wall bands are
/// counted above the intruder's axis; the wall bands are 2 d wide (the disks touching a side
/// wall and their neighbours); the cone's edges are looked for from w above the axis (closer, the
/// kernel mixes in the intruder's own level) up to w below the mean surface, and only inside
/// [w, W - w], where the kernel does not reach across a side wall.
class FieldProbe {
 public:
  FieldProbe(const PullParams& p, double surface)
      : p_(p), surface_(surface),
        grid_(Vec(0.0, 0.0), Vec(p.cell_width, surface + p.mean_diameter), spacing(p)),
        kernel_(p.cg_width * p.mean_diameter, 4.0 * p.cg_width * p.mean_diameter) {
    opt_.contact_stress = false;
  }

  /// Node spacing: cg_spacing d adjusted so that an even number of cells spans the width, which
  /// puts nodes on both side walls and on the intruder's axis (both sides of the cone alike).
  static double spacing(const PullParams& p) {
    const double cells = 2.0 * std::max(1.0, std::round(p.cell_width / (2.0 * p.cg_spacing * p.mean_diameter)));
    return p.cell_width / cells;
  }

  const analysis::RegularGrid<Dim2>& grid() const { return grid_; }
  double width() const { return kernel_.width(); }

  struct Result {
    analysis::CgFields<Dim2> fields;
    std::vector<double> speed;
    analysis::FlowZoneAreas zones;
    double wall_mobility = std::numeric_limits<double>::quiet_NaN();
    analysis::ConeFit cone;
  };

  Result measure(const analysis::Frame<Dim2>& frame, double intruder_height) const {
    Result r;
    r.fields = analysis::coarse_grain_direct(frame, grid_, kernel_, opt_);
    r.speed = analysis::normalised_speed(r.fields.velocity, p_.pull_velocity);
    r.zones = analysis::flow_zone_areas(grid_, r.speed, r.fields.packing_fraction, intruder_height);
    const double band = 2.0 * p_.mean_diameter;
    r.wall_mobility = analysis::wall_mobility(grid_, r.speed, r.fields.packing_fraction, intruder_height, band,
                                              p_.cell_width - band);
    analysis::ConeWindow w;
    w.x_centre = 0.5 * p_.cell_width;
    w.y_from = intruder_height + width();
    w.y_to = surface_ - width();
    w.x_min = width();
    w.x_max = p_.cell_width - width();
    if (w.y_to > w.y_from) r.cone = analysis::cone_edges(grid_, r.speed, r.fields.packing_fraction, w);
    return r;
  }

 private:
  PullParams p_;
  double surface_;
  analysis::RegularGrid<Dim2> grid_;
  analysis::GaussianCgKernel<Dim2> kernel_;
  analysis::CgOptions opt_;
};

/// Pulls the intruder from its rest height at V (see PullOptions) with the step pull_dt(p).
/// `on_progress(t)` is called after every sample with the time since the start of the pull.
inline PullResult pull(PullScene& s, const PullOptions& o = {}, const std::function<void(double)>& on_progress = {}) {
  using Clock = std::chrono::steady_clock;
  const auto wall_start = Clock::now();
  Sim& sim = *s.sim;
  const PullParams& p = s.params;
  PullResult r;
  r.dt = pull_dt(p);
  sim.set_dt(r.dt);
  const double t0 = sim.time();
  const std::uint64_t step0 = sim.step_count();
  const double v = p.pull_velocity;
  const double d = p.mean_diameter;
  const double final_height = o.final_height > 0.0 ? o.final_height : s.bed_height + d;
  sim.body(s.intruder_body).velocity = [t0, v](double t) { return t >= t0 ? Vec(0.0, v) : Vec(Vec::Zero()); };
  const double dts = p.sample_travel / v;  // sample period [s]
  const auto per_sample = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(dts / sim.dt())));
  const std::vector<double> edges{0.0, 0.5, 1.0 + 1e-6};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::optional<FieldProbe> probe;
  if (o.fields) probe.emplace(p, s.packing.surface);

  // Velocity maps: for each requested height h_m, the sample of largest drag among those within
  // d/2 of h_m (a loading peak, file comment).
  std::vector<double> pending = o.map_heights;
  std::sort(pending.begin(), pending.end());
  std::size_t k_map = 0;
  std::optional<VelocityMap> best;
  double next_line = 0.0;
  double analysis_seconds = 0.0;

  while (s.intruder_height() < final_height) {
    double sum = 0.0;
    for (std::uint64_t k = 0; k < per_sample; ++k) {
      if (k + 1 == per_sample) sim.request_contacts();
      sim.step();
      sum += sim.body(s.intruder_body).force.y();
    }
    const auto frame = sim.frame();
    const auto mob = analysis::friction_mobilisation(frame, edges, s.cell_walls, 1e-9);
    std::size_t n_intr = 0;
    for (const auto& c : frame.contacts)
      if (c.j == analysis::ContactRecord<Dim2>::kWall && c.wall == s.intruder_wall) ++n_intr;
    const double h = s.intruder_height();
    DragSample x{sim.time() - t0,
                 h,
                 -sum / static_cast<double>(per_sample),
                 mob.bulk.mean,
                 mob.wall.mean,
                 mob.bulk.mu_star.empty() ? nan
                                          : static_cast<double>(mob.bulk.sliding) / static_cast<double>(mob.bulk.mu_star.size()),
                 n_intr,
                 nan, nan, nan, nan, nan, nan};
    if (probe) {
      const auto a0 = Clock::now();
      auto m = probe->measure(frame, h);
      x.dragged_area = m.zones.dragged;
      x.cone_area = m.zones.cone;
      x.wall_mobility = m.wall_mobility;
      x.cone_angle = m.cone.angle;
      x.cone_left = m.cone.left.angle;
      x.cone_right = m.cone.right.angle;
      if (o.centre_line_travel > 0.0 && h - s.intruder_y0 >= next_line) {
        next_line += o.centre_line_travel;
        CentreLine line;
        line.height = h;
        const auto& g = probe->grid();
        const int ic = static_cast<int>(std::lround((0.5 * p.cell_width - g.lo().x()) / g.spacing().x()));
        for (int j = 0; j < g.count().y(); ++j) {
          const std::size_t idx = g.index(Dim2::IVec(ic, j));
          line.y.push_back(g.node(idx).y());
          line.vy.push_back(m.fields.velocity[idx].y() / v);
        }
        r.centre_line.push_back(std::move(line));
      }
      // Maps: close the windows the intruder has passed, then offer this sample to the open one.
      while (k_map < pending.size() && h > pending[k_map] + 0.5 * d) {
        if (best) r.maps.push_back(std::move(*best));
        best.reset();
        ++k_map;
      }
      if (k_map < pending.size() && h >= pending[k_map] - 0.5 * d && (!best || x.drag > best->drag)) {
        best = VelocityMap{pending[k_map], h, x.drag, std::move(m.fields), std::move(m.speed), m.cone};
      }
      analysis_seconds += std::chrono::duration<double>(Clock::now() - a0).count();
    }
    r.samples.push_back(x);
    if (on_progress) on_progress(sim.time() - t0);
  }
  if (best) r.maps.push_back(std::move(*best));
  r.steps = sim.step_count() - step0;
  r.analysis_seconds = analysis_seconds;
  r.wall_seconds = std::chrono::duration<double>(Clock::now() - wall_start).count();
  return r;
}

}  // namespace granule::examples::pull_out
