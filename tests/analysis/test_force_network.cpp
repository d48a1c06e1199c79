// Tests of granule/analysis/histogram.hpp and force_network.hpp on hand-made contact sets whose
// statistics are computed by hand in the comments (definitions: paper 000 section V, paper 002
// section 4, Thornton 2000 eq. 1).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "frame_builders.hpp"
#include "granule/analysis/force_network.hpp"

using granule::Dim2;
using granule::Dim3;
using namespace granule::analysis;

namespace {

template <class D>
ContactRecord<D> make_contact(std::uint32_t i, std::uint32_t j, double fn, double ft, double mu,
                              std::uint32_t wall = 0) {
  using Vec = typename D::Vec;
  ContactRecord<D> c;
  c.i = i;
  c.j = j;
  c.wall = wall;
  c.normal = Vec::Zero();
  c.normal[0] = 1.0;
  c.branch = -1e-3 * c.normal;
  c.fn = fn;
  c.ft = Vec::Zero();
  c.ft[1] = ft;
  c.mu = mu;
  return c;
}

template <class D>
Frame<D> particles(int n) {
  Frame<D> f;
  for (int i = 0; i < n; ++i)
    granule::test::add_particle<D>(f, D::Vec::Constant(2e-3 * i), D::Vec::Zero(), 0.5e-3, 2500.0);
  return f;
}

}  // namespace

TEST_CASE("histogram is a probability density and counts what falls outside",
          "[analysis][force_network]") {
  const auto e = uniform_edges(0.0, 2.0, 4);  // bins of width 0.5
  const Histogram h = make_histogram({0.1, 0.2, 0.6, 1.9, 2.0, -1.0, 3.0,
                                      std::numeric_limits<double>::quiet_NaN()},
                                     e);
  REQUIRE(h.bins() == 4);
  CHECK(h.samples == 8);
  CHECK(h.below == 1);
  CHECK(h.above == 1);
  CHECK(h.non_finite == 1);
  CHECK(h.counts[0] == 2);
  CHECK(h.counts[1] == 1);
  CHECK(h.counts[3] == 2);  // 2.0 sits on the closed right edge of the last bin
  CHECK(h.density[0] == Approx(2.0 / (8 * 0.5)).epsilon(1e-15));
  CHECK(h.integral() == Approx(5.0 / 8.0).epsilon(1e-15));
  CHECK(h.centre(1) == Approx(0.75));
  CHECK_THROWS_AS(make_histogram({1.0}, {0.0, 0.0}), granule::InvalidParameter);
  CHECK_THROWS_AS(uniform_edges(1.0, 0.0, 3), granule::InvalidParameter);
}

TEMPLATE_TEST_CASE("normal force pdf and very strong forces on a hand-made set",
                   "[analysis][force_network]", Dim2, Dim3) {
  using D = TestType;
  Frame<D> f = particles<D>(12);
  // Pair forces: eight of 1 N, one of 2 N, one of 40 N → ⟨fn⟩ = 50/10 = 5 N.
  for (std::uint32_t k = 0; k < 8; ++k) f.contacts.push_back(make_contact<D>(k, k + 1, 1.0, 0.0, 0.5));
  f.contacts.push_back(make_contact<D>(8, 9, 2.0, 0.0, 0.5));
  f.contacts.push_back(make_contact<D>(9, 10, 40.0, 0.0, 0.5));
  // A wall contact of 100 N, excluded by the default ParticlePair selection.
  f.contacts.push_back(make_contact<D>(11, ContactRecord<D>::kWall, 100.0, 0.0, 0.5));
  CHECK(mean_normal_force(f) == Approx(5.0).epsilon(1e-15));
  CHECK(mean_normal_force(f, ContactKind::Any) == Approx(150.0 / 11.0).epsilon(1e-15));
  // Very strong: fn > 6 · 5 = 30 N → only the 40 N contact (paper 000 section V).
  CHECK(count_strong_forces(f) == 1);
  CHECK(count_strong_forces(f, 0.3) == 2);  // fn > 1.5 N
  CHECK(count_strong_forces(f, 6.0, ContactKind::Any) == 1);  // 100 > 6·13.6 only
  // PDF of fn/⟨fn⟩ on [0, 10] in bins of 0.5: 0.2 (×8) and 0.4 in bin 0, 8.0 in bin 16.
  const ForcePdf pdf = normal_force_pdf(f, uniform_edges(0.0, 10.0, 20));
  CHECK(pdf.mean_fn == Approx(5.0));
  CHECK(pdf.histogram.integral() == Approx(1.0).epsilon(1e-14));
  CHECK(pdf.histogram.density[0] == Approx(9.0 / (10 * 0.5)).epsilon(1e-14));
  CHECK(pdf.histogram.density[16] == Approx(1.0 / (10 * 0.5)).epsilon(1e-14));
  const auto list = contact_forces(f, ContactKind::Wall);
  REQUIRE(list.size() == 1);
  CHECK(list.fn[0] == 100.0);
  CHECK(list.wall[0]);
  CHECK(list.contact[0] == 10);
  Frame<D> empty = particles<D>(2);
  CHECK_THROWS_AS(normal_force_pdf(empty, uniform_edges(0.0, 1.0, 2)), granule::InvalidParameter);
}

TEMPLATE_TEST_CASE("friction mobilisation on hand-made contacts", "[analysis][force_network]",
                   Dim2, Dim3) {
  using D = TestType;
  constexpr auto kWall = ContactRecord<D>::kWall;
  Frame<D> f = particles<D>(6);
  f.contacts.push_back(make_contact<D>(0, 1, 1.0, 0.25, 0.5));  // μ* = 0.25/0.5 = 0.5
  f.contacts.push_back(make_contact<D>(1, 2, 1.0, 0.5, 0.5));   // μ* = 1 (sliding)
  f.contacts.push_back(make_contact<D>(2, 3, 2.0, 0.1, 0.4));   // μ* = 0.1/0.8 = 0.125
  f.contacts.push_back(make_contact<D>(3, 4, 0.0, 0.1, 0.4));   // fn = 0: undefined, skipped
  f.contacts.push_back(make_contact<D>(4, kWall, 2.0, 0.3, 0.3, 0));  // wall 0: μ* = 0.5
  f.contacts.push_back(make_contact<D>(5, kWall, 1.0, 0.1, 0.5, 1));  // wall 1: μ* = 0.2
  const auto m = friction_mobilisation(f, uniform_edges(0.0, 1.0, 4));
  REQUIRE(m.bulk.mu_star.size() == 3);
  CHECK(m.bulk.mu_star[0] == Approx(0.5).epsilon(1e-15));
  CHECK(m.bulk.mu_star[1] == Approx(1.0).epsilon(1e-15));
  CHECK(m.bulk.mu_star[2] == Approx(0.125).epsilon(1e-15));
  CHECK(m.bulk.mean == Approx((0.5 + 1.0 + 0.125) / 3.0).epsilon(1e-15));
  CHECK(m.bulk.skipped == 1);
  CHECK(m.bulk.sliding == 1);
  CHECK(m.wall.mean == Approx(0.35).epsilon(1e-15));
  CHECK(m.all.mu_star.size() == 5);
  CHECK(m.all.histogram.integral() == Approx(1.0).epsilon(1e-15));
  // Bins of 0.25: bulk values 0.125 → bin 0, 0.5 → bin 2, 1.0 → bin 3 (closed right edge).
  CHECK(m.bulk.histogram.counts[0] == 1);
  CHECK(m.bulk.histogram.counts[2] == 1);
  CHECK(m.bulk.histogram.counts[3] == 1);
  // Only wall 0 in the wall group: the contact with wall 1 (say an intruder) is left out.
  const auto m0 = friction_mobilisation(f, uniform_edges(0.0, 1.0, 4), {0});
  CHECK(m0.wall.mu_star.size() == 1);
  CHECK(m0.wall.mean == Approx(0.5).epsilon(1e-15));
  CHECK(m0.all.mu_star.size() == 4);
}

TEMPLATE_TEST_CASE("coordination number with and without Thornton's rattler rule",
                   "[analysis][force_network]", Dim2, Dim3) {
  using D = TestType;
  // Chain 0–1–2–3, particle 4 isolated, one wall contact on particle 0.
  Frame<D> f = particles<D>(5);
  f.contacts.push_back(make_contact<D>(0, 1, 1.0, 0.0, 0.5));
  f.contacts.push_back(make_contact<D>(1, 2, 1.0, 0.0, 0.5));
  f.contacts.push_back(make_contact<D>(2, 3, 1.0, 0.0, 0.5));
  f.contacts.push_back(make_contact<D>(0, ContactRecord<D>::kWall, 1.0, 0.0, 0.5));
  // Pairs only: c = (1, 2, 2, 1, 0): Z = 6/5; Z_m = (6 − 2)/(5 − 1 − 2) = 2.
  auto z = coordination_number(f);
  CHECK(z.z == Approx(1.2).epsilon(1e-15));
  CHECK(z.n0 == 1);
  CHECK(z.n1 == 2);
  z = coordination_number(f, RattlerRule::ThorntonMechanical);
  CHECK(z.z == Approx(2.0).epsilon(1e-15));
  // With walls: c = (2, 2, 2, 1, 0): Z = 7/5; Z_m = (7 − 1)/(5 − 1 − 1) = 2.
  z = coordination_number(f, RattlerRule::KeepAll, true);
  CHECK(z.z == Approx(1.4).epsilon(1e-15));
  z = coordination_number(f, RattlerRule::ThorntonMechanical, true);
  CHECK(z.z == Approx(2.0).epsilon(1e-15));
  CHECK(z.contact_ends == 7);
}
