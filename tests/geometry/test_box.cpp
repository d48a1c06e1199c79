// BoxShape (solid, particles outside): clamp-based nearest point (faces, edges, corners are
// rounded exactly: distances by Pythagoras), nearest face from inside (analytic).
#include <catch2/catch.hpp>

#include <cmath>

#include "granule/boundaries/geometry/box.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;

TEMPLATE_TEST_CASE("BoxShape outside a face, an edge and a corner", "[geometry][box]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const BoxShape<TestType> box(Vec::Zero(), Vec::Constant(1.0));
  // Face: above the last-axis face.
  Vec x = Vec::Constant(0.5);
  x[TestType::dim - 1] = 1.3;
  Vec p = x;
  p[TestType::dim - 1] = 1.0;
  test::check_point(box.closest(x), 0.3, Vec::Unit(TestType::dim - 1), p, 1e-15);

  // Edge (2D: corner) beyond x = 1 and y = 1: distance sqrt(0.3^2 + 0.4^2) = 0.5.
  x = Vec::Constant(0.5);
  x[0] = 1.3;
  x[1] = 1.4;
  p = x;
  p[0] = 1.0;
  p[1] = 1.0;
  Vec n = Vec::Zero();
  n[0] = 0.6;
  n[1] = 0.8;
  const auto e = box.closest(x);
  test::check_point(e, 0.5, n, p, 1e-14);
  test::check_convention(x, e);

  // Corner below lo in every axis by 0.2: distance 0.2 sqrt(dim).
  x = Vec::Constant(-0.2);
  const auto c = box.closest(x);
  test::check_point(c, 0.2 * std::sqrt(double(TestType::dim)), Vec::Constant(-1.0 / std::sqrt(double(TestType::dim))),
                    Vec::Zero(), 1e-14);
}

TEMPLATE_TEST_CASE("BoxShape from inside picks the shallowest face", "[geometry][box]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const BoxShape<TestType> box(Vec::Zero(), Vec(Vec::Constant(2.0)));
  Vec x = Vec::Constant(1.0);
  x[0] = 0.1;  // 0.1 inside the lower x face
  const auto s = box.closest(x);
  Vec p = x;
  p[0] = 0.0;
  test::check_point(s, -0.1, Vec(-Vec::Unit(0)), p, 1e-15);
  test::check_convention(x, s);
  CHECK(s.overlap(0.05) == Approx(0.15));

  // On a face: distance 0 with the outward normal.
  x = Vec::Constant(1.0);
  x[TestType::dim - 1] = 2.0;
  const auto f = box.closest(x);
  CHECK(f.distance == 0.0);
  CHECK(f.normal == Vec::Unit(TestType::dim - 1));

  int calls = 0;
  box.for_each_contact(x, 0.01, [&](const auto&) { ++calls; });
  CHECK(calls == 1);
  CHECK_THROWS_AS(BoxShape<TestType>(Vec::Constant(1.0), Vec::Zero()), InvalidParameter);
}
