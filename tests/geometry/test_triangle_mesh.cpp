// TriangleMeshShape: welding, the one-contact-per-feature rule (flat patches, convex ridge,
// concave crease, inner and outer cube corners), the signed distance of a closed one-sided
// mesh against the analytic BoxShape, sidedness, BVH queries against brute force, posed mesh
// against the analytic PrismShape.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "granule/boundaries/geometry/box.hpp"
#include "granule/boundaries/geometry/posed_shape.hpp"
#include "granule/boundaries/geometry/prism.hpp"
#include "granule/boundaries/geometry/triangle_mesh.hpp"
#include "surface_checks.hpp"

using namespace granule;
using namespace granule::geometry;
using V3 = Eigen::Vector3d;

namespace {

std::vector<SurfacePoint<Dim3>> contacts(const TriangleMeshShape& m, const V3& x, double r_cut) {
  std::vector<SurfacePoint<Dim3>> out;
  m.for_each_contact(x, r_cut, [&](const SurfacePoint<Dim3>& s) { out.push_back(s); });
  return out;
}

// Unit cube [0, 1]^3, outward counter-clockwise winding; vertex index = x + 2y + 4z.
IndexedTriangles cube() {
  IndexedTriangles m;
  for (int k = 0; k < 8; ++k) m.vertices.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

// n x n squares of the unit square z = 0, each split along alternating diagonals.
std::vector<TriangleCorners> flat_grid(int n) {
  std::vector<TriangleCorners> soup;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double h = 1.0 / n;
      const V3 p00(i * h, j * h, 0), p10((i + 1) * h, j * h, 0), p11((i + 1) * h, (j + 1) * h, 0),
          p01(i * h, (j + 1) * h, 0);
      if ((i + j) % 2 == 0) {
        soup.push_back({p00, p10, p11});
        soup.push_back({p00, p11, p01});
      } else {
        soup.push_back({p00, p10, p01});
        soup.push_back({p10, p11, p01});
      }
    }
  }
  return soup;
}

}  // namespace

TEST_CASE("TriangleMeshShape welds shared corners", "[geometry][triangle_mesh]") {
  const auto soup = flat_grid(3);
  const TriangleMeshShape mesh(soup);
  CHECK(mesh.triangles().size() == 18u);
  CHECK(mesh.vertices().size() == 16u);    // 4 x 4 grid points
  CHECK(mesh.edge_count() == 33u);         // 2*3*4 axis edges + 9 diagonals
  // Corners off by 1e-9 weld only with a tolerance.
  std::vector<TriangleCorners> shifted = {{V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0)},
                                          {V3(1, 1e-9, 0), V3(1, 1, 0), V3(0, 1, 0)}};
  CHECK(TriangleMeshShape(shifted).vertices().size() == 5u);
  const TriangleMeshShape welded(shifted, MeshSides::TwoSided, 1e-6);
  CHECK(welded.vertices().size() == 4u);
  CHECK(welded.edge_valence(welded.edge_count() - 1) >= 1u);
}

TEST_CASE("TriangleMeshShape refuses degenerate triangles", "[geometry][triangle_mesh]") {
  std::vector<TriangleCorners> soup = {{V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0)},
                                       {V3(0, 0, 0), V3(1, 1, 1), V3(2, 2, 2)}};
  CHECK_THROWS_WITH(TriangleMeshShape(soup), Catch::Contains("triangle 1") && Catch::Contains("zero area"));
  soup[1] = {V3(0, 0, 0), V3(0, 0, 0), V3(2, 2, 2)};
  CHECK_THROWS_WITH(TriangleMeshShape(soup), Catch::Contains("triangle 1"));
  // Welding with a large tolerance collapses a small triangle.
  soup[1] = {V3(5, 5, 5), V3(5.001, 5, 5), V3(5, 5.001, 5)};
  CHECK_THROWS_AS(TriangleMeshShape(soup, MeshSides::TwoSided, 0.01), InvalidParameter);
  CHECK_THROWS_AS(TriangleMeshShape(std::vector<TriangleCorners>{}), InvalidParameter);
}

TEST_CASE("TriangleMeshShape gives one contact on a flat patch", "[geometry][triangle_mesh]") {
  const TriangleMeshShape mesh(flat_grid(4));
  // Above shared diagonals, shared axis edges, shared vertices and face interiors.
  const std::vector<V3> probes = {V3(0.125, 0.125, 0.1), V3(0.25, 0.1, 0.1), V3(0.25, 0.25, 0.1),
                                  V3(0.5, 0.5, 0.05), V3(0.3, 0.27, 0.1), V3(0.62, 0.4, 0.2)};
  for (const V3& x : probes) {
    const auto c = contacts(mesh, x, 0.3);
    INFO("x = " << x.transpose());
    REQUIRE(c.size() == 1u);
    CHECK(c[0].distance == Approx(x.z()).epsilon(1e-14));
    CHECK((c[0].normal - V3(0, 0, 1)).norm() < 1e-12);
    CHECK((c[0].point - V3(x.x(), x.y(), 0)).norm() < 1e-12);
  }
  std::mt19937_64 gen(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    const V3 x(u(gen), u(gen), 0.01 + 0.1 * u(gen));
    const auto c = contacts(mesh, x, 0.2);
    REQUIRE(c.size() == 1u);
    CHECK(c[0].distance == Approx(x.z()).epsilon(1e-12));
  }
  // Beyond the border of the sheet: one edge contact with the rounded edge.
  const auto e = contacts(mesh, V3(1.3, 0.5, 0.4), 0.6);
  REQUIRE(e.size() == 1u);
  CHECK(e[0].distance == Approx(0.5));
  CHECK((e[0].normal - V3(0.6, 0, 0.8)).norm() < 1e-12);
}

TEST_CASE("TriangleMeshShape convex ridge and concave crease", "[geometry][triangle_mesh]") {
  // Roof: ridge x = 0, z = 1 for y in [0, 1]; slopes down to x = +-1, z = 0.
  const V3 l0(-1, 0, 0), l1(-1, 1, 0), r0(1, 0, 0), r1(1, 1, 0), t0(0, 0, 1), t1(0, 1, 1);
  const std::vector<TriangleCorners> roof = {{l0, t0, t1}, {l0, t1, l1}, {t0, r0, r1}, {t0, r1, t1}};
  const TriangleMeshShape ridge(roof);
  const auto c = contacts(ridge, V3(0, 0.5, 1.3), 0.5);
  REQUIRE(c.size() == 1u);
  CHECK(c[0].distance == Approx(0.3));
  CHECK((c[0].normal - V3(0, 0, 1)).norm() < 1e-12);
  CHECK(c[0].feature >= 4u);  // an edge key (faces are 0..3)
  // Slightly to the right of the ridge but above the right face: one face contact.
  const V3 x(0.2, 0.5, 1.0);  // distance to the right slope: |0.2 + 1.0 - 1|/sqrt 2
  const auto f = contacts(ridge, x, 0.5);
  REQUIRE(f.size() == 1u);
  CHECK(f[0].distance == Approx(0.2 / std::sqrt(2.0)));
  CHECK((f[0].normal - V3(1, 0, 1).normalized()).norm() < 1e-12);

  // Valley (the roof upside down): a particle in the crease touches both faces.
  std::vector<TriangleCorners> valley;
  for (auto t : roof) {
    for (auto& p : t) p.z() = -p.z();
    std::swap(t[1], t[2]);
    valley.push_back(t);
  }
  const TriangleMeshShape crease(valley);
  const auto v = contacts(crease, V3(0, 0.5, -0.5), 0.5);
  REQUIRE(v.size() == 2u);
  for (const auto& s : v) {
    CHECK(s.distance == Approx(0.5 / std::sqrt(2.0)));
    CHECK(std::abs(std::abs(s.normal.x()) - 1.0 / std::sqrt(2.0)) < 1e-12);
    CHECK(s.normal.z() == Approx(1.0 / std::sqrt(2.0)));
  }
  CHECK(v[0].normal.x() * v[1].normal.x() < 0.0);
}

TEST_CASE("TriangleMeshShape cube corners from inside and outside", "[geometry][triangle_mesh]") {
  const TriangleMeshShape two(cube(), MeshSides::TwoSided);
  // Inner corner: three faces at 0.1, 0.2, 0.3.
  auto c = contacts(two, V3(0.1, 0.2, 0.3), 0.35);
  REQUIRE(c.size() == 3u);
  std::vector<double> d;
  for (const auto& s : c) d.push_back(s.distance);
  std::sort(d.begin(), d.end());
  CHECK(d[0] == Approx(0.1));
  CHECK(d[1] == Approx(0.2));
  CHECK(d[2] == Approx(0.3));
  // Outer corner: one vertex contact along the diagonal.
  const TriangleMeshShape one(cube(), MeshSides::OneSided);
  c = contacts(one, V3(1.2, 1.2, 1.2), 0.4);
  REQUIRE(c.size() == 1u);
  CHECK(c[0].distance == Approx(0.2 * std::sqrt(3.0)));
  CHECK((c[0].normal - V3(1, 1, 1).normalized()).norm() < 1e-12);
  CHECK(c[0].feature == one.vertex_key(7));
  // Outer edge.
  c = contacts(one, V3(1.3, 0.5, 1.4), 0.6);
  REQUIRE(c.size() == 1u);
  CHECK(c[0].distance == Approx(0.5));
  // One-sided: a point inside the closed cube is behind every face, so no contact.
  CHECK(contacts(one, V3(0.1, 0.2, 0.3), 0.35).empty());
}

TEST_CASE("TriangleMeshShape closed one-sided cube matches BoxShape", "[geometry][triangle_mesh]") {
  const TriangleMeshShape mesh(cube(), MeshSides::OneSided);
  for (std::size_t t = 0; t < mesh.triangles().size(); ++t) {
    const V3 centroid = (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0;
    CHECK(mesh.triangle_normal(t).dot(centroid - V3::Constant(0.5)) > 0.0);  // outward winding
  }
  const BoxShape<Dim3> box(V3::Zero(), V3::Ones());
  std::mt19937_64 gen(4);
  std::uniform_real_distribution<double> u(-0.7, 1.7);
  int outside_checked = 0;
  for (int k = 0; k < 2000; ++k) {
    const V3 x(u(gen), u(gen), u(gen));
    const auto m = mesh.closest(x);
    const auto b = box.closest(x);
    INFO("x = " << x.transpose());
    CHECK(m.distance == Approx(b.distance).margin(1e-13));
    CHECK((m.point - b.point).norm() < 1e-12);
    test::check_convention(x, m);
    if (b.distance > 0.0 && b.distance < 0.3) {
      const auto c = contacts(mesh, x, 0.3);
      REQUIRE(c.size() == 1u);
      CHECK(c[0].distance == Approx(b.distance).margin(1e-13));
      CHECK((c[0].normal - b.normal).norm() < 1e-9);
      ++outside_checked;
    }
  }
  CHECK(outside_checked > 100);
}

TEST_CASE("TriangleMeshShape sidedness of a single triangle", "[geometry][triangle_mesh]") {
  const std::vector<TriangleCorners> tri = {{V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0)}};
  const TriangleMeshShape one(tri, MeshSides::OneSided);
  const TriangleMeshShape two(tri, MeshSides::TwoSided);
  const V3 below(0.2, 0.2, -0.1);
  CHECK(contacts(one, below, 0.2).empty());
  const auto c = contacts(two, below, 0.2);
  REQUIRE(c.size() == 1u);
  CHECK((c[0].normal - V3(0, 0, -1)).norm() < 1e-15);
  CHECK(one.closest(below).distance == Approx(-0.1));
  CHECK(two.closest(below).distance == Approx(0.1));
  CHECK(contacts(one, V3(0.2, 0.2, 0.1), 0.2).size() == 1u);
}

TEST_CASE("TriangleMeshShape BVH queries equal brute force", "[geometry][triangle_mesh]") {
  // A bumpy sheet of 2 * 24^2 triangles.
  std::vector<TriangleCorners> soup;
  const int n = 24;
  auto z = [](double x, double y) { return 0.1 * std::sin(6 * x) * std::cos(5 * y); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double h = 1.0 / n;
      const double x0 = i * h, y0 = j * h, x1 = x0 + h, y1 = y0 + h;
      const V3 a(x0, y0, z(x0, y0)), b(x1, y0, z(x1, y0)), c(x1, y1, z(x1, y1)), d(x0, y1, z(x0, y1));
      soup.push_back({a, b, c});
      soup.push_back({a, c, d});
    }
  }
  const TriangleMeshShape mesh(soup);
  std::mt19937_64 gen(8);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  for (int k = 0; k < 200; ++k) {
    const V3 x(u(gen), u(gen), 0.5 * u(gen) - 0.1);
    double best = 1e300;
    for (const auto& t : soup) best = std::min(best, (x - closest_on_triangle(x, t[0], t[1], t[2]).point).norm());
    CHECK(mesh.closest(x).distance == Approx(best).margin(1e-14));
    // Every reported contact is a true nearby point; the nearest one is always among them.
    const auto c = contacts(mesh, x, 0.15);
    if (best < 0.15) {
      REQUIRE_FALSE(c.empty());
      double nearest = 1e300;
      for (const auto& s : c) nearest = std::min(nearest, s.distance);
      CHECK(nearest == Approx(best).margin(1e-14));
    } else {
      CHECK(c.empty());
    }
  }
}

TEST_CASE("PosedShape of a cube mesh equals the PrismShape with the same pose", "[geometry][triangle_mesh]") {
  IndexedTriangles centred = cube();
  for (auto& v : centred.vertices) v -= V3::Constant(0.5);
  const Pose<Dim3> pose = pose_3d(0.7, V3(0.3, -1, 0.4), V3(2, 1, -1));
  const PosedShape<TriangleMeshShape> posed(TriangleMeshShape(centred, MeshSides::OneSided), pose);
  const PrismShape<Dim3> prism(pose.translation(), pose.rotation(), V3::Constant(0.5));
  std::mt19937_64 gen(12);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < 300; ++k) {
    const V3 x = pose.translation() + V3(u(gen), u(gen), u(gen));
    const auto a = posed.closest(x);
    const auto b = prism.closest(x);
    CHECK(a.distance == Approx(b.distance).margin(1e-12));
    CHECK((a.point - b.point).norm() < 1e-12);
  }
  const auto box = posed.bounds();
  CHECK(box.contains(pose.to_world(V3::Constant(0.5))));
  CHECK(box.contains(pose.to_world(V3::Constant(-0.5))));
}
