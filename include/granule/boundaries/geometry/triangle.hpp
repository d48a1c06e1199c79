#pragma once
// Nearest point of a triangle abc to a point p, by the Voronoi regions of its features
// (Ericson, Real-Time Collision Detection, 2005, section 5.1.5). With ab = b - a, ac = c - a,
// the dot products d1 = ab.(p-a), d2 = ac.(p-a), d3 = ab.(p-b), d4 = ac.(p-b), d5 = ab.(p-c),
// d6 = ac.(p-c) and the barycentric numerators va = d3 d6 - d5 d4, vb = d5 d2 - d1 d6,
// vc = d1 d4 - d3 d2, the regions are tested in the order
//   vertex a (d1 <= 0, d2 <= 0), vertex b (d3 >= 0, d4 <= d3), edge ab (vc <= 0, d1 >= 0, d3 <= 0),
//   vertex c (d6 >= 0, d5 <= d6), edge ca (vb <= 0, d2 >= 0, d6 <= 0),
//   edge bc (va <= 0, d4 - d3 >= 0, d5 - d6 >= 0), face (barycentric (va, vb, vc)/(va + vb + vc)).
// Points on a region boundary go to the first region tested, so the answer is deterministic.
// Local numbering: vertex k is (a, b, c)[k]; edge k joins vertex k and vertex (k+1) mod 3
// (edge 0 = ab, edge 1 = bc, edge 2 = ca).
#include <cstdint>

#include <Eigen/Core>

namespace granule::geometry {

/// Which part of a triangle holds the nearest point.
enum class TriangleFeature : std::uint8_t { Vertex, Edge, Face };

/// Nearest point on a triangle and the feature (with its local index 0..2) it lies on.
struct TrianglePoint {
  Eigen::Vector3d point;    ///< [m]
  TriangleFeature feature;  ///< vertex, edge or face interior
  int index;                ///< local vertex / edge index; 0 for the face
};

/// Nearest point of triangle (a, b, c) to p (Ericson 2005, 5.1.5).
inline TrianglePoint closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, TriangleFeature::Vertex, 0};

  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, TriangleFeature::Vertex, 1};

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return {a + t * ab, TriangleFeature::Edge, 0};
  }

  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, TriangleFeature::Vertex, 2};

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return {a + t * ac, TriangleFeature::Edge, 2};
  }

  const double va = d3 * d6 - d5 * d4;
  const double e43 = d4 - d3;
  const double e56 = d5 - d6;
  if (va <= 0.0 && e43 >= 0.0 && e56 >= 0.0) {
    const double t = e43 / (e43 + e56);
    return {b + t * (c - b), TriangleFeature::Edge, 1};
  }

  const double inv = 1.0 / (va + vb + vc);
  return {a + ab * (vb * inv) + ac * (vc * inv), TriangleFeature::Face, 0};
}

}  // namespace granule::geometry
