#pragma once
// A thin intruder pulled up out of a 2D bed of disks at constant speed (Mandato, Cuq, Ruiz,
// Dirrenberger & Fakih et al., "intruder pull-out ... coarse-graining", paper 002 in
// shared/papers; sections 2.3-2.4, 3 and 4).
//
// Scene logic shared by main.cpp and tests/examples/test_intruder_pull_out_2d.cpp:
//  * build: a cell of width W closed by sphero-line walls (floor and two sides, 002 section 2.3
//    "Walls and intruder"), the intruder as a horizontal sphero-line of length L on its own Body,
//    lying just above the floor (gap < d_min, so no disk gets under it);
//  * fill: instead of 002's hopper (hours of simulated filling), all disks are inserted at once
//    at random, non-overlapping positions in a tall region above the cell (scene::Pour, one batch
//    of all disks at t = 0), fall under gravity and are settled (scene::settle with periodic velocity
//    zeroing); the number of disks is chosen for the requested bed height at packing fraction
//    phi = 0.82 (002 section 2.4), and the bed height reported is the measured one;
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
  double fill_time = 1.0;          ///< max settling time after the insertion [s]
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

/// The assembled scene.
struct PullScene {
  PullParams params;
  std::unique_ptr<Sim> sim;
  std::uint32_t intruder_body = 0;
  std::vector<std::uint32_t> cell_walls;  ///< floor and sides
  std::uint32_t intruder_wall = 0;
  double intruder_y0 = 0.0;   ///< initial height of the intruder axis [m]
  double bed_height = 0.0;    ///< measured surface height after settling [m]
  std::size_t particles = 0;
  bool settled = false;
  /// Height of the intruder axis at time t of the pull [m].
  double intruder_height() const { return sim->body(intruder_body).pose.translation().y(); }
};

inline double r_min(const PullParams& p) { return p.mean_diameter / (1.0 + p.size_ratio); }

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
  PullScene s;
  s.params = p;
  const double rmin = r_min(p), rmax = p.size_ratio * rmin;
  const double w = p.cell_width;
  const double top = 5.0 * p.bed_height;  // insertion region reaches this high [m]

  SimulationConfig<Dim2> cfg;
  cfg.domain.lo = Vec(-0.01, -0.01);
  cfg.domain.hi = Vec(w + 0.01, top + 0.01);
  cfg.gravity = Vec(0.0, -9.81);
  cfg.thickness = p.mean_diameter;
  // dt from the linear collision time of the lightest pair (set below once materials exist).
  const double m_min = p.density * std::numbers::pi * rmin * rmin * cfg.thickness;  // [kg]
  const double kn = p.youngs_modulus * p.mean_diameter;                            // [N/m]
  // Linear collision time of two lightest disks (m* = m/2), undamped: pi sqrt(m*/k_n).
  cfg.dt = 0.2 * std::numbers::pi * std::sqrt(0.5 * m_min / kn);
  s.sim = std::make_unique<Sim>(cfg);
  Sim& sim = *s.sim;

  Material glass;
  glass.name = "glass";
  glass.youngs_modulus = p.youngs_modulus;
  glass.poisson_ratio = 0.25;
  glass.density = p.density;
  glass.restitution = p.restitution;
  glass.friction = p.friction;
  glass.reference_length = p.mean_diameter;
  glass.tangential_stiffness_ratio = 0.5;
  const auto roll = rolling_conversion(p.friction);
  glass.rolling_friction = roll.mu_r;
  glass.rolling_stiffness_factor = roll.factor;
  const auto mat = sim.add_material(glass);
  const auto wall_mat = sim.add_wall_material(glass);

  const double rw = p.wall_radius;
  // Floor surface at y = 0, side surfaces at x = 0 and x = W.
  s.cell_walls.push_back(sim.add_wall(geometry::SpheroLineShape(Vec(-rw, -rw), Vec(w + rw, -rw), rw), wall_mat));
  s.cell_walls.push_back(sim.add_wall(geometry::SpheroLineShape(Vec(-rw, -rw), Vec(-rw, top), rw), wall_mat));
  s.cell_walls.push_back(sim.add_wall(geometry::SpheroLineShape(Vec(w + rw, -rw), Vec(w + rw, top), rw), wall_mat));

  // Intruder: horizontal segment of length L centred in the cell, its lower surface d_min / 2
  // above the floor. Body frame: the segment's mid-point.
  s.intruder_y0 = 0.5 * rmin + p.intruder_radius;
  Body<Dim2> b;
  b.name = "intruder";
  b.pose = geometry::Pose<Dim2>::translation(Vec(0.5 * w, s.intruder_y0));
  s.intruder_body = sim.add_body(b);
  const double half = 0.5 * p.intruder_length - p.intruder_radius;  // caps included in L
  s.intruder_wall = sim.add_wall(geometry::SpheroLineShape(Vec(-half, 0.0), Vec(half, 0.0), p.intruder_radius),
                                 wall_mat, s.intruder_body);

  // Number of disks for the target height at phi = 0.82: <r^2> of U[a, b] is (a^2 + ab + b^2)/3.
  const double mean_r2 = (rmin * rmin + rmin * rmax + rmax * rmax) / 3.0;
  const auto n = static_cast<std::size_t>(std::lround(0.82 * w * p.bed_height / (std::numbers::pi * mean_r2)));
  geometry::Aabb<Dim2> region{Vec(rmax, 1.0 * p.bed_height), Vec(w - rmax, top - rmax)};
  scene::Pour<Sim> pour(sim, region, scene::UniformSizes(rmin, rmax), scene::StreamSchedule(10.0 * n, n, 0.0, scene::StreamMode::Batched, 0.1), mat,
                        Vec::Zero(), 0, p.seed);
  pour.update();
  require(pour.finished(), "pull_out::build", "disks inserted", static_cast<double>(pour.inserted()),
          std::to_string(n) + " (insertion region too small)");
  s.particles = n;

  // Fall, then settle with periodic velocity zeroing.
  const double fall = std::sqrt(2.0 * top / 9.81) + 0.2;  // [s]
  const auto steps = static_cast<std::uint64_t>(fall / sim.dt());
  for (std::uint64_t k = 0; k < steps; k += 1000) {
    sim.run(1000);
    if (on_progress) on_progress(sim.step_count(), sim.time());
  }
  scene::SettleOptions so;
  so.max_time = p.fill_time;
  so.zero_velocity_interval = 0.05;
  so.kinetic_energy_per_particle = 1e-12;
  so.check_interval = 0.01;
  if (on_progress) so.on_check = [&](double, double) { on_progress(sim.step_count(), sim.time()); };
  s.settled = scene::settle(sim, so).settled;
  s.bed_height = scene::surface_height(sim, 1, 5);
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
