// Two parallel rods intruding into a 3D granular bed (paper 000, Pravin et al. 2020): net work
// W(s/d) over the gap s between the rods, F(z), force PDF and very strong forces, velocity
// profiles and strain-rate maps at half depth. The scene itself is in scene.hpp; this file
// parses options and writes CSV files. `two_rod_intrusion --help` lists the options.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/io/csv.hpp>

#include "../common/cli.hpp"
#include "study.hpp"

namespace tr = granule::examples::two_rod;
namespace cli = granule::examples::cli;
using granule::io::CsvColumn;
using granule::io::CsvWriter;

namespace {

struct Options {
  tr::BedParams bed;
  tr::RodParams rod;
  std::vector<double> gaps{0, 1, 2, 3, 5, 8};  // s/d
  bool single = true;
  bool analysis = true;
  int threads = 2;
  std::string out;
  std::uint64_t vtk_every = 0;
  bool quiet = false;
  bool paper = false;
  std::string study;                 // tag of the paper-scale study ("" : a single sweep)
  std::vector<double> seeds{1, 2, 3};  // beds of the study
  std::string results;               // where the study's result files go
  std::vector<double> field_gaps{0, 2, 3, 4, 6, 15};  // s/d with strain-rate maps (first bed)
  bool aggregate_only = false;       // study: summarise the result files, run nothing
};

// Quick mode: d = 4 mm (a particle size of the paper's sweep, appendix A.1), small box,
// 2.5 cm deep intrusion; see README.md for why the regime is kept.
void set_quick(Options& o) {
  o.bed = tr::BedParams{};
  o.bed.diameter = 4e-3;
  o.bed.dt = 3e-5;
  o.bed.length_x = 0.10;
  o.bed.length_y = 0.12;
  o.bed.fill_height = 0.05;
  o.rod = tr::RodParams{};
  o.rod.width = 5e-3;
  o.rod.length = 5e-2;
  o.rod.depth = 0.025;
  o.gaps = {0, 1, 2, 3, 5, 8};
}

// Paper mode: table I of paper 000 (25 x 25 cm box filled to 10 cm, d = 2 mm, dt = 5e-6 s,
// rods 5 mm x 5 cm pushed to 8 cm at 1 m/s).
void set_paper(Options& o) {
  o.bed = tr::BedParams{};
  o.bed.diameter = 2e-3;
  o.bed.dt = 5e-6;  // 0.062 x the Rayleigh time of a 2 mm grain of 1100 kg/m^3
  o.bed.length_x = 0.25;
  o.bed.length_y = 0.25;
  o.bed.fill_height = 0.10;
  o.bed.max_settle_time = 5.0;
  o.rod = tr::RodParams{};
  o.rod.width = 5e-3;
  o.rod.length = 5e-2;
  o.rod.depth = 0.08;
  o.gaps = {0, 1, 2, 3, 4, 5, 6, 8, 10, 12, 15, 20};
}

// Study mode (issue 25): the paper's grain scale and every dimensionless group of table I --
// d = 2 mm, rho = 1100 kg/m^3 as the grains' density (README: why), E, nu, e, mu, dt = 5e-6 s,
// rods 5 mm x 5 cm at 1 m/s to 8 cm, a 10 cm deep bed at phi ~ 0.62 -- in a box cut to
// 9 x 9 cm (the box-size check of the README), on an ensemble of independently poured beds.
// The beds are poured with friction 0.1 (README: that reaches phi = 0.62) at 1.5e-5 s (0.19 of
// the Rayleigh time; the settled bed is static and the intrusions run at 5e-6 s).
void set_study(Options& o) {
  o.bed = tr::BedParams{};
  o.bed.diameter = 2e-3;
  o.bed.dt = 5e-6;
  o.bed.pour_dt = 1.5e-5;
  o.bed.pour_friction = 0.1;
  o.bed.length_x = 0.09;
  o.bed.length_y = 0.09;
  o.bed.fill_height = 0.10;
  o.bed.max_settle_time = 3.0;
  // The rods and the grains they push move 5 um per step: with the default skin (0.1 d) the
  // list was rebuilt every 20 steps, a third of the run. 0.4 d halves the cost; W moves by
  // the run-to-run scatter only (0.3 %, examples/two_rod_intrusion/README.md).
  o.bed.skin = 0.4;
  o.rod = tr::RodParams{};
  o.rod.width = 5e-3;
  o.rod.length = 5e-2;
  o.rod.depth = 0.08;
  o.gaps = {0, 1, 2, 3, 4, 5, 6, 8, 11, 15};
}

std::string gap_text(double g) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", g);
  return buf;
}

// --paper and --study set a mode's values first, wherever they stand on the line, so that every
// other option overrides them; if both are given, the later one sets the values.
void set_mode(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--paper") {
      set_paper(o);
      o.paper = true;
    } else if (a == "--study" || a.starts_with("--study=")) {
      set_study(o);
    }
  }
}

// The options, bound to `o`; --help shows the values of the mode given (quick without one).
void add_options(CLI::App& app, Options& o) {
  app.description(
      "Two parallel rods (axes along x, surface-to-surface gap s along y) pushed down at constant\n"
      "speed into a poured bed of spheres (Pravin et al. 2020). For every gap of the sweep it writes\n"
      "F(z), the net work W = integral F dz, and at half depth the normal-force PDF, the number of\n"
      "very strong forces (f_n > 6 <f_n>), V_y and V_z profiles below the rods and a strain-rate map.\n"
      "The bed is poured once and cached as bed_<hash>.ckpt in the output directory.\n\n"
      "Without a mode: quick mode, a few minutes on 2 cores: d = 4 mm, 10 x 12 cm box filled to 5 cm,\n"
      "rods 5 mm x 5 cm to 2.5 cm depth, s/d = 0,1,2,3,5,8.");
  app.footer("Defaults shown are those of the mode given (quick without one); later options override a\n"
             "mode's values wherever the mode stands. Exit codes: 0 done, 1 the run failed (the message\n"
             "names the cause), 2 bad arguments.");
  const std::string modes = "modes";
  const std::string study = "the paper-scale study (--study)";
  const std::string scene = "options (units in brackets)";
  app.add_flag("--paper", o.paper,  // its values are set by set_mode
               "paper 000 table I: d = 2 mm, 25 x 25 cm box filled to 10 cm, depth 8 cm, dt = 5e-6 s, "
               "s/d = 0..20 (~9e5 grains: days of CPU)")
      ->group(modes);
  app.add_option_function<std::string>(
         "--study",
         [&o](const std::string& tag) {
           if (tag.empty() || tag.find_first_of("/\\ ") != std::string::npos)
             throw CLI::ValidationError("--study = '" + tag + "' is not a tag (no '/', '\\' or spaces)");
           o.study = tag;
         },
         "the paper-scale study: table I in a 9 x 9 cm box filled to 10 cm, beds poured to phi ~ 0.62, "
         "s/d = 0,1,2,3,4,5,6,8,11,15 and a single rod on every bed of --seeds; one result file per case "
         "under --results (a rerun skips the cases done), then W(s/d) over the beds (see README.md)")
      ->type_name("TAG")
      ->group(modes);
  cli::add_real_list(app, "--seeds", o.seeds, "beds (pouring seeds) of the study, whole numbers >= 1",
                     cli::at_least(1.0))
      ->default_str("1,2,3")
      ->group(study);
  app.add_flag("--aggregate-only", o.aggregate_only, "write the summaries from the result files already there")
      ->group(study);
  cli::add_text(app, "--results", o.results, "the study's result directory (default OUT/results/TAG)")
      ->type_name("DIR")
      ->group(study);
  cli::add_real(app, "--density", o.bed.density, "grain density [kg/m^3]", cli::positive())->group(study);
  cli::add_real(app, "--pour-mu", o.bed.pour_friction, "friction while the bed is poured [-] (default: --mu)",
                cli::non_negative(), o.bed.pour_friction >= 0.0)
      ->group(study);
  cli::add_real(app, "--pour-dt", o.bed.pour_dt, "time step while the bed is poured [s] (default: --dt)",
                cli::positive(), o.bed.pour_dt > 0.0)
      ->group(study);
  cli::add_real(app, "--d", o.bed.diameter, "particle diameter [m]", cli::positive())->group(scene);
  cli::add_real(app, "--width", o.rod.width, "rod width or diameter [m]", cli::positive())->group(scene);
  cli::add_real(app, "--length", o.rod.length, "rod length [m]", cli::positive())->group(scene);
  std::string gaps;
  for (double g : o.gaps) gaps += (gaps.empty() ? "" : ",") + gap_text(g);
  cli::add_real_list(app, "--gap-list", o.gaps, "gaps s/d to sweep [-]", cli::non_negative())
      ->default_str(gaps)
      ->group(scene);
  app.add_option_function<std::string>(
         "--shape",
         [&o](const std::string& s) {
           if (s == "square") {
             o.rod.shape = tr::RodShape::Square;
           } else if (s == "cylinder") {
             o.rod.shape = tr::RodShape::Cylinder;
           } else {
             throw CLI::ValidationError("--shape = '" + s + "' is not one of square|cylinder");
           }
         },
         "rod cross-section")
      ->type_name("square|cylinder")
      ->default_str("square")
      ->group(scene);
  cli::add_real(app, "--depth", o.rod.depth, "final depth of the rods' bottom [m]", cli::positive())->group(scene);
  cli::add_real(app, "--speed", o.rod.speed, "intrusion speed [m/s]", cli::positive())->group(scene);
  cli::add_real(app, "--mu", o.bed.friction, "friction coefficient of grains and walls [-]", cli::non_negative())
      ->group(scene);
  cli::add_real(app, "--dt", o.bed.dt, "time step [s]", cli::positive())->group(scene);
  cli::add_real(app, "--skin", o.bed.skin, "Verlet skin of the intrusions / d (default: study 0.4, else 0.1)",
                cli::closed(0.0, 2.0), o.bed.skin >= 0.0)
      ->group(scene);
  app.add_option_function<std::string>(
         "--box",
         [&o](const std::string& s) {
           const auto v = cli::to_real_list("--box", s, cli::positive());
           if (v.size() != 3)
             throw CLI::ValidationError("--box = '" + s + "' has " + std::to_string(v.size()) +
                                        " values, expected LX,LY,H");
           o.bed.length_x = v[0];
           o.bed.length_y = v[1];
           o.bed.fill_height = v[2];
         },
         "container length (along rods), width, fill height [m]")
      ->type_name("LX,LY,H")
      ->default_str(gap_text(o.bed.length_x) + "," + gap_text(o.bed.length_y) + "," + gap_text(o.bed.fill_height))
      ->group(scene);
  cli::add_whole<std::uint64_t>(app, "--seed", o.bed.seed, "seed of the pouring jitter [-]", 0)->group(scene);
  app.add_flag_callback("--no-single", [&o] { o.single = false; }, "skip the single-rod reference run")
      ->group(scene);
  app.add_flag_callback("--no-analysis", [&o] { o.analysis = false; },
                        "skip the half-depth analysis (PDF, profiles, strain rate)")
      ->group(scene);
  cli::add_whole(app, "--threads", o.threads, "OpenMP threads [-]", 1, 1024)->group(scene);
  cli::add_text(app, "--out", o.out,
                "output directory (default out/two_rod_intrusion, or . when the working directory already "
                "is out/two_rod_intrusion)")
      ->type_name("DIR")
      ->group(scene);
  cli::add_whole<std::uint64_t>(app, "--vtk-every", o.vtk_every,
                                "write particle and rod VTK frames every N steps [-] (0: none)", 0)
      ->group(scene);
  app.add_flag("--quiet", o.quiet, "no progress on stderr")->group(scene);
}

// What the parser cannot check option by option; a bad value is a usage error (exit code 2).
void check_options(Options& o) {
  for (double k : o.seeds)
    if (k != std::floor(k)) throw cli::UsageError("--seeds expects whole numbers >= 1, got " + gap_text(k));
  try {
    o.bed.validate();
    o.rod.validate(o.bed);
  } catch (const granule::InvalidParameter& e) {
    throw cli::UsageError(e.what());
  }
  if (o.out.empty()) {
    const auto cwd = std::filesystem::current_path();
    const bool inside = cwd.filename() == "two_rod_intrusion" && cwd.parent_path().filename() == "out";
    o.out = inside ? "." : "out/two_rod_intrusion";
  }
}

std::string gap_tag(double g) { return gap_text(g); }

void write_force(const std::filesystem::path& file, const tr::RunResult& r) {
  CsvWriter w(file, {{"time", "s"}, {"depth", "m"}, {"force_z", "N"}, {"force_z_rod_a", "N"},
                     {"force_z_rod_b", "N"}, {"work", "J"}}, {false, false});
  for (const auto& q : r.samples) w.write_row({q.time, q.depth, q.force, q.force_a, q.force_b, q.work});
}

void write_half(const std::filesystem::path& dir, const std::string& tag, const tr::HalfDepthAnalysis& h,
                double ymid, double d) {
  {
    CsvWriter w(dir / ("force_pdf_" + tag + ".csv"),
                {{"fn_over_mean_lo", ""}, {"fn_over_mean_hi", ""}, {"pdf", ""}, {"count", ""}}, {false, false});
    const auto& hist = h.pdf.histogram;
    for (std::size_t k = 0; k < hist.bins(); ++k)
      w.write_row({hist.edges[k], hist.edges[k + 1], hist.density[k], static_cast<double>(hist.counts[k])});
  }
  {
    CsvWriter w(dir / ("velocity_profile_" + tag + ".csv"),
                {{"y", "m"}, {"y_minus_centre_over_d", ""}, {"v_y", "m/s"}, {"v_y_std", "m/s"}, {"v_z", "m/s"},
                 {"v_z_std", "m/s"}, {"count", ""}},
                {false, false});
    for (std::size_t k = 0; k < h.v_y.bins(); ++k)
      w.write_row({h.v_y.centre[k], (h.v_y.centre[k] - ymid) / d, h.v_y.mean[k], h.v_y.stddev[k], h.v_z.mean[k],
                   h.v_z.stddev[k], static_cast<double>(h.v_y.count[k])});
  }
  {
    CsvWriter w(dir / ("strain_rate_" + tag + ".csv"),
                {{"y", "m"}, {"z", "m"}, {"strain_rate", "1/s"}, {"v_y", "m/s"}, {"v_z", "m/s"}}, {false, false});
    for (const auto& n : h.strain) w.write_row({n.y, n.z, n.strain_rate, n.v_y, n.v_z});
  }
}

// Binned F(z): the mean force in depth bins of `bin` from 0 to z_f (the raw record has one
// sample per step, 16 000 per run; the bins keep the committed files small).
void write_force_binned(const std::filesystem::path& file, const tr::RunResult& r, double z_f, double bin) {
  const auto n = static_cast<std::size_t>(std::llround(z_f / bin));
  std::vector<double> sum(n, 0.0);
  std::vector<int> cnt(n, 0);
  for (const auto& q : r.samples) {
    if (q.depth < 0.0 || q.depth >= z_f) continue;
    const auto k = std::min(n - 1, static_cast<std::size_t>(q.depth / bin));
    sum[k] += q.force;
    ++cnt[k];
  }
  CsvWriter w(file, {{"depth", "m"}, {"force_z", "N"}}, {false, false});
  for (std::size_t k = 0; k < n; ++k)
    if (cnt[k] > 0) w.write_row({(k + 0.5) * bin, sum[k] / cnt[k]});
}

// The paper-scale study: every (bed, gap) case in gap-major order, so that each finished gap
// has its whole ensemble; a case whose result file exists is read back instead of run.
int run_study(Options o) {
  namespace fs = std::filesystem;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&]() { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const fs::path out = o.out;
  const fs::path results = o.results.empty() ? out / "results" / o.study : fs::path(o.results);
  fs::create_directories(results / "runs");
  {
    // The contact law of every result here (scene.hpp: a build may choose another): written
    // with the first case, and a build of another law refuses the directory.
    const fs::path law_file = results / "law.txt";
    const std::string law = tr::Law::signature();
    if (std::ifstream in(law_file); in) {
      std::string had;
      std::getline(in, had);
      if (had != law)
        throw std::runtime_error("the results in " + results.string() + " were computed with the law " + had +
                                 "; this build is " + law + " (use another --results directory)");
    } else {
      tr::study_detail::write_atomically(law_file, law + "\n");
    }
  }
  const double d = o.bed.diameter;
  const std::string shape = tr::shape_name(o.rod.shape);
  auto log = [&](const std::string& s) {
    if (!o.quiet) std::cerr << "[two_rod study " << o.study << " " << static_cast<int>(elapsed()) << " s] " << s << "\n";
  };
  std::cout << "two_rod_intrusion study '" << o.study << "': d = " << d << " m, rho = " << o.bed.density
            << " kg/m^3, rods " << shape << " " << o.rod.width << " x " << o.rod.length << " m, depth " << o.rod.depth
            << " m, box " << o.bed.length_x << " x " << o.bed.length_y << " m filled to " << o.bed.fill_height
            << " m, dt = " << o.bed.dt << " s, beds poured with mu = " << o.bed.friction_while_pouring()
            << " at dt = " << o.bed.dt_while_pouring() << " s; results in " << fs::absolute(results).lexically_normal().string()
            << std::endl;
  struct Case { int seed; double gap; };
  std::vector<Case> todo;
  std::vector<double> order;
  if (o.single) order.push_back(-1.0);
  order.insert(order.end(), o.gaps.begin(), o.gaps.end());
  for (double g : order)
    for (double k : o.seeds) todo.push_back({static_cast<int>(k), g});
  std::vector<tr::CaseResult> done;
  std::size_t ran = 0, skipped = 0;
  double particle_steps_done = 0.0, seconds_running = 0.0;
  for (std::size_t i = 0; i < todo.size(); ++i) {
    const auto [seed, g] = todo[i];
    const std::string stem = tr::case_stem(shape, seed, g);
    const fs::path file = results / "runs" / (stem + ".csv");
    if (auto c = tr::read_case(file)) {
      done.push_back(*c);
      ++skipped;
      continue;
    }
    if (o.aggregate_only) continue;
    tr::BedParams bed = o.bed;
    bed.seed = static_cast<std::uint64_t>(seed);
    tr::RunOptions ro;
    ro.analyse_half_depth = o.analysis;
    ro.progress = o.quiet ? granule::io::ProgressMode::Off : granule::io::ProgressMode::Auto;
    ro.label = stem;
    const int rods = g < 0.0 ? 1 : 2;
    const double gap = g < 0.0 ? 0.0 : g * d;
    log("case " + std::to_string(i + 1) + "/" + std::to_string(todo.size()) + ": " + stem);
    const tr::LoadedBed lb = tr::load_or_prepare_bed(bed, out, log);
    const tr::RunResult r = tr::run_intrusion(bed, o.rod, rods, gap, out, ro, log);
    tr::CaseResult c;
    c.shape = shape;
    c.seed = seed;
    c.gap_over_d = g;
    c.work = r.work;
    c.body_work = r.body_work;
    c.peak_force = r.peak_force;
    c.slope = tr::force_slope(r.samples, 0.2 * o.rod.depth, o.rod.depth);
    c.very_strong = static_cast<double>(r.half.very_strong);
    c.contacts = static_cast<double>(r.half.contacts);
    c.mean_fn = r.half.pdf.mean_fn;
    c.particles = static_cast<double>(lb.info.particles);
    c.packing = lb.info.packing_fraction;
    c.surface = lb.info.surface;
    c.wall_time = r.wall_seconds;
    c.ns_per_particle_step = 1e9 * r.wall_seconds / (static_cast<double>(r.steps) * c.particles);
    c.prov = tr::provenance_now();
    // Side files first, the case file last: its presence marks the case as done.
    write_force_binned(results / "runs" / ("force_" + stem + ".csv"), r, o.rod.depth, 1e-3);
    if (o.analysis && r.half.done) {
      const auto ys = tr::rod_centres_y(bed, o.rod, rods, gap);
      const double ymid = 0.5 * (ys.front() + ys.back());
      {
        CsvWriter w(results / "runs" / ("velocity_" + stem + ".csv"),
                    {{"y_minus_centre_over_d", ""}, {"v_y", "m/s"}, {"v_z", "m/s"}, {"count", ""}}, {false, false});
        for (std::size_t k = 0; k < r.half.v_y.bins(); ++k)
          w.write_row({(r.half.v_y.centre[k] - ymid) / d, r.half.v_y.mean[k], r.half.v_z.mean[k],
                       static_cast<double>(r.half.v_y.count[k])});
      }
      const bool field = seed == static_cast<int>(o.seeds.front()) &&
                         std::find(o.field_gaps.begin(), o.field_gaps.end(), g) != o.field_gaps.end();
      if (field) {
        fs::create_directories(results / "fields");
        CsvWriter w(results / "fields" / ("strain_rate_" + stem + ".csv"),
                    {{"y_minus_centre_over_d", ""}, {"z_minus_rod_bottom_over_d", ""}, {"strain_rate", "1/s"}},
                    {false, false});
        for (const auto& n : r.half.strain)
          if (std::isfinite(n.strain_rate) && n.z - r.half.rod_bottom <= 6.0 * d)
            w.write_row({(n.y - ymid) / d, (n.z - r.half.rod_bottom) / d, n.strain_rate});
      }
    }
    tr::write_case(file, c);
    done.push_back(c);
    ++ran;
    particle_steps_done += static_cast<double>(r.steps) * c.particles;
    seconds_running += r.wall_seconds;
    const double per_case = elapsed() / static_cast<double>(ran);
    const std::size_t left = todo.size() - i - 1;
    std::printf("%-24s W = %.5g J, very strong %g, %.0f s (%.1f ns/particle-step) | %zu/%zu done | ETA %s\n",
                stem.c_str(), c.work, c.very_strong, c.wall_time, c.ns_per_particle_step, i + 1, todo.size(),
                granule::io::ProgressReporter::format_duration(per_case * static_cast<double>(left)).c_str());
    std::fflush(stdout);
  }
  // Aggregate over the beds.
  const auto stats = tr::gap_stats(done, o.gaps);
  const tr::PeakStats peak = tr::peak_stats(done, o.gaps);
  const tr::Provenance prov = tr::provenance_now();
  {
    std::ostringstream t;
    t << "shape,gap_over_d,beds,work_mean [J],work_se [J],work_over_two_single,very_strong_mean,very_strong_se,"
         "slope_mean [N/m]\n";
    for (const auto& st : stats) {
      char buf[256];
      std::snprintf(buf, sizeof(buf), "%s,%g,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", shape.c_str(), st.gap_over_d, st.beds,
                    st.work_mean, st.work_se, st.work_mean / peak.single_two, st.very_strong_mean, st.very_strong_se,
                    st.slope_mean);
      t << buf;
    }
    tr::study_detail::write_atomically(results / ("work_vs_gap_" + shape + ".csv"), t.str());
  }
  {
    std::ostringstream t;
    std::string per_bed;
    for (double g : peak.peak_per_bed) per_bed += (per_bed.empty() ? "" : " ") + tr::study_detail::num(g);
    char buf[512];
    std::snprintf(buf, sizeof(buf),
                  "%s,%d,%g,%.4g,%g,%g,\"%s\",%.6g,%.6g,%.5g,%.5g,%.5g,%.6g,", shape.c_str(), peak.beds, peak.gap,
                  peak.gap_parabola, peak.gap_lo, peak.gap_hi, per_bed.c_str(), peak.work, peak.plateau, peak.ratio,
                  peak.ratio_lo, peak.ratio_hi, peak.single_two);
    t << "shape,beds,peak_gap_over_d,peak_gap_parabola,peak_gap_p16,peak_gap_p84,peak_gap_per_bed,work_peak [J],"
         "work_plateau [J],peak_over_plateau,peak_over_plateau_p16,peak_over_plateau_p84,two_single_work [J],commit,"
         "date,machine\n"
      << buf << granule::examples::csv_quoted(prov.commit) << "," << granule::examples::csv_quoted(prov.date) << ","
      << granule::examples::csv_quoted(prov.machine) << "\n";
    tr::study_detail::write_atomically(results / ("peak_" + shape + ".csv"), t.str());
  }
  std::printf("\n%8s %5s %12s %12s %14s\n", "s/d", "beds", "W mean [J]", "W s.e. [J]", "very strong");
  for (const auto& st : stats)
    std::printf("%8g %5d %12.5g %12.3g %9.1f +- %.1f\n", st.gap_over_d, st.beds, st.work_mean, st.work_se,
                st.very_strong_mean, st.very_strong_se);
  std::printf("peak (%d complete beds): s/d = %g (parabola %.2f, bootstrap 16-84 %%: %g-%g), W* = %.4g J, "
              "plateau (s/d >= 11) %.4g J, peak/plateau = %.3f (%.3f-%.3f), 2 W_single = %.4g J\n",
              peak.beds, peak.gap, peak.gap_parabola, peak.gap_lo, peak.gap_hi, peak.work, peak.plateau, peak.ratio,
              peak.ratio_lo, peak.ratio_hi, peak.single_two);
  std::printf("%zu cases run, %zu read back; %.0f s of wall time\n", ran, skipped, elapsed());
  if (seconds_running > 0.0)
    std::printf("rate: %.1f ns per particle-step with %d threads\n", 1e9 * seconds_running / particle_steps_done,
                o.threads);
  return 0;
}

// One sweep of the gaps (no --study).
int run_sweep(const Options& o) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&]() { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::filesystem::path out = o.out;
  std::filesystem::create_directories(out);
  auto log = [&](const std::string& s) {
    if (!o.quiet) std::cerr << "[two_rod " << static_cast<int>(elapsed()) << " s] " << s << "\n";
  };
  const double d = o.bed.diameter;
  const std::string shape = tr::shape_name(o.rod.shape);
  std::cout << "two_rod_intrusion (" << (o.paper ? "paper" : "quick") << " mode): d = " << d << " m, rods "
            << shape << " " << o.rod.width << " x " << o.rod.length << " m, U0 = " << o.rod.speed
            << " m/s, depth " << o.rod.depth << " m, box " << o.bed.length_x << " x " << o.bed.length_y
            << " m filled to " << o.bed.fill_height << " m, dt = " << o.bed.dt << " s, mu = " << o.bed.friction
            << ", output in " << std::filesystem::absolute(out).lexically_normal().string() << "\n";

  // The bed (poured once, then read from the cache by every run).
  const tr::LoadedBed bed = tr::load_or_prepare_bed(o.bed, out, log);
  std::cout << "bed: " << bed.info.particles << " particles, surface " << bed.info.surface
            << " m, packing fraction " << bed.info.packing_fraction << ", "
            << (bed.info.built ? "poured now" : "read from ") << (bed.info.built ? "" : bed.info.checkpoint.string())
            << " (simulated settling " << bed.info.settle_time << " s), critical dt "
            << bed.sim->critical_time_step() << " s\n";
  {
    CsvWriter w(out / "scene.csv",
                {{"particles", ""}, {"diameter", "m"}, {"surface", "m"}, {"packing_fraction", ""},
                 {"settle_time", "s"}, {"length_x", "m"}, {"length_y", "m"}, {"fill_height", "m"}, {"dt", "s"},
                 {"rayleigh_time", "s"}, {"rod_width", "m"}, {"rod_length", "m"}, {"speed", "m/s"},
                 {"depth", "m"}, {"friction", ""}},
                {false, false});
    w.write_row({static_cast<double>(bed.info.particles), d, bed.info.surface, bed.info.packing_fraction,
                 bed.info.settle_time, o.bed.length_x, o.bed.length_y, o.bed.fill_height, o.bed.dt,
                 bed.sim->critical_time_step(), o.rod.width, o.rod.length, o.rod.speed, o.rod.depth,
                 o.bed.friction});
  }

  auto run = [&](int rods, double g) {
    tr::RunOptions ro;
    ro.analyse_half_depth = o.analysis;
    ro.progress = o.quiet ? granule::io::ProgressMode::Off : granule::io::ProgressMode::Auto;
    const std::string tag = rods == 1 ? shape + "_single" : shape + "_s" + gap_tag(g);
    ro.label = tag;
    ro.vtk_every = o.vtk_every;
    ro.vtk_dir = out / "vtk" / tag;
    log("run " + tag);
    tr::RunResult r = tr::run_intrusion(o.bed, o.rod, rods, g * d, out, ro, log);
    write_force(out / ("force_" + tag + ".csv"), r);
    if (o.analysis && r.half.done) {
      const auto ys = tr::rod_centres_y(o.bed, o.rod, rods, g * d);
      write_half(out, tag, r.half, 0.5 * (ys.front() + ys.back()), d);
    }
    return r;
  };

  double w_single = std::nan("");
  if (o.single) {
    const tr::RunResult r = run(1, 0.0);
    w_single = r.work;
    CsvWriter w(out / ("single_rod_" + shape + ".csv"),
                {{"work", "J"}, {"body_work", "J"}, {"peak_force", "N"}, {"slope", "N/m"}, {"very_strong", ""},
                 {"pair_contacts", ""}, {"mean_fn", "N"}, {"wall_time", "s"}},
                {false, false});
    w.write_row({r.work, r.body_work, r.peak_force, tr::force_slope(r.samples, 0.2 * o.rod.depth, o.rod.depth),
                 static_cast<double>(r.half.very_strong), static_cast<double>(r.half.contacts), r.half.pdf.mean_fn,
                 r.wall_seconds});
    std::cout << "single rod: W = " << r.work << " J (body work " << r.body_work << " J), " << r.wall_seconds
              << " s\n";
  }

  std::vector<double> works;
  CsvWriter table(out / ("work_vs_gap_" + shape + ".csv"),
                  {{"gap_over_d", ""}, {"gap", "m"}, {"work", "J"}, {"body_work", "J"}, {"work_over_peak", ""},
                   {"work_over_two_single", ""}, {"very_strong", ""}, {"pair_contacts", ""}, {"mean_fn", "N"},
                   {"peak_force", "N"}, {"slope", "N/m"}, {"wall_time", "s"}},
                  {true, false});
  std::vector<tr::RunResult> results;
  std::printf("%8s %12s %12s %12s %10s\n", "s/d", "W [J]", "W_body [J]", "very_strong", "time [s]");
  for (double g : o.gaps) {
    results.push_back(run(2, g));
    const auto& r = results.back();
    works.push_back(r.work);
    std::printf("%8g %12.5g %12.5g %12zu %10.1f\n", g, r.work, r.body_work, r.half.very_strong, r.wall_seconds);
    std::fflush(stdout);
  }
  const double w_max = *std::max_element(works.begin(), works.end());
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& r = results[k];
    table.write_row({o.gaps[k], o.gaps[k] * d, r.work, r.body_work, r.work / w_max, r.work / (2.0 * w_single),
                     static_cast<double>(r.half.very_strong), static_cast<double>(r.half.contacts),
                     r.half.pdf.mean_fn, r.peak_force, tr::force_slope(r.samples, 0.2 * o.rod.depth, o.rod.depth),
                     r.wall_seconds});
  }
  const tr::PeakSummary peak = tr::find_peak(o.gaps, works);
  {
    CsvWriter w(out / ("peak_" + shape + ".csv"),
                {{"gap_over_d_peak", ""}, {"work_peak", "J"}, {"work_largest_gap", "J"}, {"peak_over_largest_gap", ""},
                 {"two_single_work", "J"}, {"peak_over_two_single", ""}},
                {false, false});
    w.write_row({peak.gap_over_d, peak.work, peak.plateau_work, peak.ratio, 2.0 * w_single, peak.work / (2.0 * w_single)});
  }
  std::cout << "peak: W* = " << peak.work << " J at s/d = " << peak.gap_over_d << ", " << 100.0 * (peak.ratio - 1.0)
            << " % above W at the largest gap";
  if (o.single) std::cout << ", W*/(2 W_single) = " << peak.work / (2.0 * w_single);
  std::cout << "\ntotal wall time " << elapsed() << " s\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  set_quick(o);
  set_mode(argc, argv, o);
  CLI::App app("", "two_rod_intrusion");
  cli::configure(app);
  add_options(app, o);
  return cli::run(app, argc, argv, [&] {
    check_options(o);
#ifdef _OPENMP
    omp_set_num_threads(o.threads);
#endif
    return o.study.empty() ? run_sweep(o) : run_study(o);
  });
}
