#pragma once
// The simulation box: bounds on every axis, periodic or not. Particles must stay inside the
// bounds of non-periodic axes (walls keep them there); periodic axes wrap.
#include <string>

#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule {

template <class D>
struct Domain {
  using Vec = typename D::Vec;
  using Flags = Eigen::Matrix<bool, D::dim, 1>;
  Vec lo = Vec::Zero();   ///< lower corner [m]
  Vec hi = Vec::Ones();   ///< upper corner [m]
  Flags periodic = Flags::Constant(false);

  Vec length() const { return hi - lo; }

  void validate() const {
    for (int k = 0; k < D::dim; ++k) {
      require(std::isfinite(lo[k]), "Domain", "lo[" + std::to_string(k) + "]", lo[k], "finite");
      require(hi[k] > lo[k] && std::isfinite(hi[k]), "Domain", "hi[" + std::to_string(k) + "]",
              hi[k], "(lo[" + std::to_string(k) + "], inf)");
    }
  }

  bool contains(const Vec& x) const {
    for (int k = 0; k < D::dim; ++k)
      if (!periodic[k] && (x[k] < lo[k] || x[k] > hi[k])) return false;
    return true;
  }

  /// Minimum-image vector a - b on periodic axes.
  Vec minimum_image(const Vec& a, const Vec& b) const {
    Vec d = a - b;
    const Vec L = length();
    for (int k = 0; k < D::dim; ++k)
      if (periodic[k]) d[k] -= L[k] * std::round(d[k] / L[k]);
    return d;
  }
};

}  // namespace granule
