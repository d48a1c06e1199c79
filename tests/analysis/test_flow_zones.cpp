// Tests of granule/analysis/flow_zones.hpp on synthetic fields whose zones and cone are known:
// a source at (x_c, y0) with a mobile zone |x - x_c| <= L/2 + (y - y0) / tan(beta) above it.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "granule/analysis/flow_zones.hpp"

using namespace granule::analysis;

namespace flow_zones_test {

using Vec = granule::Dim2::Vec;

constexpr double kXc = 0.05, kY0 = 0.02, kHalf = 0.005;  // source axis, height, half length [m]

/// Signed horizontal distance of node r outside the cone edge of inclination beta [deg] (negative
/// inside the cone), for rows above the source.
double outside(const Vec& r, double beta_deg) {
  const double widen = (r.y() - kY0) / std::tan(beta_deg * std::numbers::pi / 180.0);
  return std::abs(r.x() - kXc) - (kHalf + widen);
}

/// v* = 1 inside the cone and 0 outside, optionally blurred across the edge by a Gaussian of
/// standard deviation sigma (v* = erfc(dist / (sqrt2 sigma)) / 2); zero below the source.
std::vector<double> cone_field(const RegularGrid<granule::Dim2>& g, double beta_deg, double sigma) {
  std::vector<double> s(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) {
    const Vec r = g.node(k);
    if (r.y() < kY0) continue;
    const double d = outside(r, beta_deg);
    s[k] = sigma > 0.0 ? 0.5 * std::erfc(d / (std::numbers::sqrt2 * sigma)) : (d <= 0.0 ? 1.0 : 0.0);
  }
  return s;
}

}  // namespace flow_zones_test

TEST_CASE("cone_edges recovers the inclination of a sharp and of a blurred cone", "[analysis][flow_zones]") {
  using namespace flow_zones_test;
  // Spacing 1.25 mm: the source's axis x_c = 50 mm is a node, so both sides see the same rows.
  const RegularGrid<granule::Dim2> g(Vec(0.0, 0.0), Vec(0.1, 0.15), 1.25e-3);
  const std::vector<double> phi(g.size(), 0.8);
  ConeWindow w;
  w.x_centre = kXc;
  w.y_from = kY0 + 0.005;
  w.y_to = 0.14;
  for (double beta : {45.0, 60.0, 75.0}) {
    for (double sigma : {0.0, 4.5e-3}) {
      const auto fit = cone_edges(g, cone_field(g, beta, sigma), phi, w);
      INFO("beta " << beta << ", sigma " << sigma);
      // Rows from 25 mm to 140 mm at 1.25 mm; where the edge would lie beyond the grid's side
      // (at 45 deg above y = 20 + 45 mm) the walk leaves the grid without an edge and the row is
      // dropped: at least the 25-63 mm rows remain.
      CHECK(fit.left.rows >= 25);
      CHECK(std::abs(static_cast<double>(fit.right.rows) - static_cast<double>(fit.left.rows)) <= 1.0);
      // A sharp edge is placed 3/4 of the way to the first immobile node, a sawtooth of up to one
      // node across rows; the fit over many rows averages it out to a fraction of a degree.
      CHECK(fit.left.angle == Approx(beta).margin(0.6));
      CHECK(fit.right.angle == Approx(beta).margin(0.6));
      CHECK(fit.angle == Approx(beta).margin(0.4));
      if (sigma > 0.0) {
        // The blurred edge crosses v* = 0.25 at 0.674 sigma outside the sharp one, in every row:
        // the intercept moves by that much, the slope does not.
        const double shift = 0.6745 * sigma;
        const double b = 1.0 / std::tan(beta * std::numbers::pi / 180.0);
        CHECK(fit.right.slope == Approx(b).margin(0.01));
        CHECK(fit.right.intercept - (kXc + kHalf - b * kY0) == Approx(shift).margin(2e-4));
        CHECK(fit.right.rms < 2e-4);
      }
    }
  }
}

TEST_CASE("cone_edges drops rows truncated by the limits and reads a narrowing zone above 90 deg",
          "[analysis][flow_zones]") {
  using namespace flow_zones_test;
  const RegularGrid<granule::Dim2> g(Vec(0.0, 0.0), Vec(0.1, 0.15), 1e-3);
  const std::vector<double> phi(g.size(), 0.8);
  ConeWindow w;
  w.x_centre = kXc;
  w.y_from = kY0 + 0.003;
  w.y_to = 0.14;
  // Walls 5 mm inside the grid's sides: at 60 deg the edge reaches x = 0.095 at
  // y = y0 + 0.04 tan 60 = 89 mm; the rows above are truncated and must not bend the fit.
  w.x_min = 0.005;
  w.x_max = 0.095;
  const auto s = cone_field(g, 60.0, 0.0);
  const auto fit = cone_edges(g, s, phi, w);
  const double y_wall = kY0 + 0.04 * std::tan(std::numbers::pi / 3.0);
  const auto expected_rows = static_cast<double>(std::floor((y_wall - w.y_from) / 1e-3));
  CHECK(static_cast<double>(fit.right.rows) == Approx(expected_rows).margin(1.0));
  CHECK(fit.angle == Approx(60.0).margin(0.5));
  // With one row fewer than min_rows on each side there is no fit.
  ConeWindow few = w;
  few.y_to = w.y_from + 1.5e-3;  // two rows
  const auto none = cone_edges(g, s, phi, few);
  CHECK(none.left.rows == 2);
  CHECK(std::isnan(none.left.angle));
  CHECK(std::isnan(none.angle));
  // A zone that narrows upwards: x half width 20 mm - (y - y0) tan(30 deg).
  std::vector<double> narrow(g.size(), 0.0);
  for (std::size_t k = 0; k < g.size(); ++k) {
    const Vec r = g.node(k);
    if (r.y() >= kY0 && std::abs(r.x() - kXc) <= 0.02 - (r.y() - kY0) * std::tan(std::numbers::pi / 6.0)) narrow[k] = 1.0;
  }
  w.x_min = -1.0;
  w.x_max = 1.0;
  w.y_to = kY0 + 0.03;
  const auto nfit = cone_edges(g, narrow, phi, w);
  CHECK(nfit.angle == Approx(120.0).margin(1.0));
  // An immobile axis gives no edge at all.
  const std::vector<double> still(g.size(), 0.1);
  CHECK(cone_edges(g, still, phi, w).left.rows == 0);
  // Outside the bed (packing below min_packing) nothing counts either.
  const std::vector<double> air(g.size(), 0.1 * 0.8);
  CHECK(cone_edges(g, s, air, w).right.rows == 0);
}

TEST_CASE("flow_zone_areas and wall_mobility count the bed nodes of each zone", "[analysis][flow_zones]") {
  using namespace flow_zones_test;
  // 10 x 8 nodes, spacing 1 cm (cell area 1e-4 m^2). Bed: rows 0-5 (phi 0.8), air above.
  const RegularGrid<granule::Dim2> g(Vec(0.0, 0.0), Vec(0.09, 0.07), 0.01);
  REQUIRE(g.size() == 80);
  std::vector<double> phi(g.size()), s(g.size());
  for (std::size_t k = 0; k < g.size(); ++k) {
    const auto ij = g.coords(k);
    phi[k] = ij.y() <= 5 ? 0.8 : 0.05;
    // Columns 4-5 dragged (v* = 1), 3 and 6 in the cone (0.5), the boundary values 0.25 and 0.75
    // in columns 2 and 7 (cone: the zones are slow <= v* <= fast), the rest still; column 0 is
    // mobile in rows 0-2 only.
    const int i = ij.x();
    s[k] = (i == 4 || i == 5) ? 1.0 : (i == 3 || i == 6) ? 0.5 : i == 2 ? 0.25 : i == 7 ? 0.75 : 0.1;
    if (i == 0 && ij.y() <= 2) s[k] = 0.3;
  }
  const auto a = flow_zone_areas(g, s, phi, 0.0);
  const double cell = 1e-4;
  CHECK(a.bed == Approx(60 * cell));
  CHECK(a.dragged == Approx(12 * cell));
  CHECK(a.cone == Approx((24 + 3) * cell));  // columns 2, 3, 6, 7 and three nodes of column 0
  CHECK(a.immobile == Approx((60 - 12 - 27) * cell));
  CHECK(a.fraction_dragged() == Approx(0.2));
  // Above y = 0.02 (rows 2-5): 4 rows.
  const auto above = flow_zone_areas(g, s, phi, 0.02);
  CHECK(above.bed == Approx(40 * cell));
  CHECK(above.cone == Approx((16 + 1) * cell));
  // Wall bands: x < 0.005 (column 0) and x > 0.085 (column 9), rows >= 1 in the bed: 10 nodes,
  // 2 of them mobile (column 0, rows 1 and 2).
  CHECK(wall_mobility(g, s, phi, 0.01, 0.005, 0.085) == Approx(0.2));
  CHECK(std::isnan(wall_mobility(g, s, phi, 0.065, 0.005, 0.085)));  // no bed node that high
  CHECK_THROWS_AS(flow_zone_areas(g, std::vector<double>(3, 0.0), phi, 0.0), granule::InvalidParameter);
}
