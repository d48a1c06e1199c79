// Display tessellations: every vertex lies on the exact surface (closest().distance == 0),
// closed surfaces are watertight and outward oriented, and the enclosed volume / area
// matches the faceted solid exactly (prism of a regular N-gon: N/2 R^2 sin(2 pi/N) * 2H) or
// the smooth solid approximately (capsule, stadium).
#include <catch2/catch.hpp>

#include <map>
#include <numbers>

#include "granule/boundaries/geometry/display_mesh.hpp"

using namespace granule;
using namespace granule::geometry;
using V3 = Eigen::Vector3d;
using V2 = Eigen::Vector2d;

namespace {

double enclosed_volume(const DisplayMesh& m) {  // divergence theorem, outward winding > 0
  double v = 0.0;
  for (const auto& t : m.triangles) v += m.points[t[0]].dot(m.points[t[1]].cross(m.points[t[2]])) / 6.0;
  return v;
}

bool watertight(const DisplayMesh& m) {  // every directed edge has its reverse exactly once
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [e, count] : directed) {
    if (count != 1) return false;
    const auto it = directed.find({e.second, e.first});
    if (it == directed.end() || it->second != 1) return false;
  }
  return true;
}

double outline_area(const DisplayMesh& m) {  // shoelace over the line loop
  double a = 0.0;
  for (const auto& l : m.lines) {
    const V3& p = m.points[l[0]];
    const V3& q = m.points[l[1]];
    a += 0.5 * (p.x() * q.y() - q.x() * p.y());
  }
  return a;
}

template <class S>
void check_on_surface(const S& shape, const DisplayMesh& m) {
  for (const V3& p : m.points) {
    typename S::Dimension::Vec x;
    for (int k = 0; k < S::Dimension::dim; ++k) x[k] = p[k];
    CHECK(std::abs(shape.closest(x).distance) < 1e-12);
  }
}

}  // namespace

TEST_CASE("tessellate 3D solids: on the surface, closed, exact faceted volume", "[geometry][display_mesh]") {
  const CylinderShape cyl(V3(0.1, 0.2, 0.3), V3(1, 2, 2), 0.5, 0.75);
  const int n = 16;
  const DisplayMesh c = tessellate(cyl, n);
  CHECK(c.points.size() == 2u + 2u * n);
  CHECK(c.triangles.size() == 4u * n);
  check_on_surface(cyl, c);
  CHECK(watertight(c));
  CHECK(enclosed_volume(c) == Approx(n / 2.0 * 0.25 * std::sin(2 * std::numbers::pi / n) * 1.5).epsilon(1e-12));

  const BoxShape<Dim3> box(V3(-1, 0, 0), V3(1, 2, 0.5));
  const DisplayMesh b = tessellate(box);
  check_on_surface(box, b);
  CHECK(watertight(b));
  CHECK(enclosed_volume(b) == Approx(2.0).epsilon(1e-14));

  const PrismShape<Dim3> prism(V3(1, 1, 1), Eigen::AngleAxisd(0.4, V3(1, 1, 0).normalized()).toRotationMatrix(),
                               V3(0.1, 0.2, 0.3));
  const DisplayMesh p = tessellate(prism);
  check_on_surface(prism, p);
  CHECK(enclosed_volume(p) == Approx(8 * 0.1 * 0.2 * 0.3).epsilon(1e-12));

  const CapsuleShape<Dim3> cap(V3(0, 0, 0), V3(0.3, 0.4, 0), 0.2);
  const DisplayMesh k = tessellate(cap, 48);
  check_on_surface(cap, k);
  CHECK(watertight(k));
  const double exact = std::numbers::pi * 0.04 * 0.5 + 4.0 / 3.0 * std::numbers::pi * 0.008;
  CHECK(enclosed_volume(k) == Approx(exact).epsilon(0.02));
  CHECK(enclosed_volume(k) < exact);  // inscribed facets

  const PlaneShape<Dim3> plane(V3(0, 0, 1), V3(0, 1, 1));
  const DisplayMesh q = tessellate(plane, 2.0);
  check_on_surface(plane, q);
  const V3 tri_n = (q.points[1] - q.points[0]).cross(q.points[2] - q.points[0]).normalized();
  CHECK((tri_n - plane.normal()).norm() < 1e-12);
  CHECK_THROWS_AS(tessellate(cyl, 2), InvalidParameter);
}

TEST_CASE("tessellate 2D shapes as closed outlines", "[geometry][display_mesh]") {
  const SpheroLineShape w(V2(0, 0), V2(1, 0.5), 0.1);
  const DisplayMesh s = tessellate(w, 64);
  check_on_surface(w, s);
  CHECK(outline_area(s) == Approx(std::numbers::pi * 0.01 + 0.2 * std::sqrt(1.25)).epsilon(0.01));
  for (const V3& p : s.points) CHECK(p.z() == 0.0);

  const BoxShape<Dim2> box(V2(0, 0), V2(2, 1));
  const DisplayMesh b = tessellate(box);
  CHECK(b.lines.size() == 4u);
  CHECK(outline_area(b) == Approx(2.0));

  const PosedShape<CapsuleShape<Dim2>> posed(CapsuleShape<Dim2>(V2(0, 0), V2(1, 0), 0.2), pose_2d(0.3, V2(1, 1)));
  const DisplayMesh c = tessellate(posed, 32);
  check_on_surface(posed, c);

  const PlaneShape<Dim2> line(V2(0, 1), V2(0, 1));
  const DisplayMesh l = tessellate(line, 3.0);
  CHECK(l.lines.size() == 1u);
  CHECK((l.points[0] - l.points[1]).norm() == Approx(6.0));
}

TEST_CASE("tessellate a posed triangle mesh", "[geometry][display_mesh]") {
  const std::vector<TriangleCorners> tri = {{V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0)}};
  const Pose<Dim3> pose = pose_3d(0.5, V3(0, 0, 1), V3(0, 0, 2));
  const PosedShape<TriangleMeshShape> mesh(TriangleMeshShape(tri), pose);
  const DisplayMesh m = tessellate(mesh);
  REQUIRE(m.triangles.size() == 1u);
  check_on_surface(mesh, m);
  CHECK(m.points[0].z() == Approx(2.0));
  DisplayMesh both = m;
  both.append(m);
  CHECK(both.points.size() == 6u);
  CHECK(both.triangles[1][0] == 3u);
}
