#pragma once
// Truncated Gaussian coarse-graining kernel (Weinhart et al. 2012, Granular Matter 14:289;
// Goldhirsch 2010, Granular Matter 12:239; paper 002 eq. 4–6):
//
//   G(r) = exp(−|r|² / (2 w²)) / V_w   for |r| < c,   0 otherwise,
//
// normalised exactly over its truncated support, ∫ G dV = 1:
//   2D:  V_w = 2π w² (1 − e^{−c²/2w²})                                   (002 eq. 6)
//   3D:  V_w = (2π w²)^{3/2} erf(c / (√2 w)) − 4π w² c e^{−c²/2w²}
// (3D: ∫_0^c 4π r² e^{−r²/2w²} dr, integrated by parts.)
//
// Line integral used by the contact stress (Weinhart et al. 2012, eq. 27–28):
//   L(a, b) = ∫_0^1 G(|a − s b|) ds,
// the average of the kernel along the segment from a to a − b (a: vector from the segment's
// start to the evaluation point). The segment is first clipped analytically to the support
// ball |a − s b| < c (a quadratic in s); the clipped part is split into panels no longer than
// one kernel width w, and each panel is integrated with an n-point Gauss–Legendre rule. On a
// panel of length ≤ w the integrand is a smooth piece of a Gaussian; with the default n = 7 the
// absolute error per panel is below 3e-15 · G(0) · w (measured against the closed form with erf,
// see tests/analysis/test_coarse_graining.cpp).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "granule/analysis/gauss_legendre.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

template <class D>
class GaussianCgKernel {
 public:
  using Vec = typename D::Vec;

  /// Kernel of width w with the default cutoff c = 3 w.
  explicit GaussianCgKernel(double width)  // [m]
      : GaussianCgKernel(width, 3.0 * width) {}

  /// Kernel of width w and cutoff radius c (c ≥ w; paper 002 uses c = 4 w).
  GaussianCgKernel(double width,   // [m]
                   double cutoff)  // [m]
      : w_(width), c_(cutoff) {
    require_positive(width, "GaussianCgKernel", "width");
    require(std::isfinite(cutoff) && cutoff >= width, "GaussianCgKernel", "cutoff", cutoff,
            "[width, inf)");
    const double e = std::exp(-c_ * c_ / (2.0 * w_ * w_));
    if constexpr (D::dim == 2) {
      v_w_ = 2.0 * std::numbers::pi * w_ * w_ * (1.0 - e);
    } else {
      v_w_ = std::pow(2.0 * std::numbers::pi * w_ * w_, 1.5) *
                 std::erf(c_ / (std::numbers::sqrt2 * w_)) -
             4.0 * std::numbers::pi * w_ * w_ * c_ * e;
    }
    inv_v_w_ = 1.0 / v_w_;
    inv_two_w2_ = 1.0 / (2.0 * w_ * w_);
  }

  double width() const { return w_; }          ///< w [m]
  double cutoff() const { return c_; }         ///< c [m]
  double normalisation() const { return v_w_; }  ///< V_w [m^D]

  /// G at squared distance r2 [1/m^D]; zero at and beyond the cutoff.
  double value_sq(double r2) const {  // r2 [m^2]
    return r2 < c_ * c_ ? std::exp(-r2 * inv_two_w2_) * inv_v_w_ : 0.0;
  }
  /// G(r) [1/m^D].
  double value(const Vec& r) const { return value_sq(r.squaredNorm()); }

  /// ∫_0^1 G(|a − s b|) ds [1/m^D]: the given Gauss–Legendre rule on each panel (≤ w long) of
  /// the segment clipped to the support.
  double line_integral(const Vec& a,  // [m]
                       const Vec& b,  // [m]
                       const detail::GaussLegendreRule& rule) const {
    const double bb = b.squaredNorm();
    const double c2 = c_ * c_;
    if (bb == 0.0) return value_sq(a.squaredNorm());
    // |a − s b|² = bb s² − 2 ab s + aa < c²  ⇔  s in (s0 − δ, s0 + δ).
    const double ab = a.dot(b);
    const double aa = a.squaredNorm();
    const double disc = ab * ab - bb * (aa - c2);
    if (disc <= 0.0) return 0.0;
    const double s0 = ab / bb;
    const double delta = std::sqrt(disc) / bb;
    const double s1 = std::max(0.0, s0 - delta);
    const double s2 = std::min(1.0, s0 + delta);
    if (s2 <= s1) return 0.0;
    const double len = (s2 - s1) * std::sqrt(bb);  // clipped length [m]
    const int panels = std::max(1, static_cast<int>(std::ceil(len / w_ - 1e-12)));
    const double half = 0.5 * (s2 - s1) / panels;
    double sum = 0.0;
    for (int p = 0; p < panels; ++p) {
      const double mid = s1 + (2 * p + 1) * half;
      for (std::size_t q = 0; q < rule.size(); ++q) {
        const double s = mid + half * rule.node[q];
        const double r2 = aa - 2.0 * ab * s + bb * s * s;
        sum += rule.weight[q] * std::exp(-std::max(r2, 0.0) * inv_two_w2_);
      }
    }
    return sum * half * inv_v_w_;
  }

 private:
  double w_;
  double c_;
  double v_w_ = 1.0;
  double inv_v_w_ = 1.0;
  double inv_two_w2_ = 1.0;
};

}  // namespace granule::analysis
