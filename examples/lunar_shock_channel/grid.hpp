#pragma once
// The struck 5 x 5 grid of paper 001 section 2.2 (table 1, fig. 1): a square-packed grid of
// spheres into which an incident particle (the striker) impacts one particle; the peak-force
// time of every later particle of the struck line is fitted against its position -> wave speed
// c_w(v_im).
//
// 001 says only "the same simulation setup as [93]" (Abd-Elhady et al. 2010, validated by the
// experiment [94], Abd-Elhady et al. 2009): an incident particle dropped onto a bed of equal
// particles in a square array, standing on a floor under Earth gravity. Nothing else loads the
// grid, so the static force on the struck column comes from the weights above each contact:
// contact k (counted from the top) carries k m g. That is `GridLoad::Gravity`, the default.
//
// Why a load matters: a Hertz chain with no static force is a "sonic vacuum" (Nesterenko 2001,
// ch. 1) whose only speed scale is the impact's, so c_w ~ (E*/rho)^(2/5) v_im^(1/5) at every v_im
// and there is no acoustic plateau. A static force F per contact gives the long-wave sound speed
//   c(F) = 2R sqrt(k_lin / m),  k_lin = dF/dd = 3/2 k_n d^(1/2),  F = k_n d^(3/2),
//   k_n = 4/3 E* sqrt(R*),      E* = E / (2 (1 - nu^2)),  R* = R / 2,
// which is 001 eq. 7 (Nesterenko 2001 eq. 1.7) written with the contact stiffness.
// `GridLoad::Uniform` squeezes the struck lines between two planes so that every contact along
// them carries the same F0: the grid used to map the plateau against the pre-load.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <granule/analysis/wave_front.hpp>
#include <granule/granule.hpp>

namespace granule::examples::lunar_shock {

/// Earth's and the Moon's surface gravity [m/s^2].
inline constexpr double kEarthGravity = 9.81;
inline constexpr double kLunarGravity = 1.625;

/// Particle species of 001 table 1.
struct GridMaterial {
  std::string name;
  double youngs_modulus = 0.0;  ///< [Pa]
  double poisson_ratio = 0.0;   ///< [-]
  double density = 0.0;         ///< [kg/m^3]
  double friction = 0.0;        ///< mu_s [-]
  double radius = 10.32e-3;     ///< [m]
  double paper_c0 = 0.0;        ///< sound speed reported in 001 table 1 [m/s]
  double paper_dt = 0.0;        ///< time step of 001 table 1 [s]
};

/// Steel of 001 table 1 (their ref. [93]).
inline GridMaterial steel() { return {"steel", 2.1e11, 0.28, 7870.0, 0.5, 10.32e-3, 361.87, 1e-10}; }
/// Soft particles of 001 table 1 (3D-bed material, 1D-test size).
inline GridMaterial soft() { return {"soft", 5e6, 0.2, 2500.0, 0.7, 10.32e-3, 8.57, 1e-6}; }

/// Hertz quantities of two equal spheres (and a sphere on a plane of the same material).
struct ChainHertz {
  double mass = 0.0;       ///< particle mass [kg]
  double e_eff = 0.0;      ///< E* = E / (2 (1 - nu^2)) [Pa]
  double k_pp = 0.0;       ///< k_n = 4/3 E* sqrt(R/2), sphere-sphere [N/m^1.5]
  double k_pw = 0.0;       ///< k_n = 4/3 E* sqrt(R), sphere-plane [N/m^1.5]
  double radius = 0.0;     ///< [m]

  explicit ChainHertz(const GridMaterial& m) : radius(m.radius) {
    mass = m.density * 4.0 / 3.0 * std::numbers::pi * m.radius * m.radius * m.radius;
    e_eff = m.youngs_modulus / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio));
    k_pp = 4.0 / 3.0 * e_eff * std::sqrt(0.5 * m.radius);
    k_pw = 4.0 / 3.0 * e_eff * std::sqrt(m.radius);
  }
  /// Sphere-sphere overlap carrying the force F [N] -> [m].
  double overlap_pp(double force) const { return force > 0.0 ? std::pow(force / k_pp, 2.0 / 3.0) : 0.0; }
  /// Sphere-plane overlap carrying the force F [N] -> [m].
  double overlap_pw(double force) const { return force > 0.0 ? std::pow(force / k_pw, 2.0 / 3.0) : 0.0; }
  /// Linearised contact stiffness dF/dd at static force F [N] -> [N/m].
  double k_lin(double force) const { return 1.5 * k_pp * std::sqrt(overlap_pp(force)); }
  /// Long-wave sound speed of the chain pre-loaded by F [N]: 2R sqrt(k_lin/m) [m/s].
  double sound_speed(double force) const { return 2.0 * radius * std::sqrt(k_lin(force) / mass); }
  /// Static force per contact giving the sound speed c0 [m/s] -> [N] (inverse of sound_speed).
  double force_for_sound_speed(double c0) const {
    const double k = mass * std::pow(c0 / (2.0 * radius), 2);  // required k_lin [N/m]
    const double d0 = std::pow(k / (1.5 * k_pp), 2);           // overlap [m]
    return k_pp * std::pow(d0, 1.5);
  }
  /// Solitary-wave speed of the unloaded chain for particle speed v_m [m/s] (Nesterenko 2001
  /// eq. 1.43, 001 eq. 9) [m/s].
  double sonic_vacuum_speed(double v_m, double youngs, double nu, double rho) const {
    return std::pow(16.0 / 25.0, 0.2) *
           std::pow(2.0 * youngs / (std::numbers::pi * rho * (1.0 - nu * nu)), 0.4) * std::pow(v_m, 0.2);
  }
};

/// What holds the grid together before the impact.
enum class GridLoad {
  /// [93]'s set-up: the grid stands on a floor under gravity, the striker falls onto the top of
  /// the middle column; contact k of that column (from the top) carries k m g.
  Gravity,
  /// The struck lines squeezed between two planes so that every contact along them carries
  /// GridOptions::preload; no gravity.
  Uniform,
};

inline const char* grid_load_name(GridLoad l) { return l == GridLoad::Gravity ? "gravity" : "uniform"; }

struct GridOptions {
  GridMaterial material = soft();
  int length = 6;                  ///< particles along the struck line, the striker included [-]
  int rows = 5;                    ///< lines across [-]
  GridLoad load = GridLoad::Gravity;
  double gravity = kEarthGravity;  ///< GridLoad::Gravity: g [m/s^2]
  double preload = 0.0;            ///< GridLoad::Uniform: static force per contact along the lines [N]
  double restitution = 1.0;        ///< e [-] (1: elastic chain)
  double dt = 0.0;                 ///< time step [s]; 0 = the largest the engine accepts
  /// Cap dt at the Hertz collision time of the impact over this many steps (0 = no cap) [-].
  double collision_steps = 0.0;
  /// First particle of the line used in the fit (0 is the striker; its neighbour 1 responds at
  /// once, before any wave has formed) [-].
  int first_fitted = 2;
  /// Leave the last particle (against the far plane, whose peak merges with the reflection) out
  /// of the fit [-].
  bool skip_last = true;
};

/// Static force on each contact of the struck line before the impact: entry k is the contact
/// between particles k and k+1 (k = 0: striker and first grid particle, unloaded under gravity
/// because the striker arrives from outside), the last entry the contact with the far plane [N].
inline std::vector<double> static_contact_forces(const GridOptions& o) {
  const ChainHertz hz(o.material);
  std::vector<double> f(static_cast<std::size_t>(o.length), o.preload);
  if (o.load == GridLoad::Gravity)
    for (int k = 0; k < o.length; ++k) f[static_cast<std::size_t>(k)] = k * hz.mass * o.gravity;
  return f;
}

/// Positions of the struck line's particles along the line (striker at 0) and of the far
/// plane, at Hertz equilibrium under the static forces [m]; the last entry is the plane.
inline std::vector<double> line_positions(const GridOptions& o) {
  const ChainHertz hz(o.material);
  const std::vector<double> f = static_contact_forces(o);
  std::vector<double> s{0.0};
  for (int k = 0; k + 1 < o.length; ++k)
    s.push_back(s.back() + 2.0 * hz.radius - hz.overlap_pp(f[static_cast<std::size_t>(k)]));
  s.push_back(s.back() + hz.radius - hz.overlap_pw(f.back()));
  return s;
}

/// Wave speed the long-wave chain formula predicts over the fitted particles: arrival times
/// sum a_k / c(F_k) over the contacts passed, fitted by a straight line like the measurement
/// [m/s]. For a uniform load this is c(F0); NaN if a fitted contact carries no load.
inline double chain_prediction(const GridOptions& o) {
  const ChainHertz hz(o.material);
  const std::vector<double> f = static_contact_forces(o), s = line_positions(o);
  std::vector<double> x, t;
  double time = 0.0;
  const int last = o.length - 1 - (o.skip_last ? 1 : 0);
  for (int i = o.first_fitted; i <= last; ++i) {
    if (i > o.first_fitted) {
      const double fk = f[static_cast<std::size_t>(i - 1)];
      if (!(fk > 0.0)) return std::numeric_limits<double>::quiet_NaN();
      time += (s[static_cast<std::size_t>(i)] - s[static_cast<std::size_t>(i - 1)]) / hz.sound_speed(fk);
    }
    x.push_back(s[static_cast<std::size_t>(i)]);
    t.push_back(time);
  }
  return analysis::fit_line(t, x).slope;
}

struct GridResult {
  double v_im = 0.0;               ///< impact speed [m/s]
  double c_w = 0.0;                ///< fitted wave speed [m/s]
  double c_w_uncertainty = 0.0;    ///< standard uncertainty of the slope [m/s]
  double dt = 0.0;                 ///< time step used [s]
  std::uint64_t steps = 0;         ///< steps run [-]
  std::vector<double> position;    ///< particle positions along the line (1 .. length-1) [m]
  std::vector<double> arrival;     ///< their peak-force times [s]
};

/// Builds the grid of `o` with every particle at rest at its static equilibrium, the striker
/// touching the first particle of the middle line with speed v_im towards it (v_im = 0: the
/// grid at rest). Returns the ids of the struck line, striker first. Exposed for the tests.
template <class Sim>
std::vector<std::uint64_t> build_grid(Sim& sim, const GridOptions& o, double v_im) {
  using Vec = Dim3::Vec;
  const GridMaterial& gm = o.material;
  const double r = gm.radius;
  const std::vector<double> s = line_positions(o);
  // Along the line: +x (uniform) or -z (gravity: the striker on top). Across: touching without
  // load, 1 nm apart.
  const bool gravity = o.load == GridLoad::Gravity;
  const Vec along = gravity ? Vec(0, 0, -1) : Vec(1, 0, 0);
  const Vec across = gravity ? Vec(1, 0, 0) : Vec(0, 1, 0);
  const double b = 2.0 * r + 1e-9;
  Material m;
  m.name = gm.name;
  m.youngs_modulus = gm.youngs_modulus;
  m.poisson_ratio = gm.poisson_ratio;
  m.density = gm.density;
  m.friction = gm.friction;
  m.restitution = o.restitution;
  const auto mat = sim.add_material(m);
  const auto wall = sim.add_wall_material(m);
  const Vec origin = gravity ? Vec(0, 0, s.back()) : Vec::Zero();  // the floor at z = 0
  const ChainHertz hz(gm);
  if (!gravity)  // the near plane behind the striker, loaded like the far one
    sim.add_wall(geometry::PlaneShape<Dim3>(origin + (-r + hz.overlap_pw(o.preload)) * along, along), wall);
  sim.add_wall(geometry::PlaneShape<Dim3>(origin + s.back() * along, -along), wall);
  const int mid = o.rows / 2;
  std::vector<std::uint64_t> line;
  for (int j = 0; j < o.rows; ++j) {
    // Under gravity only the middle column has the striker on top.
    for (int i = (gravity && j != mid) ? 1 : 0; i < o.length; ++i) {
      const Vec x = origin + s[static_cast<std::size_t>(i)] * along + (j - mid) * b * across;
      const Vec v = (j == mid && i == 0) ? Vec(v_im * along) : Vec(Vec::Zero());
      const auto id = sim.add_particle(x, r, mat, v);
      if (j == mid) line.push_back(id);
    }
  }
  return line;
}

/// Simulation configuration holding the grid of `o` (domain around it, gravity if any).
inline SimulationConfig<Dim3> grid_config(const GridOptions& o) {
  using Vec = Dim3::Vec;
  const double r = o.material.radius;
  const double span = line_positions(o).back() + 2.0 * r;
  const double half = 0.5 * o.rows * (2.0 * r + 1e-9) + 2.0 * r;
  SimulationConfig<Dim3> cfg;
  if (o.load == GridLoad::Gravity) {
    cfg.domain.lo = Vec(-half, -2.0 * r, -r);
    cfg.domain.hi = Vec(half, 2.0 * r, span + r);
    cfg.gravity = Vec(0, 0, -o.gravity);
  } else {
    cfg.domain.lo = Vec(-2.0 * r, -half, -2.0 * r);
    cfg.domain.hi = Vec(span, half, 2.0 * r);
  }
  cfg.dt = 1.0;  // replaced once the particles exist
  // GridOptions::dt may be set above the engine's limit on purpose (the speed-against-error
  // study goes up to the Rayleigh time); the default is the engine's suggested step.
  cfg.allow_large_time_step = true;
  // Impacts at up to 10 m/s on the soft spheres reach overlaps of ~0.6 R (001 runs them too).
  cfg.max_overlap_ratio = 1.0;
  return cfg;
}

/// Runs one impact on the grid and fits position vs peak-force time. The integrator is a
/// template argument so that benchmarks/speed_vs_error.cpp can compare schemes on this grid.
template <class Integrator = integrators::VelocityVerlet>
GridResult run_grid(const GridOptions& o, double v_im, double threshold_fraction = 0.5) {
  require(o.length >= o.first_fitted + 3 + (o.skip_last ? 1 : 0), "lunar_shock::run_grid", "length", o.length,
          "[first_fitted + 3 (+1 with skip_last), inf) particles: the fit needs three");
  require(o.first_fitted >= 1, "lunar_shock::run_grid", "first_fitted", o.first_fitted, "[1, length)");
  require(o.rows >= 1, "lunar_shock::run_grid", "rows", o.rows, "[1, inf)");
  require(o.preload >= 0.0, "lunar_shock::run_grid", "preload", o.preload, "[0, inf) N");
  require(o.gravity >= 0.0 && std::isfinite(o.gravity), "lunar_shock::run_grid", "gravity", o.gravity, "[0, inf) m/s^2");
  require(v_im > 0.0 && std::isfinite(v_im), "lunar_shock::run_grid", "v_im", v_im, "(0, inf) m/s");
  const GridMaterial& gm = o.material;
  const ChainHertz hz(gm);
  Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList, Integrator> sim(grid_config(o));
  const std::vector<std::uint64_t> line = build_grid(sim, o, v_im);
  // Time step: the engine's limit (0.2 Rayleigh times), optionally capped by the collision time.
  double dt = o.dt > 0.0 ? o.dt : sim.suggested_time_step();
  if (o.collision_steps > 0.0) {
    const PairMaterial pm = sim.materials().pair(0, 0);
    dt = std::min(dt, hertz_collision_time(0.5 * hz.mass, pm.E_eff, 0.5 * gm.radius, v_im) / o.collision_steps);
  }
  sim.set_dt(dt);

  // Run until the slower of the least-loaded contact's sound speed and the unloaded solitary
  // wave (for v_m ~ v_im / 2) has crossed the line twice: every particle has peaked by then.
  const std::vector<double> f = static_contact_forces(o), s = line_positions(o);
  double f_min = std::numeric_limits<double>::infinity();
  for (int k = 1; k + 1 < o.length; ++k) f_min = std::min(f_min, f[static_cast<std::size_t>(k)]);
  const double c_sv = hz.sonic_vacuum_speed(0.5 * v_im, gm.youngs_modulus, gm.poisson_ratio, gm.density);
  const double c_est = std::max(f_min > 0.0 ? hz.sound_speed(f_min) : 0.0, c_sv);
  const double span = s[static_cast<std::size_t>(o.length - 1)];
  const double t_end = 2.0 * span / c_est;
  std::vector<analysis::SensorSeries> series(static_cast<std::size_t>(o.length - 1));
  for (int i = 1; i < o.length; ++i) series[static_cast<std::size_t>(i - 1)].position = s[static_cast<std::size_t>(i)];
  const auto record = [&]() {
    const auto& p = sim.particles();
    for (int i = 1; i < o.length; ++i) {
      auto& ser = series[static_cast<std::size_t>(i - 1)];
      ser.time.push_back(sim.time());
      ser.signal.push_back(p.f[sim.index_of(line[static_cast<std::size_t>(i)])].norm());
    }
  };
  record();
  while (sim.time() < t_end) {
    sim.step();
    record();
  }
  GridResult res;
  res.v_im = v_im;
  res.dt = dt;
  res.steps = sim.step_count();
  std::vector<double> t, x;
  for (std::size_t k = 0; k < series.size(); ++k) {
    auto& ser = series[k];
    // The net force is zero at rest: the peak is the first local maximum above a fraction of
    // the series' largest value (a reflection from the far plane can only come later).
    const double peak = *std::max_element(ser.signal.begin(), ser.signal.end());
    analysis::ArrivalSettings as;
    as.absolute_threshold = threshold_fraction * peak;
    as.refine_parabolic = true;
    const auto ta = analysis::arrival_time(ser, as);
    res.position.push_back(ser.position);
    res.arrival.push_back(ta ? *ta : std::numeric_limits<double>::quiet_NaN());
    const int i = static_cast<int>(k) + 1;  // index along the line
    if (ta && i >= o.first_fitted && !(o.skip_last && i == o.length - 1)) {
      t.push_back(*ta);
      x.push_back(ser.position);
    }
  }
  if (t.size() >= 3) {
    const analysis::LineFit fit = analysis::fit_line(t, x);
    res.c_w = fit.slope;
    res.c_w_uncertainty = fit.slope_uncertainty;
  } else {
    res.c_w = std::numeric_limits<double>::quiet_NaN();
    res.c_w_uncertainty = std::numeric_limits<double>::quiet_NaN();
  }
  return res;
}

/// Power law c = A v^n fitted by least squares in log-log space.
struct PowerLaw {
  double exponent = 0.0;              ///< n [-]
  double exponent_uncertainty = 0.0;  ///< u(n) [-]
  double prefactor = 0.0;             ///< A [m/s / (m/s)^n]
};

inline PowerLaw fit_power_law(const std::vector<double>& v, const std::vector<double>& c) {
  std::vector<double> lv, lc;
  for (std::size_t k = 0; k < v.size(); ++k) {
    lv.push_back(std::log(v[k]));
    lc.push_back(std::log(c[k]));
  }
  const analysis::LineFit f = analysis::fit_line(lv, lc);
  return {f.slope, f.slope_uncertainty, std::exp(f.intercept)};
}

}  // namespace granule::examples::lunar_shock
