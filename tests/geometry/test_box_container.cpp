// BoxContainerShape: particles inside [lo, hi]; face k distances x_a - lo_a and hi_a - x_a
// with inward normals (analytic); several faces at an inner corner.
#include <catch2/catch.hpp>

#include <vector>

#include "granule/boundaries/geometry/box_container.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;

TEMPLATE_TEST_CASE("BoxContainerShape nearest face from inside", "[geometry][box_container]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const BoxContainerShape<TestType> box(Vec::Zero(), Vec::Constant(1.0));
  Vec x = Vec::Constant(0.5);
  x[0] = 0.9;  // 0.1 from the upper x face
  const auto s = box.closest(x);
  Vec n = Vec::Zero();
  n[0] = -1.0;
  Vec p = x;
  p[0] = 1.0;
  test::check_point(s, 0.1, n, p, 1e-15);
  CHECK(s.feature == 1u);
  test::check_convention(x, s);

  // Lower last-axis face.
  x = Vec::Constant(0.5);
  x[TestType::dim - 1] = 0.05;
  const auto b = box.closest(x);
  CHECK(b.distance == Approx(0.05));
  CHECK(b.normal[TestType::dim - 1] == 1.0);
  CHECK(b.feature == static_cast<std::uint32_t>(2 * (TestType::dim - 1)));
}

TEMPLATE_TEST_CASE("BoxContainerShape reports every face near an inner corner", "[geometry][box_container]", Dim2,
                   Dim3) {
  using Vec = typename TestType::Vec;
  const BoxContainerShape<TestType> box(Vec::Constant(-1.0), Vec::Constant(2.0));
  // Near the lower corner: distances 0.1, 0.2, (0.3).
  Vec x;
  for (int a = 0; a < TestType::dim; ++a) x[a] = -1.0 + 0.1 * (a + 1);
  std::vector<SurfacePoint<TestType>> hits;
  box.for_each_contact(x, 0.5, [&](const SurfacePoint<TestType>& s) { hits.push_back(s); });
  REQUIRE(hits.size() == static_cast<std::size_t>(TestType::dim));
  for (int a = 0; a < TestType::dim; ++a) {
    CHECK(hits[a].feature == static_cast<std::uint32_t>(2 * a));
    CHECK(hits[a].distance == Approx(0.1 * (a + 1)));
    CHECK(hits[a].normal == Vec::Unit(a));
    test::check_convention(x, hits[a]);
  }
  // A smaller cut-off keeps only the nearest face.
  hits.clear();
  box.for_each_contact(x, 0.15, [&](const SurfacePoint<TestType>& s) { hits.push_back(s); });
  REQUIRE(hits.size() == 1u);
  CHECK(hits[0].feature == 0u);
  // In the middle nothing is within 1.0.
  hits.clear();
  box.for_each_contact(Vec::Constant(0.5), 1.0, [&](const SurfacePoint<TestType>& s) { hits.push_back(s); });
  CHECK(hits.empty());
}

TEMPLATE_TEST_CASE("BoxContainerShape pushes an escaped particle back", "[geometry][box_container]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const BoxContainerShape<TestType> box(Vec::Zero(), Vec::Constant(1.0));
  Vec x = Vec::Constant(0.5);
  x[0] = 1.2;
  const auto s = box.closest(x);
  CHECK(s.distance == Approx(-0.2));
  CHECK(s.normal[0] == -1.0);
  test::check_convention(x, s);
  CHECK(box.bounds().lo == Vec::Zero());
  CHECK(box.bounds().hi == Vec::Constant(1.0));
  CHECK_THROWS_AS(BoxContainerShape<TestType>(Vec::Zero(), Vec::Zero()), InvalidParameter);
}
