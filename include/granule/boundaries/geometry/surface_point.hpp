#pragma once
// Result of a nearest-point query on a wall surface, and the small vector helpers every shape
// uses to pick deterministic normals in degenerate positions.
//
// Convention (shared by all shapes in granule::geometry):
//   x = point + distance * normal, |normal| = 1,
// where `normal` points from the surface towards the side where particles live (outside a
// solid body, inside a container). `distance` is signed: positive on the particle side,
// negative when x has crossed the surface. A particle of radius r overlaps the surface by
//   overlap = r - distance   (contact when overlap > 0).
// This `normal` is the contact normal `n` of contact/geometry.hpp (pointing from the wall to i).
#include <cmath>
#include <cstdint>
#include <limits>

#include "granule/core/dimension.hpp"

namespace granule::geometry {

/// Nearest point of a surface to a query point x.
template <class D>
struct SurfacePoint {
  using Vec = typename D::Vec;
  double distance = std::numeric_limits<double>::infinity();  ///< signed distance [m]
  Vec normal = Vec::Zero();   ///< unit vector from `point` towards x (particle side)
  Vec point = Vec::Zero();    ///< nearest surface point [m]
  /// Which surface feature was hit, stable in time (box face index, mesh triangle/edge/vertex
  /// key; 0 for shapes with a single feature). Lets the engine keep per-contact history.
  std::uint32_t feature = 0;

  /// Overlap of a particle of radius r centred at x [m] (positive in contact).
  double overlap(double r) const { return r - distance; }
};

namespace detail {

/// A unit vector perpendicular to the unit vector a, chosen deterministically.
inline Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& a) {
  // Cross with the coordinate axis least aligned with a: well conditioned for every a.
  Eigen::Index k = 0;
  a.cwiseAbs().minCoeff(&k);
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
  return a.cross(e).normalized();
}
inline Eigen::Vector2d any_perpendicular(const Eigen::Vector2d& a) {
  return Eigen::Vector2d(-a.y(), a.x());
}

/// The last coordinate axis (y in 2D, z in 3D): the fallback normal when no direction exists.
template <class D>
typename D::Vec up_axis() {
  return D::Vec::Unit(D::dim - 1);
}

/// Builds a SurfacePoint from the nearest point of a solid (particles outside): the normal is
/// (x - p)/|x - p| or, when x lies on the surface, `fallback`.
template <class D>
SurfacePoint<D> outside_point(const typename D::Vec& x, const typename D::Vec& p,
                              const typename D::Vec& fallback, std::uint32_t feature = 0) {
  SurfacePoint<D> s;
  const typename D::Vec d = x - p;
  const double len = d.norm();
  s.point = p;
  s.distance = len;
  s.normal = len > 0.0 ? typename D::Vec(d / len) : fallback;
  s.feature = feature;
  return s;
}

}  // namespace detail
}  // namespace granule::geometry
