// Lateral shock in a lunar-gravity granular channel (paper 001); see scene.hpp and README.md.
//
//   lunar_shock_channel validation [options]   5 x 5 grid: c_w(v_im), acoustic plateau, v^(1/5)
//   lunar_shock_channel channel [options]      poured bed, P (or S) waves from a virtual piston
//   lunar_shock_channel --help
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/io/csv.hpp>
#include <granule/io/progress.hpp>

#include "../common/cli.hpp"
#include "../common/provenance.hpp"

#include "scene.hpp"
#include "study.hpp"

using namespace granule;
using namespace granule::examples::lunar_shock;
namespace cli = granule::examples::cli;

namespace {

/// One load case of the grid validation.
struct GridCase {
  GridLoad load = GridLoad::Gravity;
  double gravity = kEarthGravity;  ///< [m/s^2] (gravity load)
  double preload = 0.0;            ///< [N] (uniform load)
  bool preload_paper = false;      ///< uniform F0 from table 1's c_0 by the chain formula
  std::string label() const {
    char b[64];
    if (load == GridLoad::Gravity) std::snprintf(b, sizeof(b), "gravity %g m/s^2", gravity);
    else if (preload_paper) std::snprintf(b, sizeof(b), "uniform F0 from table 1's c_0");
    else std::snprintf(b, sizeof(b), "uniform F0 = %g N", preload);
    return b;
  }
};

struct ValidationOptions {
  std::vector<GridMaterial> materials;
  std::vector<GridCase> cases;
  std::vector<double> velocities = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 3e-2, 0.1, 0.3, 1, 3, 10};
  double restitution = 1.0;
  int length = 6;
  double dt = 0.0;
  double plateau_max = 1e-4;
  double shock_min = 1.0;
  bool sweep = true;
  /// Uniform pre-loads of the sweep [m g_Earth] (half decades).
  std::vector<double> sweep_weights = {1e-2, 3.16e-2, 0.1, 0.316, 1, 3.16, 10, 31.6, 100};
};

/// A CSV file whose first line says where its numbers came from.
struct ResultFile {
  std::ofstream f;
  ResultFile(const std::filesystem::path& path, const std::string& header) : f(path) {
    if (!f) throw std::runtime_error("cannot write " + path.string());
    const examples::Provenance p = examples::provenance_now();
    f << "# lunar_shock_channel validation: commit " << p.commit << "; date " << p.date << "; machine " << p.machine
      << "\n"
      << header << "\n";
    f.precision(7);
  }
  template <class... T>
  void row(const T&... v) {
    int k = 0;
    ((f << (k++ ? "," : "") << v), ...);
    f << "\n";
  }
};

/// Mean of the plateau speeds and their relative spread (max - min) / mean.
std::pair<double, double> plateau_of(const std::vector<double>& c) {
  if (c.empty()) return {NAN, NAN};
  double s = 0, lo = 1e300, hi = -1e300;
  for (double x : c) {
    s += x;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return {s / c.size(), (hi - lo) / (s / c.size())};
}

/// The plateau against a uniform pre-load F0 = w m g_Earth, measured at two weak impacts in the
/// linear regime (the dynamic overlap 1e-3 and 1e-2 of the static one); then the F0 at which the
/// measured plateau equals table 1's c_0 (log-log interpolation between the bracketing F0).
void run_preload_sweep(const ValidationOptions& vo, const std::filesystem::path& results) {
  ResultFile sweep(results / "grid_preload_sweep.csv",
                   "material,preload [N],preload_over_weight_earth,static_overlap [m],c0_chain [m/s],"
                   "c0_measured [m/s],c0_measured_10x [m/s],measured_over_chain,c0_paper [m/s]");
  ResultFile at(results / "grid_preload_at_paper_c0.csv",
                "material,c0_paper [m/s],preload_chain [N],preload_measured [N],preload_measured_over_weight_earth,"
                "preload_measured_over_weight_moon,static_overlap_measured [m],measured_over_chain_there");
  for (const GridMaterial& gm : vo.materials) {
    const ChainHertz hz(gm);
    const double weight = hz.mass * kEarthGravity;
    std::vector<double> f0s, c0s, ratio;
    for (double w : vo.sweep_weights) {
      GridOptions o;
      o.material = gm;
      o.load = GridLoad::Uniform;
      o.preload = w * weight;
      o.restitution = vo.restitution;
      o.length = vo.length;
      o.dt = vo.dt;
      const double d0 = hz.overlap_pp(o.preload);
      const double v_lin = d0 * std::sqrt(hz.k_lin(o.preload) / hz.mass);  // particle speed of a d0 swing
      const double c_a = run_grid(o, 1e-3 * v_lin).c_w, c_b = run_grid(o, 1e-2 * v_lin).c_w;
      const double chain = hz.sound_speed(o.preload);
      std::printf("  %s F0 = %9.4g N (%7.3g m g): chain %9.5g m/s, measured %9.5g (%9.5g at 10x v_im) = %.4f chain\n",
                  gm.name.c_str(), o.preload, w, chain, c_a, c_b, c_a / chain);
      sweep.row(gm.name, o.preload, w, d0, chain, c_a, c_b, c_a / chain, gm.paper_c0);
      f0s.push_back(o.preload);
      c0s.push_back(c_a);
      ratio.push_back(c_a / chain);
    }
    double f_at = NAN, r_at = NAN;
    for (std::size_t k = 0; k + 1 < f0s.size(); ++k)
      if ((c0s[k] - gm.paper_c0) * (c0s[k + 1] - gm.paper_c0) <= 0.0) {
        const double u = std::log(gm.paper_c0 / c0s[k]) / std::log(c0s[k + 1] / c0s[k]);
        f_at = f0s[k] * std::pow(f0s[k + 1] / f0s[k], u);
        r_at = ratio[k] + u * (ratio[k + 1] - ratio[k]);
        break;
      }
    std::printf("  %s: table 1's c_0 = %g m/s is measured at F0 = %.4g N = %.3g m g_Earth = %.3g m g_Moon "
                "(chain formula: %.4g N)\n",
                gm.name.c_str(), gm.paper_c0, f_at, f_at / weight, f_at / (hz.mass * kLunarGravity),
                hz.force_for_sound_speed(gm.paper_c0));
    at.row(gm.name, gm.paper_c0, hz.force_for_sound_speed(gm.paper_c0), f_at, f_at / weight,
           f_at / (hz.mass * kLunarGravity), hz.overlap_pp(f_at), r_at);
  }
}

int run_validation(const ValidationOptions& vo, const std::filesystem::path& results) {
  std::filesystem::create_directories(results);
  ResultFile speeds(results / "grid_speeds.csv",
                    "material,load,gravity [m/s^2],preload [N],v_im [m/s],c_w [m/s],c_w_uncertainty [m/s],"
                    "c_w_over_c_w_1,dt [s]");
  ResultFile summary(results / "grid_summary.csv",
                     "material,load,gravity [m/s^2],preload [N],fitted_contact_load_min [N],"
                     "fitted_contact_load_max [N],c0_chain [m/s],c0_measured [m/s],plateau_spread,c0_paper [m/s],"
                     "measured_over_paper,c_w_1 [m/s],shock_exponent,shock_exponent_uncertainty,shock_points");
  for (const GridMaterial& gm : vo.materials) {
    const ChainHertz hz(gm);
    for (const GridCase& gc : vo.cases) {
      GridOptions o;
      o.material = gm;
      o.load = gc.load;
      o.gravity = gc.load == GridLoad::Gravity ? gc.gravity : 0.0;
      o.preload = gc.load == GridLoad::Uniform ? (gc.preload_paper ? hz.force_for_sound_speed(gm.paper_c0) : gc.preload)
                                               : 0.0;
      o.restitution = vo.restitution;
      o.length = vo.length;
      o.dt = vo.dt;
      // Static loads of the contacts the fitted wave crosses (between fitted particles).
      const std::vector<double> f = static_contact_forces(o);
      double f_lo = 1e300, f_hi = 0.0;
      for (int k = o.first_fitted; k < o.length - 1 - (o.skip_last ? 1 : 0); ++k) {
        f_lo = std::min(f_lo, f[static_cast<std::size_t>(k)]);
        f_hi = std::max(f_hi, f[static_cast<std::size_t>(k)]);
      }
      const double c_chain = chain_prediction(o);
      std::printf("%s, %s: R = %.2f mm, m = %.4g kg; fitted contacts carry %.4g-%.4g N (%.3g-%.3g m g_Earth); "
                  "chain formula c_0 = %.5g m/s\n",
                  gm.name.c_str(), gc.label().c_str(), gm.radius * 1e3, hz.mass, f_lo, f_hi,
                  f_lo / (hz.mass * kEarthGravity), f_hi / (hz.mass * kEarthGravity), c_chain);
      std::vector<GridResult> rs;
      double c_ref = NAN;
      for (double v : vo.velocities) {
        rs.push_back(run_grid(o, v));
        if (std::abs(v - 1.0) < 1e-12) c_ref = rs.back().c_w;
      }
      std::vector<double> plateau, vs, cs;
      for (const auto& r : rs) {
        std::printf("  v_im = %9.3g m/s  c_w = %10.5g +- %8.3g m/s  (dt %.3g s, %llu steps)\n", r.v_im, r.c_w,
                    r.c_w_uncertainty, r.dt, static_cast<unsigned long long>(r.steps));
        speeds.row(gm.name, grid_load_name(o.load), o.gravity, o.preload, r.v_im, r.c_w, r.c_w_uncertainty,
                   r.c_w / c_ref, r.dt);
        if (r.v_im <= vo.plateau_max * (1 + 1e-9) && std::isfinite(r.c_w)) plateau.push_back(r.c_w);
        if (r.v_im >= vo.shock_min * (1 - 1e-9) && std::isfinite(r.c_w)) {
          vs.push_back(r.v_im);
          cs.push_back(r.c_w);
        }
      }
      const auto [c0, spread] = plateau_of(plateau);
      PowerLaw pl{NAN, NAN, NAN};
      // The fit gives the exponent with its uncertainty, which needs three speeds.
      if (vs.size() >= 3) pl = fit_power_law(vs, cs);
      std::printf("  plateau (v_im <= %g m/s): c_0 = %.5g m/s (spread %.2g %%), chain formula %.5g m/s, table 1 %.5g "
                  "m/s: measured / table 1 = %.3f\n",
                  vo.plateau_max, c0, 100 * spread, c_chain, gm.paper_c0, c0 / gm.paper_c0);
      if (vs.size() >= 3)
        std::printf("  shock branch (v_im >= %g m/s, %zu speeds): c_w ~ v_im^%.4f +- %.4f (expected 1/5)\n",
                    vo.shock_min, vs.size(), pl.exponent, pl.exponent_uncertainty);
      else
        std::printf("  shock branch: %zu impact speed(s) at v_im >= %g m/s, an exponent needs three (--velocities, "
                    "--shock-min)\n", vs.size(), vo.shock_min);
      summary.row(gm.name, grid_load_name(o.load), o.gravity, o.preload, f_lo, f_hi, c_chain, c0, spread, gm.paper_c0,
                  c0 / gm.paper_c0, c_ref, pl.exponent, pl.exponent_uncertainty, vs.size());
    }
  }
  if (vo.sweep) {
    std::printf("plateau against a uniform pre-load (no gravity):\n");
    run_preload_sweep(vo, results);
  }
  std::printf("results in %s\n", results.string().c_str());
  return 0;
}

/// c_w ~ v_p^n over the shocks (v_p >= 1 m/s, 001 fig. 9: 1/5), or why there is none.
void report_exponent(const std::vector<double>& vp, const std::vector<double>& cw) {
  std::set<double> distinct(vp.begin(), vp.end());
  if (distinct.size() < 2) {
    std::printf("shock exponent: needs c_w at two or more piston speeds >= 1 m/s, have %zu (001: 1/5)\n",
                distinct.size());
    return;
  }
  const PowerLaw pl = fit_power_law(vp, cw);
  std::printf("shock exponent (%zu speeds >= 1 m/s): c_w ~ v_p^%.3f +- %.3f (001: 1/5; table 8 loose 0.18-0.19)\n",
              vp.size(), pl.exponent, pl.exponent_uncertainty);
}

int run_channel(ChannelOptions o, const std::vector<double>& vps, const std::filesystem::path& out) {
  std::filesystem::create_directories(out);
  const auto bed = prepare_bed(o);
  std::printf("bed (%s, flux %.4g 1/(s m^2)): %zu particles%s, packing fraction %.4f, mean overlap delta_0 = %.4g m,"
              " %.1f s wall\n",
              packing_name(o.packing), o.flux(), bed.particles, bed.from_cache ? " (cached)" : "",
              bed.packing_fraction, bed.mean_overlap, bed.wall_seconds);
  std::printf("  poured %zu (%.3f s simulated%s, %.1f s wall), removed %zu above the fill height; settled %.3f s"
              " (%s, %.1f s wall)\n",
              bed.poured, bed.pour_time, bed.pour_from_cache || bed.from_cache ? ", cached" : "", bed.pour_wall_seconds,
              bed.removed, bed.settle_time,
              bed.settled ? "quiet" : (o.settle_force > 0 ? "NOT quiet: settle-time reached" : "fixed time"),
              bed.settle_wall_seconds);
  const auto& q = bed.quiet;
  std::printf("  quietness: net force / weight mean %.3g, median %.3g, p99 %.3g; KE/particle %.3g J; max |v| %.3g m/s,"
              " max |omega| %.3g rad/s\n",
              q.force_mean, q.force_median, q.force_p99, q.ke_per_particle, q.max_speed, q.max_spin);
  std::printf("  bed depth %.1f particle diameters; interior packing fraction %.4f, coordination %.3f; checkpoint %s\n",
              o.depth / (2 * o.radius), bed.packing_interior, bed.coordination, bed_path(o).string().c_str());
  if (!bed.settle_history.empty()) {
    io::CsvWriter sc(out / ("bed_settle_" + std::string(packing_name(o.packing)) + ".csv"),
                     {{"time", "s"}, {"force_mean", "m g"}, {"force_median", "m g"}, {"force_p99", "m g"},
                      {"ke_per_particle", "J"}, {"max_speed", "m/s"}, {"max_spin", "rad/s"}});
    for (const auto& h : bed.settle_history)
      sc.write_row({h.time, h.force_mean, h.force_median, h.force_p99, h.ke_per_particle, h.max_speed, h.max_spin});
  }
  if (vps.empty()) return 0;
  const std::string tag = o.bender ? "s" : "p";
  io::CsvWriter summary(out / ("channel_summary_" + tag + ".csv"),
                        {{"v_p", "m/s"}, {"c_w", "m/s"}, {"c_w_sd", "m/s"}, {"c_p", "m/s"}, {"c_p_sd", "m/s"},
                         {"mach_c_p_over_c_0", ""}, {"delta_m_over_delta_0", ""}, {"delta_0", "m"}, {"dz", "m"},
                         {"dz_sd", "m"}, {"max_particle_speed", "m/s"}, {"ejected", ""}, {"dt", "s"}, {"wall_time", "s"}});
  io::CsvWriter arrivals(out / ("channel_arrivals_" + tag + ".csv"),
                         {{"v_p", "m/s"}, {"y", "m"}, {"depth", "m"}, {"arrival", "s"}});
  io::CsvWriter depths(out / ("channel_depth_speeds_" + tag + ".csv"),
                       {{"v_p", "m/s"}, {"depth", "m"}, {"c_w", "m/s"}, {"c_w_uncertainty", "m/s"}, {"c_p", "m/s"},
                        {"c_p_uncertainty", "m/s"}});
  io::CsvWriter cols(out / ("channel_columns_" + tag + ".csv"),
                     {{"v_p", "m/s"}, {"y", "m"}, {"dz", "m"}, {"delta_m_over_delta_0", ""}});
  std::vector<double> sorted = vps;
  std::sort(sorted.begin(), sorted.end());
  // c_0 = mean c_w of the acoustic waves, v_p <= 0.1 m/s (001 section 2.9, table 6).
  double c0 = NAN, c0_sum = 0.0;
  int c0_n = 0;
  std::vector<double> shock_vp, shock_cw;
  for (double v : sorted) {
    const ShockResult r = run_shock(o, v);
    if (v >= 1.0 - 1e-12 && std::isfinite(r.c_w_mean)) {
      shock_vp.push_back(v);
      shock_cw.push_back(r.c_w_mean);
    }
    if (v <= 0.1 + 1e-12 && std::isfinite(r.c_w_mean)) {
      c0_sum += r.c_w_mean;
      c0 = c0_sum / ++c0_n;
    }
    const double mach = r.c_p_mean / c0;
    std::printf("v_p = %6.3g m/s: c_w = %.3f +- %.3f m/s, c_p = %.3f +- %.3f m/s, M = c_p/c_0 = %.3f, "
                "delta_m/delta_0 = %.3f, dz = %.3g +- %.2g mm, v_max = %.3g m/s, %zu ejected  (dt %.3g s, %.0f s wall)\n",
                r.v_p, r.c_w_mean, r.c_w_sd, r.c_p_mean, r.c_p_sd, mach, r.delta_ratio_mean, r.dz_mean * 1e3,
                r.dz_sd * 1e3, r.max_particle_speed, r.ejected, r.dt, r.wall_seconds);
    std::fflush(stdout);
    summary.write_row({r.v_p, r.c_w_mean, r.c_w_sd, r.c_p_mean, r.c_p_sd, mach, r.delta_ratio_mean, r.delta_0, r.dz_mean,
                       r.dz_sd, r.max_particle_speed, double(r.ejected), r.dt, r.wall_seconds});
    const std::size_t ny = r.y.size();
    for (std::size_t k = 0; k < r.depth.size(); ++k) {
      depths.write_row({r.v_p, r.depth[k], r.c_w[k], r.c_w_u[k], r.c_p[k], r.c_p_u[k]});
      for (std::size_t j = 0; j < ny; ++j) arrivals.write_row({r.v_p, r.y[j], r.depth[k], r.arrival[k * ny + j]});
    }
    for (std::size_t j = 0; j < ny; ++j) cols.write_row({r.v_p, r.y[j], r.dz[j], r.delta_ratio[j]});
  }
  const Material mat = channel_material(false);
  const double mass = mat.density * o.particle_volume();
  const double d0_paper = paper_mean_overlap(o.packing), c0_paper = paper_sound_speed(o.packing);
  if (c0_n > 0)
    std::printf("sound speed c_0 (mean c_w over v_p <= 0.1 m/s, %d run(s)) = %.3f m/s; paper table 6 (%s): %.2f m/s\n",
                c0_n, c0, packing_name(o.packing), c0_paper);
  else
    std::printf("sound speed c_0: no acoustic run with a front (v_p <= 0.1 m/s, --vp); paper table 6 (%s): %.2f m/s\n",
                packing_name(o.packing), c0_paper);
  report_exponent(shock_vp, shock_cw);
  std::printf("  c ~ delta_0^(1/4): paper c_0 x (%.3g / %.3g um)^(1/4) = %.3f m/s; eq. 7 x sqrt(3)/2 with this bed's"
              " delta_0: %.3f m/s (with the paper's delta_0: %.3f m/s)\n",
              bed.mean_overlap * 1e6, d0_paper * 1e6, c0_paper * std::pow(bed.mean_overlap / d0_paper, 0.25),
              eq7_sound_speed(bed.mean_overlap, o.radius, mass, mat.youngs_modulus, mat.poisson_ratio),
              eq7_sound_speed(d0_paper, o.radius, mass, mat.youngs_modulus, mat.poisson_ratio));
  std::printf("output in %s\n", out.string().c_str());
  return 0;
}

// ---------------------------------------------------------------------------------------------
// The paper-scale study (study.hpp), its cost and the pour check
// ---------------------------------------------------------------------------------------------

/// Rows of a CSV with an optional '#' provenance line, keyed by column name without its unit.
std::vector<std::map<std::string, std::string>> read_table(const std::filesystem::path& file) {
  std::vector<std::map<std::string, std::string>> rows;
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> names;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto f = examples::csv_split(line);
    if (names.empty()) {
      for (const auto& h : f) names.push_back(h.substr(0, h.find(" [")));
      continue;
    }
    std::map<std::string, std::string> r;
    for (std::size_t k = 0; k < names.size() && k < f.size(); ++k) r[names[k]] = f[k];
    rows.push_back(r);
  }
  return rows;
}

std::string provenance_line(const char* what) {
  const examples::Provenance p = examples::provenance_now();
  char load[32];
  std::snprintf(load, sizeof load, "%.2f", load_average());
  return std::string("# lunar_shock_channel ") + what + ": commit " + p.commit + "; date " + p.date + "; machine " +
         p.machine + "; load average " + load + "\n";
}

/// Measured cost per particle-step for a channel of length L: the segment of the nearest length
/// (settle, shock; the pour as settle); NaN where nothing was measured.
PhaseCost phase_cost(const std::filesystem::path& cost_dir, double length) {
  PhaseCost c;
  double best_settle = 1e300, best_shock = 1e300;
  for (const auto& r : read_table(cost_dir / "cost_measured.csv")) {
    const double L = std::stod(r.at("length")), ns = std::stod(r.at("ns_per_particle_step"));
    const double cpu = std::stod(r.at("cpu_ns_per_particle_step"));
    const double d = std::abs(std::log(L / length));
    if (r.at("phase") == "settle" && d < best_settle) best_settle = d, c.settle = ns, c.settle_cpu = cpu;
    if (r.at("phase") == "shock" && d < best_shock) best_shock = d, c.shock = ns, c.shock_cpu = cpu;
  }
  // The pour at the settle segment's cost (a bed at the same step, 2 threads): the pour check's
  // own figure comes from a 2 500-grain bed on one thread, dominated by per-step overheads.
  c.pour = c.settle;
  c.pour_cpu = c.settle_cpu;
  return c;
}

struct EstimateRow {
  std::string kind, tag, name;
  double length = 0;
  CaseEstimate e;       ///< at the wall time per particle-step measured (under the load of then)
  CaseEstimate idle{};  ///< at the CPU time per particle-step over the threads (an idle machine)
};

/// Estimates of every case of `tags` (beds shared across tags counted once, in tag order) and of
/// the full 2 m paper run, for `threads` threads; also written to cost_dir/cost_estimate.csv.
std::vector<EstimateRow> estimate_all(const std::filesystem::path& results, const std::vector<std::string>& tags,
                                      double length, int threads, bool write) {
  const std::filesystem::path cost_dir = results / "cost";
  std::vector<EstimateRow> rows;
  std::set<std::string> poured, settled, run;
  for (const auto& tag : tags) {
    EstimateRow total{"study", tag, "all", length, {}};
    for (const StudyCase& c : study_cases(tag, length)) {
      const ChannelOptions o = study_options(c);
      const bool pn = poured.insert(pour_key(c)).second, sn = settled.insert(settle_key(c)).second;
      const PhaseCost pc = phase_cost(cost_dir, c.length);
      EstimateRow r{"case", tag, c.stem(), c.length, estimate_case(o, pc, pn, sn),
                    estimate_case(o, pc.idle(threads), pn, sn)};
      if (!run.insert(c.stem()).second) r.e = r.idle = {};  // run by an earlier tag, copied (find_result)
      rows.push_back(r);
      for (auto [sum, one] : {std::pair{&total.e, &r.e}, std::pair{&total.idle, &r.idle}}) {
        sum->particles = std::max(sum->particles, one->particles);
        sum->pour += one->pour;
        sum->settle += one->settle;
        sum->shock += one->shock;
      }
    }
    rows.push_back(total);
  }
  // The full paper run: 2 m, 1.5 s of shock at 1e-6 s. Ours: pour and settle at 1e-5 s; 001's:
  // everything at 1e-6 s (cost per particle-step taken as at 1e-5 s).
  for (int proto = 0; proto < 2; ++proto) {
    StudyCase c{"paper", Packing::Loose, 2.0, 10.0};
    ChannelOptions o = study_options(c, proto == 0 ? 1e-5 : 1e-6);
    o.tail_from = 0.0;
    o.run_time = 1.5;
    const PhaseCost pc = phase_cost(cost_dir, 2.0);
    rows.push_back({"paper", proto == 0 ? "2 m, pour and settle at 1e-5 s" : "2 m, all at 1e-6 s (001)", "loose_L2_vp10",
                    2.0, estimate_case(o, pc, true, true), estimate_case(o, pc.idle(threads), true, true)});
  }
  if (write) {
    std::ostringstream t;
    t << provenance_line("cost estimate")
      << "kind,tag,case,length [m],particles,pour [s],settle [s],shock [s],total [s],threads,cpu_hours,"
         "total_idle [s],cpu_hours_idle,settle_time_assumed [s]\n";
    for (const auto& r : rows) {
      char b[400];
      std::snprintf(b, sizeof b, "%s,%s,%s,%g,%.0f,%.4g,%.4g,%.4g,%.4g,%d,%.4g,%.4g,%.4g,%g\n", r.kind.c_str(),
                    examples::csv_quoted(r.tag).c_str(), r.name.c_str(), r.length, r.e.particles, r.e.pour, r.e.settle,
                    r.e.shock, r.e.total(), threads, r.e.total() * threads / 3600.0, r.idle.total(),
                    r.idle.total() * threads / 3600.0, kSettleTimeAssumed);
      t << b;
    }
    study_detail::write_atomically(cost_dir / "cost_estimate.csv", t.str());
  }
  return rows;
}

std::string hms(double s) { return io::ProgressReporter::format_duration(s); }

/// --measure-cost: settle and shock segments on lattice beds of both check lengths.
int run_measure_cost(const std::filesystem::path& results, const std::filesystem::path& out, std::uint64_t steps,
                     int threads) {
  std::vector<CostSegment> segs;
  for (double L : {kShortLength, kLongLength}) {
    StudyCase c{"cost", Packing::Loose, L, 10.0};
    const ChannelOptions o = study_options(c);
    std::fprintf(stderr, "cost: settle segment, L = %g m, %llu steps ...\n", L, static_cast<unsigned long long>(steps));
    segs.push_back(measure_settle(o, steps));
    std::fprintf(stderr, "  %.0f particles, %.1f s wall, %.1f ns/particle-step wall, %.1f CPU (load %.2f -> %.2f)\n",
                 segs.back().particles, segs.back().wall, segs.back().ns_per_particle_step,
                 segs.back().cpu_ns_per_particle_step, segs.back().load_before, segs.back().load_after);
    std::fprintf(stderr, "cost: shock segment (v_p = 10 m/s, sensors on), L = %g m, %llu steps ...\n", L,
                 static_cast<unsigned long long>(steps));
    segs.push_back(measure_shock(o, 10.0, steps, out / "cost_lattice.ckpt"));
    std::fprintf(stderr, "  %.0f particles, %.1f s wall, %.1f ns/particle-step wall, %.1f CPU (load %.2f -> %.2f)\n",
                 segs.back().particles, segs.back().wall, segs.back().ns_per_particle_step,
                 segs.back().cpu_ns_per_particle_step, segs.back().load_before, segs.back().load_after);
  }
  std::ostringstream t;
  t << provenance_line("cost segments (lattice beds)")
    << "phase,length [m],particles,steps,dt [s],wall [s],ns_per_particle_step,cpu_ns_per_particle_step,load_before,"
       "load_after,threads\n";
  for (const auto& c : segs) {
    char b[300];
    std::snprintf(b, sizeof b, "%s,%g,%.0f,%.0f,%g,%.4g,%.4g,%.4g,%.2f,%.2f,%d\n", c.phase.c_str(), c.length, c.particles,
                  c.steps, c.dt, c.wall, c.ns_per_particle_step, c.cpu_ns_per_particle_step, c.load_before, c.load_after,
                  threads);
    t << b;
  }
  study_detail::write_atomically(results / "cost" / "cost_measured.csv", t.str());
  std::printf("cost segments in %s\n", (results / "cost" / "cost_measured.csv").string().c_str());
  return 0;
}

/// --pour-check: the small bed poured at 1e-5 s and at 1e-6 s (both settled at 1e-5 s).
int run_pour_check(const std::filesystem::path& results, const std::filesystem::path& out, int threads) {
  std::ostringstream t;
  t << provenance_line("pour check")
    << "packing,seed,dt_pour [s],poured,particles,packing_fraction,packing_interior,coordination,delta_0 [m],"
       "pour_time [s],pour_wall [s],pour_ns_per_particle_step,settle_time [s],settled,threads\n";
  // Three seeds per step: the difference between the steps is compared with the scatter of
  // pours at one step.
  for (std::uint64_t seed : {1, 2, 3})
  for (double dt : {1e-5, 1e-6}) {
    ChannelOptions o = pour_check_options(Packing::Loose, dt);
    o.seed = seed;
    o.bed_dir = out / "beds";
    std::fprintf(stderr, "pour check: seed %llu, dt_pour = %g s\n", static_cast<unsigned long long>(seed), dt);
    const BedReport b = prepare_bed(o);
    const double ns = b.pour_particle_steps > 0 ? 1e9 * b.pour_wall_seconds / b.pour_particle_steps : NAN;
    std::printf("pour at dt = %g s: %zu particles, packing %.4f (interior %.4f), coordination %.3f, delta_0 %.4g m; "
                "pour %.3f s simulated, %.0f s wall, %.1f ns/particle-step%s\n",
                dt, b.particles, b.packing_fraction, b.packing_interior, b.coordination, b.mean_overlap, b.pour_time,
                b.pour_wall_seconds, ns, b.from_cache ? " (cached bed: no timing)" : "");
    char row[400];
    std::snprintf(row, sizeof row, "loose,%llu,%g,%zu,%zu,%.5f,%.5f,%.4f,%.5g,%.4f,%.4g,%.4g,%.4f,%d,%d\n",
                  static_cast<unsigned long long>(seed), dt, b.poured,
                  b.particles, b.packing_fraction, b.packing_interior, b.coordination, b.mean_overlap, b.pour_time,
                  b.pour_wall_seconds, ns, b.settle_time, b.settled ? 1 : 0, threads);
    t << row;
  }
  study_detail::write_atomically(results / "cost" / "pour_check.csv", t.str());
  return 0;
}

/// --study TAG [--list]: runs (or lists) the cases of a tag, skipping those with a result file.
int run_study(const std::string& tag, const std::filesystem::path& results, const std::filesystem::path& out,
              double length_override, bool list_only, int threads) {
  study_cases(tag, kShortLength);  // an unknown tag fails here, before anything else is said
  std::vector<StudyResult> checks;
  for (const StudyCase& c : study_cases("length", kShortLength))
    if (auto r = read_result(results / "length" / (c.stem() + ".csv"))) checks.push_back(*r);
  const LengthVerdict v = length_verdict(checks);
  double length = length_override > 0.0 ? length_override : v.length;
  std::printf("length check: %s\n", v.state == LengthVerdict::State::Pass   ? "passed, the 0.5 m channel is used"
                                    : v.state == LengthVerdict::State::Fail ? "failed, the 1 m channel is used"
                                                                            : "not complete");
  for (const auto& l : v.lines) std::printf("  %s\n", l.c_str());
  if (tag != "length" && v.state == LengthVerdict::State::NotRun && length_override <= 0.0 && !list_only)
    throw InvalidParameter("--study " + tag + ": the length check is not complete; run --study length first, or give "
                           "--study-length L [m]");
  const auto cases = study_cases(tag, length);
  const auto est = estimate_all(results, study_tags(), length, threads, list_only);
  std::map<std::string, CaseEstimate> by_name;
  for (const auto& r : est)
    if (r.kind == "case" && r.tag == tag) by_name[r.name] = r.e;
  std::printf("study '%s': %zu cases, channel %g m (case files in %s)\n", tag.c_str(), cases.size(), length,
              (results / tag).string().c_str());
  double todo_s = 0.0;
  std::vector<bool> done(cases.size(), false);
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const auto& c = cases[k];
    const CaseEstimate& e = by_name[c.stem()];
    const bool have = static_cast<bool>(list_only ? read_result(results / c.tag / (c.stem() + ".csv"))
                                                  : find_result(results, c));
    done[k] = have;
    if (!have) todo_s += e.total();
    std::printf("  %-28s %s  estimate %s (pour %s, settle %s, shock %s)\n", c.stem().c_str(), have ? "done" : "todo",
                hms(e.total()).c_str(), hms(e.pour).c_str(), hms(e.settle).c_str(), hms(e.shock).c_str());
  }
  double todo_idle = 0.0;
  for (const auto& r : est)
    if (r.kind == "case" && r.tag == tag && !done[static_cast<std::size_t>(
                                               std::find_if(cases.begin(), cases.end(),
                                                            [&](const StudyCase& c) { return c.stem() == r.name; }) -
                                               cases.begin())])
      todo_idle += r.idle.total();
  std::printf("  to do: %s wall on %d thread(s) at the wall time per particle-step measured (under the load of "
              "then), %s on an idle machine (CPU time / threads); settling assumed %g s simulated\n",
              hms(todo_s).c_str(), threads, hms(todo_idle).c_str(), kSettleTimeAssumed);
  for (const auto& r : est)
    if (r.kind != "case")
      std::printf("  %-6s %-34s %s wall (idle: %s), %.3g CPU-hours (idle: %.3g)\n", r.kind.c_str(), r.tag.c_str(),
                  hms(r.e.total()).c_str(), hms(r.idle.total()).c_str(), r.e.total() * threads / 3600.0,
                  r.idle.total() * threads / 3600.0);
  if (list_only) return 0;
  const auto t_start = std::chrono::steady_clock::now();
  double est_done = 0.0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    if (done[k]) continue;
    const StudyCase& c = cases[k];
    ChannelOptions o = study_options(c);
    o.bed_dir = out / "beds";
    const double load = load_average();
    std::fprintf(stderr, "[lunar study %s] case %zu/%zu: %s (estimate %s)\n", tag.c_str(), k + 1, cases.size(),
                 c.stem().c_str(), hms(by_name[c.stem()].total()).c_str());
    const BedReport b = prepare_bed(o);
    std::fprintf(stderr, "[lunar study %s] bed: %zu particles, packing %.4f (interior %.4f), coordination %.2f, "
                 "delta_0 %.3g m, settled %s (%.2f s simulated)%s\n", tag.c_str(), b.particles, b.packing_fraction,
                 b.packing_interior, b.coordination, b.mean_overlap, b.settled ? "to the criterion" : "NOT to the criterion",
                 b.settle_time, b.from_cache ? ", cached" : "");
    const ShockResult r = run_shock(o, c.v_p);
    StudyResult s;
    s.c = c;
    s.particles = static_cast<double>(b.particles);
    s.packing_fraction = b.packing_fraction;
    s.packing_interior = b.packing_interior;
    s.coordination = b.coordination;
    s.delta_0 = r.delta_0;
    s.c_w = r.c_w_mean;
    s.c_w_sd = r.c_w_sd;
    s.c_p = r.c_p_mean;
    s.c_p_sd = r.c_p_sd;
    s.delta_ratio = r.delta_ratio_mean;
    s.dz = r.dz_mean;
    s.dz_sd = r.dz_sd;
    s.max_particle_speed = r.max_particle_speed;
    s.ejected = static_cast<double>(r.ejected);
    s.dt = r.dt;
    s.dt_tail = r.dt_tail;
    s.run_time = o.run_time;
    s.steps = static_cast<double>(r.steps);
    s.wall_time = r.wall_seconds;
    s.ns_per_particle_step = 1e9 * r.wall_seconds / (s.steps * std::max(1.0, s.particles));
    s.load = load;
    s.prov = examples::provenance_now();
    // Side files first, the case file last: its presence marks the case done.
    std::filesystem::create_directories(results / tag);
    {
      io::CsvWriter d(results / tag / (c.stem() + "_depths.csv"),
                      {{"depth", "m"}, {"c_w", "m/s"}, {"c_w_uncertainty", "m/s"}, {"c_p", "m/s"}, {"c_p_uncertainty", "m/s"}});
      for (std::size_t k2 = 0; k2 < r.depth.size(); ++k2) d.write_row({r.depth[k2], r.c_w[k2], r.c_w_u[k2], r.c_p[k2], r.c_p_u[k2]});
      io::CsvWriter cl(results / tag / (c.stem() + "_columns.csv"), {{"y", "m"}, {"dz", "m"}, {"delta_m_over_delta_0", ""}});
      for (std::size_t j = 0; j < r.y.size(); ++j) cl.write_row({r.y[j], r.dz[j], r.delta_ratio[j]});
    }
    write_result(results / tag / (c.stem() + ".csv"), s);
    est_done += by_name[c.stem()].total();
    const double elapsed = granule::examples::lunar_shock::detail::elapsed_since(t_start);
    const double left = todo_s - est_done;
    // Scale the remaining estimate by how the cases so far compared with theirs.
    const double eta = est_done > 0.0 ? left * elapsed / est_done : left;
    std::fprintf(stderr, "[lunar study %s] %s: c_w %.3f +- %.3f, c_p %.3f +- %.3f m/s, delta_m/delta_0 %.3f, dz %.3g mm "
                 "(%.0f s) | ETA %s\n", tag.c_str(), c.stem().c_str(), s.c_w, s.c_w_sd, s.c_p, s.c_p_sd, s.delta_ratio,
                 s.dz * 1e3, s.wall_time, hms(eta).c_str());
    std::printf("%-28s c_w = %.3f +- %.3f m/s, c_p = %.3f +- %.3f m/s, delta_m/delta_0 = %.3f, dz = %.3g mm, %.0f s\n",
                c.stem().c_str(), s.c_w, s.c_w_sd, s.c_p, s.c_p_sd, s.delta_ratio, s.dz * 1e3, s.wall_time);
    std::fflush(stdout);
  }
  // Summary over the files.
  std::vector<double> acoustic, vp, cw;
  for (const StudyCase& c : cases)
    if (auto r = read_result(results / tag / (c.stem() + ".csv"))) {
      if (c.v_p <= 0.1 + 1e-12 && std::isfinite(r->c_w)) acoustic.push_back(r->c_w);
      if (c.v_p >= 1.0 - 1e-12 && std::isfinite(r->c_w) && !c.bender) {
        vp.push_back(c.v_p);
        cw.push_back(r->c_w);
      }
    }
  if (!acoustic.empty()) {
    double s = 0;
    for (double x : acoustic) s += x;
    std::printf("c_0 (mean c_w over v_p <= 0.1 m/s, %zu runs) = %.3f m/s\n", acoustic.size(), s / acoustic.size());
  }
  report_exponent(vp, cw);
  if (tag == "length") {
    std::vector<StudyResult> all;
    for (const StudyCase& c : cases)
      if (auto r = read_result(results / tag / (c.stem() + ".csv"))) all.push_back(*r);
    const LengthVerdict v2 = length_verdict(all);
    for (const auto& l : v2.lines) std::printf("  %s\n", l.c_str());
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// The command line (examples/common/cli.hpp)
// ---------------------------------------------------------------------------------------------

/// Everything the command line sets.
struct Options {
  std::filesystem::path out = "out/lunar_shock_channel";
  std::filesystem::path results;  ///< empty: OUT (validation), OUT/results (study)
  int threads = 2;
  // validation
  ValidationOptions vo;
  std::string material = "both";
  GridLoad load = GridLoad::Gravity;
  std::vector<double> gravities = {kEarthGravity, kLunarGravity};
  std::optional<double> preload;  ///< uniform load [N]; nothing: the F0 of table 1's c_0
  // channel
  ChannelOptions co;
  std::vector<double> vps = {0.1, 1.0, 10.0};
  std::filesystem::path bed_dir;  ///< empty: OUT/beds
  bool bed_only = false;
  // study
  std::string study;
  bool list = false, measure_cost = false, pour_check = false;
  double study_length = 0.0;  ///< 0: from the length check
  std::uint64_t cost_steps = 2000;
};

// Options of the channel's scene: the study fixes them (study.hpp), the validation has none.
const std::vector<std::string> lunar_channel_options = {
    "--paper",        "--length",       "--depth",          "--width",         "--packing",     "--flux",
    "--pour-speed",   "--drop",         "--settle-time",    "--settle-force",  "--settle-speed", "--settle-damping",
    "--zero-interval", "--seed",        "--vp",             "--bender",        "--frequency",   "--run-time",
    "--dt-shock",     "--dt-prepare",   "--dt-max",         "--dt-pour",       "--rolling-damping", "--sample",
    "--pre-record",   "--sensor-time",  "--cw-window",      "--cp-window",     "--bed-dir",     "--bed-only"};
const std::vector<std::string> lunar_study_options = {"--study",        "--list",       "--study-length",
                                                      "--measure-cost", "--cost-steps", "--pour-check"};

std::string list_text(const std::vector<double>& v) {
  std::string s;
  for (double x : v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", x);
    if (!s.empty()) s += ',';
    s += b;
  }
  return s;
}

/// `--name a|b|c`: one of `choices`, handed to `set`.
CLI::Option* add_choice(CLI::App& app, const std::string& name, const std::vector<std::string>& choices,
                        std::function<void(const std::string&)> set, const std::string& help,
                        const std::string& default_value) {
  std::string all;
  for (const auto& c : choices) all += (all.empty() ? "" : "|") + c;
  CLI::Option* o = app.add_option_function<std::string>(
      name,
      [name, choices, all, set](const std::string& s) {
        if (std::find(choices.begin(), choices.end(), s) == choices.end())
          throw CLI::ValidationError(name + " = '" + s + "' is not one of " + all);
        set(s);
      },
      help);
  o->type_name(all)->default_str(default_value);
  return o;
}

/// `--name A,B`: a fit window along y [m], 0 <= A < B.
CLI::Option* add_window(CLI::App& app, const std::string& name, double& from, double& to, const std::string& help) {
  CLI::Option* o = app.add_option_function<std::string>(
      name,
      [name, &from, &to](const std::string& s) {
        const auto w = cli::to_real_list(name, s, cli::non_negative());
        if (w.size() != 2)
          throw CLI::ValidationError(name + " = '" + s + "' has " + std::to_string(w.size()) + " values, expected 2");
        if (!(w[1] > w[0])) throw CLI::ValidationError(name + " = " + s + ": needs A < B");
        from = w[0];
        to = w[1];
      },
      help);
  o->type_name("A,B")->default_str(list_text({from, to}));
  return o;
}

/// The grid validation's options, on its sub-command.
void add_validation_options(CLI::App& v, Options& o) {
  add_choice(v, "--material", {"steel", "soft", "both"}, [&o](const std::string& s) { o.material = s; },
             "table-1 species", o.material);
  cli::add_real_list(v, "--velocities", o.vo.velocities, "impact speeds v_im [m/s]", cli::positive())
      ->default_str(list_text(o.vo.velocities));
  add_choice(v, "--load", {"gravity", "uniform"},
             [&o](const std::string& s) { o.load = s == "uniform" ? GridLoad::Uniform : GridLoad::Gravity; },
             "what loads the grid statically (gravity: the grid's own weight)", "gravity");
  cli::add_real_list(v, "--gravity", o.gravities, "gravity load: g values [m/s^2]", cli::positive())
      ->default_str(list_text(o.gravities));
  v.add_option_function<std::string>(
       "--preload",
       [&o](const std::string& s) {
         if (s == "paper") o.preload.reset();
         else o.preload = cli::to_real("--preload", s, cli::non_negative());
       },
       "uniform load: static force per contact along the struck lines [N]; 'paper' = the F0 whose chain "
       "sound speed 2R sqrt(k_lin/m) is table 1's c_0; 0 = no pre-load (sonic vacuum)")
      ->type_name("F0|paper")
      ->default_str("paper");
  cli::add_real_list(v, "--sweep", o.vo.sweep_weights,
                     "also measure the plateau under uniform pre-loads F0 = w m g_Earth for these w, and where it "
                     "meets table 1",
                     cli::positive())
      ->default_str(list_text(o.vo.sweep_weights));
  v.add_flag_callback("--no-sweep", [&o] { o.vo.sweep = false; }, "skip that sweep");
  cli::add_real(v, "--restitution", o.vo.restitution, "coefficient of restitution e [-] (1: elastic)",
                cli::Range{0.0, 1.0, false, true});
  cli::add_whole<int>(v, "--length", o.vo.length, "particles along the struck row, striker included (6 = striker + 5)",
                      6, 100000);
  cli::add_real(v, "--dt", o.vo.dt, "time step [s] (0: the largest the engine's check allows)", cli::non_negative());
  cli::add_real(v, "--plateau-max", o.vo.plateau_max, "plateau: mean c_w over v_im <= V [m/s] (1e-4, as 001)",
                cli::positive());
  cli::add_real(v, "--shock-min", o.vo.shock_min, "shock branch: power-law fit over v_im >= V [m/s]", cli::positive());
}

/// The channel's and the study's options, on the program itself (the `channel` sub-command and
/// no sub-command both run the channel).
void add_channel_options(CLI::App& app, Options& o) {
  const std::string ch = "channel (001 sections 2.3-2.9; quick defaults, --paper for the paper's sizes)";
  ChannelOptions& co = o.co;
  app.add_flag_callback("--paper", [] {},  // set before parsing (main), so that later options override it
                        "2 m x 20 cm x 2 cm channel, dt 1e-6 s, 1.5 s runs (~5e5 particles)")
      ->group(ch);
  cli::add_real(app, "--length", co.length, "channel length along y [m]", cli::positive())->group(ch);
  cli::add_real(app, "--depth", co.depth, "fill height [m]", cli::positive())->group(ch);
  cli::add_real(app, "--width", co.width, "periodic width along x [m]", cli::positive())->group(ch);
  add_choice(app, "--packing", {"loose", "medium", "compact"},
             [&co](const std::string& s) { co.packing = study_detail::packing_of(s); }, "insertion flux of table 3",
             packing_name(co.packing))
      ->group(ch);
  cli::add_real(app, "--flux", co.insertion_flux, "insertion flux instead [particles/(s m^2)] (0: table 3's)",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--pour-speed", co.pour_speed, "downward speed of inserted particles [m/s] (paper 0)",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--drop", co.drop_height, "insertion region bottom above the fill height [m] (paper 0.10)",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--settle-time", co.settle_time, "longest settling time [s] (paper 5)", cli::positive())->group(ch);
  cli::add_real(app, "--settle-force", co.settle_force,
                "stop settling once the mean net force per particle is below F weights m g [-] (paper 3e-7 = "
                "1e-11 N; 0: settle the whole --settle-time)",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--settle-speed", co.settle_speed, "... and no particle faster than V [m/s] (0: no condition)",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--settle-damping", co.settle_damping,
                "background damping of velocities and spins while settling [1/s] (0: none)", cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--zero-interval", co.zero_interval, "velocities zeroed this often while settling [s] (0: never)",
                cli::non_negative())
      ->group(ch);
  cli::add_whole<std::uint64_t>(app, "--seed", co.seed, "insertion seed", 0)->group(ch);
  cli::add_real_list(app, "--vp", o.vps, "piston speeds v_p [m/s]", cli::positive())
      ->default_str(list_text(o.vps))
      ->group(ch);
  app.add_flag_callback("--bender", [&co] { co.bender = true; },
                        "S wave: the sheet follows z = A sin(2 pi f t) for one period, A = v_p/(2 pi f)")
      ->group(ch);
  cli::add_real(app, "--frequency", co.bender_frequency, "bender frequency [Hz]", cli::positive())->group(ch);
  cli::add_real(app, "--run-time", co.run_time, "simulated time after the impulse [s] (0: 2.5 L / 7 m/s)",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--dt-shock", co.dt_shock,
                "shock time step [s] (0: min(engine limit, dt-max, tau_c(v_p)/20, period/20))", cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--dt-prepare", co.dt_prepare,
                "pour and settle time step [s] (0: min(engine limit, dt-max); paper 1e-6)", cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--dt-max", co.dt_max, "cap on the automatic time steps [s] (0: none, the engine limit 3e-5)",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--dt-pour", co.dt_pour, "pour time step [s] (0: the pour/settle step)", cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--rolling-damping", co.rolling_damping,
                "rolling viscous damping ratio eta_r of settling and shocks [-] (2: 001 table 2; 0: 001 section "
                "2.1, 'neglected'); the pour uses 0 either way",
                cli::closed(0.0, 10.0))
      ->group(ch);
  cli::add_real(app, "--sample", co.sample_interval, "sensor sampling interval [s]", cli::positive())->group(ch);
  cli::add_real(app, "--pre-record", co.pre_record, "sensors record T before the impulse: initial level [s]",
                cli::non_negative())
      ->group(ch);
  cli::add_real(app, "--sensor-time", co.sensor_time,
                "keep force series for T after the impulse [s] (0: whole run; paper 0.25)", cli::non_negative())
      ->group(ch);
  add_window(app, "--cw-window", co.cw_from, co.cw_to, "fit window for c_w along y [m] (paper 0,0.15)")->group(ch);
  add_window(app, "--cp-window", co.cp_from, co.cp_to, "fit window for c_p along y [m] (paper 0.3,0.5)")->group(ch);
  cli::add_text(app, "--bed-dir", o.bed_dir, "cache of settled beds (default OUT/beds)")->type_name("DIR")->group(ch);
  app.add_flag("--bed-only", o.bed_only, "prepare (or load) the bed, print it, run no shock")->group(ch);

  const std::string st = "paper-scale study (001's grains, 2 cm x 20 cm cross-section, shock dt 1e-6 s; study.hpp)";
  app.add_option_function<std::string>(
         "--study",
         [&o](const std::string& tag) {
           try {
             (void)study_cases(tag, kShortLength);
           } catch (const InvalidParameter&) {
             std::string all;
             for (const auto& t : study_tags()) all += (all.empty() ? "" : ", ") + t;
             throw CLI::ValidationError("--study = '" + tag + "' is not a study (" + all + ")");
           }
           o.study = tag;
         },
         "runs the tag's cases, one result file each in RESULTS/TAG/, skipping those done (same case in "
         "another tag: copied)")
      ->type_name("length|loose|medium|rolling|bender")
      ->group(st);
  app.add_flag("--list", o.list, "with --study: the cases, done or not, and their estimated wall time")->group(st);
  cli::add_real(app, "--study-length", o.study_length,
                "channel length of the study [m] (default: 0.5 if the length check passed, 1 if not)",
                cli::positive(), false)
      ->group(st);
  app.add_flag("--measure-cost", o.measure_cost,
               "time short segments (settle, shock) of lattice beds of 0.5 m and 1 m, write "
               "RESULTS/cost/cost_measured.csv and cost_estimate.csv")
      ->group(st);
  cli::add_whole<std::uint64_t>(app, "--cost-steps", o.cost_steps, "steps per cost segment", 100)->group(st);
  app.add_flag("--pour-check", o.pour_check,
               "pour a 5 cm x 3 cm bed at dt 1e-5 s and 1e-6 s: RESULTS/cost/pour_check.csv")
      ->group(st);
}

/// The options of every mode: output, threads, results, progress.
void add_common_options(CLI::App& app, Options& o) {
  const std::string g = "every mode";
  cli::add_text(app, "--out", o.out, "output directory")->type_name("DIR")->default_str(o.out.string())->group(g);
  cli::add_whole(app, "--threads", o.threads, "OpenMP threads", 1, 1024)->group(g);
  cli::add_text(app, "--results", o.results,
                "validation: where the CSV files go (default OUT); study: root of its result directories "
                "(default OUT/results)")
      ->type_name("DIR")
      ->group(g);
  app.add_flag_callback("--quiet", [&o] { o.co.progress = false; }, "no progress lines on stderr")->group(g);
}

/// The combinations the parser cannot check option by option (exit code 2).
void check_options(const CLI::App& app, const CLI::App& validation, const Options& o) {
  auto first_given = [&](const std::vector<std::string>& names) -> std::string {
    for (const auto& n : names)
      if (app.count(n) > 0) return n;
    return "";
  };
  if (validation.parsed()) {
    for (const auto* names : {&lunar_channel_options, &lunar_study_options})
      if (const std::string n = first_given(*names); !n.empty())
        throw cli::UsageError(n + ": a channel option, not used by validation");
    if (o.load == GridLoad::Gravity && validation.count("--preload") > 0)
      throw cli::UsageError("--preload: only with --load uniform");
    if (o.load == GridLoad::Uniform && validation.count("--gravity") > 0)
      throw cli::UsageError("--gravity: only with --load gravity");
    return;
  }
  const bool study_mode = !o.study.empty() || o.measure_cost || o.pour_check;
  if (study_mode) {
    if (const std::string n = first_given(lunar_channel_options); !n.empty())
      throw cli::UsageError(n + ": not used with --study, --measure-cost or --pour-check (study.hpp fixes the channel)");
  } else if (app.count("--results") > 0) {
    throw cli::UsageError("--results: only with validation, --study, --measure-cost or --pour-check");
  }
  if (o.study.empty())
    for (const char* n : {"--list", "--study-length"})
      if (app.count(n) > 0) throw cli::UsageError(std::string(n) + ": only with --study");
  if (!o.measure_cost && app.count("--cost-steps") > 0) throw cli::UsageError("--cost-steps: only with --measure-cost");
}

int run_validation_mode(Options& o) {
  ValidationOptions& vo = o.vo;
  if (o.material == "steel" || o.material == "both") vo.materials.push_back(steel());
  if (o.material == "soft" || o.material == "both") vo.materials.push_back(soft());
  if (o.load == GridLoad::Gravity) {
    for (double g : o.gravities) vo.cases.push_back({GridLoad::Gravity, g, 0.0, false});
  } else {
    vo.cases.push_back({GridLoad::Uniform, 0.0, o.preload.value_or(0.0), !o.preload.has_value()});
  }
  return run_validation(vo, o.results.empty() ? o.out : o.results);
}

int run_channel_mode(Options& o) {
  const bool study_mode = !o.study.empty() || o.measure_cost || o.pour_check;
  if (study_mode) {
    const std::filesystem::path root = o.results.empty() ? o.out / "results" : o.results;
    if (o.pour_check) run_pour_check(root, o.out, o.threads);
    if (o.measure_cost) run_measure_cost(root, o.out, o.cost_steps, o.threads);
    if (!o.study.empty()) return run_study(o.study, root, o.out, o.study_length, o.list, o.threads);
    estimate_all(root, study_tags(), kShortLength, o.threads, true);
    return 0;
  }
  o.co.bed_dir = o.bed_dir.empty() ? o.out / "beds" : o.bed_dir;
  if (o.bed_only) o.vps.clear();
  return run_channel(o.co, o.vps, o.out);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  // --paper sets the channel's defaults wherever it stands; the options given override them.
  for (int a = 1; a < argc; ++a)
    if (std::string(argv[a]) == "--paper") o.co = ChannelOptions::paper();
  CLI::App app("Lateral shock in a lunar-gravity granular channel (paper 001; README.md).\n"
               "  lunar_shock_channel [channel] [options]     poured bed, P (or S) waves from a virtual piston;\n"
               "                                              with --study, --measure-cost, --pour-check: the\n"
               "                                              paper-scale study\n"
               "  lunar_shock_channel validation [options]    5 x 5 grid: c_w(v_im), acoustic plateau, v^(1/5)\n"
               "                                              (lunar_shock_channel validation --help)",
               "lunar_shock_channel");
  cli::configure(app);
  app.footer("Exit codes: 0 done, 1 the run failed (the message names the cause), 2 bad arguments.");
  app.require_subcommand(0, 1);
  add_common_options(app, o);
  add_channel_options(app, o);
  CLI::App* channel = app.add_subcommand("channel", "the channel (the same as no sub-command)");
  channel->fallthrough();
  CLI::App* validation = app.add_subcommand("validation", "001 section 2.2's 5 x 5 grid: c_w(v_im), plateau, v^(1/5)");
  validation->fallthrough();
  validation->footer("001 section 2.2 = the set-up of its ref. [93]: a 5 x 5 grid standing on a floor, an\n"
                     "incident particle dropped onto the top of the middle column. The options of every mode\n"
                     "(--out, --threads, --results, --quiet; lunar_shock_channel --help) may be given too.\n"
                     "Exit codes: 0 done, 1 the run failed (the message names the cause), 2 bad arguments.");
  add_validation_options(*validation, o);
  return cli::run(app, argc, argv, [&] {
    check_options(app, *validation, o);
#ifdef _OPENMP
    omp_set_num_threads(o.threads);
#endif
    std::filesystem::create_directories(o.out);
    return validation->parsed() ? run_validation_mode(o) : run_channel_mode(o);
  });
}
