#pragma once
// Result files of intruder_pull_out_2d and its convergence study (issue 27).
//
// Every CSV file this example writes starts with one comment line naming the run and where the
// result came from (commit, date, machine, OpenMP threads), then a header with units in
// brackets. summary.csv is a long table, quantity,value,unit,description: every statistic of
// statistics.hpp, the run's parameters (with the stiffness number kappa and the inertial number
// I), its cost, and the provenance.
//
// The study: a list of cases (study_cases), one directory per case under the results
// directory with its summary, the pull binned per millimetre of travel, the drag's spectrum in
// third-octave bands and two coarse-grained velocity maps on a grid of 1.5 d (the kernel's
// width: the field holds nothing finer). A case's summary.csv is written last, through a
// temporary file and a rename, so it exists whole or not at all and marks the case as done: a
// rerun skips it. Settled beds are cached as checkpoints (scene.hpp, save_bed) in the output
// directory, so the pulls at several speeds of one stiffness start from the same bed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "statistics.hpp"

#include "../common/csv_fields.hpp"
#include "../common/provenance.hpp"

namespace granule::examples::pull_out {

using examples::Provenance;
using examples::provenance_now;

namespace study_detail {
/// Writes `text` to `file` through a temporary and a rename: the file exists whole or not at all.
inline void write_atomically(const std::filesystem::path& file, const std::string& text) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
    if (!o) throw IoError("intruder_pull_out_2d: cannot open '" + tmp.string() + "' for writing");
    o << text;
    o.flush();
    if (!o) throw IoError("intruder_pull_out_2d: writing '" + tmp.string() + "' failed");
  }
  std::filesystem::rename(tmp, file);
}

inline std::string num(double v, int digits = 6) {
  if (std::isnan(v)) return "nan";
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
  return buf;
}

}  // namespace study_detail

/// "# intruder_pull_out_2d <what>: commit ..., date ..., machine ..."
inline std::string provenance_line(const std::string& what, const Provenance& p) {
  return "# intruder_pull_out_2d " + what + ": commit " + p.commit + "; date " + p.date + "; machine " + p.machine +
         "\n";
}

/// A numeric table with the provenance line, written atomically; `digits`: significant digits
/// per column (the last value for the remaining columns).
inline void write_table(const std::filesystem::path& file, const std::string& comment,
                        const std::vector<std::string>& columns, const std::vector<std::vector<double>>& rows,
                        const std::vector<int>& digits) {
  std::ostringstream s;
  s << comment;
  for (std::size_t k = 0; k < columns.size(); ++k) s << (k ? "," : "") << columns[k];
  s << "\n";
  for (const auto& r : rows) {
    for (std::size_t k = 0; k < r.size(); ++k)
      s << (k ? "," : "") << study_detail::num(r[k], digits[std::min(k, digits.size() - 1)]);
    s << "\n";
  }
  study_detail::write_atomically(file, s.str());
}
inline void write_table(const std::filesystem::path& file, const std::string& comment,
                        const std::vector<std::string>& columns, const std::vector<std::vector<double>>& rows,
                        int digits = 6) {
  write_table(file, comment, columns, rows, std::vector<int>{digits});
}

/// One line of summary.csv: a number, or a text when `text` is not empty.
struct SummaryRow {
  std::string quantity;
  double value = 0.0;
  std::string unit;
  std::string description;
  std::string text;
};

/// Everything a run reports (file comment).
/// `prov`: where the run came from; `analysis`: where these statistics were computed (the same
/// for a fresh run; another commit for a run analysed again by --restat).
inline std::vector<SummaryRow> summary_rows(const PullScene& s, const PullResult& r, const DragStatistics& st,
                                            const Provenance& prov, const Provenance& analysis) {
  const PullParams& p = s.params;
  std::vector<SummaryRow> v;
  auto add = [&](const std::string& q, double x, const std::string& unit, const std::string& what) {
    v.push_back({q, x, unit, what, ""});
  };
  // Parameters.
  add("cell_width", p.cell_width, "m", "W");
  add("bed_height_target", p.bed_height, "m", "target bed height H (disks: 1600 per 100 mm x 150 mm)");
  add("disks", static_cast<double>(s.particles), "", "number of disks");
  add("thickness", p.thickness, "m", "disk thickness t");
  add("youngs_modulus", p.youngs_modulus, "Pa", "E (k_n = E d)");
  add("normal_stiffness", normal_stiffness(p), "N/m", "k_n");
  add("pull_velocity", p.pull_velocity, "m/s", "V");
  add("kappa", stiffness_number(p), "", "stiffness number k_n / (rho phi g H t), phi = 0.82");
  add("inertial_number", inertial_number(p), "", "I = V / sqrt(phi g H), phi = 0.82");
  add("dt_pull", r.dt, "s", "time step of the pull");
  add("dt_engine", engine_dt(p), "s", "0.2 x linear critical time of the lightest pair (filling)");
  add("dt_critical_paper", paper_critical_time(p), "s", "002's dt_c = sqrt(m_min / k_n)");
  add("dt_pull_over_dt_c", r.dt / paper_critical_time(p), "", "002: 1/60");
  add("sample_travel", p.sample_travel, "m", "intruder travel per drag sample");
  add("cg_width", p.cg_width * p.mean_diameter, "m", "coarse-graining kernel width w (cutoff 4 w)");
  add("seed", static_cast<double>(p.seed), "", "insertion seed");
  // Bed.
  add("mean_surface", s.packing.surface, "m", "mean surface height of the settled bed");
  add("top_surface", s.bed_height, "m", "mean top of the 5 highest disks");
  add("phi_interior", s.packing.interior, "", "packing fraction 2 d from walls and floor, 3 d below the surface");
  add("phi_interior_min", s.packing.interior_min, "", "lowest interior slab (~3 d)");
  add("phi_interior_max", s.packing.interior_max, "", "highest interior slab");
  add("phi_interior_slabs", static_cast<double>(s.packing.slabs), "", "interior slabs");
  add("phi_whole", s.packing.whole, "", "packing fraction of the whole bed up to the mean surface");
  add("fill_time", s.fill_sim_time, "s", "simulated filling and settling");
  add("settled", s.settled ? 1.0 : 0.0, "", "kinetic-energy criterion met");
  add("column_weight", st.column_weight, "N", "M g L / W: weight of the bed above the intruder's length");
  add("h1", st.h1, "m", "002's H1 = (W - L)/2 tan 60 deg");
  // Drag.
  add("drag_mean", st.drag_mean, "N", "mean drag over the pull");
  add("drag_std", st.drag_std, "N", "standard deviation of the drag over the pull");
  add("peak", st.peak, "N", "largest drag");
  add("peak_height", st.peak_height, "m", "intruder height of the largest drag");
  add("peak_over_column", st.peak / st.column_weight, "", "peak / (M g L / W)");
  add("smoothed_peak", st.smoothed_peak, "N", "largest drag of the d/2 running mean");
  add("smoothed_peak_height", st.smoothed_peak_height, "m", "its height");
  add("drop", st.drop, "N", "first minimum after it (d/2 running mean, hysteresis 10 % of its peak)");
  add("drop_height", st.drop_height, "m", "its height");
  add("reload", st.reload, "N", "the maximum after the drop");
  add("reload_height", st.reload_height, "m", "its height");
  for (int t = 0; t < 3; ++t) {
    const Third& th = st.thirds[static_cast<std::size_t>(t)];
    const std::string k = "third" + std::to_string(t + 1) + "_";
    const std::string w = " in third " + std::to_string(t + 1) + " of the pull";
    add(k + "h_lo", th.h_lo, "m", "lower height" + w);
    add(k + "h_hi", th.h_hi, "m", "upper height" + w);
    add(k + "drag_mean", th.drag_mean, "N", "mean drag" + w);
    add(k + "drag_std", th.drag_std, "N", "standard deviation of the drag" + w);
    add(k + "mu_bulk", th.mu_bulk, "", "mean bulk mu*" + w);
    add(k + "mu_wall", th.mu_wall, "", "mean wall mu*" + w);
    add(k + "dragged_area", th.dragged_area, "m^2", "mean area with v* > 0.75 above the intruder" + w);
  }
  const char* qn[3] = {"q1", "q2", "q5"};
  for (std::size_t q = 0; q < 3; ++q) {
    add(std::string("quiet_thickness_") + qn[q], st.quiet_thickness[q], "m",
        "mean surface minus the height of the last drop > " + study_detail::num(100 * st.quiet_q[q], 3) +
            " % of the peak within d/2 of travel, axis >= 2 d below the surface");
  }
  add("last_drop_height", st.last_drop_height[1], "m", "height of the last drop > q x peak (q = 2 %)");
  // Spectrum.
  add("spectrum_from", st.segment_lo, "m", "fluctuating part used for the spectrum: from");
  add("spectrum_to", st.segment_hi, "m", "to");
  add("spectrum_whole", st.segment_whole ? 1.0 : 0.0, "", "1: fluctuating part < 8 d, whole pull after the peak used");
  add("half_d_ratio", st.half_d.ratio, "", "R: PSD of the half-octave band at d/2 over its neighbours' geometric mean");
  add("half_d_critical", st.half_d.critical, "", "95 % point of R for a smooth spectrum");
  add("half_d_bins", static_cast<double>(st.half_d.band.bins), "", "spectral bins in the d/2 band");
  add("half_d_stands_out", st.half_d.stands_out ? 1.0 : 0.0, "", "1: R above its 95 % point");
  add("half_d_testable", st.half_d.testable ? 1.0 : 0.0, "", "1: enough bins in all three bands");
  add("event_spacing", st.event_spacing, "m", "median spacing of drag maxima (hysteresis 2 % of the peak)");
  add("events", static_cast<double>(st.events), "", "maxima counted");
  add("dominant_wavelength", st.dominant_wavelength, "m", "largest f PSD among third-octave bands in [d/4, 4 d]");
  // mu*.
  add("mu_bulk_below_h1", st.mu_bulk_below_h1, "", "mean bulk mu* with the intruder below H1");
  add("mu_wall_below_h1", st.mu_wall_below_h1, "", "mean wall mu* below H1");
  add("mu_bulk_above_h1", st.mu_bulk_above_h1, "", "mean bulk mu* from H1 to the mean surface");
  add("mu_wall_above_h1", st.mu_wall_above_h1, "", "mean wall mu* from H1 to the mean surface");
  add("mu_bulk_end", st.mu_bulk_end, "", "mean bulk mu* over the last 10 % of the pull below the surface");
  add("mu_wall_end", st.mu_wall_end, "", "mean wall mu* over the last 10 % of the pull below the surface");
  add("sliding_bulk", st.sliding_bulk, "", "mean fraction of bulk contacts at the Coulomb threshold");
  // Zones.
  add("cone_angle", st.cone_angle, "deg", "median inclination of the mobile zone's edges at the drag maxima below the quiet layer");
  add("cone_angle_p25", st.cone_angle_p25, "deg", "its lower quartile");
  add("cone_angle_p75", st.cone_angle_p75, "deg", "its upper quartile");
  add("cone_samples", static_cast<double>(st.cone_samples), "", "drag maxima with a measured cone");
  add("cone_angle_loading", st.cone_angle_loading, "deg", "median over all loading samples below the quiet layer");
  add("wall_mobility_below_h1", st.wall_mobility_below_h1, "", "mobile fraction of the wall bands, loading samples below H1");
  add("wall_mobility_above_h1", st.wall_mobility_above_h1, "", "the same above H1");
  for (std::size_t m = 0; m < r.maps.size(); ++m) {
    const std::string k = "map" + std::to_string(m + 1) + "_";
    add(k + "height", r.maps[m].height, "m", "intruder height of velocity map " + std::to_string(m + 1));
    add(k + "drag", r.maps[m].drag, "N", "drag at that loading peak");
    add(k + "cone_angle", r.maps[m].cone.angle, "deg", "cone measured on that map");
  }
  // Cost.
  const double n = static_cast<double>(s.particles);
  add("fill_steps", static_cast<double>(s.fill_steps), "", "steps of filling and settling");
  add("pull_steps", static_cast<double>(r.steps), "", "steps of the pull");
  add("fill_wall_time", s.fill_wall_seconds, "s", "wall time of the filling (0: bed read from the cache)");
  add("pull_wall_time", r.wall_seconds, "s", "wall time of the pull, analysis included");
  add("analysis_wall_time", r.analysis_seconds, "s", "of which coarse-graining and zones");
  add("ns_per_particle_step", r.steps > 0 ? 1e9 * (r.wall_seconds - r.analysis_seconds) / (n * static_cast<double>(r.steps)) : 0.0,
      "ns", "pull without the analysis");
  v.push_back({"analysis_commit", 0.0, "", "git commit of the statistics", analysis.commit});
  v.push_back({"analysis_date", 0.0, "", "UTC", analysis.date});
  v.push_back({"commit", 0.0, "", "git commit of the build", prov.commit});
  v.push_back({"date", 0.0, "", "UTC", prov.date});
  v.push_back({"machine", 0.0, "", "CPU, hardware threads, OpenMP threads", prov.machine});
  return v;
}

inline void write_summary(const std::filesystem::path& file, const std::string& comment,
                          const std::vector<SummaryRow>& rows) {
  std::ostringstream s;
  s << comment << "quantity,value,unit,description\n";
  for (const auto& r : rows)
    s << r.quantity << "," << (r.text.empty() ? study_detail::num(r.value, 7) : csv_quoted(r.text)) << ","
      << r.unit << "," << csv_quoted(r.description) << "\n";
  study_detail::write_atomically(file, s.str());
}

/// Numbers and texts of a summary.csv; nullopt if it is missing or incomplete (no machine row).
inline std::optional<std::map<std::string, std::string>> read_summary(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  std::map<std::string, std::string> m;
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    const auto f = csv_split(line);
    if (f.size() >= 2) m[f[0]] = f[1];
  }
  if (!m.count("machine")) return std::nullopt;
  return m;
}

/// The samples of a pull: every column (`full`) or the ones the statistics read, with 5 digits
/// (the study's files).
inline void write_samples(const std::filesystem::path& file, const std::string& comment, const PullResult& r, bool full) {
  std::vector<std::vector<double>> t;
  for (const auto& x : r.samples) {
    if (full) {
      t.push_back({x.time, x.height, x.drag, x.mu_star_bulk, x.mu_star_wall, x.sliding_bulk,
                   static_cast<double>(x.contacts_intruder), x.dragged_area, x.cone_area, x.wall_mobility, x.cone_angle,
                   x.cone_left, x.cone_right});
    } else {
      t.push_back({x.height, x.drag, x.mu_star_bulk, x.mu_star_wall, x.sliding_bulk, x.dragged_area, x.wall_mobility,
                   x.cone_angle});
    }
  }
  if (full) {
    write_table(file, comment,
                {"time [s]", "intruder_height [m]", "drag_force [N]", "mu_star_bulk", "mu_star_walls", "sliding_bulk",
                 "intruder_contacts", "dragged_area [m^2]", "cone_area [m^2]", "wall_mobility", "cone_angle [deg]",
                 "cone_left [deg]", "cone_right [deg]"},
                t, 8);
  } else {
    write_table(file, comment,
                {"intruder_height [m]", "drag_force [N]", "mu_star_bulk", "mu_star_walls", "sliding_bulk",
                 "dragged_area [m^2]", "wall_mobility", "cone_angle [deg]"},
                t, std::vector<int>{6, 4});  // heights to 0.1 um, the rest to 4 digits: small files
  }
}

/// Samples written by write_samples (either form; missing columns are NaN).
inline std::vector<DragSample> read_samples(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw IoError("intruder_pull_out_2d: cannot read '" + file.string() + "'");
  std::vector<std::string> names;
  std::vector<DragSample> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto f = csv_split(line);
    if (names.empty()) {
      for (auto n : f) names.push_back(n.substr(0, n.find(" [")));
      continue;
    }
    DragSample x{nan, nan, nan, nan, nan, nan, 0, nan, nan, nan, nan, nan, nan};
    for (std::size_t k = 0; k < f.size() && k < names.size(); ++k) {
      const double v = f[k] == "nan" ? nan : std::stod(f[k]);
      const std::string& n = names[k];
      if (n == "time") x.time = v;
      else if (n == "intruder_height") x.height = v;
      else if (n == "drag_force") x.drag = v;
      else if (n == "mu_star_bulk") x.mu_star_bulk = v;
      else if (n == "mu_star_walls") x.mu_star_wall = v;
      else if (n == "sliding_bulk") x.sliding_bulk = v;
      else if (n == "intruder_contacts") x.contacts_intruder = static_cast<std::size_t>(v);
      else if (n == "dragged_area") x.dragged_area = v;
      else if (n == "cone_area") x.cone_area = v;
      else if (n == "wall_mobility") x.wall_mobility = v;
      else if (n == "cone_angle") x.cone_angle = v;
      else if (n == "cone_left") x.cone_left = v;
      else if (n == "cone_right") x.cone_right = v;
    }
    out.push_back(x);
  }
  return out;
}

/// Columns and rows of the binned pull.
inline void write_profile(const std::filesystem::path& file, const std::string& comment,
                          const std::vector<ProfileRow>& rows) {
  std::vector<std::vector<double>> t;
  for (const auto& r : rows)
    t.push_back({r.height, static_cast<double>(r.samples), r.drag, r.drag_min, r.drag_max, r.mu_bulk, r.mu_wall, r.sliding,
                 r.cone_angle, r.wall_mobility, r.dragged_area});
  write_table(file, comment,
              {"intruder_height [m]", "samples", "drag [N]", "drag_min [N]", "drag_max [N]", "mu_star_bulk",
               "mu_star_walls", "sliding_bulk", "cone_angle [deg]", "wall_mobility", "dragged_area [m^2]"},
              t, 4);
}

/// Third-octave bands of the drag's spectrum (and the d/2 test's three bands in the comment).
inline void write_bands(const std::filesystem::path& file, const std::string& comment, const DragStatistics& st) {
  std::vector<std::vector<double>> t;
  for (const auto& b : st.bands)
    t.push_back({1.0 / std::sqrt(b.f_lo * b.f_hi), 1.0 / b.f_hi, 1.0 / b.f_lo, b.psd, static_cast<double>(b.bins)});
  write_table(file, comment,
              {"wavelength [m]", "wavelength_lo [m]", "wavelength_hi [m]", "psd [N^2 m]", "bins"}, t);
}

/// A velocity map: every `stride`-th node on both axes, `digits` significant digits.
inline void write_map(const std::filesystem::path& file, const std::string& comment, const VelocityMap& m, double v,
                      int stride, int digits) {
  const auto& g = m.fields.grid;
  std::vector<std::vector<double>> t;
  for (int j = 0; j < g.count().y(); j += stride)
    for (int i = 0; i < g.count().x(); i += stride) {
      const std::size_t k = g.index(Dim2::IVec(i, j));
      const Vec x = g.node(k);
      const Vec u = m.fields.velocity[k] / v;
      t.push_back({x.x(), x.y(), u.x(), u.y(), m.speed[k], m.fields.packing_fraction[k]});
    }
  write_table(file, comment,
              {"x [m]", "y [m]", "vx_over_V", "vy_over_V", "speed_over_V", "packing_fraction"}, t, digits);
}

/// File name of a map at intruder height h: velocity_map_h<mm>mm.csv.
inline std::string map_name(double h) {
  char name[64];
  std::snprintf(name, sizeof name, "velocity_map_h%03.0fmm.csv", h * 1e3);
  return name;
}

/// One case of the study.
struct StudyCase {
  std::string name;
  PullParams params;
};

namespace study_detail {
/// "6e7", "1.8e9": E in the shortest scientific form.
inline std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", v);
  std::string s = buf;
  const auto e = s.find("e+");
  if (e != std::string::npos) {
    std::string exp = s.substr(e + 2);
    while (exp.size() > 1 && exp[0] == '0') exp.erase(0, 1);
    s = s.substr(0, e) + "e" + exp;
  }
  return s;
}
inline std::string case_name(const PullParams& p, const std::string& prefix = "") {
  std::string n = prefix + "E" + sci(p.youngs_modulus) + "_V" + num(p.pull_velocity * 1e3, 3) + "mmps_seed" +
                  std::to_string(p.seed);
  if (p.dt_rule == TimeStepRule::Paper) n += "_dtpaper";
  return n;
}
}  // namespace study_detail

/// The paper's cell and bed (W = 100 mm, 150 mm, 1600 disks, filled from the outlet at 250 /s),
/// t = 3 d, sampled every 0.1 mm of travel.
inline PullParams study_base() {
  PullParams p;
  const PullParams q = paper_params();
  p.cell_width = q.cell_width;
  p.bed_height = q.bed_height;
  p.fill_rate = q.fill_rate;
  p.sample_travel = 1e-4;
  return p;
}

/// Cases of a study tag (README, "Convergence"):
///  convergence  a cross in (kappa, I) on the paper's cell: E = 6e7, 1.8e8, 6e8, 1.8e9 Pa (kappa =
///               6.6e3 ... 2e5) at V = 20 mm/s, and V = 20, 6, 2, 1.2 mm/s (I = 1.8e-2 ... 1.1e-3,
///               the last 002's) at E = 6e8 Pa; E = 1.8e9 Pa at V = 6 mm/s (does kappa still not
///               matter at a slower pull?); beds 2 to 5 at the cheapest point for the scatter
///               between beds (the sigma that decides which results have converged);
///  dtcheck      the quick cell at E = 6e8 Pa, V = 20 mm/s, pulled from one bed with the engine's
///               step and with 002's dt_c / 60 (26 times smaller).
inline std::vector<StudyCase> study_cases(const std::string& tag) {
  std::vector<StudyCase> out;
  auto add = [&](PullParams p, const std::string& prefix = "") { out.push_back({study_detail::case_name(p, prefix), p}); };
  if (tag == "convergence") {
    for (double e : {6e7, 1.8e8, 6e8, 1.8e9}) {
      PullParams p = study_base();
      p.youngs_modulus = e;
      p.pull_velocity = 0.02;
      add(p);
    }
    for (double v : {6e-3, 2e-3, 1.2e-3}) {
      PullParams p = study_base();
      p.youngs_modulus = 6e8;
      p.pull_velocity = v;
      add(p);
    }
    {  // is the cross separable? the stiffest E at a slow pull, against E = 6e8 Pa there
      PullParams p = study_base();
      p.youngs_modulus = 1.8e9;
      p.pull_velocity = 6e-3;
      add(p);
    }
    for (std::uint64_t seed : {2u, 3u, 4u, 5u}) {
      PullParams p = study_base();
      p.youngs_modulus = 6e7;
      p.pull_velocity = 0.02;
      p.seed = seed;
      add(p);
    }
  } else if (tag == "dtcheck") {
    for (TimeStepRule rule : {TimeStepRule::Engine, TimeStepRule::Paper}) {
      PullParams p;  // quick cell
      p.youngs_modulus = 6e8;
      p.pull_velocity = 0.02;
      p.dt_rule = rule;
      add(p, "quick_");
    }
  } else {
    throw InvalidParameter("--study: unknown tag '" + tag + "' (convergence, dtcheck)");
  }
  return out;
}

/// The statistics of a run computed again from its files (`dir`: summary.csv and samples.csv, or
/// drag.csv for a single run): the scene's numbers come from the summary, the samples from their
/// file; the velocity maps keep the heights, drags and cones the run found. summary.csv is
/// rewritten with the new statistics, the run's provenance and this build's as the analysis'.
struct Reanalysis {
  PullScene scene;  ///< without a simulation: the numbers of the summary
  PullResult result;  ///< the samples; maps without fields
  DragStatistics stats;
};

inline Reanalysis restat(const std::filesystem::path& dir, const StatisticsOptions& o) {
  const auto sm = read_summary(dir / "summary.csv");
  if (!sm) throw IoError("intruder_pull_out_2d --restat: no complete summary.csv in '" + dir.string() + "'");
  auto num = [&](const std::string& k) {
    const auto it = sm->find(k);
    if (it == sm->end()) throw IoError("intruder_pull_out_2d --restat: summary.csv in '" + dir.string() + "' has no " + k);
    return it->second == "nan" ? std::numeric_limits<double>::quiet_NaN() : std::stod(it->second);
  };
  PullScene s;
  PullParams& p = s.params;
  p.cell_width = num("cell_width");
  p.bed_height = num("bed_height_target");
  p.thickness = num("thickness");
  p.youngs_modulus = num("youngs_modulus");
  p.pull_velocity = num("pull_velocity");
  p.sample_travel = num("sample_travel");
  p.cg_width = num("cg_width") / p.mean_diameter;
  p.seed = static_cast<std::uint64_t>(num("seed"));
  p.dt = num("dt_pull");
  s.particles = static_cast<std::size_t>(num("disks"));
  s.bed_height = num("top_surface");
  s.packing.surface = num("mean_surface");
  s.packing.interior = num("phi_interior");
  s.packing.interior_min = num("phi_interior_min");
  s.packing.interior_max = num("phi_interior_max");
  if (sm->count("phi_interior_slabs")) s.packing.slabs = static_cast<std::size_t>(num("phi_interior_slabs"));
  s.packing.whole = num("phi_whole");
  s.fill_sim_time = num("fill_time");
  s.settled = num("settled") != 0.0;
  s.bed_mass = num("column_weight") * p.cell_width / (kGravity * p.intruder_length);
  s.fill_steps = static_cast<std::uint64_t>(num("fill_steps"));
  s.fill_wall_seconds = num("fill_wall_time");
  PullResult r;
  const auto samples = dir / "samples.csv";
  r.samples = read_samples(std::filesystem::exists(samples) ? samples : dir / "drag.csv");
  r.dt = p.dt;
  r.steps = static_cast<std::uint64_t>(num("pull_steps"));
  r.wall_seconds = num("pull_wall_time");
  r.analysis_seconds = num("analysis_wall_time");
  for (int m = 1; sm->count("map" + std::to_string(m) + "_height"); ++m) {
    VelocityMap v;
    const std::string k = "map" + std::to_string(m) + "_";
    v.target = v.height = num(k + "height");
    v.drag = num(k + "drag");
    v.cone.angle = num(k + "cone_angle");
    r.maps.push_back(std::move(v));
  }
  DragStatistics st = drag_statistics(s, r, o);
  const Provenance run{sm->at("commit"), sm->at("date"), sm->at("machine")};
  const auto rows = summary_rows(s, r, st, run, provenance_now());
  // Keep the first line (the run's provenance comment) of the old file.
  std::string comment;
  {
    std::ifstream in(dir / "summary.csv");
    std::getline(in, comment);
    comment = comment.rfind("#", 0) == 0 ? comment + "\n" : std::string();
  }
  write_summary(dir / "summary.csv", comment, rows);
  return {std::move(s), std::move(r), std::move(st)};
}

}  // namespace granule::examples::pull_out
