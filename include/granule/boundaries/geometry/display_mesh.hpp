#pragma once
// Approximate surfaces of the wall shapes for display (ParaView, OVITO), written by
// io::SurfaceVtkWriter. 3D shapes become triangles, 2D shapes become line segments (points
// padded with z = 0). Curved surfaces are faceted with `facets` segments per full turn; every
// vertex of a tessellation lies on the exact surface. Infinite planes are drawn as a square
// (3D) or a segment (2D) of half size `half_size` around their reference point.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "granule/boundaries/geometry/box.hpp"
#include "granule/boundaries/geometry/box_container.hpp"
#include "granule/boundaries/geometry/capsule.hpp"
#include "granule/boundaries/geometry/cylinder.hpp"
#include "granule/boundaries/geometry/cylinder_container.hpp"
#include "granule/boundaries/geometry/plane.hpp"
#include "granule/boundaries/geometry/posed_shape.hpp"
#include "granule/boundaries/geometry/prism.hpp"
#include "granule/boundaries/geometry/sphero_line.hpp"
#include "granule/boundaries/geometry/triangle_mesh.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Triangles and line segments over a shared list of 3D points (display only).
struct DisplayMesh {
  std::vector<Eigen::Vector3d> points;                  ///< [m]; z = 0 for 2D shapes
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into points
  std::vector<std::array<std::uint32_t, 2>> lines;      ///< indices into points

  std::uint32_t add_point(const Eigen::Vector3d& p) {
    points.push_back(p);
    return static_cast<std::uint32_t>(points.size() - 1);
  }
  std::uint32_t add_point(const Eigen::Vector2d& p) { return add_point(Eigen::Vector3d(p.x(), p.y(), 0.0)); }
  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) { triangles.push_back({a, b, c}); }
  void add_line(std::uint32_t a, std::uint32_t b) { lines.push_back({a, b}); }

  /// Appends another mesh (indices shifted).
  void append(const DisplayMesh& o) {
    const auto base = static_cast<std::uint32_t>(points.size());
    points.insert(points.end(), o.points.begin(), o.points.end());
    for (const auto& t : o.triangles) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    for (const auto& l : o.lines) lines.push_back({l[0] + base, l[1] + base});
  }
  /// Moves every point by a 3D pose.
  void transform(const Pose<Dim3>& pose) {
    for (auto& p : points) p = pose.to_world(p);
  }
  /// Moves every point by a 2D pose (in the x-y plane).
  void transform(const Pose<Dim2>& pose) {
    for (auto& p : points) {
      const Eigen::Vector2d q = pose.to_world(Eigen::Vector2d(p.x(), p.y()));
      p = Eigen::Vector3d(q.x(), q.y(), p.z());
    }
  }
};

namespace detail {

inline void check_facets(int facets, const char* where) {
  require(facets >= 3, where, "facets", facets, "[3, inf)");
}

inline DisplayMesh box_surface(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  DisplayMesh m;
  for (int k = 0; k < 8; ++k) {
    m.add_point(Eigen::Vector3d(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z()));
  }
  // Outward counter-clockwise faces; vertex index = ix + 2 iy + 4 iz.
  const std::array<std::array<std::uint32_t, 3>, 12> faces = {{{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                                               {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                                               {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}}};
  for (const auto& f : faces) m.add_triangle(f[0], f[1], f[2]);
  return m;
}

inline DisplayMesh box_surface(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  DisplayMesh m;
  const auto a = m.add_point(Eigen::Vector2d(lo.x(), lo.y()));
  const auto b = m.add_point(Eigen::Vector2d(hi.x(), lo.y()));
  const auto c = m.add_point(Eigen::Vector2d(hi.x(), hi.y()));
  const auto d = m.add_point(Eigen::Vector2d(lo.x(), hi.y()));
  m.add_line(a, b);
  m.add_line(b, c);
  m.add_line(c, d);
  m.add_line(d, a);
  return m;
}

/// Closed outline of a 2D stadium (segment a-b, radius r): two half circles joined by lines.
inline DisplayMesh stadium_outline(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double r, int facets) {
  const Eigen::Vector2d ab = b - a;
  const double angle0 = ab.squaredNorm() > 0.0 ? std::atan2(ab.y(), ab.x()) : 0.0;
  const int half = (facets + 1) / 2;
  DisplayMesh m;
  // Around b from -90 to +90 degrees relative to the axis, then around a from +90 to +270.
  for (int end = 0; end < 2; ++end) {
    const Eigen::Vector2d& c = end == 0 ? b : a;
    for (int k = 0; k <= half; ++k) {
      const double phi = angle0 - std::numbers::pi / 2 + end * std::numbers::pi + std::numbers::pi * k / half;
      m.add_point(Eigen::Vector2d(c + r * Eigen::Vector2d(std::cos(phi), std::sin(phi))));
    }
  }
  const auto n = static_cast<std::uint32_t>(m.points.size());
  for (std::uint32_t k = 0; k < n; ++k) m.add_line(k, (k + 1) % n);
  return m;
}

}  // namespace detail

/// A segment of half length `half_size` [m] along the line.
inline DisplayMesh tessellate(const PlaneShape<Dim2>& s, double half_size) {
  require_positive(half_size, "geometry::tessellate(PlaneShape<Dim2>)", "half_size");
  const Eigen::Vector2d t = detail::any_perpendicular(s.normal());
  DisplayMesh m;
  const auto a = m.add_point(Eigen::Vector2d(s.point() - half_size * t));
  const auto b = m.add_point(Eigen::Vector2d(s.point() + half_size * t));
  m.add_line(a, b);
  return m;
}

/// A square of half size `half_size` [m] centred on the plane point, facing along the normal.
inline DisplayMesh tessellate(const PlaneShape<Dim3>& s, double half_size) {
  require_positive(half_size, "geometry::tessellate(PlaneShape<Dim3>)", "half_size");
  const Eigen::Vector3d u = detail::any_perpendicular(s.normal());
  const Eigen::Vector3d w = s.normal().cross(u);
  DisplayMesh m;
  const double h = half_size;
  const auto a = m.add_point(Eigen::Vector3d(s.point() - h * u - h * w));
  const auto b = m.add_point(Eigen::Vector3d(s.point() + h * u - h * w));
  const auto c = m.add_point(Eigen::Vector3d(s.point() + h * u + h * w));
  const auto d = m.add_point(Eigen::Vector3d(s.point() - h * u + h * w));
  m.add_triangle(a, b, c);
  m.add_triangle(a, c, d);
  return m;
}

template <class D>
DisplayMesh tessellate(const BoxContainerShape<D>& s) {
  return detail::box_surface(s.lo(), s.hi());
}

template <class D>
DisplayMesh tessellate(const BoxShape<D>& s) {
  return detail::box_surface(s.lo(), s.hi());
}

template <class D>
DisplayMesh tessellate(const PrismShape<D>& s) {
  DisplayMesh m = detail::box_surface(typename D::Vec(-s.half_extents()), s.half_extents());
  m.transform(s.pose());
  return m;
}

/// Side: 2 triangles per facet; caps: triangle fans around their centres.
inline DisplayMesh tessellate(const CylinderShape& s, int facets = 32) {
  detail::check_facets(facets, "geometry::tessellate(CylinderShape)");
  const Eigen::Vector3d u = detail::any_perpendicular(s.axis());
  const Eigen::Vector3d w = s.axis().cross(u);
  DisplayMesh m;
  const Eigen::Vector3d top = s.centre() + s.half_length() * s.axis();
  const Eigen::Vector3d bottom = s.centre() - s.half_length() * s.axis();
  const auto top_c = m.add_point(top);
  const auto bottom_c = m.add_point(bottom);
  const auto n = static_cast<std::uint32_t>(facets);
  for (std::uint32_t k = 0; k < n; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / n;
    const Eigen::Vector3d r = s.radius() * (std::cos(phi) * u + std::sin(phi) * w);
    m.add_point(Eigen::Vector3d(bottom + r));  // 2 + 2k
    m.add_point(Eigen::Vector3d(top + r));     // 3 + 2k
  }
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t b0 = 2 + 2 * k, t0 = b0 + 1, b1 = 2 + 2 * ((k + 1) % n), t1 = b1 + 1;
    m.add_triangle(b0, b1, t1);
    m.add_triangle(b0, t1, t0);
    m.add_triangle(top_c, t0, t1);
    m.add_triangle(bottom_c, b1, b0);
  }
  return m;
}

/// Side: 2 triangles per facet; caps (closed tube only): triangle fans around their centres.
inline DisplayMesh tessellate(const CylinderContainerShape& s, int facets = 32) {
  detail::check_facets(facets, "geometry::tessellate(CylinderContainerShape)");
  DisplayMesh m = tessellate(CylinderShape(s.centre(), s.axis(), s.radius(), s.half_length()), facets);
  if (!s.closed()) {
    m.triangles.erase(std::remove_if(m.triangles.begin(), m.triangles.end(),
                                     [](const auto& t) { return t[0] < 2; }),  // the cap fans
                      m.triangles.end());
  }
  return m;
}

/// Closed outline (lines) of a 2D circle container.
inline DisplayMesh tessellate(const CircleContainerShape& s, int facets = 32) {
  detail::check_facets(facets, "geometry::tessellate(CircleContainerShape)");
  return detail::stadium_outline(s.centre(), s.centre(), s.radius(), facets);
}

/// Two hemispheres (latitude rings) joined by the cylindrical side.
inline DisplayMesh tessellate(const CapsuleShape<Dim3>& s, int facets = 24) {
  detail::check_facets(facets, "geometry::tessellate(CapsuleShape<Dim3>)");
  const Eigen::Vector3d ab = s.b() - s.a();
  const Eigen::Vector3d axis = ab.squaredNorm() > 0.0 ? Eigen::Vector3d(ab.normalized()) : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d u = detail::any_perpendicular(axis);
  const Eigen::Vector3d w = axis.cross(u);
  const auto n = static_cast<std::uint32_t>(facets);
  const int rings = std::max(1, facets / 4);  // latitude steps per hemisphere, equator excluded
  DisplayMesh m;
  const auto south = m.add_point(Eigen::Vector3d(s.a() - s.radius() * axis));
  // Latitude rings from the south pole to the north pole: around a at -90 + 90 (j+1)/rings
  // degrees (ending with a's equator), around b at 90 j/rings degrees (starting with b's
  // equator); the band between the two equators is the cylindrical side.
  std::vector<std::uint32_t> ring_start;
  for (int hemi = 0; hemi < 2; ++hemi) {
    const Eigen::Vector3d& c = hemi == 0 ? s.a() : s.b();
    for (int j = 0; j < rings; ++j) {
      const double lat = hemi == 0 ? -std::numbers::pi / 2 * (1.0 - double(j + 1) / rings)
                                   : std::numbers::pi / 2 * double(j) / rings;
      ring_start.push_back(static_cast<std::uint32_t>(m.points.size()));
      for (std::uint32_t k = 0; k < n; ++k) {
        const double phi = 2.0 * std::numbers::pi * k / n;
        const Eigen::Vector3d dir = std::cos(lat) * (std::cos(phi) * u + std::sin(phi) * w) + std::sin(lat) * axis;
        m.add_point(Eigen::Vector3d(c + s.radius() * dir));
      }
    }
  }
  const auto north = m.add_point(Eigen::Vector3d(s.b() + s.radius() * axis));
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t k1 = (k + 1) % n;
    m.add_triangle(south, ring_start.front() + k1, ring_start.front() + k);
    m.add_triangle(north, ring_start.back() + k, ring_start.back() + k1);
  }
  for (std::size_t r = 0; r + 1 < ring_start.size(); ++r) {
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t k1 = (k + 1) % n;
      const std::uint32_t a0 = ring_start[r] + k, a1 = ring_start[r] + k1;
      const std::uint32_t b0 = ring_start[r + 1] + k, b1 = ring_start[r + 1] + k1;
      m.add_triangle(a0, a1, b1);
      m.add_triangle(a0, b1, b0);
    }
  }
  return m;
}

/// Closed outline (lines) of a 2D capsule.
inline DisplayMesh tessellate(const CapsuleShape<Dim2>& s, int facets = 24) {
  detail::check_facets(facets, "geometry::tessellate(CapsuleShape<Dim2>)");
  return detail::stadium_outline(s.a(), s.b(), s.radius(), facets);
}

/// Closed outline (lines) of a sphero-line.
inline DisplayMesh tessellate(const SpheroLineShape& s, int facets = 24) {
  detail::check_facets(facets, "geometry::tessellate(SpheroLineShape)");
  return detail::stadium_outline(s.c1(), s.c2(), s.r_w(), facets);
}

/// The mesh itself.
inline DisplayMesh tessellate(const TriangleMeshShape& s) {
  DisplayMesh m;
  m.points = s.vertices();
  m.triangles = s.triangles();
  return m;
}

/// A posed shape: the body-frame tessellation moved by the pose.
template <class S, class... Args>
DisplayMesh tessellate(const PosedShape<S>& s, Args... args) {
  DisplayMesh m = tessellate(s.shape(), args...);
  m.transform(s.pose());
  return m;
}

}  // namespace granule::geometry
