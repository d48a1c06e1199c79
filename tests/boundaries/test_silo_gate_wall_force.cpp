// Issue 29: boundaries of the classic validation scenes.
//  - CylinderContainerShape / CircleContainerShape: particles inside a cylinder (silo, drum).
//    The wall pass treats each surface point as a flat wall (R* = r): a sphere resting on the
//    concave side carries its weight with the flat-wall Hertz overlap (Johnson 1985, eq. 4.23),
//    delta = (3 F / (4 E* sqrt(r)))^(2/3), not the concave one (principal radii r and
//    r Rc / (Rc - r), R* = sqrt(r^2 Rc / (Rc - r)): about 3.8 % less overlap at Rc = 5 r).
//  - Simulation::set_wall_active: a gate that opens; the particles then fall freely.
//  - Wall::force / torque: the force of the particles on each wall, beside Body::force.
//  - Checkpoints keep the switch: a restart across the opening is bitwise.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <random>

#include <granule/granule.hpp>
#include <granule/boundaries/geometry/display_mesh.hpp>
#include <granule/io/checkpoint.hpp>

#include "../engine/engine_helpers.hpp"
#include "../geometry/surface_checks.hpp"

using namespace granule;
using V3 = Eigen::Vector3d;

namespace {

double hertz_overlap(double force, double e_eff, double r_eff) {
  return std::pow(3.0 * force / (4.0 * e_eff * std::sqrt(r_eff)), 2.0 / 3.0);
}

template <class D>
SimulationConfig<D> box_config(double size, double dt) {
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(size);
  cfg.dt = dt;
  cfg.thickness = 1e-3;
  cfg.gravity = Vec::Zero();
  cfg.gravity[1] = -9.81;
  return cfg;
}

}  // namespace

TEST_CASE("CylinderContainerShape: side, rim beyond an open end, caps of a closed drum", "[geometry][cylinder]") {
  using geometry::CylinderContainerShape;
  const CylinderContainerShape tube(V3(1, 1, 1), V3(0, 0, 2), 1.0, 2.0);
  // Inside: side at distance R - rho, normal towards the axis.
  test::check_point(tube.closest(V3(1.7, 1, 1.5)), 0.3, V3(-1, 0, 0), V3(2, 1, 1.5), 1e-14);
  test::check_point(tube.closest(V3(1, 0.4, 2.9)), 0.4, V3(0, 1, 0), V3(1, 0, 2.9), 1e-14);
  // Escaped radially: negative distance, pushed back in.
  test::check_point(tube.closest(V3(2.1, 1, 1)), -0.1, V3(-1, 0, 0), V3(2, 1, 1), 1e-14);
  // Beyond the open upper end (h = 2.4 > H = 2): nearest is the rim (2, 1, 3); offsets
  // (-0.3 radial, 0.4 axial) -> distance 0.5, normal (-0.6, 0, 0.8).
  test::check_point(tube.closest(V3(1.7, 1, 3.4)), 0.5, V3(-0.6, 0, 0.8), V3(2, 1, 3), 1e-14);
  // Continuous across the end: at h = H the rim distance equals the side distance.
  CHECK(tube.closest(V3(1.7, 1, 3.0 + 1e-12)).distance == Approx(0.3).margin(1e-11));
  // Open: a particle on the axis far below sees no cap.
  int calls = 0;
  tube.for_each_contact(V3(1, 1, -0.9), 0.2, [&](const auto&) { ++calls; });
  CHECK(calls == 0);

  const CylinderContainerShape drum(V3::Zero(), V3(1, 0, 0), 0.5, 0.3, true);
  // Near the lower cap (x = -0.3) and the side (rho = 0.5) at once: two contacts.
  std::vector<geometry::SurfacePoint<Dim3>> hits;
  drum.for_each_contact(V3(-0.25, 0, -0.42), 0.1, [&](const auto& s) { hits.push_back(s); });
  REQUIRE(hits.size() == 2);
  test::check_point(hits[0], 0.08, V3(0, 0, 1), V3(-0.25, 0, -0.5), 1e-14);
  CHECK(hits[0].feature == 0u);
  test::check_point(hits[1], 0.05, V3(1, 0, 0), V3(-0.3, 0, -0.42), 1e-14);
  CHECK(hits[1].feature == 1u);
  test::check_point(drum.closest(V3(0.28, 0.1, 0)), 0.02, V3(-1, 0, 0), V3(0.3, 0.1, 0), 1e-14);
  CHECK(drum.closest(V3(0.28, 0.1, 0)).feature == 2u);
  // Closed: the side is the infinite cylinder, also beyond the caps.
  CHECK(drum.side(V3(0.5, 0.4, 0)).distance == Approx(0.1));
  for (const V3& x : {V3(0.1, 0.2, 0.3), V3(0.35, -0.1, 0.2), V3(0, 0, 0)}) test::check_convention(x, drum.closest(x));
  CHECK_THROWS_AS(CylinderContainerShape(V3::Zero(), V3::Zero(), 1.0, 1.0), InvalidParameter);
  CHECK_THROWS_AS(CylinderContainerShape(V3::Zero(), V3(0, 0, 1), 0.0, 1.0), InvalidParameter);

  const geometry::CircleContainerShape circle(Eigen::Vector2d(1, 2), 0.5);
  test::check_point(circle.closest(Eigen::Vector2d(1.3, 2.4)), 0.0, Eigen::Vector2d(-0.6, -0.8),
                    Eigen::Vector2d(1.3, 2.4), 1e-14);
  test::check_point(circle.closest(Eigen::Vector2d(1, 1.6)), 0.1, Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 1.5),
                    1e-14);

  // Display: an open tube is its side (2 triangles per facet), a closed drum has the cap fans
  // too; every vertex lies on the surface.
  CHECK(geometry::tessellate(tube, 16).triangles.size() == 32u);
  const auto closed_mesh = geometry::tessellate(drum, 16);
  CHECK(closed_mesh.triangles.size() == 64u);
  for (const auto& v : closed_mesh.points) CHECK(std::abs(drum.closest(v).distance) < 1e-14);
  const auto ring = geometry::tessellate(circle, 16);
  CHECK(ring.lines.size() == ring.points.size());
  for (const auto& v : ring.points) CHECK(std::abs(circle.closest(Eigen::Vector2d(v.x(), v.y())).distance) < 1e-14);
}

// A sphere (disk) resting at the bottom of a horizontal cylinder (circle) under gravity -y.
// Reference: the wall carries exactly the weight m g, and the overlap is the flat-wall Hertz
// overlap delta = (3 m g / (4 E* sqrt(r)))^(2/3) (the wall pass uses R* = r). The tolerance
// 1e-9 is far below the 3.8 % a concave R* would make.
TEMPLATE_TEST_CASE("A particle at rest inside a cylinder loads its side with its weight (flat-wall Hertz)",
                   "[engine][statics][cylinder]", Dim2, Dim3) {
  using D = TestType;
  using Vec = typename D::Vec;
  const auto cfg = box_config<D>(0.02, 1e-5);
  Simulation<D, contact::HertzMindlin> sim(cfg);
  const Material m = test::soft_material(0.1, 0.5);
  const auto mat = sim.add_material(m);
  const auto wmat = sim.add_wall_material(m);
  const double r = 1e-3, rc = 5e-3;
  const Vec c = Vec::Constant(0.01);
  std::uint32_t wall = 0;
  if constexpr (D::dim == 3) {
    wall = sim.add_wall(geometry::CylinderContainerShape(c, V3(1, 0, 0), rc, 0.009), wmat);
  } else {
    wall = sim.add_wall(geometry::CircleContainerShape(c, rc), wmat);
  }
  Vec x = c;
  x[1] = c[1] - rc + r;  // touching, zero overlap
  const auto id = sim.add_particle(x, r, mat);
  const Vec weight = sim.particles().mass[0] * cfg.gravity;
  sim.run(3000);
  const double overlap = r - (sim.particles().x[sim.index_of(id)][1] - (c[1] - rc));
  const double expected = hertz_overlap(weight.norm(), mix(m, m).E_eff, r);
  const Vec f_wall = sim.wall(wall).force;
  INFO("dim " << D::dim << ": wall force " << f_wall.transpose() << " N, weight " << weight.transpose()
              << " N; overlap " << overlap << " m, flat-wall Hertz " << expected << " m");
  CHECK(sim.contact_count() == 1);
  CHECK((f_wall - weight).norm() < 1e-9 * weight.norm());
  CHECK(overlap == Approx(expected).epsilon(1e-9));
  CHECK(f_wall == sim.body(0).force);  // the world's only wall: the same sum, bitwise
}

// A closed drum rotating about its axis (x) at Omega on a body whose origin is on the axis, a
// sphere at its bottom spinning at the rolling speed omega = Omega Rc / (r - delta) (the arm the
// wall pass uses: centre to contact point), so the contact does not slip. Reference: the sphere
// stays where it is, keeps its spin, and the drum carries its weight, with no torque about the
// axis (no friction). A wrong wall velocity (pose rotation, lever arm) would make the contact
// slip and friction (mu = 0.5) would move the sphere by millimetres within the run.
TEST_CASE("A sphere rolling in place at the bottom of a rotating drum", "[engine][cylinder][kinematics]") {
  using D = Dim3;
  const auto cfg = box_config<D>(0.02, 1e-5);
  Simulation<D, contact::HertzMindlin> sim(cfg);
  const Material m = test::soft_material(0.1, 0.5);
  const auto mat = sim.add_material(m);
  const auto wmat = sim.add_wall_material(m);
  const double r = 1e-3, rc = 5e-3, omega = 3.0;  // [m], [m], [rad/s]
  const V3 c = V3::Constant(0.01);
  Body<D> drum;
  drum.name = "drum";
  drum.pose = geometry::Pose<D>::translation(c);
  drum.angular_velocity = [omega](double) { return V3(omega, 0, 0); };
  const auto b = sim.add_body(drum);
  const auto wall = sim.add_wall(geometry::CylinderContainerShape(V3::Zero(), V3(1, 0, 0), rc, 0.004, true), wmat, b);
  const double mass = m.density * 4.0 / 3.0 * M_PI * r * r * r;
  const double delta = hertz_overlap(mass * 9.81, mix(m, m).E_eff, r);
  const V3 x0(c.x(), c.y() - rc + r - delta, c.z());
  sim.add_particle(x0, r, mat);
  sim.particles().omega[0] = V3(omega * rc / (r - delta), 0, 0);
  const V3 spin0 = sim.particles().omega[0];
  sim.run(10000);  // 0.1 s: the drum turns 0.3 rad
  const V3 dx = sim.particles().x[0] - x0;
  const V3 f_wall = sim.wall(wall).force;
  INFO("displacement " << dx.transpose() << " m, spin " << sim.particles().omega[0].transpose()
                       << " rad/s (start " << spin0.x() << "), drum force " << f_wall.transpose()
                       << " N, torque " << sim.wall(wall).torque.transpose() << " N m, weight " << mass * 9.81);
  CHECK(Eigen::AngleAxisd(sim.body(b).pose.rotation()).angle() == Approx(omega * sim.time()).epsilon(1e-9));
  CHECK(dx.norm() < 1e-9);
  CHECK((sim.particles().omega[0] - spin0).norm() < 1e-6 * spin0.norm());
  CHECK((f_wall - mass * cfg.gravity).norm() < 1e-6 * mass * 9.81);
  CHECK(std::abs(sim.wall(wall).torque.x()) < 1e-9 * mass * 9.81 * rc);
  // The body's readout is the wall's (one wall on the body), bitwise.
  CHECK(sim.body(b).force == f_wall);
  CHECK(sim.body(b).torque == sim.wall(wall).torque);
}

namespace {

// A silo: an open vertical tube (axis y) of radius 2.6 r on the world body, closed below by a
// plane gate on its own fixed body, with `count` spheres dropped in from random heights.
struct Silo {
  using D = Dim3;
  using Sim = Simulation<D, contact::HertzMindlin>;
  static constexpr double r = 1e-3, rc = 2.6e-3;
  std::unique_ptr<Sim> sim;
  std::uint32_t tube = 0, gate = 0, gate_body = 0;

  explicit Silo(int count) {
    auto cfg = box_config<D>(0.04, 1e-5);
    cfg.skin = 2e-4;
    sim = std::make_unique<Sim>(cfg);
    const Material m = test::soft_material(0.3, 0.5);
    const auto mat = sim->add_material(m);
    const auto wmat = sim->add_wall_material(m);
    const V3 c(0.02, 0.025, 0.02);
    tube = sim->add_wall(geometry::CylinderContainerShape(c, V3(0, 1, 0), rc, 0.015), wmat);
    gate_body = sim->add_body(Body<D>{});
    gate = sim->add_wall(geometry::PlaneShape<D>(V3(0, 0.01, 0), V3(0, 1, 0)), wmat, gate_body);
    std::mt19937_64 rng(29);
    for (int k = 0; k < count; ++k) {
      const double a = test::uniform(rng, 0.0, 2 * M_PI), s = test::uniform(rng, 0.0, rc - r - 1e-4);
      sim->add_particle(V3(c.x() + s * std::cos(a), 0.0115 + 2.1e-3 * k, c.z() + s * std::sin(a)), r, mat);
    }
  }
};

}  // namespace

// A column of 12 spheres settled in the silo. Reference: at rest the floor (gate) and the side
// together carry the total weight, sum m g, to the settle tolerance (the kinetic energy left,
// checked below); the side takes part of it through friction (Janssen). Per-wall readout: the
// gate is the only wall of its body, so its force is the body's bitwise; the tube's force is the
// world body's (its only wall).
TEST_CASE("Silo column: floor and side wall forces sum to the weight", "[engine][cylinder][wall_force]") {
  Silo silo(12);
  auto& sim = *silo.sim;
  double mass = 0.0;
  for (std::size_t i = 0; i < sim.particles().owned(); ++i) mass += sim.particles().mass[i];
  const V3 weight = mass * sim.config().gravity;
  sim.run(60000);  // 0.6 s
  const V3 f_gate = sim.wall(silo.gate).force, f_tube = sim.wall(silo.tube).force;
  INFO("gate " << f_gate.transpose() << " N, tube " << f_tube.transpose() << " N, weight " << weight.transpose()
               << " N, kinetic energy " << sim.kinetic_energy() << " J");
  CHECK(sim.kinetic_energy() < 1e-12);
  CHECK((f_gate + f_tube - weight).norm() < 1e-4 * weight.norm());
  // The side takes part through friction (Janssen). Which way depends on the column's last
  // slip: the baseline build settles with the side carrying weight, -march=native's fused
  // multiply-adds give another trajectory whose last rebound leaves the side pressing the
  // column down (+7e-5 N); both are static states.
  CHECK(std::abs(f_tube.y()) > 0.01 * weight.norm());
  CHECK(f_gate == sim.body(silo.gate_body).force);
  CHECK(f_tube == sim.body(0).force);
  // Against the recorded contacts of one more step: a wall's force is minus the sum of the
  // forces on the particles touching it, fn n + ft, and its torque about a point q minus the
  // sum of (contact point - q) x (fn n + ft); wall_torque_about moves the readout's reference
  // point (the body origin) to q with T_q = T_o + (o - q) x F.
  sim.request_contacts();
  sim.run(1);
  const V3 q(0.02, 0.012, 0.021);
  for (const std::uint32_t w : {silo.tube, silo.gate}) {
    V3 f = V3::Zero(), t = V3::Zero();
    int touching = 0;
    for (const auto& c : sim.recorded_contacts()) {
      if (c.j != c.kWall || c.wall != w) continue;
      const V3 fi = c.fn * c.normal + c.ft;
      f -= fi;
      t -= (c.contact_point - q).cross(fi);
      ++touching;
    }
    INFO("wall " << w << ": " << touching << " contacts, readout " << sim.wall(w).force.transpose() << " N, "
                 << sim.wall_torque_about(w, q).transpose() << " N m; from the contacts " << f.transpose() << " N, "
                 << t.transpose() << " N m");
    CHECK(touching > 0);
    CHECK((sim.wall(w).force - f).norm() < 1e-10 * weight.norm());
    CHECK((sim.wall_torque_about(w, q) - t).norm() < 1e-10 * weight.norm() * 0.01);
  }
}

// A single sphere resting on the closed gate (away from the side), then the gate opens.
// Reference: free fall from rest, z(t) = z0 - g t^2 / 2. The step before the opening still gives
// its force F0 (the contact balancing the weight, to the settle residue) to the first half kick,
// so velocity Verlet gives exactly z_n = z0 + n dt v_1/2 - g dt^2 n (n - 1) / 2 with
// v_1/2 = v0 + dt F0 / (2 m): checked to 1e-12 m; against the continuous fall it lags by
// g t dt / 2 (plus |v_1/2| t). The gate's contact, history and force are gone.
TEST_CASE("An opened gate lets a resting sphere fall freely", "[engine][wall_active]") {
  Silo silo(1);
  auto& sim = *silo.sim;
  sim.run(30000);
  REQUIRE(sim.kinetic_energy() < 1e-14);
  REQUIRE(sim.wall(silo.gate).force.y() < 0.0);
  const double y0 = sim.particles().x[0].y(), g = 9.81, dt = sim.dt();
  const double v_half = sim.particles().v[0].y() + 0.5 * dt * sim.particles().f[0].y() / sim.particles().mass[0];
  const std::size_t entries_before = sim.neighbour_list().wall.size();
  sim.set_wall_active(silo.gate, false);
  CHECK_FALSE(sim.wall(silo.gate).active);
  const int n = 500;
  sim.run(n);
  const double t = n * dt;
  const double y = sim.particles().x[0].y();
  INFO("y0 " << y0 << " m, after " << t << " s: " << y << " m, free fall " << y0 - 0.5 * g * t * t << " m");
  CHECK(std::abs(y - (y0 - 0.5 * g * t * t)) <= 0.5 * g * t * dt + std::abs(v_half) * t + 1e-12);
  CHECK(y == Approx(y0 + n * dt * v_half - 0.5 * g * dt * dt * n * (n - 1)).margin(1e-12));
  CHECK(sim.contact_count() == 0);
  CHECK(sim.wall(silo.gate).force == V3::Zero());
  for (const auto& e : sim.neighbour_list().wall) CHECK(e.wall != silo.gate);
  CHECK(sim.neighbour_list().wall.size() < entries_before);
  // Switching to the state it has is no change (no rebuild).
  const auto builds = sim.neighbour_list().builds;
  sim.set_wall_active(silo.gate, false);
  sim.run(1);
  CHECK(sim.neighbour_list().builds == builds);
  CHECK_THROWS_AS(sim.set_wall_active(7, false), InvalidParameter);
}

// A sphere pushed sideways on the gate loads the tangential spring (10 steps of slip, below the
// Coulomb limit); the gate is switched off for one step and on again. Reference: a re-activated
// wall starts with fresh contacts, so its history is that of a first touch (one step's
// increment, about a tenth of the loaded spring), not the loaded spring.
TEST_CASE("A re-activated wall starts with fresh contact history", "[engine][wall_active]") {
  Silo silo(1);
  auto& sim = *silo.sim;
  sim.run(30000);
  // Push: the spring takes up a slip of about 1 mm/s for 10 steps, 0.1 um (Coulomb: ~0.2 um).
  sim.particles().v[0] = V3(1e-3, 0, 0);
  sim.run(10);
  const auto gate_state = [&]() {
    const auto& l = sim.neighbour_list();
    for (std::size_t e = 0; e < l.wall.size(); ++e)
      if (l.wall[e].wall == silo.gate) return l.wall_state[e];
    return Silo::Sim::State{};
  };
  const double loaded = gate_state().tangential.xi.norm();
  REQUIRE(loaded > 5e-8);
  sim.set_wall_active(silo.gate, false);
  sim.run(1);
  sim.set_wall_active(silo.gate, true);
  sim.run(1);
  const double fresh = gate_state().tangential.xi.norm();
  INFO("tangential displacement before " << loaded << " m, after re-activation " << fresh << " m");
  CHECK(fresh < 0.2 * loaded);
}

// Restart across the opening: N steps, open, M steps, against N steps, open, write a checkpoint,
// read it into a freshly built scene (all walls active), M steps -- and against a checkpoint
// written before the opening, opened after reading. Bitwise, and with the same wall forces.
TEST_CASE("A checkpoint restart across a gate opening is bitwise", "[engine][wall_active][restart]") {
  const std::uint64_t n = 20000, m = 3000;
  Silo straight(12);
  straight.sim->run(n);
  straight.sim->set_wall_active(straight.gate, false);
  straight.sim->run(m);

  const auto path = (std::filesystem::temp_directory_path() / "granule_ckpt_gate").string();
  for (int before = 0; before < 2; ++before) {
    Silo first(12);
    first.sim->run(n);
    if (!before) first.sim->set_wall_active(first.gate, false);
    io::write_checkpoint(*first.sim, path);
    Silo resumed(12);
    io::read_checkpoint(*resumed.sim, path);
    CHECK(resumed.sim->wall(resumed.gate).active == (before == 1));
    if (before) resumed.sim->set_wall_active(resumed.gate, false);
    resumed.sim->run(m);
    const auto& a = straight.sim->particles();
    const auto& b = resumed.sim->particles();
    REQUIRE(a.owned() == b.owned());
    bool same = true;
    for (std::size_t i = 0; i < a.owned(); ++i) same = same && a.x[i] == b.x[i] && a.v[i] == b.v[i] && a.omega[i] == b.omega[i];
    INFO("checkpoint written " << (before ? "before" : "after") << " the opening");
    CHECK(same);
    CHECK(straight.sim->wall(straight.tube).force == resumed.sim->wall(resumed.tube).force);
    CHECK(straight.sim->body(0).force == resumed.sim->body(0).force);
  }
  // The gate opened: the column has fallen out of the tube's lower end past the old gate.
  double lowest = 1.0;
  for (std::size_t i = 0; i < straight.sim->particles().owned(); ++i)
    lowest = std::min(lowest, straight.sim->particles().x[i].y());
  CHECK(lowest < 0.01);
  std::filesystem::remove(path);
}
