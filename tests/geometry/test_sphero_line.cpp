// SpheroLineShape: the three cases of paper 002 eq. 1-3 (caps at C1, C2 and the flat sides),
// hand-computed, plus agreement with CapsuleShape<Dim2> for a tilted segment.
#include <catch2/catch.hpp>

#include <random>

#include "granule/boundaries/geometry/capsule.hpp"
#include "granule/boundaries/geometry/sphero_line.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;
using V2 = Eigen::Vector2d;

TEST_CASE("SpheroLineShape cases of paper 002 eq. 1-3", "[geometry][sphero_line]") {
  const SpheroLineShape w(V2(0, 0), V2(2, 0), 0.1);  // C = (1, 0), u = (1, 0), v = (0, 1)
  CHECK(w.v() == V2(0, 1));
  // eq. 3 above and below the segment.
  test::check_point(w.closest(V2(1, 0.5)), 0.4, V2(0, 1), V2(1, 0.1));
  test::check_point(w.closest(V2(0.5, -0.3)), 0.2, V2(0, -1), V2(0.5, -0.1), 1e-15);
  // eq. 1: CO.u = -1.3 <= -L/2 -> |O C1| = 0.5.
  test::check_point(w.closest(V2(-0.3, 0.4)), 0.4, V2(-0.6, 0.8), V2(-0.06, 0.08), 1e-15);
  // eq. 2: CO.u = 1.6 >= L/2 -> |O C2| = 1.
  test::check_point(w.closest(V2(2.6, -0.8)), 0.9, V2(0.6, -0.8), V2(2.06, -0.08), 1e-15);
  // Overlap as the paper writes it: delta = (d_i + d_w)/2 - |CO.v| for d_i = 0.9, d_w = 0.2.
  CHECK(w.closest(V2(1, 0.5)).overlap(0.45) == Approx((0.9 + 0.2) / 2 - 0.5));
  // Exactly at the boundary between eq. 2 and eq. 3 both formulas agree.
  CHECK(w.closest(V2(2, 0.3)).distance == Approx(0.2));
  CHECK_THROWS_AS(SpheroLineShape(V2(1, 1), V2(1, 1), 0.1), InvalidParameter);
}

TEST_CASE("SpheroLineShape equals CapsuleShape<Dim2>", "[geometry][sphero_line]") {
  const V2 c1(0.3, -0.7), c2(-1.1, 0.9);
  const SpheroLineShape w(c1, c2, 0.05);
  const CapsuleShape<Dim2> cap(c1, c2, 0.05);
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 500; ++k) {
    const V2 x(u(gen), u(gen));
    const auto a = w.closest(x);
    const auto b = cap.closest(x);
    CHECK(a.distance == Approx(b.distance).margin(1e-14));
    CHECK((a.normal - b.normal).norm() < 1e-12);
    test::check_convention(x, a);
  }
  CHECK(w.bounds().lo.x() == Approx(-1.15));
  CHECK(w.bounds().hi.y() == Approx(0.95));
}
