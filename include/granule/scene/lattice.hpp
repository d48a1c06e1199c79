#pragma once
// Regular packings filling an axis-aligned region with particles of radius r whose centres
// are `spacing` s >= 2r apart (nearest neighbours), every particle lying wholly inside the
// region (centre in [lo + r, hi - r]); an optional predicate keeps a subset (clipping).
//   simple_lattice    square (2D) / simple cubic (3D): x = lo + r + s (i, j[, k])
//   hexagonal_lattice 2D triangular: rows s sqrt(3)/2 apart, odd rows shifted by s/2
//   fcc_lattice       3D face-centred cubic: the points of a cubic grid of step s/sqrt(2)
//                     whose integer coordinates have an even sum (cube edge a = s sqrt 2,
//                     12 nearest neighbours at distance s); packing fraction pi/(3 sqrt 2)
//                     for s = 2r (Conway & Sloane, Sphere Packings, Lattices and Groups, ch. 1).
// Points on the boundary of the allowed range are kept (tolerance 1e-9 s). The order is
// x fastest, then y, then z.
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/core/error.hpp"

namespace granule::scene {

/// Keeps a lattice point when it returns true (centre position [m]).
template <class D>
using LatticeClip = std::function<bool(const typename D::Vec&)>;

namespace detail {

template <class D>
void check_lattice(const geometry::Aabb<D>& region, double radius, double spacing, const char* where) {
  require_positive(radius, where, "radius");
  require(spacing >= 2.0 * radius * (1.0 - 1e-12) && std::isfinite(spacing), where, "spacing", spacing,
          "[2 radius, inf) = [" + granule::detail::to_text(2.0 * radius) + ", inf) m");
  require(region.is_finite() && !region.is_empty(), where, "region extent (min)", region.extent().minCoeff(),
          "a finite, non-empty box");
}

/// Number of grid steps of size `step` from a to b inclusive (0 when b < a).
inline long steps_in(double a, double b, double step, double tol) {
  if (b < a - tol) return 0;
  return static_cast<long>(std::floor((b - a + tol) / step)) + 1;
}

}  // namespace detail

/// Square (2D) or simple cubic (3D) lattice.
template <class D>
std::vector<typename D::Vec> simple_lattice(const geometry::Aabb<D>& region, double radius, double spacing,
                                            const LatticeClip<D>& keep = {}) {
  detail::check_lattice(region, radius, spacing, "scene::simple_lattice");
  using Vec = typename D::Vec;
  const double tol = 1e-9 * spacing;
  std::array<long, 3> n{1, 1, 1};
  for (int a = 0; a < D::dim; ++a) n[a] = detail::steps_in(region.lo[a] + radius, region.hi[a] - radius, spacing, tol);
  std::vector<Vec> out;
  for (long k = 0; k < n[2]; ++k) {
    for (long j = 0; j < n[1]; ++j) {
      for (long i = 0; i < n[0]; ++i) {
        const long idx[3] = {i, j, k};
        Vec x;
        for (int a = 0; a < D::dim; ++a) x[a] = region.lo[a] + radius + spacing * static_cast<double>(idx[a]);
        if (!keep || keep(x)) out.push_back(x);
      }
    }
  }
  return out;
}

/// 2D triangular (hexagonal close-packed in the plane) lattice.
inline std::vector<Dim2::Vec> hexagonal_lattice(const geometry::Aabb<Dim2>& region, double radius, double spacing,
                                                const LatticeClip<Dim2>& keep = {}) {
  detail::check_lattice(region, radius, spacing, "scene::hexagonal_lattice");
  const double tol = 1e-9 * spacing;
  const double row = spacing * std::sqrt(3.0) / 2.0;
  const double x0 = region.lo.x() + radius, x1 = region.hi.x() - radius;
  const long rows = detail::steps_in(region.lo.y() + radius, region.hi.y() - radius, row, tol);
  std::vector<Dim2::Vec> out;
  for (long j = 0; j < rows; ++j) {
    const double shift = (j % 2 == 1) ? 0.5 * spacing : 0.0;
    const long cols = detail::steps_in(x0 + shift, x1, spacing, tol);
    for (long i = 0; i < cols; ++i) {
      const Dim2::Vec x(x0 + shift + spacing * static_cast<double>(i), region.lo.y() + radius + row * static_cast<double>(j));
      if (!keep || keep(x)) out.push_back(x);
    }
  }
  return out;
}

/// 3D face-centred cubic lattice.
inline std::vector<Dim3::Vec> fcc_lattice(const geometry::Aabb<Dim3>& region, double radius, double spacing,
                                          const LatticeClip<Dim3>& keep = {}) {
  detail::check_lattice(region, radius, spacing, "scene::fcc_lattice");
  const double step = spacing / std::sqrt(2.0);  // half the cube edge
  const double tol = 1e-9 * spacing;
  std::array<long, 3> n{};
  for (int a = 0; a < 3; ++a) n[a] = detail::steps_in(region.lo[a] + radius, region.hi[a] - radius, step, tol);
  std::vector<Dim3::Vec> out;
  for (long k = 0; k < n[2]; ++k) {
    for (long j = 0; j < n[1]; ++j) {
      for (long i = (j + k) % 2; i < n[0]; i += 2) {
        const Dim3::Vec x = region.lo + Dim3::Vec::Constant(radius) +
                            step * Dim3::Vec(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
        if (!keep || keep(x)) out.push_back(x);
      }
    }
  }
  return out;
}

}  // namespace granule::scene
