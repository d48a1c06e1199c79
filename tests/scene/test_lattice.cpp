// Lattices: counts per axis floor((L - 2r)/s) + 1 (hand-computed for each case), nearest
// neighbour distance s, FCC coordination number 12 (Conway & Sloane 1999, ch. 1), all
// particles inside the region, clipping by a predicate.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "granule/scene/lattice.hpp"

using namespace granule;
using namespace granule::scene;
using geometry::Aabb;

namespace {
template <class V>
double min_pair_distance(const std::vector<V>& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) best = std::min(best, (p[i] - p[j]).norm());
  }
  return best;
}
template <class D>
void check_inside(const std::vector<typename D::Vec>& p, const Aabb<D>& box, double r) {
  for (const auto& x : p) {
    CHECK(((x.array() - r) >= box.lo.array() - 1e-12).all());
    CHECK(((x.array() + r) <= box.hi.array() + 1e-12).all());
  }
}
}  // namespace

TEMPLATE_TEST_CASE("simple_lattice counts and spacing", "[scene][lattice]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const Aabb<TestType> box(Vec::Zero(), Vec::Ones());
  // (1 - 0.1)/0.1 + 1 = 10 per axis: the boundary points are kept.
  auto p = simple_lattice<TestType>(box, 0.05, 0.1);
  CHECK(p.size() == static_cast<std::size_t>(std::pow(10, TestType::dim)));
  CHECK(min_pair_distance(p) == Approx(0.1));
  check_inside(p, box, 0.05);
  // floor(0.9/0.11) + 1 = 9 per axis.
  p = simple_lattice<TestType>(box, 0.05, 0.11);
  CHECK(p.size() == static_cast<std::size_t>(std::pow(9, TestType::dim)));
  // Clip to a ball of radius 0.3 around the centre.
  const Vec c = Vec::Constant(0.5);
  p = simple_lattice<TestType>(box, 0.05, 0.1, [&](const Vec& x) { return (x - c).norm() < 0.3; });
  for (const auto& x : p) CHECK((x - c).norm() < 0.3);
  // 2D: points (0.05 + 0.1 i) within 0.3 of 0.5: i, j in 2..7 minus corners -> counted by hand below.
  std::size_t expect = 0;
  const int n = 10;
  if constexpr (TestType::dim == 2) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) expect += std::hypot(0.05 + 0.1 * i - 0.5, 0.05 + 0.1 * j - 0.5) < 0.3;
  } else {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k)
          expect += std::sqrt(std::pow(0.05 + 0.1 * i - 0.5, 2) + std::pow(0.05 + 0.1 * j - 0.5, 2) +
                              std::pow(0.05 + 0.1 * k - 0.5, 2)) < 0.3;
  }
  CHECK(p.size() == expect);
  CHECK(simple_lattice<TestType>(Aabb<TestType>(Vec::Zero(), Vec::Constant(0.05)), 0.05, 0.1).empty());
  CHECK_THROWS_AS(simple_lattice<TestType>(box, 0.05, 0.09), InvalidParameter);
  CHECK_THROWS_AS(simple_lattice<TestType>(box, 0.0, 0.1), InvalidParameter);
  CHECK_THROWS_AS(simple_lattice<TestType>(Aabb<TestType>::infinite(), 0.05, 0.1), InvalidParameter);
}

TEST_CASE("hexagonal_lattice rows and spacing", "[scene][lattice]") {
  const Aabb<Dim2> box(Dim2::Vec(0, 0), Dim2::Vec(1, 1));
  const auto p = hexagonal_lattice(box, 0.05, 0.1);
  // Rows 0.0866 apart: floor(0.9/0.0866) + 1 = 11 rows; even rows hold 10 disks
  // (x = 0.05 .. 0.95), odd rows 9 (x = 0.1 .. 0.9): 6 * 10 + 5 * 9 = 105.
  CHECK(p.size() == 105u);
  CHECK(min_pair_distance(p) == Approx(0.1));
  check_inside(p, box, 0.05);
  // Each interior disk has 6 neighbours at distance s.
  const Dim2::Vec centre = p[5 * 10 + 2 * 9 + 4];  // row 4 (even), 5th disk
  int neighbours = 0;
  for (const auto& q : p) neighbours += std::abs((q - centre).norm() - 0.1) < 1e-12;
  CHECK(neighbours == 6);
}

TEST_CASE("fcc_lattice count, spacing and coordination", "[scene][lattice]") {
  const Aabb<Dim3> box(Dim3::Vec::Zero(), Dim3::Vec::Ones());
  const double s = 0.1 * std::sqrt(2.0);  // half cube edge 0.1
  const auto p = fcc_lattice(box, 0.05, s);
  // 10 grid positions per axis, half of the 1000 grid points have an even index sum.
  CHECK(p.size() == 500u);
  CHECK(min_pair_distance(p) == Approx(s));
  check_inside(p, box, 0.05);
  Dim3::Vec centre(0.45, 0.45, 0.45);  // indices (4, 4, 4): even sum
  int neighbours = 0;
  bool present = false;
  for (const auto& q : p) {
    neighbours += std::abs((q - centre).norm() - s) < 1e-12;
    present = present || (q - centre).norm() < 1e-12;
  }
  CHECK(present);
  CHECK(neighbours == 12);
  // Close packing (s = 2r) in a large box approaches pi/(3 sqrt 2) = 0.7405.
  const double r = 0.01;
  const auto dense = fcc_lattice(box, r, 2 * r);
  const double phi = dense.size() * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  CHECK(phi == Approx(std::numbers::pi / (3 * std::sqrt(2.0))).epsilon(0.08));
}
