// AabbTree: sphere queries and nearest-item search equal brute force over random boxes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <vector>

#include "granule/boundaries/geometry/aabb_tree.hpp"

using namespace granule;
using namespace granule::geometry;

TEMPLATE_TEST_CASE("AabbTree queries equal brute force", "[geometry][aabb_tree]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  std::mt19937_64 gen(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Aabb<TestType>> boxes;
  std::vector<Vec> centres;
  for (int k = 0; k < 500; ++k) {
    Vec c;
    for (int a = 0; a < TestType::dim; ++a) c[a] = u(gen);
    centres.push_back(c);
    boxes.emplace_back(c - Vec::Constant(0.01), c + Vec::Constant(0.01));
  }
  const AabbTree<TestType> tree(boxes, 3);
  CHECK(tree.size() == 500u);
  for (int q = 0; q < 100; ++q) {
    Vec x;
    for (int a = 0; a < TestType::dim; ++a) x[a] = 1.2 * u(gen) - 0.1;
    std::vector<std::uint32_t> got;
    tree.for_each_near(x, 0.1, [&](std::uint32_t i) { got.push_back(i); });
    std::sort(got.begin(), got.end());
    std::vector<std::uint32_t> want;
    for (std::uint32_t i = 0; i < boxes.size(); ++i) {
      if (boxes[i].squared_distance(x) <= 0.01) want.push_back(i);
    }
    CHECK(got == want);
    // Nearest centre (distance to the centre >= distance to its box).
    const auto [best, d] = tree.nearest(x, [&](std::uint32_t i) { return (centres[i] - x).norm(); });
    std::uint32_t want_best = 0;
    for (std::uint32_t i = 1; i < centres.size(); ++i) {
      if ((centres[i] - x).norm() < (centres[want_best] - x).norm()) want_best = i;
    }
    CHECK(best == want_best);
    CHECK(d == (centres[want_best] - x).norm());
  }
  const AabbTree<TestType> empty;
  CHECK(empty.nearest(Vec::Zero(), [](std::uint32_t) { return 0.0; }).first == 0u);
  int calls = 0;
  empty.for_each_near(Vec::Zero(), 1.0, [&](std::uint32_t) { ++calls; });
  CHECK(calls == 0);
}
