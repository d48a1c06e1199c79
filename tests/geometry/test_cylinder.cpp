// CylinderShape (solid, flat caps): hand-computed side, cap, rim and inside cases; a tilted
// cylinder against the same cylinder rotated by a Pose; nearest point against a brute-force
// sampling of the surface.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "granule/boundaries/geometry/cylinder.hpp"
#include "granule/boundaries/geometry/posed_shape.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;
using V3 = Eigen::Vector3d;

TEST_CASE("CylinderShape side, cap and rim from outside", "[geometry][cylinder]") {
  const CylinderShape cyl(V3::Zero(), V3(0, 0, 3), 1.0, 2.0);
  test::check_point(cyl.closest(V3(1.5, 0, 0.5)), 0.5, V3(1, 0, 0), V3(1, 0, 0.5));
  test::check_point(cyl.closest(V3(0.3, 0.2, 2.4)), 0.4, V3(0, 0, 1), V3(0.3, 0.2, 2.0));
  test::check_point(cyl.closest(V3(0.3, 0.2, -2.4)), 0.4, V3(0, 0, -1), V3(0.3, 0.2, -2.0));
  // Rim: offsets (0.3 radial, 0.4 axial) -> distance 0.5, normal (0.6, 0, 0.8).
  test::check_point(cyl.closest(V3(1.3, 0, 2.4)), 0.5, V3(0.6, 0, 0.8), V3(1, 0, 2), 1e-14);
  // Rim in another azimuth: radial direction (0, -1).
  test::check_point(cyl.closest(V3(0, -1.3, -2.4)), 0.5, V3(0, -0.6, -0.8), V3(0, -1, -2), 1e-14);
  for (const V3& x : {V3(1.5, 0, 0.5), V3(1.3, 0, 2.4), V3(-0.2, 0.1, 7.0)}) test::check_convention(x, cyl.closest(x));
}

TEST_CASE("CylinderShape from inside picks side or cap", "[geometry][cylinder]") {
  const CylinderShape cyl(V3(1, 1, 1), V3(0, 0, 1), 1.0, 2.0);
  test::check_point(cyl.closest(V3(1.9, 1, 1)), -0.1, V3(1, 0, 0), V3(2, 1, 1), 1e-14);
  test::check_point(cyl.closest(V3(1.2, 1, 2.95)), -0.05, V3(0, 0, 1), V3(1.2, 1, 3), 1e-14);
  test::check_point(cyl.closest(V3(1.2, 1, -0.95)), -0.05, V3(0, 0, -1), V3(1.2, 1, -1), 1e-14);
  // On the axis the side is nearest (depth 1 < 2): a fixed radial direction.
  const auto s = cyl.closest(V3(1, 1, 1.5));
  CHECK(s.distance == Approx(-1.0));
  CHECK(std::abs(s.normal.z()) < 1e-15);
  test::check_convention(V3(1, 1, 1.5), s);
  CHECK(cyl.closest(V3(1, 1, 1.5)).normal == s.normal);  // deterministic
  int calls = 0;
  cyl.for_each_contact(V3(2.2, 1, 1), 0.25, [&](const auto& c) {
    ++calls;
    CHECK(c.overlap(0.25) == Approx(0.05));
  });
  CHECK(calls == 1);
  CHECK_THROWS_AS(CylinderShape(V3::Zero(), V3::Zero(), 1.0, 1.0), InvalidParameter);
  CHECK_THROWS_AS(CylinderShape(V3::Zero(), V3(0, 0, 1), -1.0, 1.0), InvalidParameter);
  CHECK_THROWS_AS(CylinderShape(V3::Zero(), V3(0, 0, 1), 1.0, 0.0), InvalidParameter);
}

TEST_CASE("CylinderShape with a tilted axis equals a rotated upright cylinder", "[geometry][cylinder]") {
  const V3 axis = V3(1, 1, 0).normalized();
  const V3 c(0.5, -0.2, 0.3);
  const CylinderShape tilted(c, axis, 0.4, 0.7);
  // Rotation taking z to axis: 90 deg about (x - y)/sqrt(2)... use the quaternion between them.
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(V3(0, 0, 1), axis);
  const PosedShape<CylinderShape> posed(CylinderShape(V3::Zero(), V3(0, 0, 1), 0.4, 0.7), pose_3d(q, c));
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int k = 0; k < 200; ++k) {
    const V3 x = c + V3(u(gen), u(gen), u(gen));
    const auto a = tilted.closest(x);
    const auto b = posed.closest(x);
    CHECK(a.distance == Approx(b.distance).margin(1e-13));
    CHECK((a.point - b.point).norm() < 1e-12);
    test::check_convention(x, a);
  }
  // Bounds: half extent along x is H/sqrt(2) + R sqrt(1 - 1/2).
  const auto box = tilted.bounds();
  CHECK(box.hi.x() - c.x() == Approx(0.7 / std::sqrt(2.0) + 0.4 * std::sqrt(0.5)));
  CHECK(box.hi.z() - c.z() == Approx(0.4));
}

TEST_CASE("CylinderShape nearest point agrees with a sampled surface", "[geometry][cylinder]") {
  const CylinderShape cyl(V3::Zero(), V3(0, 0, 1), 1.0, 0.5);
  // Surface samples: side (n_phi x n_h), caps (rings).
  std::vector<V3> samples;
  const int n_phi = 720;
  for (int i = 0; i < n_phi; ++i) {
    const double phi = 2 * std::numbers::pi * i / n_phi;
    for (int j = 0; j <= 100; ++j) samples.emplace_back(std::cos(phi), std::sin(phi), -0.5 + j / 100.0);
    for (int j = 0; j <= 100; ++j) {
      samples.emplace_back(j / 100.0 * std::cos(phi), j / 100.0 * std::sin(phi), 0.5);
      samples.emplace_back(j / 100.0 * std::cos(phi), j / 100.0 * std::sin(phi), -0.5);
    }
  }
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 40; ++k) {
    const V3 x(u(gen), u(gen), u(gen));
    const auto s = cyl.closest(x);
    if (s.distance < 0.0) continue;
    double best = 1e300;
    for (const V3& p : samples) best = std::min(best, (x - p).norm());
    // Sample spacing <= 0.01 -> sampled minimum exceeds the true one by less than 0.01.
    CHECK(s.distance <= best + 1e-12);
    CHECK(s.distance >= best - 0.01);
  }
}
