#pragma once
// A wall of the engine: a surface shape from granule::geometry, a material and the body that
// carries it (body 0 is the fixed world). Walls take part in contacts through the same contact
// model as particle pairs, with the wall treated as a partner of infinite mass and radius.
// The shape set is a closed std::variant, so dispatch is a switch, never a virtual call.
#include <cstdint>
#include <variant>

#include "granule/boundaries/body.hpp"
#include "granule/boundaries/geometry/box.hpp"
#include "granule/boundaries/geometry/box_container.hpp"
#include "granule/boundaries/geometry/capsule.hpp"
#include "granule/boundaries/geometry/cylinder.hpp"
#include "granule/boundaries/geometry/cylinder_container.hpp"
#include "granule/boundaries/geometry/plane.hpp"
#include "granule/boundaries/geometry/prism.hpp"
#include "granule/boundaries/geometry/sphero_line.hpp"
#include "granule/boundaries/geometry/triangle_mesh.hpp"

namespace granule {

/// The shapes a wall can take in dimension D.
template <class D>
struct WallShapes;

template <>
struct WallShapes<Dim2> {
  using type = std::variant<geometry::PlaneShape<Dim2>, geometry::BoxContainerShape<Dim2>,
                            geometry::BoxShape<Dim2>, geometry::CapsuleShape<Dim2>,
                            geometry::PrismShape<Dim2>, geometry::SpheroLineShape,
                            geometry::CircleContainerShape>;
};

template <>
struct WallShapes<Dim3> {
  using type = std::variant<geometry::PlaneShape<Dim3>, geometry::BoxContainerShape<Dim3>,
                            geometry::BoxShape<Dim3>, geometry::CapsuleShape<Dim3>,
                            geometry::PrismShape<Dim3>, geometry::CylinderShape,
                            geometry::TriangleMeshShape, geometry::CylinderContainerShape>;
};

template <class D>
struct Wall {
  using Vec = typename D::Vec;
  typename WallShapes<D>::type shape;
  std::uint32_t material = 0;
  std::uint32_t body = 0;
  /// An inactive wall has no contacts (Simulation::set_wall_active: a gate that opens).
  bool active = true;
  Vec force = Vec::Zero();                ///< force of the particles on this wall, last step [N]
  typename D::AngVec torque = D::zero_ang();  ///< their torque about the body's pose origin [N m]

  /// Calls f(SurfacePoint<D>) in world coordinates for every feature within r_cut of x.
  template <class F>
  void for_each_contact(const Body<D>& b, const Vec& x, double r_cut, F&& f) const {
    const Vec xb = b.pose.to_body(x);
    std::visit([&](const auto& s) {
      s.for_each_contact(xb, r_cut, [&](const geometry::SurfacePoint<D>& sp) { f(b.pose.to_world(sp)); });
    }, shape);
  }

  /// Largest distance of the shape from its body origin (infinite for unbounded shapes) [m].
  double extent() const {
    return std::visit([](const auto& s) {
      const auto box = s.bounds();
      if (!box.is_finite()) return std::numeric_limits<double>::infinity();
      return std::max(box.lo.cwiseAbs().maxCoeff(), box.hi.cwiseAbs().maxCoeff()) * std::sqrt(double(D::dim));
    }, shape);
  }
};

}  // namespace granule
