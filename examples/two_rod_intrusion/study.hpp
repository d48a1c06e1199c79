#pragma once
// The paper-scale study of two_rod_intrusion (issue 25): an ensemble of independently poured
// beds, one intrusion per (bed, gap), each written to its own small CSV file under the results
// directory together with the commit, date and machine, so that a rerun skips what is done and
// a killed run loses at most the case it was running. From the files it aggregates W(s/d) over
// the beds (mean and standard error), the peak gap with a bootstrap interval, and the peak over
// the plateau (the mean W at s/d >= 11, the paper's "large separation").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "scene.hpp"

#include "../common/csv_fields.hpp"
#include "../common/provenance.hpp"

namespace granule::examples::two_rod {

using examples::Provenance;
using examples::provenance_now;

/// One intrusion of the study (one bed, one gap, or the single rod: gap_over_d < 0).
struct CaseResult {
  std::string shape;
  int seed = 0;
  double gap_over_d = -1.0;  ///< s/d; -1 for the single rod
  double work = 0.0;         ///< W [J]
  double body_work = 0.0;    ///< drive's work [J]
  double peak_force = 0.0;   ///< [N]
  double slope = 0.0;        ///< dF/dz over [0.2 z_f, z_f] [N/m]
  double very_strong = 0.0;  ///< pair contacts with f_n > 6 <f_n> at half depth
  double contacts = 0.0;     ///< pair contacts at half depth
  double mean_fn = 0.0;      ///< <f_n> at half depth [N]
  double particles = 0.0;
  double packing = 0.0;      ///< interior packing fraction of the bed [-]
  double surface = 0.0;      ///< [m]
  double wall_time = 0.0;    ///< [s]
  double ns_per_particle_step = 0.0;
  Provenance prov;
};

inline std::string gap_label(double g) {
  if (g < 0.0) return "single";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "s%g", g);
  return buf;
}

inline std::string case_stem(const std::string& shape, int seed, double g) {
  return shape + "_bed" + std::to_string(seed) + "_" + gap_label(g);
}

namespace study_detail {
constexpr const char* kHeader =
    "shape,bed_seed,gap_over_d,work [J],body_work [J],peak_force [N],slope [N/m],very_strong,"
    "pair_contacts,mean_fn [N],particles,packing_fraction,surface [m],wall_time [s],"
    "ns_per_particle_step,commit,date,machine";


/// Writes `text` to `file` through a temporary and a rename: the file exists whole or not at all.
inline void write_atomically(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::create_directories(file.parent_path());
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
    if (!o) throw IoError("two_rod study: cannot open '" + tmp.string() + "' for writing");
    o << text;
    o.flush();
    if (!o) throw IoError("two_rod study: writing '" + tmp.string() + "' failed");
  }
  std::filesystem::rename(tmp, file);
}

inline std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}
}  // namespace study_detail

inline void write_case(const std::filesystem::path& file, const CaseResult& c) {
  using study_detail::num;
  std::ostringstream s;
  s << study_detail::kHeader << "\n"
    << c.shape << "," << c.seed << "," << num(c.gap_over_d) << "," << num(c.work) << "," << num(c.body_work) << ","
    << num(c.peak_force) << "," << num(c.slope) << "," << num(c.very_strong) << "," << num(c.contacts) << ","
    << num(c.mean_fn) << "," << num(c.particles) << "," << num(c.packing) << "," << num(c.surface) << ","
    << num(c.wall_time) << "," << num(c.ns_per_particle_step) << "," << csv_quoted(c.prov.commit) << ","
    << csv_quoted(c.prov.date) << "," << csv_quoted(c.prov.machine) << "\n";
  study_detail::write_atomically(file, s.str());
}

/// Reads a case file written by write_case; nullopt if it is missing or not complete.
inline std::optional<CaseResult> read_case(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string header, row;
  if (!in || !std::getline(in, header) || !std::getline(in, row)) return std::nullopt;
  if (header != study_detail::kHeader) return std::nullopt;
  const auto f = csv_split(row);
  if (f.size() != 18) return std::nullopt;
  CaseResult c;
  try {
    c.shape = f[0];
    c.seed = std::stoi(f[1]);
    double* numeric[] = {&c.gap_over_d, &c.work, &c.body_work, &c.peak_force, &c.slope, &c.very_strong,
                         &c.contacts, &c.mean_fn, &c.particles, &c.packing, &c.surface, &c.wall_time,
                         &c.ns_per_particle_step};
    for (std::size_t k = 0; k < 13; ++k) *numeric[k] = std::stod(f[2 + k]);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  c.prov = {f[15], f[16], f[17]};
  return c;
}

/// W over the beds at one gap.
struct GapStats {
  double gap_over_d = 0.0;
  int beds = 0;
  double work_mean = 0.0, work_se = 0.0;              ///< [J]
  double very_strong_mean = 0.0, very_strong_se = 0.0;
  double slope_mean = 0.0;                            ///< [N/m]
};

/// Peak of the mean W(s/d), with a bootstrap over beds.
struct PeakStats {
  double gap = 0.0;            ///< s/d of the largest mean W
  double gap_parabola = 0.0;   ///< vertex of the parabola through the peak and its neighbours
  double gap_lo = 0.0, gap_hi = 0.0;  ///< 16th and 84th percentile of the bootstrap peak gap
  double work = 0.0;           ///< mean W at the peak [J]
  double plateau = 0.0;        ///< mean W over the gaps >= plateau_from [J]
  double ratio = 0.0;          ///< work / plateau
  double ratio_lo = 0.0, ratio_hi = 0.0;  ///< bootstrap 16th / 84th percentile
  double single_two = 0.0;     ///< 2 x the mean single-rod W [J] (NaN without single runs)
  int beds = 0;                ///< beds with every gap done
  std::vector<double> peak_per_bed;  ///< s/d of the largest W of each complete bed
};

inline double mean_of(const std::vector<double>& v) {
  return v.empty() ? std::nan("") : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}
inline double se_of(const std::vector<double>& v) {
  if (v.size() < 2) return std::nan("");
  const double m = mean_of(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));
}

/// Statistics of `cases` (one shape) over the gaps in `gaps`.
inline std::vector<GapStats> gap_stats(const std::vector<CaseResult>& cases, const std::vector<double>& gaps) {
  std::vector<GapStats> out;
  for (double g : gaps) {
    std::vector<double> w, vs, sl;
    for (const auto& c : cases)
      if (c.gap_over_d == g) {
        w.push_back(c.work);
        vs.push_back(c.very_strong);
        sl.push_back(c.slope);
      }
    if (w.empty()) continue;
    out.push_back({g, static_cast<int>(w.size()), mean_of(w), se_of(w), mean_of(vs), se_of(vs), mean_of(sl)});
  }
  return out;
}

/// Peak statistics over the beds that have every gap of `gaps` done; the bootstrap draws beds
/// with replacement (each bed keeps its whole W(s/d): one pour serves every gap).
inline PeakStats peak_stats(const std::vector<CaseResult>& cases, const std::vector<double>& gaps,
                            double plateau_from = 11.0, int resamples = 4000) {
  PeakStats p;
  std::map<int, std::map<double, double>> by_bed;
  std::vector<double> singles;
  for (const auto& c : cases) {
    if (c.gap_over_d < 0.0) {
      singles.push_back(c.work);
    } else {
      by_bed[c.seed][c.gap_over_d] = c.work;
    }
  }
  p.single_two = singles.empty() ? std::nan("") : 2.0 * mean_of(singles);
  std::vector<std::vector<double>> beds;  // W per gap, complete beds only
  for (const auto& [seed, m] : by_bed) {
    std::vector<double> w;
    for (double g : gaps) {
      const auto it = m.find(g);
      if (it == m.end()) break;
      w.push_back(it->second);
    }
    if (w.size() == gaps.size()) beds.push_back(w);
  }
  p.beds = static_cast<int>(beds.size());
  const double nan = std::nan("");
  if (beds.empty()) {
    p.gap = p.gap_parabola = p.gap_lo = p.gap_hi = p.work = p.plateau = p.ratio = p.ratio_lo = p.ratio_hi = nan;
    return p;
  }
  const std::size_t ng = gaps.size();
  auto summarise = [&](const std::vector<std::size_t>& pick, double& gap, double& ratio, double* work,
                       double* plateau, std::size_t* kmax) {
    std::vector<double> mean(ng, 0.0);
    for (std::size_t b : pick)
      for (std::size_t k = 0; k < ng; ++k) mean[k] += beds[b][k] / static_cast<double>(pick.size());
    const auto k = static_cast<std::size_t>(std::max_element(mean.begin(), mean.end()) - mean.begin());
    double plat = 0.0;
    int n = 0;
    for (std::size_t j = 0; j < ng; ++j)
      if (gaps[j] >= plateau_from) {
        plat += mean[j];
        ++n;
      }
    plat = n > 0 ? plat / n : nan;
    gap = gaps[k];
    ratio = mean[k] / plat;
    if (work) *work = mean[k];
    if (plateau) *plateau = plat;
    if (kmax) *kmax = k;
    return mean;
  };
  std::vector<std::size_t> all(beds.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  std::size_t kmax = 0;
  const auto mean = summarise(all, p.gap, p.ratio, &p.work, &p.plateau, &kmax);
  p.gap_parabola = p.gap;
  if (kmax > 0 && kmax + 1 < ng) {
    // Vertex of the parabola through three points with unequal spacing.
    const double x0 = gaps[kmax - 1], x1 = gaps[kmax], x2 = gaps[kmax + 1];
    const double y0 = mean[kmax - 1], y1 = mean[kmax], y2 = mean[kmax + 1];
    const double den = (x0 - x1) * (x0 - x2) * (x1 - x2);
    const double a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den;
    const double b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / den;
    if (a < 0.0) p.gap_parabola = std::clamp(-b / (2.0 * a), x0, x2);
  }
  for (const auto& w : beds)
    p.peak_per_bed.push_back(gaps[static_cast<std::size_t>(std::max_element(w.begin(), w.end()) - w.begin())]);
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<std::size_t> pick_bed(0, beds.size() - 1);
  std::vector<double> g_s, r_s;
  for (int r = 0; r < resamples; ++r) {
    std::vector<std::size_t> pick(beds.size());
    for (auto& b : pick) b = pick_bed(rng);
    double g = 0.0, ratio = 0.0;
    summarise(pick, g, ratio, nullptr, nullptr, nullptr);
    g_s.push_back(g);
    r_s.push_back(ratio);
  }
  auto pct = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    const double pos = q * static_cast<double>(v.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const auto hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (v[hi] - v[lo]) * (pos - static_cast<double>(lo));
  };
  p.gap_lo = pct(g_s, 0.16);
  p.gap_hi = pct(g_s, 0.84);
  p.ratio_lo = pct(r_s, 0.16);
  p.ratio_hi = pct(r_s, 0.84);
  return p;
}

}  // namespace granule::examples::two_rod
