// Exact restart: running 2N steps equals running N, writing a checkpoint, reading it into a
// freshly built scene and running N more -- bitwise. Damaged or mismatched files are refused.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <granule/granule.hpp>
#include <granule/io/checkpoint.hpp>

using namespace granule;

namespace {

template <class D, class Model = contact::HertzMindlinEpsd>
struct Scene {
  using Vec = typename D::Vec;
  using Sim = Simulation<D, Model, neighbours::VerletList>;
  std::unique_ptr<Sim> sim;

  Scene() {
    SimulationConfig<D> cfg;
    cfg.domain.lo = Vec::Zero();
    cfg.domain.hi = Vec::Constant(0.02);
    cfg.domain.periodic[0] = true;
    if constexpr (D::dim == 3) cfg.domain.periodic[1] = true;
    cfg.gravity = -9.81 * Vec::Unit(D::dim - 1);
    cfg.dt = 2e-6;
    cfg.skin = 1e-4;
    cfg.thickness = 1e-3;
    sim = std::make_unique<Sim>(cfg);
    Material m;
    m.youngs_modulus = 5e6;
    m.poisson_ratio = 0.3;
    m.density = 1100;
    m.restitution = 0.5;
    m.friction = 0.5;
    m.rolling_friction = 0.1;
    m.rolling_damping = 0.3;
    const auto mat = sim->add_material(m);
    const auto wall = sim->add_wall_material(m);
    sim->add_wall(geometry::PlaneShape<D>(Vec::Zero(), Vec::Unit(D::dim - 1)), wall);
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    // A loose column of particles on a lattice with jitter, falling onto the floor.
    const double r = 5e-4;
    int placed = 0;
    for (int a = 0; a < 12 && placed < 150; ++a)
      for (int b = 0; b < 12 && placed < 150; ++b)
        for (int c = 0; c < (D::dim == 3 ? 6 : 1) && placed < 150; ++c) {
          Vec x;
          x[0] = 1e-3 + a * 1.6e-3 + 2e-4 * u(rng);
          x[D::dim - 1] = 1e-3 + b * 1.6e-3;
          if constexpr (D::dim == 3) x[1] = 1e-3 + c * 1.6e-3 + 2e-4 * u(rng);
          const double rr = r * (0.8 + 0.4 * u(rng));
          Vec v = Vec::Zero();
          v[0] = 0.05 * (u(rng) - 0.5);
          v[D::dim - 1] = -1.0;
          sim->add_particle(x, rr, mat, v);
          ++placed;
        }
  }
};

template <class Sim>
void require_same_state(const Sim& a, const Sim& b) {
  const auto& pa = a.particles();
  const auto& pb = b.particles();
  REQUIRE(pa.owned() == pb.owned());
  REQUIRE(a.time() == b.time());
  REQUIRE(a.step_count() == b.step_count());
  for (std::size_t i = 0; i < pa.owned(); ++i) {
    REQUIRE(pa.id[i] == pb.id[i]);
    REQUIRE(pa.x[i] == pb.x[i]);  // bitwise
    REQUIRE(pa.v[i] == pb.v[i]);
    REQUIRE(pa.omega[i] == pb.omega[i]);
  }
}

std::string checkpoint_temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("granule_ckpt_" + name)).string();
}

}  // namespace

TEMPLATE_TEST_CASE("checkpoint restart is bitwise exact", "[restart]", Dim2, Dim3) {
  using D = TestType;
  const std::uint64_t n = 2500;
  Scene<D> straight;
  straight.sim->run(2 * n);

  Scene<D> first;
  first.sim->run(n);
  const std::string path = checkpoint_temp_path("exact_" + std::to_string(D::dim));
  io::write_checkpoint(*first.sim, path, {7, 11});
  REQUIRE(std::filesystem::exists(path));
  REQUIRE_FALSE(std::filesystem::exists(path + ".tmp"));

  Scene<D> resumed;
  const auto user = io::read_checkpoint(*resumed.sim, path);
  REQUIRE(user == std::vector<std::uint64_t>{7, 11});
  REQUIRE(resumed.sim->step_count() == n);
  resumed.sim->run(n);
  // The run must have rebuilt its list several times and carried frictional history.
  REQUIRE(straight.sim->neighbour_list().builds > 3);
  REQUIRE(straight.sim->contact_count() > 15);
  require_same_state(*straight.sim, *resumed.sim);
  std::filesystem::remove(path);
}

TEST_CASE("checkpoint refuses damaged and mismatched files", "[restart]") {
  Scene<Dim3> s3;
  s3.sim->run(10);
  const std::string path = checkpoint_temp_path("refuse");
  io::write_checkpoint(*s3.sim, path);
  const auto size = std::filesystem::file_size(path);

  SECTION("truncated") {
    std::filesystem::resize_file(path, size - 100);
    Scene<Dim3> other;
    REQUIRE_THROWS_WITH(io::read_checkpoint(*other.sim, path), Catch::Contains("truncated"));
  }
  SECTION("corrupted byte") {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.put('\x5a');
    f.close();
    Scene<Dim3> other;
    REQUIRE_THROWS_WITH(io::read_checkpoint(*other.sim, path), Catch::Contains("checksum"));
  }
  SECTION("foreign file") {
    std::ofstream(path, std::ios::trunc) << "solid not-a-checkpoint\nendsolid\n and some more text to be long enough";
    Scene<Dim3> other;
    REQUIRE_THROWS_WITH(io::read_checkpoint(*other.sim, path), Catch::Contains("not a granule checkpoint"));
  }
  SECTION("wrong dimension") {
    Scene<Dim2> other;
    REQUIRE_THROWS_WITH(io::read_checkpoint(*other.sim, path), Catch::Contains("3D"));
  }
  SECTION("wrong contact model") {
    Scene<Dim3, contact::HertzMindlin> other;
    REQUIRE_THROWS_WITH(io::read_checkpoint(*other.sim, path), Catch::Contains("EpsdRolling"));
  }
  SECTION("missing file") {
    Scene<Dim3> other;
    REQUIRE_THROWS_AS(io::read_checkpoint(*other.sim, path + ".absent"), IoError);
  }
  std::filesystem::remove(path);
}
