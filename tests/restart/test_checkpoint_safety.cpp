// Checkpoint loads are all or nothing: a refused file (another dt, wall count or materials, or a
// crafted state with sizes, indices or values out of range) leaves the simulation bitwise as it
// was, so a caller that catches the error runs on unharmed. Materials are recorded and compared;
// files of formats 3 and 4 still load; I/O failures are IoError with the system's reason; time
// is t0 + (steps since the last dt change) x dt, continued bitwise across a restart.
#include <catch2/catch.hpp>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <system_error>
#include <vector>

#include <sys/resource.h>

#include <granule/granule.hpp>
#include <granule/io/checkpoint.hpp>
#include <granule/io/stl.hpp>

using namespace granule;
using Catch::Matchers::Contains;

namespace ckpt_safety {

using Vec = Dim3::Vec;
using Sim = Simulation<Dim3, contact::HertzMindlinEpsd, neighbours::VerletList>;

struct Options {
  double dt = 2e-6;
  double friction = 0.5;
  bool extra_wall = false;     // a lid: one wall more than the source scene
  bool pair_override = false;  // set_pair on the grain-wall pair
};

// 150 grains falling onto a floor in a box periodic in x and y (as tests/restart/test_checkpoint.cpp).
std::unique_ptr<Sim> make(const Options& o = {}) {
  SimulationConfig<Dim3> cfg;
  cfg.domain.lo = Vec::Zero();
  cfg.domain.hi = Vec::Constant(0.02);
  cfg.domain.periodic[0] = cfg.domain.periodic[1] = true;
  cfg.gravity = Vec(0, 0, -9.81);
  cfg.dt = o.dt;
  cfg.skin = 1e-4;
  auto sim = std::make_unique<Sim>(cfg);
  Material m;
  m.name = "grain";
  m.youngs_modulus = 5e6;
  m.poisson_ratio = 0.3;
  m.density = 1100;
  m.restitution = 0.5;
  m.friction = o.friction;
  m.rolling_friction = 0.1;
  m.rolling_damping = 0.3;
  const auto mat = sim->add_material(m);
  m.name = "floor";
  const auto wall = sim->add_wall_material(m);
  if (o.pair_override) {
    PairOverride po;
    po.friction = 0.2;
    sim->set_pair(mat, wall, po);
  }
  sim->add_wall(geometry::PlaneShape<Dim3>(Vec::Zero(), Vec::UnitZ()), wall);
  if (o.extra_wall) sim->add_wall(geometry::PlaneShape<Dim3>(Vec(0, 0, 0.02), -Vec::UnitZ()), wall);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int placed = 0;
  for (int a = 0; a < 12 && placed < 150; ++a)
    for (int b = 0; b < 12 && placed < 150; ++b)
      for (int c = 0; c < 6 && placed < 150; ++c, ++placed) {
        const Vec x(1e-3 + a * 1.6e-3 + 2e-4 * u(rng), 1e-3 + c * 1.6e-3 + 2e-4 * u(rng), 1e-3 + b * 1.6e-3);
        const double r = 5e-4 * (0.8 + 0.4 * u(rng));
        sim->add_particle(x, r, mat, Vec(0.05 * (u(rng) - 0.5), 0.0, -1.0));
      }
  return sim;
}

// Everything save_state writes: particles, ghosts, list and history, bodies, walls, time.
std::vector<std::uint8_t> state_bytes(Sim& sim) {
  io::BinaryWriter w;
  sim.save_state(w);
  return w.bytes();
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("granule_ckpt_safety_" + name)).string();
}

std::string reason(int err) { return std::generic_category().message(err); }

// The IoError message of read_checkpoint(sim, path), or a text saying what happened instead.
std::string load_error(Sim& sim, const std::string& path) {
  try {
    io::read_checkpoint(sim, path);
  } catch (const IoError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<other exception: ") + e.what() + ">";
  }
  return "<accepted>";
}

// A checkpoint file of format `version` (3 or 4) holding sim's state: the format-5 layout without
// the materials section and without the time origin (16 bytes after the state); format 3 also
// without the wall states (active flag, force, torque per wall) before the group modes.
std::vector<std::uint8_t> old_checkpoint(Sim& sim, std::uint32_t version, const std::vector<std::uint64_t>& user) {
  std::vector<std::uint8_t> state = state_bytes(sim);
  state.resize(state.size() - 16);
  if (version == 3) {
    const std::size_t modes = 8;  // an empty vector of group modes: its length alone
    const std::size_t walls = sim.walls().size() * (1 + sizeof(Vec) + sizeof(Dim3::AngVec));
    state.erase(state.end() - static_cast<std::ptrdiff_t>(modes + walls), state.end() - static_cast<std::ptrdiff_t>(modes));
  }
  io::BinaryWriter w;
  for (char c : io::kCheckpointMagic) w.pod(c);
  w.pod(version);
  w.pod<std::uint32_t>(0x01020304u);
  w.pod<std::uint32_t>(3);
  w.str(io::detail::scene_signature<Sim>());
  w.vec(user);
  std::vector<std::uint8_t> out = w.bytes();
  out.insert(out.end(), state.begin(), state.end());
  const std::uint64_t len = out.size(), sum = io::detail::fnv1a(out.data(), out.size());
  const auto* l = reinterpret_cast<const std::uint8_t*>(&len);
  const auto* s = reinterpret_cast<const std::uint8_t*>(&sum);
  out.insert(out.end(), l, l + 8);
  out.insert(out.end(), s, s + 8);
  return out;
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

template <class S>
void require_same_motion(const S& a, const S& b) {
  const auto& pa = a.particles();
  const auto& pb = b.particles();
  REQUIRE(pa.owned() == pb.owned());
  for (std::size_t i = 0; i < pa.owned(); ++i) {
    REQUIRE(pa.id[i] == pb.id[i]);
    REQUIRE(pa.x[i] == pb.x[i]);  // bitwise
    REQUIRE(pa.v[i] == pb.v[i]);
    REQUIRE(pa.omega[i] == pb.omega[i]);
  }
}

}  // namespace ckpt_safety

using namespace ckpt_safety;

TEST_CASE("A refused checkpoint leaves the simulation bitwise as it was", "[restart][checkpoint]") {
  auto source = make();
  source->run(300);
  const std::string path = temp_path("source");
  io::write_checkpoint(*source, path);
  struct Case {
    const char* name;
    Options options;
    const char* message;
  };
  // (Before, dt and wall-count mismatches were found after time, step and particles had been
  // overwritten.)
  const Case cases[] = {
      {"another time step", {.dt = 1.5e-6}, "time step 1.9999999999999999e-06 s differs"},
      {"another wall count", {.extra_wall = true}, "1 walls, the scene 2 and 2"},
      {"another friction", {.friction = 0.3}, "material 0 ('grain'): friction 0.5 in the checkpoint, 0.29999999999999999 in the scene"},
      {"another pair table", {.pair_override = true}, "pair (0, 1): mu_s 0.5 in the checkpoint, 0.20000000000000001 in the scene (set_pair)"},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    auto target = make(c.options);
    auto twin = make(c.options);  // the same scene, never offered the file
    target->run(200);
    twin->run(200);
    const auto before = state_bytes(*target);
    const std::string what = load_error(*target, path);
    INFO(what);
    CHECK_THAT(what, Contains(c.message));
    REQUIRE(state_bytes(*target) == before);
    target->run(200);
    twin->run(200);
    REQUIRE(state_bytes(*target) == state_bytes(*twin));
  }
  std::filesystem::remove(path);
}

TEST_CASE("Crafted checkpoints with sizes, indices or values out of range are refused", "[restart][checkpoint]") {
  struct Case {
    const char* name;
    void (*tamper)(Sim&);
    const char* message;
  };
  const Case cases[] = {
      {"owned larger than the arrays",  // (read past the arrays: a heap overflow found with ASan)
       [](Sim& s) { s.particles().set_owned(s.particles().size() + 1000); }, "particles but holds arrays of"},
      {"material index 99", [](Sim& s) { s.particles().material[7] = 99; }, "material index 99"},
      {"NaN radius", [](Sim& s) { s.particles().radius[3] = std::numeric_limits<double>::quiet_NaN(); }, "radius = nan"},
      {"infinite velocity", [](Sim& s) { s.particles().v[5][2] = -std::numeric_limits<double>::infinity(); }, "v[2] = -inf"},
      {"prescribed in a group that does not exist",
       [](Sim& s) {
         s.particles().motion[2] = Motion::Prescribed;
         s.particles().group[2] = 7;
       },
       "prescribed, in group 7"},
      {"a ghost of a slot out of range",
       [](Sim& s) {
         auto& p = s.particles();
         REQUIRE(p.ghosts() > 0);
         p.ghost_owner[0] = 100000;
       },
       "ghost of slot 100000"},
  };
  const std::string path = temp_path("crafted");
  for (const Case& c : cases) {
    INFO(c.name);
    auto source = make();
    source->run(100);
    c.tamper(*source);
    io::write_checkpoint(*source, path);  // a well-formed file (checksum and all) with a bad state
    auto target = make();
    target->run(50);
    const auto before = state_bytes(*target);
    const std::string what = load_error(*target, path);
    INFO(what);
    CHECK_THAT(what, Contains(c.message));
    REQUIRE(state_bytes(*target) == before);
  }
  std::filesystem::remove(path);
}

TEST_CASE("Checkpoints record the materials; other ones are refused unless allowed", "[restart][checkpoint]") {
  auto source = make();
  source->run(300);
  const std::string path = temp_path("materials");
  io::write_checkpoint(*source, path);
  // The same materials load; so do other ones when asked for, and the state is then the source's.
  auto same = make();
  REQUIRE_NOTHROW(io::read_checkpoint(*same, path));
  CHECK(state_bytes(*same) == state_bytes(*source));
  auto other = make({.friction = 0.3});
  CHECK_THROWS_AS(io::read_checkpoint(*other, path), IoError);
  REQUIRE_NOTHROW(io::read_checkpoint(*other, path, {.allow_other_materials = true}));
  CHECK(state_bytes(*other) == state_bytes(*source));
  CHECK(other->materials()[0].friction == 0.3);  // the scene keeps its own materials
  std::filesystem::remove(path);
}

TEST_CASE("Checkpoints of formats 3 and 4 still load and continue the run", "[restart][checkpoint]") {
  auto source = make();
  source->run(400);
  const std::string path5 = temp_path("format5");
  io::write_checkpoint(*source, path5, {3, 5});
  auto current = make();
  io::read_checkpoint(*current, path5);
  current->run(300);
  for (std::uint32_t version : {4u, 3u}) {
    INFO("format " << version);
    const std::string path = temp_path("format" + std::to_string(version));
    write_bytes(path, old_checkpoint(*source, version, {3, 5}));
    auto old = make();
    const auto user = io::read_checkpoint(*old, path);
    CHECK(user == std::vector<std::uint64_t>{3, 5});
    CHECK(old->time() == source->time());
    CHECK(old->step_count() == source->step_count());
    if (version == 3) CHECK(old->wall(0).force == Vec::Zero());  // readouts zero until the next step
    if (version == 4) CHECK(old->wall(0).force == source->wall(0).force);
    old->run(300);
    // No motion here depends on time: the trajectories agree bitwise; time itself counts from the
    // stored time instead of from zero, which may differ in the last bit.
    require_same_motion(*old, *current);
    CHECK(old->time() == Approx(current->time()).epsilon(1e-14));
    std::filesystem::remove(path);
  }
  std::filesystem::remove(path5);
}

TEST_CASE("Time is t0 + steps x dt, across dt changes and restarts", "[restart][time]") {
  SECTION("20 000 steps of 5e-6 s are 0.1 s") {
    SimulationConfig<Dim3> cfg;
    cfg.domain.lo = Vec(-0.01, -0.01, -0.06);  // room for the fall of 0.049 m
    cfg.domain.hi = Vec(0.01, 0.01, 0.01);
    cfg.gravity = Vec(0, 0, -9.81);
    cfg.dt = 5e-6;
    Simulation<Dim3, contact::HertzMindlin> sim(cfg);
    Material m;
    m.youngs_modulus = 5e6;
    m.poisson_ratio = 0.3;
    m.density = 2500;
    sim.add_particle(Vec::Zero(), 1e-3, sim.add_material(m));
    sim.run(20000);
    CHECK(sim.time() == 20000 * 5e-6);
    CHECK(sim.time() == 0.1);
    double sum = 0.0;  // the running sum it was before
    for (int k = 0; k < 20000; ++k) sum += 5e-6;
    CHECK(sum != 0.1);
    // Free fall: velocity Verlet integrates a constant acceleration exactly (Allen & Tildesley
    // 1987, sec. 3.2), so z = -g t^2 / 2 up to rounding: 0.04905 m.
    CHECK(sim.particles().x[0].z() == Approx(-0.5 * 9.81 * 0.01).epsilon(1e-12));
  }
  SECTION("a change of dt counts on from the time of the change; a restart continues it bitwise") {
    auto straight = make({.dt = 1e-6});
    straight->run(700);
    const double t_change = straight->time();
    CHECK(t_change == 700 * 1e-6);
    straight->set_dt(2e-6);
    straight->run(300);
    CHECK(straight->time() == std::fma(300.0, 2e-6, t_change));  // (t0 + n dt, rounded once)
    const std::string path = temp_path("dt_change");
    io::write_checkpoint(*straight, path);
    straight->run(300);
    CHECK(straight->time() == std::fma(600.0, 2e-6, t_change));  // (t0 + n dt, rounded once)
    auto resumed = make({.dt = 2e-6});
    io::read_checkpoint(*resumed, path);
    resumed->run(300);
    CHECK(resumed->time() == straight->time());
    REQUIRE(state_bytes(*resumed) == state_bytes(*straight));
    std::filesystem::remove(path);
  }
}

TEST_CASE("Checkpoint and STL I/O failures are IoError with the system's reason", "[restart][io]") {
  namespace fs = std::filesystem;
  auto sim = make();
  sim->run(10);
  const fs::path dir = temp_path("a_directory");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto io_error = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const IoError& e) {
      return e.what();
    } catch (const std::exception& e) {
      return std::string("<other exception: ") + e.what() + ">";
    }
    return "<no exception>";
  };
  SECTION("a directory given as a file") {
    // (An std::ifstream opens a directory and throws std::ios_base::failure at the first read.)
    CHECK_THAT(io_error([&] { io::read_checkpoint(*sim, dir.string()); }),
               Contains("read_checkpoint") && Contains(dir.string()) && Contains(reason(EISDIR)));
    CHECK_THAT(io_error([&] { io::read_stl(dir); }), Contains(dir.string()) && Contains(reason(EISDIR)));
    CHECK_THAT(io_error([&] { io::write_checkpoint(*sim, dir.string()); }),
               Contains("write_checkpoint") && Contains(reason(EISDIR)));
    CHECK_FALSE(fs::exists(dir.string() + ".tmp"));
    CHECK(fs::is_directory(dir));
  }
  SECTION("a missing file and an unwritable location") {
    CHECK_THAT(io_error([&] { io::read_checkpoint(*sim, (dir / "absent.ckpt").string()); }),
               Contains("cannot open") && Contains(reason(ENOENT)));
    CHECK_THAT(io_error([&] { io::read_stl(dir / "absent.stl"); }), Contains("cannot open") && Contains(reason(ENOENT)));
    const fs::path nowhere = dir / "no_such_directory" / "bed.ckpt";
    CHECK_THAT(io_error([&] { io::write_checkpoint(*sim, nowhere.string()); }),
               Contains("cannot open") && Contains(nowhere.string()) && Contains(reason(ENOENT)));
  }
  SECTION("a write that fails half-way leaves no temporary file and the old checkpoint intact") {
    // The file-size limit (RLIMIT_FSIZE) makes write() fail with EFBIG part-way, as a full disk
    // fails with ENOSPC; SIGXFSZ is ignored so that the call returns the error.
    const fs::path file = dir / "bed.ckpt";
    io::write_checkpoint(*sim, file.string());
    const auto good = fs::file_size(file);
    rlimit old{};
    REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
    rlimit small = old;
    small.rlim_cur = 4096;
    REQUIRE(good > small.rlim_cur);
    sim->run(10);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);
    REQUIRE(setrlimit(RLIMIT_FSIZE, &small) == 0);
    const std::string what = io_error([&] { io::write_checkpoint(*sim, file.string()); });
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    CHECK_THAT(what, Contains("writing") && Contains(reason(EFBIG)));
    CHECK_FALSE(fs::exists(file.string() + ".tmp"));
    REQUIRE(fs::file_size(file) == good);
    auto back = make();
    CHECK_NOTHROW(io::read_checkpoint(*back, file.string()));
    CHECK(back->step_count() == 10);
  }
  fs::remove_all(dir);
}
