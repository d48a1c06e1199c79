// Tests of granule/analysis/regular_grid.hpp and bin_grid.hpp: node layout, flat indices,
// frame-covering grids with exactly tiled periodic axes, bin lookup.
#include <catch2/catch.hpp>

#include "frame_builders.hpp"
#include "granule/analysis/bin_grid.hpp"
#include "granule/analysis/regular_grid.hpp"

using granule::Dim2;
using granule::Dim3;
using namespace granule::analysis;

TEMPLATE_TEST_CASE("regular grid layout and indices", "[analysis][regular_grid]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  // lo = 0, hi = 1, h = 0.1: 11 nodes per axis, the last one at 1 despite round-off in 1/0.1.
  const RegularGrid<D> g(Vec::Zero(), Vec::Ones(), 0.1);
  CHECK(g.count()[0] == 11);
  CHECK(g.size() == static_cast<std::size_t>(std::pow(11, D::dim)));
  CHECK(g.hi()[0] == Approx(1.0));
  CHECK(g.cell_volume() == Approx(std::pow(0.1, D::dim)));
  for (std::size_t t : {std::size_t{0}, std::size_t{17}, g.size() - 1}) CHECK(g.index(g.coords(t)) == t);
  typename D::IVec k = D::IVec::Ones();
  k[0] = 3;
  CHECK(g.node(k)[0] == Approx(0.3));
  CHECK(g.node(g.index(k))[1] == Approx(0.1));
  std::vector<double> ones(g.size(), 2.0);
  CHECK(integrate(g, ones) == Approx(2.0 * g.size() * g.cell_volume()));
}

TEMPLATE_TEST_CASE("grid covering a frame tiles periodic axes exactly", "[analysis][regular_grid]",
                   Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  auto f = granule::test::random_frame<D>(50, Vec::Zero(), Vec::Constant(1e-2), 1e-4, 1000.0);
  f.periodic[0] = true;
  const auto g = RegularGrid<D>::covering(f, 3e-4, 1e-3);
  // Periodic x: round(10 mm / 0.3 mm) = 33 nodes of 10/33 mm, starting at box_lo.
  CHECK(g.periodic()[0]);
  CHECK(g.count()[0] == 33);
  CHECK(g.spacing()[0] == Approx(1e-2 / 33).epsilon(1e-14));
  CHECK(g.period(0) == Approx(1e-2).epsilon(1e-14));
  CHECK(g.lo()[0] == 0.0);
  // Other axes: particle extent ± margin, spacing as asked.
  CHECK_FALSE(g.periodic()[1]);
  CHECK(g.spacing()[1] == 3e-4);
  double ymin = 1.0;
  double ymax = -1.0;
  for (const auto& x : f.x) {
    ymin = std::min(ymin, x[1]);
    ymax = std::max(ymax, x[1]);
  }
  CHECK(g.lo()[1] == Approx(ymin - 1e-3));
  CHECK(g.hi()[1] >= ymax + 1e-3 - 3e-4);
}

TEMPLATE_TEST_CASE("bin grid lookup", "[analysis][regular_grid]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  const BinGrid<D> b(Vec::Zero(), Vec::Constant(2.0), D::IVec::Constant(4));
  CHECK(b.width()[0] == 0.5);
  CHECK(b.bin_measure() == Approx(std::pow(0.5, D::dim)));
  const auto k = b.locate(Vec::Constant(0.74));
  REQUIRE(k.has_value());
  CHECK((*k)[0] == 1);
  CHECK(b.locate(Vec::Constant(2.0)).value()[0] == 3);  // closed at hi
  CHECK_FALSE(b.locate(Vec::Constant(-0.1)).has_value());
  CHECK(b.centre(*k)[0] == Approx(0.75));
  CHECK(b.coords(b.index(*k)) == *k);
  CHECK_THROWS_AS(BinGrid<D>(Vec::Zero(), Vec::Zero(), D::IVec::Ones()), granule::InvalidParameter);
}
