// Spatial decomposition without MPI (parallel/decomposition.hpp): the rank grid of least cut
// area, balanced cuts by recursive coordinate multisection, owner lookup and the halo test.
// Expected values are worked out by hand in the comments: areas are sums of cut faces, the
// balanced loads follow from counting lattice particles on each side of a cut.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "granule/parallel/decomposition.hpp"
#include "../support/message_of.hpp"

using namespace granule;
using granule::parallel::choose_grid;
using granule::parallel::cut_area;
using granule::parallel::Decomposition;
using granule::parallel::RankGrid;
using granule::test::message_of;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

Domain<Dim3> decomp_box3(double lx, double ly, double lz) {
  Domain<Dim3> b;
  b.lo = Dim3::Vec::Zero();
  b.hi = Dim3::Vec(lx, ly, lz);
  return b;
}

Domain<Dim2> decomp_box2(double lx, double ly) {
  Domain<Dim2> b;
  b.lo = Dim2::Vec::Zero();
  b.hi = Dim2::Vec(lx, ly);
  return b;
}

/// A pour filling a unit box from the bottom: a 10 x 10 lattice of columns, five full layers
/// (z = 0.05 ... 0.45) and a sixth layer (z = 0.55) only over x < 0.5: 500 + 50 = 550 particles.
std::vector<Dim3::Vec> decomp_pour() {
  std::vector<Dim3::Vec> x;
  for (int k = 0; k < 6; ++k)
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j)
        if (k < 5 || i < 5) x.emplace_back((i + 0.5) / 10, (j + 0.5) / 10, (k + 0.5) / 10);
  return x;
}

/// The one inner cut of a two-part axis, after checking the outer bounds are the unit box's.
double decomp_middle_cut(const std::vector<double>& b) {
  REQUIRE(b.size() == 3);
  CHECK(b.front() == 0.0);
  CHECK(b.back() == 1.0);
  return b[1];
}

template <class D>
int decomp_regions_holding(const Decomposition<D>& dec, const typename D::Vec& c) {
  int n = 0;
  typename D::Vec lo, hi;
  for (int r = 0; r < dec.ranks(); ++r) {
    dec.region(r, lo, hi);
    bool in = true;
    for (int k = 0; k < D::dim; ++k) {
      const bool last = hi[k] == dec.box().hi[k];
      in = in && c[k] >= lo[k] && (c[k] < hi[k] || (last && c[k] == hi[k]));
    }
    n += in;
  }
  return n;
}

}  // namespace

TEST_CASE("choose_grid cuts a cube of 8 ranks into 2 x 2 x 2", "[parallel][decomposition]") {
  const auto cube = decomp_box3(1, 1, 1);
  CHECK(choose_grid(cube, 8) == RankGrid{{2, 2, 2}});
  CHECK(cut_area(cube, RankGrid{{2, 2, 2}}) == 3.0);  // one plane across each axis
  CHECK(cut_area(cube, RankGrid{{4, 2, 1}}) == 4.0);  // three planes across x, one across y
  CHECK(choose_grid(cube, 4) == RankGrid{{2, 2, 1}});  // 2 planes; x and y win the tie
  CHECK(choose_grid(cube, 1) == RankGrid{{1, 1, 1}});
  CHECK(choose_grid(cube, 27) == RankGrid{{3, 3, 3}});
}

TEST_CASE("choose_grid gives a long channel slabs along its length", "[parallel][decomposition]") {
  // 20 x 1 x 1: 16 slabs cut 15 unit faces; 8 x 2 x 1 would cut 7 + 20 = 27.
  const auto channel = decomp_box3(20, 1, 1);
  CHECK(choose_grid(channel, 4) == RankGrid{{4, 1, 1}});
  CHECK(choose_grid(channel, 16) == RankGrid{{16, 1, 1}});
  CHECK(cut_area(channel, RankGrid{{16, 1, 1}}) == 15.0);
  CHECK(choose_grid(decomp_box3(1, 20, 1), 4) == RankGrid{{1, 4, 1}});
  // A flat bed 10 x 10 x 1 is cut in x and y, never across its height.
  CHECK(choose_grid(decomp_box3(10, 10, 1), 4) == RankGrid{{2, 2, 1}});
  // With a minimum width of 2 m a 20 m channel holds at most 10 slabs: 16 ranks become 8 x 2
  // only if 2 parts of 1 m fit across y, which they do not, so it is refused.
  CHECK_THROWS_AS(choose_grid(channel, 16, 2.0), InvalidParameter);
  CHECK(choose_grid(channel, 10, 2.0) == RankGrid{{10, 1, 1}});
}

TEST_CASE("choose_grid in 2D", "[parallel][decomposition]") {
  CHECK(choose_grid(decomp_box2(1, 1), 4) == RankGrid{{2, 2, 1}});
  CHECK(choose_grid(decomp_box2(10, 1), 6) == RankGrid{{6, 1, 1}});
  CHECK(choose_grid(decomp_box2(1, 10), 6) == RankGrid{{1, 6, 1}});
  CHECK(cut_area(decomp_box2(10, 1), RankGrid{{6, 1, 1}}) == 5.0);  // five cut lines 1 m long
}

TEST_CASE("choose_grid counts the wrap of a periodic axis as a cut", "[parallel][decomposition]") {
  auto box = decomp_box3(1.5, 1, 1);
  CHECK(choose_grid(box, 2) == RankGrid{{2, 1, 1}});  // one 1 m^2 cut against 1.5 m^2
  box.periodic[0] = true;
  // Split in two, a periodic x has two faces between the ranks (2 m^2): y is cut instead.
  CHECK(cut_area(box, RankGrid{{2, 1, 1}}) == 2.0);
  CHECK(cut_area(box, RankGrid{{1, 2, 1}}) == 1.5);
  CHECK(choose_grid(box, 2) == RankGrid{{1, 2, 1}});
  // Unsplit, the periodic axis costs nothing: its images stay on the rank.
  CHECK(cut_area(box, RankGrid{{1, 1, 1}}) == 0.0);
}

TEST_CASE("Multisection balances a pour that fills the box from the bottom", "[parallel][decomposition]") {
  const auto box = decomp_box3(1, 1, 1);
  const auto x = decomp_pour();
  REQUIRE(x.size() == 550);

  SECTION("two ranks one above the other") {
    const RankGrid grid{{1, 1, 2}};
    // Uniform cuts: 500 below z = 0.5, 50 above; imbalance 500 / 275 = 20/11.
    const auto uniform = Decomposition<Dim3>(box, grid).load(x);
    CHECK(uniform.per_rank == std::vector<double>{500, 50});
    CHECK(uniform.imbalance() == Approx(20.0 / 11.0).epsilon(1e-15));
    CHECK(uniform.needs_rebalance(1.1));
    // Balanced: the target 275 lies between 200 and 300 below the layers' gaps; 300 is nearer,
    // so the cut is midway between z = 0.25 and 0.35, and the loads 300 and 250: 12/11.
    const auto dec = Decomposition<Dim3>::balanced(box, grid, x);
    CHECK(decomp_middle_cut(dec.cuts(2)) == Approx(0.3).epsilon(1e-15));
    const auto load = dec.load(x);
    CHECK(load.per_rank == std::vector<double>{300, 250});
    CHECK(load.imbalance() == Approx(12.0 / 11.0).epsilon(1e-15));
    CHECK_FALSE(load.needs_rebalance(1.1));
    CHECK(load.needs_rebalance(1.05));
  }

  SECTION("2 x 1 x 2: the z cuts of each x slab are its own") {
    // x slabs of 10 columns hold 60 (x < 0.5, with the top layer) or 50 particles: the target
    // 275 is nearest to 300 (after five slabs), so x is cut at 0.5: 300 left, 250 right.
    // Left: six layers of 50, target 150 met exactly at z = 0.3. Right: five layers of 50,
    // target 125 between 100 and 150, equally near: the lower gap, z = 0.2, gives 100 | 150.
    const auto dec = Decomposition<Dim3>::balanced(box, RankGrid{{2, 1, 2}}, x);
    CHECK(decomp_middle_cut(dec.cuts(0)) == Approx(0.5).epsilon(1e-15));
    CHECK(decomp_middle_cut(dec.cuts(2, 0)) == Approx(0.3).epsilon(1e-15));
    CHECK(decomp_middle_cut(dec.cuts(2, 1)) == Approx(0.2).epsilon(1e-15));
    const auto load = dec.load(x);
    CHECK(load.per_rank == std::vector<double>{150, 150, 100, 150});
    CHECK(load.imbalance() == Approx(150.0 / 137.5).epsilon(1e-15));
  }

  SECTION("measured cost as weights") {
    // Four particles along x with costs 1, 1, 1, 3: half the total (3) lies below x = 0.35.
    const std::vector<Dim3::Vec> y{{0.1, 0.5, 0.5}, {0.2, 0.5, 0.5}, {0.3, 0.5, 0.5}, {0.4, 0.5, 0.5}};
    const std::vector<double> cost{1, 1, 1, 3};
    const auto dec = Decomposition<Dim3>::balanced(box, RankGrid{{2, 1, 1}}, y, cost);
    CHECK(dec.cuts(0)[1] == Approx(0.35).epsilon(1e-15));
    CHECK(dec.load(y, cost).per_rank == std::vector<double>{3, 3});
    CHECK(dec.load(y, cost).imbalance() == 1.0);
  }

  SECTION("parts keep the minimum width") {
    // All weight at z < 0.1: balance would put the cut near 0.05, but parts must be 0.4 wide.
    const std::vector<Dim3::Vec> low{{0.5, 0.5, 0.01}, {0.5, 0.5, 0.02}, {0.5, 0.5, 0.03}, {0.5, 0.5, 0.04}};
    const auto dec = Decomposition<Dim3>::balanced(box, RankGrid{{1, 1, 2}}, low, {}, 0.4);
    CHECK(dec.cuts(2)[1] == Approx(0.4).epsilon(1e-15));
  }
}

TEST_CASE("Every point has exactly one owner, whose region holds it", "[parallel][decomposition]") {
  auto box = decomp_box3(2, 1, 1);
  box.periodic[0] = true;
  std::mt19937 rng(28);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Dim3::Vec> x(2000);
  for (auto& p : x) p = Dim3::Vec(2 * u(rng) * u(rng), u(rng), u(rng) * u(rng));  // skewed
  const auto dec = Decomposition<Dim3>::balanced(box, RankGrid{{3, 2, 2}}, x);
  // The regions tile the box.
  double volume = 0.0;
  Dim3::Vec lo, hi;
  for (int r = 0; r < dec.ranks(); ++r) {
    dec.region(r, lo, hi);
    volume += (hi - lo).prod();
  }
  CHECK(volume == Approx(2.0).epsilon(1e-12));
  // Each particle, each cut position and each box corner: one owner, the region holding it.
  std::vector<Dim3::Vec> probes = x;
  for (double cx : dec.cuts(0)) probes.emplace_back(cx, 0.5, 0.5);
  for (double cz : dec.cuts(2, 3)) probes.emplace_back(dec.cuts(0)[2] - 1e-9, dec.cuts(1, 1)[1], cz);
  probes.emplace_back(0, 0, 0);
  probes.emplace_back(2, 1, 1);
  int bad = 0;
  for (const auto& p : probes) {
    const Dim3::Vec c = dec.wrapped(p);
    const int r = dec.owner(p);
    dec.region(r, lo, hi);
    const bool holds = (c.array() >= lo.array()).all() && (c.array() <= hi.array()).all();
    if (!holds || decomp_regions_holding(dec, c) != 1) ++bad;
  }
  CHECK(bad == 0);
  // A point on a cut belongs to the upper part; a periodic image has the same owner.
  const double c1 = dec.cuts(0)[1];
  CHECK(dec.coordinates(dec.owner(Dim3::Vec(c1, 0.5, 0.5)))[0] == 1);
  CHECK(dec.owner(Dim3::Vec(0.3 + 2.0, 0.4, 0.6)) == dec.owner(Dim3::Vec(0.3, 0.4, 0.6)));
  CHECK(dec.owner(Dim3::Vec(0.3 - 4.0, 0.4, 0.6)) == dec.owner(Dim3::Vec(0.3, 0.4, 0.6)));
  // The loads add up to the particle count.
  CHECK(dec.load(x).total() == 2000.0);
}

TEST_CASE("Ghost ranks near edges and corners are those within the halo width", "[parallel][decomposition]") {
  const Decomposition<Dim3> dec(decomp_box3(1, 1, 1), RankGrid{{2, 2, 2}});
  // Ranks: (ix * 2 + iy) * 2 + iz. Near the centre every other rank is within 0.1:
  // the farthest, rank 7, at sqrt(3) * 0.05 = 0.087.
  CHECK_THAT(dec.ghost_ranks(Dim3::Vec(0.45, 0.45, 0.45), 0.1), Equals(std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
  // Near the x and y cuts, 0.3 below the z cut: ranks 2 (y), 4 (x) and 6 (across the edge,
  // sqrt(2) * 0.05 = 0.071 away); with a halo of 0.06 the edge rank drops out (Euclidean, not a box).
  CHECK_THAT(dec.ghost_ranks(Dim3::Vec(0.45, 0.45, 0.2), 0.1), Equals(std::vector<int>{2, 4, 6}));
  CHECK_THAT(dec.ghost_ranks(Dim3::Vec(0.45, 0.45, 0.2), 0.06), Equals(std::vector<int>{2, 4}));
  CHECK(dec.ghost_ranks(Dim3::Vec(0.2, 0.2, 0.2), 0.1).empty());
  // Without periodic axes no shift is ever non-zero.
  for (const auto& t : dec.halo_targets(Dim3::Vec(0.45, 0.45, 0.45), 0.1)) CHECK(t.shift.isZero());
}

TEST_CASE("Ghost ranks across periodic boundaries", "[parallel][decomposition]") {
  auto box = decomp_box3(1, 1, 1);
  box.periodic[0] = true;
  box.periodic[1] = true;
  const Decomposition<Dim3> dec(box, RankGrid{{4, 1, 1}});
  // x = 0.02 on rank 0 is 0.02 from rank 3's region through the wrap: image +1 along x. Along
  // the periodic y, which rank 0 spans alone, y = 0.97 needs its own image at y - 1.
  const auto t = dec.halo_targets(Dim3::Vec(0.02, 0.97, 0.5), 0.1);
  const auto has = [&](int rank, int sx, int sy) {
    return std::count_if(t.begin(), t.end(), [&](const auto& h) {
      return h.rank == rank && h.shift == Eigen::Vector3i(sx, sy, 0);
    });
  };
  CHECK(has(3, 1, 0) == 1);
  CHECK(has(0, 0, -1) == 1);  // the owner's own image (the existing periodic ghost)
  CHECK(has(3, 1, -1) == 1);  // across the corner of both wraps
  CHECK(t.size() == 3);
  CHECK_THAT(dec.ghost_ranks(Dim3::Vec(0.02, 0.97, 0.5), 0.1), Equals(std::vector<int>{3}));
  CHECK_THAT(dec.ghost_ranks(Dim3::Vec(0.98, 0.5, 0.5), 0.1), Equals(std::vector<int>{0}));
  CHECK(dec.halo_targets(Dim3::Vec(0.98, 0.5, 0.5), 0.1)[0].shift == Eigen::Vector3i(-1, 0, 0));
  // A point on a cut belongs to the upper rank and is a ghost of the lower one.
  CHECK(dec.owner(Dim3::Vec(0.5, 0.5, 0.5)) == 2);
  CHECK_THAT(dec.ghost_ranks(Dim3::Vec(0.5, 0.5, 0.5), 0.1), Equals(std::vector<int>{1}));

  SECTION("2D, both axes periodic, a corner") {
    Domain<Dim2> sq = decomp_box2(1, 1);
    sq.periodic = Domain<Dim2>::Flags::Constant(true);
    const Decomposition<Dim2> d2(sq, RankGrid{{2, 2, 1}});
    const auto t2 = d2.halo_targets(Dim2::Vec(0.01, 0.01), 0.05);
    CHECK_THAT(d2.ghost_ranks(Dim2::Vec(0.01, 0.01), 0.05), Equals(std::vector<int>{1, 2, 3}));
    CHECK(t2.size() == 3);
    for (const auto& h : t2) {
      const Eigen::Vector2i expected(h.rank >= 2 ? 1 : 0, h.rank % 2 == 1 ? 1 : 0);
      CHECK(h.shift == expected);
    }
  }
}

TEMPLATE_TEST_CASE("Every partner within the halo width finds a ghost copy on its rank", "[parallel][decomposition]",
                   Dim2, Dim3) {
  // For random pairs p, q closer than w (minimum image), the rank that owns q must hold p
  // itself (same rank, no wrap between them) or a ghost copy p + shift * L closer than w to q.
  // Balanced cuts on skewed points, periodic along x and y, not along z.
  using D = TestType;
  using Vec = typename D::Vec;
  Domain<D> box;
  box.lo = Vec::Zero();
  box.hi = Vec::Ones();
  box.hi[0] = 3.0;
  box.periodic[0] = true;
  box.periodic[1] = true;
  const double w = 0.15;
  std::mt19937 rng(2028);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto point = [&] {
    Vec p;
    for (int k = 0; k < D::dim; ++k) p[k] = box.lo[k] + (box.hi[k] - box.lo[k]) * u(rng) * u(rng);
    return p;
  };
  std::vector<Vec> x(1500);
  for (auto& p : x) p = point();
  const RankGrid grid = D::dim == 2 ? RankGrid{{3, 2, 1}} : RankGrid{{3, 2, 2}};
  const auto dec = Decomposition<D>::balanced(box, grid, x, {}, w);
  const Vec L = box.length();
  int missing = 0, pairs = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Vec p = dec.wrapped(point());
    Vec d;
    do {
      for (int k = 0; k < D::dim; ++k) d[k] = w * (2 * u(rng) - 1);
    } while (d.norm() >= w);
    Vec q = p + d;
    if (!box.periodic[D::dim - 1] && (q[D::dim - 1] < 0.0 || q[D::dim - 1] > 1.0)) continue;  // outside z
    q = dec.wrapped(q);
    ++pairs;
    const int rq = dec.owner(q);
    bool found = rq == dec.owner(p) && (p - q).norm() < w;
    for (const auto& t : dec.halo_targets(p, w)) {
      const Vec ghost = p + (t.shift.template cast<double>().array() * L.array()).matrix();
      if (t.rank == rq && (ghost - q).norm() < w) found = true;
    }
    missing += !found;
  }
  CHECK(pairs > 3000);
  CHECK(missing == 0);
}

TEST_CASE("Decomposition refuses bad input with named errors", "[parallel][decomposition]") {
  const auto cube = decomp_box3(1, 1, 1);
  CHECK_THAT(message_of<InvalidParameter>([&] { choose_grid(cube, 0); }),
             Equals("Decomposition: ranks = 0 is outside the valid range [1, inf)"));
  CHECK_THAT(message_of<InvalidParameter>([&] { choose_grid(decomp_box3(1, 0, 1), 2); }),
             Equals("Decomposition: box length along y = 0 is outside the valid range (0, inf)"));
  CHECK_THAT(message_of<InvalidParameter>([&] { choose_grid(decomp_box3(1, -2, 1), 2); }),
             Contains("box length along y = -2"));
  // 64 ranks need 4 parts along some axis, but 0.3 m wide parts fit only 3 times into 1 m.
  CHECK_THAT(message_of<InvalidParameter>([&] { choose_grid(cube, 64, 0.3); }),
             Equals("Decomposition: ranks = 64 cannot be arranged as a grid of parts at least 0.29999999999999999 "
                    "m wide (at most x 3, y 3, z 3 parts along the axes)"));
  CHECK_THAT(message_of<InvalidParameter>([&] { Decomposition<Dim3>(cube, RankGrid{{4, 1, 1}}, 0.3); }),
             Contains("4 parts along x cannot each be min_width"));
  const std::vector<Dim3::Vec> x{{0.1, 0.1, 0.1}, {0.2, 0.2, 0.2}};
  CHECK_THAT(message_of<InvalidParameter>(
                 [&] { Decomposition<Dim3>::balanced(cube, RankGrid{{2, 1, 1}}, x, {1.0, std::nan("")}); }),
             Equals("Decomposition: weight[1] = nan is outside the valid range [0, inf)"));
  CHECK_THAT(message_of<InvalidParameter>(
                 [&] { Decomposition<Dim3>::balanced(cube, RankGrid{{2, 1, 1}}, x, {-1.0, 1.0}); }),
             Contains("weight[0] = -1"));
  CHECK_THAT(message_of<InvalidParameter>([&] { Decomposition<Dim3>::balanced(cube, RankGrid{{2, 1, 1}}, x, {1.0}); }),
             Contains("number of weights = 1"));
  CHECK_THAT(message_of<InvalidParameter>([&] { parallel::Load{{1.0, 2.0}}.needs_rebalance(0.5); }),
             Contains("rebalance threshold = 0.5"));
  auto periodic = cube;
  periodic.periodic[2] = true;
  CHECK_THAT(message_of<InvalidParameter>(
                 [&] { Decomposition<Dim3>(periodic, RankGrid{{1, 1, 2}}).halo_targets(x[0], 1.0); }),
             Contains("halo width = 1"));
}
