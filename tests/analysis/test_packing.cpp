// Tests of granule/analysis/intersection_volume.hpp, bin_grid.hpp and packing.hpp.
// References: sphere cap V = π h² (3r − h)/3 and circular segment A = r² acos(d/r) − d √(r² − d²)
// (standard geometry, e.g. CRC Standard Mathematical Tables); quadrants / octants by symmetry;
// Monte Carlo estimates with a fixed seed and their binomial standard error.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "frame_builders.hpp"
#include "granule/analysis/packing.hpp"

using granule::Dim2;
using granule::Dim3;
using namespace granule::analysis;
using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

namespace {
constexpr double pi = std::numbers::pi;
constexpr double big = 1e3;
}  // namespace

TEST_CASE("disk-rectangle area against analytic shapes and Monte Carlo", "[analysis][packing]") {
  const double r = 0.7;
  const V2 c(0.3, -0.2);
  CHECK(disk_rectangle_area(c, r, V2(-big, -big), V2(big, big)) ==
        Approx(pi * r * r).epsilon(1e-15));
  CHECK(disk_rectangle_area(c, r, c, V2(big, big)) == Approx(pi * r * r / 4).epsilon(1e-14));
  CHECK(disk_rectangle_area(c, r, V2(-big, c.y()), V2(big, big)) ==
        Approx(pi * r * r / 2).epsilon(1e-14));
  CHECK(disk_rectangle_area(c, r, V2(5.0, 5.0), V2(6.0, 6.0)) == 0.0);
  for (double d : {-0.6, -0.2, 0.0, 0.35, 0.69}) {
    // Segment beyond the line x = c_x + d.
    const double seg = r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
    CHECK(disk_rectangle_area(c, r, V2(c.x() + d, -big), V2(big, big)) ==
          Approx(seg).epsilon(1e-13));
    CHECK(disk_rectangle_area(c, r, V2(-big, c.y() + d), V2(big, big)) ==
          Approx(seg).epsilon(1e-13));
  }
  // A partition of the plane into rectangles sums to the full disk.
  double sum = 0.0;
  for (int i = -6; i < 6; ++i)
    for (int j = -6; j < 6; ++j)
      sum += disk_rectangle_area(c, r, V2(0.23 * i, 0.19 * j), V2(0.23 * (i + 1), 0.19 * (j + 1)));
  CHECK(sum == Approx(pi * r * r).epsilon(1e-13));
  // Monte Carlo (fixed seed): a rectangle with one corner inside the disk.
  const V2 lo(0.1, -0.5);
  const V2 hi(1.5, 0.05);
  std::mt19937_64 gen(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int samples = 1000000;
  int in = 0;
  for (int s = 0; s < samples; ++s) {
    const V2 p = c + r * V2(u(gen), u(gen));
    if ((p - c).squaredNorm() < r * r && (p.array() >= lo.array()).all() &&
        (p.array() <= hi.array()).all())
      ++in;
  }
  const double frac = static_cast<double>(in) / samples;
  const double estimate = frac * 4 * r * r;
  const double sigma = 4 * r * r * std::sqrt(frac * (1 - frac) / samples);
  CHECK(std::abs(disk_rectangle_area(c, r, lo, hi) - estimate) < 4 * sigma);
}

TEST_CASE("sphere-box volume against caps, half, quadrant, octant, partitions, Monte Carlo",
          "[analysis][packing]") {
  const double r = 1.3;
  const V3 c(0.2, -0.4, 0.9);
  const double full = 4.0 / 3.0 * pi * r * r * r;
  CHECK(sphere_box_volume(c, r, V3::Constant(-big), V3::Constant(big)) ==
        Approx(full).epsilon(1e-15));
  for (int axis = 0; axis < 3; ++axis) {
    for (double d : {-1.1, -0.5, 0.0, 0.4, 1.25}) {
      // Cap above the plane x_axis = c + d: height h = r − d.
      const double h = r - d;
      const double cap = pi * h * h * (3 * r - h) / 3;
      V3 lo = V3::Constant(-big);
      lo[axis] = c[axis] + d;
      CHECK(sphere_box_volume(c, r, lo, V3::Constant(big)) == Approx(cap).epsilon(1e-13));
    }
  }
  // Half, quadrant and octant through the centre (general path for the last two).
  CHECK(sphere_box_volume(c, r, V3(c.x(), -big, -big), V3::Constant(big)) ==
        Approx(full / 2).epsilon(1e-14));
  CHECK(sphere_box_volume(c, r, V3(c.x(), c.y(), -big), V3::Constant(big)) ==
        Approx(full / 4).epsilon(1e-13));
  CHECK(sphere_box_volume(c, r, c, V3::Constant(big)) == Approx(full / 8).epsilon(1e-13));
  // Half of an x-slab of half-width a: ½ π (2 r² a − 2a³/3) (general path: cut in x and y).
  for (double a : {0.3, 0.9, 1.2}) {
    const double slab = pi * (2 * r * r * a - 2 * a * a * a / 3);
    CHECK(sphere_box_volume(c, r, V3(c.x() - a, c.y(), -big), V3(c.x() + a, big, big)) ==
          Approx(slab / 2).epsilon(1e-13));
  }
  // Quarter of a cap: cap above z = c + d, restricted to x ≥ c_x, y ≥ c_y.
  {
    const double d = 0.5;
    const double h = r - d;
    CHECK(sphere_box_volume(c, r, V3(c.x(), c.y(), c.z() + d), V3::Constant(big)) ==
          Approx(pi * h * h * (3 * r - h) / 12).epsilon(1e-13));
  }
  // Partitions of space into boxes sum to the full volume, for several offsets.
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const V3 w(0.5 + 0.6 * u(gen), 0.4 + 0.8 * u(gen), 0.7 + 0.5 * u(gen));
    const V3 off(u(gen), u(gen), u(gen));
    double sum = 0.0;
    for (int i = -4; i <= 4; ++i)
      for (int j = -5; j <= 5; ++j)
        for (int k = -4; k <= 4; ++k) {
          const V3 lo = c + (V3(i, j, k) - off).cwiseProduct(w);
          sum += sphere_box_volume(c, r, lo, lo + w);
        }
    CHECK(sum == Approx(full).epsilon(1e-13));
  }
  // Monte Carlo (fixed seed): a box with one corner inside the sphere.
  const V3 lo(0.5, -0.9, 0.3);
  const V3 hi(2.0, 0.1, 1.5);
  std::mt19937_64 mc(2024);
  std::uniform_real_distribution<double> s(-1.0, 1.0);
  const int samples = 1000000;
  int in = 0;
  for (int q = 0; q < samples; ++q) {
    const V3 p = c + r * V3(s(mc), s(mc), s(mc));
    if ((p - c).squaredNorm() < r * r && (p.array() >= lo.array()).all() &&
        (p.array() <= hi.array()).all())
      ++in;
  }
  const double frac = static_cast<double>(in) / samples;
  const double cube = 8 * r * r * r;
  const double sigma = cube * std::sqrt(frac * (1 - frac) / samples);
  CHECK(std::abs(sphere_box_volume(c, r, lo, hi) - frac * cube) < 4 * sigma);
  CHECK_THROWS_AS(sphere_box_volume(c, -1.0, lo, hi), granule::InvalidParameter);
}

TEMPLATE_TEST_CASE("packing fraction of a periodic lattice is exact in every bin",
                   "[analysis][packing]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using IVec = typename D::IVec;
  // Lattice of spacing a, shifted so that particles straddle bin faces, edges and corners; the
  // box is periodic and the bins tile it, so every bin holds exactly one particle volume per a^D.
  const double a = 1.0e-3;
  const double r = 0.45e-3;
  const int n = 6;
  Frame<D> f = granule::test::lattice_frame<D>(n, a, r, 2500.0, Vec::Constant(0.13e-3));
  f.box_lo = Vec::Zero();
  f.box_hi = Vec::Constant(n * a);
  f.periodic.setConstant(true);
  const double exact = (D::dim == 2 ? pi * r * r : 4.0 / 3.0 * pi * r * r * r) / std::pow(a, D::dim);
  for (int per_cell : {1, 2}) {
    const BinGrid<D> bins(Vec::Zero(), Vec::Constant(n * a), IVec::Constant(n / per_cell));
    const auto phi = packing_fraction(f, bins);
    for (double p : phi) CHECK(p == Approx(exact).epsilon(1e-12));
  }
  // Paper 001 sensor grid: one bin across the periodic width (axis 0), fine bins elsewhere.
  IVec cnt = IVec::Constant(n);
  cnt[0] = 1;
  const auto phi = packing_fraction(f, BinGrid<D>(Vec::Zero(), Vec::Constant(n * a), cnt));
  for (double p : phi) CHECK(p == Approx(exact).epsilon(1e-12));
  // Without periodicity the particles crossing the outer box faces lose their outer parts.
  f.periodic.setConstant(false);
  const auto open = packing_fraction(f, BinGrid<D>(Vec::Zero(), Vec::Constant(n * a), cnt));
  double total = 0.0;
  for (double p : open) total += p;
  CHECK(total / static_cast<double>(open.size()) < exact);
}

TEMPLATE_TEST_CASE("bed height per column from the top particles", "[analysis][packing]", Dim2,
                   Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  using IVec = typename D::IVec;
  const double r = 1e-3;
  Frame<D> f;
  // Two columns along axis 0 of width 4r; heights z = 1, 3, 5, 7 mm in column 0 and 2, 4 mm in
  // column 1 (vertical axis = last).
  auto put = [&](double x0, double z) {
    Vec x = Vec::Constant(2e-3);
    x[0] = x0;
    x[D::dim - 1] = z;
    granule::test::add_particle<D>(f, x, Vec::Zero(), r, 2500.0);
  };
  for (double z : {1e-3, 3e-3, 5e-3, 7e-3}) put(1e-3, z);
  for (double z : {2e-3, 4e-3}) put(6e-3, z);
  IVec cnt = IVec::Ones();
  cnt[0] = 2;
  Vec hi = Vec::Constant(4e-3);
  hi[0] = 8e-3;
  hi[D::dim - 1] = 1.0;
  const BinGrid<D> cols(Vec::Zero(), hi, cnt);
  // Fixed N_h = 3: column 0 → (7 + 5 + 3)/3 mm; column 1 has only 2 particles → (4 + 2)/2.
  auto h = bed_height(f, cols, D::dim - 1, 3);
  CHECK(h[0].height == Approx(5e-3).epsilon(1e-14));
  CHECK(h[0].used == 3);
  CHECK(h[1].height == Approx(3e-3).epsilon(1e-14));
  CHECK(h[1].used == 2);
  // Automatic N_h: 2D width / diameter = 4r / 2r = 2; 3D (4r · 4r) / (π r²) = 16/π ≈ 5.1 → 5.
  h = bed_height(f, cols);
  if constexpr (D::dim == 2) {
    CHECK(h[0].used == 2);
    CHECK(h[0].height == Approx(6e-3).epsilon(1e-14));
  } else {
    CHECK(h[0].used == 4);  // only 4 particles in the column
    CHECK(h[0].height == Approx(4e-3).epsilon(1e-14));
  }
  CHECK_THROWS_AS(bed_height(f, BinGrid<D>(Vec::Zero(), hi, IVec::Constant(2))),
                  granule::InvalidParameter);
}
