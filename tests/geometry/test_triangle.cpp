// closest_on_triangle: each Voronoi region of Ericson (2005) 5.1.5 with a hand-computed
// answer, and agreement with a brute-force barycentric sampling for random points.
#include <catch2/catch.hpp>

#include <random>

#include "granule/boundaries/geometry/triangle.hpp"

using namespace granule::geometry;
using V3 = Eigen::Vector3d;

namespace {
void check(const TrianglePoint& tp, TriangleFeature f, int index, const V3& point) {
  CHECK(tp.feature == f);
  CHECK(tp.index == index);
  CHECK((tp.point - point).norm() < 1e-15);
}
}  // namespace

TEST_CASE("closest_on_triangle Voronoi regions", "[geometry][triangle]") {
  const V3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  check(closest_on_triangle(V3(0.2, 0.2, 1), a, b, c), TriangleFeature::Face, 0, V3(0.2, 0.2, 0));
  check(closest_on_triangle(V3(0.2, 0.2, -3), a, b, c), TriangleFeature::Face, 0, V3(0.2, 0.2, 0));
  check(closest_on_triangle(V3(-1, -1, 0.5), a, b, c), TriangleFeature::Vertex, 0, a);
  check(closest_on_triangle(V3(2, -0.5, 0), a, b, c), TriangleFeature::Vertex, 1, b);
  check(closest_on_triangle(V3(-0.5, 2, 0.1), a, b, c), TriangleFeature::Vertex, 2, c);
  check(closest_on_triangle(V3(0.5, -1, 0.3), a, b, c), TriangleFeature::Edge, 0, V3(0.5, 0, 0));
  check(closest_on_triangle(V3(1, 1, 0.7), a, b, c), TriangleFeature::Edge, 1, V3(0.5, 0.5, 0));
  check(closest_on_triangle(V3(-1, 0.5, -0.2), a, b, c), TriangleFeature::Edge, 2, V3(0, 0.5, 0));
}

TEST_CASE("closest_on_triangle agrees with brute-force sampling", "[geometry][triangle]") {
  std::mt19937_64 gen(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const V3 a(u(gen), u(gen), u(gen)), b(u(gen), u(gen), u(gen)), c(u(gen), u(gen), u(gen));
    const V3 p(2 * u(gen), 2 * u(gen), 2 * u(gen));
    const TrianglePoint tp = closest_on_triangle(p, a, b, c);
    double best = 1e300;
    const int n = 300;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        const V3 q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        best = std::min(best, (p - q).norm());
      }
    }
    const double d = (p - tp.point).norm();
    CHECK(d <= best + 1e-12);
    CHECK(d >= best - 2.0 * ((b - a).norm() + (c - a).norm()) / n);
  }
}
