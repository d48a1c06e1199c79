// PlaneShape: signed distance (x - p).n, foot point x - d n, constant normal (analytic).
#include <catch2/catch.hpp>

#include "granule/boundaries/geometry/plane.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;

TEMPLATE_TEST_CASE("PlaneShape distance, normal and foot point", "[geometry][plane]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Vec p = Vec::Zero();
  p[TestType::dim - 1] = 1.0;
  Vec n = Vec::Zero();
  n[0] = 3.0;
  n[TestType::dim - 1] = 4.0;  // normalised to (0.6, .., 0.8)
  const PlaneShape<TestType> plane(p, n);
  Vec x = Vec::Constant(2.0);
  const auto s = plane.closest(x);
  // (x - p).n = 2 * 0.6 + (2 - 1) * 0.8 = 2.0
  CHECK(s.distance == Approx(2.0).epsilon(1e-15));
  CHECK(s.normal[0] == Approx(0.6));
  CHECK(s.normal[TestType::dim - 1] == Approx(0.8));
  test::check_convention(x, s);
  CHECK(std::abs((s.point - p).dot(s.normal)) < 1e-15);
  CHECK(s.overlap(2.5) == Approx(0.5));

  // Behind the plane: negative distance, same normal.
  const Vec behind = p - 0.25 * s.normal;
  const auto b = plane.closest(behind);
  CHECK(b.distance == Approx(-0.25));
  test::check_convention(behind, b);

  int calls = 0;
  plane.for_each_contact(x, 2.0, [&](const auto&) { ++calls; });
  CHECK(calls == 0);  // distance 2 is not below r_cut 2
  plane.for_each_contact(x, 2.1, [&](const auto& c) {
    ++calls;
    CHECK(c.distance == Approx(2.0));
  });
  CHECK(calls == 1);
  CHECK_FALSE(plane.bounds().is_finite());
}

TEMPLATE_TEST_CASE("PlaneShape refuses a zero normal", "[geometry][plane]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  CHECK_THROWS_AS(PlaneShape<TestType>(Vec::Zero(), Vec::Zero()), InvalidParameter);
  CHECK_THROWS_WITH(PlaneShape<TestType>(Vec::Zero(), Vec::Zero()), Catch::Contains("|normal|"));
}
