// Whole-scene throughput of granule on the two benchmark beds of issue 6, in particle-steps per
// second, from a settled bed shared with the peer codes (benchmarks/run_peers.sh).
//
// The scenes A (lunar bed, paper 001) and B (intrusion bed, paper 000) are defined in beds.hpp.
// Walls are planes of the particle material. Box sizes follow from the particle count and an
// expected packing fraction (0.58 for A, 0.60 for B).
//
// Usage:
//   bench_scene_throughput --scene A|B [--particles N] --prepare FILE [--threads T]
//       places N particles on a jittered simple-cubic lattice (spacing 1.2 d, jitter +-0.09 d)
//       above the floor and pours them: they fall under the scene's gravity with the largest
//       time step the engine accepts (0.2 x Rayleigh time) and a pouring material (friction
//       --pour-friction, default 0.1, no rolling resistance, no cohesion; otherwise the lattice
//       stands in columns), until the kinetic energy has dropped to 5 % of its peak; then the
//       scene's own material takes over from those positions and the bed is damped to rest:
//       quick-min every 5 steps (velocity of a particle zeroed when it moves against its net
//       force), all velocities zeroed every 5 ms, until the kinetic energy per particle is below
//       --settle-ke x m g d (5e-5) and the mean net force below --settle-force x m g (0.05), at
//       most --settle-max-time (0.5 s). The bed is written at rest (positions and radii) as a
//       LAMMPS data file with io::write_lammps_data; the box of the file is the container.
//   bench_scene_throughput --scene A|B --data FILE [--steps S] [--threads T] [--warmup W]
//       [--repeat R] [--skin S_m] [--rolling-damping ETA] [--one-at-a-time] [--end-state FILE]
//       reads the bed (walls on the faces of the file's box, periodic x for A), runs W warm-up
//       steps (50), then times R runs (1) of S steps (1000) around Simulation::run only, with
//       std::chrono::steady_clock (wall) and CLOCK_PROCESS_CPUTIME_ID (CPU of all threads), and
//       prints machine information, contacts, mean overlap, memory per particle and per
//       contact, and one summary line of key=value pairs with particle_steps_per_s=<best of R>
//       (the line benchmarks/run_peers.sh reads; end_state= when --end-state is given).
//       --prepare with --steps also runs the timing from the file just written.
//       --one-at-a-time times the scalar pair loop (SimulationConfig::packed_contacts = false).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <time.h>
#include <exception>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <granule/granule.hpp>
#include <granule/io/lammps_data.hpp>

#include "beds.hpp"

namespace {

using namespace granule;
using Vec = Dim3::Vec;

struct Options {
  char scene = 'B';
  std::size_t particles = 20000;
  int threads = 1;
  std::uint64_t steps = 0;       // 0: default (1000 with --data, none after --prepare)
  bool steps_given = false;
  std::uint64_t warmup = 50;
  int repeat = 1;
  std::string prepare, data, end_state;
  double skin = -1.0;            // [m]; < 0: engine default 0.1 d
  bool packed = true;            // SimulationConfig::packed_contacts of the timed run
  double rolling_damping = 0.0;  // [-] scene A eta_r
  double settle_ke = 5.0e-5;     // [-] settle threshold, KE per particle / (m g d)
  double settle_force = 5.0e-2;  // [-] settle threshold, mean |net force| / (m g)
  double settle_max_time = 0.5;  // [s] simulated cap of the settling
  double pour_friction = 0.1;    // [-] sliding friction while pouring
  std::uint64_t seed = 20240611;
};

using granule_bench::Box;
using granule_bench::SceneSpec;
using granule_bench::footprint;
using granule_bench::make_spec;

// ---- machine information ---------------------------------------------------------------------

std::string read_first_line(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  return line;
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

std::string mem_total() {
  std::ifstream f("/proc/meminfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("MemTotal", 0) == 0) {
      std::istringstream s(line.substr(9));
      double kb = 0.0;
      s >> kb;
      std::ostringstream o;
      o.precision(3);
      o << kb / 1048576.0 << " GiB";
      return o.str();
    }
  return "unknown";
}

std::string now_text() {
  const std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S %Z", std::localtime(&t));
  return buf;
}

// CPU time of the whole process (all threads) [s]: with one thread a load-independent measure.
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

void print_machine() {
  std::printf("date=%s\n", now_text().c_str());
  std::printf("machine: cpu=\"%s\" logical_cpus=%ld memory=%s\n", cpu_model().c_str(),
              static_cast<long>(std::thread::hardware_concurrency()), mem_total().c_str());
  std::printf("compiler=\"%s\" avx512f=%d avx2=%d openmp_threads=%d\n", __VERSION__,
#ifdef __AVX512F__
              1,
#else
              0,
#endif
#ifdef __AVX2__
              1,
#else
              0,
#endif
              max_threads());
  std::printf("loadavg_start=\"%s\"\n", read_first_line("/proc/loadavg").c_str());
}

// ---- geometry of the scenes --------------------------------------------------------------------

template <class Model>
using Sim = Simulation<Dim3, Model, neighbours::VerletList>;

template <class Model>
std::unique_ptr<Sim<Model>> make_sim(const SceneSpec& s, const Material& material, const Box& box,
                                     double dt, double skin,
                                     const std::vector<Vec>& x, const std::vector<double>& r,
                                     const std::vector<Vec>& v, bool packed = true,
                                     bool check_rolling = true) {
  SimulationConfig<Dim3> cfg = granule_bench::config_of(s, box);
  cfg.packed_contacts = packed;
  cfg.check_rolling_stability = check_rolling;
  cfg.dt = dt;
  cfg.skin = skin;
  auto sim = std::make_unique<Sim<Model>>(cfg);
  const std::uint32_t mat = granule_bench::add_container(*sim, s, material, box);
  for (std::size_t i = 0; i < x.size(); ++i) sim->add_particle(x[i], r[i], mat, v[i]);
  return sim;
}

// Pair contacts (no walls) and their mean overlap, from the neighbour list.
template <class S>
std::pair<std::size_t, double> pair_contacts(const S& sim) {
  const auto& p = sim.particles();
  const auto& list = sim.neighbour_list();
  std::size_t count = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < p.owned(); ++i)
    for (std::uint32_t e = list.row_begin[i]; e < list.row_begin[i + 1]; ++e) {
      const std::uint32_t j = list.nbr[e];
      const double overlap = p.radius[i] + p.radius[j] - (p.x[i] - p.x[j]).norm();
      if (overlap > 0.0) {
        ++count;
        sum += overlap;
      }
    }
  return {count, count ? sum / static_cast<double>(count) : 0.0};
}

// ---- preparing a bed ---------------------------------------------------------------------------

template <class Model>
void prepare(const SceneSpec& s, const Options& o) {
  const double r = s.radius, d = 2.0 * r;
  Box box = footprint(s, o.particles);
  const double a = 1.2 * d;        // [m] lattice spacing
  const double jitter = 0.09 * d;  // [m] uniform +- jitter per coordinate
  const double edge = r + jitter + 0.01 * d;  // [m] clearance of lattice centres from walls
  auto sites = [&](int k) {
    const double len = box.hi[k] - box.lo[k];
    if (k == 0 && s.periodic_x) return std::max(1, static_cast<int>(std::floor(len / a)));
    return std::max(1, static_cast<int>(std::floor((len - 2.0 * edge) / a)) + 1);
  };
  const int nx = sites(0), ny = sites(1);
  const std::size_t per_layer = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  const std::size_t layers = (o.particles + per_layer - 1) / per_layer;
  const double lattice_top = edge + static_cast<double>(layers - 1) * a;
  box.hi[2] = lattice_top + r + jitter + 2.0 * d;  // head room above the lattice

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> x;
  x.reserve(o.particles);
  auto coord = [&](int k, int i, int n) {
    const double len = box.hi[k] - box.lo[k];
    if (k == 0 && s.periodic_x) return box.lo[k] + (i + 0.5) * len / n;
    const double span = (n - 1) * a;
    return box.lo[k] + 0.5 * (len - span) + i * a;
  };
  for (std::size_t l = 0; l < layers && x.size() < o.particles; ++l)
    for (int j = 0; j < ny && x.size() < o.particles; ++j)
      for (int i = 0; i < nx && x.size() < o.particles; ++i) {
        Vec p(coord(0, i, nx), coord(1, j, ny), box.lo[2] + edge + static_cast<double>(l) * a);
        for (int k = 0; k < 3; ++k) p[k] += jitter * u(rng);
        if (s.periodic_x) p[0] -= std::floor((p[0] - box.lo[0]) / (box.hi[0] - box.lo[0])) * (box.hi[0] - box.lo[0]);
        x.push_back(p);
      }
  const std::vector<double> radii(x.size(), r);
  const std::vector<Vec> v0(x.size(), Vec::Zero());

  // Largest time step the engine accepts: safety (0.2) x Rayleigh time.
  double dt_settle = 0.0;
  {
    auto probe = make_sim<Model>(s, s.material, box, s.dt, o.skin, {x.front()}, {r}, {Vec::Zero()});
    dt_settle = probe->suggested_time_step();
  }
  // The pour: low friction, no rolling resistance and no cohesion, so that the lattice collapses
  // into a random packing instead of standing in columns (001 pours with e = 0 and without
  // rolling damping for a similar reason).
  Material pour = s.material;
  pour.friction = o.pour_friction;
  pour.rolling_friction = 0.0;
  pour.rolling_damping = 0.0;
  pour.cohesion_energy_density = 0.0;
  // Without rolling resistance the rotational limit is that of the tangential springs alone,
  // which the 8-10 contacts of a particle in the pile-up bring below dt_settle; the pour only
  // has to make a random packing, so it runs without that check.
  auto sim = make_sim<Model>(s, pour, box, dt_settle, o.skin, x, radii, v0, true, false);
  std::printf("prepare: scene=%c particles=%zu box=[%g %g %g]..[%g %g %g] m lattice=%dx%dx%zu "
              "dt_settle=%g s (production dt %g s) pour friction=%g\n",
              s.name, x.size(), box.lo[0], box.lo[1], box.lo[2], box.hi[0], box.hi[1], box.hi[2],
              nx, ny, layers, dt_settle, s.dt, o.pour_friction);
  std::fflush(stdout);

  const double mass = s.material.density * Dim3::volume(r, 1.0);
  const double ke_scale = mass * s.gravity * d;  // [J] m g d
  const double n = static_cast<double>(x.size());
  const double t_free_fall = std::sqrt(2.0 * lattice_top / s.gravity);  // [s]
  const auto chunk = static_cast<std::uint64_t>(std::ceil(1.0e-3 / dt_settle));  // 1 ms
  const auto wall_start = std::chrono::steady_clock::now();

  // Phase 1: free fall and pile-up, until the kinetic energy has dropped to 5 % of its peak.
  double ke_max = 0.0;
  while (true) {
    sim->run(chunk);
    const double ke = sim->kinetic_energy();
    ke_max = std::max(ke_max, ke);
    if (sim->time() > 0.5 * t_free_fall && ke < 0.05 * ke_max) break;
    if (sim->time() > 3.0 * t_free_fall + 0.1) break;
  }
  std::printf("prepare: fall done at t=%.4f s (%llu steps), KE/particle=%.3e m g d\n", sim->time(),
              static_cast<unsigned long long>(sim->step_count()), sim->kinetic_energy() / n / ke_scale);
  std::fflush(stdout);

  // Damping: quick-min every 5 steps (stop each particle moving against its net force or torque;
  // Sheppard, Terrell & Henkelman 2008) and all velocities zeroed every 5 ms, until both the
  // kinetic energy and the mean net force per particle are below the thresholds.
  auto zero_every = static_cast<std::uint64_t>(std::ceil(5.0e-3 / dt_settle));
  const double weight = mass * s.gravity;  // [N]
  double ke_rel = 0.0, f_rel = 0.0;
  auto damp = [&](Sim<Model>& sm, double ke_limit, double f_limit, double t_cap, const char* label) {
    const double t_end = sm.time() + t_cap;
    while (sm.time() < t_end) {
      auto& p = sm.particles();
      for (std::size_t i = 0; i < p.owned(); ++i) {
        p.v[i].setZero();
        p.omega[i].setZero();
      }
      for (std::uint64_t k = 0; k < zero_every; k += 5) {
        sm.run(5);
        for (std::size_t i = 0; i < p.owned(); ++i) {
          if (p.v[i].dot(p.f[i]) < 0.0) p.v[i].setZero();
          if (p.omega[i].dot(p.torque[i]) < 0.0) p.omega[i].setZero();
        }
      }
      double fsum = 0.0;
      for (std::size_t i = 0; i < p.owned(); ++i) fsum += p.f[i].norm();
      ke_rel = sm.kinetic_energy() / n / ke_scale;
      f_rel = fsum / n / weight;
      std::fprintf(stderr, "prepare: %s t=%.4f s KE/particle=%.3e m g d mean |F_net|=%.3e m g\n",
                   label, sm.time(), ke_rel, f_rel);
      if (ke_rel < ke_limit && f_rel < f_limit) return true;
    }
    return false;
  };
  damp(*sim, 1.0e-3, 1.0, 0.3, "pour");

  // Phase 2: the scene's material from the poured positions, damped to rest.
  std::vector<Vec> xp(sim->particles().x.begin(), sim->particles().x.begin() + sim->particles().owned());
  const double t_pour = sim->time();
  const std::uint64_t steps_pour = sim->step_count();
  // The settle runs with the rotational check on, at 0.8 x the limit of the poured contacts
  // (infinite for models without EPSD rolling), found by one step of a probe without the check.
  {
    auto probe = make_sim<Model>(s, s.material, box, dt_settle, o.skin, xp, radii, v0, true, false);
    probe->run(1);
    const double limit = probe->rolling_stability_limit().limit;
    if (0.8 * limit < dt_settle) {
      std::printf("prepare: settle dt %g s (0.8 x the rotational limit %g s of the poured bed)\n",
                  0.8 * limit, limit);
      dt_settle = 0.8 * limit;
      zero_every = static_cast<std::uint64_t>(std::ceil(5.0e-3 / dt_settle));
    }
  }
  sim = make_sim<Model>(s, s.material, box, dt_settle, o.skin, xp, radii, v0);
  const bool settled = damp(*sim, o.settle_ke, o.settle_force, o.settle_max_time, "settle");
  const double wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  double z_max = 0.0;
  const auto& p = sim->particles();
  for (std::size_t i = 0; i < p.owned(); ++i) z_max = std::max(z_max, p.x[i][2]);
  std::printf("prepare: %s after %.4f s pour + %.4f s settle (%llu steps, %.1f s wall); "
              "KE/particle = %.3e m g d (threshold %.1e), mean |F_net| = %.3e m g (threshold %.1e)\n",
              settled ? "settled" : "NOT settled (time cap reached)", t_pour, sim->time(),
              static_cast<unsigned long long>(steps_pour + sim->step_count()), wall_seconds, ke_rel,
              o.settle_ke, f_rel, o.settle_force);
  const auto [npair, mean_overlap] = pair_contacts(*sim);
  // Packing fraction of the slab 2 d < z < z_top - 3 d (centres counted), away from floor and surface.
  const double z_lo = box.lo[2] + 2.0 * d, z_hi = z_max - 3.0 * d;
  std::size_t in_slab = 0;
  for (std::size_t i = 0; i < p.owned(); ++i) in_slab += p.x[i][2] > z_lo && p.x[i][2] < z_hi;
  const double area = (box.hi[0] - box.lo[0]) * (box.hi[1] - box.lo[1]);
  const double phi = z_hi > z_lo ? static_cast<double>(in_slab) * Dim3::volume(r, 1.0) / (area * (z_hi - z_lo)) : 0.0;
  std::printf("prepare: top particle z=%.5f m, packing fraction of the slab %.4f..%.4f m = %.4f, "
              "pair contacts=%zu (%.2f per particle), mean overlap=%.4e m (%.3e r)\n",
              z_max, z_lo, z_hi, phi, npair, 2.0 * static_cast<double>(npair) / n, mean_overlap,
              mean_overlap / r);

  // The bed at rest: positions only (the peer codes start from the same state, without history).
  analysis::Frame<Dim3> fr = sim->frame();
  fr.box_lo = box.lo;
  fr.box_hi = box.hi;
  const std::array<bool, 3> periodic = {s.periodic_x, false, false};
  io::write_lammps_data(o.prepare, fr, box.lo, box.hi, s.material.density, periodic,
                        /*with_velocities=*/false);
  std::printf("prepare: wrote %s (walls: z=%g; y=%g and y=%g%s)\n", o.prepare.c_str(), box.lo[2],
              box.lo[1], box.hi[1],
              s.periodic_x ? "; x periodic" : ("; x=" + std::to_string(box.lo[0]) + " and x=" +
                                               std::to_string(box.hi[0])).c_str());
  std::fflush(stdout);
}

// ---- timing from a data file ---------------------------------------------------------------------

template <class Model>
int run_timed(const SceneSpec& s, const Options& o, const std::string& file) {
  const io::LammpsData data = io::read_lammps_data(file);
  const auto& f = data.frame;
  for (double rho : data.density)
    if (std::abs(rho - s.material.density) > 1e-9 * s.material.density) {
      std::fprintf(stderr, "scene_throughput: %s has density %g, scene %c uses %g kg/m^3\n",
                   file.c_str(), rho, s.name, s.material.density);
      return 1;
    }
  Box box;
  box.lo = f.box_lo;
  box.hi = f.box_hi;
  auto sim = make_sim<Model>(s, s.material, box, s.dt, o.skin, f.x, f.radius, f.v, o.packed);
  const std::size_t n = sim->particles().owned();

  print_machine();
  std::printf("scene=%c model=%s particles=%zu threads=%d dt=%g s skin=%s rolling_damping=%g "
              "pairs=%s data=%s\n",
              s.name, s.model.c_str(), n, o.threads, s.dt,
              o.skin < 0.0 ? "default(0.1 d)" : std::to_string(o.skin).c_str(),
              s.material.rolling_damping, o.packed ? "packed" : "one-at-a-time", file.c_str());

  sim->run(o.warmup);
  double best = 0.0, best_seconds = 0.0, best_cpu = 0.0;
  std::size_t builds_best = 0;
  for (int rep = 0; rep < o.repeat; ++rep) {
    const std::size_t builds0 = sim->neighbour_list().builds;
    const double c0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    sim->run(o.steps);
    const auto t1 = std::chrono::steady_clock::now();
    const double cpu = process_cpu_seconds() - c0;
    const double seconds = std::chrono::duration<double>(t1 - t0).count();
    const double rate = static_cast<double>(n) * static_cast<double>(o.steps) / seconds;
    const std::size_t builds = sim->neighbour_list().builds - builds0;
    std::printf("run %d: steps=%llu seconds=%.4f cpu_seconds=%.4f particle_steps_per_s_run=%.5e "
                "particle_steps_per_cpu_s_run=%.5e rebuilds=%zu loadavg=\"%s\"\n",
                rep + 1, static_cast<unsigned long long>(o.steps), seconds, cpu, rate,
                static_cast<double>(n) * static_cast<double>(o.steps) / cpu, builds,
                read_first_line("/proc/loadavg").c_str());
    if (rate > best) {
      best = rate;
      best_seconds = seconds;
      best_cpu = cpu;
      builds_best = builds;
    }
  }
  const auto [npair, mean_overlap] = pair_contacts(*sim);
  const std::size_t total_bytes = sim->memory_bytes();
  const std::size_t list_bytes = sim->neighbour_list().memory_bytes();
  const std::size_t entries = sim->neighbour_list().entries();
  std::printf("contacts=%zu (pairs and walls) pair_contacts=%zu mean_overlap=%.5e m "
              "mean_overlap_over_r=%.4e list_entries=%zu\n",
              sim->contact_count(), npair, mean_overlap, mean_overlap / f.radius.front(), entries);
  std::string end_note;
  if (!o.end_state.empty()) {
    analysis::Frame<Dim3> fr = sim->frame();
    const std::array<bool, 3> periodic = {s.periodic_x, false, false};
    io::write_lammps_data(o.end_state, fr, box.lo, box.hi, s.material.density, periodic, true);
    end_note = " end_state=" + o.end_state;
  }
  // The summary line read by benchmarks/run_peers.sh (run_granule): key=value pairs.
  std::printf("scene=%c particles=%zu threads=%d steps=%llu seconds=%.4f cpu_seconds=%.4f "
              "rebuilds=%zu particle_steps_per_s=%.6e particle_steps_per_cpu_s=%.6e%s\n",
              s.name, n, o.threads, static_cast<unsigned long long>(o.steps), best_seconds, best_cpu,
              builds_best, best, static_cast<double>(n) * static_cast<double>(o.steps) / best_cpu,
              end_note.c_str());
  // Per particle: everything, and the particle store with the pair loop's work arrays; per
  // contact and per list entry: the list with its history.
  std::printf("memory_bytes=%zu bytes_per_particle=%.1f store_bytes_per_particle=%.1f list_bytes=%zu "
              "bytes_per_contact=%.1f bytes_per_list_entry=%.1f histories=%zu\n",
              total_bytes, static_cast<double>(total_bytes) / static_cast<double>(n),
              static_cast<double>(total_bytes - list_bytes) / static_cast<double>(n),
              list_bytes, npair ? static_cast<double>(list_bytes) / static_cast<double>(sim->contact_count()) : 0.0,
              entries ? static_cast<double>(list_bytes) / static_cast<double>(entries) : 0.0,
              sim->neighbour_list().histories());
  std::printf("loadavg_end=\"%s\"\n", read_first_line("/proc/loadavg").c_str());
  return 0;
}

template <class Model>
int run_scene(const SceneSpec& s, const Options& o) {
  if (!o.prepare.empty()) {
    prepare<Model>(s, o);
    if (!o.steps_given) return 0;
    return run_timed<Model>(s, o, o.prepare);
  }
  return run_timed<Model>(s, o, o.data);
}

[[noreturn]] void usage(const char* argv0, const std::string& why) {
  std::fprintf(stderr,
               "%s: %s\nusage: %s --scene A|B (--prepare FILE [--particles N] | --data FILE) "
               "[--steps S] [--threads T] [--warmup W] [--repeat R] [--skin M] [--one-at-a-time] [--end-state FILE] "
               "[--rolling-damping ETA] [--settle-ke X] [--settle-force X] [--settle-max-time S] [--pour-friction MU] [--seed K]\n",
               argv0, why.c_str(), argv0);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(argv[0], "missing value after " + a);
      return argv[++i];
    };
    try {
      if (a == "--scene") {
        const std::string v = value();
        if (v != "A" && v != "B") usage(argv[0], "--scene must be A or B, got " + v);
        o.scene = v[0];
      } else if (a == "--particles") {
        o.particles = std::stoull(value());
      } else if (a == "--threads") {
        o.threads = std::stoi(value());
      } else if (a == "--steps") {
        o.steps = std::stoull(value());
        o.steps_given = true;
      } else if (a == "--warmup") {
        o.warmup = std::stoull(value());
      } else if (a == "--repeat") {
        o.repeat = std::stoi(value());
      } else if (a == "--prepare") {
        o.prepare = value();
      } else if (a == "--data") {
        o.data = value();
      } else if (a == "--end-state") {
        o.end_state = value();
      } else if (a == "--one-at-a-time") {
        o.packed = false;
      } else if (a == "--skin") {
        o.skin = std::stod(value());
      } else if (a == "--rolling-damping") {
        o.rolling_damping = std::stod(value());
      } else if (a == "--settle-ke") {
        o.settle_ke = std::stod(value());
      } else if (a == "--settle-force") {
        o.settle_force = std::stod(value());
      } else if (a == "--pour-friction") {
        o.pour_friction = std::stod(value());
      } else if (a == "--settle-max-time") {
        o.settle_max_time = std::stod(value());
      } else if (a == "--seed") {
        o.seed = std::stoull(value());
      } else {
        usage(argv[0], "unknown option " + a);
      }
    } catch (const std::logic_error&) {
      usage(argv[0], "bad value for " + a);
    }
  }
  if (o.prepare.empty() == o.data.empty()) usage(argv[0], "give exactly one of --prepare and --data");
  if (o.particles < 1) usage(argv[0], "--particles must be at least 1");
  if (o.threads < 1) usage(argv[0], "--threads must be at least 1");
  if (o.repeat < 1) usage(argv[0], "--repeat must be at least 1");
  if (!o.steps_given) o.steps = 1000;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
#ifdef _OPENMP
  omp_set_num_threads(o.threads);
#endif
  try {
    const SceneSpec s = make_spec(o.scene, o.rolling_damping);
    if (o.scene == 'A') return run_scene<contact::HertzMindlinEpsdSjkr>(s, o);
    return run_scene<contact::HertzMindlin>(s, o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scene_throughput: %s\n", e.what());
    return 1;
  }
}
