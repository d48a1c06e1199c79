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
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/io/csv.hpp>

#include "scene.hpp"

namespace tr = granule::examples::two_rod;
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
  o.bed.dt = 5e-6;
  // 5e-6 s is 0.31 x the Rayleigh time of a 2 mm grain (0.2 is the engine's default limit);
  // it is the paper's value and resolves a 1 m/s Hertz collision with ~40 steps (README.md).
  o.bed.allow_large_time_step = true;
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

void usage() {
  std::cout <<
R"(usage: two_rod_intrusion [options]

Two parallel rods (axes along x, surface-to-surface gap s along y) pushed down at constant
speed into a poured bed of spheres (Pravin et al. 2020). For every gap of the sweep it writes
F(z), the net work W = integral F dz, and at half depth the normal-force PDF, the number of
very strong forces (f_n > 6 <f_n>), V_y and V_z profiles below the rods and a strain-rate map.
The bed is poured once and cached as bed_<hash>.ckpt in the output directory.

modes
  (none)                 quick mode, a few minutes on 2 cores: d = 4 mm, 10 x 12 cm box
                         filled to 5 cm, rods 5 mm x 5 cm to 2.5 cm depth, s/d = 0,1,2,3,5,8
  --paper                paper 000 table I: d = 2 mm, 25 x 25 cm box filled to 10 cm,
                         depth 8 cm, dt = 5e-6 s, s/d = 0..20 (~9e5 grains: days of CPU)
                         (given first, later options override its values)
options (units in brackets)
  --d D                  particle diameter [m]
  --width D              rod width or diameter [m]                     (default 0.005)
  --length L             rod length [m]                                (default 0.05)
  --gap-list a,b,...     gaps s/d to sweep [-]
  --shape square|cylinder  rod cross-section                           (default square)
  --depth Z              final depth of the rods' bottom [m]
  --speed U              intrusion speed [m/s]                         (default 1)
  --mu MU                friction coefficient of grains and walls [-]  (default 0.5)
  --dt DT                time step [s]
  --box LX,LY,H          container length (along rods), width, fill height [m]
  --seed N               seed of the pouring jitter [-]                (default 1)
  --no-single            skip the single-rod reference run
  --no-analysis          skip the half-depth analysis (PDF, profiles, strain rate)
  --threads N            OpenMP threads [-]                            (default 2)
  --out DIR              output directory (default out/two_rod_intrusion, or . when the
                         working directory already is out/two_rod_intrusion)
  --vtk-every N          write particle and rod VTK frames every N steps [-] (0: none)
  --quiet                no progress on stderr
  --help                 this text
)";
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(std::stod(item));
  return v;
}

double number(const std::string& opt, const std::string& text) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size()) throw granule::InvalidParameter(opt + " expects a number, got '" + text + "'");
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  set_quick(o);
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--paper") {
      set_paper(o);
      o.paper = true;
    }
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw granule::InvalidParameter(a + " needs a value");
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      usage();
      std::exit(0);
    } else if (a == "--paper") {
    } else if (a == "--d") {
      o.bed.diameter = number(a, value());
    } else if (a == "--width") {
      o.rod.width = number(a, value());
    } else if (a == "--length") {
      o.rod.length = number(a, value());
    } else if (a == "--gap-list") {
      o.gaps = parse_list(value());
    } else if (a == "--shape") {
      const std::string s = value();
      if (s == "square") {
        o.rod.shape = tr::RodShape::Square;
      } else if (s == "cylinder") {
        o.rod.shape = tr::RodShape::Cylinder;
      } else {
        throw granule::InvalidParameter("--shape is '" + s + "', valid: square, cylinder");
      }
    } else if (a == "--depth") {
      o.rod.depth = number(a, value());
    } else if (a == "--speed") {
      o.rod.speed = number(a, value());
    } else if (a == "--mu") {
      o.bed.friction = number(a, value());
    } else if (a == "--dt") {
      o.bed.dt = number(a, value());
    } else if (a == "--box") {
      const auto v = parse_list(value());
      if (v.size() != 3) throw granule::InvalidParameter("--box expects LX,LY,H [m]");
      o.bed.length_x = v[0];
      o.bed.length_y = v[1];
      o.bed.fill_height = v[2];
    } else if (a == "--seed") {
      o.bed.seed = static_cast<std::uint64_t>(number(a, value()));
    } else if (a == "--no-single") {
      o.single = false;
    } else if (a == "--no-analysis") {
      o.analysis = false;
    } else if (a == "--threads") {
      o.threads = static_cast<int>(number(a, value()));
    } else if (a == "--out") {
      o.out = value();
    } else if (a == "--vtk-every") {
      o.vtk_every = static_cast<std::uint64_t>(number(a, value()));
    } else if (a == "--quiet") {
      o.quiet = true;
    } else {
      throw granule::InvalidParameter("unknown option '" + a + "' (see --help)");
    }
  }
  if (o.gaps.empty()) throw granule::InvalidParameter("--gap-list is empty");
  for (double g : o.gaps)
    if (!(g >= 0.0)) throw granule::InvalidParameter("gaps s/d must be >= 0");
  if (o.threads < 1) throw granule::InvalidParameter("--threads must be >= 1");
  o.bed.validate();
  o.rod.validate(o.bed);
  if (o.out.empty()) {
    const auto cwd = std::filesystem::current_path();
    const bool inside = cwd.filename() == "two_rod_intrusion" && cwd.parent_path().filename() == "out";
    o.out = inside ? "." : "out/two_rod_intrusion";
  }
  return o;
}

std::string gap_tag(double g) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", g);
  return buf;
}

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

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
#ifdef _OPENMP
    omp_set_num_threads(o.threads);
#endif
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
  } catch (const std::exception& e) {
    std::cerr << "two_rod_intrusion: " << e.what() << "\n";
    return 1;
  }
}
