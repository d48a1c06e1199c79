#pragma once
// A shape placed in the world by a Pose: closest(x) = pose.to_world(shape.closest(pose.to_body(x))).
// Distances are invariant under rigid motion, so only the point and the normal are mapped back.
// Moving walls keep one PosedShape and call set_pose() every step.
#include <utility>

#include "granule/boundaries/geometry/pose.hpp"
#include "granule/boundaries/geometry/shape.hpp"

namespace granule::geometry {

/// Any SurfaceShape evaluated in a moving body frame.
template <SurfaceShape S>
class PosedShape {
 public:
  using Dimension = typename S::Dimension;
  using Vec = typename Dimension::Vec;

  explicit PosedShape(S shape, Pose<Dimension> pose = {}) : shape_(std::move(shape)), pose_(pose) {}

  const S& shape() const { return shape_; }
  const Pose<Dimension>& pose() const { return pose_; }
  void set_pose(const Pose<Dimension>& pose) { pose_ = pose; }

  SurfacePoint<Dimension> closest(const Vec& x) const {
    return pose_.to_world(shape_.closest(pose_.to_body(x)));
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    shape_.for_each_contact(pose_.to_body(x), r_cut,
                            [&](const SurfacePoint<Dimension>& s) { f(pose_.to_world(s)); });
  }

  Aabb<Dimension> bounds() const { return pose_.to_world(shape_.bounds()); }

 private:
  S shape_;
  Pose<Dimension> pose_;
};

}  // namespace granule::geometry
