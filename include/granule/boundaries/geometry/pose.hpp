#pragma once
// Rigid placement of a body: x_world = R x_body + t, with R a proper rotation (R^T R = I,
// det R = +1). Shapes are written in their body frame; PosedShape (posed_shape.hpp) evaluates
// them anywhere by mapping the query point into the body frame and the answer back.
#include <cmath>
#include <string>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Rotation + translation in 2D or 3D.
template <class D>
class Pose {
 public:
  using Vec = typename D::Vec;
  using Mat = typename D::Mat;

  /// Identity pose.
  Pose() : rotation_(Mat::Identity()), translation_(Vec::Zero()), rotated_(false) {}

  /// `rotation` must be orthonormal with determinant +1 (to 1e-9); `translation` [m].
  Pose(const Mat& rotation, const Vec& translation) : rotation_(rotation), translation_(translation) {
    const double orth = (rotation.transpose() * rotation - Mat::Identity()).cwiseAbs().maxCoeff();
    require(orth <= 1e-9, "geometry::Pose", "max |R^T R - I|", orth, "[0, 1e-9]");
    const double det = rotation.determinant();
    require(std::abs(det - 1.0) <= 1e-9, "geometry::Pose", "det R", det, "1 +- 1e-9 (proper rotation)");
    require(translation.allFinite(), "geometry::Pose", "translation (max |t_k|)",
            translation.cwiseAbs().maxCoeff(), "finite numbers");
    note_rotation();
  }

  /// Pure translation.
  static Pose translation(const Vec& t) { return Pose(Mat::Identity(), t); }

  const Mat& rotation() const { return rotation_; }
  const Vec& translation() const { return translation_; }

  /// Body -> world for points and directions.
  Vec to_world(const Vec& body_point) const {
    return rotated_ ? Vec(rotation_ * body_point + translation_) : Vec(body_point + translation_);
  }
  Vec rotate(const Vec& body_dir) const { return rotated_ ? Vec(rotation_ * body_dir) : body_dir; }
  /// World -> body for points and directions.
  Vec to_body(const Vec& world_point) const {
    return rotated_ ? Vec(rotation_.transpose() * (world_point - translation_)) : Vec(world_point - translation_);
  }
  Vec rotate_back(const Vec& world_dir) const {
    return rotated_ ? Vec(rotation_.transpose() * world_dir) : world_dir;
  }

  /// A surface point computed in the body frame, expressed in the world frame.
  SurfacePoint<D> to_world(const SurfacePoint<D>& s) const {
    SurfacePoint<D> w = s;
    w.point = to_world(s.point);
    w.normal = rotate(s.normal);
    return w;
  }

  /// World box enclosing a body-frame box (its 2^dim corners transformed).
  Aabb<D> to_world(const Aabb<D>& body_box) const {
    if (body_box.is_empty()) return body_box;
    if (!body_box.is_finite()) return Aabb<D>::infinite();
    Aabb<D> out = Aabb<D>::empty();
    for (int corner = 0; corner < (1 << D::dim); ++corner) {
      Vec c;
      for (int k = 0; k < D::dim; ++k) c[k] = (corner >> k) & 1 ? body_box.hi[k] : body_box.lo[k];
      out.extend(to_world(c));
    }
    return out;
  }

  /// Composition: (a * b).to_world(x) == a.to_world(b.to_world(x)).
  Pose operator*(const Pose& b) const {
    Pose p;
    p.rotation_ = rotation_ * b.rotation_;
    p.translation_ = rotation_ * b.translation_ + translation_;
    p.note_rotation();
    return p;
  }
  Pose inverse() const {
    Pose p;
    p.rotation_ = rotation_.transpose();
    p.translation_ = -(rotation_.transpose() * translation_);
    p.note_rotation();
    return p;
  }

 private:
  // Most walls (the planes of a box, a translated rod) are not rotated: for them the two 3x3
  // products per wall contact (into the body frame and back) were 1.7 % of scene B's time.
  void note_rotation() { rotated_ = rotation_ != Mat::Identity(); }

  Mat rotation_;
  Vec translation_;
  bool rotated_;  ///< rotation_ is not the identity
};

/// 2D pose from a rotation angle about z [rad] and a translation [m].
inline Pose<Dim2> pose_2d(double angle, const Dim2::Vec& translation) {
  require_finite(angle, "geometry::pose_2d", "angle");
  return Pose<Dim2>(Eigen::Rotation2Dd(angle).toRotationMatrix(), translation);
}

/// 3D pose from a rotation of `angle` [rad] about the unit `axis`, and a translation [m].
inline Pose<Dim3> pose_3d(double angle, const Dim3::Vec& axis, const Dim3::Vec& translation) {
  require_finite(angle, "geometry::pose_3d", "angle");
  require(axis.norm() > 0.0 && axis.allFinite(), "geometry::pose_3d", "|axis|", axis.norm(), "(0, inf)");
  return Pose<Dim3>(Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(), translation);
}

/// 3D pose from a quaternion (normalised here) and a translation [m].
inline Pose<Dim3> pose_3d(const Eigen::Quaterniond& q, const Dim3::Vec& translation) {
  require(q.norm() > 0.0 && q.coeffs().allFinite(), "geometry::pose_3d", "|q|", q.norm(), "(0, inf)");
  return Pose<Dim3>(q.normalized().toRotationMatrix(), translation);
}

}  // namespace granule::geometry
