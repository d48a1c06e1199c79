#pragma once
// SIMD lanes for the contact laws.
//
// The pair loop is bound by its square roots and divisions (docs/performance.md, "Roofline"),
// which a vector unit does 4-4.5x faster per element than the scalar one. So the laws that can
// are written once over a *real type* R: `double` for one contact, or `Lane` -- a pack of W
// doubles (std::experimental::simd at the machine's native width; W = 8 with AVX-512, 2 with
// SSE2) -- for W contacts at once. Dim3Lanes and Dim2Lanes are the dimension policies of the
// packed form: their vectors hold one pack per axis (LaneVec3, LaneVec2), with the few
// Eigen-like members the laws use (dot, cross, squaredNorm), so a law reads the same for all.
//
// Laws are branch-free in the packed form: where a scalar law would write `if (c) x = f();`
// it writes `where_assign(c, x, [&] { return f(); })`. For a scalar `c` that is the `if` itself
// (no extra work on the scalar path); for a mask it evaluates f once when any lane needs it and
// blends it into the lanes where c holds. Lanes where c is false may compute inf or NaN inside
// f (e.g. a division by a zero stiffness); they are never blended in.
#include <cstddef>
#include <experimental/simd>
#include <type_traits>

namespace granule {

namespace stdx = std::experimental;

using Lane = stdx::native_simd<double>;
using LaneMask = Lane::mask_type;
inline constexpr std::size_t lane_width = Lane::size();

/// A 3-vector of packs: component k of lane l is the k-th coordinate of contact l.
struct LaneVec3 {
  Lane x, y, z;

  Lane dot(const LaneVec3& b) const { return x * b.x + y * b.y + z * b.z; }
  Lane squaredNorm() const { return x * x + y * y + z * z; }
  LaneVec3 cross(const LaneVec3& b) const {
    return {y * b.z - z * b.y, z * b.x - x * b.z, x * b.y - y * b.x};
  }
  LaneVec3& operator+=(const LaneVec3& b) { x += b.x; y += b.y; z += b.z; return *this; }
  LaneVec3& operator-=(const LaneVec3& b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
  LaneVec3& operator*=(const Lane& s) { x *= s; y *= s; z *= s; return *this; }
  friend LaneVec3 operator+(const LaneVec3& a, const LaneVec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend LaneVec3 operator-(const LaneVec3& a, const LaneVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend LaneVec3 operator-(const LaneVec3& a) { return {-a.x, -a.y, -a.z}; }
  friend LaneVec3 operator*(const Lane& s, const LaneVec3& a) { return {s * a.x, s * a.y, s * a.z}; }
  friend LaneVec3 operator*(const LaneVec3& a, const Lane& s) { return {a.x * s, a.y * s, a.z * s}; }
  friend LaneVec3 operator*(double s, const LaneVec3& a) { return Lane(s) * a; }
  friend LaneVec3 operator*(const LaneVec3& a, double s) { return a * Lane(s); }
};

/// A 2-vector of packs (the in-plane vectors of W 2D contacts).
struct LaneVec2 {
  Lane x, y;

  Lane dot(const LaneVec2& b) const { return x * b.x + y * b.y; }
  Lane squaredNorm() const { return x * x + y * y; }
  LaneVec2& operator+=(const LaneVec2& b) { x += b.x; y += b.y; return *this; }
  LaneVec2& operator-=(const LaneVec2& b) { x -= b.x; y -= b.y; return *this; }
  LaneVec2& operator*=(const Lane& s) { x *= s; y *= s; return *this; }
  friend LaneVec2 operator+(const LaneVec2& a, const LaneVec2& b) { return {a.x + b.x, a.y + b.y}; }
  friend LaneVec2 operator-(const LaneVec2& a, const LaneVec2& b) { return {a.x - b.x, a.y - b.y}; }
  friend LaneVec2 operator-(const LaneVec2& a) { return {-a.x, -a.y}; }
  friend LaneVec2 operator*(const Lane& s, const LaneVec2& a) { return {s * a.x, s * a.y}; }
  friend LaneVec2 operator*(const LaneVec2& a, const Lane& s) { return {a.x * s, a.y * s}; }
  friend LaneVec2 operator*(double s, const LaneVec2& a) { return Lane(s) * a; }
  friend LaneVec2 operator*(const LaneVec2& a, double s) { return a * Lane(s); }
};

/// Dimension policy of W packed 2D contacts (see Dim<2>, core/dimension.hpp): angular
/// velocities and torques are one pack (their z component).
struct Dim2Lanes {
  static constexpr int dim = 2;
  using Real = Lane;
  using Vec = LaneVec2;
  using AngVec = Lane;
  static constexpr double inertia_factor = 0.5;
  static Vec zero() { return {Lane(0.0), Lane(0.0)}; }
  static AngVec zero_ang() { return Lane(0.0); }
  /// omega x r for a rotation about z.
  static Vec cross(const AngVec& w, const Vec& r) { return {-w * r.y, w * r.x}; }
  /// z component of a x b.
  static AngVec cross(const Vec& a, const Vec& b) { return a.x * b.y - a.y * b.x; }
  static Real squared_norm(const AngVec& w) { return w * w; }
};

/// Dimension policy of W packed 3D contacts (see Dim<3>, core/dimension.hpp).
struct Dim3Lanes {
  static constexpr int dim = 3;
  using Real = Lane;
  using Vec = LaneVec3;
  using AngVec = LaneVec3;
  static constexpr double inertia_factor = 0.4;
  static Vec zero() { return {Lane(0.0), Lane(0.0), Lane(0.0)}; }
  static AngVec zero_ang() { return zero(); }
  static Vec cross(const Vec& a, const Vec& b) { return a.cross(b); }
  static Real squared_norm(const AngVec& w) { return w.squaredNorm(); }
};

/// The packed policy of a dimension: LanesOf<Dim<2>> is Dim2Lanes, LanesOf<Dim<3>> Dim3Lanes.
template <class D>
using LanesOf = std::conditional_t<D::dim == 2, Dim2Lanes, Dim3Lanes>;

/// target = v in the lanes where c holds: every masked assignment of the packed code comes
/// here. (libstdc++ 12's `stdx::where(c, target) = v` assigns nothing when clang compiles it
/// for AVX-512, whose masks are bit masks -- clang 14 and 16 checked, 2026-12-07: no contact
/// law or rebuild test worked and disks fell through the floor. There the blend is written lane
/// by lane instead; tests/core/test_lanes.cpp holds both compilers to it.)
inline void assign_lanes(const LaneMask& c, Lane& target, const Lane& v) {
#if defined(__clang__) && defined(__AVX512F__)
  const Lane old = target;
  target = Lane([&](auto l) { return c[l] ? v[l] : old[l]; });
#else
  stdx::where(c, target) = v;
#endif
}

/// `if (c) target = f();` -- the scalar form.
template <class T, class F>
inline void where_assign(bool c, T& target, F&& f) {
  if (c) target = static_cast<T>(f());
}

/// The packed form: f() is evaluated once if any lane of c is set and blended into those lanes.
template <class F>
inline void where_assign(const LaneMask& c, Lane& target, F&& f) {
  if (stdx::any_of(c)) {
    const Lane v = f();
    assign_lanes(c, target, v);
  }
}

template <class F>
inline void where_assign(const LaneMask& c, LaneVec3& target, F&& f) {
  if (stdx::any_of(c)) {
    const LaneVec3 v = f();
    assign_lanes(c, target.x, v.x);
    assign_lanes(c, target.y, v.y);
    assign_lanes(c, target.z, v.z);
  }
}

template <class F>
inline void where_assign(const LaneMask& c, LaneVec2& target, F&& f) {
  if (stdx::any_of(c)) {
    const LaneVec2 v = f();
    assign_lanes(c, target.x, v.x);
    assign_lanes(c, target.y, v.y);
  }
}

/// As where_assign, but the packed form evaluates f() always and blends it, without the any_of
/// branch: for conditions whose lanes a branch predictor cannot foresee (a contact sliding or
/// not). Scalar: the `if`.
template <class T, class F>
inline void blend_assign(bool c, T& target, F&& f) {
  if (c) target = static_cast<T>(f());
}

template <class F>
inline void blend_assign(const LaneMask& c, Lane& target, F&& f) {
  const Lane v = f();
  assign_lanes(c, target, v);
}

template <class F>
inline void blend_assign(const LaneMask& c, LaneVec3& target, F&& f) {
  const LaneVec3 v = f();
  assign_lanes(c, target.x, v.x);
  assign_lanes(c, target.y, v.y);
  assign_lanes(c, target.z, v.z);
}

template <class F>
inline void blend_assign(const LaneMask& c, LaneVec2& target, F&& f) {
  const LaneVec2 v = f();
  assign_lanes(c, target.x, v.x);
  assign_lanes(c, target.y, v.y);
}

/// c ? a : b, lane by lane (both are evaluated).
inline double select(bool c, double a, double b) { return c ? a : b; }
inline Lane select(const LaneMask& c, const Lane& a, const Lane& b) {
  Lane r = b;
  assign_lanes(c, r, a);
  return r;
}

}  // namespace granule
