// Simplified JKR cohesion (SJKR): a cohesive pair (and a cohesive particle on a wall) released
// with a small overlap and no gravity settles where the Hertz repulsion balances the cohesive
// pull k_c A(delta), with A the exact contact area (3D circle, 2D strip of the disk thickness).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>

#include "contact_test_support.hpp"

using namespace granule;
using namespace granule::contact_test;

namespace {

using HertzSjkr = contact::ContactModel<contact::HertzNormal, contact::NoTangential, contact::NoRolling,
                                        contact::SjkrCohesion>;

// Squared radius of the contact circle (3D) / half-width of the contact strip (2D):
// two spheres of radius r at centre distance d = 2 r - delta (Weisstein, "Sphere-Sphere
// Intersection"; paper 001 eq. A7): a^2 = delta (4 r - delta) / 4; sphere on a plane:
// a^2 = 2 r delta - delta^2 (chord of a circle).
double contact_radius_sq(double r, double delta, bool wall) {
  return wall ? 2.0 * r * delta - delta * delta : delta * (4.0 * r - delta) / 4.0;
}

// Net repulsive force at overlap delta [N]: 4/3 E* sqrt(R*) delta^3/2 - k_c A(delta).
template <class D>
double net_force(double delta, double r, double E_eff, double k_c, double thickness, bool wall) {
  const double r_eff = wall ? r : 0.5 * r;
  const double a2 = contact_radius_sq(r, delta, wall);
  const double area = D::dim == 3 ? std::numbers::pi * a2 : 2.0 * std::sqrt(a2) * thickness;
  return 4.0 / 3.0 * E_eff * std::sqrt(r_eff) * delta * std::sqrt(delta) - k_c * area;
}

// Bisection for the non-trivial root of net_force in (0, r/2): attraction wins at small delta
// (area ~ delta or ~ sqrt(delta) against delta^3/2), repulsion at large delta.
template <class D>
double equilibrium_overlap(double r, double E_eff, double k_c, double thickness, bool wall) {
  double lo = 1e-9 * r, hi = 0.5 * r;
  REQUIRE(net_force<D>(lo, r, E_eff, k_c, thickness, wall) < 0.0);
  REQUIRE(net_force<D>(hi, r, E_eff, k_c, thickness, wall) > 0.0);
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (net_force<D>(mid, r, E_eff, k_c, thickness, wall) < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Settled {
  double overlap = 0.0;        ///< final overlap [m]
  double speed = 0.0;          ///< final relative speed [m/s]
};

template <class D>
Settled settle(const Material& mat, double r, double thickness, double overlap0, bool wall, double dt,
               double t_end) {
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Constant(-0.02);
  cfg.domain.hi = Vec::Constant(0.02);
  cfg.dt = dt;
  cfg.thickness = thickness;
  Simulation<D, HertzSjkr> sim(cfg);
  const auto pm = sim.add_material(mat);
  const Vec ax = wall ? up<D>() : unit<D>(0);
  std::uint64_t a = 0, b = 0;
  if (wall) {
    sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), ax), sim.add_wall_material(mat));
    a = sim.add_particle(Vec((r - overlap0) * ax), r, pm);
  } else {
    a = sim.add_particle(Vec((r - 0.5 * overlap0) * ax), r, pm);
    b = sim.add_particle(Vec(-(r - 0.5 * overlap0) * ax), r, pm);
  }
  sim.run_until(t_end);
  const auto& p = sim.particles();
  Settled s;
  const std::size_t i = sim.index_of(a);
  if (wall) {
    s.overlap = r - p.x[i].dot(ax);
    s.speed = p.v[i].norm();
  } else {
    const std::size_t j = sim.index_of(b);
    s.overlap = 2.0 * r - (p.x[i] - p.x[j]).norm();
    s.speed = (p.v[i] - p.v[j]).norm();
  }
  return s;
}

}  // namespace

// Reference: force balance of the SJKR law (LIGGGHTS sjkr; paper 001 eq. A1, A6-A8):
//   4/3 E* sqrt(R*) delta^3/2 = k_c A(delta),   A = pi a^2 (3D), 2 a t (2D disks of thickness t),
// with the exact intersection radius a(delta) above, solved by bisection. E = 5 MPa, k_c chosen so
// that delta_eq / r is 3-6 %; e = 0.3 damps the pair to rest. Tolerance 0.2 % (the brief asks for
// 1 %; the engine settles to round-off): using the small-overlap area 2 pi R* delta instead of the
// exact one shifts delta_eq by 3 % in 3D, a missing pi or a 2D area pi a^2 by far more.
TEMPLATE_TEST_CASE("SJKR cohesion: a resting pair settles at the force-balance overlap",
                   "[contact][cohesion][sjkr]", Dim2, Dim3) {
  using D = TestType;
  Material mat;
  mat.youngs_modulus = 5.0e6;  // [Pa]
  mat.poisson_ratio = 0.3;
  mat.density = 2500.0;        // [kg/m^3]
  mat.restitution = 0.3;
  mat.cohesion_energy_density = D::dim == 3 ? 2.0e5 : 1.0e5;  // k_c [J/m^3]
  const double r = 2.0e-3, t = 1.0e-3;  // [m]
  const double E_eff = mat.youngs_modulus / (2.0 * (1.0 - mat.poisson_ratio * mat.poisson_ratio));
  for (const bool wall : {false, true}) {
    const double d_eq = equilibrium_overlap<D>(r, E_eff, mat.cohesion_energy_density, t, wall);
    const auto s = settle<D>(mat, r, t, 0.5 * d_eq, wall, 2.0e-6, 0.03);
    INFO("dim " << D::dim << (wall ? " wall" : " pair") << ": delta_eq = " << s.overlap << " m (theory " << d_eq
                << ", delta/r = " << d_eq / r << "), residual speed " << s.speed << " m/s");
    CHECK(d_eq / r > 0.02);  // not a tiny overlap: the exact area matters
    CHECK(s.overlap == Approx(d_eq).epsilon(2e-3));
    CHECK(s.speed < 1e-6);
  }
}

// Reference: the exact intersection radius (as above) against SjkrCohesion::contact_radius_sq and
// area for a hand-built geometry of unequal spheres: a^2 = (-d+r1+r2)(d-r1+r2)(d+r1-r2)(d+r1+r2)
// / (4 d^2) (Weisstein), written out here with numbers: r1 = 3 mm, r2 = 1 mm, d = 3.9 mm gives
// a^2 = 0.1 * 1.9 * 5.9 * 7.9 / (4 * 15.21) mm^2 = 1.455749... mm^2. Wall: a^2 = 2 r delta - delta^2.
TEMPLATE_TEST_CASE("SJKR contact area: exact intersection circle and strip", "[contact][cohesion][sjkr]", Dim2,
                   Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  const double r1 = 3.0e-3, r2 = 1.0e-3, d = 3.9e-3;
  const auto g = make_pair_geometry<D>(Vec(d * unit<D>(0)), Vec::Zero(), r1, r2, 1e-3, 1e-4, Vec::Zero(), Vec::Zero(),
                                       D::zero_ang(), D::zero_ang(), 1e-6);
  const double a2 = 0.1 * 1.9 * 5.9 * 7.9 / (4.0 * 15.21) * 1e-6;  // [m^2]
  CHECK(contact::SjkrCohesion::contact_radius_sq(g) == Approx(a2).epsilon(1e-12));
  const contact::SjkrCohesion::Params prm{2.0e5, 0.5e-3};
  const double area = D::dim == 3 ? std::numbers::pi * a2 : 2.0 * std::sqrt(a2) * 0.5e-3;
  CHECK(contact::SjkrCohesion::area(prm, g) == Approx(area).epsilon(1e-12));
  CHECK(contact::SjkrCohesion::eval(prm, g) == Approx(2.0e5 * area).epsilon(1e-12));
  // Through the model: the cohesive pull is subtracted from the normal force.
  Material m;
  m.youngs_modulus = 5.0e6;
  m.poisson_ratio = 0.3;
  m.density = 2500.0;
  m.cohesion_energy_density = 2.0e5;
  const auto params = contact::HertzMindlinEpsdSjkr::make(mix(m, m), 0.5e-3);
  typename contact::HertzMindlinEpsdSjkr::template State<D> st{};
  const auto f = contact::HertzMindlinEpsdSjkr::evaluate(params, g, st);
  const double E_eff = 5.0e6 / (2.0 * (1.0 - 0.09));
  const double fe = 4.0 / 3.0 * E_eff * std::sqrt(g.r_eff) * std::pow(g.overlap, 1.5);
  CHECK(f.fn == Approx(fe - 2.0e5 * area).epsilon(1e-12));
  // Flat wall: a^2 = 2 r delta - delta^2.
  contact::ContactGeometry<D> gw = g;
  gw.distance = std::numeric_limits<double>::infinity();
  gw.r_j = std::numeric_limits<double>::infinity();
  gw.overlap = 2.0e-4;
  CHECK(contact::SjkrCohesion::contact_radius_sq(gw) == Approx(2.0 * r1 * 2.0e-4 - 4.0e-8).epsilon(1e-12));
}
