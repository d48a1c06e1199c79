#pragma once
// The SurfaceShape concept: what every wall primitive in granule::geometry provides. Shapes
// are pure geometry (no material, no motion); a wall of the engine holds a shape plus a Pose.
//
//   struct MyShape {
//     using Dimension = Dim3;                                   // Dim2 or Dim3
//     SurfacePoint<Dim3> closest(const Vec& x) const;           // nearest surface point
//     template <class F>                                        // every feature within r_cut:
//     void for_each_contact(const Vec& x, double r_cut, F&& f) const;   // f(const SurfacePoint&)
//     Aabb<Dim3> bounds() const;                                // infinite box if unbounded
//   };
//
// closest(x) follows the conventions of surface_point.hpp (x = point + distance * normal,
// distance > 0 on the particle side). for_each_contact(x, r_cut, f) calls f once for every
// surface feature whose signed distance to x is below r_cut: for a convex solid that is its
// closest point; for a box container each face; for a triangle mesh each local minimum of the
// distance (see triangle_mesh.hpp). With r_cut = particle radius, every reported point is a
// contact with overlap = r_cut - distance > 0.
#include <concepts>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"

namespace granule::geometry {

template <class S>
concept SurfaceShape = requires(const S& s, const typename S::Dimension::Vec& x) {
  typename S::Dimension;
  { s.closest(x) } -> std::same_as<SurfacePoint<typename S::Dimension>>;
  { s.bounds() } -> std::same_as<Aabb<typename S::Dimension>>;
  s.for_each_contact(x, 1.0, [](const SurfacePoint<typename S::Dimension>&) {});
};

}  // namespace granule::geometry
