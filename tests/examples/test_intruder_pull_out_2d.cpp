// Regression test of the 2D intruder pull-out scene (examples/intruder_pull_out_2d, paper 002):
// in a tiny bed the pulled intruder is resisted (positive mean drag, of the order of the weight
// of the disk column above it) and the drag fluctuates by loading/rupture events (002 section
// 3.1): its standard deviation is a sizeable fraction of its mean.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "../../examples/intruder_pull_out_2d/scene.hpp"

namespace po = granule::examples::pull_out;

TEST_CASE("rolling conversion reproduces paper 002's rolling law at the mean size", "[examples]") {
  // 002 section 2.3: |M| <= mu d 1e-2 F_n, k_r = d^2 k_n 1e-3; EPSD with R* = d/4 (equal disks).
  const double mu = 0.5, d = 3e-3, kn = 1.92e8;
  const auto c = po::rolling_conversion(mu);
  const double r_star = d / 4.0;
  CHECK(c.mu_r * r_star == Approx(mu * d * 1e-2).epsilon(1e-12));
  CHECK(c.factor * kn * c.mu_r * c.mu_r * r_star * r_star == Approx(d * d * kn * 1e-3).epsilon(1e-12));
}

TEST_CASE("intruder pull-out 2d: positive, fluctuating drag", "[examples]") {
  po::PullParams p;
  p.cell_width = 0.025;
  p.bed_height = 0.025;
  p.pull_velocity = 0.03;
  p.sample_travel = 3e-4;
  p.fill_time = 0.5;
  auto s = po::build(p);
  REQUIRE(s.bed_height > 0.6 * p.bed_height);
  REQUIRE(s.bed_height < 1.4 * p.bed_height);
  // The hopper-like filling (default) packs the interior of the bed at 002's Phi = 0.82 +- 0.02
  // (measured here: 0.832 in one 13 mm x 9 mm interior slab; the whole bed, walls and surface
  // layer included, is looser).
  REQUIRE(s.packing.slabs >= 1);
  CHECK(s.packing.interior > 0.78);
  CHECK(s.packing.interior < 0.87);
  CHECK(s.packing.whole < s.packing.interior);
  // Pull through the lower two thirds of the bed.
  const auto r = po::pull(s, 0.66 * s.bed_height);
  REQUIRE(r.samples.size() > 30);
  // Reference scale: weight of the disk column above the intruder at mid pull, rho phi g h L t
  // (phi = 0.82, 002 section 2.4). The mean drag must be positive and of that order.
  const double h = 0.5 * s.bed_height;
  const double column = p.density * 0.82 * 9.81 * h * p.intruder_length * p.mean_diameter;
  CHECK(r.mean_drag > 0.2 * column);
  CHECK(r.mean_drag < 10.0 * column);
  CHECK(r.std_drag > 0.2 * r.mean_drag);
  // Friction mobilisation is a fraction in [0, 1] in the bulk. In this bed of ~70 disks the
  // layer above the rising intruder is lifted and briefly loses nearly every contact (measured:
  // 0-4 contacts in the whole bed for a few samples near 0.5 h); such a sample has no bulk mu*
  // (NaN by definition in force_network.hpp), so only samples with bulk contacts are checked,
  // and most samples must have them.
  std::size_t with_bulk = 0;
  for (const auto& x : r.samples) {
    if (std::isnan(x.mu_star_bulk)) continue;
    ++with_bulk;
    CHECK(x.mu_star_bulk >= 0.0);
    CHECK(x.mu_star_bulk <= 1.0 + 1e-9);
  }
  CHECK(with_bulk >= (8 * r.samples.size()) / 10);
}
