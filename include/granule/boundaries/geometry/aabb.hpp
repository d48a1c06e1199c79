#pragma once
// Axis-aligned bounding box in 2D or 3D. Used by the wall shapes (bounds()), the triangle
// bounding-volume hierarchy, the lattice and insertion generators and the neighbour candidate
// tests of walls. An infinite box (lo = -inf, hi = +inf) stands for unbounded shapes such as
// planes; an empty box (lo = +inf, hi = -inf) is the neutral element of extend().
#include <algorithm>
#include <cmath>
#include <limits>

#include "granule/core/dimension.hpp"

namespace granule::geometry {

/// Closed box [lo, hi] (component-wise) [m].
template <class D>
struct Aabb {
  using Vec = typename D::Vec;
  Vec lo = Vec::Zero();  ///< lower corner [m]
  Vec hi = Vec::Zero();  ///< upper corner [m]

  Aabb() = default;
  Aabb(const Vec& lower, const Vec& upper) : lo(lower), hi(upper) {}

  /// The whole space.
  static Aabb infinite() {
    const double inf = std::numeric_limits<double>::infinity();
    return Aabb(Vec::Constant(-inf), Vec::Constant(inf));
  }
  /// Contains nothing; extend() it to build a bounding box.
  static Aabb empty() {
    const double inf = std::numeric_limits<double>::infinity();
    return Aabb(Vec::Constant(inf), Vec::Constant(-inf));
  }

  /// True when some lo component exceeds its hi component.
  bool is_empty() const { return (lo.array() > hi.array()).any(); }
  /// True when all corners are finite numbers.
  bool is_finite() const { return lo.allFinite() && hi.allFinite(); }
  Vec extent() const { return hi - lo; }
  Vec centre() const { return 0.5 * (lo + hi); }

  bool contains(const Vec& x) const {
    return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  }
  bool overlaps(const Aabb& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
  /// Box grown by `margin` [m] on every side (infinite sides stay infinite).
  Aabb expanded(double margin) const {
    return Aabb(lo - Vec::Constant(margin), hi + Vec::Constant(margin));
  }
  void extend(const Vec& x) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  void extend(const Aabb& o) {
    lo = lo.cwiseMin(o.lo);
    hi = hi.cwiseMax(o.hi);
  }
  /// Squared distance from x to the box (0 inside) [m^2].
  double squared_distance(const Vec& x) const {
    const Vec below = (lo - x).cwiseMax(0.0);
    const Vec above = (x - hi).cwiseMax(0.0);
    return below.squaredNorm() + above.squaredNorm();
  }
};

}  // namespace granule::geometry
