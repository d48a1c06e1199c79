// Errors of the engine: every invalid set-up throws InvalidParameter whose message names the
// parameter (and the valid range); a run that goes unstable throws InstabilityError naming the
// step, the particle id and its position, leaving the simulation state and everything observers
// wrote at earlier steps intact.
#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include "engine_helpers.hpp"
#include "../support/message_of.hpp"

using namespace granule;
using Catch::Matchers::Contains;
using granule::test::message_of;

namespace {

template <class D>
SimulationConfig<D> small_config() {
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(0.05);
  cfg.dt = 1e-6;
  cfg.thickness = 1e-3;
  return cfg;
}

Material with(void (*edit)(Material&)) {
  Material m = test::soft_material();
  edit(m);
  return m;
}

}  // namespace

TEMPLATE_TEST_CASE("Invalid particles are rejected with the parameter named", "[engine][errors]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Simulation<TestType, contact::HertzMindlin> sim(small_config<TestType>());
  const auto mat = sim.add_material(test::soft_material());
  const auto wmat = sim.add_wall_material(test::soft_material());
  const Vec inside = Vec::Constant(0.02);
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(inside, -1e-3, mat); }),
             Contains("radius = -0.001"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(inside, 0.0, mat); }),
             Contains("radius = 0"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(inside, std::numeric_limits<double>::quiet_NaN(), mat); }),
             Contains("radius"));
  Vec nan_x = inside;
  nan_x[1] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(nan_x, 1e-3, mat); }),
             Contains("x[1] = nan"));
  Vec outside = inside;
  outside[0] = 0.0625;  // exactly representable, so the message shows it exactly
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(outside, 1e-3, mat); }),
             Contains("x[0] = 0.0625") && Contains("inside the non-periodic domain"));
  Vec nan_v = Vec::Zero();
  nan_v[0] = std::numeric_limits<double>::infinity();
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(inside, 1e-3, mat, nan_v); }),
             Contains("v[0] = inf"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(inside, 1e-3, 7u); }),
             Contains("material = 7"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(inside, 1e-3, wmat); }),
             Contains("material") && Contains("wall material"));
  // None of the rejected particles was added.
  CHECK(sim.particles().owned() == 0);
  // A periodic axis accepts any finite coordinate (it is wrapped).
  SimulationConfig<TestType> cfg = small_config<TestType>();
  cfg.domain.periodic[0] = true;
  Simulation<TestType, contact::HertzMindlin> periodic(cfg);
  const auto pm = periodic.add_material(test::soft_material());
  CHECK_NOTHROW(periodic.add_particle(outside, 1e-3, pm));
}

TEST_CASE("Invalid materials are rejected with the field named", "[engine][errors]") {
  Simulation<Dim3, contact::HertzMindlin> sim(small_config<Dim3>());
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.youngs_modulus = 0.0; })); }),
             Contains("youngs_modulus = 0") && Contains("(0, inf) Pa"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.youngs_modulus = -1e7; })); }),
             Contains("youngs_modulus = -10000000"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.poisson_ratio = 0.5; })); }),
             Contains("poisson_ratio = 0.5") && Contains("[0, 0.5)"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.poisson_ratio = -0.1; })); }),
             Contains("poisson_ratio = -0.1"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.restitution = 0.0; })); }),
             Contains("restitution = 0") && Contains("(0, 1]"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.restitution = 1.2; })); }),
             Contains("restitution = 1.2"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.friction = -0.1; })); }),
             Contains("friction = -0.1"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.density = 0.0; })); }),
             Contains("density = 0"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_material(with([](Material& m) { m.density = -2500.0; })); }),
             Contains("density = -2500"));
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_wall_material(with([](Material& m) { m.density = -1.0; })); }),
             Contains("density = -1"));
  CHECK(sim.materials().size() == 0);
  // Walls may have no mass.
  CHECK_NOTHROW(sim.add_wall_material(with([](Material& m) { m.density = 0.0; })));
  // Edge values that are valid.
  CHECK_NOTHROW(sim.add_material(with([](Material& m) {
    m.poisson_ratio = 0.0;
    m.restitution = 1.0;
    m.friction = 0.0;
  })));
}

TEMPLATE_TEST_CASE("Invalid configurations are rejected with the parameter named", "[engine][errors]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  auto cfg = small_config<TestType>();
  cfg.dt = 0.0;
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin> s(cfg); }),
             Contains("dt = 0"));
  cfg.dt = -0.25;
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin> s(cfg); }),
             Contains("dt = -0.25"));
  cfg = small_config<TestType>();
  cfg.domain.hi[0] = cfg.domain.lo[0];
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin> s(cfg); }),
             Contains("hi[0] = 0"));
  cfg = small_config<TestType>();
  cfg.domain.hi[1] = -0.01;
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin> s(cfg); }),
             Contains("hi[1] = -0.01"));
  cfg = small_config<TestType>();
  cfg.skin = 1e-4;
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin, neighbours::BruteForce> s(cfg); }),
             Contains("skin = 0.0001") && Contains("BruteForce"));
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin, neighbours::LinkedCells> s(cfg); }),
             Contains("skin = 0.0001") && Contains("LinkedCells"));
  CHECK_NOTHROW(Simulation<TestType, contact::HertzMindlin, neighbours::VerletList>(cfg));
  cfg = small_config<TestType>();
  cfg.gravity[0] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin> s(cfg); }),
             Contains("gravity[0]"));
  cfg = small_config<TestType>();
  cfg.thickness = 0.0;
  CHECK_THAT(message_of<InvalidParameter>([&] { Simulation<TestType, contact::HertzMindlin> s(cfg); }),
             Contains("thickness = 0"));

  // A periodic box must exceed twice the interaction range 2 r_max + skin.
  cfg = small_config<TestType>();
  cfg.domain.periodic[1] = true;
  cfg.domain.hi[1] = 0.01;  // 10 mm < 2 (2 x 3 mm + 0.6 mm)
  Simulation<TestType, contact::HertzMindlin> small_box(cfg);
  const auto mat = small_box.add_material(test::soft_material());
  small_box.add_particle(Vec::Constant(0.005), 3e-3, mat);
  CHECK_THAT(message_of<InvalidParameter>([&] { small_box.step(); }),
             Contains("periodic length along axis 1 = 0.01") && Contains("interaction range"));
  CHECK(small_box.step_count() == 0);
}

TEMPLATE_TEST_CASE("A time step above the stability limit is refused unless explicitly allowed", "[engine][errors]",
                   Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  auto build = [](bool allow) {
    auto cfg = small_config<TestType>();
    cfg.allow_large_time_step = allow;
    auto sim = std::make_unique<Simulation<TestType, contact::HertzMindlin>>(cfg);
    const auto mat = sim->add_material(test::soft_material());
    sim->add_particle(Vec::Constant(0.02), 1e-3, mat);
    sim->add_particle(Vec::Constant(0.03), 1e-3, mat);
    return sim;
  };
  auto sim = build(false);
  const double limit = sim->suggested_time_step();
  // Rayleigh time of a 1 mm particle (Li, Xu & Thornton 2005): pi r sqrt(rho/G) / (0.1631 nu + 0.8766).
  const Material m = test::soft_material();
  const double t_r = std::acos(-1.0) * 1e-3 * std::sqrt(m.density / m.shear_modulus()) / (0.1631 * 0.3 + 0.8766);
  CHECK(sim->critical_time_step() == Approx(t_r).epsilon(1e-12));
  CHECK(limit == Approx(0.2 * t_r).epsilon(1e-12));
  sim->set_dt(1.01 * limit);
  CHECK_THAT(message_of<InvalidParameter>([&] { sim->step(); }),
             Contains("dt = ") && Contains("time_step_safety") && Contains("allow_large_time_step"));
  CHECK(sim->step_count() == 0);
  sim->set_dt(0.99 * limit);
  CHECK_NOTHROW(sim->run(3));
  CHECK(sim->step_count() == 3);
  CHECK_THAT(message_of<InvalidParameter>([&] { sim->set_dt(0.0); }),
             Contains("dt = 0"));

  auto allowed = build(true);
  allowed->set_dt(20.0 * limit);
  CHECK_NOTHROW(allowed->run(3));
  CHECK(allowed->step_count() == 3);
}

TEMPLATE_TEST_CASE("Two particles almost on top of each other stop the run with an InstabilityError",
                   "[engine][errors]", Dim2, Dim3) {
  using Vec = typename TestType::Vec;
  Simulation<TestType, contact::HertzMindlin> sim(small_config<TestType>());
  const auto mat = sim.add_material(test::soft_material());
  Vec a = Vec::Constant(0.02);
  Vec b = a;
  b[0] += 1e-5;  // overlap 1.99 mm of 1 mm radii
  const auto ia = sim.add_particle(a, 1e-3, mat);
  const auto ib = sim.add_particle(b, 1e-3, mat);
  std::string what;
  try {
    sim.step();
  } catch (const InstabilityError& e) {
    what = e.what();
  }
  INFO(what);
  REQUIRE(!what.empty());
  CHECK_THAT(what, Contains("step 0") && Contains("max_overlap_ratio"));
  // It names one of the two particles and its position (9 significant digits).
  auto names = [&](std::uint64_t id, const Vec& x) {
    std::ostringstream s;
    s.precision(9);
    s << "particle id " << id << " at (" << x[0] << ", " << x[1];
    return what.find(s.str()) != std::string::npos;
  };
  CHECK((names(ia, a) || names(ib, b)));
  CHECK(sim.particles().owned() == 2);
}

namespace {

// A particle shot at a plane with a time step 6x over the limit (allowed explicitly): it moves
// 1 mm per step and the overlap check stops the run at the step where it is 1 mm deep.
template <class D>
void check_instability_mid_run(const std::string& path) {
  using Vec = typename D::Vec;
  auto cfg = small_config<D>();
  cfg.domain.lo[1] = -0.02;  // room below the plane, so the overlap check (not the domain) fires
  cfg.dt = 1e-4;
  cfg.allow_large_time_step = true;
  Simulation<D, contact::HertzMindlin> sim(cfg);
  const auto mat = sim.add_material(test::soft_material(0.5, 0.5));
  const auto wmat = sim.add_wall_material(test::soft_material(0.5, 0.5));
  sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), Vec::Unit(1)), wmat);
  Vec x0 = Vec::Constant(0.02);
  x0[1] = 5.0e-3;
  Vec v0 = Vec::Zero();
  v0[1] = -10.0;  // [m/s]
  const auto id = sim.add_particle(x0, 1e-3, mat, v0);
  const auto spectator = sim.add_particle(Vec::Constant(0.04), 1e-3, mat);
  std::remove(path.c_str());
  sim.every(1, [&path](auto& s) {
    std::ofstream out(path, std::ios::app);
    out.precision(17);
    out << s.step_count() << " " << s.particles().x[s.index_of(0)][1] << "\n";
  });
  std::string what;
  try {
    sim.run(100);
  } catch (const InstabilityError& e) {
    what = e.what();
  }
  INFO(what);
  REQUIRE(!what.empty());
  // Steps 1..4 bring the centre to y = 4, 3, 2, 1 mm; step 5 puts it 1 mm deep (> 0.5 r).
  CHECK(sim.step_count() == 5);
  CHECK_THAT(what, Contains("step 5") && Contains("particle id " + std::to_string(id)) &&
                       Contains("with wall 0") && Contains("max_overlap_ratio"));
  // The state is intact: both particles present, finite, and the reported position is the
  // particle's current one.
  REQUIRE(sim.particles().owned() == 2);
  const auto& p = sim.particles();
  const Vec x = p.x[sim.index_of(id)];
  CHECK(x.allFinite());
  CHECK(p.x[sim.index_of(spectator)] == Vec::Constant(0.04));
  std::ostringstream pos;
  pos.precision(9);
  pos << "at (" << x[0] << ", " << x[1];
  CHECK_THAT(what, Contains(pos.str()));
  CHECK(x[1] == Approx(0.0).margin(1e-5));
  // The observer's output of steps 1..4 is complete.
  std::ifstream in(path);
  std::string line;
  std::size_t lines = 0;
  while (std::getline(in, line)) {
    ++lines;
    std::istringstream ls(line);
    std::uint64_t step = 0;
    double y = 0.0;
    ls >> step >> y;
    CHECK(step == lines);
    CHECK(y == Approx(5e-3 - 1e-3 * double(lines)).margin(1e-5));
  }
  CHECK(lines == 4);
  std::remove(path.c_str());
}

}  // namespace

TEMPLATE_TEST_CASE("A run that blows up throws InstabilityError and keeps earlier output", "[engine][errors]", Dim2,
                   Dim3) {
  check_instability_mid_run<TestType>("granule_test_instability_" + std::to_string(TestType::dim) + "d.txt");
}

TEMPLATE_TEST_CASE("A particle leaving the non-periodic domain throws InstabilityError", "[engine][errors]", Dim2,
                   Dim3) {
  using Vec = typename TestType::Vec;
  Simulation<TestType, contact::HertzMindlin> sim(small_config<TestType>());
  const auto mat = sim.add_material(test::soft_material());
  Vec x = Vec::Constant(0.025);
  x[0] = 0.049;
  Vec v = Vec::Zero();
  v[0] = 10.0;  // leaves through x = 0.05 m after ~100 steps of 1 us
  const auto id = sim.add_particle(x, 1e-3, mat, v);
  std::string what;
  try {
    sim.run(1000);
  } catch (const InstabilityError& e) {
    what = e.what();
  }
  INFO(what);
  REQUIRE(!what.empty());
  CHECK_THAT(what, Contains("particle id " + std::to_string(id)) && Contains("left the non-periodic domain") &&
                       Contains("step " + std::to_string(sim.step_count())));
  // Detected at the first neighbour rebuild after leaving: within skin/2 = 0.1 mm of the face.
  const double xs = sim.particles().x[0][0];
  CHECK(xs > 0.05);
  CHECK(xs < 0.05 + 1e-4 + 1e-5);
}

// The finiteness test runs in the step's second kick (Simulation::step): a prescribed velocity
// that turns NaN after t = 3.25 dt puts the particle's position at NaN in step 4's drift, which
// no contact and no rebuild notices (NaN compares false); the run must stop at that step,
// naming the particle, with the other particle's state untouched by NaN.
TEMPLATE_TEST_CASE("A non-finite position stops the run at the step it appears", "[engine][errors]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  auto cfg = small_config<D>();
  Simulation<D, contact::HertzMindlin> sim(cfg);
  const auto mat = sim.add_material(test::soft_material(0.5, 0.5));
  const double dt = sim.config().dt;
  const auto bad = sim.add_particle(Vec::Constant(0.01), 1e-3, mat, Vec::Zero(), 2);
  sim.prescribe_group_velocity(2, [dt](double t) {
    Vec v = Vec::Zero();
    v[0] = t > 3.25 * dt ? std::numeric_limits<double>::quiet_NaN() : 0.01;
    return v;
  });
  const auto other = sim.add_particle(Vec::Constant(0.04), 1e-3, mat);
  const std::string what = message_of<InstabilityError>([&] { sim.run(100); });
  INFO(what);
  CHECK(sim.step_count() == 4);
  CHECK_THAT(what, Contains("step 4") && Contains("particle id " + std::to_string(bad)) &&
                       Contains("not finite"));
  const auto& p = sim.particles();
  CHECK(p.x[sim.index_of(other)].allFinite());
  CHECK(p.v[sim.index_of(other)].allFinite());
}

// A particle that cannot fit in the box, or that a wall overlaps by more than max_overlap_ratio
// x its radius (it pokes through the wall), is refused where it is added; the first step would
// otherwise stop as unstable (or, for a particle wider than the box, never settle).
TEMPLATE_TEST_CASE("add_particle refuses a particle larger than the box or through a wall", "[engine][errors]", Dim2,
                   Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  Simulation<D, contact::HertzMindlin> sim(small_config<D>());  // box [0, 0.05] m
  const auto mat = sim.add_material(test::soft_material());
  const auto wmat = sim.add_wall_material(test::soft_material());
  const Vec centre = Vec::Constant(0.025);
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(centre, 0.03, mat); }),
             Contains("radius = 0.029999999999999999") && Contains("(0, 0.025000000000000001] m") &&
                 Contains("does not fit in the box"));
  const auto floor = sim.add_wall(geometry::PlaneShape<D>(Vec::Constant(0.01), Vec::Unit(D::dim - 1)), wmat);
  Vec x = centre;
  x[D::dim - 1] = 0.01 + 0.4e-3;  // 0.6 mm deep for a 1 mm radius: more than half of it
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(x, 1e-3, mat); }),
             Contains("overlaps wall 0 by 0.0006") && Contains("max_overlap_ratio (0.5)") && Contains("pokes through"));
  x[D::dim - 1] = 0.01 - 2e-3;  // the centre behind the wall
  CHECK_THAT(message_of<InvalidParameter>([&] { sim.add_particle(x, 1e-3, mat); }), Contains("pokes through"));
  CHECK(sim.particles().owned() == 0);
  // A shallower overlap is an ordinary contact; an inactive wall is not checked.
  x[D::dim - 1] = 0.01 + 0.6e-3;
  CHECK_NOTHROW(sim.add_particle(x, 1e-3, mat));
  sim.set_wall_active(floor, false);
  x[D::dim - 1] = 0.01 + 0.1e-3;
  x[0] += 0.01;
  CHECK_NOTHROW(sim.add_particle(x, 1e-3, mat));
  CHECK(sim.particles().owned() == 2);
}
