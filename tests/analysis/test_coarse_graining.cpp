// Tests of granule/analysis/cg_kernel.hpp, regular_grid.hpp and coarse_graining.hpp.
// References: Weinhart et al. 2012 (Granular Matter 14:289) and paper 002 eq. 4–9 for the
// definitions; closed forms derived in the comments next to each check.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <numbers>
#include <random>

#include "frame_builders.hpp"
#include "granule/analysis/coarse_graining.hpp"

using granule::Dim2;
using granule::Dim3;
using namespace granule::analysis;

namespace {

// Closed form of ∫_{s1}^{s2} exp(−|a − s b|² / (2w²)) ds (complete the square in s):
// exp(−d⊥² / 2w²) · √(π/2) w / |b| · [erf(|b|(s2 − s0)/(√2 w)) − erf(|b|(s1 − s0)/(√2 w))],
// s0 = a·b / |b|², d⊥² = |a|² − (a·b)² / |b|².
template <class Vec>
double gaussian_segment(const Vec& a, const Vec& b, double w, double s1, double s2) {
  const double bb = b.squaredNorm();
  const double nb = std::sqrt(bb);
  const double s0 = a.dot(b) / bb;
  const double dperp2 = std::max(a.squaredNorm() - a.dot(b) * a.dot(b) / bb, 0.0);
  const double k = nb / (std::numbers::sqrt2 * w);
  return std::exp(-dperp2 / (2.0 * w * w)) * std::sqrt(std::numbers::pi / 2.0) * w / nb *
         (std::erf(k * (s2 - s0)) - std::erf(k * (s1 - s0)));
}

// The sum Σ_k G(k h) h^D of the kernel sampled on a grid of spacing h (the discrete
// normalisation used by the FFT path).
template <class D>
double sampled_kernel_sum(const GaussianCgKernel<D>& kernel, double h) {
  const int kk = static_cast<int>(std::floor(kernel.cutoff() / h));
  double s = 0.0;
  const int k2 = D::dim == 3 ? kk : 0;
  for (int z = -k2; z <= k2; ++z)
    for (int y = -kk; y <= kk; ++y)
      for (int x = -kk; x <= kk; ++x) s += kernel.value_sq(h * h * (x * x + y * y + z * z));
  return s * std::pow(h, D::dim);
}

template <class D>
double total_mass(const Frame<D>& f) {
  double m = 0.0;
  for (double x : f.mass) m += x;
  return m;
}

// Out-of-plane factor: fields are per unit volume of the slab in 2D (∫ρ dA = M / t).
template <class D>
double slab(const Frame<D>& f) {
  return D::dim == 2 ? f.thickness : 1.0;
}

// A random frame with one contact per pair of particles closer than 2r, with repulsive normal
// forces and tangential forces of random direction (not force-balanced: the CG is linear in the
// contact terms, so balance does not matter for comparing the two paths).
template <class D>
Frame<D> random_frame_with_contacts(std::size_t n, double size, double r, std::uint32_t seed) {
  using Vec = typename D::Vec;
  Frame<D> f = granule::test::random_frame<D>(n, Vec::Zero(), Vec::Constant(size), r, 2500.0, seed);
  std::mt19937_64 gen(seed + 1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = i + 1; j < n; ++j) {
      const Vec b = f.x[j] - f.x[i];
      if (b.norm() >= 2.0 * r) continue;
      ContactRecord<D> c;
      c.i = i;
      c.j = j;
      c.branch = b;
      c.normal = -b.normalized();
      c.contact_point = f.x[i] + 0.5 * b;
      c.fn = 1.0 + u(gen) * 0.5;
      Vec t;
      for (int a = 0; a < D::dim; ++a) t[a] = u(gen);
      t -= t.dot(c.normal) * c.normal;
      c.ft = 0.3 * t;
      c.mu = 0.5;
      f.contacts.push_back(c);
    }
  }
  return f;
}

}  // namespace

TEMPLATE_TEST_CASE("cg kernel is normalised exactly over its truncated support",
                   "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  // ∫ G dV = ∫_0^c S_D(r) G(r) dr with S_2 = 2πr, S_3 = 4πr²; the radial integrand is smooth on
  // [0, c], so composite Gauss–Legendre converges to round-off.
  const granule::detail::GaussLegendreRule rule(20);
  const double w = 1.3e-3;
  for (double ratio : {1.0, 2.0, 3.0, 4.0, 8.0}) {
    const GaussianCgKernel<D> kernel(w, ratio * w);
    const int panels = 40;
    const double len = kernel.cutoff() / panels;
    double integral = 0.0;
    for (int p = 0; p < panels; ++p) {
      for (std::size_t q = 0; q < rule.size(); ++q) {
        const double r = (p + 0.5 + 0.5 * rule.node[q]) * len;
        const double shell = D::dim == 2 ? 2.0 * std::numbers::pi * r
                                         : 4.0 * std::numbers::pi * r * r;
        integral += 0.5 * len * rule.weight[q] * shell * kernel.value_sq(r * r);
      }
    }
    CHECK(std::abs(integral - 1.0) < 1e-13);
  }
  // Default cutoff is 3 w; 2D normalisation is paper 002 eq. 6.
  const GaussianCgKernel<D> def(w);
  CHECK(def.cutoff() == Approx(3.0 * w).epsilon(1e-15));
  if constexpr (D::dim == 2) {
    CHECK(def.normalisation() ==
          Approx(2.0 * std::numbers::pi * w * w * (1.0 - std::exp(-4.5))).epsilon(1e-14));
  }
}

TEMPLATE_TEST_CASE("cg kernel line integral matches the erf closed form",
                   "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  const double w = 1.0e-3;
  const GaussianCgKernel<D> kernel(w, 3.0 * w);
  const granule::detail::GaussLegendreRule rule(7);
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    Vec a;
    Vec b;
    for (int d = 0; d < D::dim; ++d) {
      a[d] = 3.5 * w * u(gen);
      b[d] = 3.0 * w * u(gen);
    }
    // Clip to the support |a − s b| < c independently of the implementation.
    const double bb = b.squaredNorm();
    const double disc = a.dot(b) * a.dot(b) - bb * (a.squaredNorm() - 9.0 * w * w);
    double ref = 0.0;
    if (disc > 0.0) {
      const double s1 = std::max(0.0, (a.dot(b) - std::sqrt(disc)) / bb);
      const double s2 = std::min(1.0, (a.dot(b) + std::sqrt(disc)) / bb);
      if (s2 > s1) ref = gaussian_segment(a, b, w, s1, s2);
    }
    const double got = kernel.line_integral(a, b, rule) * kernel.normalisation();
    worst = std::max(worst, std::abs(got - ref));
  }
  // Absolute error in units of G(0) (the integrand's peak): panels ≤ w, 7 points.
  CHECK(worst < 1e-14);
}

TEMPLATE_TEST_CASE("cg of a uniform lattice gives its exact density and packing fraction",
                   "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  // Simple lattice of spacing a: far from the edges the exact continuum density is m / a^D and
  // the packing fraction V_p / a^D. The CG sum Σ_i G(r − r_i) a^D differs from ∫G = 1 by
  // (i) aliasing of the Gaussian on the lattice, ≈ 2D exp(−2π² w²/a²) ≤ 1.6e-8 for w ≥ a
  // (Poisson summation), and (ii) the sampling of the discontinuous truncation at r = c by the
  // lattice sites, of order e^{−c²/2w²} times the lattice-point discrepancy of the cutoff
  // sphere: measured ≤ 3e-4 for c = 4w (paper 002's cutoff) and w/a ∈ [1, 3], but up to 1.6e-2
  // for c = 3w and w = a. Hence the 1e-3 tolerance with c = 4w.
  const double a = 1.0e-3;
  const double r = 0.45e-3;
  const double rho_p = 2500.0;
  const int n = D::dim == 2 ? 24 : 16;
  const Frame<D> f = granule::test::lattice_frame<D>(n, a, r, rho_p);
  const double vp = D::volume(r, f.thickness);
  const double rho_exact = rho_p * vp / (std::pow(a, D::dim) * slab(f));
  const double phi_exact = vp / (std::pow(a, D::dim) * slab(f));
  for (double w_over_a : {1.0, 1.5}) {
    const GaussianCgKernel<D> kernel(w_over_a * a, 4.0 * w_over_a * a);
    const RegularGrid<D> grid(Vec::Zero(), Vec::Constant((n - 1) * a), 0.5 * a);
    const double edge = kernel.cutoff() + a;
    for (int path = 0; path < 2; ++path) {
      const CgFields<D> cg = path == 0 ? coarse_grain_direct(f, grid, kernel)
                                       : coarse_grain_fft(f, grid, kernel);
      std::size_t checked = 0;
      double worst_rho = 0.0;
      double worst_phi = 0.0;
      for (std::size_t t = 0; t < grid.size(); ++t) {
        const Vec x = grid.node(t);
        if ((x.array() < edge).any() || (x.array() > (n - 1) * a - edge).any()) continue;
        ++checked;
        worst_rho = std::max(worst_rho, std::abs(cg.density[t] / rho_exact - 1.0));
        worst_phi = std::max(worst_phi, std::abs(cg.packing_fraction[t] / phi_exact - 1.0));
      }
      INFO("path " << path << " w/a " << w_over_a);
      CHECK(checked > 0);
      CHECK(worst_rho < 1e-3);
      CHECK(worst_phi < 1e-3);
    }
  }
}

TEMPLATE_TEST_CASE("cg velocity of a rigid rotation is exact at lattice inversion centres",
                   "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  // v_i = Ω × (x_i − x0). V(r) = Ω × (r̄ − x0) with r̄ = Σ m G(r − x_i) x_i / Σ m G; at a node
  // that is an inversion centre of the lattice (site, mid-edge, face or cell centre: every node
  // of a grid of spacing a/2 aligned with the lattice) the truncated ball of sites is symmetric,
  // so r̄ = r exactly and V(r) = Ω × (r − x0) to round-off, for any kernel width and cutoff.
  const double a = 1.0e-3;
  const int n = D::dim == 2 ? 20 : 12;
  Frame<D> f = granule::test::lattice_frame<D>(n, a, 0.4e-3, 2500.0);
  const Vec x0 = Vec::Constant(0.37e-3);
  typename D::AngVec omega;
  if constexpr (D::dim == 2) {
    omega = 3.0;
  } else {
    omega = Vec(1.0, -2.0, 0.5);
  }
  for (std::size_t i = 0; i < f.size(); ++i) f.v[i] = D::cross(omega, Vec(f.x[i] - x0));
  const GaussianCgKernel<D> kernel(1.2 * a);
  const RegularGrid<D> grid(Vec::Zero(), Vec::Constant((n - 1) * a), 0.5 * a);
  const double edge = kernel.cutoff() + a;
  const double vscale = D::norm(omega) * n * a;
  for (int path = 0; path < 2; ++path) {
    const CgFields<D> cg = path == 0 ? coarse_grain_direct(f, grid, kernel)
                                     : coarse_grain_fft(f, grid, kernel);
    double worst = 0.0;
    std::size_t checked = 0;
    for (std::size_t t = 0; t < grid.size(); ++t) {
      const Vec x = grid.node(t);
      if ((x.array() < edge).any() || (x.array() > (n - 1) * a - edge).any()) continue;
      ++checked;
      worst = std::max(worst, (cg.velocity[t] - D::cross(omega, Vec(x - x0))).norm());
    }
    INFO("path " << path);
    CHECK(checked > 0);
    CHECK(worst < 1e-12 * vscale);
  }
}

TEMPLATE_TEST_CASE("cg conserves mass", "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  const std::size_t n = D::dim == 2 ? 400 : 300;
  Frame<D> f = granule::test::random_frame<D>(n, Vec::Zero(), Vec::Constant(8e-3), 0.5e-3, 2500.0);
  if constexpr (D::dim == 2) {
    f.thickness = 2.0e-3;  // exercise the out-of-plane scaling
    for (std::size_t i = 0; i < n; ++i) f.mass[i] = 2500.0 * D::volume(f.radius[i], f.thickness);
  }
  const double mass = total_mass(f);
  const double w = 1.0e-3;
  const double h = 0.5 * w;
  // Direct path, c = 7w, w = 2h: the node sum Σ ρ h^D equals ∫ρ dV = M up to the lattice error
  // of the truncated Gaussian, e^{−24.5} ≈ 2e-11 relative to the peak (measured ≤ 6e-12).
  {
    const GaussianCgKernel<D> kernel(w, 7.0 * w);
    const auto grid = RegularGrid<D>::covering(f, h, kernel.cutoff() + h);
    const auto cg = coarse_grain_direct(f, grid, kernel);
    CHECK(std::abs(integrate(grid, cg.density) * slab(f) / mass - 1.0) < 1e-10);
  }
  // Default cutoff c = 3w: the same sum carries the truncation's lattice error (≈ 1e-3).
  {
    const GaussianCgKernel<D> kernel(w);
    const auto grid = RegularGrid<D>::covering(f, h, kernel.cutoff() + h);
    const auto cg = coarse_grain_direct(f, grid, kernel);
    const double err = std::abs(integrate(grid, cg.density) * slab(f) / mass - 1.0);
    std::printf("[cg] %dD direct path, c = 3w, w = 2h: relative mass error %.2e\n", D::dim, err);
    CHECK(err < 5e-3);
    // Grid path: the sampled kernel is normalised discretely, the CIC weights sum to one, so the
    // node sum equals M to round-off.
    const auto cgf = coarse_grain_fft(f, grid, kernel);
    CHECK(std::abs(integrate(grid, cgf.density) * slab(f) / mass - 1.0) < 1e-12);
  }
}

TEMPLATE_TEST_CASE("cg kinetic stress of two counter-moving coincident particles",
                   "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  // Two equal particles at the same point with velocities ±u: V = 0 everywhere and
  // σ^k(r) = −Σ m v v G = −2 m u uᵀ G(r − x).
  Frame<D> f;
  const double h = 0.25e-3;
  const Vec x = Vec::Constant(8.0 * h);  // on a grid node (FFT path: exact CIC deposit)
  Vec u = Vec::Zero();
  u[0] = 0.3;
  u[1] = -0.2;
  granule::test::add_particle<D>(f, x, u, 0.5e-3, 2000.0);
  granule::test::add_particle<D>(f, x, Vec(-u), 0.5e-3, 2000.0);
  f.box_lo = Vec::Zero();
  f.box_hi = Vec::Constant(16.0 * h);
  // c/h = 6.3 is not an integer: no node sits exactly on the cutoff sphere, where rounding
  // would decide whether the kernel's discontinuity is included.
  const GaussianCgKernel<D> kernel(2.1 * h);
  const RegularGrid<D> grid(Vec::Zero(), Vec::Constant(16.0 * h), h);
  const double m = f.mass[0];
  const double discrete = sampled_kernel_sum(kernel, h);
  for (int path = 0; path < 2; ++path) {
    const auto cg = path == 0 ? coarse_grain_direct(f, grid, kernel) : coarse_grain_fft(f, grid, kernel);
    // The grid path uses the discretely normalised kernel: G / Σ_k G(kh) h^D.
    const double norm = path == 0 ? 1.0 : 1.0 / discrete;
    const double peak = 2.0 * m * u.squaredNorm() * kernel.value_sq(0.0) * norm / slab(f);
    double worst = 0.0;
    double worst_v = 0.0;
    for (std::size_t t = 0; t < grid.size(); ++t) {
      const Mat expected =
          -2.0 * m * u * u.transpose() * kernel.value(Vec(grid.node(t) - x)) * norm / slab(f);
      worst = std::max(worst, (cg.kinetic_stress[t] - expected).norm());
      worst_v = std::max(worst_v, cg.velocity[t].norm());
    }
    INFO("path " << path);
    CHECK(worst < 1e-12 * peak);
    CHECK(worst_v < 1e-12);
  }
}

TEMPLATE_TEST_CASE("cg contact stress of a two-particle contact and a wall contact",
                   "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  // A static contact between i and j = i + b, force F = fn n + ft on i (n = −b/|b|, ft ⊥ n),
  // and a wall contact of i with branch b_w to the contact point and force F_w.
  // σ^c(r) = b Fᵀ L(r − x_i, b) + b_w F_wᵀ L(r − x_i, b_w), L the kernel's line integral;
  // ∫σ^c dV = b Fᵀ + b_w F_wᵀ (each line integral integrates to one).
  Frame<D> f;
  const double rad = 0.5e-3;
  Vec xi = Vec::Constant(5.1e-3);
  Vec b = Vec::Zero();
  b[0] = 0.8 * 2.0 * rad;
  b[1] = 0.6 * 2.0 * rad * 0.99;
  granule::test::add_particle<D>(f, xi, Vec::Zero(), rad, 2500.0);
  granule::test::add_particle<D>(f, Vec(xi + b), Vec::Zero(), rad, 2500.0);
  f.box_lo = Vec::Zero();
  f.box_hi = Vec::Constant(10.2e-3);
  ContactRecord<D> c;
  c.i = 0;
  c.j = 1;
  c.branch = b;
  c.normal = -b.normalized();
  c.fn = 2.5;
  Vec t = Vec::Zero();
  t[0] = -c.normal[1];
  t[1] = c.normal[0];
  c.ft = 0.7 * t;
  f.contacts.push_back(c);
  ContactRecord<D> wc;
  wc.i = 0;
  wc.j = ContactRecord<D>::kWall;
  Vec bw = Vec::Zero();
  bw[D::dim - 1] = -rad;
  wc.branch = bw;
  wc.normal = -bw.normalized();
  wc.fn = 4.0;
  Vec tw = Vec::Zero();
  tw[0] = 1.1;
  wc.ft = tw;
  f.contacts.push_back(wc);
  const Vec force = c.fn * c.normal + c.ft;
  const Vec wall_force = wc.fn * wc.normal + wc.ft;
  const Mat total = b * force.transpose() + bw * wall_force.transpose();

  const double w = 0.6e-3;
  {
    // Pointwise against the closed form; integral with c = 8w, h = w/2 (lattice error ~1e-14).
    const GaussianCgKernel<D> kernel(w, 8.0 * w);
    const auto grid = RegularGrid<D>::covering(f, 0.5 * w, kernel.cutoff() + w);
    const auto cg = coarse_grain_direct(f, grid, kernel);
    Mat integral = Mat::Zero();
    double worst = 0.0;
    for (std::size_t k = 0; k < grid.size(); ++k) {
      integral += cg.contact_stress[k] * grid.cell_volume() * slab(f);
      const Vec a = grid.node(k) - xi;
      // Both segments lie inside the support when |a| + |b| < c: no clipping, closed form.
      if (a.norm() + b.norm() < kernel.cutoff()) {
        const Mat expected = (b * force.transpose() * gaussian_segment(a, b, w, 0.0, 1.0) +
                              bw * wall_force.transpose() * gaussian_segment(a, bw, w, 0.0, 1.0)) /
                             (kernel.normalisation() * slab(f));
        worst = std::max(worst, (cg.contact_stress[k] - expected).norm());
      }
    }
    const double peak = total.norm() * kernel.value_sq(0.0) / slab(f);
    CHECK(worst < 1e-13 * peak);
    CHECK((integral - total).norm() < 1e-10 * total.norm());
  }
  {
    // Grid path, default cutoff: the integral is exact to round-off (discrete normalisation,
    // CIC and Gauss weights summing to one).
    const GaussianCgKernel<D> kernel(w);
    const auto grid = RegularGrid<D>::covering(f, 0.5 * w, kernel.cutoff() + w);
    const auto cg = coarse_grain_fft(f, grid, kernel);
    Mat integral = Mat::Zero();
    for (std::size_t k = 0; k < grid.size(); ++k)
      integral += cg.contact_stress[k] * grid.cell_volume() * slab(f);
    CHECK((integral - total).norm() < 1e-12 * total.norm());
  }
}

TEMPLATE_TEST_CASE("cg grid path converges to the direct path as w/h grows",
                   "[analysis][coarse_graining]", Dim2, Dim3) {
  using D = TestType;
  const double r = 0.5e-3;
  const std::size_t n = D::dim == 2 ? 150 : 200;
  const double size = D::dim == 2 ? 10e-3 : 6e-3;
  const Frame<D> f = random_frame_with_contacts<D>(n, size, r, 99);
  const double w = 1.0e-3;
  const GaussianCgKernel<D> kernel(w);
  double previous = 1.0;
  for (double ratio : {1.0, 2.0, 4.0}) {
    const auto grid = RegularGrid<D>::covering(f, w / ratio, 0.0);
    const auto direct = coarse_grain_direct(f, grid, kernel);
    const auto fft = coarse_grain_fft(f, grid, kernel);
    double rho_max = 0.0;
    double sig_max = 0.0;
    for (std::size_t t = 0; t < grid.size(); ++t) {
      rho_max = std::max(rho_max, direct.density[t]);
      sig_max = std::max(sig_max, direct.contact_stress[t].norm());
    }
    double err_rho = 0.0;
    double err_sig = 0.0;
    for (std::size_t t = 0; t < grid.size(); ++t) {
      err_rho = std::max(err_rho, std::abs(fft.density[t] - direct.density[t]) / rho_max);
      err_sig = std::max(err_sig, (fft.contact_stress[t] - direct.contact_stress[t]).norm() / sig_max);
    }
    INFO("w/h = " << ratio << " density error " << err_rho << " contact stress error " << err_sig);
    // CIC is linear interpolation of G between nodes: error ≲ (h/w)²/8 · max|G''| w² / max G.
    CHECK(err_rho < 0.2 / (ratio * ratio));
    CHECK(err_sig < 0.2 / (ratio * ratio));
    CHECK(err_rho < previous);
    previous = err_rho;
  }
}

TEST_CASE("cg handles periodic axes in both paths", "[analysis][coarse_graining]") {
  using D = Dim2;
  using Vec = D::Vec;
  Frame<D> f = granule::test::random_frame<D>(200, Vec(0.0, 0.0), Vec(12e-3, 8e-3), 0.4e-3, 2500.0, 5);
  f.periodic[0] = true;
  const double w = 0.8e-3;
  const GaussianCgKernel<D> kernel(w);
  const auto grid = RegularGrid<D>::covering(f, w / 4.0, kernel.cutoff() + w);
  REQUIRE(grid.periodic()[0]);
  REQUIRE(grid.period(0) == Approx(12e-3).epsilon(1e-14));
  const auto direct = coarse_grain_direct(f, grid, kernel);
  const auto fft = coarse_grain_fft(f, grid, kernel);
  const double mass = total_mass(f);
  // Circular convolution along x keeps the mass exactly in the grid path.
  CHECK(std::abs(integrate(grid, fft.density) * slab(f) / mass - 1.0) < 1e-12);
  double rho_max = 0.0;
  for (double r : direct.density) rho_max = std::max(rho_max, r);
  double err = 0.0;
  for (std::size_t t = 0; t < grid.size(); ++t)
    err = std::max(err, std::abs(fft.density[t] - direct.density[t]) / rho_max);
  CHECK(err < 0.15 / 16.0);

  // A single particle just inside x = 0 contributes at the node just below x = L through the
  // minimum image: ρ = m G(d_min) / t.
  Frame<D> one;
  granule::test::add_particle<D>(one, Vec(0.1e-3, 4e-3), Vec::Zero(), 0.4e-3, 2500.0);
  one.box_lo = Vec(0.0, 0.0);
  one.box_hi = Vec(12e-3, 8e-3);
  one.periodic[0] = true;
  const auto g1 = RegularGrid<D>::covering(one, 0.5e-3, kernel.cutoff() + w);
  const auto cg1 = coarse_grain_direct(one, g1, kernel);
  const D::IVec k(g1.count()[0] - 1, static_cast<int>(std::lround((4e-3 - g1.lo()[1]) / 0.5e-3)));
  const Vec node = g1.node(k);
  const Vec d(node[0] - 12e-3 - 0.1e-3, node[1] - 4e-3);
  CHECK(cg1.density[g1.index(k)] == Approx(one.mass[0] * kernel.value(d)).epsilon(1e-13));
}

TEST_CASE("cg rejects invalid input", "[analysis][coarse_graining]") {
  using D = Dim3;
  using Vec = D::Vec;
  CHECK_THROWS_AS(GaussianCgKernel<D>(0.0), granule::InvalidParameter);
  CHECK_THROWS_AS(GaussianCgKernel<D>(1e-3, 0.5e-3), granule::InvalidParameter);
  CHECK_THROWS_AS(RegularGrid<D>(Vec::Zero(), Vec::Ones(), -1.0), granule::InvalidParameter);
  CHECK_THROWS_AS(RegularGrid<D>(Vec::Ones(), Vec::Zero(), 0.1), granule::InvalidParameter);
  Frame<D> f = granule::test::random_frame<D>(10, Vec::Zero(), Vec::Constant(5e-3), 0.4e-3, 2500.0);
  const GaussianCgKernel<D> kernel(1e-3);
  const RegularGrid<D> grid(Vec::Zero(), Vec::Constant(5e-3), 0.5e-3);
  // Periodic frame with a non-periodic grid: the FFT path cannot wrap, it refuses.
  f.periodic[2] = true;
  CHECK_THROWS_AS(coarse_grain_fft(f, grid, kernel), granule::InvalidParameter);
  // Cutoff larger than half the period: the minimum image is ambiguous.
  CHECK_THROWS_AS(coarse_grain_direct(f, grid, GaussianCgKernel<D>(1e-3, 2.6e-3)),
                  granule::InvalidParameter);
  // Periodic axis without a box length.
  Frame<D> nobox = f;
  nobox.box_hi[2] = nobox.box_lo[2];
  CHECK_THROWS_AS(coarse_grain_direct(nobox, grid, kernel), granule::InvalidParameter);
  f.periodic[2] = false;
  f.mass.pop_back();
  CHECK_THROWS_AS(coarse_grain_direct(f, grid, kernel), granule::InvalidParameter);
}

// Grid-vs-direct accuracy and speed table for docs/analysis.md (hidden, slow: run with
// `<test binary> "[cg_table]"`).
TEMPLATE_TEST_CASE("cg grid vs direct error and speed table", "[.slow][analysis][cg_table]", Dim2,
                   Dim3) {
  using D = TestType;
  using clock = std::chrono::steady_clock;
  const double r = 0.5e-3;
  const std::size_t n = D::dim == 2 ? 3000 : 3000;
  const double size = D::dim == 2 ? 40e-3 : 14e-3;
  const Frame<D> f = random_frame_with_contacts<D>(n, size, r, 2024);
  const double w = 1.0e-3;
  const GaussianCgKernel<D> kernel(w);
  std::printf("%dD: %zu particles, %zu contacts, w = 1 mm = 2r, c = 3w\n", D::dim, f.size(),
              f.contacts.size());
  std::printf("| w/h | nodes | direct wall / CPU [s] | grid wall / CPU [s] | max err rho | "
              "max err V (rho > 0.1 max) | max err sigma_c | mass err direct | mass err grid |\n");
  for (double ratio : {0.5, 1.0, 2.0, 4.0, 8.0}) {
    if (D::dim == 3 && ratio > 4.0) continue;
    const auto grid = RegularGrid<D>::covering(f, w / ratio, kernel.cutoff() + w);
    const auto t0 = clock::now();
    const std::clock_t c0 = std::clock();
    const auto direct = coarse_grain_direct(f, grid, kernel);
    const auto t1 = clock::now();
    const std::clock_t c1 = std::clock();
    const auto fft = coarse_grain_fft(f, grid, kernel);
    const auto t2 = clock::now();
    const std::clock_t c2 = std::clock();
    double rho_max = 0.0;
    double sig_max = 0.0;
    for (std::size_t t = 0; t < grid.size(); ++t) {
      rho_max = std::max(rho_max, direct.density[t]);
      sig_max = std::max(sig_max, direct.contact_stress[t].norm());
    }
    double err_rho = 0.0;
    double err_v = 0.0;
    double err_sig = 0.0;
    for (std::size_t t = 0; t < grid.size(); ++t) {
      err_rho = std::max(err_rho, std::abs(fft.density[t] - direct.density[t]) / rho_max);
      if (direct.density[t] > 0.1 * rho_max)
        err_v = std::max(err_v, (fft.velocity[t] - direct.velocity[t]).norm());
      err_sig = std::max(err_sig, (fft.contact_stress[t] - direct.contact_stress[t]).norm() / sig_max);
    }
    const double mass = total_mass(f) / slab(f);
    const double cps = static_cast<double>(CLOCKS_PER_SEC);
    std::printf("| %.1f | %zu | %.2f / %.2f | %.2f / %.2f | %.2e | %.2e m/s | %.2e | %.1e | %.1e |\n",
                ratio, grid.size(), std::chrono::duration<double>(t1 - t0).count(),
                static_cast<double>(c1 - c0) / cps, std::chrono::duration<double>(t2 - t1).count(),
                static_cast<double>(c2 - c1) / cps, err_rho, err_v, err_sig,
                std::abs(integrate(grid, direct.density) / mass - 1.0),
                std::abs(integrate(grid, fft.density) / mass - 1.0));
  }
  SUCCEED();
}
