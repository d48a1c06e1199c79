#pragma once
// Wave-front tracking from sensor time series (paper 001 section 2.8.3, fig. 6).
//
// Arrival time at one sensor: the time of the first local maximum of the signal that exceeds a
// threshold — by default `relative_threshold` × the initial level (001: "one order of magnitude
// greater than the initial average particle force", factor 10), the initial level being the
// mean of the first `baseline_samples` samples; or an absolute threshold. A local maximum is a
// sample strictly above its predecessor and not below its successor (the first sample of a
// plateau). Optionally the peak time is refined by the vertex of the parabola through the
// maximum and its two neighbours (uniform or non-uniform sampling).
//
// Front speed: least-squares line position = x0 + c · t through (arrival time, sensor position);
// points whose residual exceeds `reject_sigmas` (001: 2) times the residual standard deviation
// s = √(Σ r² / (n − 2)) of this first fit are rejected, and the line is fitted again. The
// speed c comes with its standard uncertainty from the regression,
//   u(c) = s / √(Σ (t − t̄)²)
// (ordinary least squares, e.g. Taylor 1997, "An Introduction to Error Analysis", eq. 8.17).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include "granule/core/error.hpp"

namespace granule::analysis {

/// One sensor: its position along the propagation axis and a sampled signal.
struct SensorSeries {
  double position = 0.0;        ///< [m]
  std::vector<double> time;     ///< sample times, increasing [s]
  std::vector<double> signal;   ///< sampled signal (e.g. mean particle force [N])
};

/// How an arrival is detected.
struct ArrivalSettings {
  double relative_threshold = 10.0;          ///< factor on the initial level (001: 10) [-]
  std::optional<double> absolute_threshold;  ///< if set, used instead of the relative one
  std::size_t baseline_samples = 1;          ///< samples averaged for the initial level
  bool refine_parabolic = false;             ///< sub-sample peak time by a parabola
};

/// Time of the first local maximum above the threshold, or nothing if there is none [s].
inline std::optional<double> arrival_time(const SensorSeries& s, const ArrivalSettings& opt = {}) {
  require(s.time.size() == s.signal.size(), "arrival_time", "signal.size()",
          static_cast<double>(s.signal.size()), "time.size()");
  require(opt.baseline_samples >= 1, "arrival_time", "baseline_samples",
          static_cast<double>(opt.baseline_samples), "[1, inf)");
  const std::size_t n = s.signal.size();
  if (n < 3 || opt.baseline_samples > n) return std::nullopt;
  double threshold;
  if (opt.absolute_threshold) {
    threshold = *opt.absolute_threshold;
  } else {
    double base = 0.0;
    for (std::size_t k = 0; k < opt.baseline_samples; ++k) base += s.signal[k];
    base /= static_cast<double>(opt.baseline_samples);
    threshold = opt.relative_threshold * base;
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double y = s.signal[k];
    if (!(y > threshold) || !(y > s.signal[k - 1]) || !(y >= s.signal[k + 1])) continue;
    if (!opt.refine_parabolic) return s.time[k];
    // Vertex of the parabola through (t_{k-1}, y_{k-1}), (t_k, y_k), (t_{k+1}, y_{k+1}).
    const double t0 = s.time[k - 1] - s.time[k];
    const double t2 = s.time[k + 1] - s.time[k];
    const double d0 = (s.signal[k - 1] - y) / t0;  // slopes of the two chords
    const double d2 = (s.signal[k + 1] - y) / t2;
    const double curvature = (d2 - d0) / (t2 - t0);  // leading coefficient
    if (!(curvature < 0.0)) return s.time[k];
    const double slope_at_k = d0 - curvature * t0;   // derivative of the parabola at t_k
    const double shift = -slope_at_k / (2.0 * curvature);
    return s.time[k] + std::clamp(shift, t0, t2);
  }
  return std::nullopt;
}

/// Least-squares straight line y = intercept + slope · x with standard uncertainties.
struct LineFit {
  double slope = 0.0;
  double intercept = 0.0;
  double slope_uncertainty = 0.0;      ///< u(slope)
  double intercept_uncertainty = 0.0;  ///< u(intercept)
  double residual_sigma = 0.0;         ///< s = √(Σ r² / (n − 2))
  std::size_t points = 0;
};

/// Ordinary least-squares fit of y on x (at least 3 points, x not all equal).
inline LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  require(x.size() == y.size(), "fit_line", "y.size()", static_cast<double>(y.size()),
          "x.size()");
  require(x.size() >= 3, "fit_line", "points", static_cast<double>(x.size()), "[3, inf)");
  const double n = static_cast<double>(x.size());
  double mx = 0.0;
  double my = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    mx += x[k];
    my += y[k];
  }
  mx /= n;
  my /= n;
  double sxx = 0.0;
  double sxy = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
  }
  require(sxx > 0.0, "fit_line", "spread of x", sxx, "(0, inf)");
  LineFit f;
  f.points = x.size();
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double ssr = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double r = y[k] - f.intercept - f.slope * x[k];
    ssr += r * r;
  }
  f.residual_sigma = std::sqrt(ssr / (n - 2.0));
  f.slope_uncertainty = f.residual_sigma / std::sqrt(sxx);
  f.intercept_uncertainty = f.residual_sigma * std::sqrt(1.0 / n + mx * mx / sxx);
  return f;
}

/// Result of a front-speed measurement.
struct FrontSpeed {
  double speed = 0.0;              ///< c [m/s]
  double speed_uncertainty = 0.0;  ///< u(c) from the final regression [m/s]
  LineFit first_fit;               ///< fit with every arrival
  LineFit final_fit;               ///< fit after rejecting outliers
  std::vector<double> arrival;     ///< arrival time per sensor (NaN if none) [s]
  std::vector<bool> kept;          ///< sensor used in the final fit
  std::size_t kept_points = 0;     ///< points in the final fit
  std::size_t arrivals = 0;        ///< sensors with an arrival
};

/// Robust front speed from arrival times at known positions (NaN times are skipped). Throws
/// InvalidParameter when fewer than 3 points are available before or after the rejection.
inline FrontSpeed front_speed_from_arrivals(const std::vector<double>& position,
                                            const std::vector<double>& arrival,
                                            double reject_sigmas = 2.0) {
  require(position.size() == arrival.size(), "front_speed_from_arrivals", "arrival.size()",
          static_cast<double>(arrival.size()), "position.size()");
  require(reject_sigmas > 0.0, "front_speed_from_arrivals", "reject_sigmas", reject_sigmas,
          "(0, inf)");
  FrontSpeed out;
  out.arrival = arrival;
  out.kept.assign(arrival.size(), false);
  std::vector<double> t;
  std::vector<double> x;
  std::vector<std::size_t> idx;
  for (std::size_t k = 0; k < arrival.size(); ++k) {
    if (!std::isfinite(arrival[k])) continue;
    t.push_back(arrival[k]);
    x.push_back(position[k]);
    idx.push_back(k);
  }
  out.arrivals = t.size();
  out.first_fit = fit_line(t, x);
  // Rejection band; the round-off term keeps exactly collinear points from being rejected.
  double scale = 0.0;
  for (double v : x) scale = std::max(scale, std::abs(v));
  const double band = reject_sigmas * out.first_fit.residual_sigma +
                      64.0 * std::numeric_limits<double>::epsilon() * scale;
  std::vector<double> t2;
  std::vector<double> x2;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double r = x[k] - out.first_fit.intercept - out.first_fit.slope * t[k];
    if (std::abs(r) <= band) {
      t2.push_back(t[k]);
      x2.push_back(x[k]);
      out.kept[idx[k]] = true;
    }
  }
  out.final_fit = fit_line(t2, x2);
  out.kept_points = t2.size();
  out.speed = out.final_fit.slope;
  out.speed_uncertainty = out.final_fit.slope_uncertainty;
  return out;
}

/// Arrival time at every sensor, then the robust front speed (paper 001 section 2.8.3).
inline FrontSpeed front_speed(const std::vector<SensorSeries>& sensors,
                              const ArrivalSettings& settings = {}, double reject_sigmas = 2.0) {
  std::vector<double> pos(sensors.size());
  std::vector<double> arr(sensors.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < sensors.size(); ++k) {
    pos[k] = sensors[k].position;
    if (const auto t = arrival_time(sensors[k], settings)) arr[k] = *t;
  }
  return front_speed_from_arrivals(pos, arr, reject_sigmas);
}

}  // namespace granule::analysis
