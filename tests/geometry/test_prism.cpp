// PrismShape (oriented solid box): body-frame cases mapped by the rotation (analytic),
// equality with BoxShape when axis-aligned.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "granule/boundaries/geometry/box.hpp"
#include "granule/boundaries/geometry/prism.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;

TEST_CASE("PrismShape 2D rotated by 30 degrees", "[geometry][prism]") {
  using V2 = Eigen::Vector2d;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(std::numbers::pi / 6).toRotationMatrix();
  const V2 c(1, 1);
  const PrismShape<Dim2> prism(c, R, V2(0.5, 0.25));
  // Body point (0.8, 0): 0.3 outside the +x face.
  test::check_point(prism.closest(c + R * V2(0.8, 0)), 0.3, R * V2(1, 0), c + R * V2(0.5, 0), 1e-14);
  // Body corner region (0.8, 0.65): offsets (0.3, 0.4) -> 0.5.
  test::check_point(prism.closest(c + R * V2(0.8, 0.65)), 0.5, R * V2(0.6, 0.8), c + R * V2(0.5, 0.25), 1e-14);
  // Inside, 0.05 below the +y face.
  test::check_point(prism.closest(c + R * V2(0.1, 0.2)), -0.05, R * V2(0, 1), c + R * V2(0.1, 0.25), 1e-14);
  // Bounds of the rotated rectangle: half width 0.5 cos30 + 0.25 sin30.
  CHECK(prism.bounds().hi.x() - 1.0 == Approx(0.5 * std::cos(std::numbers::pi / 6) + 0.25 * 0.5));
}

TEST_CASE("PrismShape 3D edge of a square rod", "[geometry][prism]") {
  using V3 = Eigen::Vector3d;
  // Square rod of side 0.02 m, length 0.3 m, rotated 45 deg about its own (z) axis.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(std::numbers::pi / 4, V3::UnitZ()).toRotationMatrix();
  const PrismShape<Dim3> rod(V3(0, 0, 0.15), R, V3(0.01, 0.01, 0.15));
  // Along world +x lies the body edge (0.01, 0.01)*; a point 0.005 beyond it along x.
  const double edge = 0.01 * std::sqrt(2.0);
  const auto s = rod.closest(V3(edge + 0.005, 0, 0.1));
  CHECK(s.distance == Approx(0.005).epsilon(1e-12));
  CHECK((s.normal - V3(1, 0, 0)).norm() < 1e-12);
  CHECK((s.point - V3(edge, 0, 0.1)).norm() < 1e-14);
  // Bottom corner of the rod, straight below it.
  const auto b = rod.closest(V3(edge, 0, -0.02));
  CHECK(b.distance == Approx(0.02));
  CHECK((b.normal - V3(0, 0, -1)).norm() < 1e-12);
}

TEMPLATE_TEST_CASE("PrismShape without rotation equals BoxShape", "[geometry][prism]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const Vec c = Vec::Constant(0.3);
  Vec e = Vec::Constant(0.2);
  e[0] = 0.4;
  const PrismShape<TestType> prism(c, e);
  const BoxShape<TestType> box(c - e, c + e);
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 300; ++k) {
    Vec x;
    for (int a = 0; a < TestType::dim; ++a) x[a] = u(gen);
    const auto p = prism.closest(x);
    const auto b = box.closest(x);
    CHECK(p.distance == Approx(b.distance).margin(1e-15));
    CHECK((p.point - b.point).norm() < 1e-15);
  }
  CHECK_THROWS_AS(PrismShape<TestType>(c, Vec::Zero()), InvalidParameter);
}
