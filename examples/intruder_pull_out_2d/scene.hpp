#pragma once
// A thin intruder pulled up out of a 2D bed of disks at constant speed (Mandato, Cuq, Ruiz,
// Dirrenberger & Fakih et al., "intruder pull-out ... coarse-graining", paper 002 in
// shared/papers; sections 2.3-2.4, 3 and 4).
//
// Scene logic shared by main.cpp and tests/examples/test_intruder_pull_out_2d.cpp:
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
//    settling (measure_packing: analysis/packing.hpp, exact disk-bin areas);
//  * pull: the intruder moves up at V; every sample the vertical force of the disks on it,
//    averaged over the sample's steps, is recorded as the drag F = -F_y (positive when the bed
//    resists the rise), with the mean friction mobilisation mu* = |ft|/(mu fn) of the bulk and
//    of the cell walls (002 section 4, force_network.hpp), and at chosen heights the
//    coarse-grained velocity field divided by V (002 eq. 7-9, coarse_graining.hpp); the power
//    spectrum (spectrum.hpp, Hann window) of the drag minus its least-squares line.
// Contact law (002 section 2.3): linear normal spring k_n = E d (Material::reference_length =
// mean diameter), restitution e, incremental Coulomb friction with k_t = k_n / 2, and a rolling
// resistance standing in for 002's law |M| <= mu d 1e-2 F_n, k_r = d^2 k_n 1e-3. granule's EPSD
// law has |M| <= mu_r R* F_n and k_r = c k_n mu_r^2 R*^2; for two disks of the mean diameter
// R* = d/4, which gives mu_r = 4 mu 1e-2 and c = 1e-3 * 16 / (4 mu 1e-2)^2 (exact for equal
// mean-size pairs only: both EPSD quantities scale with R* of the actual pair).
// Coordinates: x across the cell [0, W], y up; the floor surface is y = 0.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <granule/analysis/coarse_graining.hpp>
#include <granule/analysis/force_network.hpp>
#include <granule/analysis/packing.hpp>
#include <granule/analysis/spectrum.hpp>
#include <granule/boundaries/geometry/sphero_line.hpp>
#include <granule/granule.hpp>
#include <granule/scene/pour.hpp>
#include <granule/scene/settle.hpp>

namespace granule::examples::pull_out {

using Vec = Dim2::Vec;
using Sim = Simulation<Dim2, contact::LinearCoulombRolling, neighbours::VerletList>;

/// Every parameter of the scene (defaults: the quick mode; paper_params() gives 002's values).
struct PullParams {
  double cell_width = 0.040;       ///< W [m]
  double bed_height = 0.050;       ///< target bed height [m]
  double mean_diameter = 3e-3;     ///< d [m]
  double size_ratio = 2.0;         ///< d_max / d_min, radii uniform [-]
  double density = 2500.0;         ///< rho [kg/m^3]
  double youngs_modulus = 2e7;     ///< E, k_n = E d [Pa]
  double friction = 0.5;           ///< mu [-]
  double restitution = 0.9;        ///< e [-]
  double intruder_length = 0.010;  ///< L [m]
  double intruder_radius = 1e-3;   ///< cap radius of the intruder sphero-line (half thickness) [m]
  double wall_radius = 1e-3;       ///< cap radius of the cell walls [m]
  double pull_velocity = 0.02;     ///< V [m/s]
  double sample_travel = 2e-4;     ///< intruder travel between two drag samples [m]
  double fill_time = 1.0;          ///< max settling time after the filling [s]
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

/// 002's values: 100 mm cell, 150 mm bed, E = 64 GPa, V = 1.2 mm/s.
inline PullParams paper_params() {
  PullParams p;
  p.cell_width = 0.100;
  p.bed_height = 0.150;
  p.youngs_modulus = 64e9;
  p.pull_velocity = 1.2e-3;
  p.sample_travel = 1e-4;
  p.fill_rate = 250.0;  // the quick mode's rate per cell width, i.e. the same surface rise speed
  return p;
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
  PackingReport packing;      ///< measured after settling
  /// Height of the intruder axis at time t of the pull [m].
  double intruder_height() const { return sim->body(intruder_body).pose.translation().y(); }
};

inline double r_min(const PullParams& p) { return p.mean_diameter / (1.0 + p.size_ratio); }

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
  cfg.gravity = Vec(0.0, -9.81);
  cfg.thickness = p.mean_diameter;
  const double m_min = p.density * std::numbers::pi * rmin * rmin * cfg.thickness;  // [kg]
  const double kn = p.youngs_modulus * p.mean_diameter;                            // [N/m]
  // The largest step the engine accepts: 0.2 x the linear critical time of the two lightest
  // disks (m* = m/2). At e = 0.9 it is 3 % below 0.2 x the undamped pi sqrt(m*/k_n): the dashpot
  // lowers the stability limit (linear_critical_time).
  cfg.dt = 0.2 * linear_critical_time(kn, 0.5 * m_min, p.restitution);
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
  const double top = stream ? release + slab : 5.0 * p.bed_height;
  const double mu_fill = p.fill_friction >= 0.0 ? p.fill_friction : p.friction;
  const bool restore = mu_fill != p.friction;

  std::uint32_t mat = 0;
  s.sim = detail::make_cell(p, mu_fill, top, top, s, mat);
  Sim* sim = s.sim.get();

  // Number of disks: 002's count per cell area, 1600 disks for a 100 mm x 150 mm bed (section 2.4).
  const auto n = static_cast<std::size_t>(std::lround(1600.0 * w * p.bed_height / (0.100 * 0.150)));
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
  const double fall = std::sqrt(2.0 * top / 9.81) + 0.2;  // [s]
  const auto steps = static_cast<std::uint64_t>(fall / sim->dt());
  for (std::uint64_t k = 0; k < steps; k += 1000) {
    sim->run(1000);
    report();
  }
  scene::SettleOptions so;
  so.max_time = p.fill_time;
  so.zero_velocity_interval = 0.05;
  so.kinetic_energy_per_particle = 1e-12;
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
    s.sim = detail::make_cell(p, p.friction, top, top, s, mat);
    sim = s.sim.get();
    for (std::size_t i = 0; i < xs.size(); ++i) sim->add_particle(xs[i], rs[i], mat);
    s.fill_sim_time = t_fill;
  }
  s.settled = scene::settle(*sim, so).settled;
  s.fill_sim_time += sim->time();
  s.bed_height = scene::surface_height(*sim, 1, 5);
  s.packing = measure_packing(*sim, p);
  return s;
}

/// One drag sample.
struct DragSample {
  double time;            ///< since the start of the pull [s]
  double height;          ///< intruder axis height above the floor [m]
  double drag;            ///< -F_y of the disks on the intruder, averaged over the sample [N]
  double mu_star_bulk;    ///< mean mu* of particle-particle contacts at the sample's end [-]
  double mu_star_wall;    ///< mean mu* of particle-cell wall contacts [-]
  std::size_t contacts_intruder;  ///< disks touching the intruder at the sample's end
};

/// Coarse-grained velocity map at one intruder height.
struct VelocityMap {
  double height;  ///< [m]
  analysis::CgFields<Dim2> fields;
};

/// Result of the pull.
struct PullResult {
  std::vector<DragSample> samples;
  std::vector<VelocityMap> maps;
  analysis::PowerSpectrum spectrum;  ///< of the linearly detrended drag vs time (f [Hz]; wavelength V / f)
  double mean_drag = 0.0;            ///< [N]
  double std_drag = 0.0;             ///< [N]
};

/// Pulls the intruder from its rest height up to `final_height` (axis) at V; velocity maps at the
/// requested axis heights (kernel width w = d/2, cutoff 4w as in 002 section 2.5, grid step d/2).
inline PullResult pull(PullScene& s, double final_height, const std::vector<double>& map_heights = {},
                       const std::function<void(double)>& on_progress = {}) {
  Sim& sim = *s.sim;
  const PullParams& p = s.params;
  const double t0 = sim.time();
  const double v = p.pull_velocity;
  sim.body(s.intruder_body).velocity = [t0, v](double t) { return t >= t0 ? Vec(0.0, v) : Vec(Vec::Zero()); };
  const double dts = p.sample_travel / v;  // sample period [s]
  const auto per_sample = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(dts / sim.dt())));
  const double sample_dt = per_sample * sim.dt();
  PullResult r;
  std::vector<double> drags;
  std::vector<double> pending = map_heights;
  std::sort(pending.begin(), pending.end());
  const std::vector<double> edges{0.0, 0.5, 1.0 + 1e-6};
  std::size_t k_map = 0;
  while (s.intruder_height() < final_height) {
    double sum = 0.0;
    for (std::uint64_t k = 0; k < per_sample; ++k) {
      if (k + 1 == per_sample) sim.request_contacts();
      sim.step();
      sum += sim.body(s.intruder_body).force.y();
    }
    const auto frame = sim.frame();
    const auto mob = analysis::friction_mobilisation(frame, edges, s.cell_walls);
    std::size_t n_intr = 0;
    for (const auto& c : frame.contacts)
      if (c.j == analysis::ContactRecord<Dim2>::kWall && c.wall == s.intruder_wall) ++n_intr;
    DragSample d{sim.time() - t0, s.intruder_height(), -sum / per_sample, mob.bulk.mean, mob.wall.mean, n_intr};
    r.samples.push_back(d);
    drags.push_back(d.drag);
    while (k_map < pending.size() && d.height >= pending[k_map]) {
      const double h = 0.5 * p.mean_diameter;
      analysis::RegularGrid<Dim2> grid(Vec(0.0, 0.0), Vec(p.cell_width, s.bed_height), h);
      analysis::GaussianCgKernel<Dim2> kernel(0.5 * p.mean_diameter, 2.0 * p.mean_diameter);
      analysis::CgOptions opt;
      opt.contact_stress = false;
      r.maps.push_back({d.height, analysis::coarse_grain_direct(frame, grid, kernel, opt)});
      ++k_map;
    }
    if (on_progress) on_progress(sim.time() - t0);
  }
  if (drags.size() >= 2) {
    const double n = static_cast<double>(drags.size());
    double m = 0.0;
    for (double x : drags) m += x;
    m /= n;
    double var = 0.0;
    for (double x : drags) var += (x - m) * (x - m);
    r.mean_drag = m;
    r.std_drag = std::sqrt(var / n);
    // Spectrum of the fluctuations: the least-squares line through (k, F_k) (the slow relaxation
    // of the drag, 002 section 3.1) is removed first.
    const double k_mean = 0.5 * (n - 1.0);
    double skf = 0.0, skk = 0.0;
    for (std::size_t k = 0; k < drags.size(); ++k) {
      skf += (k - k_mean) * (drags[k] - m);
      skk += (k - k_mean) * (k - k_mean);
    }
    const double slope = skf / skk;
    std::vector<double> fluct(drags.size());
    for (std::size_t k = 0; k < drags.size(); ++k) fluct[k] = drags[k] - m - slope * (k - k_mean);
    r.spectrum = analysis::power_spectrum(fluct, sample_dt, analysis::SpectralWindow::Hann);
  }
  return r;
}

}  // namespace granule::examples::pull_out
