// The masked assignments of the packed laws (core/lanes.hpp): assign_lanes and what is built on it
// (select, where_assign, blend_assign). Every branch of a packed law is one of these, so a
// blend that silently assigns nothing turns every law off: with libstdc++ 12's stdx::where
// compiled by clang for AVX-512 (2026-12-07) the packed contacts and the 2D rebuild test did
// nothing and disks fell through the floor. Reference: the lane-by-lane definition itself
// (lane l of the result is v[l] where c[l] holds, the old value elsewhere), checked on masks
// with every lane set, none set, and alternating ones. This file also runs in the wide test
// flavours (tests/CMakeLists.txt), including the clang one of `granule.sh test-clang`.
#include <catch2/catch.hpp>

#include <cstddef>

#include "granule/core/lanes.hpp"

using granule::Lane;
using granule::LaneMask;
using granule::LaneVec2;
using granule::LaneVec3;
using granule::lane_width;

namespace {

// Lane l: base + l.
Lane ramp(double base) {
  Lane r = 0.0;
  for (std::size_t l = 0; l < lane_width; ++l) r[l] = base + static_cast<double>(l);
  return r;
}

// The three masks: all lanes, none, and the even ones (a mixed mask: lane 0 set, lane 1 not).
LaneMask mask(int kind) {
  LaneMask m(false);
  for (std::size_t l = 0; l < lane_width; ++l) m[l] = kind == 0 || (kind == 2 && l % 2 == 0);
  return m;
}

void check_blend(const Lane& got, const LaneMask& c, const Lane& v, const Lane& old) {
  for (std::size_t l = 0; l < lane_width; ++l) {
    INFO("lane " << l << " of " << lane_width << ", mask " << c[l]);
    CHECK(static_cast<double>(got[l]) == static_cast<double>(c[l] ? v[l] : old[l]));
  }
}

}  // namespace

TEST_CASE("assign_lanes and select blend exactly the lanes of the mask", "[core][lanes]") {
  const Lane old = ramp(100.0), v = ramp(-5.0);
  for (int kind = 0; kind < 3; ++kind) {
    const LaneMask c = mask(kind);
    Lane t = old;
    granule::assign_lanes(c, t, v);
    check_blend(t, c, v, old);
    check_blend(granule::select(c, v, old), c, v, old);
  }
  // A mask from a comparison, as the laws make them: lanes 0 .. W/2 - 1 of ramp(-W/2) are < 0.
  const Lane x = ramp(-static_cast<double>(lane_width / 2));
  Lane worst = 0.0;
  granule::assign_lanes(x > worst, worst, x);
  for (std::size_t l = 0; l < lane_width; ++l) CHECK(static_cast<double>(worst[l]) == (x[l] > 0.0 ? x[l] : 0.0));
  // The scalar forms are the plain conditional.
  CHECK(granule::select(true, 1.0, 2.0) == 1.0);
  CHECK(granule::select(false, 1.0, 2.0) == 2.0);
}

TEST_CASE("where_assign and blend_assign on packs and packed vectors", "[core][lanes]") {
  for (int kind = 0; kind < 3; ++kind) {
    const LaneMask c = mask(kind);
    INFO("mask kind " << kind);
    Lane a = ramp(10.0), b = ramp(10.0);
    granule::where_assign(c, a, [] { return ramp(-1.0); });
    granule::blend_assign(c, b, [] { return ramp(-1.0); });
    check_blend(a, c, ramp(-1.0), ramp(10.0));
    check_blend(b, c, ramp(-1.0), ramp(10.0));
    LaneVec2 p{ramp(1.0), ramp(2.0)}, q{ramp(1.0), ramp(2.0)};
    granule::where_assign(c, p, [] { return LaneVec2{ramp(-3.0), ramp(-4.0)}; });
    granule::blend_assign(c, q, [] { return LaneVec2{ramp(-3.0), ramp(-4.0)}; });
    for (const LaneVec2* r : {&p, &q}) {
      check_blend(r->x, c, ramp(-3.0), ramp(1.0));
      check_blend(r->y, c, ramp(-4.0), ramp(2.0));
    }
    LaneVec3 s{ramp(1.0), ramp(2.0), ramp(3.0)}, u{ramp(1.0), ramp(2.0), ramp(3.0)};
    granule::where_assign(c, s, [] { return LaneVec3{ramp(-3.0), ramp(-4.0), ramp(-5.0)}; });
    granule::blend_assign(c, u, [] { return LaneVec3{ramp(-3.0), ramp(-4.0), ramp(-5.0)}; });
    for (const LaneVec3* r : {&s, &u}) {
      check_blend(r->x, c, ramp(-3.0), ramp(1.0));
      check_blend(r->y, c, ramp(-4.0), ramp(2.0));
      check_blend(r->z, c, ramp(-5.0), ramp(3.0));
    }
  }
  // where_assign does not evaluate f when no lane is set.
  Lane t = ramp(0.0);
  bool called = false;
  granule::where_assign(mask(1), t, [&] {
    called = true;
    return ramp(1.0);
  });
  CHECK_FALSE(called);
  double x = 1.0;
  granule::where_assign(true, x, [] { return 2.0; });
  CHECK(x == 2.0);
}
