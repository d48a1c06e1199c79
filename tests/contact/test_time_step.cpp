// Time-step helpers (Rayleigh time, Hertz and linear collision times, Hertz maximum overlap) and
// the engine's critical / suggested time step, against hand computation.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "contact_test_support.hpp"
#include "granule/materials/time_step.hpp"

using namespace granule;
using namespace granule::contact_test;

// Reference: Rayleigh time t_R = pi r sqrt(rho/G) / (0.1631 nu + 0.8766) (Li, Xu & Thornton 2005;
// LIGGGHTS docs). By hand: r = 1 mm, rho = 2500 kg/m^3, E = 5 MPa, nu = 0.2, G = E/2.4 = 2.083333e6 Pa:
// sqrt(rho/G) = sqrt(1.2e-3) = 3.464102e-2 s/m; pi r sqrt(rho/G) = 1.088279e-4 s;
// 0.1631 * 0.2 + 0.8766 = 0.90922  ->  t_R = 1.196938e-4 s.
// Hertz collision time, paper 001 eq. A17: m* = 5.235988e-6 kg (two 1 mm spheres of 2500 kg/m^3),
// E* = 2.604167e6 Pa, R* = 5e-4 m, v = 1 m/s: 2.94 (m*^2 / ((16/15)^2 E*^2 R* v))^(1/5)
// = 2.745831e-4 s; Johnson's exact constant 2.8683 gives 2.748890e-4 s (0.11 % more).
// delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) = 9.339561e-5 m.
// Linear: k = 1e3 N/m, e = 0.5: sqrt(m*/k) sqrt(pi^2 + ln^2 e) = 2.327934e-4 s.
TEST_CASE("Time-step helpers against hand computation", "[contact][time_step]") {
  CHECK(rayleigh_time(1.0e-3, 2500.0, 5.0e6 / 2.4, 0.2) == Approx(1.196938e-4).epsilon(1e-6));
  const double m = 5.235988e-6, E = 2.604167e6, R = 5.0e-4;
  CHECK(hertz_collision_time(m, E, R, 1.0) == Approx(2.745831e-4).epsilon(1e-6));
  CHECK(hertz_collision_time(m, E, R, 1.0) == Approx(hertz_duration_exact(m, E, R, 1.0)).epsilon(2e-3));
  CHECK(hertz_duration_exact(m, E, R, 1.0) == Approx(2.748890e-4).epsilon(1e-6));
  CHECK(hertz_max_overlap(m, E, R, 1.0) == Approx(9.339561e-5).epsilon(1e-6));
  CHECK(linear_collision_time(1.0e3, m, 0.5) == Approx(2.327934e-4).epsilon(1e-6));
  // Scaling with speed: t_c ~ v^(-1/5), delta_max ~ v^(4/5).
  CHECK(hertz_collision_time(m, E, R, 32.0) == Approx(hertz_collision_time(m, E, R, 1.0) / 2.0).epsilon(1e-12));
  CHECK(hertz_max_overlap(m, E, R, 32.0) == Approx(hertz_max_overlap(m, E, R, 1.0) * 16.0).epsilon(1e-12));
  CHECK_THROWS_AS(hertz_collision_time(m, E, R, 0.0), InvalidParameter);
}

// Reference: simulation.hpp, critical_time_step(): the smallest Rayleigh time of the particles for
// Hertz laws, the linear collision time with m* = m/2 for linear laws; suggested = 0.2 x critical;
// a larger dt is refused with InvalidParameter unless allow_large_time_step is set. Numbers as
// above (3D spheres of r = 1 mm; 2D disks of thickness 1 mm: m = rho pi r^2 t = 7.853982e-6 kg).
TEMPLATE_TEST_CASE("Simulation critical and suggested time step", "[contact][time_step]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  Material mat;
  mat.youngs_modulus = 5.0e6;
  mat.poisson_ratio = 0.2;
  mat.density = 2500.0;
  mat.restitution = 0.5;
  mat.normal_stiffness = 1.0e3;
  SimulationConfig<D> cfg;
  cfg.domain.hi = Vec::Constant(0.02);  // small box: the cell grid spans the whole domain
  cfg.dt = 1.0e-7;
  cfg.thickness = 1.0e-3;
  {
    Simulation<D, contact::HertzMindlin> sim(cfg);
    const auto pm = sim.add_material(mat);
    sim.add_particle(Vec::Constant(0.01), 1.0e-3, pm);
    sim.add_particle(Vec::Constant(0.005), 2.0e-3, pm);
    CHECK(sim.critical_time_step() == Approx(1.196938e-4).epsilon(1e-6));
    CHECK(sim.suggested_time_step() == Approx(0.2 * 1.196938e-4).epsilon(1e-6));
  }
  {
    Simulation<D, contact::LinearSpringDashpot> sim(cfg);
    const auto pm = sim.add_material(mat);
    sim.add_particle(Vec::Constant(0.01), 1.0e-3, pm);
    const double m = mass_of<D>(2500.0, 1.0e-3, 1.0e-3);
    CHECK(sim.critical_time_step() == Approx(linear_collision_time(1.0e3, 0.5 * m, 0.5)).epsilon(1e-12));
    if constexpr (D::dim == 3) CHECK(sim.critical_time_step() == Approx(2.327934e-4).epsilon(1e-6));
  }
  {
    SimulationConfig<D> big = cfg;
    big.dt = 0.3 * 1.196938e-4;
    Simulation<D, contact::HertzMindlin> sim(big);
    const auto pm = sim.add_material(mat);
    sim.add_particle(Vec::Constant(0.01), 1.0e-3, pm);
    CHECK_THROWS_AS(sim.step(), InvalidParameter);
    big.allow_large_time_step = true;
    Simulation<D, contact::HertzMindlin> ok(big);
    ok.add_particle(Vec::Constant(0.01), 1.0e-3, ok.add_material(mat));
    CHECK_NOTHROW(ok.step());
  }
}
