// Two engines in one process on paper 002's pull-out bed (issue 27's comparison, timed so that
// the host's swings cancel): this checkout's engine (namespace granule) and an older commit's,
// its headers copied with the namespace renamed to granule_before (benchmarks/inrun/
// pull_out_2d_inrun.sh makes the copy and builds this file). Each engine runs its own copy of a
// bed (the script gives both the older engine's, which the newer one reads too; their
// trajectories then part only by rounding), both on one thread; they take turns of
// W steps, and the CPU time of each turn is added to its engine's total. A slow spell of the
// host then falls on both in equal parts, which alternating whole runs of seconds does not
// achieve (one binary gave 42-68 ns per particle-step in consecutive runs on 2026-12-07). Each
// turn starts with the caches full of the other engine's data: with turns of 25 steps that
// cost the faster engine ~6 % (Zen 3: 2.31x against 2.45-2.48x with 400), so 400 (~30 ms).
//
//   bench_pull_out_2d_inrun --now FILE --before FILE [--steps S] [--turn W] [--warmup N]
//       [--velocity V] [--E PA]
// S (20000) steps per engine after N (2000) warm-up steps, in turns of W (400) steps; prints
// one line of key=value pairs: ns per particle-step of each engine and their ratio.
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <numbers>
#include <string>
#include <type_traits>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/boundaries/geometry/sphero_line.hpp>
#include <granule/granule.hpp>
#include <granule/io/checkpoint.hpp>
#include <granule_before/boundaries/geometry/sphero_line.hpp>
#include <granule_before/granule.hpp>
#include <granule_before/io/checkpoint.hpp>

namespace now {
#include "../pull_out_2d_scene.hpp"
}  // namespace now

namespace before {
namespace granule = ::granule_before;
#include "../pull_out_2d_scene.hpp"
}  // namespace before

namespace {

struct Options {
  std::string now, before;
  std::uint64_t steps = 20000, turn = 400, warmup = 2000;
  double velocity = 0.02, youngs_modulus = 2e7;
};

[[noreturn]] void usage_error(const std::string& what) {
  std::fprintf(stderr, "bench_pull_out_2d_inrun: %s (see the comment at the top of the source)\n", what.c_str());
  std::exit(2);
}

double positive(const std::string& option, const char* text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || errno != 0 || !std::isfinite(v) || v <= 0.0)
    usage_error(option + " needs a positive number, got '" + text + "'");
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (a + 1 >= argc) usage_error(arg + " needs a value");
    const char* value = argv[++a];
    const auto count = [&] { return static_cast<std::uint64_t>(positive(arg, value)); };
    if (arg == "--now") o.now = value;
    else if (arg == "--before") o.before = value;
    else if (arg == "--steps") o.steps = count();
    else if (arg == "--turn") o.turn = count();
    else if (arg == "--warmup") o.warmup = count();
    else if (arg == "--velocity") o.velocity = positive(arg, value);
    else if (arg == "--E") o.youngs_modulus = positive(arg, value);
    else usage_error("unknown option '" + arg + "'");
  }
  if (o.now.empty() || o.before.empty()) usage_error("give --now FILE and --before FILE");
  return o;
}

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Reads the bed and starts the intruder up at v; the same for both engines' scenes.
template <class Scene, class Read>
Scene start(Scene s, const std::string& file, double v, Read read) {
  auto& sim = *s.sim;
  read(sim, file);
  const double t0 = sim.time();
  using Vec = Eigen::Vector2d;
  sim.body(s.intruder).velocity = [t0, v](double t) { return t >= t0 ? Vec(0.0, v) : Vec(Vec::Zero()); };
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  auto a = start(now::make_scene(o.youngs_modulus, true), o.now, o.velocity,
                 [](auto& sim, const std::string& f) { granule::io::read_checkpoint(sim, f); });
  auto b = start(before::make_scene(o.youngs_modulus, true), o.before, o.velocity,
                 [](auto& sim, const std::string& f) { granule_before::io::read_checkpoint(sim, f); });
  a.sim->run(o.warmup);
  b.sim->run(o.warmup);
  double ta = 0.0, tb = 0.0;
  std::uint64_t done = 0;
  while (done < o.steps) {
    const std::uint64_t w = std::min(o.turn, o.steps - done);
    double t = thread_seconds();
    a.sim->run(w);
    ta += thread_seconds() - t;
    t = thread_seconds();
    b.sim->run(w);
    tb += thread_seconds() - t;
    done += w;
  }
  const double na = static_cast<double>(a.sim->particles().owned()), nb = static_cast<double>(b.sim->particles().owned());
  const double ns_now = ta / (na * static_cast<double>(o.steps)) * 1e9;
  const double ns_before = tb / (nb * static_cast<double>(o.steps)) * 1e9;
  std::printf("scene=pull_out_2d_inrun steps=%llu turn=%llu now_ns_per_particle_step=%.2f "
              "before_ns_per_particle_step=%.2f speedup=%.3f now_contacts_per_disk=%.3f before_contacts_per_disk=%.3f\n",
              static_cast<unsigned long long>(o.steps), static_cast<unsigned long long>(o.turn), ns_now, ns_before,
              ns_before / ns_now, static_cast<double>(a.sim->contact_count()) / na,
              static_cast<double>(b.sim->contact_count()) / nb);
  return 0;
}
