#pragma once
// What the MPI test suites (tests/parallel/*_suite.cpp) share: the two engines compared, the
// failure count every rank keeps (summed or maxed over the ranks at the end), the comparison of
// a gathered state with the one-process run, the settled bed that starts both runs, and a file's
// bytes.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "granule/granule.hpp"
#include "granule/parallel/mpi_domains.hpp"
#include "parallel/scene.hpp"

namespace granule::test_parallel {

using Single = Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList>;
using Distributed = Simulation<Dim3, contact::HertzMindlin, neighbours::VerletList, integrators::VelocityVerlet,
                               parallel::MpiDomains>;

/// Failed checks on this rank.
inline int failures = 0;

/// Counts a failed check and prints it with the rank that saw it.
inline void check(bool ok, const std::string& what, int rank) {
  if (!ok) {
    ++failures;
    std::printf("rank %d: FAILED: %s\n", rank, what.c_str());
    std::fflush(stdout);
  }
}

/// The bytes of the file at `path` (empty if it cannot be read).
inline std::string file_contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Largest differences between two gathered states: position / r, velocity, angular velocity,
/// and the relative difference of the floor force.
struct Difference {
  double dx = 0, dv = 0, dw = 0, floor = 0;
  bool same_ids = true;  ///< both hold the same (non-empty) particles in the same order
};

/// `a` (with floor force `fa`) against `b` (`fb`); positions compared unwrapped, since a particle
/// may sit on the other side of a periodic face in one of the runs.
inline Difference compare_gathered(const GatheredParticles<Dim3>& a, const GatheredParticles<Dim3>& b,
                                   const Dim3::Vec& fa, const Dim3::Vec& fb, const Domain<Dim3>& dom) {
  using Vec = Dim3::Vec;
  Difference d;
  d.same_ids = a.size() == b.size() && a.id == b.id && a.size() > 0;
  if (!d.same_ids) return d;
  const Vec L = dom.length();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec xa = a.x[i] + (a.image[i].cast<double>().array() * L.array()).matrix();
    const Vec xb = b.x[i] + (b.image[i].cast<double>().array() * L.array()).matrix();
    d.dx = std::max(d.dx, (xa - xb).norm() / a.radius[i]);
    d.dv = std::max(d.dv, (a.v[i] - b.v[i]).norm());
    d.dw = std::max(d.dw, (a.omega[i] - b.omega[i]).norm());
  }
  d.floor = (fa - fb).norm() / std::max(fb.norm(), 1e-300);
  return d;
}

using Bed = std::vector<std::pair<Dim3::Vec, double>>;  ///< positions and radii

/// The scene poured and settled in one process with the floor still: the positions (at rest) are
/// the start of the runs compared.
inline Bed settled_bed(const SceneOptions& o, std::uint64_t steps) {
  SceneOptions still = o;
  still.floor_speed = 0.0;
  Single s(scene_config(still));
  populate(s, still);
  s.run(steps);
  const auto g = s.gather();
  Bed bed;
  for (std::size_t i = 0; i < g.size(); ++i) bed.push_back({g.x[i], g.radius[i]});
  return bed;
}

/// The scene's materials and walls, with the particles of `bed` in place of its lattice.
template <class Sim>
void populate_bed(Sim& sim, const SceneOptions& o, const Bed& bed) {
  populate(sim, o);
  sim.remove_particles([](std::size_t) { return true; });
  for (const auto& [x, r] : bed) sim.add_particle(x, r, 0);
}

}  // namespace granule::test_parallel
