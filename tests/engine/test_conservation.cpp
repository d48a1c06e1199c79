// Conservation in an elastic frictionless gas in a fully periodic box (no walls, no gravity):
//  - total momentum: every pair force is applied as +F on i and -F on j (ghost forces go back to
//    their owners), so sum m v changes only by round-off; we require |P(t) - P(0)| < 1e-12 of
//    sum |m v| over 10^4 steps.
//  - energy: velocity Verlet is symplectic for smooth conservative forces (Hairer, Lubich &
//    Wanner 2003, ch. VIII); contact forces are not smooth at first touch, so each collision
//    leaves a small energy error, O(dt^2) for the linear spring and of higher order for Hertz,
//    whose force vanishes smoothly (as delta^3/2) at contact. For the error (max over the run of
//    |E - E0| / E0, E = kinetic + elastic) we require < 3e-4 over 10^4 steps at dt = t_c / 50
//    (measured up to 1.2e-4), and that dividing dt by 4 shrinks it by more than 3 (O(dt^2)
//    would give 16).
#include <catch2/catch.hpp>

#include "engine_helpers.hpp"

using namespace granule;

namespace {

constexpr double kRmin = 0.8e-3;  // [m]
constexpr double kRmax = 1.2e-3;  // [m]
constexpr double kSpeed = 1.0;    // velocity components uniform in [-1, 1] m/s

struct GasResult {
  double momentum_error = 0.0;  ///< max |P(t) - P(0)| / sum |m v|
  double energy_error = 0.0;    ///< max |E(t) - E(0)| / E(0)
  double final_energy_error = 0.0;
  std::size_t collisions = 0;   ///< contacts summed over steps (a measure of activity)
};

template <class D>
std::vector<test::SphereSpec<D>> gas_packing(const Domain<D>& dom) {
  return test::random_packing<D>(2024, dom, D::dim == 2 ? 200 : 150, kRmin, kRmax, 0.0);
}

template <class D>
Domain<D> gas_domain() {
  using Vec = typename D::Vec;
  return test::box_domain<D>(Vec::Constant(D::dim == 2 ? 0.04 : 0.016), true);
}

// Collision time t_c of the stiffest collision: two particles of the smallest radius, head-on at
// the largest relative speed of the initial state (Hertz: 001 eq. A17; linear: pi sqrt(m*/k)).
template <class D, class Model>
double collision_time() {
  const Material m = test::soft_material(1.0);
  const double mass = m.density * D::volume(kRmin, 1e-3);
  const PairMaterial pm = mix(m, m);
  if constexpr (Model::NormalLaw::hertzian) {
    const double v_rel = 2.0 * kSpeed * std::sqrt(double(D::dim));
    return hertz_collision_time(0.5 * mass, pm.E_eff, 0.5 * kRmin, v_rel);
  } else {
    return linear_collision_time(pm.k_n_linear, 0.5 * mass, 1.0);
  }
}

template <class D, class Model>
GasResult run_gas(double dt, std::size_t steps) {
  using Vec = typename D::Vec;
  const auto dom = gas_domain<D>();
  const auto pk = gas_packing<D>(dom);
  SimulationConfig<D> cfg;
  cfg.domain = dom;
  cfg.dt = dt;
  cfg.thickness = 1e-3;
  Simulation<D, Model, neighbours::VerletList> sim(cfg);
  const auto mat = sim.add_material(test::soft_material(1.0));
  std::mt19937_64 rng(5);
  for (const auto& s : pk) {
    Vec v;
    for (int k = 0; k < D::dim; ++k) v[k] = test::uniform(rng, -kSpeed, kSpeed);
    v[0] += 0.3;  // a net drift, so momentum is not trivially zero
    sim.add_particle(s.x, s.r, mat, v);
  }
  GasResult r;
  double scale = 0.0;
  const Vec p0 = test::total_momentum(sim, &scale);
  const double e0 = sim.kinetic_energy() + sim.elastic_energy();
  for (std::size_t s = 0; s < steps; ++s) {
    sim.step();
    r.collisions += sim.contact_count();
    r.momentum_error = std::max(r.momentum_error, (test::total_momentum(sim) - p0).norm() / scale);
    if (s % 10 == 9 || s + 1 == steps) {
      const double e = sim.kinetic_energy() + sim.elastic_energy();
      r.energy_error = std::max(r.energy_error, std::abs(e - e0) / e0);
      r.final_energy_error = std::abs(e - e0) / e0;
    }
  }
  return r;
}

template <class D, class Model>
void check_gas(const char* name) {
  const double tc = collision_time<D, Model>();
  const std::size_t steps = 10000;
  const GasResult r50 = run_gas<D, Model>(tc / 50.0, steps);
  const GasResult r25 = run_gas<D, Model>(tc / 25.0, steps / 2);
  const GasResult r100 = run_gas<D, Model>(tc / 100.0, steps * 2);
  INFO(name << " dim " << D::dim << ": t_c = " << tc << " s; collisions (contact-steps) " << r50.collisions
            << "; momentum error " << r50.momentum_error << "; max energy error at t_c/25, t_c/50, t_c/100 "
            << "(same physical time): " << r25.energy_error << ", " << r50.energy_error << ", "
            << r100.energy_error << " (final " << r25.final_energy_error << ", " << r50.final_energy_error
            << ", " << r100.final_energy_error << ")");
  CHECK(r50.collisions > 2000);  // the gas really collides (2000 contact-steps ~ 40 collisions)
  CHECK(r50.momentum_error < 1e-12);
  CHECK(r25.momentum_error < 1e-12);
  CHECK(r100.momentum_error < 1e-12);
  // Measured (max over the run): 3e-5 .. 1.2e-4 at t_c/50; the error is a random walk of
  // per-collision errors, so its dt-scaling is irregular (ratios t_c/25 : t_c/100 of 7 to 36).
  CHECK(r50.energy_error < 3e-4);
  CHECK(r100.energy_error < r25.energy_error / 3.0);
}

}  // namespace

TEMPLATE_TEST_CASE("Elastic frictionless gas conserves momentum and energy (Hertz)", "[engine][conservation]",
                   Dim2, Dim3) {
  check_gas<TestType, contact::HertzFrictionless>("HertzFrictionless");
}

TEMPLATE_TEST_CASE("Elastic frictionless gas conserves momentum and energy (linear)", "[engine][conservation]",
                   Dim2, Dim3) {
  check_gas<TestType, contact::LinearFrictionless>("LinearFrictionless");
}
