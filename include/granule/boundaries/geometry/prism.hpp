#pragma once
// Rectangular prism (oriented box) as a solid, particles outside: centre c, rotation R whose
// columns are the body axes in the world frame, half extents e. It is the BoxShape [-e, e]
// placed by the pose x = R y + c, so edges and corners are rounded exactly as in box.hpp.
// The square rods of paper 000 are prisms with e = (d/2, d/2, L/2).
#include "granule/boundaries/geometry/box.hpp"
#include "granule/boundaries/geometry/pose.hpp"

namespace granule::geometry {

/// Solid oriented box.
template <class D>
class PrismShape {
 public:
  using Dimension = D;
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;

  /// `centre` [m], `rotation` (proper, orthonormal), `half_extents` [m] (all > 0).
  PrismShape(const Vec& centre, const Mat& rotation, const Vec& half_extents)
      : pose_(rotation, centre), box_(checked(-half_extents), half_extents) {}

  /// Axis-aligned prism (identity rotation).
  PrismShape(const Vec& centre, const Vec& half_extents) : PrismShape(centre, Mat::Identity(), half_extents) {}

  Vec centre() const { return pose_.translation(); }
  const Mat& rotation() const { return pose_.rotation(); }
  Vec half_extents() const { return box_.hi(); }
  const Pose<D>& pose() const { return pose_; }

  SurfacePoint<D> closest(const Vec& x) const { return pose_.to_world(box_.closest(pose_.to_body(x))); }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<D> s = closest(x);
    if (s.distance < r_cut) f(s);
  }

  Aabb<D> bounds() const { return pose_.to_world(box_.bounds()); }

 private:
  static Vec checked(const Vec& minus_e) {
    for (int k = 0; k < D::dim; ++k) {
      require(minus_e[k] < 0.0 && std::isfinite(minus_e[k]), "geometry::PrismShape",
              "half_extents[" + std::to_string(k) + "]", -minus_e[k], "(0, inf)");
    }
    return minus_e;
  }

  Pose<D> pose_;
  BoxShape<D> box_;
};

}  // namespace granule::geometry
