// The 2D laws evaluated as one number along the tangent (incremental_coulomb.hpp, epsd.hpp,
// history.hpp): in 2D the tangent "plane" is the line of t = z x n = (-n_y, n_x), so the
// incremental Coulomb force is f t with f the rotated length, plus the increment -k_t v_t dt
// along t, clamped to [-mu |F_n|, mu |F_n|], and the EPSD rolling torque is clamped to
// [-M_max, M_max]. These tests hold them to the vector forms they replaced (2026-12-07): the
// projection of the history onto the new tangent line with its length restored (Luding 2008,
// "Cohesive, frictional powders: contact models for tension", section 2.2.3), the increment,
// and the rescaling onto the Coulomb circle (the 3D code, which still does exactly that). Same
// force to a few ulps, on random contacts that stick, slide forwards and backwards, and turn by
// up to 0.3 rad in one step; a tolerance of 1e-13 relative catches a wrong sign, a missing
// rotation or a lost increment by many orders of magnitude.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "granule/contact/model.hpp"
#include "granule/core/dimension.hpp"

using namespace granule;
using namespace granule::contact;

namespace {

using Vec = Dim2::Vec;

// The vector form: project onto the tangent line of n, restore the length, add the increment,
// rescale onto the limit when it is exceeded.
Vec coulomb_vector_form(Vec ft, const Vec& n, const Vec& vt, double kt_dt, double limit) {
  const double before2 = ft.squaredNorm();
  ft -= ft.dot(n) * n;
  const double after2 = ft.squaredNorm();
  if (after2 > 0.0) ft *= std::sqrt(before2 / after2);
  ft -= kt_dt * vt;
  const double f = ft.norm();
  if (f > limit) ft *= limit / f;
  return ft;
}

struct Case {
  ContactGeometry<Dim2> g;
  NormalResultOf<Dim2> nr;
  Vec ft;
};

// A contact whose normal has turned by up to 0.3 rad since its history was stored, with a
// tangential force of up to twice the Coulomb limit on either side, and a slip velocity whose
// increment is up to the limit.
Case random_case(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case c;
  const double phi = 3.14159 * u(rng), turn = 0.3 * u(rng);
  c.g.n = Vec(std::cos(phi), std::sin(phi));
  const Vec t_old(-std::sin(phi - turn), std::cos(phi - turn));
  const Vec n_old(std::cos(phi - turn), std::sin(phi - turn));
  c.nr.fn = 0.5 + u(rng);  // [N]; negative in some cases (|F_n| sets the limit)
  c.nr.kn = 6.0e4;         // [N/m]
  c.g.dt = 1.0e-6;         // [s]
  const double limit = 0.5 * std::abs(c.nr.fn);
  // Stored in the old frame: mostly along the old tangent, a little along the old normal.
  c.ft = 2.0 * limit * u(rng) * t_old + 0.1 * limit * u(rng) * n_old;
  const Vec t(-c.g.n.y(), c.g.n.x());
  c.g.vt = (limit / (0.5 * c.nr.kn * c.g.dt)) * u(rng) * t;
  return c;
}

}  // namespace

TEST_CASE("2D incremental Coulomb along the tangent equals the projected vector form", "[contact][2d]") {
  IncrementalCoulombTangential::Params p{0.5, 0.5};
  std::mt19937_64 rng(27);
  int sliding = 0;
  for (int k = 0; k < 20000; ++k) {
    Case c = random_case(rng);
    const double limit = p.mu_s * std::abs(c.nr.fn);
    const Vec expected = coulomb_vector_form(c.ft, c.g.n, c.g.vt, p.ratio * c.nr.kn * c.g.dt, limit);
    IncrementalCoulombTangential::State<Dim2> s;
    s.ft = c.ft;
    const Vec got = IncrementalCoulombTangential::eval<Dim2>(p, c.g, c.nr, s);
    INFO("case " << k << ": expected " << expected.transpose() << ", got " << got.transpose());
    REQUIRE((got - expected).norm() <= 1e-13 * limit);
    REQUIRE(s.ft == got);  // the history is the force
    REQUIRE(std::abs(got.dot(c.g.n)) <= 1e-15 * limit);  // tangential
    if (std::abs(got.norm() - limit) <= 1e-12 * limit) ++sliding;
  }
  // Both regimes were exercised.
  CHECK(sliding > 2000);
  CHECK(sliding < 18000);
}

TEST_CASE("2D incremental Coulomb: a history along the normal has no tangential part", "[contact][2d]") {
  IncrementalCoulombTangential::Params p{0.5, 0.5};
  ContactGeometry<Dim2> g;
  g.n = Vec(0.6, 0.8);
  g.vt = Vec::Zero();
  g.dt = 1e-6;
  NormalResultOf<Dim2> nr;
  nr.fn = 1.0;
  nr.kn = 6e4;
  IncrementalCoulombTangential::State<Dim2> s;
  // (Along a normal whose cross product with the history is exact in any arithmetic: for
  // n = (0.6, 0.8) the two products of n x ft round to the same double only when they are not
  // fused into one multiply-add, and -march=native with FMA fuses them; then the rounding error
  // picks a side of the line and the history keeps its length, which is the rotation's answer
  // to a history that is along n only to within rounding.)
  for (const Vec& axis : {Vec(0.0, 1.0), Vec(-1.0, 0.0)}) {
    ContactGeometry<Dim2> ga = g;
    ga.n = axis;
    s.ft = 0.3 * axis;
    CHECK(IncrementalCoulombTangential::eval<Dim2>(p, ga, nr, s).norm() == 0.0);
  }
  // A history along -t keeps its side of the line (sign), its length, and turns with n.
  s.ft = Vec(0.8, -0.6) * 0.2;  // -t for this n, t = (-0.8, 0.6)
  const Vec f = IncrementalCoulombTangential::eval<Dim2>(p, g, nr, s);
  CHECK(f.x() == Approx(0.16).margin(1e-16));
  CHECK(f.y() == Approx(-0.12).margin(1e-16));
  // A NaN history stays NaN (the engine's checks then see the failed run; it must not be
  // zeroed as "no tangential part").
  s.ft = Vec(std::nan(""), 0.1);
  CHECK(std::isnan(IncrementalCoulombTangential::eval<Dim2>(p, g, nr, s).x()));
}

TEST_CASE("2D EPSD rolling: the clamp equals the rescaling onto the limit", "[contact][2d][rolling]") {
  EpsdRolling::Params p{0.02, 40.0, 0.3};
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int mobilised = 0;
  for (int k = 0; k < 20000; ++k) {
    ContactGeometry<Dim2> g;
    g.r_eff = 7.5e-4;
    g.i_roll = 1e-9;
    g.dt = 1e-6;
    g.omega_rel = 50.0 * u(rng);
    g.omega_rel_damp = g.omega_rel;
    NormalResultOf<Dim2> nr;
    nr.fn = 0.5 + u(rng);
    nr.kn = 6e4;
    const double m_max = p.mu_r * g.r_eff * std::abs(nr.fn);
    EpsdRolling::State<Dim2> s;
    s.m_roll = 1.5 * m_max * u(rng);
    // The vector form on one component: increment; past the limit, scale by M_max / |M| and no
    // damping; below it the dashpot C_r = 2 eta_r sqrt(I_r k_r) (001 eq. A13-A15).
    const double kr = p.factor * nr.kn * p.mu_r * p.mu_r * g.r_eff * g.r_eff;
    double m = s.m_roll - kr * g.dt * g.omega_rel;
    const bool held = m * m >= m_max * m_max;
    double expected_state = m, expected = m;
    if (held) {
      expected_state = m * (m_max / std::sqrt(m * m));
      expected = expected_state;
      ++mobilised;
    } else {
      expected = m - p.eta_r * 2.0 * std::sqrt(g.i_roll * kr) * g.omega_rel_damp;
    }
    const double got = EpsdRolling::eval<Dim2>(p, g, nr, s);
    INFO("case " << k);
    REQUIRE(std::abs(s.m_roll - expected_state) <= 1e-15 * m_max);
    REQUIRE(std::abs(got - expected) <= 1e-15 * m_max + 1e-15 * std::abs(expected));
  }
  CHECK(mobilised > 2000);
  CHECK(mobilised < 18000);
}
