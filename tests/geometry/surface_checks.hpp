#pragma once
// Checks shared by the geometry tests: the SurfacePoint convention of surface_point.hpp,
//   x = point + distance * normal, |normal| = 1.
#include <catch2/catch.hpp>

#include "granule/boundaries/geometry/surface_point.hpp"

namespace granule::test {

template <class D>
void check_convention(const typename D::Vec& x, const geometry::SurfacePoint<D>& s, double tol = 1e-12) {
  INFO("x = " << x.transpose() << ", point = " << s.point.transpose() << ", normal = "
              << s.normal.transpose() << ", distance = " << s.distance);
  CHECK(std::abs(s.normal.norm() - 1.0) <= 1e-12);
  CHECK((s.point + s.distance * s.normal - x).norm() <= tol);
}

template <class D>
void check_point(const geometry::SurfacePoint<D>& s, double distance, const typename D::Vec& normal,
                 const typename D::Vec& point, double tol = 1e-12) {
  INFO("got distance " << s.distance << ", normal " << s.normal.transpose() << ", point " << s.point.transpose());
  CHECK(s.distance == Approx(distance).margin(tol));
  CHECK((s.normal - normal).norm() <= tol);
  CHECK((s.point - point).norm() <= tol);
}

}  // namespace granule::test
