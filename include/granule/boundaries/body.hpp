#pragma once
// A rigid body with prescribed kinematics that carries walls (containers, intruders, pistons).
// Its velocity and angular velocity are functions of time; its pose is integrated from them.
// Every step the engine accumulates the force and torque the particles exert on it, and the
// work the drive must do against them:  W = -integral (F . V + T . Omega) dt  (paper 000
// section II: W = integral F dz for an intruder pushed at constant speed).
#include <cmath>
#include <functional>
#include <string>

#include "granule/boundaries/geometry/pose.hpp"
#include "granule/core/dimension.hpp"

namespace granule {

template <class D>
struct Body {
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  std::string name = "body";
  geometry::Pose<D> pose;                       ///< body frame -> world frame
  std::function<Vec(double)> velocity;          ///< V(t) [m/s]; empty = at rest
  std::function<AngVec(double)> angular_velocity;  ///< Omega(t) [rad/s] about the pose origin
  Vec current_velocity = Vec::Zero();           ///< V at the current step [m/s]
  AngVec current_angular_velocity = D::zero_ang();  ///< [rad/s]
  Vec force = Vec::Zero();                      ///< force of the particles on the body [N]
  AngVec torque = D::zero_ang();                ///< their torque about the pose origin [N m]
  double work = 0.0;                            ///< work done by the drive [J]
  Vec displacement_since_build = Vec::Zero();   ///< for the neighbour-list skin criterion [m]
  double rotation_since_build = 0.0;            ///< |Omega| dt summed since the last build [rad]

  bool moving() const { return static_cast<bool>(velocity) || static_cast<bool>(angular_velocity); }

  /// Velocity of the body's material point at world position p [m/s].
  Vec point_velocity(const Vec& p) const {
    return current_velocity + D::cross(current_angular_velocity, Vec(p - pose.translation()));
  }

  /// Advances the pose from time t to t + dt (velocities evaluated at the midpoint).
  void advance(double t, double dt) {
    if (!moving()) return;
    const double tm = t + 0.5 * dt;
    const Vec V = velocity ? velocity(tm) : Vec::Zero();
    const AngVec W = angular_velocity ? angular_velocity(tm) : D::zero_ang();
    typename D::Mat R = pose.rotation();
    const double angle = D::norm(W) * dt;
    if (angle > 0.0) {
      // Re-orthonormalise through an angle (2D) or a unit quaternion (3D) so that round-off
      // never accumulates over millions of steps.
      if constexpr (D::dim == 2) {
        R = Eigen::Rotation2Dd(std::atan2(R(1, 0), R(0, 0)) + W * dt).toRotationMatrix();
      } else {
        Eigen::Quaterniond q(Eigen::AngleAxisd(angle, W.normalized()).toRotationMatrix() * R);
        q.normalize();
        R = q.toRotationMatrix();
      }
    }
    pose = geometry::Pose<D>(R, pose.translation() + V * dt);
    displacement_since_build += V * dt;
    rotation_since_build += angle;
    set_velocities(t + dt);
  }

  /// Sets the current velocities from the kinematic functions at time t.
  void set_velocities(double t) {
    current_velocity = velocity ? velocity(t) : Vec::Zero();
    current_angular_velocity = angular_velocity ? angular_velocity(t) : D::zero_ang();
  }
};

}  // namespace granule
