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
#include <sstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/io/csv.hpp>

#include "scene.hpp"

using namespace granule;
using namespace granule::examples::lunar_shock;

namespace {

void usage() {
  std::printf(
      "usage: lunar_shock_channel validation|channel [options]\n"
      "\n"
      "common:\n"
      "  --out DIR              output directory (out/lunar_shock_channel)\n"
      "  --threads N            OpenMP threads (2)\n"
      "\n"
      "validation (001 section 2.2: 5 x 5 grid, incident particle along the middle row):\n"
      "  --material steel|soft|both   table-1 species (both)\n"
      "  --velocities LIST      impact speeds v_im, comma separated [m/s]\n"
      "                         (1e-6,1e-5,1e-4,1e-3,1e-2,3e-2,0.1,0.3,1,3,10)\n"
      "  --preload F0           static force per contact along the rows [N];\n"
      "                         'paper' = the F0 whose chain sound speed 2R sqrt(k_lin/m) is table 1's\n"
      "                         c_0 (default), 0 = no pre-load (sonic vacuum)\n"
      "  --restitution E        coefficient of restitution e [-] (1: elastic)\n"
      "  --length N             particles along the struck row, striker included (6 = striker + 5)\n"
      "  --dt DT                time step [s] (0: the largest the engine's check allows)\n"
      "  --plateau-max V        plateau: mean c_w over v_im <= V [m/s] (1e-4, as 001)\n"
      "  --shock-min V          shock branch: power-law fit over v_im >= V [m/s] (1)\n"
      "\n"
      "channel (001 sections 2.3-2.9; quick defaults, --paper for the paper's sizes):\n"
      "  --paper                2 m x 20 cm x 2 cm channel, dt 1e-6 s, 1.5 s runs (~5e5 particles)\n"
      "  --length L             channel length along y [m] (0.25)\n"
      "  --depth H              fill height [m] (0.035)\n"
      "  --width W              periodic width along x [m] (0.02)\n"
      "  --packing loose|medium|compact   insertion flux of table 3 (loose)\n"
      "  --flux Q               insertion flux instead [particles/(s m^2)]\n"
      "  --pour-speed V         downward speed of inserted particles [m/s] (0.65; paper 0)\n"
      "  --drop H               insertion region bottom above the fill height [m] (0.02; paper 0.10)\n"
      "  --settle-time T        longest settling time [s] (1; paper 5)\n"
      "  --settle-force F       stop settling once the mean net force per particle is below F weights m g\n"
      "                         [-] (1e-3; paper 3e-7 = 1e-11 N; 0: settle the whole --settle-time)\n"
      "  --settle-speed V       ... and no particle faster than V [m/s] (1e-3; 0: no condition)\n"
      "  --settle-damping G     background damping of velocities and spins while settling [1/s] (0: none)\n"
      "  --zero-interval T      velocities zeroed this often while settling [s] (0.025; 0: never)\n"
      "  --seed S               insertion seed (1)\n"
      "  --vp LIST              piston speeds v_p, comma separated [m/s] (0.1,1,10)\n"
      "  --bender               S wave: sheet follows z = A sin(2 pi f t) for one period, A = v_p/(2 pi f)\n"
      "  --frequency F          bender frequency [Hz] (5e4)\n"
      "  --run-time T           simulated time after the impulse [s] (0: 2.5 L / 7 m/s)\n"
      "  --dt-shock DT          shock time step [s] (0: min(engine limit, dt-max, tau_c(v_p)/20, period/20))\n"
      "  --dt-prepare DT        pour and settle time step [s] (0: min(engine limit, dt-max); paper 1e-6)\n"
      "  --dt-max DT            cap on the automatic time steps [s] (1e-5; 0: none, the engine limit 3e-5)\n"
      "  --sample DT            sensor sampling interval [s] (2e-5)\n"
      "  --pre-record T         sensors record T before the impulse: initial level [s] (1e-3)\n"
      "  --sensor-time T        keep force series for T after the impulse [s] (0: whole run; paper 0.25)\n"
      "  --cw-window A,B        fit window for c_w along y [m] (0,0.08; paper 0,0.15)\n"
      "  --cp-window A,B        fit window for c_p along y [m] (0.12,0.2; paper 0.3,0.5)\n"
      "  --bed-dir DIR          cache of settled beds (OUT/beds)\n"
      "  --quiet                no progress lines on stderr\n");
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(std::stod(item));
  return v;
}

int run_validation(const std::vector<GridMaterial>& mats, const std::vector<double>& velocities, double preload,
                   bool preload_paper, double restitution, int length, double dt, double plateau_max,
                   double shock_min, const std::filesystem::path& out) {
  io::CsvWriter csv(out / "validation.csv",
                    {{"material", ""}, {"preload", "N"}, {"v_im", "m/s"}, {"c_w", "m/s"}, {"c_w_uncertainty", "m/s"},
                     {"c_w_over_c_w_1", ""}, {"dt", "s"}});
  io::CsvWriter summary(out / "validation_summary.csv",
                        {{"material", ""}, {"preload", "N"}, {"static_overlap", "m"}, {"c0_chain", "m/s"},
                         {"c0_measured", "m/s"}, {"plateau_spread", ""}, {"c0_paper", "m/s"},
                         {"shock_exponent", ""}, {"shock_exponent_uncertainty", ""}});
  int status = 0;
  for (std::size_t mi = 0; mi < mats.size(); ++mi) {
    const GridMaterial& gm = mats[mi];
    const ChainHertz hz(gm);
    GridOptions o;
    o.material = gm;
    o.preload = preload_paper ? hz.force_for_sound_speed(gm.paper_c0) : preload;
    o.restitution = restitution;
    o.length = length;
    o.dt = dt;
    std::printf("%s: R = %.2f mm, m = %.4g kg, pre-load F0 = %.4g N per contact (overlap %.4g m), chain c_0 = %.4g m/s\n",
                gm.name.c_str(), gm.radius * 1e3, hz.mass, o.preload, o.preload > 0 ? hz.overlap_pp(o.preload) : 0.0,
                o.preload > 0 ? hz.sound_speed(o.preload) : 0.0);
    std::vector<GridResult> rs;
    double c_ref = 0.0;
    for (double v : velocities) {
      rs.push_back(run_grid(o, v));
      if (std::abs(v - 1.0) < 1e-12) c_ref = rs.back().c_w;
    }
    std::vector<double> plateau, vs, cs;
    for (const auto& r : rs) {
      std::printf("  v_im = %9.3g m/s  c_w = %10.5g +- %8.3g m/s  (dt %.3g s, %llu steps)\n", r.v_im, r.c_w,
                  r.c_w_uncertainty, r.dt, static_cast<unsigned long long>(r.steps));
      csv.write_row({double(mi), o.preload, r.v_im, r.c_w, r.c_w_uncertainty, c_ref > 0 ? r.c_w / c_ref : NAN, r.dt});
      if (r.v_im <= plateau_max * (1 + 1e-9)) plateau.push_back(r.c_w);
      if (r.v_im >= shock_min * (1 - 1e-9)) {
        vs.push_back(r.v_im);
        cs.push_back(r.c_w);
      }
    }
    double c0 = NAN, spread = NAN, lo = 1e300, hi = -1e300, s = 0;
    for (double c : plateau) {
      s += c;
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    }
    if (!plateau.empty()) {
      c0 = s / plateau.size();
      spread = (hi - lo) / c0;
    }
    PowerLaw pl{NAN, NAN, NAN};
    if (vs.size() >= 3) pl = fit_power_law(vs, cs);
    const double c0_chain = o.preload > 0 ? hz.sound_speed(o.preload) : 0.0;
    std::printf("  plateau (v_im <= %g m/s): c_0 = %.5g m/s (spread %.2g %%), chain formula %.5g m/s, paper %.5g m/s\n",
                plateau_max, c0, 100 * spread, c0_chain, gm.paper_c0);
    std::printf("  shock branch (v_im >= %g m/s): c_w ~ v_im^%.4f +- %.4f (expected 1/5)\n", shock_min, pl.exponent,
                pl.exponent_uncertainty);
    if (o.preload > 0 && std::isfinite(c0)) {
      // c0 ~ F0^(1/6) in the acoustic limit: the pre-load whose measured plateau is the paper's.
      const double f_meas = o.preload * std::pow(gm.paper_c0 / c0, 6.0);
      std::printf("  pre-load giving the paper's c_0 with this measurement: F0 = %.4g N (overlap %.4g m, %.3g m g)\n",
                  f_meas, hz.overlap_pp(f_meas), f_meas / (hz.mass * 9.81));
    }
    summary.write_row({double(mi), o.preload, o.preload > 0 ? hz.overlap_pp(o.preload) : 0.0, c0_chain, c0, spread,
                       gm.paper_c0, pl.exponent, pl.exponent_uncertainty});
    if (!std::isfinite(pl.exponent)) status = 1;
  }
  std::printf("material index: 0..%zu in the order given; output in %s\n", mats.size() - 1, out.string().c_str());
  return status;
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
  std::printf("  bed depth %.1f particle diameters; checkpoint %s\n", o.depth / (2 * o.radius), bed_path(o).string().c_str());
  if (!bed.settle_history.empty()) {
    io::CsvWriter sc(out / ("bed_settle_" + std::string(packing_name(o.packing)) + ".csv"),
                     {{"time", "s"}, {"force_mean", "m g"}, {"force_median", "m g"}, {"force_p99", "m g"},
                      {"ke_per_particle", "J"}, {"max_speed", "m/s"}, {"max_spin", "rad/s"}});
    for (const auto& h : bed.settle_history)
      sc.write_row({h.time, h.force_mean, h.force_median, h.force_p99, h.ke_per_particle, h.max_speed, h.max_spin});
  }
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
  for (double v : sorted) {
    const ShockResult r = run_shock(o, v);
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
  std::printf("sound speed c_0 (mean c_w over v_p <= 0.1 m/s, %d run(s)) = %.3f m/s; paper table 6 (%s): %.2f m/s\n",
              c0_n, c0, packing_name(o.packing), c0_paper);
  std::printf("  c ~ delta_0^(1/4): paper c_0 x (%.3g / %.3g um)^(1/4) = %.3f m/s; eq. 7 x sqrt(3)/2 with this bed's"
              " delta_0: %.3f m/s (with the paper's delta_0: %.3f m/s)\n",
              bed.mean_overlap * 1e6, d0_paper * 1e6, c0_paper * std::pow(bed.mean_overlap / d0_paper, 0.25),
              eq7_sound_speed(bed.mean_overlap, o.radius, mass, mat.youngs_modulus, mat.poisson_ratio),
              eq7_sound_speed(d0_paper, o.radius, mass, mat.youngs_modulus, mat.poisson_ratio));
  std::printf("output in %s\n", out.string().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    usage();
    return argc < 2 ? 2 : 0;
  }
  const std::string mode = argv[1];
  if (mode != "validation" && mode != "channel") {
    std::fprintf(stderr, "unknown sub-command '%s'\n", mode.c_str());
    usage();
    return 2;
  }
  std::filesystem::path out = "out/lunar_shock_channel";
  int threads = 2;
  // validation
  std::string material = "both";
  std::vector<double> velocities = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 3e-2, 0.1, 0.3, 1, 3, 10};
  double preload = 0.0, restitution = 1.0, dt = 0.0, plateau_max = 1e-4, shock_min = 1.0;
  bool preload_paper = true;
  int length = 6;
  // channel
  ChannelOptions co;
  bool paper = false;
  std::vector<double> vps = {0.1, 1.0, 10.0};
  std::vector<std::pair<std::string, std::string>> channel_args;
  std::string bed_dir;
  try {
    for (int a = 2; a < argc; ++a) {
      const std::string arg = argv[a];
      auto next = [&]() -> std::string {
        if (a + 1 >= argc) throw InvalidParameter(arg + " needs a value");
        return argv[++a];
      };
      if (arg == "--help" || arg == "-h") {
        usage();
        return 0;
      } else if (arg == "--out") out = next();
      else if (arg == "--threads") threads = std::stoi(next());
      else if (arg == "--material") material = next();
      else if (arg == "--velocities") velocities = parse_list(next());
      else if (arg == "--preload") {
        const std::string v = next();
        preload_paper = v == "paper";
        if (!preload_paper) preload = std::stod(v);
      } else if (arg == "--restitution") restitution = std::stod(next());
      else if (arg == "--length" && mode == "validation") length = std::stoi(next());
      else if (arg == "--dt") dt = std::stod(next());
      else if (arg == "--plateau-max") plateau_max = std::stod(next());
      else if (arg == "--shock-min") shock_min = std::stod(next());
      else if (arg == "--paper") paper = true;
      else if (arg == "--bender") co.bender = true;
      else if (arg == "--quiet") co.progress = false;
      else if (arg == "--vp") vps = parse_list(next());
      else if (arg == "--bed-dir") bed_dir = next();
      else if (arg == "--length" || arg == "--depth" || arg == "--width" || arg == "--packing" || arg == "--flux" ||
               arg == "--pour-speed" || arg == "--drop" || arg == "--settle-time" || arg == "--seed" ||
               arg == "--settle-force" || arg == "--settle-speed" || arg == "--settle-damping" || arg == "--zero-interval" ||
               arg == "--dt-prepare" || arg == "--dt-max" ||
               arg == "--frequency" || arg == "--run-time" || arg == "--dt-shock" || arg == "--sample" ||
               arg == "--cw-window" || arg == "--cp-window" || arg == "--pre-record" || arg == "--sensor-time")
        channel_args.emplace_back(arg, next());
      else {
        std::fprintf(stderr, "unknown option '%s'\n", arg.c_str());
        usage();
        return 2;
      }
    }
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    std::filesystem::create_directories(out);
    if (mode == "validation") {
      std::vector<GridMaterial> mats;
      if (material == "steel" || material == "both") mats.push_back(steel());
      if (material == "soft" || material == "both") mats.push_back(soft());
      if (mats.empty()) throw InvalidParameter("--material must be steel, soft or both, not '" + material + "'");
      return run_validation(mats, velocities, preload, preload_paper, restitution, length, dt, plateau_max, shock_min,
                            out);
    }
    if (paper) {
      const bool bender = co.bender, progress = co.progress;
      co = ChannelOptions::paper();
      co.bender = bender;
      co.progress = progress;
    }
    for (const auto& [k, v] : channel_args) {
      if (k == "--length") co.length = std::stod(v);
      else if (k == "--depth") co.depth = std::stod(v);
      else if (k == "--width") co.width = std::stod(v);
      else if (k == "--packing") {
        if (v == "loose") co.packing = Packing::Loose;
        else if (v == "medium") co.packing = Packing::Medium;
        else if (v == "compact") co.packing = Packing::Compact;
        else throw InvalidParameter("--packing must be loose, medium or compact, not '" + v + "'");
      } else if (k == "--flux") co.insertion_flux = std::stod(v);
      else if (k == "--pour-speed") co.pour_speed = std::stod(v);
      else if (k == "--drop") co.drop_height = std::stod(v);
      else if (k == "--settle-time") co.settle_time = std::stod(v);
      else if (k == "--settle-force") co.settle_force = std::stod(v);
      else if (k == "--settle-speed") co.settle_speed = std::stod(v);
      else if (k == "--settle-damping") co.settle_damping = std::stod(v);
      else if (k == "--zero-interval") co.zero_interval = std::stod(v);
      else if (k == "--seed") co.seed = std::stoull(v);
      else if (k == "--frequency") co.bender_frequency = std::stod(v);
      else if (k == "--run-time") co.run_time = std::stod(v);
      else if (k == "--dt-shock") co.dt_shock = std::stod(v);
      else if (k == "--dt-prepare") co.dt_prepare = std::stod(v);
      else if (k == "--dt-max") co.dt_max = std::stod(v);
      else if (k == "--sample") co.sample_interval = std::stod(v);
      else if (k == "--pre-record") co.pre_record = std::stod(v);
      else if (k == "--sensor-time") co.sensor_time = std::stod(v);
      else if (k == "--cw-window" || k == "--cp-window") {
        const auto w = parse_list(v);
        if (w.size() != 2) throw InvalidParameter(k + " needs two numbers A,B");
        (k == "--cw-window" ? co.cw_from : co.cp_from) = w[0];
        (k == "--cw-window" ? co.cw_to : co.cp_to) = w[1];
      }
    }
    co.bed_dir = bed_dir.empty() ? out / "beds" : std::filesystem::path(bed_dir);
    return run_channel(co, vps, out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
