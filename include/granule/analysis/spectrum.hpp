#pragma once
// One-sided power spectral density of a uniformly sampled signal (periodogram through FFTW).
//
// With samples x_n (n = 0 … N−1, interval Δt, f_s = 1/Δt), mean removed, window w_n and
//   X_k = Σ_n w_n x_n e^{−2πi kn/N},
// the one-sided PSD at f_k = k f_s / N, k = 0 … ⌊N/2⌋, is
//   P_k = c_k |X_k|² / (f_s Σ_n w_n²),   c_k = 1 for k = 0 and k = N/2 (N even), 2 otherwise.
// Parseval then gives Σ_k P_k Δf = Σ_n (w_n x_n)² / Σ_n w_n²  (Δf = f_s / N): the variance of the
// signal for the rectangular window exactly; with the Hann window the window-weighted variance,
// equal to the variance for a stationary signal (exactly for a sine with a whole number ≥ 2 of
// periods in the record). Hann: w_n = ½ (1 − cos(2πn/N)) (periodic form; Harris 1978, Proc.
// IEEE 66:51). PSD units: [signal]² / Hz.
#include <fftw3.h>

#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "granule/analysis/fftw_support.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

/// Data window applied before the transform.
enum class SpectralWindow {
  Rectangular,  ///< no window
  Hann          ///< w_n = ½ (1 − cos 2πn/N)
};

/// One-sided PSD.
struct PowerSpectrum {
  std::vector<double> frequency;  ///< f_k [Hz]
  std::vector<double> psd;        ///< P_k [signal²/Hz]
  double df = 0.0;                ///< frequency resolution f_s / N [Hz]
  double variance = 0.0;          ///< variance of the detrended samples [signal²]
  /// Σ P_k Δf [signal²].
  double integral() const {
    double s = 0.0;
    for (double p : psd) s += p;
    return s * df;
  }
};

/// One-sided PSD of `samples` taken every `dt` seconds (mean removed first).
inline PowerSpectrum power_spectrum(const std::vector<double>& samples, double dt,  // [s]
                                    SpectralWindow window = SpectralWindow::Rectangular) {
  require_positive(dt, "power_spectrum", "dt");
  const std::size_t n = samples.size();
  require(n >= 2, "power_spectrum", "samples.size()", static_cast<double>(n), "[2, inf)");
  require(n <= 1u << 30, "power_spectrum", "samples.size()", static_cast<double>(n),
          "[2, 2^30]");
  double mean = 0.0;
  for (double x : samples) mean += x;
  mean /= static_cast<double>(n);
  detail::FftwBuffer<double> in(n);
  detail::FftwBuffer<fftw_complex> out(n / 2 + 1);
  double variance = 0.0;
  double sum_w2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double d = samples[k] - mean;
    variance += d * d;
    const double w = window == SpectralWindow::Hann
                         ? 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * static_cast<double>(k) /
                                                 static_cast<double>(n)))
                         : 1.0;
    sum_w2 += w * w;
    in[k] = w * d;
  }
  const auto plan = detail::FftwPlan::r2c({static_cast<int>(n)}, in.data(), out.data());
  plan.execute_r2c(in.data(), out.data());
  const double fs = 1.0 / dt;
  PowerSpectrum s;
  s.df = fs / static_cast<double>(n);
  s.variance = variance / static_cast<double>(n);
  const std::size_t m = n / 2 + 1;
  s.frequency.resize(m);
  s.psd.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    const double p = out[k][0] * out[k][0] + out[k][1] * out[k][1];
    const bool edge = k == 0 || (n % 2 == 0 && k == n / 2);
    s.frequency[k] = static_cast<double>(k) * s.df;
    s.psd[k] = (edge ? 1.0 : 2.0) * p / (fs * sum_w2);
  }
  return s;
}

/// Frequency of the largest PSD value above f = 0 [Hz]; with `interpolate`, refined by the
/// vertex of the parabola through the logarithms of the peak bin and its two neighbours
/// (Gaussian interpolation; a smaller bias than a parabola through the PSD values themselves,
/// about 0.02 bin against 0.1 for a Hann-windowed sine 0.3 bin off centre).
inline double peak_frequency(const PowerSpectrum& s, bool interpolate = false) {
  require(s.psd.size() >= 2, "peak_frequency", "psd.size()", static_cast<double>(s.psd.size()),
          "[2, inf)");
  std::size_t best = 1;
  for (std::size_t k = 2; k < s.psd.size(); ++k)
    if (s.psd[k] > s.psd[best]) best = k;
  if (!interpolate || best + 1 >= s.psd.size()) return s.frequency[best];
  if (!(s.psd[best - 1] > 0.0) || !(s.psd[best + 1] > 0.0)) return s.frequency[best];
  const double a = std::log(s.psd[best - 1]);
  const double b = std::log(s.psd[best]);
  const double c = std::log(s.psd[best + 1]);
  const double denom = a - 2.0 * b + c;
  if (!(denom < 0.0)) return s.frequency[best];
  const double shift = 0.5 * (a - c) / denom;
  return s.frequency[best] + shift * s.df;
}

}  // namespace granule::analysis
