#pragma once
// Small frame factories shared by the analysis tests (not a test file itself).
#include <cstdint>
#include <random>

#include "granule/analysis/frame.hpp"
#include "granule/core/dimension.hpp"

namespace granule::test {

/// Appends a particle of radius r and density rho at x with velocity v.
template <class D>
void add_particle(analysis::Frame<D>& f, const typename D::Vec& x, const typename D::Vec& v,
                  double r, double rho) {
  f.x.push_back(x);
  f.v.push_back(v);
  f.omega.push_back(D::zero_ang());
  f.radius.push_back(r);
  f.mass.push_back(rho * D::volume(r, f.thickness));
  f.id.push_back(f.x.size() - 1);
  f.group.push_back(0);
}

/// Simple square / cubic lattice of n^D sites with spacing a, first site at `origin`; particles
/// of radius r and density rho, at rest.
template <class D>
analysis::Frame<D> lattice_frame(int n, double a, double r, double rho,
                                 const typename D::Vec& origin = D::Vec::Zero()) {
  analysis::Frame<D> f;
  f.thickness = 1.0;
  typename D::IVec k = D::IVec::Zero();
  const int total = (D::dim == 2) ? n * n : n * n * n;
  for (int s = 0; s < total; ++s) {
    int rest = s;
    for (int d = 0; d < D::dim; ++d) {
      k[d] = rest % n;
      rest /= n;
    }
    add_particle<D>(f, origin + a * k.template cast<double>(), D::Vec::Zero(), r, rho);
  }
  f.box_lo = origin - D::Vec::Constant(a);
  f.box_hi = origin + D::Vec::Constant(n * a);
  return f;
}

/// n particles uniformly at random (fixed seed) in [lo, hi], random velocities in [-1, 1] m/s.
template <class D>
analysis::Frame<D> random_frame(std::size_t n, const typename D::Vec& lo,
                                const typename D::Vec& hi, double r, double rho,
                                std::uint32_t seed = 12345) {
  analysis::Frame<D> f;
  f.thickness = 1.0;
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    typename D::Vec x;
    typename D::Vec v;
    for (int d = 0; d < D::dim; ++d) {
      x[d] = lo[d] + (hi[d] - lo[d]) * u(gen);
      v[d] = 2.0 * u(gen) - 1.0;
    }
    add_particle<D>(f, x, v, r, rho);
  }
  f.box_lo = lo;
  f.box_hi = hi;
  return f;
}

}  // namespace granule::test
