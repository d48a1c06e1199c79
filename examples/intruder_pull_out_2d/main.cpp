// Paper 002: a thin intruder pulled up at constant speed out of a 2D bed of disks. Prints the
// statistics the README quotes (drag peak, drop and reload, thirds, quiet top layer, spectrum and
// the test of the d/2 peak spacing, mu* below and above H1, flow zones and cone angle, packing)
// and writes them with the drag, its spectrum and coarse-grained velocity maps as CSV files; with
// --study it runs the convergence study of issue 27 case by case. See README.md, scene.hpp,
// statistics.hpp and study.hpp; `intruder_pull_out_2d --help` lists the options.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/io/progress.hpp>

#include "../common/cli.hpp"
#include "study.hpp"

using namespace granule;
namespace cli = granule::examples::cli;
namespace po = granule::examples::pull_out;
namespace fs = std::filesystem;

namespace {

enum class Mode { Quick, Medium, Paper };

struct Options {
  po::PullParams p;
  Mode mode = Mode::Quick;
  fs::path out = "out/intruder_pull_out_2d";
  std::string study;          // tag ("" : a single run)
  fs::path results;           // study: result directory (default OUT/results/TAG)
  bool list = false;          // study: print the plan, run nothing
  std::vector<std::string> cases;  // study: run only these (all when empty)
  std::vector<fs::path> restat;    // run directories to analyse again
  int threads = 1;
  double ns_per_particle_step = 94.0;  // for the estimates until a case has measured it
  po::StatisticsOptions stats;
  bool physics_set = false;   // an option that changes the scene was given
  std::string physics_option;
};

// --paper and --medium set their values first, wherever they stand on the line, so that the
// other options override them; of the two, the later one counts.
void set_mode(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--paper") o.mode = Mode::Paper;
    if (a == "--medium") o.mode = Mode::Medium;
  }
  if (o.mode == Mode::Paper) {
    o.p = po::paper_params();
  } else if (o.mode == Mode::Medium) {
    const po::PullParams q = po::paper_params();
    o.p.cell_width = q.cell_width;
    o.p.bed_height = q.bed_height;
    o.p.fill_rate = q.fill_rate;
    o.p.sample_travel = q.sample_travel;
  }
}

// The options that change the scene (a study's cases set it; --restat runs nothing).
const std::vector<std::string> physics_options = {
    "--paper",     "--medium",    "--width",         "--bed-height",        "--E",
    "--thickness", "--velocity",  "--dt-rule",       "--dt",                "--sample-travel",
    "--cg-width",  "--fill-rate", "--fill-source-width", "--fill-release-height", "--fill-friction",
    "--seed"};

// The options, bound to `o`; --help shows the values of the mode given (quick without one).
void add_options(CLI::App& app, Options& o) {
  app.description(
      "A thin intruder (L = 10 mm) lying on the floor of a 2D bed of disks (d = 3 mm, radii uniform in\n"
      "[1, 2] mm) is pulled up at constant speed V (paper 002). Prints the drag statistics, mu*, the\n"
      "flow zones and the cone angle, and writes CSV files into --out.\n\n"
      "Without a mode: quick, W = 40 mm, bed 50 mm (213 disks), E = 6e7 Pa, V = 20 mm/s (~10 s).");
  app.footer("Defaults shown are those of the mode given (quick without one); later options override a\n"
             "mode's values wherever the mode stands. Exit codes: 0 done, 1 the run failed (the message\n"
             "names the cause), 2 bad arguments.");
  const std::string modes = "modes";
  const std::string scene = "options (units in brackets)";
  // The modes' values are set by set_mode; the flags are here for --help and check_options.
  app.add_flag_callback("--medium", [] {}, "002's cell and bed (W = 100 mm, 150 mm, 1600 disks), quick E and V (~3 min)")
      ->group(modes);
  app.add_flag_callback("--paper", [] {},
                        "002's values: W = 100 mm, bed 150 mm, E = 64 GPa, V = 1.2 mm/s and its step dt_c / 60 "
                        "(~1e10 steps: hundreds of hours; the estimate is printed)")
      ->group(modes);
  app.add_option_function<std::string>(
         "--study",
         [&o](const std::string& tag) {
           try {
             (void)po::study_cases(tag);
           } catch (const InvalidParameter&) {
             throw CLI::ValidationError("--study = '" + tag + "' is not a study (convergence, dtcheck)");
           }
           o.study = tag;
         },
         "the convergence study, case by case (TAG: convergence, dtcheck; see README.md); a rerun skips "
         "the cases done")
      ->type_name("TAG")
      ->group(modes);
  app.add_flag("--list", o.list, "with --study: print the cases and their estimated cost, run nothing")->group(modes);
  cli::add_text(app, "--results", o.results, "with --study: result directory (default OUT/results/TAG)")
      ->type_name("DIR")
      ->group(modes);
  app.add_option_function<std::string>(
         "--cases",
         [&o](const std::string& v) {
           std::stringstream ss(v);
           o.cases.clear();
           for (std::string item; std::getline(ss, item, ',');)
             if (!item.empty()) o.cases.push_back(item);
           if (o.cases.empty()) throw CLI::ValidationError("--cases = '" + v + "' names no case");
         },
         "with --study: run only these cases (names as --list prints them)")
      ->type_name("A,B,...")
      ->group(modes);
  app.add_option_function<std::vector<std::string>>(
         "--restat",
         [&o](const std::vector<std::string>& dirs) {
           for (const auto& d : dirs) {
             if (d.empty() || !fs::is_directory(d)) throw CLI::ValidationError("--restat = '" + d + "' is not a directory");
             o.restat.emplace_back(d);
           }
         },
         "compute the statistics again from the files of a run or study case in DIR (summary.csv with "
         "samples.csv or drag.csv) and rewrite its summary.csv; may be repeated; runs nothing")
      ->type_name("DIR")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->group(modes);
  cli::add_real(app, "--ns-per-particle-step", o.ns_per_particle_step,
                "with --study: cost rate for the estimates until one is measured", cli::positive())
      ->group(modes);

  cli::add_real(app, "--width", o.p.cell_width, "cell width W [m]", cli::positive())->group(scene);
  cli::add_real(app, "--bed-height", o.p.bed_height, "target bed height H [m]", cli::positive())->group(scene);
  cli::add_real(app, "--E", o.p.youngs_modulus, "Young's modulus, k_n = E d [Pa]", cli::positive())->group(scene);
  cli::add_real(app, "--thickness", o.p.thickness, "disk thickness t [m] (3 d: what 002's step implies)",
                cli::positive())
      ->group(scene);
  cli::add_real(app, "--velocity", o.p.pull_velocity, "pull-out speed V [m/s]", cli::positive())->group(scene);
  app.add_option_function<std::string>(
         "--dt-rule",
         [&o](const std::string& r) {
           if (r == "engine") {
             o.p.dt_rule = po::TimeStepRule::Engine;
           } else if (r == "paper") {
             o.p.dt_rule = po::TimeStepRule::Paper;
           } else {
             throw CLI::ValidationError("--dt-rule = '" + r + "' is not one of engine|paper");
           }
         },
         "step of the pull: engine = 0.2 x the linear critical time of the lightest pair, paper = 002's "
         "dt_c / 60, dt_c = sqrt(m_min/k_n)")
      ->type_name("engine|paper")
      ->default_str(o.p.dt_rule == po::TimeStepRule::Paper ? "paper" : "engine")
      ->group(scene);
  cli::add_real(app, "--dt", o.p.dt, "step of the pull [s] (overrides --dt-rule)", cli::positive(), o.p.dt > 0.0)
      ->group(scene);
  cli::add_real(app, "--sample-travel", o.p.sample_travel, "intruder travel per drag sample [m]", cli::positive())
      ->group(scene);
  cli::add_real(app, "--cg-width", o.p.cg_width,
                "coarse-graining kernel width w / d [-] (002 section 2.5; the former 0.5 remains available)",
                cli::positive())
      ->group(scene);
  cli::add_real(app, "--quiet-fraction", o.stats.quiet_fraction,
                "a drop larger than Q x peak is a fluctuation [-]", cli::Range{0.0, 1.0, false, false})
      ->type_name("Q")
      ->group(scene);
  cli::add_real(app, "--fill-rate", o.p.fill_rate, "disks released per second while filling [1/s]; 0: all at once",
                cli::non_negative())
      ->group(scene);
  cli::add_real(app, "--fill-source-width", o.p.fill_source_width,
                "width of the release region, centred [m]; 0: whole cell", cli::non_negative())
      ->group(scene);
  cli::add_real(app, "--fill-release-height", o.p.fill_release_height,
                "height of the release region above the floor [m]; 0: 3 x bed", cli::non_negative())
      ->group(scene);
  cli::add_real(app, "--fill-friction", o.p.fill_friction,
                "friction while filling (mu restored before settling) [-]; < 0: mu")
      ->group(scene);
  cli::add_whole<std::uint64_t>(app, "--seed", o.p.seed, "insertion seed", 1)->group(scene);
  cli::add_whole(app, "--threads", o.threads, "OpenMP threads (the engine runs 1600 disks on one)", 1, 1024)
      ->group(scene);
  cli::add_text(app, "--out", o.out, "output directory")->type_name("DIR")->default_str(o.out.string())->group(scene);
}

// The combinations the parser cannot check option by option (exit code 2).
void check_options(const CLI::App& app, Options& o) {
  for (const auto& name : physics_options)
    if (app.count(name) > 0) {
      o.physics_set = true;
      o.physics_option = name;
      break;
    }
  if (!o.restat.empty() && (!o.study.empty() || o.physics_set))
    throw cli::UsageError("--restat: runs nothing, so it takes no mode or scene option (only --quiet-fraction)");
  if (!o.study.empty() && o.physics_set)
    throw cli::UsageError(o.physics_option + ": not used with --study (the study's cases set the scene)");
  if (o.study.empty() && (o.list || !o.results.empty() || !o.cases.empty()))
    throw cli::UsageError(std::string(o.list ? "--list" : !o.cases.empty() ? "--cases" : "--results") +
                          ": only with --study");
  if (!o.study.empty())
    for (const auto& c : o.cases) {
      const auto all = po::study_cases(o.study);
      if (std::none_of(all.begin(), all.end(), [&](const po::StudyCase& x) { return x.name == c; }))
        throw cli::UsageError("--cases: '" + c + "' is not a case of study " + o.study + "; --list prints them");
    }
}

std::string mm(double m) { return po::study_detail::num(m * 1e3, 4) + " mm"; }
std::string g3(double v) { return po::study_detail::num(v, 3); }

void print_scene(const po::PullParams& p) {
  std::printf("scene: W = %s, target bed %s, t = %s, E = %s Pa (k_n = %s N/m), V = %s m/s; kappa = k_n/(rho phi g H t) "
              "= %s, I = V/sqrt(phi g H) = %s (phi = 0.82); pull step %s s (%s; engine 0.2 x critical %s s, "
              "002's dt_c/60 = %s s)\n",
              mm(p.cell_width).c_str(), mm(p.bed_height).c_str(), mm(p.thickness).c_str(), g3(p.youngs_modulus).c_str(),
              g3(po::normal_stiffness(p)).c_str(), g3(p.pull_velocity).c_str(), g3(po::stiffness_number(p)).c_str(),
              g3(po::inertial_number(p)).c_str(), g3(po::pull_dt(p)).c_str(),
              p.dt > 0.0 ? "given" : (p.dt_rule == po::TimeStepRule::Paper ? "002's rule" : "engine's rule"),
              g3(po::engine_dt(p)).c_str(), g3(po::paper_critical_time(p) / 60.0).c_str());
}

void print_estimate(const char* label, const po::CostEstimate& c, double ns, bool cached) {
  const double ps = static_cast<double>(c.particles) * ((cached ? 0.0 : c.fill_steps) + c.pull_steps);
  std::fprintf(stderr, "%s: %zu disks, %s%.3g steps of pull (%.3g m at dt %.3g s) = %.3g particle-steps: about %s at %.0f ns "
               "per particle-step\n",
               label, c.particles,
               cached ? "bed from the cache, " : (g3(c.fill_steps) + " steps of filling (" + g3(c.fill_time) + " s) + ").c_str(),
               c.pull_steps, c.pull_travel, c.pull_dt, ps, io::ProgressReporter::format_duration(ps * ns * 1e-9).c_str(), ns);
}

void print_statistics(const po::PullScene& s, const po::PullResult& r, const po::DragStatistics& st,
                      const po::StatisticsOptions& opt) {
  const auto& pk = s.packing;
  const double d = s.params.mean_diameter;
  std::printf("bed: %zu disks, mean surface %s (top of the 5 highest disks %s); packing fraction %.3f in the interior "
              "(%zu slabs %.3f-%.3f), %.3f over the whole bed (002: 0.82 +- 0.02); filled and settled in %.2f s simulated\n",
              s.particles, mm(pk.surface).c_str(), mm(s.bed_height).c_str(), pk.interior, pk.slabs, pk.interior_min,
              pk.interior_max, pk.whole, s.fill_sim_time);
  const std::string drop = std::isfinite(st.drop) ? g3(st.drop) + " N at " + mm(st.drop_height) : "none";
  const std::string reload = std::isfinite(st.reload) ? g3(st.reload) + " N at " + mm(st.reload_height) : "none";
  std::printf("drag: peak %s N at h = %s (%.3g x the weight M g L/W = %s N above the intruder); over d/2 of travel: peak "
              "%s N at %s, first drop after it to %s, reload to %s (turning points, hysteresis %g %% of that peak); whole "
              "pull mean %s N, std %s N\n",
              g3(st.peak).c_str(), mm(st.peak_height).c_str(), st.peak / st.column_weight, g3(st.column_weight).c_str(),
              g3(st.smoothed_peak).c_str(), mm(st.smoothed_peak_height).c_str(), drop.c_str(), reload.c_str(),
              100.0 * opt.reload_hysteresis, g3(st.drag_mean).c_str(), g3(st.drag_std).c_str());
  for (const auto& th : st.thirds)
    std::printf("  third %s-%s: drag mean %s N, std %s N; mu* bulk %s, walls %s; dragged zone (v* > 0.75) %s mm^2\n",
                mm(th.h_lo).c_str(), mm(th.h_hi).c_str(), g3(th.drag_mean).c_str(), g3(th.drag_std).c_str(),
                g3(th.mu_bulk).c_str(), g3(th.mu_wall).c_str(), g3(th.dragged_area * 1e6).c_str());
  std::printf("quiet top layer: last drop > %g %% of the peak (within d/2 of travel) at h = %s, %s below the mean surface "
              "(q = 1 %%: %s, 5 %%: %s; 002: 45 mm in a 150 mm bed, = (W - L)/2 = %s here)\n",
              100.0 * st.quiet_q[1], mm(st.last_drop_height[1]).c_str(), mm(st.quiet_thickness[1]).c_str(),
              mm(st.quiet_thickness[0]).c_str(), mm(st.quiet_thickness[2]).c_str(),
              mm(0.5 * (s.params.cell_width - s.params.intruder_length)).c_str());
  const auto& t = st.half_d;
  std::printf("spectrum of the drag minus its 4 d running mean, h = %s-%s%s: band at d/2 (%s) R = %s against a 95 %% point "
              "of %s (%zu, %zu, %zu bins): %s; drag maxima (hysteresis %g %% of the peak) spaced %s (median of %zu, %.2f d); "
              "largest power per octave at lambda = %s (002: peaks spaced about d/2)\n",
              mm(st.segment_lo).c_str(), mm(st.segment_hi).c_str(),
              st.segment_whole ? " (fluctuating part < 8 d: whole pull after the peak)" : "", mm(0.5 * d).c_str(),
              g3(t.ratio).c_str(), g3(t.critical).c_str(), t.longer.bins, t.band.bins, t.shorter.bins,
              !t.testable ? "record too short to test" : (t.stands_out ? "a peak at d/2 stands out" : "no peak at d/2 stands out"),
              100.0 * st.quiet_q[1], mm(st.event_spacing).c_str(), st.events, st.event_spacing / d,
              mm(st.dominant_wavelength).c_str());
  std::printf("mu* (bulk / walls): below H1 = %s %s / %s, above H1 %s / %s, last 10 %% of the pull %s / %s (002: maximum "
              "low in the bed, above H1 both fall towards 0.24); bulk contacts at the Coulomb threshold %.1f %% (002: < 20 %%)\n",
              mm(st.h1).c_str(), g3(st.mu_bulk_below_h1).c_str(), g3(st.mu_wall_below_h1).c_str(),
              g3(st.mu_bulk_above_h1).c_str(), g3(st.mu_wall_above_h1).c_str(), g3(st.mu_bulk_end).c_str(),
              g3(st.mu_wall_end).c_str(), 100.0 * st.sliding_bulk);
  std::printf("flow zones (w = %.2g d): edges of the mobile zone (v* = 0.25) inclined %s deg from the horizontal at the "
              "drag maxima (quartiles %s-%s, %zu maxima below the quiet layer; all loading samples: %s deg; 002: 60 deg); "
              "wall bands mobile (v* >= 0.25) %s below H1, %s above\n",
              s.params.cg_width, g3(st.cone_angle).c_str(), g3(st.cone_angle_p25).c_str(), g3(st.cone_angle_p75).c_str(),
              st.cone_samples, g3(st.cone_angle_loading).c_str(), g3(st.wall_mobility_below_h1).c_str(),
              g3(st.wall_mobility_above_h1).c_str());
  for (const auto& m : r.maps)
    std::printf("  map at h = %s (loading peak near %s, drag %s N): cone %s deg (left %s, right %s)\n", mm(m.height).c_str(),
                mm(m.target).c_str(), g3(m.drag).c_str(), g3(m.cone.angle).c_str(), g3(m.cone.left.angle).c_str(),
                g3(m.cone.right.angle).c_str());
  const double n = static_cast<double>(s.particles);
  std::printf("cost: filling %s steps%s, pull %s steps in %.1f s (of which %.1f s coarse-graining): %.0f ns per "
              "particle-step\n",
              g3(static_cast<double>(s.fill_steps)).c_str(),
              s.from_cache ? " (bed read from the cache)" : (" in " + g3(s.fill_wall_seconds) + " s").c_str(),
              g3(static_cast<double>(r.steps)).c_str(), r.wall_seconds, r.analysis_seconds,
              r.steps ? 1e9 * (r.wall_seconds - r.analysis_seconds) / (n * static_cast<double>(r.steps)) : 0.0);
}

// Heights of the velocity maps: fractions of the pull from the rest height to the top + d.
std::vector<double> map_heights(const po::PullScene& s, const std::vector<double>& fractions) {
  const double top = s.bed_height + s.params.mean_diameter;
  std::vector<double> h;
  for (double f : fractions) h.push_back(s.intruder_y0 + f * (top - s.intruder_y0));
  return h;
}

int run_single(const Options& o) {
  fs::create_directories(o.out);
  const po::PullParams& p = o.p;
  print_scene(p);
  print_estimate("estimate", po::estimate_cost(p), o.ns_per_particle_step, false);
  const po::CostEstimate est = po::estimate_cost(p);
  io::ProgressReporter fill_progress({.end_time = est.fill_time, .label = "fill"});
  auto s = po::build(p, [&](std::uint64_t n, double t) { fill_progress.update(n, t); });
  fill_progress.finish(s.sim->step_count(), s.sim->time());
  const double d = p.mean_diameter;
  const double final_height = s.bed_height + d;
  po::PullOptions opt;
  opt.final_height = final_height;
  opt.map_heights = map_heights(s, {0.1, 0.3, 0.5, 0.7, 0.9});
  opt.centre_line_travel = std::max(p.sample_travel, d / 6.0);
  io::ProgressReporter progress({.end_time = (final_height - s.intruder_y0) / p.pull_velocity, .label = "pull"});
  const auto r = po::pull(s, opt, [&](double t) { progress.update(s.sim->step_count(), t); });
  progress.finish(s.sim->step_count(), r.samples.empty() ? 0.0 : r.samples.back().time);
  const auto st = po::drag_statistics(s, r, o.stats);
  print_statistics(s, r, st, o.stats);

  const po::Provenance prov = po::provenance_now();
  const std::string c = po::provenance_line("run", prov);
  po::write_samples(o.out / "drag.csv", c, r, true);
  {
    std::vector<std::vector<double>> t;
    for (std::size_t k = 1; k < st.spectrum.frequency.size(); ++k)
      t.push_back({st.spectrum.frequency[k], 1.0 / st.spectrum.frequency[k], st.spectrum.psd[k]});
    po::write_table(o.out / "drag_spectrum.csv", c, {"spatial_frequency [1/m]", "wavelength [m]", "psd [N^2 m]"}, t);
  }
  po::write_bands(o.out / "drag_bands.csv", c, st);
  po::write_profile(o.out / "profile.csv", c, po::binned_profile(r, 1e-3));
  for (const auto& m : r.maps) po::write_map(o.out / po::map_name(m.height), c, m, p.pull_velocity, 1, 5);
  {
    std::vector<std::vector<double>> t;
    for (const auto& l : r.centre_line)
      for (std::size_t k = 0; k < l.y.size(); ++k) t.push_back({l.height, l.y[k], l.vy[k]});
    po::write_table(o.out / "centre_line.csv", c, {"intruder_height [m]", "y [m]", "vy_over_V"}, t, 4);
  }
  po::write_summary(o.out / "summary.csv", c, po::summary_rows(s, r, st, prov, prov));
  std::printf("output in %s\n", o.out.string().c_str());
  return 0;
}

// The study: every case of the tag in order of estimated cost; a case whose summary.csv exists
// is read back instead of run.
int run_study(const Options& o) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto cases = po::study_cases(o.study);
  const fs::path results = o.results.empty() ? o.out / "results" / o.study : o.results;
  const fs::path beds = o.out / "beds";
  // Cost order; a bed shared by several cases is paid by the first of them.
  struct Planned {
    po::StudyCase c;
    po::CostEstimate est;
    bool fill = true;
  };
  std::vector<Planned> plan;
  for (const auto& c : cases) plan.push_back({c, po::estimate_cost(c.params), true});
  std::stable_sort(plan.begin(), plan.end(), [](const Planned& a, const Planned& b) {
    return a.est.seconds(1.0) < b.est.seconds(1.0);
  });
  std::map<std::uint64_t, bool> bed_seen;
  for (auto& x : plan) {
    const auto key = po::bed_key(x.c.params);
    x.fill = !bed_seen[key];
    bed_seen[key] = true;
  }
  {
    // plan.csv: the cases in run order with kappa, I and the estimated steps (report.py lists
    // the cases not run yet from it).
    std::vector<std::vector<double>> t;
    for (const auto& x : plan) {
      const auto& p = x.c.params;
      t.push_back({p.youngs_modulus, p.pull_velocity, static_cast<double>(p.seed), p.dt_rule == po::TimeStepRule::Paper ? 1.0 : 0.0,
                   p.thickness, p.cell_width, p.bed_height, po::stiffness_number(p), po::inertial_number(p),
                   static_cast<double>(x.est.particles), x.fill ? x.est.fill_steps : 0.0, x.est.pull_steps});
    }
    std::ostringstream s;
    s << po::provenance_line("study " + o.study + " plan", po::provenance_now());
    s << "case,youngs_modulus [Pa],pull_velocity [m/s],seed,dt_paper_rule,thickness [m],cell_width [m],bed_height [m],"
         "kappa,inertial_number,disks,fill_steps_estimate,pull_steps_estimate\n";
    for (std::size_t k = 0; k < plan.size(); ++k) {
      s << plan[k].c.name;
      for (double v : t[k]) s << "," << po::study_detail::num(v, 6);
      s << "\n";
    }
    po::study_detail::write_atomically(results / "plan.csv", s.str());
  }
  double ns = o.ns_per_particle_step;
  auto case_seconds = [&](const Planned& x) {
    return ns * 1e-9 * static_cast<double>(x.est.particles) * ((x.fill ? x.est.fill_steps : 0.0) + x.est.pull_steps);
  };
  std::printf("intruder_pull_out_2d study '%s': %zu cases, results in %s, beds cached in %s\n", o.study.c_str(),
              plan.size(), fs::absolute(results).lexically_normal().string().c_str(),
              fs::absolute(beds).lexically_normal().string().c_str());
  std::printf("%-32s %9s %9s %9s %9s %10s %10s %12s %10s\n", "case (run order)", "E [Pa]", "V [m/s]", "kappa", "I",
              "dt [s]", "fill st.", "pull steps", "estimate");
  double total = 0.0;
  for (const auto& x : plan) {
    const auto& p = x.c.params;
    total += case_seconds(x);
    std::printf("%-32s %9.3g %9.3g %9.3g %9.3g %10.3g %10.3g %12.3g %10s\n", x.c.name.c_str(), p.youngs_modulus,
                p.pull_velocity, po::stiffness_number(p), po::inertial_number(p), x.est.pull_dt,
                x.fill ? x.est.fill_steps : 0.0, x.est.pull_steps,
                io::ProgressReporter::format_duration(case_seconds(x)).c_str());
  }
  std::printf("total about %s at %.0f ns per particle-step (%.2f CPU-hours), coarse-graining not counted\n",
              io::ProgressReporter::format_duration(total).c_str(), ns, total / 3600.0);
  std::fflush(stdout);
  if (o.list) return 0;

  auto selected = [&](const Planned& x) {
    return o.cases.empty() || std::find(o.cases.begin(), o.cases.end(), x.c.name) != o.cases.end();
  };
  auto done = [&](const Planned& x) { return po::read_summary(results / x.c.name / "summary.csv").has_value(); };
  std::size_t ran = 0, skipped = 0;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const auto& x = plan[i];
    const fs::path dir = results / x.c.name;
    if (!selected(x)) continue;
    if (done(x)) {
      ++skipped;
      std::printf("[%zu/%zu] %s: done before, skipped\n", i + 1, plan.size(), x.c.name.c_str());
      continue;
    }
    double remaining = 0.0;
    for (std::size_t k = i; k < plan.size(); ++k)
      if (selected(plan[k]) && (k == i || !done(plan[k]))) remaining += case_seconds(plan[k]);
    const po::PullParams& p = x.c.params;
    const fs::path bed_file = beds / ("bed_" + std::to_string(po::bed_key(p)) + ".ckpt");
    auto cached = po::load_bed(p, bed_file);
    std::fprintf(stderr, "[study %s %s] case %zu/%zu %s: kappa %.3g, I %.3g; this case about %s, the study's rest about %s\n",
                 o.study.c_str(), io::ProgressReporter::format_duration(std::chrono::duration<double>(Clock::now() - start).count()).c_str(),
                 i + 1, plan.size(), x.c.name.c_str(), po::stiffness_number(p), po::inertial_number(p),
                 io::ProgressReporter::format_duration(ns * 1e-9 * static_cast<double>(x.est.particles) *
                                                       ((cached ? 0.0 : x.est.fill_steps) + x.est.pull_steps)).c_str(),
                 io::ProgressReporter::format_duration(remaining).c_str());
    print_estimate(("  " + x.c.name).c_str(), x.est, ns, cached.has_value());
    po::PullScene s;
    if (cached) {
      s = std::move(*cached);
    } else {
      io::ProgressReporter fp({.end_time = x.est.fill_time, .log_interval = 60.0, .label = x.c.name + " fill"});
      s = po::build(p, [&](std::uint64_t n, double t) { fp.update(n, t); });
      fp.finish(s.sim->step_count(), s.sim->time());
      po::save_bed(s, bed_file);
    }
    po::PullOptions opt;
    opt.map_heights = map_heights(s, {0.2, 0.6});
    const double travel = s.bed_height + p.mean_diameter - s.intruder_y0;
    io::ProgressReporter pp({.end_time = travel / p.pull_velocity, .log_interval = 60.0, .label = x.c.name + " pull"});
    const auto r = po::pull(s, opt, [&](double t) { pp.update(s.sim->step_count(), t); });
    pp.finish(s.sim->step_count(), r.samples.empty() ? 0.0 : r.samples.back().time);
    const auto st = po::drag_statistics(s, r, o.stats);
    const po::Provenance prov = po::provenance_now();
    const std::string c = po::provenance_line("study " + o.study + ", case " + x.c.name, prov);
    // Side files first, summary.csv last: its presence marks the case as done.
    po::write_samples(dir / "samples.csv", c, r, false);
    po::write_profile(dir / "profile.csv", c, po::binned_profile(r, 1e-3));
    po::write_bands(dir / "bands.csv", c, st);
    // Maps every third node of the d/2 grid: 1.5 d, the kernel's width.
    for (const auto& m : r.maps) po::write_map(dir / po::map_name(m.target), c, m, p.pull_velocity, 3, 3);
    po::write_summary(dir / "summary.csv", c, po::summary_rows(s, r, st, prov, prov));
    ++ran;
    const double n = static_cast<double>(s.particles);
    if (r.steps > 0) ns = 1e9 * (r.wall_seconds - r.analysis_seconds) / (n * static_cast<double>(r.steps));
    std::printf("[%zu/%zu] %s: peak %.4g N at %.1f mm, quiet layer %.1f mm, mu* above H1 %.3g, cone %.3g deg, d/2 R = %.3g "
                "(%s); pull %.0f s, %.0f ns per particle-step\n",
                i + 1, plan.size(), x.c.name.c_str(), st.peak, st.peak_height * 1e3, st.quiet_thickness[1] * 1e3,
                st.mu_bulk_above_h1, st.cone_angle, st.half_d.ratio, st.half_d.stands_out ? "stands out" : "does not stand out",
                r.wall_seconds, ns);
    std::fflush(stdout);
  }
  std::printf("%zu cases run, %zu done before; %s of wall time\n", ran, skipped,
              io::ProgressReporter::format_duration(std::chrono::duration<double>(Clock::now() - start).count()).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  set_mode(argc, argv, o);
  CLI::App app("", "intruder_pull_out_2d");
  cli::configure(app);
  add_options(app, o);
  return cli::run(app, argc, argv, [&] {
    check_options(app, o);
#ifdef _OPENMP
    omp_set_num_threads(o.threads);
#endif
    if (!o.restat.empty()) {
      for (const auto& dir : o.restat) {
        const auto a = po::restat(dir, o.stats);
        std::printf("== %s: statistics computed again from its files\n", dir.string().c_str());
        print_scene(a.scene.params);
        print_statistics(a.scene, a.result, a.stats, o.stats);
      }
      return 0;
    }
    return o.study.empty() ? run_single(o) : run_study(o);
  });
}
