// CapsuleShape: distance to the core segment minus the radius (analytic), side and both ends,
// on the segment, degenerate segment (sphere).
#include <catch2/catch.hpp>

#include "granule/boundaries/geometry/capsule.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;

TEMPLATE_TEST_CASE("CapsuleShape side and round ends", "[geometry][capsule]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const int up = TestType::dim - 1;
  const Vec a = Vec::Zero();
  const Vec b = 2.0 * Vec::Unit(up);
  const CapsuleShape<TestType> cap(a, b, 0.5);
  // Side: 1 from the axis.
  Vec x = Vec::Unit(0) + Vec::Unit(up);
  test::check_point(cap.closest(x), 0.5, Vec::Unit(0), Vec(0.5 * Vec::Unit(0) + Vec::Unit(up)));
  // End b: offset (0.6 sideways, 0.8 beyond b) -> 1 from b.
  x = b + 0.6 * Vec::Unit(0) + 0.8 * Vec::Unit(up);
  const Vec n = 0.6 * Vec::Unit(0) + 0.8 * Vec::Unit(up);
  test::check_point(cap.closest(x), 0.5, n, Vec(b + 0.5 * n), 1e-15);
  // End a: straight below.
  x = a - 0.7 * Vec::Unit(up);
  test::check_point(cap.closest(x), 0.2, Vec(-Vec::Unit(up)), Vec(-0.5 * Vec::Unit(up)), 1e-15);
  // Inside: 0.1 from the axis -> distance -0.4.
  x = 0.1 * Vec::Unit(0) + 1.5 * Vec::Unit(up);
  const auto in = cap.closest(x);
  CHECK(in.distance == Approx(-0.4));
  test::check_convention(x, in);
  // On the axis: fixed perpendicular normal.
  x = 1.0 * Vec::Unit(up);
  const auto on = cap.closest(x);
  CHECK(on.distance == Approx(-0.5));
  CHECK(std::abs(on.normal[up]) < 1e-15);
  test::check_convention(x, on);
  const auto box = cap.bounds();
  CHECK(box.lo == Vec::Constant(-0.5));
  CHECK(box.hi[up] == Approx(2.5));
}

TEMPLATE_TEST_CASE("CapsuleShape with a zero-length segment is a ball", "[geometry][capsule]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const CapsuleShape<TestType> ball(Vec::Constant(1.0), Vec::Constant(1.0), 0.25);
  Vec x = Vec::Constant(1.0);
  x[0] += 1.0;
  test::check_point(ball.closest(x), 0.75, Vec::Unit(0), Vec(Vec::Constant(1.0) + 0.25 * Vec::Unit(0)));
  const auto c = ball.closest(Vec::Constant(1.0));
  CHECK(c.distance == -0.25);
  CHECK(c.normal == Vec::Unit(TestType::dim - 1));
  CHECK_THROWS_AS(CapsuleShape<TestType>(Vec::Zero(), Vec::Zero(), -0.1), InvalidParameter);
}
