#pragma once
// Triangle mesh wall (3D), e.g. an STL surface. Vertices are welded into a shared topology
// (vertices, edges, triangles) on construction; nearest points use closest_on_triangle()
// (Ericson 2005, 5.1.5) over the candidates of an AabbTree.
//
// Sides. TwoSided: both sides of every triangle are particle side; distance = |x - p| >= 0.
// OneSided: only the front side (counter-clockwise winding, n = (b - a) x (c - a)/|...|) is
// particle side. closest() returns a signed distance whose sign is that of (x - p) . N, with N
// the angle-weighted pseudo-normal of the nearest feature (Baerentzen & Aanaes, IEEE TVCG 2005):
// the face normal, the normalised sum of the two face normals of an edge, the sum of the
// incident face normals weighted by their angles at a vertex. For a closed, consistently
// oriented mesh this is the signed distance of the solid. for_each_contact() of a one-sided
// mesh ignores features with x behind them ((x - p) . N < 0).
//
// Contact rule (one contact per touched feature, no double counting). A particle touches the
// mesh where the distance |x - y| over surface points y has a local minimum closer than r_cut.
// Every such minimum is the nearest point of at least one triangle, so the candidates are the
// nearest points of the triangles within r_cut. Each candidate is labelled with its global
// feature (triangle face, welded edge or welded vertex); duplicates of a shared edge/vertex
// reported by several triangles are merged by label. A face candidate is always a local
// minimum. An edge candidate at p is kept only when no adjacent face lets the distance
// decrease, i.e. (x - p) . t_F <= 0 for every adjacent triangle F, t_F the unit vector in F's
// plane perpendicular to the edge pointing into F. A vertex candidate V is kept only when
// (x - V) . u_k <= 0 for every incident edge direction u_k. Finally, candidates whose points
// coincide (to 1e-8 r_cut) are merged, faces taking precedence. So a flat patch gives one
// contact however it is triangulated, a convex ridge or corner gives one edge/vertex contact,
// and a concave crease gives one contact per face, as a smooth surface would.
//
// SurfacePoint::feature: face t -> t, edge e -> T + e, vertex v -> T + E + v (T triangles,
// E edges).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "granule/boundaries/geometry/aabb.hpp"
#include "granule/boundaries/geometry/aabb_tree.hpp"
#include "granule/boundaries/geometry/surface_point.hpp"
#include "granule/boundaries/geometry/triangle.hpp"
#include "granule/core/error.hpp"

namespace granule::geometry {

/// Whether one or both sides of a mesh are particle side.
enum class MeshSides { OneSided, TwoSided };

/// A triangle given by its three corner positions [m].
using TriangleCorners = std::array<Eigen::Vector3d, 3>;

/// Shared-vertex mesh: positions and, per triangle, three vertex indices.
struct IndexedTriangles {
  std::vector<Eigen::Vector3d> vertices;                ///< [m]
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< vertex indices, counter-clockwise
};

/// Merges corners closer than `tolerance` [m] (0: bit-identical coordinates only). The first
/// occurrence of a position becomes the representative; the order is deterministic.
inline IndexedTriangles weld_triangles(std::span<const TriangleCorners> soup, double tolerance = 0.0) {
  require_non_negative(tolerance, "geometry::weld_triangles", "tolerance");
  IndexedTriangles out;
  out.triangles.reserve(soup.size());
  if (tolerance == 0.0) {
    std::map<std::array<double, 3>, std::uint32_t> index;
    for (const TriangleCorners& t : soup) {
      std::array<std::uint32_t, 3> ids{};
      for (int k = 0; k < 3; ++k) {
        // + 0.0 maps -0.0 to +0.0 so that both weld together.
        const std::array<double, 3> key{t[k].x() + 0.0, t[k].y() + 0.0, t[k].z() + 0.0};
        const auto [it, inserted] = index.try_emplace(key, static_cast<std::uint32_t>(out.vertices.size()));
        if (inserted) out.vertices.push_back(t[k]);
        ids[k] = it->second;
      }
      out.triangles.push_back(ids);
    }
    return out;
  }
  struct CellHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& c) const {
      std::uint64_t h = 1469598103934665603ull;
      for (std::int64_t v : c) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>, CellHash> grid;
  const double tol2 = tolerance * tolerance;
  for (const TriangleCorners& t : soup) {
    std::array<std::uint32_t, 3> ids{};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p = t[k];
      std::array<std::int64_t, 3> cell{};
      for (int a = 0; a < 3; ++a) cell[a] = static_cast<std::int64_t>(std::floor(p[a] / tolerance));
      std::uint32_t found = static_cast<std::uint32_t>(-1);
      for (int dx = -1; dx <= 1 && found == static_cast<std::uint32_t>(-1); ++dx) {
        for (int dy = -1; dy <= 1 && found == static_cast<std::uint32_t>(-1); ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
            if (it == grid.end()) continue;
            for (std::uint32_t v : it->second) {
              if ((out.vertices[v] - p).squaredNorm() <= tol2 && v < found) found = v;
            }
          }
        }
      }
      if (found == static_cast<std::uint32_t>(-1)) {
        found = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back(p);
        grid[cell].push_back(found);
      }
      ids[k] = found;
    }
    out.triangles.push_back(ids);
  }
  return out;
}

namespace detail {

/// Empty string for a valid triangle, else why it is degenerate (non-finite corner, repeated
/// corner, or zero area: |(b - a) x (c - a)| <= 1e-12 * (longest edge)^2).
inline std::string triangle_defect(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  if (!a.allFinite() || !b.allFinite() || !c.allFinite()) return "non-finite vertex coordinate";
  if (a == b || b == c || c == a) return "repeated vertex";
  const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  if ((b - a).cross(c - a).norm() <= 1e-12 * longest2) return "zero area";
  return {};
}

/// A few elements inline, more on the heap (no allocation in the common case).
template <class T, std::size_t N>
class SmallBuffer {
 public:
  void push_back(const T& v) {
    if (size_ < N) {
      inline_[size_] = v;
    } else {
      overflow_.push_back(v);
    }
    ++size_;
  }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t k) { return k < N ? inline_[k] : overflow_[k - N]; }
  const T& operator[](std::size_t k) const { return k < N ? inline_[k] : overflow_[k - N]; }

 private:
  std::array<T, N> inline_{};
  std::vector<T> overflow_;
  std::size_t size_ = 0;
};

}  // namespace detail

/// Triangle mesh wall with welded topology and a BVH.
class TriangleMeshShape {
 public:
  using Dimension = Dim3;
  using Vec = Dim3::Vec;
  using Indices = std::array<std::uint32_t, 3>;

  /// From a triangle soup; corners within `weld_tolerance` [m] are merged.
  explicit TriangleMeshShape(std::span<const TriangleCorners> soup, MeshSides sides = MeshSides::TwoSided,
                             double weld_tolerance = 0.0)
      : TriangleMeshShape(weld_triangles(soup, weld_tolerance), sides) {}

  /// From shared vertices and index triples (counter-clockwise seen from the front side).
  explicit TriangleMeshShape(IndexedTriangles mesh, MeshSides sides = MeshSides::TwoSided)
      : vertices_(std::move(mesh.vertices)), triangles_(std::move(mesh.triangles)), sides_(sides) {
    require(!triangles_.empty(), "geometry::TriangleMeshShape", "number of triangles", 0.0, "[1, inf)");
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        require(triangles_[t][k] < vertices_.size(), "geometry::TriangleMeshShape",
                "vertex index of triangle " + std::to_string(t), triangles_[t][k],
                "[0, " + std::to_string(vertices_.size()) + ")");
      }
      const std::string defect = detail::triangle_defect(corner(t, 0), corner(t, 1), corner(t, 2));
      if (!defect.empty()) {
        throw InvalidParameter("geometry::TriangleMeshShape: triangle " + std::to_string(t) +
                               " is degenerate (" + defect + ")");
      }
    }
    build_topology();
    std::vector<Aabb<Dim3>> boxes(triangles_.size());
    bounds_ = Aabb<Dim3>::empty();
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      boxes[t] = Aabb<Dim3>::empty();
      for (int k = 0; k < 3; ++k) boxes[t].extend(corner(t, k));
      bounds_.extend(boxes[t]);
    }
    scale_ = bounds_.extent().norm();
    tree_ = AabbTree<Dim3>(boxes);
  }

  const std::vector<Vec>& vertices() const { return vertices_; }
  const std::vector<Indices>& triangles() const { return triangles_; }
  std::size_t edge_count() const { return edges_.size(); }
  /// Vertex indices (lower first) of edge e.
  const std::array<std::uint32_t, 2>& edge(std::size_t e) const { return edges_[e]; }
  /// Number of triangles sharing edge e (1: boundary, 2: manifold, > 2: non-manifold).
  std::size_t edge_valence(std::size_t e) const { return edge_tri_start_[e + 1] - edge_tri_start_[e]; }
  MeshSides sides() const { return sides_; }
  const Vec& triangle_normal(std::size_t t) const { return face_normal_[t]; }
  const Vec& corner(std::size_t t, int k) const { return vertices_[triangles_[t][k]]; }

  std::uint32_t face_key(std::size_t t) const { return static_cast<std::uint32_t>(t); }
  std::uint32_t edge_key(std::size_t e) const { return static_cast<std::uint32_t>(triangles_.size() + e); }
  std::uint32_t vertex_key(std::size_t v) const {
    return static_cast<std::uint32_t>(triangles_.size() + edges_.size() + v);
  }
  /// Pseudo-normal of a feature key (face normal, edge or angle-weighted vertex normal).
  const Vec& pseudo_normal(std::uint32_t key) const {
    if (key < triangles_.size()) return face_normal_[key];
    if (key < triangles_.size() + edges_.size()) return edge_normal_[key - triangles_.size()];
    return vertex_normal_[key - triangles_.size() - edges_.size()];
  }

  SurfacePoint<Dim3> closest(const Vec& x) const {
    const auto [t, d] = tree_.nearest(x, [&](std::uint32_t tri) {
      return (x - closest_on_triangle(x, corner(tri, 0), corner(tri, 1), corner(tri, 2)).point).norm();
    });
    const TrianglePoint tp = closest_on_triangle(x, corner(t, 0), corner(t, 1), corner(t, 2));
    const std::uint32_t key = feature_key(t, tp);
    const Vec& pn = pseudo_normal(key);
    const Vec dvec = x - tp.point;
    SurfacePoint<Dim3> s;
    s.point = tp.point;
    s.feature = key;
    if (d == 0.0) {
      s.distance = 0.0;
      s.normal = pn;
      return s;
    }
    const bool behind = sides_ == MeshSides::OneSided && dvec.dot(pn) < 0.0;
    s.distance = behind ? -d : d;
    s.normal = behind ? Vec(-dvec / d) : Vec(dvec / d);
    return s;
  }

  template <class F>
  void for_each_contact(const Vec& x, double r_cut, F&& f) const {
    if (!(r_cut > 0.0)) return;
    detail::SmallBuffer<Candidate, 24> cand;
    tree_.for_each_near(x, r_cut, [&](std::uint32_t t) {
      const TrianglePoint tp = closest_on_triangle(x, corner(t, 0), corner(t, 1), corner(t, 2));
      const double d = (x - tp.point).norm();
      if (d >= r_cut) return;
      const std::uint32_t key = feature_key(t, tp);
      for (std::size_t k = 0; k < cand.size(); ++k) {
        if (cand[k].key == key) return;
      }
      cand.push_back({tp.point, d, key, tp.feature, false});
    });
    const double eps = 1e-10;
    const double merge_tol2 = std::pow(1e-8 * r_cut + 1e-12 * scale_, 2);
    // Faces first, so that they win the merge of coincident points.
    for (TriangleFeature kind : {TriangleFeature::Face, TriangleFeature::Edge, TriangleFeature::Vertex}) {
      for (std::size_t k = 0; k < cand.size(); ++k) {
        Candidate& c = cand[k];
        if (c.kind != kind) continue;
        const Vec dvec = x - c.point;
        if (sides_ == MeshSides::OneSided && dvec.dot(pseudo_normal(c.key)) < 0.0) continue;
        if (kind == TriangleFeature::Edge && !edge_is_minimum(c.key - edge_base(), dvec, eps * c.distance)) continue;
        if (kind == TriangleFeature::Vertex && !vertex_is_minimum(c.key - vertex_base(), dvec, eps * c.distance)) {
          continue;
        }
        bool duplicate = false;
        for (std::size_t m = 0; m < cand.size(); ++m) {
          if (cand[m].kept && (cand[m].point - c.point).squaredNorm() <= merge_tol2) duplicate = true;
        }
        c.kept = !duplicate;
      }
    }
    // Report in candidate order (the deterministic tree traversal order).
    for (std::size_t k = 0; k < cand.size(); ++k) {
      const Candidate& c = cand[k];
      if (!c.kept) continue;
      SurfacePoint<Dim3> s;
      s.point = c.point;
      s.distance = c.distance;
      s.normal = c.distance > 0.0 ? Vec((x - c.point) / c.distance) : pseudo_normal(c.key);
      s.feature = c.key;
      f(s);
    }
  }

  Aabb<Dim3> bounds() const { return bounds_; }

 private:
  struct Candidate {
    Vec point = Vec::Zero();
    double distance = 0.0;
    std::uint32_t key = 0;
    TriangleFeature kind = TriangleFeature::Face;
    bool kept = false;
  };

  std::uint32_t edge_base() const { return static_cast<std::uint32_t>(triangles_.size()); }
  std::uint32_t vertex_base() const { return static_cast<std::uint32_t>(triangles_.size() + edges_.size()); }

  std::uint32_t feature_key(std::uint32_t t, const TrianglePoint& tp) const {
    switch (tp.feature) {
      case TriangleFeature::Face: return face_key(t);
      case TriangleFeature::Edge: return edge_key(tri_edges_[t][tp.index]);
      case TriangleFeature::Vertex: break;
    }
    return vertex_key(triangles_[t][tp.index]);
  }

  bool edge_is_minimum(std::uint32_t e, const Vec& dvec, double tol) const {
    for (std::uint32_t k = edge_tri_start_[e]; k < edge_tri_start_[e + 1]; ++k) {
      if (dvec.dot(edge_inward_[k]) > tol) return false;
    }
    return true;
  }

  bool vertex_is_minimum(std::uint32_t v, const Vec& dvec, double tol) const {
    for (std::uint32_t k = vertex_edge_start_[v]; k < vertex_edge_start_[v + 1]; ++k) {
      if (dvec.dot(vertex_edge_dir_[k]) > tol) return false;
    }
    return true;
  }

  void build_topology() {
    const std::size_t nt = triangles_.size();
    const std::size_t nv = vertices_.size();
    face_normal_.resize(nt);
    tri_edges_.resize(nt);
    std::unordered_map<std::uint64_t, std::uint32_t> edge_id;
    edge_id.reserve(3 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
      face_normal_[t] = (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0)).normalized();
      for (int k = 0; k < 3; ++k) {
        std::uint32_t a = triangles_[t][k];
        std::uint32_t b = triangles_[t][(k + 1) % 3];
        if (a > b) std::swap(a, b);
        const std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | b;
        const auto [it, inserted] = edge_id.try_emplace(key, static_cast<std::uint32_t>(edges_.size()));
        if (inserted) edges_.push_back({a, b});
        tri_edges_[t][k] = it->second;
      }
    }
    const std::size_t ne = edges_.size();
    // Edge -> adjacent triangles (CSR), with the inward in-plane perpendicular of each.
    edge_tri_start_.assign(ne + 1, 0);
    for (std::size_t t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) ++edge_tri_start_[tri_edges_[t][k] + 1];
    }
    for (std::size_t e = 0; e < ne; ++e) edge_tri_start_[e + 1] += edge_tri_start_[e];
    edge_inward_.resize(3 * nt);
    edge_tri_.resize(3 * nt);
    std::vector<std::uint32_t> fill(edge_tri_start_.begin(), edge_tri_start_.end() - 1);
    edge_normal_.assign(ne, Vec::Zero());
    for (std::size_t t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = tri_edges_[t][k];
        const Vec& p = corner(t, k);
        const Vec dir = (corner(t, (k + 1) % 3) - p).normalized();
        const Vec to_third = corner(t, (k + 2) % 3) - p;
        edge_tri_[fill[e]] = static_cast<std::uint32_t>(t);
        edge_inward_[fill[e]++] = (to_third - to_third.dot(dir) * dir).normalized();
        edge_normal_[e] += face_normal_[t];
      }
    }
    for (std::size_t e = 0; e < ne; ++e) {
      const double len = edge_normal_[e].norm();
      edge_normal_[e] = len > 1e-12 ? Vec(edge_normal_[e] / len) : face_normal_[edge_tri_[edge_tri_start_[e]]];
    }
    // Vertex -> incident edge directions (CSR) and angle-weighted vertex normals.
    vertex_edge_start_.assign(nv + 1, 0);
    for (const auto& e : edges_) {
      ++vertex_edge_start_[e[0] + 1];
      ++vertex_edge_start_[e[1] + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) vertex_edge_start_[v + 1] += vertex_edge_start_[v];
    vertex_edge_dir_.resize(2 * ne);
    std::vector<std::uint32_t> vfill(vertex_edge_start_.begin(), vertex_edge_start_.end() - 1);
    for (const auto& e : edges_) {
      const Vec d = (vertices_[e[1]] - vertices_[e[0]]).normalized();
      vertex_edge_dir_[vfill[e[0]]++] = d;
      vertex_edge_dir_[vfill[e[1]]++] = -d;
    }
    vertex_normal_.assign(nv, Vec::Zero());
    std::vector<std::uint32_t> some_triangle(nv, 0);
    for (std::size_t t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) {
        const Vec u = (corner(t, (k + 1) % 3) - corner(t, k)).normalized();
        const Vec w = (corner(t, (k + 2) % 3) - corner(t, k)).normalized();
        const double angle = std::atan2(u.cross(w).norm(), u.dot(w));
        vertex_normal_[triangles_[t][k]] += angle * face_normal_[t];
        some_triangle[triangles_[t][k]] = static_cast<std::uint32_t>(t);
      }
    }
    for (std::size_t v = 0; v < nv; ++v) {
      const double len = vertex_normal_[v].norm();
      vertex_normal_[v] = len > 1e-12 ? Vec(vertex_normal_[v] / len) : face_normal_[some_triangle[v]];
    }
  }

  std::vector<Vec> vertices_;
  std::vector<Indices> triangles_;
  MeshSides sides_;
  std::vector<Vec> face_normal_;
  std::vector<std::array<std::uint32_t, 3>> tri_edges_;  // global edge of local edge k
  std::vector<std::array<std::uint32_t, 2>> edges_;
  std::vector<std::uint32_t> edge_tri_start_;  // CSR offsets, size E + 1
  std::vector<std::uint32_t> edge_tri_;        // adjacent triangle per CSR slot
  std::vector<Vec> edge_inward_;               // per (edge, adjacent triangle)
  std::vector<Vec> edge_normal_;
  std::vector<std::uint32_t> vertex_edge_start_;  // CSR offsets, size V + 1
  std::vector<Vec> vertex_edge_dir_;              // unit directions away from the vertex
  std::vector<Vec> vertex_normal_;
  Aabb<Dim3> bounds_;
  double scale_ = 0.0;  // bounding-box diagonal [m]
  AabbTree<Dim3> tree_;
};

}  // namespace granule::geometry
