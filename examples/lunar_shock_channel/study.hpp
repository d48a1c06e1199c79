#pragma once
// The paper-scale channel study (issue 26): 001's grains, material, contact law, 2 cm x 20 cm
// cross-section (80 diameters deep), shock step 1e-6 s, in a channel shortened only as far as a
// measured length check allows. One small CSV per case under results/<tag>/ with the commit,
// date, machine and load, so that a rerun skips what is done; the case list, the length-check
// verdict and the cost model are here so that the regression test can check them cheaply.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../common/csv_fields.hpp"
#include "../common/provenance.hpp"

#include "scene.hpp"

namespace granule::examples::lunar_shock {

/// The study tags, in the order the lead would run them.
inline const std::vector<std::string>& study_tags() {
  static const std::vector<std::string> t{"length", "loose", "medium", "rolling", "bender"};
  return t;
}

/// Piston speeds of 001 table 8 for the loose bed: v_p = 10^n, n = -2, -1, -1/2, -1/4, 0, 1/4,
/// 1/2, 3/4, 1 [m/s].
inline std::vector<double> paper_loose_speeds() {
  std::vector<double> v;
  for (double n : {-2.0, -1.0, -0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0}) v.push_back(std::pow(10.0, n));
  return v;
}

/// Lengths of the length check [m]: the shorter is used only if it agrees with the longer.
constexpr double kShortLength = 0.5, kLongLength = 1.0;
/// Speeds of the length check: one acoustic, the strongest shock [m/s].
constexpr double kCheckAcoustic = 0.1, kCheckShock = 10.0;
/// Largest relative difference between the two lengths that passes (c_w, c_p, delta_m/delta_0):
/// below 001's own depth spreads of table 8 (loose: 7-15 % in c_w, 6-10 % in c_p).
constexpr double kLengthTolerance = 0.05;

/// One case of the study: one bed, one wave.
struct StudyCase {
  std::string tag;              ///< study it belongs to
  Packing packing = Packing::Loose;
  double length = kShortLength; ///< [m]
  double v_p = 0.1;             ///< piston speed (bender: peak speed) [m/s]
  double rolling_damping = 2.0; ///< eta_r of settling and shock [-]
  bool bender = false;          ///< S wave instead of P wave

  /// File stem: every parameter that changes the result, so that equal stems are equal cases
  /// in any study directory.
  std::string stem() const {
    char b[128];
    std::snprintf(b, sizeof b, "%s_L%g_vp%g%s%s", packing_name(packing), length, v_p,
                  rolling_damping != 2.0 ? ("_etar" + fmt(rolling_damping)).c_str() : "", bender ? "_S" : "");
    return b;
  }

 private:
  static std::string fmt(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", x);
    return b;
  }
};

/// Cases of a study tag; `length` is the channel length of every tag but "length" [m].
/// Throws InvalidParameter for an unknown tag.
inline std::vector<StudyCase> study_cases(const std::string& tag, double length) {
  std::vector<StudyCase> c;
  auto add = [&](Packing p, double L, double v, double eta = 2.0, bool s = false) {
    c.push_back({tag, p, L, v, eta, s});
  };
  if (tag == "length") {
    for (double L : {kShortLength, kLongLength})
      for (double v : {kCheckShock, kCheckAcoustic}) add(Packing::Loose, L, v);
  } else if (tag == "loose") {
    // The acoustic pair (c_0) and the strongest shock first, then the rest of table 8.
    std::vector<double> order{0.1, 10.0, 0.01};
    for (double v : paper_loose_speeds())
      if (std::none_of(order.begin(), order.end(), [&](double o) { return std::abs(o - v) < 1e-12; }))
        order.push_back(v);
    for (double v : order) add(Packing::Loose, length, v);
  } else if (tag == "medium") {
    for (double v : {0.1, 10.0, 0.01}) add(Packing::Medium, length, v);
  } else if (tag == "rolling") {
    // The other reading of 001's rolling damping (section 2.1: neglected).
    for (double v : {0.1, 10.0}) add(Packing::Loose, length, v, 0.0);
  } else if (tag == "bender") {
    add(Packing::Loose, length, 10.0, 2.0, true);
  } else {
    std::string all;
    for (const auto& t : study_tags()) all += (all.empty() ? "" : ", ") + t;
    throw InvalidParameter("--study must be one of " + all + ", not '" + tag + "'");
  }
  return c;
}

/// Channel options of a study case: 001's sizes (ChannelOptions::paper) at the case's length,
/// packing and rolling damping; pour and settle at `dt_prepare`, the shock at 1e-6 s until a
/// front of 3 m/s has reached the end wall (below every front the quick channel measured: 3.9
/// m/s at v_p = 0.01 m/s), then the tail at 1e-5 s for 0.4 s (landing, and the final height
/// averaged over the last 0.2 s).
inline ChannelOptions study_options(const StudyCase& c, double dt_prepare = 1e-5) {
  ChannelOptions o = ChannelOptions::paper();
  o.length = c.length;
  o.packing = c.packing;
  o.rolling_damping = c.rolling_damping;
  o.bender = c.bender;
  o.dt_prepare = dt_prepare;
  o.dt_shock = 1e-6;
  o.tail_from = c.length / 3.0;
  o.tail_dt = 1e-5;
  o.run_time = o.tail_from + 0.4;
  // c_p over 30-45 cm at both lengths of the check (001: 30-50 cm in 2 m), clear of the end
  // wall of the 0.5 m channel.
  o.cp_from = 0.30;
  o.cp_to = 0.45;
  return o;
}

/// The result of one case, as written to its file.
struct StudyResult {
  StudyCase c;
  double particles = 0, packing_fraction = 0, packing_interior = 0, coordination = 0, delta_0 = 0;
  double c_w = NAN, c_w_sd = NAN, c_p = NAN, c_p_sd = NAN, delta_ratio = NAN, dz = NAN, dz_sd = NAN;
  double max_particle_speed = 0, ejected = 0, dt = 0, dt_tail = 0, run_time = 0, steps = 0, wall_time = 0;
  double ns_per_particle_step = 0, load = 0;
  Provenance prov;
};

namespace study_detail {
constexpr const char* kHeader =
    "tag,case,packing,length [m],v_p [m/s],wave,rolling_damping,particles,packing_fraction,packing_interior,"
    "coordination,delta_0 [m],c_w [m/s],c_w_sd [m/s],c_p [m/s],c_p_sd [m/s],delta_m_over_delta_0,dz [m],dz_sd [m],"
    "max_particle_speed [m/s],ejected,dt [s],dt_tail [s],run_time [s],steps,wall_time [s],ns_per_particle_step,"
    "load_average,commit,date,machine";
constexpr std::size_t kFields = 31;

inline std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.7g", v);
  return b;
}

/// Writes `text` to `file` through a temporary and a rename: the file is whole or absent.
inline void write_atomically(const std::filesystem::path& file, const std::string& text) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
    if (!o) throw IoError("lunar_shock study: cannot open '" + tmp.string() + "' for writing");
    o << text;
    o.flush();
    if (!o) throw IoError("lunar_shock study: writing '" + tmp.string() + "' failed");
  }
  std::filesystem::rename(tmp, file);
}

inline Packing packing_of(const std::string& s) {
  if (s == "loose") return Packing::Loose;
  if (s == "medium") return Packing::Medium;
  if (s == "compact") return Packing::Compact;
  throw InvalidParameter("packing must be loose, medium or compact, not '" + s + "'");
}
}  // namespace study_detail

/// The 1-minute load average of the machine (/proc/loadavg), NaN where there is none.
inline double load_average() {
  std::ifstream f("/proc/loadavg");
  double l = NAN;
  if (!(f >> l)) return NAN;
  return l;
}

inline void write_result(const std::filesystem::path& file, const StudyResult& r) {
  using study_detail::num;
  std::ostringstream s;
  s << study_detail::kHeader << "\n"
    << r.c.tag << "," << r.c.stem() << "," << packing_name(r.c.packing) << "," << num(r.c.length) << "," << num(r.c.v_p)
    << "," << (r.c.bender ? "S" : "P") << "," << num(r.c.rolling_damping);
  for (double v : {r.particles, r.packing_fraction, r.packing_interior, r.coordination, r.delta_0, r.c_w, r.c_w_sd, r.c_p,
                   r.c_p_sd, r.delta_ratio, r.dz, r.dz_sd, r.max_particle_speed, r.ejected, r.dt, r.dt_tail, r.run_time,
                   r.steps, r.wall_time, r.ns_per_particle_step, r.load})
    s << "," << num(v);
  s << "," << csv_quoted(r.prov.commit) << "," << csv_quoted(r.prov.date) << "," << csv_quoted(r.prov.machine) << "\n";
  study_detail::write_atomically(file, s.str());
}

/// Reads a file written by write_result; nullopt when it is missing, partial or of another format.
inline std::optional<StudyResult> read_result(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string header, row;
  if (!in || !std::getline(in, header) || !std::getline(in, row)) return std::nullopt;
  if (header != study_detail::kHeader) return std::nullopt;
  const auto f = csv_split(row);
  if (f.size() != study_detail::kFields) return std::nullopt;
  StudyResult r;
  try {
    r.c.tag = f[0];
    r.c.packing = study_detail::packing_of(f[2]);
    r.c.length = std::stod(f[3]);
    r.c.v_p = std::stod(f[4]);
    r.c.bender = f[5] == "S";
    r.c.rolling_damping = std::stod(f[6]);
    double* v[] = {&r.particles, &r.packing_fraction, &r.packing_interior, &r.coordination, &r.delta_0, &r.c_w,
                   &r.c_w_sd, &r.c_p, &r.c_p_sd, &r.delta_ratio, &r.dz, &r.dz_sd, &r.max_particle_speed, &r.ejected,
                   &r.dt, &r.dt_tail, &r.run_time, &r.steps, &r.wall_time, &r.ns_per_particle_step, &r.load};
    for (std::size_t k = 0; k < 21; ++k) *v[k] = std::stod(f[7 + k]);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  // A file renamed by hand, or whose parameters do not give its name, is not that case.
  if (r.c.stem() != f[1] || file.stem().string() != f[1]) return std::nullopt;
  r.prov = {f[28], f[29], f[30]};
  return r;
}

/// The result of `c` if one exists: results/<tag>/<stem>.csv, or the same stem in a sibling
/// study directory (copied into <tag>/ so that each directory is complete).
inline std::optional<StudyResult> find_result(const std::filesystem::path& results_root, const StudyCase& c) {
  namespace fs = std::filesystem;
  const fs::path own = results_root / c.tag / (c.stem() + ".csv");
  if (auto r = read_result(own)) return r;
  if (!fs::is_directory(results_root)) return std::nullopt;
  for (const auto& d : fs::directory_iterator(results_root)) {
    if (!d.is_directory() || d.path().filename() == c.tag) continue;
    const fs::path other = d.path() / (c.stem() + ".csv");
    if (auto r = read_result(other)) {
      fs::create_directories(own.parent_path());
      fs::copy_file(other, own, fs::copy_options::overwrite_existing);
      return r;
    }
  }
  return std::nullopt;
}

/// Verdict of the length check.
struct LengthVerdict {
  enum class State { NotRun, Pass, Fail } state = State::NotRun;
  double length = kShortLength;  ///< length the other studies use [m]
  /// Largest relative difference short/long over the quantities and speeds compared (NaN if
  /// not complete), and which quantity it was.
  double worst = NAN;
  std::string worst_what;
  std::vector<std::string> lines;  ///< one per speed and quantity
};

/// The check: at both speeds, c_w, c_p and delta_m/delta_0 of the two lengths agree within
/// kLengthTolerance (relative to the long channel). NotRun until all four cases exist; a
/// quantity that is NaN at either length fails (nothing to compare is not an agreement).
inline LengthVerdict length_verdict(const std::vector<StudyResult>& results) {
  LengthVerdict v;
  auto find = [&](double L, double vp) -> const StudyResult* {
    for (const auto& r : results)
      if (r.c.packing == Packing::Loose && !r.c.bender && r.c.rolling_damping == 2.0 && std::abs(r.c.length - L) < 1e-9 &&
          std::abs(r.c.v_p - vp) < 1e-9)
        return &r;
    return nullptr;
  };
  bool pass = true;
  double worst = 0.0;
  for (double vp : {kCheckShock, kCheckAcoustic}) {
    const StudyResult *s = find(kShortLength, vp), *l = find(kLongLength, vp);
    if (!s || !l) {
      v.state = LengthVerdict::State::NotRun;
      v.length = kShortLength;
      v.lines.clear();
      v.lines.push_back("length check not complete: run --study length");
      return v;
    }
    const std::pair<const char*, double StudyResult::*> q[] = {
        {"c_w", &StudyResult::c_w}, {"c_p", &StudyResult::c_p}, {"delta_m/delta_0", &StudyResult::delta_ratio}};
    for (const auto& [name, m] : q) {
      const double a = s->*m, b = l->*m;
      const double d = std::abs(a - b) / std::abs(b);
      const bool ok = std::isfinite(d) && d <= kLengthTolerance;
      pass = pass && ok;
      if (!std::isfinite(d) || d > worst) {
        worst = std::isfinite(d) ? d : INFINITY;
        v.worst_what = std::string(name) + " at v_p = " + study_detail::num(vp) + " m/s";
      }
      char b2[200];
      std::snprintf(b2, sizeof b2, "v_p = %g m/s, %s: %.4g (%g m) vs %.4g (%g m): %.1f %% %s", vp, name, a, kShortLength,
                    b, kLongLength, 100.0 * d, ok ? "agree" : "DIFFER");
      v.lines.push_back(b2);
    }
  }
  v.worst = worst;
  v.state = pass ? LengthVerdict::State::Pass : LengthVerdict::State::Fail;
  v.length = pass ? kShortLength : kLongLength;
  return v;
}

// ---------------------------------------------------------------------------------------------
// Cost model
// ---------------------------------------------------------------------------------------------

/// Measured cost per particle-step of the three phases [ns] on the measuring machine.
struct PhaseCost {
  double pour = NAN, settle = NAN, shock = NAN;
  /// CPU time of all threads per particle-step [ns]; over the threads it estimates the wall
  /// time on an idle machine.
  double pour_cpu = NAN, settle_cpu = NAN, shock_cpu = NAN;
  PhaseCost idle(int threads) const {
    const double t = static_cast<double>(std::max(1, threads));
    return {pour_cpu / t, settle_cpu / t, shock_cpu / t, pour_cpu, settle_cpu, shock_cpu};
  }
};

/// Assumed settling time to 001's criterion (3e-7 m g) [s]: not measured at paper scale (README).
constexpr double kSettleTimeAssumed = 2.0;

/// Estimated wall time of one case's parts [s].
struct CaseEstimate {
  double particles = 0, pour = 0, settle = 0, shock = 0;
  double total() const { return pour + settle + shock; }
};

/// Particles of a bed of length L at 001's loose packing fraction (table 3: 536 180 in 2 m).
inline double bed_particles(const ChannelOptions& o) {
  const double phi = o.packing == Packing::Loose ? 0.5472 : o.packing == Packing::Medium ? 0.5865 : 0.6196;
  return phi * o.length * o.width * o.depth / o.particle_volume();
}

/// Pour: pour_count() particles inserted at the table-3 rate, then the fall from the top of the
/// insertion region and 0.2 s of coming to rest; every particle present costs a particle-step.
inline double pour_particle_steps(const ChannelOptions& o) {
  const double n = static_cast<double>(o.pour_count());
  const double rate = o.flux() * o.length * o.width;
  const double t_insert = n / rate;
  const double t_land = std::sqrt(2.0 * (o.depth + o.drop_height + o.region_height) / o.gravity) + 0.2;
  return n * (0.5 * t_insert + t_land) / pour_dt(o);
}

/// Estimate of one case; `pour_new` / `settle_new`: its bed still has to be poured / settled.
inline CaseEstimate estimate_case(const ChannelOptions& o, const PhaseCost& cost, bool pour_new, bool settle_new) {
  CaseEstimate e;
  e.particles = bed_particles(o);
  if (pour_new) e.pour = pour_particle_steps(o) * cost.pour * 1e-9;
  if (settle_new) e.settle = e.particles * kSettleTimeAssumed / prepare_dt(o) * cost.settle * 1e-9;
  const double t_fine = o.pre_record + (o.tail_from > 0.0 ? std::min(o.tail_from, o.run_time) : o.run_time);
  const double t_tail = o.tail_from > 0.0 ? std::max(0.0, o.run_time - o.tail_from) : 0.0;
  const double steps = t_fine / o.dt_shock + t_tail / o.tail_dt;
  e.shock = e.particles * steps * cost.shock * 1e-9;
  return e;
}

/// Keys of a case's beds for the estimate: cases with equal keys share one poured (settled) bed;
/// the pour has no rolling damping whatever the reading, so both readings share it.
inline std::string pour_key(const StudyCase& c) {
  char b[96];
  std::snprintf(b, sizeof b, "%s_L%g", packing_name(c.packing), c.length);
  return b;
}
inline std::string settle_key(const StudyCase& c) {
  char b[32];
  std::snprintf(b, sizeof b, "_etar%g", c.rolling_damping);
  return pour_key(c) + b;
}


// ---------------------------------------------------------------------------------------------
// Cost measurement: short segments of the real code paths
// ---------------------------------------------------------------------------------------------

/// One measured segment.
struct CostSegment {
  std::string phase;       ///< "settle" or "shock" (lattice bed), "pour" (a real small pour)
  double length = 0;       ///< channel length [m]
  double particles = 0;
  double steps = 0;
  double dt = 0;           ///< [s]
  double wall = 0;         ///< [s]
  double ns_per_particle_step = 0;
  /// CPU time of the process (all threads) per particle-step [ns]: on a shared machine the wall
  /// time depends on the load, the CPU time much less.
  double cpu_ns_per_particle_step = 0;
  double load_before = NAN, load_after = NAN;  ///< 1-minute load average [-]
};

/// CPU time of this process, all threads [s].
inline double process_cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// Fills `sim` with a simple cubic lattice of touching spheres over the whole fill height
/// (packing fraction pi/6 = 0.524, 001 loose 0.547, six contacts each): a stand-in for a
/// settled bed of the same size, to measure the cost per particle-step without pouring one.
inline void fill_lattice(ChannelSim& sim, const ChannelOptions& o) {
  const double d = 2.0 * o.radius;
  const int nx = static_cast<int>(std::floor(o.width / d + 1e-9));
  const int ny = static_cast<int>(std::floor(o.length / d + 1e-9));
  const int nz = static_cast<int>(std::floor(o.depth / d + 1e-9));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) sim.add_particle(Vec((i + 0.5) * d, (j + 0.5) * d, (k + 0.5) * d), o.radius, 0);
}

/// Settling cost: `steps` steps of settle_bed on a lattice bed at prepare_dt(o).
inline CostSegment measure_settle(ChannelOptions o, std::uint64_t steps) {
  o.progress = false;
  auto sim = make_channel(o, prepare_dt(o), false);
  fill_lattice(*sim, o);
  o.settle_time = static_cast<double>(steps) * prepare_dt(o);
  o.settle_force = 0.0;
  CostSegment c{"settle", o.length, static_cast<double>(sim->particles().owned()), static_cast<double>(steps),
                prepare_dt(o)};
  c.load_before = load_average();
  BedReport rep;
  const auto t = std::chrono::steady_clock::now();
  const double cpu0 = process_cpu_seconds();
  detail::settle_bed(o, *sim, rep);
  c.wall = detail::elapsed_since(t);
  c.cpu_ns_per_particle_step = 1e9 * (process_cpu_seconds() - cpu0) / (c.steps * c.particles);
  c.load_after = load_average();
  c.ns_per_particle_step = 1e9 * c.wall / (c.steps * c.particles);
  return c;
}

/// Shock cost: run_shock (sensors, heights, ceiling) at o.dt_shock on a lattice bed written to
/// `scratch` as a checkpoint, about `steps` steps including a 0.2 ms pre-record.
inline CostSegment measure_shock(ChannelOptions o, double v_p, std::uint64_t steps, const std::filesystem::path& scratch) {
  o.progress = false;
  {
    auto sim = make_channel(o, prepare_dt(o), false);
    fill_lattice(*sim, o);
    std::filesystem::create_directories(scratch.parent_path());
    io::write_checkpoint(*sim, scratch.string());
  }
  o.pre_record = 2e-4;
  o.tail_from = 0.0;
  o.run_time = static_cast<double>(steps) * o.dt_shock - o.pre_record;
  CostSegment c{"shock", o.length};
  c.load_before = load_average();
  const double cpu0 = process_cpu_seconds();
  const ShockResult r = run_shock(o, v_p, scratch);
  const double cpu = process_cpu_seconds() - cpu0;
  c.load_after = load_average();
  c.particles = static_cast<double>(r.particles);
  c.steps = static_cast<double>(r.steps);
  c.dt = r.dt;
  c.wall = r.wall_seconds;
  c.ns_per_particle_step = 1e9 * c.wall / (c.steps * c.particles);
  c.cpu_ns_per_particle_step = 1e9 * cpu / (c.steps * c.particles);
  std::filesystem::remove(scratch);
  return c;
}

/// The small bed of the pour check (README, "Pour protocol"): the table-3 flux into a 5 cm x
/// 2 cm channel filled 3 cm deep, inserted 2-5 cm above the fill at 0.65 m/s downwards so that
/// the grains land at 0.70-0.77 m/s, inside 001's 0.57-0.99 m/s (a fall from rest through 10-30 cm),
/// without 0.3-0.6 s of free fall (affordable at 1e-6 s).
inline ChannelOptions pour_check_options(Packing p, double dt_pour) {
  ChannelOptions o = ChannelOptions::paper();
  o.packing = p;
  o.length = 0.05;
  o.depth = 0.03;
  o.drop_height = 0.02;
  o.region_height = 0.03;
  o.pour_speed = 0.65;
  o.dt_prepare = 1e-5;
  o.dt_pour = dt_pour;
  o.settle_force = 1e-3;  // the quick criterion: enough to compare two pours
  o.settle_speed = 1e-3;
  o.settle_time = 1.0;
  return o;
}

}  // namespace granule::examples::lunar_shock
