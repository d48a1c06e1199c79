// Whole-scene throughput of granule's 2D path on the pull-out bed of paper 002 (issue 27):
// 1600 disks in a 100 mm wide cell closed by sphero-line walls, with the 10 mm intruder on a
// Body being pulled up through the bed. This is the scene the 2D study runs for hours, so it is
// the one the 2D pair loop is measured on.
//
//   Model (002 section 2.3, as examples/intruder_pull_out_2d): contact::LinearCoulombRolling,
//   k_n = E d (d = 3 mm mean diameter, radii uniform in [1, 2] mm), e = 0.9, mu = 0.5,
//   k_t = k_n / 2, EPSD rolling mu_r = 0.02 with c = 40 (002's rolling law at the mean size),
//   rho = 2500 kg/m^3, disk thickness d, g = 9.81 m/s^2, dt = 0.2 x the linear critical time of
//   two of the lightest disks. E = 2e7 Pa by default (the example's medium mode); the step
//   scales with E^-1/2 and the cost per step barely depends on it.
//
// Usage:
//   bench_scene_pull_out_2d --prepare FILE [--particles N] [--E PA] [--seed S]
//       inserts N disks (1600) at random in a tall region above the cell, lets them fall and
//       settles them (scene::settle: velocities zeroed every 0.05 s until the kinetic energy
//       per disk is below 1e-12 J); writes the settled bed as a checkpoint (io/checkpoint.hpp).
//   bench_scene_pull_out_2d --data FILE [--steps S] [--warmup W] [--repeat R] [--velocity V]
//       [--threads T] [--one-at-a-time] [--E PA]
//       reads the bed, sets the intruder moving up at V (0.02 m/s), runs W warm-up steps (2000),
//       then times R runs (3) of S steps (20000) around Simulation::run with
//       CLOCK_PROCESS_CPUTIME_ID (CPU time of all threads) and the wall clock, and prints one
//       line of key=value pairs: ns per particle-step (CPU, best of R), contacts per disk and an
//       end-state hash (FNV-1a of positions and velocities after the last run), so that two
//       builds or the two pair loops can be compared for equality as well as speed; then runs
//       S steps more, untimed, to count the list's rebuilds per 1000 steps.
//       --one-at-a-time times the scalar pair loop (SimulationConfig::packed_contacts = false).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <chrono>
#include <fstream>
#include <memory>
#include <numbers>
#include <string>
#include <time.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/boundaries/geometry/sphero_line.hpp>
#include <granule/granule.hpp>
#include <granule/io/checkpoint.hpp>
#include <granule/scene/pour.hpp>
#include <granule/scene/settle.hpp>

namespace {

using namespace granule;
#include "pull_out_2d_scene.hpp"

struct Options {
  std::string prepare, data;
  std::size_t particles = 1600;
  double youngs_modulus = 2e7;  // [Pa]
  double velocity = 0.02;       // [m/s]
  std::uint64_t steps = 20000, warmup = 2000, seed = 1;
  int repeat = 3, threads = 1;
  bool packed = true;
};

[[noreturn]] void usage_error(const std::string& what) {
  std::fprintf(stderr, "bench_scene_pull_out_2d: %s (see the comment at the top of the source)\n", what.c_str());
  std::exit(2);
}

double positive_number(const char* option, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v) || v <= 0.0)
    usage_error(std::string(option) + " needs a positive number, got '" + text + "'");
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto value = [&]() -> const char* {
      if (a + 1 >= argc) usage_error(arg + " needs a value");
      return argv[++a];
    };
    const auto count = [&]() { return static_cast<std::uint64_t>(positive_number(arg.c_str(), value())); };
    if (arg == "--prepare") o.prepare = value();
    else if (arg == "--data") o.data = value();
    else if (arg == "--particles") o.particles = count();
    else if (arg == "--E") o.youngs_modulus = positive_number("--E", value());
    else if (arg == "--velocity") o.velocity = positive_number("--velocity", value());
    else if (arg == "--steps") o.steps = count();
    else if (arg == "--warmup") o.warmup = count();
    else if (arg == "--seed") o.seed = count();
    else if (arg == "--repeat") o.repeat = static_cast<int>(count());
    else if (arg == "--threads") o.threads = static_cast<int>(count());
    else if (arg == "--one-at-a-time") o.packed = false;
    else usage_error("unknown option '" + arg + "'");
  }
  if (o.prepare.empty() == o.data.empty()) usage_error("give exactly one of --prepare FILE and --data FILE");
  return o;
}


double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

int prepare(const Options& o) {
  Scene s = make_scene(o.youngs_modulus, true);
  Sim& sim = *s.sim;
  const geometry::Aabb<Dim2> region{Vec(kRmax, kBedHeight), Vec(kWidth - kRmax, kTop - kRmax)};
  scene::Pour<Sim> pour(sim, region, scene::UniformSizes(kRmin, kRmax),
                        scene::StreamSchedule(10.0 * o.particles, o.particles, 0.0, scene::StreamMode::Batched, 0.1),
                        s.material, Vec::Zero(), 0, o.seed);
  pour.update();
  if (!pour.finished()) usage_error("the insertion region holds only " + std::to_string(pour.inserted()) + " disks");
  const double t0 = cpu_seconds();
  const auto fall = static_cast<std::uint64_t>((std::sqrt(2.0 * kTop / 9.81) + 0.2) / sim.dt());
  sim.run(fall);
  scene::SettleOptions so;
  so.max_time = 2.0;
  so.zero_velocity_interval = 0.05;
  so.kinetic_energy_per_particle = 1e-12;
  so.check_interval = 0.01;
  const bool settled = scene::settle(sim, so).settled;
  io::write_checkpoint(sim, o.prepare);
  std::printf("prepared %zu disks, settled %s, surface %.4f m, %llu steps in %.1f s CPU; bed in %s\n", o.particles,
              settled ? "yes" : "no", scene::surface_height(sim, 1, 5),
              static_cast<unsigned long long>(sim.step_count()), cpu_seconds() - t0, o.prepare.c_str());
  return settled ? 0 : 1;
}

std::uint64_t state_hash(const Sim& sim) {
  const auto& p = sim.particles();
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&](const double* v, std::size_t n) {
    const auto* b = reinterpret_cast<const unsigned char*>(v);
    for (std::size_t k = 0; k < n * sizeof(double); ++k) h = (h ^ b[k]) * 1099511628211ull;
  };
  for (std::size_t i = 0; i < p.owned(); ++i) {
    mix(p.x[i].data(), 2);
    mix(p.v[i].data(), 2);
    mix(&p.omega[i], 1);
  }
  return h;
}

int time_runs(const Options& o) {
  Scene s = make_scene(o.youngs_modulus, o.packed);
  Sim& sim = *s.sim;
  io::read_checkpoint(sim, o.data);
  const double v = o.velocity, t0 = sim.time();
  sim.body(s.intruder).velocity = [t0, v](double t) { return t >= t0 ? Vec(0.0, v) : Vec(Vec::Zero()); };
  sim.run(o.warmup);
  const double n = static_cast<double>(sim.particles().owned());
  double best = 1e300, wall_best = 1e300;
  for (int r = 0; r < o.repeat; ++r) {
    const double c0 = cpu_seconds();
    const auto w0 = std::chrono::steady_clock::now();
    sim.run(o.steps);
    const double cpu = cpu_seconds() - c0;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    best = std::min(best, cpu);
    wall_best = std::min(wall_best, wall);
  }
  const std::uint64_t end_state = state_hash(sim);
  const double contacts = static_cast<double>(sim.contact_count()) / n;
  const double entries = static_cast<double>(sim.neighbour_list().nbr.size()) / n;
  // Rebuilds per 1000 steps, counted over one more run of S steps after the timed ones (the
  // list's build positions change at each rebuild): comparing them after every step cost 2 % of
  // a step, so the timed runs go without.
  std::uint64_t rebuilds = 0;
  auto build_x = sim.neighbour_list().x_at_build;
  sim.every(1, [&](Sim& s) {
    if (s.neighbour_list().x_at_build != build_x) {
      ++rebuilds;
      build_x = s.neighbour_list().x_at_build;
    }
  });
  sim.run(o.steps);
  const double per = best / (n * static_cast<double>(o.steps)) * 1e9;
  std::printf("scene=pull_out_2d pair_loop=%s disks=%.0f E=%g dt=%.4g steps=%llu threads=%d contacts_per_disk=%.3f "
              "entries_per_disk=%.3f rebuilds_per_1000_steps=%.2f cpu_ns_per_particle_step=%.2f "
              "wall_ns_per_particle_step=%.2f end_state=%016llx\n",
              o.packed ? "packed" : "one-at-a-time", n, o.youngs_modulus, sim.dt(),
              static_cast<unsigned long long>(o.steps), o.threads, contacts, entries,
              1000.0 * static_cast<double>(rebuilds) / static_cast<double>(o.steps), per,
              wall_best / (n * static_cast<double>(o.steps)) * 1e9, static_cast<unsigned long long>(end_state));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
#ifdef _OPENMP
  omp_set_num_threads(o.threads);
#endif
  try {
    return o.prepare.empty() ? time_runs(o) : prepare(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_scene_pull_out_2d: %s\n", e.what());
    return 1;
  }
}
