// Dimension traits Dim<2> / Dim<3>: cross products, volumes and inertia factors.
// References: omega x r for omega = w e_z is w (-r_y, r_x); (a x b)_z = a_x b_y - a_y b_x;
// disk volume pi r^2 t; sphere volume 4/3 pi r^3; moments of inertia of a solid disk
// (I = 1/2 m r^2) and a solid sphere (I = 2/5 m r^2), e.g. Goldstein, Classical Mechanics, ch. 5.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "granule/core/dimension.hpp"

using granule::Dim2;
using granule::Dim3;

TEST_CASE("Dim<2>::cross of a scalar angular velocity and a vector", "[core][dimension]") {
  const Dim2::Vec v = Dim2::cross(2.0, Dim2::Vec(3.0, 5.0));
  CHECK(v.x() == -10.0);
  CHECK(v.y() == 6.0);
}

TEST_CASE("Dim<2>::cross of two vectors is the z component of the 3D product", "[core][dimension]") {
  const Dim2::Vec a(1.0, 2.0);
  const Dim2::Vec b(3.0, 4.0);
  CHECK(Dim2::cross(a, b) == -2.0);
  const Dim3::Vec c = Dim3::cross(Dim3::Vec(1.0, 2.0, 0.0), Dim3::Vec(3.0, 4.0, 0.0));
  CHECK(c.z() == Dim2::cross(a, b));
  // omega x r in 2D agrees with the 3D product for omega along z.
  const Dim3::Vec w3 = Dim3::cross(Dim3::Vec(0.0, 0.0, 2.0), Dim3::Vec(3.0, 5.0, 0.0));
  const Dim2::Vec w2 = Dim2::cross(2.0, Dim2::Vec(3.0, 5.0));
  CHECK(w3.x() == w2.x());
  CHECK(w3.y() == w2.y());
}

TEST_CASE("Dim volumes", "[core][dimension]") {
  const double r = 0.5;          // [m]
  const double thickness = 0.1;  // [m]
  CHECK(Dim2::volume(r, thickness) == Approx(std::numbers::pi * 0.025).epsilon(1e-15));
  CHECK(Dim3::volume(r, thickness) == Approx(std::numbers::pi / 6.0).epsilon(1e-15));
  CHECK(Dim3::volume(r, 7.0) == Dim3::volume(r, thickness));  // thickness is ignored in 3D
}

TEST_CASE("Dim inertia factors of a solid disk and a solid sphere", "[core][dimension]") {
  CHECK(Dim2::inertia_factor == 0.5);
  CHECK(Dim3::inertia_factor == 0.4);
  STATIC_REQUIRE(Dim2::dim == 2);
  STATIC_REQUIRE(Dim3::dim == 3);
}

TEST_CASE("Dim::along projects an angular vector on the normal", "[core][dimension]") {
  const Dim3::AngVec a = Dim3::along(Dim3::AngVec(1.0, 2.0, 3.0), Dim3::Vec(0.0, 0.0, 1.0));
  CHECK(a.x() == 0.0);
  CHECK(a.y() == 0.0);
  CHECK(a.z() == 3.0);
  CHECK(Dim2::along(4.0, Dim2::Vec(1.0, 0.0)) == 0.0);  // no twisting in 2D
}

TEMPLATE_TEST_CASE("Dim::cross(omega, r) is perpendicular to r", "[core][dimension]", Dim2, Dim3) {
  using D = TestType;
  typename D::Vec r = D::Vec::LinSpaced(1.0, 2.0);
  typename D::AngVec w{};
  if constexpr (D::dim == 2) {
    w = 1.5;
  } else {
    w = typename D::AngVec(0.3, -1.2, 0.7);
  }
  const typename D::Vec u = D::cross(w, r);
  CHECK(std::abs(u.dot(r)) < 1e-15);
  CHECK(u.norm() > 0.5);
}
