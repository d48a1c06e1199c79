// Random insertion: no overlap among all pairs (new-new and new-existing, checked by brute
// force), every particle inside the region, reproducible for a seed, honest failure counts
// in a crowded region, the accept predicate; StreamSchedule counts (hand-computed, and the
// LIGGGHTS ins/stream example of paper 001 section 2.4: 1e5 particles/s in 0.1 s batches).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "granule/scene/insertion.hpp"
#include "granule/scene/lattice.hpp"
#include "granule/scene/size_distribution.hpp"

using namespace granule;
using namespace granule::scene;
using geometry::Aabb;

TEMPLATE_TEST_CASE("insert_random never overlaps and stays in the region", "[scene][insertion]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  const Aabb<TestType> region(Vec::Zero(), Vec::Constant(0.2));
  // Existing particles: a lattice straddling the region's lower boundary.
  const auto old_x = simple_lattice<TestType>(Aabb<TestType>(Vec::Constant(-0.05), Vec::Constant(0.03)), 0.01, 0.025);
  const std::vector<double> old_r(old_x.size(), 0.01);
  const UniformSizes sizes(0.004, 0.008);
  RandomGenerator rng(17);
  const std::size_t want = TestType::dim == 2 ? 100 : 300;  // area fraction ~30 % in 2D
  const auto res = insert_random<TestType>(region, sizes, rng, want, old_x, old_r);
  REQUIRE(res.count() == want);
  CHECK(res.failed == 0u);
  CHECK(res.radii.size() == want);
  for (std::size_t i = 0; i < res.count(); ++i) {
    const Vec& x = res.positions[i];
    const double r = res.radii[i];
    CHECK(((x.array() - r) >= region.lo.array()).all());
    CHECK(((x.array() + r) <= region.hi.array()).all());
    CHECK(r >= 0.004);
    CHECK(r <= 0.008);
    for (std::size_t j = i + 1; j < res.count(); ++j) CHECK((x - res.positions[j]).norm() >= r + res.radii[j]);
    for (std::size_t j = 0; j < old_x.size(); ++j) CHECK((x - old_x[j]).norm() >= r + old_r[j]);
  }
  // Same seed, same result.
  RandomGenerator again(17);
  const auto res2 = insert_random<TestType>(region, sizes, again, want, old_x, old_r);
  REQUIRE(res2.count() == res.count());
  for (std::size_t i = 0; i < res.count(); ++i) CHECK(res2.positions[i] == res.positions[i]);
}

TEMPLATE_TEST_CASE("insert_random reports failures in a full region", "[scene][insertion]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  // Centres of radius-0.25 particles lie in [0.25, 0.75]^dim and must be 0.51 apart; the 2^dim
  // sub-cubes of side 0.25 have a diagonal < 0.51, so at most 2^dim fit and most of 20 fail.
  const Aabb<TestType> region(Vec::Zero(), Vec::Ones());
  RandomGenerator rng(3);
  InsertionOptions<TestType> opt;
  opt.max_attempts = 200;
  opt.min_gap = 0.01;
  const auto res = insert_random<TestType>(region, MonodisperseSizes(0.25), rng, 20, {}, {}, opt);
  CHECK(res.count() >= 1u);
  CHECK(res.count() <= static_cast<std::size_t>(1 << TestType::dim));
  CHECK(res.count() + res.failed == 20u);
  CHECK(res.attempts <= 20u * 200u);
  for (std::size_t i = 0; i < res.count(); ++i)
    for (std::size_t j = i + 1; j < res.count(); ++j)
      CHECK((res.positions[i] - res.positions[j]).norm() >= 0.5 + 0.01);
}

TEST_CASE("insert_random honours the accept predicate", "[scene][insertion]") {
  using V3 = Dim3::Vec;
  const Aabb<Dim3> region(V3(-1, -1, 0), V3(1, 1, 1));
  InsertionOptions<Dim3> opt;
  opt.accept = [](const V3& x, double r) { return std::hypot(x.x(), x.y()) + r <= 0.5; };  // inside a silo
  RandomGenerator rng(8);
  const auto res = insert_random<Dim3>(region, DiscreteSizes({0.02, 0.04}, {0.5, 0.5}), rng, 200, {}, {}, opt);
  CHECK(res.count() == 200u);
  for (std::size_t i = 0; i < res.count(); ++i) CHECK(std::hypot(res.positions[i].x(), res.positions[i].y()) + res.radii[i] <= 0.5);
  CHECK_THROWS_AS(insert_random<Dim3>(Aabb<Dim3>(V3::Zero(), V3(1, 1, 0.01)), MonodisperseSizes(0.02), rng, 1),
                  InvalidParameter);
  const std::vector<V3> xs(2, V3::Zero());
  const std::vector<double> rs(1, 0.1);
  CHECK_THROWS_AS(insert_random<Dim3>(region, MonodisperseSizes(0.02), rng, 1, xs, rs), InvalidParameter);
}

TEST_CASE("StreamSchedule continuous and batched", "[scene][insertion]") {
  // Paper 001, section 2.4: 1e5 particles/s in batches of one tenth of the rate every 0.1 s.
  const StreamSchedule batched(1e5, 100000, 0.0, StreamMode::Batched, 0.1);
  CHECK(batched.target(-1e-3) == 0u);
  CHECK(batched.target(0.0) == 10000u);
  CHECK(batched.target(0.0999) == 10000u);
  // t accumulated from 1000 steps of 1e-4 s is slightly off 0.1; still the second batch.
  double t = 0.0;
  for (int k = 0; k < 1000; ++k) t += 1e-4;
  CHECK(batched.target(t) == 20000u);
  CHECK(batched.target(0.95) == 100000u);
  CHECK(batched.target(5.0) == 100000u);
  CHECK(batched.end_time() == Approx(0.9));
  CHECK(batched.due(0.25, 12000) == 18000u);
  CHECK(batched.due(0.25, 40000) == 0u);

  const StreamSchedule cont(250.0, 1000, 1.0);
  CHECK(cont.target(1.0) == 0u);
  CHECK(cont.target(1.1) == 25u);
  CHECK(cont.target(4.0) == 750u);
  CHECK(cont.target(100.0) == 1000u);
  CHECK(cont.end_time() == Approx(5.0));
  CHECK(cont.finished(1000));
  CHECK_FALSE(cont.finished(999));
  // Batches with a fractional size: cumulative floor((k + 1) * 2.5).
  const StreamSchedule frac(25.0, 100, 0.0, StreamMode::Batched, 0.1);
  CHECK(frac.target(0.0) == 2u);
  CHECK(frac.target(0.1) == 5u);
  CHECK(frac.target(0.2) == 7u);
  CHECK_THROWS_AS(StreamSchedule(0.0, 10), InvalidParameter);
  CHECK_THROWS_AS(StreamSchedule(1.0, 10, 0.0, StreamMode::Batched, 0.0), InvalidParameter);
}
