// Paper 002's pull-out cell for the 2D benchmarks (bench_scene_pull_out_2d and the in-run
// comparison benchmarks/inrun/pull_out_2d_inrun.cpp): the model, the constants and the walls.
// Included inside a namespace in which `granule` names the engine (the in-run comparison
// includes it twice, once for an older engine renamed granule_before); it includes nothing
// itself, so the includer has included <granule/granule.hpp>, sphero_line.hpp, <memory> and
// <numbers> first.
using Vec = granule::Dim2::Vec;
using Sim = granule::Simulation<granule::Dim2, granule::contact::LinearCoulombRolling, granule::neighbours::VerletList>;

constexpr double kWidth = 0.100;        // cell width W [m] (002 section 2.3)
constexpr double kBedHeight = 0.150;    // 002's bed for 1600 disks [m]
constexpr double kDiameter = 3e-3;      // mean diameter d [m]
constexpr double kRmin = 1e-3, kRmax = 2e-3;  // [m]
constexpr double kCap = 1e-3;           // cap radius of the walls and of the intruder [m]
constexpr double kIntruderLength = 0.010;  // [m], caps included
constexpr double kTop = 5.0 * kBedHeight;  // walls and domain reach this high [m]

struct Scene {
  std::unique_ptr<Sim> sim;
  std::uint32_t material = 0, intruder = 0;
};

// The cell of 002 section 2.3: floor and sides as sphero-lines whose surfaces are y = 0, x = 0
// and x = W, and the intruder, a horizontal sphero-line on its own body just above the floor.
inline Scene make_scene(double youngs_modulus, bool packed) {
  using namespace granule;
  SimulationConfig<Dim2> cfg;
  cfg.domain.lo = Vec(-0.01, -0.01);
  cfg.domain.hi = Vec(kWidth + 0.01, kTop + 0.01);
  cfg.gravity = Vec(0.0, -9.81);
  cfg.thickness = kDiameter;
  cfg.packed_contacts = packed;
  Material m;
  m.name = "glass";
  m.youngs_modulus = youngs_modulus;
  m.poisson_ratio = 0.25;
  m.density = 2500.0;
  m.restitution = 0.9;
  m.friction = 0.5;
  m.reference_length = kDiameter;  // k_n = E d
  m.tangential_stiffness_ratio = 0.5;
  m.rolling_friction = 4.0 * 0.5 * 1e-2;                          // mu_r = 4 mu 1e-2
  m.rolling_stiffness_factor = 1e-3 * 16.0 / (0.02 * 0.02);       // c = 40
  const double m_min = m.density * std::numbers::pi * kRmin * kRmin * kDiameter;
  cfg.dt = 0.2 * linear_critical_time(youngs_modulus * kDiameter, 0.5 * m_min, m.restitution);
  Scene s;
  s.sim = std::make_unique<Sim>(cfg);
  Sim& sim = *s.sim;
  s.material = sim.add_material(m);
  const auto wall_mat = sim.add_wall_material(m);
  sim.add_wall(geometry::SpheroLineShape(Vec(-kCap, -kCap), Vec(kWidth + kCap, -kCap), kCap), wall_mat);
  sim.add_wall(geometry::SpheroLineShape(Vec(-kCap, -kCap), Vec(-kCap, kTop), kCap), wall_mat);
  sim.add_wall(geometry::SpheroLineShape(Vec(kWidth + kCap, -kCap), Vec(kWidth + kCap, kTop), kCap), wall_mat);
  Body<Dim2> b;
  b.name = "intruder";
  b.pose = geometry::Pose<Dim2>::translation(Vec(0.5 * kWidth, 0.5 * kRmin + kCap));
  s.intruder = sim.add_body(b);
  const double half = 0.5 * kIntruderLength - kCap;
  sim.add_wall(geometry::SpheroLineShape(Vec(-half, 0.0), Vec(half, 0.0), kCap), wall_mat, s.intruder);
  return s;
}
