// Effective pair properties (E*, G*, restitution, friction mixing) and the damping constant beta,
// checked against numbers computed by hand.
#include <catch2/catch.hpp>

#include <cmath>

#include "granule/materials/pair_material.hpp"

using namespace granule;

// Reference: paper 000 eq. B8-B9 (Hertz, Mindlin; Di Renzo & Di Maio 2004):
//   1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2,  1/G* = 2 (2 - nu1)(1 + nu1)/E1 + 2 (2 - nu2)(1 + nu2)/E2.
// By hand, aluminium-like E1 = 70 GPa, nu1 = 0.25 with steel-like E2 = 210 GPa, nu2 = 0.3:
//   1/E* = 0.9375/70e9 + 0.91/210e9 = 1.339286e-11 + 4.333333e-12 = 1.772619e-11  -> E* = 5.641370e10 Pa
//   1/G* = 4.375/70e9 + 4.42/210e9  = 6.25e-11 + 2.104762e-11    = 8.354762e-11  -> G* = 1.196922e10 Pa
// (paper 001 eq. A3 prints (2 + nu)(1 - nu), which would give 1.5736e10 Pa: 31 % off).
// Like materials, E = 5 MPa, nu = 0.2: E* = E / (2 (1 - nu^2)) = 2.604167e6 Pa,
//   G* = E / (4 (2 - nu)(1 + nu)) = 5.787037e5 Pa.
// Tolerance 1e-6 (the hand values carry 7 digits).
TEST_CASE("Pair material mixing: E* and G* by hand (000 eq. B8-B9)", "[contact][material]") {
  Material a, b;
  a.youngs_modulus = 70.0e9;
  a.poisson_ratio = 0.25;
  a.density = 2700.0;
  a.restitution = 0.8;
  a.friction = 0.2;
  a.rolling_friction = 0.01;
  a.cohesion_energy_density = 1.0e3;
  b.youngs_modulus = 210.0e9;
  b.poisson_ratio = 0.3;
  b.density = 7800.0;
  b.restitution = 0.6;
  b.friction = 0.4;
  b.rolling_friction = 0.03;
  b.cohesion_energy_density = 3.0e3;
  const PairMaterial p = mix(a, b);
  CHECK(p.E_eff == Approx(5.641370e10).epsilon(1e-6));
  CHECK(p.G_eff == Approx(1.196922e10).epsilon(1e-6));
  // Equivalent shear form (2 - nu1)/G1 + (2 - nu2)/G2, G = E / (2 (1 + nu)).
  const double g1 = a.shear_modulus(), g2 = b.shear_modulus();
  CHECK(1.0 / p.G_eff == Approx((2.0 - 0.25) / g1 + (2.0 - 0.3) / g2).epsilon(1e-12));
  // Symmetric in the two materials.
  CHECK(mix(b, a).E_eff == Approx(p.E_eff).epsilon(1e-15));
  CHECK(mix(b, a).G_eff == Approx(p.G_eff).epsilon(1e-15));
  // Unlike materials: arithmetic means (pair_material.hpp; overridable per pair).
  CHECK(p.restitution == Approx(0.7));
  CHECK(p.mu_s == Approx(0.3));
  CHECK(p.mu_r == Approx(0.02));
  CHECK(p.k_c == Approx(2.0e3));

  Material s;
  s.youngs_modulus = 5.0e6;
  s.poisson_ratio = 0.2;
  s.density = 2500.0;
  const PairMaterial q = mix(s, s);
  CHECK(q.E_eff == Approx(2.604167e6).epsilon(1e-6));
  CHECK(q.G_eff == Approx(5.787037e5).epsilon(1e-6));
}

// Reference: linear stiffness of unlike materials, two half-contacts in series
// (pair_material.hpp): k = 2 k_a k_b / (k_a + k_b); like materials keep their k_n
// (paper 002: k_n = E d is the contact stiffness). By hand: k_a = 1e3, k_b = 3e3 -> 1.5e3 N/m;
// k from E L: E = 1e6 Pa, L = 2e-3 m -> 2e3 N/m.
TEST_CASE("Pair material mixing: linear normal stiffness", "[contact][material]") {
  Material a, b;
  a.youngs_modulus = b.youngs_modulus = 1.0e6;
  a.density = b.density = 1000.0;
  a.normal_stiffness = 1.0e3;
  b.normal_stiffness = 3.0e3;
  CHECK(mix(a, b).k_n_linear == Approx(1.5e3).epsilon(1e-12));
  CHECK(mix(a, a).k_n_linear == Approx(1.0e3).epsilon(1e-12));
  Material c = a;
  c.normal_stiffness = 0.0;
  c.reference_length = 2.0e-3;
  CHECK(mix(c, c).k_n_linear == Approx(2.0e3).epsilon(1e-12));
}

// Reference: beta = ln e / sqrt(ln^2 e + pi^2) (000 eq. B7, 001 eq. A5). By hand:
// e = 0.5: ln e = -0.6931472, ln^2 e + pi^2 = 10.350057, sqrt = 3.217151 -> beta = -0.2154538;
// e = 0.9 -> -0.03351845; e = 0.1 -> -0.5911550; e = 1 -> 0 (no damping).
TEST_CASE("Damping constant beta(e) by hand (001 eq. A5)", "[contact][material]") {
  PairMaterial p;
  p.restitution = 0.5;
  CHECK(p.beta() == Approx(-0.2154538).epsilon(1e-6));
  p.restitution = 0.9;
  CHECK(p.beta() == Approx(-0.03351845).epsilon(1e-6));
  p.restitution = 0.1;
  CHECK(p.beta() == Approx(-0.5911550).epsilon(1e-6));
  p.restitution = 1.0;
  CHECK(p.beta() == 0.0);
}
