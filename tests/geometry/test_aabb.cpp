// Aabb: containment, overlap, growth and point distance (analytic).
#include <catch2/catch.hpp>

#include "granule/boundaries/geometry/aabb.hpp"

using namespace granule;
using namespace granule::geometry;

TEMPLATE_TEST_CASE("Aabb basic operations", "[geometry][aabb]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Aabb<TestType> box = Aabb<TestType>::empty();
  CHECK(box.is_empty());
  box.extend(Vec::Zero());
  box.extend(Vec::Constant(2.0));
  CHECK_FALSE(box.is_empty());
  CHECK(box.is_finite());
  CHECK(box.contains(Vec::Constant(1.0)));
  CHECK_FALSE(box.contains(Vec::Constant(2.5)));
  CHECK(box.centre() == Vec::Constant(1.0));
  // Distance from (3, 3[, 3]) to the corner (2, 2[, 2]) is sqrt(dim).
  CHECK(box.squared_distance(Vec::Constant(3.0)) == Approx(double(TestType::dim)));
  CHECK(box.squared_distance(Vec::Constant(1.0)) == 0.0);
  const Aabb<TestType> other(Vec::Constant(2.5), Vec::Constant(3.0));
  CHECK_FALSE(box.overlaps(other));
  CHECK(box.expanded(0.5).overlaps(other));
  CHECK(Aabb<TestType>::infinite().overlaps(other));
  CHECK_FALSE(Aabb<TestType>::infinite().is_finite());
}
