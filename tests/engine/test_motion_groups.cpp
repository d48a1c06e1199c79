// Frozen and prescribed particle groups, and walls on moving bodies:
//  - a frozen particle never moves, whatever hits it;
//  - a prescribed group moves with v(t): the engine drifts with the midpoint velocity,
//    x_{n+1} = x_n + dt v(t_n + dt/2), so x(t) equals that sum to round-off and the exact
//    integral x0 + A sin(w t) within the midpoint-rule error A (w dt)^2 / 24 per unit w t;
//  - a wall on a body driven at constant velocity into a column of spheres: the force the body
//    reports is minus what the particles receive (Newton's third law, checked against the
//    particles' own force sums and against the recorded contacts), the body's work is
//    W = -sum F . V dt, and for elastic frictionless contacts W equals the energy gained by the
//    particles (kinetic + elastic + gravitational).
#include <catch2/catch.hpp>

#include <cmath>

#include "engine_helpers.hpp"

using namespace granule;

namespace {

constexpr double kMotionR = 1.0e-3;  // [m]

template <class D>
SimulationConfig<D> motion_config() {
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(0.04);
  cfg.dt = 5e-6;
  cfg.thickness = 1e-3;
  cfg.gravity = Vec::Zero();
  cfg.gravity[1] = -9.81;
  return cfg;
}

}  // namespace

TEMPLATE_TEST_CASE("A frozen particle never moves under impacts", "[engine][groups]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Simulation<TestType, contact::HertzMindlin> sim(motion_config<TestType>());
  const auto mat = sim.add_material(test::soft_material(0.8, 0.5));
  const Vec centre = Vec::Constant(0.02);
  const auto frozen = sim.add_particle(centre, 2 * kMotionR, mat, Vec::Zero(), 1);
  sim.freeze_group(1);
  // Projectiles from every axis direction, slightly off-centre (so friction acts too).
  std::vector<std::uint64_t> shots;
  std::vector<Vec> v0;
  for (int k = 0; k < TestType::dim; ++k) {
    for (double s : {-1.0, 1.0}) {
      Vec x = centre + s * 4.5 * kMotionR * Vec::Unit(k);
      x[(k + 1) % TestType::dim] += 0.5 * kMotionR;
      const Vec v = -s * 1.0 * Vec::Unit(k);  // [m/s]
      shots.push_back(sim.add_particle(x, kMotionR, mat, v));
      v0.push_back(v);
    }
  }
  std::size_t max_contacts = 0;
  for (int s = 0; s < 1500; ++s) {
    sim.step();
    max_contacts = std::max(max_contacts, sim.contact_count());
    const auto& p = sim.particles();
    const std::size_t i = sim.index_of(frozen);
    REQUIRE(p.x[i] == centre);  // bitwise, at every step
    REQUIRE(p.v[i] == Vec::Zero());
    REQUIRE(TestType::squared_norm(p.omega[i]) == 0.0);
  }
  CHECK(max_contacts == shots.size());  // all projectiles were in contact at once
  // Every projectile bounced back (its velocity along the shot axis reversed).
  for (std::size_t k = 0; k < shots.size(); ++k) {
    const Vec v = sim.particles().v[sim.index_of(shots[k])];
    CHECK(v.dot(v0[k]) < -0.3 * v0[k].squaredNorm());
  }
}

TEMPLATE_TEST_CASE("A prescribed group follows v(t) exactly, whatever hits it", "[engine][groups]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Simulation<TestType, contact::HertzMindlin> sim(motion_config<TestType>());
  const auto mat = sim.add_material(test::soft_material(0.8, 0.5));
  const double amp = 0.5e-3;                      // [m]
  const double w = 2.0 * std::acos(-1.0) * 50.0;  // [rad/s], 50 Hz: peak acceleration 5 g
  auto vel = [amp, w](double t) {
    Vec v = Vec::Zero();
    v[0] = amp * w * std::cos(w * t);
    v[1] = 0.5 * amp * w * std::cos(2.0 * w * t);
    return v;
  };
  const Vec x0 = Vec::Constant(0.02);
  const auto shaker = sim.add_particle(x0, 2 * kMotionR, mat, Vec::Zero(), 3);
  sim.prescribe_group_velocity(3, vel);
  // A free particle resting on top of the shaker gets thrown around by it.
  Vec xf = x0;
  xf[1] += 3.0 * kMotionR;
  const auto free_id = sim.add_particle(xf, kMotionR, mat);
  const double dt = sim.dt();
  Vec midpoint_sum = x0;
  double worst_sum = 0.0, worst_exact = 0.0;
  std::size_t contact_steps = 0;
  for (int s = 0; s < 4000; ++s) {  // 20 ms = one period
    midpoint_sum += dt * vel(s * dt + 0.5 * dt);
    sim.step();
    // The engine's time is the step count times dt (not a running sum, which drifts).
    const double t = sim.time();
    REQUIRE(t == (s + 1) * dt);
    contact_steps += sim.contact_count() > 0;
    const std::size_t i = sim.index_of(shaker);
    const Vec x = sim.particles().x[i];
    Vec exact = x0;
    exact[0] += amp * std::sin(w * t);
    exact[1] += 0.25 * amp * std::sin(2.0 * w * t);
    worst_sum = std::max(worst_sum, (x - midpoint_sum).norm());
    worst_exact = std::max(worst_exact, (x - exact).norm());
    REQUIRE(sim.particles().v[i] == vel(t));  // the velocity at the step's end is v(t), exactly
    REQUIRE(TestType::squared_norm(sim.particles().omega[i]) == 0.0);
  }
  // Midpoint rule: per step dt v(t + dt/2) vs the integral, relative error (w dt)^2 / 24 of the
  // step's displacement; summed over the run the bound is A (w dt)^2 / 24 * w t (with 2w for the y
  // term) -- here ~2e-9 m; measured ~1e-10 m because the error oscillates with the sinusoid.
  const double bound = amp * std::pow(2.0 * w * dt, 2) / 24.0 * (2.0 * w * sim.time());
  INFO("max |x - midpoint sum| = " << worst_sum << " m, max |x - exact| = " << worst_exact << " m, bound "
                                   << bound << " m, steps in contact " << contact_steps);
  CHECK(worst_sum < 1e-14);
  CHECK(worst_exact < bound);
  CHECK(contact_steps > 20);  // the free particle was really hit
  CHECK(sim.particles().v[sim.index_of(free_id)].norm() > 0.0);
}

namespace {

// A column of 5 spheres on the floor (a plane on the world body) compressed by a piston plane on
// body 1 moving down at constant speed. Elastic frictionless contacts (e = 1).
template <class D>
void check_piston() {
  using Vec = typename D::Vec;
  auto cfg = motion_config<D>();
  cfg.gravity[1] = -50.0;
  Simulation<D, contact::HertzFrictionless> sim(cfg);
  const auto mat = sim.add_material(test::soft_material(1.0));
  const auto wmat = sim.add_wall_material(test::soft_material(1.0));
  const Vec up = Vec::Unit(1);
  const double speed = 0.05;  // [m/s]
  sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), up), wmat);  // floor, body 0
  Body<D> piston;
  piston.name = "piston";
  piston.velocity = [speed, up](double) { return Vec(-speed * up); };
  const auto pb = sim.add_body(piston);
  const double top = 10.0 * kMotionR + 0.2 * kMotionR;
  sim.add_wall(geometry::PlaneShape<D>(Vec(top * up), Vec(-up)), wmat, pb);
  Vec x = Vec::Constant(0.02);
  double mass = 0.0;
  for (int k = 0; k < 5; ++k) {
    x[1] = (2 * k + 1) * kMotionR;
    sim.add_particle(x, kMotionR, mat);
    mass += sim.particles().mass.back();
  }
  const Vec weight = mass * cfg.gravity;
  sim.every(1, [](auto&) {}, true);  // record contacts every step
  const double e0 = sim.kinetic_energy() + sim.elastic_energy() + sim.gravitational_energy();
  double work = 0.0, worst_third_law = 0.0, worst_records = 0.0, worst_momentum = 0.0, force_scale = 0.0;
  Vec momentum = Vec::Zero();
  Vec f_prev = weight;  // total force on the particles at the start (at rest, no contacts)
  const double dt = sim.dt();
  for (int s = 0; s < 2400; ++s) {
    sim.step();
    const auto& p = sim.particles();
    Vec f_particles = Vec::Zero(), new_momentum = Vec::Zero();
    for (std::size_t i = 0; i < p.owned(); ++i) {
      f_particles += p.f[i];
      new_momentum += p.mass[i] * p.v[i];
    }
    // Third law: what the particles receive from the walls is minus what the bodies report.
    const Vec from_walls = -(sim.body(0).force + sim.body(pb).force);
    force_scale = std::max(force_scale, sim.body(pb).force.norm());
    worst_third_law = std::max(worst_third_law, (f_particles - (weight + from_walls)).norm());
    // The same from the recorded contacts with the piston.
    Vec on_particles = Vec::Zero();
    for (const auto& c : sim.frame().contacts)
      if (c.j == analysis::ContactRecord<D>::kWall && c.wall == 1) on_particles += c.fn * c.normal + c.ft;
    worst_records = std::max(worst_records, (on_particles + sim.body(pb).force).norm());
    // Velocity Verlet momentum balance: P_{n+1} - P_n = dt/2 (F_n + F_{n+1}).
    worst_momentum = std::max(worst_momentum, (new_momentum - momentum - 0.5 * dt * (f_prev + f_particles)).norm());
    momentum = new_momentum;
    f_prev = f_particles;
    work -= sim.body(pb).force.dot(sim.body(pb).current_velocity) * dt;
  }
  const double e1 = sim.kinetic_energy() + sim.elastic_energy() + sim.gravitational_energy();
  const double w_body = sim.body(pb).work;
  INFO("dim " << D::dim << ": piston force " << sim.body(pb).force.transpose() << " N (max " << force_scale
              << "), floor force " << sim.body(0).force.transpose() << " N, weight " << weight.transpose()
              << " N; work " << w_body << " J, energy gain " << e1 - e0 << " J; worst third-law residual "
              << worst_third_law << " N, records residual " << worst_records << " N, momentum residual "
              << worst_momentum << " N s");
  REQUIRE(force_scale > 10.0 * weight.norm());  // the piston really compresses the column
  CHECK(sim.contact_count() == 6);             // floor, 4 pairs, piston
  CHECK(worst_third_law < 1e-12 * force_scale);
  CHECK(worst_records < 1e-12 * force_scale);
  CHECK(worst_momentum < 1e-12 * force_scale * dt);
  CHECK(w_body == Approx(work).epsilon(1e-13));
  CHECK(w_body > 0.0);
  // Energy balance of the drive, to the accuracy of the rectangle rule the engine uses for W
  // (error ~ dt/2 x dW/dt at the end, 1e-3 relative here).
  CHECK(e1 - e0 == Approx(w_body).epsilon(3e-3));
}

}  // namespace

TEMPLATE_TEST_CASE("A wall on a moving body reports the reaction force and its work", "[engine][groups]", Dim2,
                   Dim3) {
  check_piston<TestType>();
}

// Regression test of a fixed engine bug ("non-free pairs"): two touching particles
// that are both non-free (prescribed-prescribed, or prescribed-frozen) are kept in the pair list
// (pair_list.hpp build_rows excludes only frozen-frozen pairs) and evaluated with
// m* = 1 / (0 + 0) = inf, so the damping term is inf * 0 = NaN and the run stops with
// InstabilityError at step 0. A piston built of touching prescribed particles (paper 001's
// virtual piston) cannot run. Expected: such pairs exert no force and the run proceeds.
TEMPLATE_TEST_CASE("Touching prescribed and frozen particles do not break the run", "[engine][groups]",
                   Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  auto cfg = motion_config<TestType>();
  Simulation<TestType, contact::HertzMindlin> sim(cfg);
  const auto mat = sim.add_material(test::soft_material(0.5, 0.5));
  Vec x = Vec::Constant(0.02);
  const auto a = sim.add_particle(x, kMotionR, mat, Vec::Zero(), 1);
  x[0] += 1.9 * kMotionR;
  const auto b = sim.add_particle(x, kMotionR, mat, Vec::Zero(), 1);  // overlaps a by 0.1 r
  x[0] += 1.9 * kMotionR;
  sim.add_particle(x, kMotionR, mat, Vec::Zero(), 2);  // overlaps b, frozen
  const Vec v = 0.01 * Vec::Unit(1);
  sim.prescribe_group_velocity(1, [v](double) { return v; });
  sim.freeze_group(2);
  REQUIRE_NOTHROW(sim.run(100));
  const Vec expected = Vec::Constant(0.02) + 100 * sim.dt() * v;
  CHECK((sim.particles().x[sim.index_of(a)] - expected).norm() < 1e-15);
  CHECK(sim.particles().x[sim.index_of(b)].allFinite());
}

// Regression test of a fixed engine bug ("release_group"): freeze_group,
// release_group and assign_group change motion modes without invalidating the neighbour list,
// but pair_list.hpp drops frozen-frozen pairs when it builds. After releasing a frozen stack,
// the pair between two of its particles is missing until some particle has moved skin/2: the
// upper sphere sinks into the lower one for ~2000 steps, then is shot out by a 10 % overlap.
// Expected: the contact acts from the first step after the release.
TEMPLATE_TEST_CASE("Released frozen particles interact at once", "[engine][groups]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Simulation<TestType, contact::HertzFrictionless> sim(motion_config<TestType>());
  const auto mat = sim.add_material(test::soft_material(0.5));
  const auto wmat = sim.add_wall_material(test::soft_material(0.5));
  sim.add_wall(geometry::PlaneShape<TestType>(Vec::Zero(), Vec::Unit(1)), wmat);
  Vec x = Vec::Constant(0.02);
  x[1] = kMotionR;
  const auto lower = sim.add_particle(x, kMotionR, mat, Vec::Zero(), 1);
  x[1] = 3.0 * kMotionR;
  const auto upper = sim.add_particle(x, kMotionR, mat, Vec::Zero(), 1);
  sim.freeze_group(1);
  sim.run(10);
  sim.release_group(1);
  double worst_overlap = 0.0;
  for (int s = 0; s < 3000; ++s) {
    sim.step();
    const auto& p = sim.particles();
    const double gap = (p.x[sim.index_of(upper)] - p.x[sim.index_of(lower)]).norm() - 2.0 * kMotionR;
    worst_overlap = std::max(worst_overlap, -gap);
  }
  // The same stack never frozen: largest (dynamic) overlap 1.1e-3 r in 2D, 1.3e-3 r in 3D.
  INFO("largest overlap " << worst_overlap / kMotionR << " r");
  CHECK(worst_overlap < 3e-3 * kMotionR);
}
