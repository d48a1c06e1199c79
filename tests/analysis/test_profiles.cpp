// Tests of granule/analysis/profiles.hpp on hand-made particle sets (means and standard
// deviations computed by hand in the comments).
#include <catch2/catch.hpp>

#include <cmath>

#include "frame_builders.hpp"
#include "granule/analysis/profiles.hpp"

using granule::Dim2;
using granule::Dim3;
using namespace granule::analysis;

TEMPLATE_TEST_CASE("binned velocity profile: number and mass averages", "[analysis][profiles]",
                   Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  Frame<D> f;
  // Profile along axis 1 over [0, 4) mm in 2 bins of 2 mm; region [0, 1] mm on the other axes.
  auto put = [&](double y, double vy, double r, bool inside = true) {
    Vec x = Vec::Constant(0.5e-3);
    if (!inside) x[0] = 5e-3;
    x[1] = y;
    Vec v = Vec::Zero();
    v[1] = vy;
    granule::test::add_particle<D>(f, x, v, r, 1000.0);
  };
  put(0.5e-3, 1.0, 1e-4);
  put(1.5e-3, 3.0, 2e-4);   // mass 8× (3D) or 4× (2D) the first
  put(2.5e-3, -2.0, 1e-4);
  put(1.0e-3, 100.0, 1e-4, false);  // outside the region: ignored
  Vec lo = Vec::Zero();
  Vec hi = Vec::Constant(1e-3);
  hi[1] = 4e-3;
  const Profile p = velocity_profile(f, lo, hi, 1, 2, 1);
  REQUIRE(p.bins() == 2);
  CHECK(p.centre[0] == Approx(1e-3));
  CHECK(p.count[0] == 2);
  CHECK(p.count[1] == 1);
  // Bin 0: values 1 and 3 → mean 2, population stddev 1. Bin 1: −2, stddev 0.
  CHECK(p.mean[0] == Approx(2.0).epsilon(1e-15));
  CHECK(p.stddev[0] == Approx(1.0).epsilon(1e-15));
  CHECK(p.mean[1] == Approx(-2.0).epsilon(1e-15));
  CHECK(p.stddev[1] == 0.0);
  // Mass weights: m2 = k m1 with k = 2^D → mean (1 + 3k)/(1 + k), variance k (3 − 1)²/(1 + k)².
  const double k = std::pow(2.0, D::dim);
  const Profile pm = velocity_profile(f, lo, hi, 1, 2, 1, ProfileWeight::Mass);
  CHECK(pm.mean[0] == Approx((1.0 + 3.0 * k) / (1.0 + k)).epsilon(1e-14));
  CHECK(pm.stddev[0] == Approx(2.0 * std::sqrt(k) / (1.0 + k)).epsilon(1e-14));
  // Any quantity: radius profile with an empty bin.
  const Profile pr = binned_profile(f, lo, hi, 1, 4, [&](std::size_t i) { return f.radius[i]; });
  CHECK(pr.count[3] == 0);
  CHECK(std::isnan(pr.mean[3]));
  CHECK(pr.mean[0] == Approx(1e-4));
  CHECK_THROWS_AS(velocity_profile(f, lo, hi, D::dim, 2, 1), granule::InvalidParameter);
  CHECK_THROWS_AS(velocity_profile(f, hi, lo, 1, 2, 1), granule::InvalidParameter);
}
