#pragma once
// The statistics of a pull that the README quotes, computed from the samples of pull() (paper
// 002 sections 3 and 4). Every definition is here, with the paper's words it makes measurable:
//
//  * peak: the largest drag sample and its intruder height (002 section 3.1: "a high force
//    peak").
//  * drop and reload: on the drag smoothed by a running mean over d/2 of travel, the turning
//    points with a hysteresis of 10 % of the smoothed peak (a turning point is confirmed when
//    the signal has moved back from it by more than that; smaller wiggles are ignored): after
//    the smoothed peak, the next minimum is the drop ("followed by its disappearance") and the
//    next maximum the reload ("and then a new loading step"). The smoothing: at V = 20 mm/s the
//    samples (0.1 mm of travel each) scatter by +-50 % from one to the next (measured on the
//    medium bed), and on the raw samples the turning points were that scatter, 0.1-0.2 mm
//    apart. On the smoothed drag of the medium bed, 10 % found the drop at 15 mm and the reload
//    at 19 mm, 5 % a wiggle of the peak's own decay (at 4 mm), 25 % nothing before 26 mm; on
//    the quick bed 15 % found none.
//  * thirds: the pull split into thirds of its height range; mean and standard deviation of the
//    drag, mean mu* of the bulk and of the walls, mean area of the dragged zone in each.
//  * quiet top layer (002 section 3.1: "in the top layer, these fluctuations vanish ... until a
//    depth of nearly 45 mm from the free surface"): the drop at a sample is how far the drag lies
//    below its largest value over the preceding d/2 of travel (a rupture takes the drag down
//    within a fraction of d; the slow relaxation trend moves it by less than 1 % of the peak over
//    d/2). The top layer starts above the last sample whose drop exceeds q = 2 % of the peak;
//    its thickness is the mean surface height minus that sample's height (also given for q = 1 %
//    and 5 %, to show how much the number depends on q). Drops are counted only while the
//    intruder's axis is at least 2 d below the mean surface: above that it carries its last
//    layer of disks, which roll off it as it emerges (drops of a few disk weights, not
//    ruptures of force chains; measured on the quick bed up to the very surface). A layer
//    without any drop is reported as 2 d thick at least.
//  * spectrum and the d/2 spacing (002 section 3.1: "the peaks are spaced apart of
//    approximately a grain radius (d/2)"): over the fluctuating part of the pull, from the reload
//    to the start of the quiet layer (the whole pull after the peak when that part is shorter
//    than 8 d), the drag minus its running mean over 4 d of travel (which removes the relaxation
//    trend and leaves wavelengths below 4 d nearly untouched), Hann window, one-sided PSD
//    against the spatial frequency 1/lambda (analysis/spectrum.hpp with the sample's travel as
//    the interval). Test of a peak at lambda = d/2: the mean PSD in the half-octave band around
//    d/2 over the geometric mean of the two neighbouring half-octave bands, R. A smooth (power-
//    law) spectrum gives R = 1 exactly; R stands out when it exceeds the one-sided 95 % point of
//    R under that null hypothesis, exp(1.645 s) with s^2 = 1.94 (1/n_0 + (1/n_- + 1/n_+) / 4),
//    n the bins of each band: a Hann periodogram bin has unit relative variance, and neighbour
//    bins correlate by 4/9 (and 1/36 two apart), so a band mean of n bins has a relative
//    variance of 1.94 / n.
//    Also given: the median spacing of successive drag maxima with a hysteresis of 2 % of the
//    peak in the same part, and the wavelength of the largest f PSD (power per octave) among
//    third-octave bands between d/4 and 4 d.
//  * mu* (002 section 4, fig. 13): mean of the bulk and the wall values over the samples with the
//    intruder below H1 = (W - L)/2 tan 60 deg (section 3.2 c), above H1 up to the mean surface,
//    and over the last 10 % of the pull below the surface ("both values ... decrease toward
//    0.24"); the mean fraction of bulk contacts at the Coulomb threshold (fig. 12c: "less than
//    20 % of the contacts").
//  * cone (002 section 3.2 c: "during loading phases ... the opening angle of the cone is almost
//    constant with time and equals 60 deg"; fig. 8 shows the fields "during loading phases just
//    before the rupture of force chains"): median and quartiles of the measured inclination of
//    the mobile zone's edges (scene.hpp, FieldProbe) at the drag's maxima (turning points with a
//    hysteresis of q = 2 % of the peak: each is followed by a drop, a rupture) below the quiet
//    layer; also the median over all loading samples (drag above the previous sample's), which
//    on the medium bed was 5-7 deg steeper: the zone is widest just before a rupture. The wall
//    bands' mobile fraction over the loading samples below and above H1 (section 4: "above H1
//    ... the mobility of particles is lost in the vicinity of the walls").
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <granule/analysis/spectrum.hpp>

#include "scene.hpp"

namespace granule::examples::pull_out {

/// Thresholds of the statistics (file comment).
struct StatisticsOptions {
  double reload_hysteresis = 0.10;  ///< of the smoothed peak, for the drop and the reload [-]
  double reload_smoothing = 0.5;    ///< running mean before the drop and the reload / d [-]
  double quiet_fraction = 0.02;     ///< q: drops above q x peak are fluctuations [-]
  double drop_window = 0.5;         ///< travel over which a drop is measured / d [-]
  double emergence = 2.0;           ///< drops are not counted within this depth / d below the surface [-]
  double detrend_window = 4.0;      ///< running mean removed before the spectrum / d [-]
  double min_segment = 8.0;         ///< shortest fluctuating part used for the spectrum / d [-]
};

/// A turning point of a signal.
struct TurningPoint {
  std::size_t index = 0;
  bool maximum = false;
};

/// Alternating maxima and minima of x: a maximum is confirmed once x has fallen more than `delta`
/// below it, a minimum once x has risen more than `delta` above it (the last, unconfirmed
/// extreme is not returned).
inline std::vector<TurningPoint> turning_points(const std::vector<double>& x, double delta) {
  std::vector<TurningPoint> out;
  if (x.empty()) return out;
  int dir = 0;  // -1: after a maximum, looking for a minimum; +1: the reverse; 0: not known yet
  std::size_t hi = 0, lo = 0;  // candidate extremes since the last turning point
  for (std::size_t k = 1; k < x.size(); ++k) {
    if (dir != -1 && x[k] > x[hi]) hi = k;
    if (dir != +1 && x[k] < x[lo]) lo = k;
    if (dir != -1 && x[k] < x[hi] - delta) {
      out.push_back({hi, true});
      dir = -1;
      lo = k;
    } else if (dir != +1 && x[k] > x[lo] + delta) {
      out.push_back({lo, false});
      dir = +1;
      hi = k;
    }
  }
  return out;
}

/// x minus its centred running mean over `window` samples (odd; shorter at the ends).
inline std::vector<double> minus_running_mean(const std::vector<double>& x, std::size_t window) {
  const std::size_t half = window / 2;
  std::vector<double> prefix(x.size() + 1, 0.0);
  for (std::size_t k = 0; k < x.size(); ++k) prefix[k + 1] = prefix[k] + x[k];
  std::vector<double> out(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const std::size_t a = k >= half ? k - half : 0, b = std::min(x.size(), k + half + 1);
    out[k] = x[k] - (prefix[b] - prefix[a]) / static_cast<double>(b - a);
  }
  return out;
}

/// Mean PSD of the bins with a spatial frequency in [f_lo, f_hi).
struct BandPower {
  double f_lo = 0.0, f_hi = 0.0;  ///< [1/m]
  double psd = std::numeric_limits<double>::quiet_NaN();  ///< [N^2 m]
  std::size_t bins = 0;
};

inline BandPower band_power(const analysis::PowerSpectrum& s, double f_lo, double f_hi) {
  BandPower b{f_lo, f_hi};
  double sum = 0.0;
  for (std::size_t k = 1; k < s.frequency.size(); ++k)
    if (s.frequency[k] >= f_lo && s.frequency[k] < f_hi) {
      sum += s.psd[k];
      ++b.bins;
    }
  if (b.bins > 0) b.psd = sum / static_cast<double>(b.bins);
  return b;
}

/// The test of a spectral peak at one wavelength (file comment).
struct PeakTest {
  double wavelength = 0.0;  ///< [m]
  BandPower band, longer, shorter;
  double ratio = std::numeric_limits<double>::quiet_NaN();     ///< R [-]
  double critical = std::numeric_limits<double>::quiet_NaN();  ///< 95 % point of R without a peak [-]
  bool testable = false;    ///< every band has >= 2 bins and lies below the Nyquist frequency
  bool stands_out = false;  ///< testable and R > critical
};

inline PeakTest peak_test(const analysis::PowerSpectrum& s, double wavelength) {
  PeakTest t;
  t.wavelength = wavelength;
  const double f0 = 1.0 / wavelength, q = std::pow(2.0, 0.25);
  t.band = band_power(s, f0 / q, f0 * q);
  t.longer = band_power(s, f0 / (q * q * q), f0 / q);
  t.shorter = band_power(s, f0 * q, f0 * q * q * q);
  const double nyquist = s.frequency.empty() ? 0.0 : s.frequency.back();
  t.testable = t.band.bins >= 2 && t.longer.bins >= 2 && t.shorter.bins >= 2 && f0 * q * q * q <= nyquist * (1.0 + 1e-9);
  if (t.band.bins > 0 && t.longer.bins > 0 && t.shorter.bins > 0) {
    t.ratio = t.band.psd / std::sqrt(t.longer.psd * t.shorter.psd);
    const double var = 1.94 * (1.0 / t.band.bins + 0.25 * (1.0 / t.longer.bins + 1.0 / t.shorter.bins));
    t.critical = std::exp(1.645 * std::sqrt(var));
  }
  t.stands_out = t.testable && t.ratio > t.critical;
  return t;
}

/// Statistics of one third of the pull.
struct Third {
  double h_lo = 0.0, h_hi = 0.0;  ///< [m]
  std::size_t samples = 0;
  double drag_mean = 0.0, drag_std = 0.0;  ///< [N]
  double mu_bulk = 0.0, mu_wall = 0.0;     ///< [-]
  double dragged_area = 0.0;               ///< mean area with v* > 0.75 above the intruder [m^2]
};

/// Everything the program prints and the study stores (file comment).
struct DragStatistics {
  double nan = std::numeric_limits<double>::quiet_NaN();
  double surface = nan;        ///< mean surface [m]
  double h_first = nan, h_last = nan;  ///< heights of the first and last sample [m]
  double column_weight = nan;  ///< M g L / W [N]
  double h1 = nan;             ///< 002's H1 for this cell (beta = 60 deg) [m]
  double drag_mean = nan, drag_std = nan;  ///< over the whole pull [N]
  double peak = nan, peak_height = nan;    ///< largest sample [N], [m]
  double smoothed_peak = nan, smoothed_peak_height = nan;  ///< of the d/2 running mean [N], [m]
  double drop = nan, drop_height = nan;    ///< first minimum after the smoothed peak [N], [m]
  double reload = nan, reload_height = nan;  ///< the maximum after it [N], [m]
  std::array<Third, 3> thirds{};
  // quiet top layer for q = 1 %, 2 % (options.quiet_fraction), 5 %
  std::array<double, 3> quiet_q{0.01, 0.02, 0.05};
  std::array<double, 3> last_drop_height{nan, nan, nan};  ///< [m]
  std::array<double, 3> quiet_thickness{nan, nan, nan};   ///< [m]
  // spectrum
  double segment_lo = nan, segment_hi = nan;  ///< heights of the part used [m]
  bool segment_whole = false;  ///< the fluctuating part was too short: the whole pull after the peak
  double sample_travel = nan;  ///< [m]
  analysis::PowerSpectrum spectrum;  ///< against the spatial frequency 1/lambda [1/m], PSD [N^2 m]
  std::vector<BandPower> bands;      ///< third-octave bands from lambda = 4 d down to the Nyquist wavelength
  PeakTest half_d;                   ///< the test at lambda = d/2
  double dominant_wavelength = nan;  ///< of the largest f PSD among the bands in [d/4, 4 d] [m]
  double event_spacing = nan;        ///< median distance between successive maxima [m]
  std::size_t events = 0;            ///< maxima counted
  // mu*
  double mu_bulk_below_h1 = nan, mu_wall_below_h1 = nan;
  double mu_bulk_above_h1 = nan, mu_wall_above_h1 = nan;
  double mu_bulk_end = nan, mu_wall_end = nan;  ///< last 10 % of the pull below the surface
  double sliding_bulk = nan;                    ///< mean fraction at the Coulomb threshold
  // zones
  double cone_angle = nan, cone_angle_p25 = nan, cone_angle_p75 = nan;  ///< at the drag maxima [deg]
  std::size_t cone_samples = 0;       ///< maxima with a measured cone
  double cone_angle_loading = nan;    ///< median over all loading samples [deg]
  double wall_mobility_below_h1 = nan, wall_mobility_above_h1 = nan;
};

namespace stats_detail {
inline double mean_finite(const std::vector<double>& v) {
  double s = 0.0;
  std::size_t n = 0;
  for (double x : v)
    if (std::isfinite(x)) {
      s += x;
      ++n;
    }
  return n > 0 ? s / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}
/// q-quantile (linear interpolation) of the finite values.
inline double quantile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (v[hi] - v[lo]) * (pos - static_cast<double>(lo));
}
}  // namespace stats_detail

/// Statistics of the pull `r` of scene `s` (file comment).
inline DragStatistics drag_statistics(const PullScene& s, const PullResult& r, const StatisticsOptions& o = {}) {
  using stats_detail::mean_finite;
  DragStatistics st;
  const auto& x = r.samples;
  const PullParams& p = s.params;
  const double d = p.mean_diameter;
  st.surface = s.packing.surface;
  st.column_weight = s.column_weight();
  st.h1 = h1_height(p);
  st.quiet_q[1] = o.quiet_fraction;
  if (x.size() < 4) return st;
  const std::size_t n = x.size();
  std::vector<double> f(n), h(n);
  for (std::size_t k = 0; k < n; ++k) {
    f[k] = x[k].drag;
    h[k] = x[k].height;
  }
  st.h_first = h.front();
  st.h_last = h.back();
  st.sample_travel = (h.back() - h.front()) / static_cast<double>(n - 1);
  {
    double m = 0.0, v = 0.0;
    for (double y : f) m += y / static_cast<double>(n);
    for (double y : f) v += (y - m) * (y - m) / static_cast<double>(n);
    st.drag_mean = m;
    st.drag_std = std::sqrt(v);
  }
  const auto k_peak = static_cast<std::size_t>(std::max_element(f.begin(), f.end()) - f.begin());
  st.peak = f[k_peak];
  st.peak_height = h[k_peak];

  // Drop and reload: turning points after the peak of the d/2 running mean, with a hysteresis
  // of 10 % of that peak.
  {
    auto window = static_cast<std::size_t>(std::lround(o.reload_smoothing * d / st.sample_travel));
    window += 1 - window % 2;
    const auto fluct = minus_running_mean(f, window);
    std::vector<double> smooth(n);
    for (std::size_t k = 0; k < n; ++k) smooth[k] = f[k] - fluct[k];
    const auto k_sp = static_cast<std::size_t>(std::max_element(smooth.begin(), smooth.end()) - smooth.begin());
    st.smoothed_peak = smooth[k_sp];
    st.smoothed_peak_height = h[k_sp];
    const std::vector<double> tail(smooth.begin() + static_cast<std::ptrdiff_t>(k_sp), smooth.end());
    const auto tp = turning_points(tail, o.reload_hysteresis * st.smoothed_peak);
    std::size_t i = 0;
    while (i < tp.size() && tp[i].maximum) ++i;  // the peak itself
    if (i < tp.size()) {
      st.drop = tail[tp[i].index];
      st.drop_height = h[k_sp + tp[i].index];
      if (i + 1 < tp.size()) {
        st.reload = tail[tp[i + 1].index];
        st.reload_height = h[k_sp + tp[i + 1].index];
      }
    }
  }

  // Thirds of the height range.
  const double span = st.h_last - st.h_first;
  for (int t = 0; t < 3; ++t) {
    Third& th = st.thirds[static_cast<std::size_t>(t)];
    th.h_lo = st.h_first + span * t / 3.0;
    th.h_hi = st.h_first + span * (t + 1) / 3.0;
    std::vector<double> ft, mb, mw, da;
    for (std::size_t k = 0; k < n; ++k) {
      const bool in = h[k] >= th.h_lo && (t == 2 ? h[k] <= th.h_hi : h[k] < th.h_hi);
      if (!in) continue;
      ft.push_back(f[k]);
      mb.push_back(x[k].mu_star_bulk);
      mw.push_back(x[k].mu_star_wall);
      da.push_back(x[k].dragged_area);
    }
    th.samples = ft.size();
    th.drag_mean = mean_finite(ft);
    double v = 0.0;
    for (double y : ft) v += (y - th.drag_mean) * (y - th.drag_mean);
    th.drag_std = ft.empty() ? st.nan : std::sqrt(v / static_cast<double>(ft.size()));
    th.mu_bulk = mean_finite(mb);
    th.mu_wall = mean_finite(mw);
    th.dragged_area = mean_finite(da);
  }

  // Drops: below the largest drag of the preceding d/2 of travel; the quiet layer above the last
  // drop larger than q x peak (below the mean surface).
  std::vector<double> drop(n, 0.0);
  {
    std::size_t a = 0;
    for (std::size_t k = 0; k < n; ++k) {
      while (h[a] < h[k] - o.drop_window * d) ++a;
      double m = f[k];
      for (std::size_t j = a; j <= k; ++j) m = std::max(m, f[j]);
      drop[k] = m - f[k];
    }
  }
  for (std::size_t q = 0; q < 3; ++q) {
    double last = st.h_first;
    for (std::size_t k = 0; k < n; ++k)
      if (h[k] <= st.surface - o.emergence * d && drop[k] > st.quiet_q[q] * st.peak) last = h[k];
    st.last_drop_height[q] = last;
    st.quiet_thickness[q] = st.surface - last;
  }

  // Spectrum of the fluctuating part.
  {
    double lo = std::isfinite(st.reload_height) ? st.reload_height : st.peak_height;
    double hi = st.last_drop_height[1];
    if (!(hi - lo >= o.min_segment * d)) {
      lo = st.peak_height;
      hi = std::min(st.surface, st.h_last);
      st.segment_whole = true;
    }
    st.segment_lo = lo;
    st.segment_hi = hi;
    std::vector<double> seg;
    for (std::size_t k = 0; k < n; ++k)
      if (h[k] >= lo && h[k] <= hi) seg.push_back(f[k]);
    if (seg.size() >= 16) {
      auto window = static_cast<std::size_t>(std::lround(o.detrend_window * d / st.sample_travel));
      window += 1 - window % 2;
      const auto fluct = minus_running_mean(seg, std::max<std::size_t>(window, 3));
      st.spectrum = analysis::power_spectrum(fluct, st.sample_travel, analysis::SpectralWindow::Hann);
      st.half_d = peak_test(st.spectrum, 0.5 * d);
      const double nyquist = st.spectrum.frequency.back();
      const double third = std::pow(2.0, 1.0 / 6.0);
      double best = -1.0;
      for (int k = -9; k <= 18; ++k) {
        const double lam = 0.5 * d * std::pow(2.0, k / 3.0);  // band centres, d/2 among them
        if (lam > 4.0 * d * (1.0 + 1e-9)) continue;
        const double fc = 1.0 / lam;
        if (fc * third > nyquist) continue;
        const BandPower b = band_power(st.spectrum, fc / third, fc * third);
        if (b.bins == 0) continue;
        st.bands.push_back(b);
        if (lam >= 0.25 * d * (1.0 - 1e-9) && fc * b.psd > best) {
          best = fc * b.psd;
          st.dominant_wavelength = lam;
        }
      }
      std::sort(st.bands.begin(), st.bands.end(), [](const BandPower& a, const BandPower& b) { return a.f_lo < b.f_lo; });
      const auto tp = turning_points(seg, o.quiet_fraction * st.peak);
      std::vector<double> peaks;
      std::size_t k0 = 0;
      while (k0 < n && h[k0] < lo) ++k0;
      for (const auto& t : tp)
        if (t.maximum) peaks.push_back(h[k0 + t.index]);
      st.events = peaks.size();
      std::vector<double> gaps;
      for (std::size_t k = 1; k < peaks.size(); ++k) gaps.push_back(peaks[k] - peaks[k - 1]);
      st.event_spacing = stats_detail::quantile(gaps, 0.5);
    }
  }

  // mu* below and above H1, at the end of the pull, and sliding contacts.
  {
    std::vector<double> bb, bw, ab, aw, eb, ew, sl;
    const double end_from = st.surface - 0.1 * (st.surface - st.h_first);
    for (std::size_t k = 0; k < n; ++k) {
      sl.push_back(x[k].sliding_bulk);
      if (h[k] > st.surface) continue;
      (h[k] < st.h1 ? bb : ab).push_back(x[k].mu_star_bulk);
      (h[k] < st.h1 ? bw : aw).push_back(x[k].mu_star_wall);
      if (h[k] >= end_from) {
        eb.push_back(x[k].mu_star_bulk);
        ew.push_back(x[k].mu_star_wall);
      }
    }
    st.mu_bulk_below_h1 = mean_finite(bb);
    st.mu_wall_below_h1 = mean_finite(bw);
    st.mu_bulk_above_h1 = mean_finite(ab);
    st.mu_wall_above_h1 = mean_finite(aw);
    st.mu_bulk_end = mean_finite(eb);
    st.mu_wall_end = mean_finite(ew);
    st.sliding_bulk = mean_finite(sl);
  }

  // Cone at the drag's maxima (just before a rupture) and over the loading samples; wall
  // mobility over the loading samples.
  {
    std::vector<double> peaks, loading, wb, wa;
    for (const auto& t : turning_points(f, o.quiet_fraction * st.peak))
      if (t.maximum && h[t.index] < st.last_drop_height[1]) peaks.push_back(x[t.index].cone_angle);
    for (std::size_t k = 1; k < n; ++k) {
      if (!(f[k] > f[k - 1]) || h[k] > st.surface) continue;
      if (h[k] < st.last_drop_height[1]) loading.push_back(x[k].cone_angle);
      (h[k] < st.h1 ? wb : wa).push_back(x[k].wall_mobility);
    }
    st.cone_samples = static_cast<std::size_t>(
        std::count_if(peaks.begin(), peaks.end(), [](double v) { return std::isfinite(v); }));
    st.cone_angle = stats_detail::quantile(peaks, 0.5);
    st.cone_angle_p25 = stats_detail::quantile(peaks, 0.25);
    st.cone_angle_p75 = stats_detail::quantile(peaks, 0.75);
    st.cone_angle_loading = stats_detail::quantile(loading, 0.5);
    st.wall_mobility_below_h1 = mean_finite(wb);
    st.wall_mobility_above_h1 = mean_finite(wa);
  }
  return st;
}

/// One row of the downsampled pull (bins of intruder height).
struct ProfileRow {
  double height = 0.0;  ///< bin centre [m]
  std::size_t samples = 0;
  double drag = 0.0, drag_min = 0.0, drag_max = 0.0;  ///< [N]
  double mu_bulk = 0.0, mu_wall = 0.0, sliding = 0.0;  ///< [-]
  double cone_angle = 0.0;     ///< median over the bin's loading samples [deg]
  double wall_mobility = 0.0;  ///< [-]
  double dragged_area = 0.0;   ///< [m^2]
};

/// The samples binned by intruder height in bins of `bin` [m] from the first sample's height.
inline std::vector<ProfileRow> binned_profile(const PullResult& r, double bin) {
  std::vector<ProfileRow> out;
  const auto& x = r.samples;
  if (x.empty()) return out;
  const double h0 = x.front().height;
  std::size_t k = 0;
  while (k < x.size()) {
    const auto b = static_cast<long>(std::floor((x[k].height - h0) / bin));
    ProfileRow row;
    row.height = h0 + (static_cast<double>(b) + 0.5) * bin;
    std::vector<double> drag, mb, mw, sl, cone, wm, da;
    for (; k < x.size() && static_cast<long>(std::floor((x[k].height - h0) / bin)) == b; ++k) {
      drag.push_back(x[k].drag);
      mb.push_back(x[k].mu_star_bulk);
      mw.push_back(x[k].mu_star_wall);
      sl.push_back(x[k].sliding_bulk);
      if (k > 0 && x[k].drag > x[k - 1].drag) cone.push_back(x[k].cone_angle);
      wm.push_back(x[k].wall_mobility);
      da.push_back(x[k].dragged_area);
    }
    row.samples = drag.size();
    row.drag = stats_detail::mean_finite(drag);
    row.drag_min = *std::min_element(drag.begin(), drag.end());
    row.drag_max = *std::max_element(drag.begin(), drag.end());
    row.mu_bulk = stats_detail::mean_finite(mb);
    row.mu_wall = stats_detail::mean_finite(mw);
    row.sliding = stats_detail::mean_finite(sl);
    row.cone_angle = stats_detail::quantile(cone, 0.5);
    row.wall_mobility = stats_detail::mean_finite(wm);
    row.dragged_area = stats_detail::mean_finite(da);
    out.push_back(row);
  }
  return out;
}

}  // namespace granule::examples::pull_out
