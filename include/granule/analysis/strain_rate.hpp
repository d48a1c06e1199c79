#pragma once
// Strain-rate tensor of a velocity field sampled on a RegularGrid (paper 000 section IV):
//   ε̇ = ½ (∇u + ∇uᵀ),   (∇u)_ab = ∂u_a / ∂x_b,
// and its magnitude |ε̇| = √(ε̇_ij ε̇_ij) (Frobenius norm, as 000 defines it).
// Derivatives: central differences (u_{k+1} − u_{k−1}) / 2h inside the grid and across periodic
// axes; second-order one-sided differences (∓3u_0 ± 4u_1 ∓ u_2) / 2h at the ends of a
// non-periodic axis with ≥ 3 nodes, first-order with 2 nodes, and zero on an axis with a single
// node. Every formula is exact for fields quadratic along the axis.
// The overload taking CgFields marks with NaN the nodes whose stencil touches a node with
// density below a threshold (outside the material the CG velocity is undefined).
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "granule/analysis/coarse_graining.hpp"
#include "granule/analysis/regular_grid.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

namespace detail_sr {

// Calls f(node index, coefficient) for the finite-difference stencil of ∂/∂x_a at node k,
// coefficients already divided by the spacing.
template <class D, class F>
void stencil(const RegularGrid<D>& g, const typename D::IVec& k, int a, F&& f) {
  const int n = g.count()[a];
  const double h = g.spacing()[a];
  auto at = [&](int ka) {
    typename D::IVec q = k;
    q[a] = ka;
    return g.index(q);
  };
  if (n == 1) return;
  if (g.periodic()[a]) {
    f(at((k[a] + 1) % n), 0.5 / h);
    f(at((k[a] - 1 + n) % n), -0.5 / h);
    return;
  }
  if (n == 2) {
    f(at(1), 1.0 / h);
    f(at(0), -1.0 / h);
  } else if (k[a] == 0) {
    f(at(0), -1.5 / h);
    f(at(1), 2.0 / h);
    f(at(2), -0.5 / h);
  } else if (k[a] == n - 1) {
    f(at(n - 1), 1.5 / h);
    f(at(n - 2), -2.0 / h);
    f(at(n - 3), 0.5 / h);
  } else {
    f(at(k[a] + 1), 0.5 / h);
    f(at(k[a] - 1), -0.5 / h);
  }
}

}  // namespace detail_sr

/// Velocity gradient (∇u)_ab = ∂u_a/∂x_b at every node [1/s].
template <class D>
std::vector<typename D::Mat> velocity_gradient(const RegularGrid<D>& grid,
                                               const std::vector<typename D::Vec>& velocity) {
  using Mat = typename D::Mat;
  require(velocity.size() == grid.size(), "velocity_gradient", "velocity.size()",
          static_cast<double>(velocity.size()), "grid.size()");
  std::vector<Mat> out(grid.size(), Mat::Zero());
  const auto nodes = static_cast<std::ptrdiff_t>(grid.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t t = 0; t < nodes; ++t) {
    const auto k = grid.coords(static_cast<std::size_t>(t));
    Mat g = Mat::Zero();
    for (int b = 0; b < D::dim; ++b) {
      detail_sr::stencil(grid, k, b, [&](std::size_t q, double c) { g.col(b) += c * velocity[q]; });
    }
    out[static_cast<std::size_t>(t)] = g;
  }
  return out;
}

/// Strain-rate tensor ε̇ = ½ (∇u + ∇uᵀ) at every node [1/s].
template <class D>
std::vector<typename D::Mat> strain_rate(const RegularGrid<D>& grid,
                                         const std::vector<typename D::Vec>& velocity) {
  auto g = velocity_gradient(grid, velocity);
  for (auto& m : g) m = 0.5 * (m + m.transpose()).eval();
  return g;
}

/// Strain rate of a coarse-grained velocity field; NaN where the stencil touches a node with
/// density below `min_density` [kg/m^3].
template <class D>
std::vector<typename D::Mat> strain_rate(const CgFields<D>& fields, double min_density) {
  require_non_negative(min_density, "strain_rate", "min_density");
  auto e = strain_rate(fields.grid, fields.velocity);
  const auto& grid = fields.grid;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t t = 0; t < grid.size(); ++t) {
    const auto k = grid.coords(t);
    bool ok = fields.density[t] >= min_density;
    for (int b = 0; b < D::dim && ok; ++b) {
      detail_sr::stencil(grid, k, b, [&](std::size_t q, double) {
        if (!(fields.density[q] >= min_density)) ok = false;
      });
    }
    if (!ok) e[t].setConstant(nan);
  }
  return e;
}

/// |ε̇| = √(ε̇_ij ε̇_ij) [1/s].
template <class Mat>
double strain_rate_magnitude(const Mat& e) {
  return std::sqrt(e.cwiseProduct(e).sum());
}

/// |ε̇| at every node [1/s].
template <class Mat>
std::vector<double> strain_rate_magnitude(const std::vector<Mat>& e) {
  std::vector<double> out(e.size());
  for (std::size_t t = 0; t < e.size(); ++t) out[t] = strain_rate_magnitude(e[t]);
  return out;
}

}  // namespace granule::analysis
