// Tests of granule/analysis/strain_rate.hpp. References: finite differences are exact for
// quadratic fields; the central difference of sin(kx) is cos(kx) sin(kh)/h exactly; a rigid
// rotation has zero strain rate and simple shear u = (γ̇ y, 0, 0) has ε̇_xy = ε̇_yx = γ̇/2,
// |ε̇| = γ̇/√2 (paper 000 section IV definitions).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "frame_builders.hpp"
#include "granule/analysis/strain_rate.hpp"

using granule::Dim2;
using granule::Dim3;
using namespace granule::analysis;

TEMPLATE_TEST_CASE("strain rate of quadratic fields is exact on the whole grid",
                   "[analysis][strain_rate]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;
  const RegularGrid<D> grid(Vec::Zero(), Vec::Constant(1.0), Vec::Constant(0.125));
  Mat A = Mat::Zero();
  for (int a = 0; a < D::dim; ++a)
    for (int b = 0; b < D::dim; ++b) A(a, b) = 0.3 * a - 0.7 * b + 0.1 * (a + 1) * (b + 2);
  // u = A x + c + (x_0², 0, …): ∇u = A + 2 x_0 e_0 e_0ᵀ.
  std::vector<Vec> u(grid.size());
  for (std::size_t t = 0; t < grid.size(); ++t) {
    const Vec x = grid.node(t);
    u[t] = A * x + Vec::Constant(0.4);
    u[t][0] += x[0] * x[0];
  }
  const auto g = velocity_gradient(grid, u);
  const auto e = strain_rate(grid, u);
  double worst = 0.0;
  double worst_e = 0.0;
  for (std::size_t t = 0; t < grid.size(); ++t) {
    Mat expected = A;
    expected(0, 0) += 2.0 * grid.node(t)[0];
    worst = std::max(worst, (g[t] - expected).norm());
    worst_e = std::max(worst_e, (e[t] - 0.5 * (expected + expected.transpose())).norm());
  }
  CHECK(worst < 1e-13);
  CHECK(worst_e < 1e-13);
}

TEST_CASE("strain rate across a periodic axis", "[analysis][strain_rate]") {
  using D = Dim2;
  using Vec = D::Vec;
  // u_x = sin(k x) on a periodic x axis: central difference = cos(k x) sin(k h)/h exactly,
  // at the wrapped end nodes too.
  RegularGrid<D> grid(Vec(0.0, 0.0), Vec(0.95, 0.5), 0.05);
  grid.set_periodic(0, true);
  REQUIRE(grid.period(0) == Approx(1.0));
  const double k = 2.0 * std::numbers::pi;
  const double h = 0.05;
  std::vector<Vec> u(grid.size());
  for (std::size_t t = 0; t < grid.size(); ++t) u[t] = Vec(std::sin(k * grid.node(t)[0]), 0.0);
  const auto g = velocity_gradient(grid, u);
  double worst = 0.0;
  for (std::size_t t = 0; t < grid.size(); ++t)
    worst = std::max(worst, std::abs(g[t](0, 0) - std::cos(k * grid.node(t)[0]) * std::sin(k * h) / h));
  CHECK(worst < 1e-12);
}

TEMPLATE_TEST_CASE("strain rate of coarse-grained rigid rotation and simple shear",
                   "[analysis][strain_rate]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  // Lattice with grid nodes at its inversion centres: the CG velocity equals the imposed linear
  // field exactly there (see test_coarse_graining.cpp), and central differences of a linear field
  // are exact, so ε̇ = 0 (rotation) and |ε̇| = γ̇/√2 (shear) at interior nodes to round-off.
  const double a = 1.0e-3;
  const int n = D::dim == 2 ? 20 : 12;
  Frame<D> f = granule::test::lattice_frame<D>(n, a, 0.4e-3, 2500.0);
  // c = 3.3 a: no lattice site lies exactly on the cutoff sphere of a node, where round-off
  // alone would decide whether the kernel's jump is included and break the symmetry.
  const GaussianCgKernel<D> kernel(1.1 * a);
  const RegularGrid<D> grid(Vec::Zero(), Vec::Constant((n - 1) * a), 0.5 * a);
  const double edge = kernel.cutoff() + 1.5 * a;
  auto interior = [&](std::size_t t) {
    const Vec x = grid.node(t);
    return !((x.array() < edge).any() || (x.array() > (n - 1) * a - edge).any());
  };
  typename D::AngVec omega;
  if constexpr (D::dim == 2) {
    omega = 5.0;
  } else {
    omega = Vec(2.0, 1.0, -3.0);
  }
  for (std::size_t i = 0; i < f.size(); ++i) f.v[i] = D::cross(omega, f.x[i]);
  const auto rot = strain_rate(coarse_grain_direct(f, grid, kernel), 0.0);
  const double gamma = 40.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    f.v[i] = Vec::Zero();
    f.v[i][0] = gamma * f.x[i][1];
  }
  const auto cg = coarse_grain_direct(f, grid, kernel);
  const auto shear = strain_rate(cg, 0.0);
  const auto mag = strain_rate_magnitude(shear);
  std::size_t checked = 0;
  double worst_rot = 0.0;
  double worst_mag = 0.0;
  double worst_xy = 0.0;
  for (std::size_t t = 0; t < grid.size(); ++t) {
    if (!interior(t)) continue;
    ++checked;
    worst_rot = std::max(worst_rot, strain_rate_magnitude(rot[t]));
    worst_mag = std::max(worst_mag, std::abs(mag[t] - gamma / std::sqrt(2.0)));
    worst_xy = std::max(worst_xy, std::abs(shear[t](0, 1) - gamma / 2));
  }
  CHECK(checked > 0);
  CHECK(worst_rot < 1e-10 * D::norm(omega));
  CHECK(worst_mag < 1e-10 * gamma);
  CHECK(worst_xy < 1e-10 * gamma);
  // Nodes whose stencil reaches below the density threshold are NaN.
  double rho_max = 0.0;
  for (double r : cg.density) rho_max = std::max(rho_max, r);
  const auto masked = strain_rate(cg, 0.5 * rho_max);
  CHECK(std::isnan(masked[0](0, 0)));
  const std::size_t centre = grid.index(D::IVec::Constant(n - 1));
  CHECK_FALSE(std::isnan(masked[centre](0, 1)));
}
