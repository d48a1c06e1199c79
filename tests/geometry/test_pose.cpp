// Pose and PosedShape: rigid-motion algebra (x = R y + t, composition and inverse) and the
// invariance of distances under rigid motion (a posed plane equals the moved plane).
#include <catch2/catch.hpp>

#include <numbers>
#include <random>

#include "granule/boundaries/geometry/box.hpp"
#include "granule/boundaries/geometry/plane.hpp"
#include "granule/boundaries/geometry/posed_shape.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;

TEST_CASE("Pose algebra in 3D", "[geometry][pose]") {
  using V3 = Eigen::Vector3d;
  const Pose<Dim3> a = pose_3d(0.3, V3(1, 2, 3), V3(1, -1, 0.5));
  const Pose<Dim3> b = pose_3d(-1.1, V3(0, 1, 0), V3(0.2, 0.0, -0.3));
  const V3 x(0.7, -0.4, 1.9);
  CHECK((a.to_body(a.to_world(x)) - x).norm() < 1e-15);
  CHECK(((a * b).to_world(x) - a.to_world(b.to_world(x))).norm() < 1e-15);
  CHECK((a.inverse().to_world(x) - a.to_body(x)).norm() < 1e-15);
  // 90 degrees about z maps x to y.
  const Pose<Dim3> q = pose_3d(std::numbers::pi / 2, V3(0, 0, 2), V3::Zero());
  CHECK((q.rotate(V3(1, 0, 0)) - V3(0, 1, 0)).norm() < 1e-15);
  Eigen::Matrix3d bad = Eigen::Matrix3d::Identity();
  bad(0, 0) = -1.0;  // a reflection
  CHECK_THROWS_WITH(Pose<Dim3>(bad, V3::Zero()), Catch::Contains("det R"));
  CHECK_THROWS_AS(Pose<Dim3>(2.0 * Eigen::Matrix3d::Identity(), V3::Zero()), InvalidParameter);
}

// An unrotated pose skips its rotation products (Pose::rotated_); the composition or inverse
// of poses that rotate must not. Exact results: a translation alone is one addition.
TEST_CASE("An unrotated pose translates exactly; compositions keep their rotation", "[geometry][pose]") {
  using V3 = Eigen::Vector3d;
  const V3 t(0.25, -1.5, 3.0), x(0.7, -0.4, 1.9), d(0.0, 0.6, -0.8);
  const Pose<Dim3> shift = Pose<Dim3>::translation(t);
  CHECK(shift.to_world(x) == x + t);
  CHECK(shift.to_body(x) == x - t);
  CHECK(shift.rotate(d) == d);
  CHECK(shift.rotate_back(d) == d);
  CHECK(Pose<Dim3>().to_world(x) == x);
  // A rotation composed with a shift, and the inverse of a rotation, still rotate.
  const Pose<Dim3> q = pose_3d(std::numbers::pi / 2, V3(0, 0, 1), V3::Zero());
  CHECK(((q * shift).rotate(V3(1, 0, 0)) - V3(0, 1, 0)).norm() < 1e-15);
  CHECK(((shift * q).to_world(V3(1, 0, 0)) - (V3(0, 1, 0) + t)).norm() < 1e-15);
  CHECK((q.inverse().rotate(V3(0, 1, 0)) - V3(1, 0, 0)).norm() < 1e-15);
  CHECK((shift.inverse().to_world(x) - (x - t)).norm() == 0.0);
}

TEST_CASE("Pose algebra in 2D", "[geometry][pose]") {
  using V2 = Eigen::Vector2d;
  const Pose<Dim2> p = pose_2d(std::numbers::pi / 2, V2(1, 0));
  CHECK((p.to_world(V2(1, 0)) - V2(1, 1)).norm() < 1e-15);
  CHECK((p.to_body(V2(1, 1)) - V2(1, 0)).norm() < 1e-15);
  // World box of the unit square rotated by 90 degrees and shifted by (1, 0).
  const Aabb<Dim2> box = p.to_world(Aabb<Dim2>(V2(0, 0), V2(2, 1)));
  CHECK((box.lo - V2(0, 0)).norm() < 1e-15);
  CHECK((box.hi - V2(1, 2)).norm() < 1e-15);
  CHECK_FALSE(p.to_world(Aabb<Dim2>::infinite()).is_finite());
}

TEMPLATE_TEST_CASE("PosedShape of a plane equals the moved plane", "[geometry][pose]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Vec n = Vec::Zero();
  n[TestType::dim - 1] = 1.0;
  const PlaneShape<TestType> body(Vec::Zero(), n);
  Pose<TestType> pose;
  if constexpr (TestType::dim == 2) {
    pose = pose_2d(0.4, Vec(0.5, -0.2));
  } else {
    pose = pose_3d(0.4, Vec(1, 0.5, 0.2), Vec(0.5, -0.2, 0.1));
  }
  const PosedShape<PlaneShape<TestType>> posed(body, pose);
  const PlaneShape<TestType> moved(pose.translation(), pose.rotate(n));
  std::mt19937_64 gen(9);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 100; ++k) {
    Vec x;
    for (int a = 0; a < TestType::dim; ++a) x[a] = u(gen);
    const auto s = posed.closest(x);
    const auto m = moved.closest(x);
    CHECK(s.distance == Approx(m.distance).margin(1e-14));
    CHECK((s.normal - m.normal).norm() < 1e-14);
    CHECK((s.point - m.point).norm() < 1e-14);
    test::check_convention(x, s, 1e-14);
    int calls = 0;
    posed.for_each_contact(x, 0.5, [&](const SurfacePoint<TestType>& c) {
      ++calls;
      CHECK((c.point - m.point).norm() < 1e-14);
    });
    CHECK(calls == (m.distance < 0.5 ? 1 : 0));
  }
}

TEST_CASE("PosedShape moves with set_pose", "[geometry][pose]") {
  using V2 = Eigen::Vector2d;
  PosedShape<BoxShape<Dim2>> box(BoxShape<Dim2>(V2(-1, -1), V2(1, 1)));
  CHECK(box.closest(V2(2, 0)).distance == Approx(1.0));
  box.set_pose(Pose<Dim2>::translation(V2(0.5, 0)));
  CHECK(box.closest(V2(2, 0)).distance == Approx(0.5));
  CHECK(box.bounds().lo.x() == Approx(-0.5));
  // Rotated by 45 degrees the corner points along +x: distance from (2, 0) is 2 - (0.5 + sqrt 2).
  box.set_pose(pose_2d(std::numbers::pi / 4, V2(0.5, 0)));
  CHECK(box.closest(V2(2, 0)).distance == Approx(1.5 - std::sqrt(2.0)));
}
