// Static equilibrium under gravity: once the motion has been damped out, a wall carries exactly
// the weight of what rests on it, and every Hertz contact carries the weight above it with the
// overlap of the Hertz solution, F = 4/3 E* sqrt(R*) delta^3/2 (Hertz 1882; Johnson 1985,
// "Contact Mechanics", eq. 4.23), i.e. delta = (3 F / (4 E* sqrt(R*)))^(2/3), with
// R* = r for a sphere on a flat wall and r/2 for two equal spheres.
#include <catch2/catch.hpp>

#include "engine_helpers.hpp"

using namespace granule;

namespace {

constexpr double kLoadR = 1.0e-3;  // [m]

template <class D>
SimulationConfig<D> rest_config() {
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(0.02);
  cfg.dt = 1e-5;  // 0.12 x the Rayleigh time
  cfg.thickness = 1e-3;
  cfg.gravity = Vec::Zero();
  cfg.gravity[1] = -9.81;
  return cfg;
}

// Overlap of a Hertz contact of effective modulus E* and radius R* carrying force F.
double hertz_overlap(double force, double e_eff, double r_eff) {
  return std::pow(3.0 * force / (4.0 * e_eff * std::sqrt(r_eff)), 2.0 / 3.0);
}

}  // namespace

TEMPLATE_TEST_CASE("A sphere resting on a plane wall loads it with exactly its weight", "[engine][statics]", Dim2,
                   Dim3) {
  using Vec = typename TestType::Vec;
  const auto cfg = rest_config<TestType>();
  Simulation<TestType, contact::HertzMindlin> sim(cfg);
  const Material m = test::soft_material(0.1, 0.5);
  const auto mat = sim.add_material(m);
  const auto wmat = sim.add_wall_material(m);
  sim.add_wall(geometry::PlaneShape<TestType>(Vec::Zero(), Vec::Unit(1)), wmat);
  Vec x = Vec::Constant(0.01);
  x[1] = kLoadR;  // touching, zero overlap
  const auto id = sim.add_particle(x, kLoadR, mat);
  const double mass = sim.particles().mass[0];
  const Vec weight = mass * cfg.gravity;
  sim.run(3000);
  const Vec f_wall = sim.body(0).force;
  const double overlap = kLoadR - sim.particles().x[sim.index_of(id)][1];
  const double expected = hertz_overlap(weight.norm(), mix(m, m).E_eff, kLoadR);
  INFO("dim " << TestType::dim << ": wall force " << f_wall.transpose() << " N, weight " << weight.transpose()
              << " N, relative error " << (f_wall - weight).norm() / weight.norm() << "; overlap " << overlap
              << " m, Hertz " << expected << " m");
  CHECK(sim.contact_count() == 1);
  CHECK((f_wall - weight).norm() < 1e-9 * weight.norm());
  CHECK(overlap == Approx(expected).epsilon(1e-9));
  // Nothing sideways.
  CHECK(std::abs(sim.particles().x[0][0] - 0.01) < 1e-15);
}

TEMPLATE_TEST_CASE("A column of five spheres loads the floor with its total weight", "[engine][statics]", Dim2,
                   Dim3) {
  using Vec = typename TestType::Vec;
  const auto cfg = rest_config<TestType>();
  Simulation<TestType, contact::HertzMindlin> sim(cfg);
  const Material m = test::soft_material(0.1, 0.5);
  const auto mat = sim.add_material(m);
  const auto wmat = sim.add_wall_material(m);
  sim.add_wall(geometry::BoxContainerShape<TestType>(cfg.domain.lo, cfg.domain.hi), wmat);
  Vec x = Vec::Constant(0.01);
  std::vector<std::uint64_t> ids;
  for (int k = 0; k < 5; ++k) {
    x[1] = (2 * k + 1) * kLoadR;
    ids.push_back(sim.add_particle(x, kLoadR, mat));
  }
  const double mass = sim.particles().mass[0];
  const Vec weight = 5.0 * mass * cfg.gravity;
  sim.run(12000);  // the residual force decays by ~6x per 1000 steps: 4e-13 relative here
  sim.request_contacts();
  sim.step();
  const Vec f_wall = sim.body(0).force;
  INFO("dim " << TestType::dim << ": floor force " << f_wall.transpose() << " N, weight " << weight.transpose()
              << " N, relative error " << (f_wall - weight).norm() / weight.norm());
  CHECK(sim.contact_count() == 5);  // floor + 4 pairs
  CHECK((f_wall - weight).norm() < 1e-9 * weight.norm());
  // Each pair carries the weight of the spheres above it, with the Hertz overlap.
  const auto fr = sim.frame();
  const double e_eff = mix(m, m).E_eff;
  std::size_t pairs = 0;
  for (const auto& c : fr.contacts) {
    if (c.j == analysis::ContactRecord<TestType>::kWall) continue;
    ++pairs;
    const double top = std::max(fr.x[c.i][1], fr.x[c.j][1]);  // centre of the upper sphere
    const int above = static_cast<int>(std::lround((9 * kLoadR - top) / (2 * kLoadR))) + 1;  // it and those above
    const double load = above * mass * std::abs(cfg.gravity[1]);
    INFO("pair at height " << top << ": fn " << c.fn << " N, load " << load << " N");
    CHECK(c.fn == Approx(load).epsilon(1e-9));
    CHECK(c.overlap == Approx(hertz_overlap(load, e_eff, 0.5 * kLoadR)).epsilon(1e-9));
  }
  CHECK(pairs == 4);
}
