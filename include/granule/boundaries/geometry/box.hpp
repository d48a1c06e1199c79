#pragma once
// Solid axis-aligned box [lo, hi]; particles live outside. Outside, the nearest point is the
// clamp of x to the box, q = min(max(x, lo), hi), so faces, edges and corners are rounded
// exactly (normal (x - q)/|x - q|). Inside (a particle that has crossed a face), the nearest
// face wins: depth to face a-lower is x_a - lo_a (outward normal -e_a), to a-upper hi_a - x_a
// (normal +e_a); distance = -depth. Ties: lower axis first, lower face first.
#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Solid axis-aligned box (particles outside).
template <class D>
class BoxShape {
 public:
  using Dimension = D;
  using Vec = typename D::Vec;

  /// Corners [m]; hi - lo must be positive in every component.
  BoxShape(const Vec& lo, const Vec& hi) : lo_(lo), hi_(hi) {
    for (int a = 0; a < D::dim; ++a) {
      require(std::isfinite(lo[a]) && std::isfinite(hi[a]) && hi[a] > lo[a], "geometry::BoxShape",
              "hi - lo (axis " + std::to_string(a) + ")", hi[a] - lo[a], "(0, inf)");
    }
  }

  const Vec& lo() const { return lo_; }
  const Vec& hi() const { return hi_; }

  SurfacePoint<D> closest(const Vec& x) const {
    const Vec q = x.cwiseMax(lo_).cwiseMin(hi_);
    if (q != x) return detail::outside_point<D>(x, q, detail::up_axis<D>());
    // Inside or on the surface: the face of least depth.
    SurfacePoint<D> s;
    double depth = x[0] - lo_[0];
    int axis = 0;
    double sign = -1.0;
    for (int a = 0; a < D::dim; ++a) {
      const double dl = x[a] - lo_[a];
      const double dh = hi_[a] - x[a];
      if (dl < depth) { depth = dl; axis = a; sign = -1.0; }
      if (dh < depth) { depth = dh; axis = a; sign = 1.0; }
    }
    s.distance = -depth;
    s.normal = Vec::Zero();
    s.normal[axis] = sign;
    s.point = x;
    s.point[axis] = sign > 0.0 ? hi_[axis] : lo_[axis];
    return s;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    const SurfacePoint<D> s = closest(x);
    if (s.distance < r_cut) f(s);
  }

  Aabb<D> bounds() const { return Aabb<D>(lo_, hi_); }

 private:
  Vec lo_;
  Vec hi_;
};

}  // namespace granule::geometry
