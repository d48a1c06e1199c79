#pragma once
// Dimension traits: everything that differs between 2D disks and 3D spheres lives here,
// so the rest of the engine is written once for both.
//
//   Dim<2>: disks in the x-y plane. Angular velocity and torque are scalars (z component).
//           Mass m = rho * pi r^2 * t (t: out-of-plane thickness, a per-simulation setting),
//           moment of inertia I = 1/2 m r^2 (solid disk / cylinder about its axis).
//   Dim<3>: spheres. Angular velocity and torque are 3-vectors. m = rho * 4/3 pi r^3,
//           I = 2/5 m r^2 (solid sphere).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace granule {

template <int N>
struct Dim;

template <>
struct Dim<2> {
  static constexpr int dim = 2;
  static constexpr int rot_dim = 1;           // independent rotation components
  using Real = double;                        // scalar of one contact (core/lanes.hpp: packed)
  using Vec = Eigen::Vector2d;                // position, velocity, force  [SI]
  using AngVec = double;                      // angular velocity, torque (z)
  using Mat = Eigen::Matrix2d;                // stress and strain-rate tensors
  using IVec = Eigen::Vector2i;               // cell indices
  static constexpr double inertia_factor = 0.5;  // I = k m r^2

  /// Volume of a disk of radius r and out-of-plane thickness t [m^3].
  static double volume(double r, double thickness) { return std::numbers::pi * r * r * thickness; }
  static AngVec zero_ang() { return 0.0; }
  static Vec zero() { return Vec::Zero(); }
  /// omega x r for a rotation about z.
  static Vec cross(AngVec w, const Vec& r) { return Vec(-w * r.y(), w * r.x()); }
  /// z component of a x b.
  static AngVec cross(const Vec& a, const Vec& b) { return a.x() * b.y() - a.y() * b.x(); }
  static double norm(AngVec w) { return std::abs(w); }
  static double squared_norm(AngVec w) { return w * w; }
  static bool all_finite(AngVec w) { return std::isfinite(w); }
  /// Component of an angular vector along the contact normal (zero in 2D: no twisting).
  static AngVec along(AngVec, const Vec&) { return 0.0; }
  /// Component k of an angular vector (the scalar itself in 2D).
  static double component(AngVec w, int /*k*/) { return w; }
  static double dot(AngVec a, AngVec b) { return a * b; }
};

template <>
struct Dim<3> {
  static constexpr int dim = 3;
  static constexpr int rot_dim = 3;
  using Real = double;
  using Vec = Eigen::Vector3d;
  using AngVec = Eigen::Vector3d;
  using Mat = Eigen::Matrix3d;
  using IVec = Eigen::Vector3i;
  static constexpr double inertia_factor = 0.4;

  /// Volume of a sphere of radius r [m^3]; the thickness argument is ignored in 3D.
  static double volume(double r, double /*thickness*/) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }
  static AngVec zero_ang() { return AngVec::Zero(); }
  static Vec zero() { return Vec::Zero(); }
  static Vec cross(const Vec& a, const Vec& b) { return a.cross(b); }
  static double norm(const AngVec& w) { return w.norm(); }
  static double squared_norm(const AngVec& w) { return w.squaredNorm(); }
  static bool all_finite(const AngVec& w) { return w.allFinite(); }
  static AngVec along(const AngVec& w, const Vec& n) { return w.dot(n) * n; }
  static double component(const AngVec& w, int k) { return w[k]; }
  static double dot(const AngVec& a, const AngVec& b) { return a.dot(b); }
};

using Dim2 = Dim<2>;
using Dim3 = Dim<3>;

}  // namespace granule
