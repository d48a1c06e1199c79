#pragma once
// Particle radius distributions, each drawing from a RandomGenerator and knowing its exact
// mean and standard deviation (used by tests and for reporting):
//   MonodisperseSizes  r
//   UniformSizes       r ~ U[r_min, r_max]:  mean (a+b)/2, sd (b-a)/sqrt(12)
//   NormalSizes        r ~ N(mu, sigma) truncated to [r_min, r_max] by rejection. With
//                      alpha = (a-mu)/sigma, beta = (b-mu)/sigma, Z = Phi(beta) - Phi(alpha):
//                      mean = mu + sigma (phi(alpha) - phi(beta))/Z,
//                      var  = sigma^2 [1 + (alpha phi(alpha) - beta phi(beta))/Z - ((phi(alpha) - phi(beta))/Z)^2]
//                      (Johnson, Kotz & Balakrishnan, Continuous Univariate Distributions I, 1994, 13.10)
//   LogNormalSizes     ln r ~ N(mu, sigma) truncated to [r_min, r_max] by rejection:
//                      E[r^k] = exp(k mu + k^2 sigma^2/2) [Phi((ln b - mu - k sigma^2)/sigma)
//                               - Phi((ln a - mu - k sigma^2)/sigma)] / Z
//                      (same source, ch. 14); from_mean_sd() converts an untruncated mean m and
//                      sd s: sigma^2 = ln(1 + s^2/m^2), mu = ln m - sigma^2/2.
//   DiscreteSizes      radii r_k with number fractions p_k (normalised); from_volume_fractions()
//                      converts volume fractions v_k: p_k ~ v_k / r_k^dim.
// Truncation windows must hold at least 1e-6 of the probability, so that rejection ends
// quickly. SizeDistribution holds any of them for choices made at run time.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "granule/core/error.hpp"
#include "granule/scene/random.hpp"

namespace granule::scene {

namespace detail {
inline double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }
inline double normal_pdf(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi); }

inline void check_window(double r_min, double r_max, const std::string& where) {
  require(r_min > 0.0 && std::isfinite(r_min), where, "r_min", r_min, "(0, inf) m");
  require(r_max > r_min && std::isfinite(r_max), where, "r_max", r_max, "(r_min, inf) m");
}
inline void check_mass(double z, const std::string& where) {
  require(z >= 1e-6, where, "probability of [r_min, r_max]", z, "[1e-6, 1] (widen the window or move the mean)");
}
}  // namespace detail

/// All particles of one radius.
class MonodisperseSizes {
 public:
  explicit MonodisperseSizes(double radius) : r_(radius) {
    require_positive(radius, "scene::MonodisperseSizes", "radius");
  }
  double sample(RandomGenerator&) const { return r_; }
  double r_min() const { return r_; }
  double r_max() const { return r_; }
  double mean() const { return r_; }
  double stddev() const { return 0.0; }

 private:
  double r_;  // [m]
};

/// Radius uniform in [r_min, r_max].
class UniformSizes {
 public:
  UniformSizes(double r_min, double r_max) : a_(r_min), b_(r_max) {
    require(r_min > 0.0 && std::isfinite(r_min), "scene::UniformSizes", "r_min", r_min, "(0, inf) m");
    require(r_max >= r_min && std::isfinite(r_max), "scene::UniformSizes", "r_max", r_max, "[r_min, inf) m");
  }
  /// a + (b - a) u with u in [0, 1), clamped so that b itself is a valid upper bound.
  double sample(RandomGenerator& rng) const { return std::min(b_, rng.uniform(a_, b_)); }
  double r_min() const { return a_; }
  double r_max() const { return b_; }
  double mean() const { return 0.5 * (a_ + b_); }
  double stddev() const { return (b_ - a_) / std::sqrt(12.0); }

 private:
  double a_, b_;  // [m]
};

/// Normal radius N(mu, sigma) truncated to [r_min, r_max].
class NormalSizes {
 public:
  NormalSizes(double mu, double sigma, double r_min, double r_max) : mu_(mu), sigma_(sigma), a_(r_min), b_(r_max) {
    const std::string where = "scene::NormalSizes";
    require_finite(mu, where, "mu");
    require_positive(sigma, where, "sigma");
    detail::check_window(r_min, r_max, where);
    alpha_ = (a_ - mu_) / sigma_;
    beta_ = (b_ - mu_) / sigma_;
    z_ = detail::normal_cdf(beta_) - detail::normal_cdf(alpha_);
    detail::check_mass(z_, where);
  }
  double sample(RandomGenerator& rng) const {
    while (true) {
      const double r = rng.normal(mu_, sigma_);
      if (r >= a_ && r <= b_) return r;
    }
  }
  double r_min() const { return a_; }
  double r_max() const { return b_; }
  double mean() const {
    return mu_ + sigma_ * (detail::normal_pdf(alpha_) - detail::normal_pdf(beta_)) / z_;
  }
  double stddev() const {
    const double pa = detail::normal_pdf(alpha_), pb = detail::normal_pdf(beta_);
    const double m = (pa - pb) / z_;
    return sigma_ * std::sqrt(1.0 + (alpha_ * pa - beta_ * pb) / z_ - m * m);
  }

 private:
  double mu_, sigma_, a_, b_;  // [m]
  double alpha_ = 0.0, beta_ = 0.0, z_ = 1.0;
};

/// Log-normal radius (ln r ~ N(mu, sigma), r in m) truncated to [r_min, r_max].
class LogNormalSizes {
 public:
  LogNormalSizes(double mu, double sigma, double r_min, double r_max) : mu_(mu), sigma_(sigma), a_(r_min), b_(r_max) {
    const std::string where = "scene::LogNormalSizes";
    require_finite(mu, where, "mu");
    require_positive(sigma, where, "sigma");
    detail::check_window(r_min, r_max, where);
    z_ = partial_moment(0);
    detail::check_mass(z_, where);
  }
  /// From the mean and standard deviation [m] of the untruncated log-normal radius.
  static LogNormalSizes from_mean_sd(double mean, double sd, double r_min, double r_max) {
    require_positive(mean, "scene::LogNormalSizes::from_mean_sd", "mean");
    require_positive(sd, "scene::LogNormalSizes::from_mean_sd", "sd");
    const double s2 = std::log1p(sd * sd / (mean * mean));
    return LogNormalSizes(std::log(mean) - 0.5 * s2, std::sqrt(s2), r_min, r_max);
  }
  double sample(RandomGenerator& rng) const {
    while (true) {
      const double r = std::exp(rng.normal(mu_, sigma_));
      if (r >= a_ && r <= b_) return r;
    }
  }
  double r_min() const { return a_; }
  double r_max() const { return b_; }
  double mu() const { return mu_; }
  double sigma() const { return sigma_; }
  double mean() const { return partial_moment(1) / z_; }
  double stddev() const {
    const double m = mean();
    return std::sqrt(std::max(0.0, partial_moment(2) / z_ - m * m));
  }

 private:
  // E[r^k; a <= r <= b] for the untruncated log-normal.
  double partial_moment(int k) const {
    const double s2 = sigma_ * sigma_;
    const double hi = (std::log(b_) - mu_ - k * s2) / sigma_;
    const double lo = (std::log(a_) - mu_ - k * s2) / sigma_;
    return std::exp(k * mu_ + 0.5 * k * k * s2) * (detail::normal_cdf(hi) - detail::normal_cdf(lo));
  }

  double mu_, sigma_, a_, b_;
  double z_ = 1.0;
};

/// A mixture of discrete radii with number fractions.
class DiscreteSizes {
 public:
  /// `radii` [m] and number fractions (>= 0, normalised here; their sum must be > 0).
  DiscreteSizes(std::vector<double> radii, std::vector<double> number_fractions)
      : radii_(std::move(radii)), p_(std::move(number_fractions)) {
    const std::string where = "scene::DiscreteSizes";
    require(!radii_.empty(), where, "number of radii", 0.0, "[1, inf)");
    require(p_.size() == radii_.size(), where, "number of fractions", static_cast<double>(p_.size()),
            std::to_string(radii_.size()) + " (one per radius)");
    double sum = 0.0;
    for (std::size_t k = 0; k < radii_.size(); ++k) {
      require_positive(radii_[k], where, "radii[" + std::to_string(k) + "]");
      require_non_negative(p_[k], where, "fractions[" + std::to_string(k) + "]");
      sum += p_[k];
    }
    require(sum > 0.0, where, "sum of fractions", sum, "(0, inf)");
    cumulative_.resize(p_.size());
    double c = 0.0;
    r_min_ = std::numeric_limits<double>::infinity();
    r_max_ = 0.0;
    for (std::size_t k = 0; k < p_.size(); ++k) {
      p_[k] /= sum;
      c += p_[k];
      cumulative_[k] = c;
      if (p_[k] > 0.0) {
        r_min_ = std::min(r_min_, radii_[k]);
        r_max_ = std::max(r_max_, radii_[k]);
      }
    }
    cumulative_.back() = 1.0;
  }

  /// From volume (= mass, for one density) fractions in `dim` dimensions: p_k ~ v_k / r_k^dim.
  static DiscreteSizes from_volume_fractions(std::vector<double> radii, std::vector<double> volume_fractions, int dim) {
    require(dim == 2 || dim == 3, "scene::DiscreteSizes::from_volume_fractions", "dim", dim, "{2, 3}");
    require(volume_fractions.size() == radii.size(), "scene::DiscreteSizes::from_volume_fractions",
            "number of fractions", static_cast<double>(volume_fractions.size()),
            std::to_string(radii.size()) + " (one per radius)");
    std::vector<double> p(radii.size());
    for (std::size_t k = 0; k < radii.size(); ++k) {
      require_positive(radii[k], "scene::DiscreteSizes::from_volume_fractions", "radii[" + std::to_string(k) + "]");
      p[k] = volume_fractions[k] / std::pow(radii[k], dim);
    }
    return DiscreteSizes(std::move(radii), std::move(p));
  }

  double sample(RandomGenerator& rng) const {
    const double u = rng.uniform();
    const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), u);
    return radii_[static_cast<std::size_t>(it - cumulative_.begin())];
  }
  double r_min() const { return r_min_; }
  double r_max() const { return r_max_; }
  double mean() const {
    double m = 0.0;
    for (std::size_t k = 0; k < p_.size(); ++k) m += p_[k] * radii_[k];
    return m;
  }
  double stddev() const {
    const double m = mean();
    double v = 0.0;
    for (std::size_t k = 0; k < p_.size(); ++k) v += p_[k] * (radii_[k] - m) * (radii_[k] - m);
    return std::sqrt(v);
  }
  const std::vector<double>& radii() const { return radii_; }
  /// Normalised number fractions.
  const std::vector<double>& fractions() const { return p_; }

 private:
  std::vector<double> radii_;
  std::vector<double> p_;
  std::vector<double> cumulative_;
  double r_min_ = 0.0, r_max_ = 0.0;
};

/// Any of the distributions above, chosen at run time.
class SizeDistribution {
 public:
  using Variant = std::variant<MonodisperseSizes, UniformSizes, NormalSizes, LogNormalSizes, DiscreteSizes>;
  template <class S>
    requires std::is_constructible_v<Variant, S>
  SizeDistribution(S s) : v_(std::move(s)) {}

  double sample(RandomGenerator& rng) const {
    return std::visit([&](const auto& s) { return s.sample(rng); }, v_);
  }
  double r_min() const { return std::visit([](const auto& s) { return s.r_min(); }, v_); }
  double r_max() const { return std::visit([](const auto& s) { return s.r_max(); }, v_); }
  double mean() const { return std::visit([](const auto& s) { return s.mean(); }, v_); }
  double stddev() const { return std::visit([](const auto& s) { return s.stddev(); }, v_); }
  const Variant& variant() const { return v_; }

 private:
  Variant v_;
};

}  // namespace granule::scene
