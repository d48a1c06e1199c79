// Speed against error (issue 6): how accurate granule is at a given time step, and what that
// time step costs, for the integrators (integrators::VelocityVerlet, the default,
// integrators::SymplecticEuler and integrators::VelocityVerletPredictedDamping). Four measurements, each over a sweep of time steps given as
// a fraction of the Hertz collision time t_c (dt/t_c from 1/200 to 1/5) plus the steps the
// engine's Rayleigh rule gives (s x t_R, s = 0.2 = SimulationConfig::time_step_safety, 0.5 and
// 1, the largest value the config accepts):
//
// 1. Head-on Hertz collision (contact::HertzFrictionless, two equal spheres, R = 1 mm,
//    E = 5 MPa, nu = 0.3, rho = 2500 kg/m^3, relative speed 1 m/s; e = 0.5, 0.9 and 1).
//    Restitution = relative separation speed / impact speed, read in free flight after the
//    contact. Contact duration = time between the crossings of zero overlap by the incoming
//    and the outgoing free-flight trajectories (both straight lines, so no interpolation of
//    the sampled overlap enters). Each (e, dt) is run at 32 phases of the first touch within a
//    step (the contact starts (3 + phase) steps after t = 0, phase = (k + 1/2)/32); the CSV has
//    the mean signed error (what many collisions at random phases give on average) and the
//    largest error over the phases (the scatter of a single collision).
//    References: the requested e (the engine's damping realises e exactly in the continuum
//    limit, docs/physics.md), and for the duration the continuum one-contact problem. In the
//    units x = delta_max X, t = (delta_max/v) T (delta_max the elastic maximum overlap,
//    15 m* v^2 / (16 E* sqrt(R*)) = (5 m* v^2 / (4 k_H))^(2/5)) the engine's law
//      m* x'' = -k_H x^3/2 - sqrt(5) |beta| sqrt(m* k_H) x^1/4 x',  k_H = 4/3 E* sqrt(R*)
//    becomes  X'' = -5/4 X^3/2 - 5/2 |beta| X^1/4 X',  X(0) = 0, X'(0) = 1, the same for every
//    material and speed. It is integrated here by classical RK4, the step halved until e and T
//    change by less than 1e-11 (relative); the end of contact inside the last step is found by
//    bisection on the length of that RK4 step. Elastic: T = 2 int_0^1 (1 - s^5/2)^-1/2 ds
//    = 2 sqrt(pi) Gamma(2/5) / (5/2 Gamma(9/10)) = 2.9432, i.e. t_c = 2.8683 (m*^2/(R* E*^2 v))^1/5
//    (Johnson 1985, section 11.4); the RK4 solution with beta = 0 is checked against it.
//    t_c (the unit of dt) is the elastic Hertz time at the impact speed for every e.
// 2. Elastic frictionless periodic gas (HertzFrictionless, e = 1, VerletList with the default
//    skin): n^3 spheres (R = 1 mm, same material) on a simple cubic lattice in a periodic cube
//    at packing fraction 0.3, jittered, with Gaussian velocities (0.2 m/s per component, zero
//    mean); no initial overlap. t_c = elastic Hertz time of two spheres at the mean normal
//    impact speed of a Maxwell gas, sqrt(pi) x 0.2 m/s. Run for a fixed simulated time (in
//    units of t_c); E = kinetic + elastic (Simulation::kinetic_energy + elastic_energy) sampled
//    200 times. Reported: the least-squares slope of (E - E0)/E0 against time ("drift", per s
//    and per t_c), its largest and final values, and the rms scatter about the fitted line
//    ("fluctuation"); CPU time per particle-step (the sampling of E excluded), rebuilds,
//    contacts per particle. A run that stops with InstabilityError is written with NaNs.
// 3. Wave speed in the struck 5 x 5 grid of paper 001 (section 2.2), set up as
//    examples/lunar_shock_channel/scene.hpp does it (soft particles of 001 table 1, pre-load F0
//    giving 001's c_0 by the chain formula, e = 1): a shock (v_im = 1 m/s; t_c = Hertz time of
//    the impact) and an acoustic pulse (v_im = 1e-4 m/s; the time unit is then the linearised
//    contact's half period pi sqrt(m*/k_lin), k_lin = dF/dd at F0), run by scene.hpp's
//    run_grid<Integrator>() itself (same particles, planes, recording, peak picking and fit as
//    the example). The reference front speed is the
//    run at the smallest time step, dt = t_c/1600 (8x below the sweep; t_c/400 and t_c/800
//    are run too, so the reference's own error can be judged).
// 4. Neighbour skin against cost: not repeated here; docs/performance.md, "Neighbour search"
//    (bench_neighbours step_vs_skin) already has the sweep.
//
// Timing: CPU time of the whole process (CLOCK_PROCESS_CPUTIME_ID), one OpenMP thread by default
// (--threads), which does not count the time the process waits for a core on a shared machine.
// Collisions are repeated until each (integrator, e, dt) has used at least 0.05 s (0.01 s with
// --quick); only the stepping loop is timed. Cost per simulated contact time = CPU seconds per
// particle and per t_c of simulated time = (CPU per particle-step) x t_c / dt. A 2-particle
// step is dominated by fixed per-step overhead, so the collision's absolute cost is not a bulk
// figure; the gas gives the bulk cost.
//
// Usage: bench_speed_vs_error [--quick] [--out DIR] [--threads T] [--gas-side n]
//                             [--gas-time T_over_tc]
//   --quick     5 sweep steps (instead of 12), 2 Rayleigh steps (0.2 and 1 t_R), an 8^3 gas
//               for 30 t_c (instead of 16^3 for 100 t_c); under ~20 s
//   --out DIR   where the CSV files go (default: the current directory)
// Output (CSV, units in the headers; integrator: 2 = VelocityVerlet, 1 = SymplecticEuler,
// 3 = VelocityVerletPredictedDamping (collisions, and the gas for its cost: elastic contacts
// have no dashpot, so its gas trajectory is velocity Verlet's exactly; not run on the grid);
// safety: s of dt = s t_R, nan for the dt/t_c sweep):
//   speed_vs_error_collision.csv, speed_vs_error_ode.csv, speed_vs_error_scheme.csv,
//   speed_vs_error_gas.csv, speed_vs_error_gas_series.csv, speed_vs_error_grid.csv,
//   speed_vs_error_default.csv
// Progress lines on stderr; a summary on stdout. Plots: benchmarks/plot_speed_vs_error.py.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <time.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/granule.hpp>
#include <granule/io/csv.hpp>
#include <granule/scene/random.hpp>

#include "../examples/lunar_shock_channel/scene.hpp"

namespace {

using namespace granule;
using Vec = Dim3::Vec;
namespace ls = granule::examples::lunar_shock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- small utilities ------------------------------------------------------------------------

/// CPU time of the whole process, all threads [s].
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string first_line(const char* path) {
  std::ifstream in(path);
  std::string s;
  std::getline(in, s);
  return s;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&t));
  return buf;
}

/// The CSV's `integrator` column: 2 = VelocityVerlet, 1 = SymplecticEuler,
/// 3 = VelocityVerletPredictedDamping.
template <class Integrator>
constexpr double integrator_code() {
  if constexpr (std::is_same_v<Integrator, integrators::VelocityVerlet>) return 2.0;
  if constexpr (std::is_same_v<Integrator, integrators::SymplecticEuler>) return 1.0;
  return 3.0;
}

template <class Integrator>
const char* short_name() {
  if constexpr (std::is_same_v<Integrator, integrators::VelocityVerlet>) return "VV";
  if constexpr (std::is_same_v<Integrator, integrators::SymplecticEuler>) return "SE";
  return "PD";
}

struct Options {
  bool quick = false;
  int threads = 1;
  std::filesystem::path out = ".";
  int gas_side = 0;       // 0: 16 (8 with --quick)
  double gas_time = 0.0;  // [t_c]; 0: 100 (30 with --quick)
};

/// One time step of a sweep: dt = ratio x t_c; `safety` is s when dt = s t_R, else NaN.
struct StepPoint {
  double ratio = 0.0;
  double safety = kNaN;
};

/// dt/t_c from 1/200 to 1/5 (geometric), then s t_R for the Rayleigh steps, sorted by dt.
std::vector<StepPoint> step_points(bool quick, double tr_over_tc) {
  std::vector<StepPoint> pts;
  const int n = quick ? 5 : 12;
  for (int k = 0; k < n; ++k) pts.push_back({std::pow(1.0 / 200.0, 1.0 - k / double(n - 1)) * std::pow(0.2, k / double(n - 1))});
  const std::vector<double> safeties = quick ? std::vector<double>{0.2, 1.0} : std::vector<double>{0.2, 0.5, 1.0};
  for (double s : safeties) pts.push_back({s * tr_over_tc, s});
  std::sort(pts.begin(), pts.end(), [](const StepPoint& a, const StepPoint& b) { return a.ratio < b.ratio; });
  return pts;
}

// ---- Hertz theory ---------------------------------------------------------------------------

/// int_0^1 (1 - s^(5/2))^(-1/2) ds = sqrt(pi) Gamma(2/5) / (5/2 Gamma(9/10)) = 1.4716.
double hertz_duration_integral() {
  return std::sqrt(std::numbers::pi) * std::tgamma(0.4) / (2.5 * std::tgamma(0.9));
}

/// Two equal spheres of one material: effective quantities and the elastic Hertz impact.
struct HertzPair {
  double mass = 0.0;   ///< particle mass [kg]
  double m_eff = 0.0;  ///< [kg]
  double e_eff = 0.0;  ///< E* [Pa]
  double r_eff = 0.0;  ///< R* [m]
  HertzPair(const Material& m, double r) {
    mass = m.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    m_eff = 0.5 * mass;
    e_eff = m.youngs_modulus / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio));
    r_eff = 0.5 * r;
  }
  /// delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) [m].
  double max_overlap(double v) const { return std::pow(15.0 * m_eff * v * v / (16.0 * e_eff * std::sqrt(r_eff)), 0.4); }
  /// Elastic contact duration 2 (delta_max / v) x 1.4716 [s].
  double duration(double v) const { return 2.0 * max_overlap(v) / v * hertz_duration_integral(); }
};

double beta_of(double e) {
  if (e >= 1.0) return 0.0;
  const double l = std::log(e);
  return l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
}

/// Largest step the engine's check accepts for spheres of this material, over t_c: the
/// default time_step_safety x Rayleigh time.
double rayleigh_time_of(const Material& m, double r) {
  return rayleigh_time(r, m.density, m.shear_modulus(), m.poisson_ratio);
}
double default_safety() { return SimulationConfig<Dim3>{}.time_step_safety; }

// ---- reference: the scaled one-contact ODE -----------------------------------------------------

struct ContactSolution {
  double restitution = 0.0;  ///< -X'(T_end)
  double duration = 0.0;     ///< T_end in units of delta_max / v
  long steps = 0;            ///< RK4 steps per elastic duration of the final solve
  double change_e = 0.0;     ///< |e(h) - e(2h)| at the final refinement
  double change_t = 0.0;     ///< |T(h) - T(2h)| / T
};

/// X'' = -5/4 X^3/2 - 5/2 |beta| X^1/4 X' from X = 0, X' = 1 until X returns to 0, by RK4
/// with h = T_elastic / n. The force is zero for X <= 0 (no contact), as in the engine.
ContactSolution solve_contact(double beta, long n) {
  const double damp = 2.5 * std::abs(beta);
  const auto acc = [damp](double x, double u) {
    if (x <= 0.0) return 0.0;
    const double q = std::sqrt(std::sqrt(x));
    return -1.25 * x * std::sqrt(x) - damp * q * u;
  };
  const auto rk4 = [&](double x, double u, double h, double& xn, double& un) {
    const double a1 = acc(x, u);
    const double x2 = x + 0.5 * h * u, u2 = u + 0.5 * h * a1, a2 = acc(x2, u2);
    const double x3 = x + 0.5 * h * u2, u3 = u + 0.5 * h * a2, a3 = acc(x3, u3);
    const double x4 = x + h * u3, u4 = u + h * a3, a4 = acc(x4, u4);
    xn = x + h / 6.0 * (u + 2.0 * u2 + 2.0 * u3 + u4);
    un = u + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
  };
  const double h = 2.0 * hertz_duration_integral() / static_cast<double>(n);
  double x = 0.0, u = 1.0, t = 0.0;
  ContactSolution s;
  s.steps = n;
  for (long k = 0; k < 10 * n; ++k) {
    double xn = 0.0, un = 0.0;
    rk4(x, u, h, xn, un);
    if (k > 0 && xn <= 0.0) {
      // Zero of X inside this step: bisection on the length of a single RK4 step from (x, u).
      double lo = 0.0, hi = h;
      for (int it = 0; it < 200 && hi - lo > 1e-17 * (1.0 + t); ++it) {
        const double mid = 0.5 * (lo + hi);
        double xm = 0.0, um = 0.0;
        rk4(x, u, mid, xm, um);
        (xm > 0.0 ? lo : hi) = mid;
      }
      double xe = 0.0, ue = 0.0;
      rk4(x, u, 0.5 * (lo + hi), xe, ue);
      s.duration = t + 0.5 * (lo + hi);
      s.restitution = -ue;
      return s;
    }
    x = xn;
    u = un;
    t += h;
  }
  throw std::runtime_error("solve_contact: the contact did not end");
}

/// Halves the step from 2^12 steps per elastic duration until e and T change by < 1e-10.
/// (The damping term X^1/4 is not smooth where the contact starts and ends, so RK4 converges
/// more slowly than h^4 there; 1e-10 is reached with ~2^21 steps, far below the errors
/// measured in the engine, >= 1e-6.)
ContactSolution reference_contact(double beta) {
  constexpr double kTolerance = 1e-10;
  ContactSolution prev = solve_contact(beta, 1L << 12);
  for (long n = 1L << 13; n <= (1L << 24); n *= 2) {
    ContactSolution cur = solve_contact(beta, n);
    cur.change_e = std::abs(cur.restitution - prev.restitution);
    cur.change_t = std::abs(cur.duration - prev.duration) / cur.duration;
    if (cur.change_e < kTolerance && cur.change_t < kTolerance) return cur;
    prev = cur;
  }
  std::fprintf(stderr, "speed_vs_error: ODE reference for beta = %g did not converge to %g (change %g, %g)\n",
               beta, kTolerance, prev.change_e, prev.change_t);
  return prev;
}

/// The same scaled one-contact problem stepped the way the engine steps it (kick a1 dt, drift,
/// force with the velocity after the first kick, kick a2 dt), starting in free flight with the
/// first touch (3 + phase) steps after t = 0, and measured as in head_on(). With
/// `predictor` the force is instead evaluated with the velocity predicted for the end of the
/// step, v + a2 dt a(x, v) (one fixed-point iteration of the implicit second kick). Returns
/// {restitution, duration in units of delta_max / v}. Used to find out why the engine's
/// errors scale as they do (see the file comment and docs/performance.md).
std::array<double, 2> scheme_impact(double beta, double h, double phase, double a1, double a2, bool predictor) {
  const double damp = 2.5 * std::abs(beta);
  const auto acc = [damp](double x, double u) {
    if (x <= 0.0) return 0.0;
    return -1.25 * x * std::sqrt(x) - damp * std::sqrt(std::sqrt(x)) * u;
  };
  const double x0 = -(3.0 + phase) * h;  // overlap < 0: the gap
  double x = x0, u = 1.0, f = 0.0, t = 0.0;
  bool touched = false;
  for (long k = 0; k < 100000000L; ++k) {
    u += a1 * h * f;
    x += h * u;
    t += h;
    f = predictor ? acc(x, u + a2 * h * acc(x, u)) : acc(x, u);
    u += a2 * h * f;
    if (x > 0.0) touched = true;
    if (touched && x <= 0.0) break;
  }
  // Free flight again: overlap x <= 0 on the outgoing line of slope u < 0.
  return {-u, (t - x / u) - (-x0)};
}

// ---- 1. head-on collision -------------------------------------------------------------------

Material soft_material(double e) {
  Material m;
  m.name = "soft";
  m.youngs_modulus = 5e6;  // [Pa]
  m.poisson_ratio = 0.3;   // [-]
  m.density = 2500.0;      // [kg/m^3]
  m.restitution = e;
  return m;
}
constexpr double kRadius = 1e-3;    // collision and gas spheres [m]
constexpr double kImpactSpeed = 1.0;  // relative speed of the head-on collision [m/s]

struct Impact {
  double restitution = 0.0;
  double duration = 0.0;  ///< [s]
  std::uint64_t steps = 0;
  double cpu = 0.0;       ///< CPU seconds of the stepping loop
};

template <class Integrator>
Impact head_on(const Material& mat, double dt, double phase) {
  const double r = kRadius, v = kImpactSpeed;
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Vec::Constant(-10.0 * r);
  cfg.domain.hi = Vec::Constant(10.0 * r);
  cfg.dt = dt;
  cfg.allow_large_time_step = true;  // the sweep goes beyond the engine's limit on purpose
  cfg.max_overlap_ratio = 1.0;
  Simulation<Dim3, contact::HertzFrictionless, neighbours::VerletList, Integrator> sim(cfg);
  const auto pm = sim.add_material(mat);
  const double gap = (3.0 + phase) * v * dt;
  const auto a = sim.add_particle(Vec(r + 0.5 * gap, 0, 0), r, pm, Vec(-0.5 * v, 0, 0));
  const auto b = sim.add_particle(Vec(-r - 0.5 * gap, 0, 0), r, pm, Vec(0.5 * v, 0, 0));
  const auto& p = sim.particles();
  const auto separation = [&] { return p.x[sim.index_of(a)].x() - p.x[sim.index_of(b)].x(); };
  const double t_start = (separation() - 2.0 * r) / v;  // incoming free flight reaches zero gap
  Impact res;
  bool touched = false;
  const double c0 = cpu_seconds();
  for (std::uint64_t k = 0; k < 100000000ULL; ++k) {
    sim.step();
    const double s = separation();
    if (s < 2.0 * r) touched = true;
    if (touched && s >= 2.0 * r) break;
  }
  res.cpu = cpu_seconds() - c0;
  // The force at this position is zero: the velocity is the outgoing free-flight velocity and
  // the position lies on that straight line (both integrators).
  const double v_out = p.v[sim.index_of(a)].x() - p.v[sim.index_of(b)].x();
  const double t_end = sim.time() - (separation() - 2.0 * r) / v_out;
  res.restitution = v_out / v;
  res.duration = t_end - t_start;
  res.steps = sim.step_count();
  return res;
}

struct ImpactStats {
  double e_mean_error = 0.0, e_max_error = 0.0;  // e_meas - e (mean, signed) and max |.|
  double t_mean_error = 0.0, t_max_error = 0.0;  // (t_meas - t_ref)/t_ref
  double cpu_per_step = 0.0;                     // [s]
  double steps_per_contact = 0.0;
};

constexpr int kPhases = 32;  // phases of the first touch within a step

template <class Integrator>
ImpactStats impact_sweep(double e, double dt, double t_ref, double min_cpu) {
  ImpactStats st;
  double cpu = 0.0, steps = 0.0;
  for (int pass = 0; pass == 0 || cpu < min_cpu; ++pass) {
    for (int k = 0; k < kPhases; ++k) {
      const Impact im = head_on<Integrator>(soft_material(e), dt, (k + 0.5) / kPhases);
      cpu += im.cpu;
      steps += static_cast<double>(im.steps);
      if (pass > 0) continue;
      const double de = im.restitution - e, dtc = (im.duration - t_ref) / t_ref;
      st.e_mean_error += de / kPhases;
      st.t_mean_error += dtc / kPhases;
      st.e_max_error = std::max(st.e_max_error, std::abs(de));
      st.t_max_error = std::max(st.t_max_error, std::abs(dtc));
    }
  }
  st.cpu_per_step = cpu / steps;
  st.steps_per_contact = t_ref / dt;
  return st;
}

void run_collisions(const Options& o, io::CsvWriter& csv, io::CsvWriter& ode_csv, io::CsvWriter& scheme_csv) {
  const HertzPair hp(soft_material(1.0), kRadius);
  const double dmax = hp.max_overlap(kImpactSpeed);
  const double tc = hp.duration(kImpactSpeed);
  const double tr = rayleigh_time_of(soft_material(1.0), kRadius);
  std::fprintf(stderr, "[collision] t_c = %.6e s (elastic Hertz, 1 m/s), t_R = %.6e s, default dt = %.4f t_c\n", tc,
               tr, default_safety() * tr / tc);
  const double min_cpu = o.quick ? 0.01 : 0.05;
  for (double e : {0.5, 0.9, 1.0}) {
    const ContactSolution ref = reference_contact(beta_of(e));
    const double t_ref = ref.duration * dmax / kImpactSpeed;
    ode_csv.write_row({e, ref.restitution, ref.restitution - e, ref.duration, t_ref, static_cast<double>(ref.steps),
                       ref.change_e, ref.change_t, 2.0 * hertz_duration_integral()});
    std::fprintf(stderr, "[collision] e = %.2f: ODE e = %.12f (|e_ODE - e| = %.1e), T = %.10f (x delta_max/v), "
                 "t_ref = %.6e s, %ld RK4 steps\n", e, ref.restitution, std::abs(ref.restitution - e), ref.duration,
                 t_ref, ref.steps);
    for (const StepPoint& sp : step_points(o.quick, tr / tc)) {
      const double dt = sp.ratio * tc;
      const auto row = [&](auto tag, const ImpactStats& st) {
        using I = decltype(tag);
        const double cost = st.cpu_per_step / 2.0 * (tc / dt);  // per particle per simulated t_c
        csv.write_row({integrator_code<I>(), e, sp.ratio, sp.safety, dt, tc, st.steps_per_contact, st.e_mean_error,
                       st.e_max_error, st.t_mean_error, st.t_max_error, st.cpu_per_step, cost});
        std::fprintf(stderr, "[collision] %s e = %.2f dt = t_c/%-7.2f e error %+.3e (max %.3e)  t_c error %+.3e "
                     "(max %.3e)  %.3g us/step\n", short_name<I>(), e, 1.0 / sp.ratio, st.e_mean_error, st.e_max_error,
                     st.t_mean_error, st.t_max_error, 1e6 * st.cpu_per_step);
      };
      row(integrators::VelocityVerlet{}, impact_sweep<integrators::VelocityVerlet>(e, dt, t_ref, min_cpu));
      row(integrators::SymplecticEuler{}, impact_sweep<integrators::SymplecticEuler>(e, dt, t_ref, min_cpu));
      row(integrators::VelocityVerletPredictedDamping{},
          impact_sweep<integrators::VelocityVerletPredictedDamping>(e, dt, t_ref, min_cpu));
      // The engine's step re-done on the scaled problem (variant 0), and with the damping
      // evaluated at a predicted end-of-step velocity (variant 1); same phases.
      for (int variant = 0; variant < 2; ++variant) {
        double em = 0, ex = 0, tm = 0, tx = 0;
        for (int k = 0; k < kPhases; ++k) {
          const auto [es, ts] = scheme_impact(beta_of(e), sp.ratio * 2.0 * hertz_duration_integral(),
                                              (k + 0.5) / kPhases, 0.5, 0.5, variant == 1);
          const double de = es - e, dtc = (ts - ref.duration) / ref.duration;
          em += de / kPhases;
          tm += dtc / kPhases;
          ex = std::max(ex, std::abs(de));
          tx = std::max(tx, std::abs(dtc));
        }
        scheme_csv.write_row({static_cast<double>(variant), e, sp.ratio, sp.safety, em, ex, tm, tx});
      }
    }
  }
}

// ---- 2. elastic periodic gas ----------------------------------------------------------------

constexpr double kGasSigma = 0.2;    // velocity standard deviation per component [m/s]
constexpr double kGasPacking = 0.3;  // packing fraction [-]

struct GasSetup {
  double box = 0.0;               ///< cube edge [m]
  std::vector<Vec> x, v;
  double tc = 0.0;                ///< [s]
};

GasSetup make_gas(int side) {
  GasSetup g;
  const double r = kRadius;
  const std::size_t n = static_cast<std::size_t>(side) * side * side;
  g.box = std::cbrt(static_cast<double>(n) * 4.0 / 3.0 * std::numbers::pi * r * r * r / kGasPacking);
  const double a = g.box / side;  // lattice spacing, 1.2 d at packing 0.3
  const double jitter = 0.45 * (a - 2.0 * r);
  scene::RandomGenerator rng(20261124);
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        Vec x((i + 0.5) * a, (j + 0.5) * a, (k + 0.5) * a);
        for (int c = 0; c < 3; ++c) x[c] += rng.uniform(-jitter, jitter);
        g.x.push_back(x);
      }
  Vec mean = Vec::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    g.v.emplace_back(rng.normal(0.0, kGasSigma), rng.normal(0.0, kGasSigma), rng.normal(0.0, kGasSigma));
    mean += g.v.back();
  }
  mean /= static_cast<double>(n);
  for (auto& v : g.v) v -= mean;
  const HertzPair hp(soft_material(1.0), r);
  g.tc = hp.duration(std::sqrt(std::numbers::pi) * kGasSigma);  // mean normal impact speed
  return g;
}

struct GasResult {
  bool stable = true;
  std::uint64_t steps = 0;
  double drift = kNaN;          ///< slope of (E - E0)/E0 against t [1/s]
  double max_dev = kNaN;        ///< max |E - E0| / E0
  double final_dev = kNaN;      ///< (E_end - E0) / E0
  double fluctuation = kNaN;    ///< rms of (E - E0)/E0 about the fitted line
  double cpu = 0.0;             ///< [s], stepping only
  double cpu_per_ps = kNaN;     ///< [s] per particle-step
  double rebuilds = 0.0;
  double contacts = 0.0;        ///< mean contacts per particle
  std::vector<std::array<double, 2>> series;  ///< (t, (E - E0)/E0)
};

template <class Integrator>
GasResult run_gas(const GasSetup& g, double dt, double t_end) {
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(g.box);
  cfg.domain.periodic = Domain<Dim3>::Flags::Constant(true);
  cfg.dt = dt;
  cfg.allow_large_time_step = true;
  Simulation<Dim3, contact::HertzFrictionless, neighbours::VerletList, Integrator> sim(cfg);
  const auto mat = sim.add_material(soft_material(1.0));
  for (std::size_t i = 0; i < g.x.size(); ++i) sim.add_particle(g.x[i], kRadius, mat, g.v[i]);
  const double n = static_cast<double>(g.x.size());
  GasResult res;
  const double e0 = sim.kinetic_energy() + sim.elastic_energy();
  const std::uint64_t total = static_cast<std::uint64_t>(std::llround(t_end / dt));
  const std::uint64_t every = std::max<std::uint64_t>(1, total / 200);
  const std::size_t builds0 = sim.neighbour_list().builds;
  double contact_steps = 0.0;
  res.series.push_back({0.0, 0.0});
  try {
    while (sim.step_count() < total) {
      const std::uint64_t chunk = std::min(every, total - sim.step_count());
      const double c0 = cpu_seconds();
      for (std::uint64_t k = 0; k < chunk; ++k) {
        sim.step();
        contact_steps += static_cast<double>(sim.contact_count());
      }
      res.cpu += cpu_seconds() - c0;
      const double e = sim.kinetic_energy() + sim.elastic_energy();
      res.series.push_back({sim.time(), (e - e0) / e0});
    }
  } catch (const InstabilityError& ex) {
    res.stable = false;
    std::fprintf(stderr, "[gas] %s dt = %.4g s: unstable (%s)\n", short_name<Integrator>(), dt, ex.what());
  }
  res.steps = sim.step_count();
  res.rebuilds = static_cast<double>(sim.neighbour_list().builds - builds0);
  if (!res.stable || res.steps == 0) return res;
  res.cpu_per_ps = res.cpu / (n * static_cast<double>(res.steps));
  res.contacts = contact_steps / (n * static_cast<double>(res.steps));
  // Least-squares line through the samples after the first 10 % of the run (the lattice
  // start: the contact number and elastic energy first rise to their steady level);
  // drift = slope, fluctuation = rms residual about the line.
  double st = 0, sy = 0, stt = 0, sty = 0, m = 0;
  res.max_dev = 0.0;
  for (const auto& [t, y] : res.series) {
    res.max_dev = std::max(res.max_dev, std::abs(y));
    if (t < 0.1 * t_end) continue;
    st += t;
    sy += y;
    stt += t * t;
    sty += t * y;
    m += 1.0;
  }
  res.drift = (m * sty - st * sy) / (m * stt - st * st);
  const double c = (sy - res.drift * st) / m;
  double ss = 0.0;
  for (const auto& [t, y] : res.series)
    if (t >= 0.1 * t_end) ss += std::pow(y - c - res.drift * t, 2);
  res.fluctuation = std::sqrt(ss / m);
  res.final_dev = res.series.back()[1];
  return res;
}

void run_gas_sweep(const Options& o, io::CsvWriter& csv, io::CsvWriter& series_csv, double& tc_out,
                   double& tr_out) {
  const int side = o.gas_side > 0 ? o.gas_side : (o.quick ? 8 : 16);
  const double t_over_tc = o.gas_time > 0.0 ? o.gas_time : (o.quick ? 30.0 : 100.0);
  const GasSetup g = make_gas(side);
  const double tr = rayleigh_time_of(soft_material(1.0), kRadius);
  tc_out = g.tc;
  tr_out = tr;
  std::fprintf(stderr, "[gas] %zu particles, box %.4g m, t_c = %.6e s, simulated time %.0f t_c, default dt = %.4f t_c\n",
               g.x.size(), g.box, g.tc, t_over_tc, default_safety() * tr / g.tc);
  for (const StepPoint& sp : step_points(o.quick, tr / g.tc)) {
    const double dt = sp.ratio * g.tc;
    const auto one = [&](auto tag) {
      using I = decltype(tag);
      const GasResult r = run_gas<I>(g, dt, t_over_tc * g.tc);
      csv.write_row({integrator_code<I>(), sp.ratio, sp.safety, dt, g.tc, static_cast<double>(g.x.size()), t_over_tc * g.tc,
                     r.stable ? 1.0 : 0.0, static_cast<double>(r.steps), r.drift, r.drift * g.tc, r.max_dev,
                     r.final_dev, r.fluctuation, r.cpu, r.cpu_per_ps, r.cpu_per_ps * g.tc / dt, r.rebuilds,
                     r.contacts});
      for (const auto& [t, y] : r.series) series_csv.write_row({integrator_code<I>(), sp.ratio, t / g.tc, y});
      std::fprintf(stderr, "[gas] %s dt = t_c/%-7.2f drift %+.3e per t_c  max|dE|/E %.3e  fluct %.3e  %.1f ns/ps  "
                   "rebuilds %.0f  contacts/particle %.3f  cpu %.2f s\n", short_name<I>(), 1.0 / sp.ratio,
                   r.drift * g.tc, r.max_dev, r.fluctuation, 1e9 * r.cpu_per_ps, r.rebuilds, r.contacts, r.cpu);
    };
    one(integrators::VelocityVerlet{});
    one(integrators::SymplecticEuler{});
    // Elastic gas: the same trajectory as velocity Verlet (no dashpot); run for its cost.
    one(integrators::VelocityVerletPredictedDamping{});
  }
}

// ---- 3. struck 5 x 5 grid (paper 001 section 2.2) ---------------------------------------------

/// scene.hpp's run_grid with the integrator chosen; `cpu` receives the CPU seconds of the whole
/// run (the set-up of 25 particles is negligible next to the stepping loop).
template <class Integrator>
ls::GridResult grid_run(const ls::GridOptions& o, double v_im, double& cpu) {
  const double c0 = cpu_seconds();
  ls::GridResult res = ls::run_grid<Integrator>(o, v_im);
  cpu = cpu_seconds() - c0;
  return res;
}

void run_grid_sweep(const Options& o, io::CsvWriter& csv, std::vector<std::array<double, 4>>& scales) {
  const ls::GridMaterial gm = ls::soft();
  const ls::ChainHertz hz(gm);
  ls::GridOptions base;
  base.material = gm;
  base.load = ls::GridLoad::Uniform;
  base.preload = hz.force_for_sound_speed(gm.paper_c0);
  base.restitution = 1.0;
  Material m;
  m.youngs_modulus = gm.youngs_modulus;
  m.poisson_ratio = gm.poisson_ratio;
  m.density = gm.density;
  const double tr = rayleigh_time_of(m, gm.radius);
  const double n = static_cast<double>(base.length * base.rows);
  const double m_eff = 0.5 * hz.mass;
  // case 0: shock, t_c of the impact; case 1: acoustic, half period of the linearised contact.
  const std::array<double, 2> speeds{1.0, 1e-4};
  const std::array<double, 2> units{
      2.0 * std::pow(15.0 * m_eff / (16.0 * hz.e_eff * std::sqrt(0.5 * gm.radius)), 0.4) * std::pow(speeds[0], -0.2) *
          hertz_duration_integral(),
      std::numbers::pi * std::sqrt(m_eff / hz.k_lin(base.preload))};
  for (int c = 0; c < 2; ++c) {
    const double v_im = speeds[static_cast<std::size_t>(c)], tc = units[static_cast<std::size_t>(c)];
    scales.push_back({2.0 + c, tc, tr, v_im});
    std::fprintf(stderr, "[grid] %s: v_im = %g m/s, F0 = %.5g N, time unit %.6e s, t_R = %.6e s, default dt = %.4f "
                 "unit\n", c == 0 ? "shock" : "acoustic", v_im, base.preload, tc, tr, default_safety() * tr / tc);
    std::vector<StepPoint> pts{{1.0 / 1600.0}, {1.0 / 800.0}, {1.0 / 400.0}};
    for (const StepPoint& sp : step_points(o.quick, tr / tc)) pts.push_back(sp);
    // Reference: the smallest dt, velocity Verlet (both integrators are run there).
    std::array<double, 2> ref{kNaN, kNaN};
    for (const StepPoint& sp : pts) {
      ls::GridOptions go = base;
      go.dt = sp.ratio * tc;
      double cpu_vv = 0.0, cpu_se = 0.0;
      // A run that stops with InstabilityError keeps c_w = NaN (and steps = 0).
      const auto guarded = [&](auto&& f) {
        ls::GridResult g;
        g.c_w = g.c_w_uncertainty = kNaN;
        try {
          g = f();
        } catch (const InstabilityError& ex) {
          std::fprintf(stderr, "[grid] dt = %.4g s: unstable (%s)\n", go.dt, ex.what());
        }
        return g;
      };
      const ls::GridResult vv = guarded([&] { return grid_run<integrators::VelocityVerlet>(go, v_im, cpu_vv); });
      const ls::GridResult se = guarded([&] { return grid_run<integrators::SymplecticEuler>(go, v_im, cpu_se); });
      if (std::isnan(ref[0])) ref = {vv.c_w, se.c_w};
      const auto row = [&](double order, const ls::GridResult& g, double c_ref, double cpu) {
        const double cpu_ps = g.steps > 0 ? cpu / (n * static_cast<double>(g.steps)) : kNaN;
        csv.write_row({static_cast<double>(c), order, v_im, sp.ratio, sp.safety, go.dt, tc, g.c_w, g.c_w_uncertainty,
                       c_ref, (g.c_w - c_ref) / c_ref, static_cast<double>(g.steps), cpu, cpu_ps,
                       cpu_ps * tc / go.dt});
      };
      row(2.0, vv, ref[0], cpu_vv);
      row(1.0, se, ref[0], cpu_se);
      std::fprintf(stderr, "[grid] %s dt = unit/%-7.2f c_w VV %.8g (rel. to ref %+.3e)  SE %.8g (%+.3e)\n",
                   c == 0 ? "shock" : "acoustic", 1.0 / sp.ratio, vv.c_w, (vv.c_w - ref[0]) / ref[0], se.c_w,
                   (se.c_w - ref[0]) / ref[0]);
    }
  }
}

// ---- default time step against the collision time ---------------------------------------------

/// dt_default / t_c = time_step_safety x t_R / t_c for two equal spheres meeting at v, as a
/// function of v / sqrt(E/rho) and nu (independent of size, E and rho otherwise).
double default_over_tc(double nu, double v_over_c) {
  Material m = soft_material(1.0);
  m.poisson_ratio = nu;
  const double c = std::sqrt(m.youngs_modulus / m.density);
  const HertzPair hp(m, kRadius);
  return default_safety() * rayleigh_time_of(m, kRadius) / hp.duration(v_over_c * c);
}

void print_usage() {
  std::fprintf(stderr,
               "usage: bench_speed_vs_error [--quick] [--out DIR] [--threads T] [--gas-side n] [--gas-time T_over_tc]\n"
               "  --quick        fewer time steps, 8^3 gas for 30 t_c (under ~20 s)\n"
               "  --out DIR      directory of the CSV files (default: current directory)\n"
               "  --threads T    OpenMP threads (default 1; CPU time counts all threads)\n"
               "  --gas-side n   gas of n^3 particles (default 16, quick 8)\n"
               "  --gas-time T   simulated gas time in collision times (default 100, quick 30)\n");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      const auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--quick") {
        o.quick = true;
      } else if (a == "--out") {
        o.out = next();
      } else if (a == "--threads") {
        o.threads = std::stoi(next());
      } else if (a == "--gas-side") {
        o.gas_side = std::stoi(next());
      } else if (a == "--gas-time") {
        o.gas_time = std::stod(next());
      } else if (a == "--help" || a == "-h") {
        print_usage();
        return 0;
      } else {
        throw std::invalid_argument("unknown option " + a);
      }
    }
    if (o.threads < 1) throw std::invalid_argument("--threads must be >= 1");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "speed_vs_error: %s\n", e.what());
    print_usage();
    return 2;
  }
#ifdef _OPENMP
  omp_set_num_threads(o.threads);
#endif
  try {
    std::filesystem::create_directories(o.out);
    const double cpu0 = cpu_seconds();
    std::printf("speed_vs_error: %s, mode %s, threads %d, load average \"%s\"\n", utc_now().c_str(),
                o.quick ? "quick" : "full", o.threads, first_line("/proc/loadavg").c_str());
    std::printf("time_step_safety (SimulationConfig default) = %g; times are CPU time (CLOCK_PROCESS_CPUTIME_ID)\n",
                default_safety());

    io::CsvWriter collision(o.out / "speed_vs_error_collision.csv",
                            {{"integrator", ""}, {"restitution", ""}, {"dt_over_tc", ""}, {"safety", ""},
                             {"dt", "s"}, {"tc", "s"}, {"steps_per_contact", ""}, {"e_error_mean", ""},
                             {"e_error_max", ""}, {"duration_rel_error_mean", ""}, {"duration_rel_error_max", ""},
                             {"cpu_per_step", "s"}, {"cpu_per_particle_per_tc", "s"}});
    io::CsvWriter ode(o.out / "speed_vs_error_ode.csv",
                      {{"restitution", ""}, {"e_ode", ""}, {"e_ode_minus_e", ""}, {"duration_scaled", ""},
                       {"duration", "s"}, {"rk4_steps_per_elastic_duration", ""}, {"last_change_e", ""},
                       {"last_change_duration_rel", ""}, {"elastic_duration_scaled_theory", ""}});
    io::CsvWriter scheme(o.out / "speed_vs_error_scheme.csv",
                         {{"variant", ""}, {"restitution", ""}, {"dt_over_tc", ""}, {"safety", ""},
                          {"e_error_mean", ""}, {"e_error_max", ""}, {"duration_rel_error_mean", ""},
                          {"duration_rel_error_max", ""}});
    run_collisions(o, collision, ode, scheme);

    io::CsvWriter gas(o.out / "speed_vs_error_gas.csv",
                      {{"integrator", ""}, {"dt_over_tc", ""}, {"safety", ""}, {"dt", "s"}, {"tc", "s"},
                       {"particles", ""}, {"simulated_time", "s"}, {"stable", ""}, {"steps", ""}, {"drift", "1/s"},
                       {"drift_per_tc", ""}, {"max_rel_energy_error", ""}, {"final_rel_energy_error", ""},
                       {"fluctuation", ""}, {"cpu", "s"}, {"cpu_per_particle_step", "s"},
                       {"cpu_per_particle_per_tc", "s"}, {"rebuilds", ""}, {"contacts_per_particle", ""}});
    io::CsvWriter gas_series(o.out / "speed_vs_error_gas_series.csv",
                             {{"integrator", ""}, {"dt_over_tc", ""}, {"time_over_tc", ""},
                              {"rel_energy_error", ""}});
    double gas_tc = 0.0, gas_tr = 0.0;
    run_gas_sweep(o, gas, gas_series, gas_tc, gas_tr);

    io::CsvWriter grid(o.out / "speed_vs_error_grid.csv",
                       {{"case", ""}, {"integrator", ""}, {"v_im", "m/s"}, {"dt_over_tc", ""}, {"safety", ""},
                        {"dt", "s"}, {"tc", "s"}, {"c_w", "m/s"}, {"c_w_uncertainty", "m/s"}, {"c_w_reference", "m/s"},
                        {"c_w_rel_error", ""}, {"steps", ""}, {"cpu", "s"},
                        {"cpu_per_particle_step", "s"}, {"cpu_per_particle_per_tc", "s"}});
    std::vector<std::array<double, 4>> scales;
    run_grid_sweep(o, grid, scales);

    // Default step over t_c: the four scenes, and the general map against v / sqrt(E/rho).
    io::CsvWriter def(o.out / "speed_vs_error_default.csv",
                      {{"scene", ""}, {"nu", ""}, {"v_over_c", ""}, {"tc", "s"}, {"rayleigh_time", "s"},
                       {"dt_default", "s"}, {"dt_default_over_tc", ""}});
    const HertzPair hp(soft_material(1.0), kRadius);
    const double c_soft = std::sqrt(5e6 / 2500.0);
    const double tr = rayleigh_time_of(soft_material(1.0), kRadius);
    std::printf("default dt = %g t_R against the time unit of each measurement:\n", default_safety());
    const auto scene_row = [&](double id, double nu, double voc, double tc, double t_r, const char* what) {
      def.write_row({id, nu, voc, tc, t_r, default_safety() * t_r, default_safety() * t_r / tc});
      std::printf("  %-44s dt_default = %.4e s = t_c / %.2f\n", what, default_safety() * t_r, tc / (default_safety() * t_r));
    };
    scene_row(0, 0.3, kImpactSpeed / c_soft, hp.duration(kImpactSpeed), tr, "collision (soft, 1 m/s)");
    scene_row(1, 0.3, std::sqrt(std::numbers::pi) * kGasSigma / c_soft, gas_tc, gas_tr, "gas (soft, mean impact speed)");
    for (const auto& s : scales)
      scene_row(s[0], 0.2, s[3] / std::sqrt(5e6 / 2500.0), s[1], s[2],
                s[0] == 2.0 ? "grid shock (001 soft, v_im 1 m/s)" : "grid acoustic (unit pi sqrt(m*/k_lin))");
    for (double nu : {0.2, 0.3, 0.45})
      for (double lg = -6.0; lg <= -0.99; lg += 0.25) {
        const double voc = std::pow(10.0, lg);
        def.write_row({-1.0, nu, voc, kNaN, kNaN, kNaN, default_over_tc(nu, voc)});
      }
    std::printf("  map (scene -1 rows): dt_default/t_c = %.4f (v/c = 1e-4), %.4f (1e-3), %.4f (1e-2), nu = 0.3\n",
                default_over_tc(0.3, 1e-4), default_over_tc(0.3, 1e-3), default_over_tc(0.3, 1e-2));
    std::printf("total CPU %.1f s; CSV files in %s\n", cpu_seconds() - cpu0, o.out.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "speed_vs_error: %s\n", e.what());
    return 1;
  }
  return 0;
}
