#pragma once
// The work of one force evaluation of a Simulation: per-layer accumulators, the packed pair
// loop's per-thread arrays and its queue of wall contacts (data only; the passes that fill them
// are simulation/pair_pass.hpp and simulation/wall_pass.hpp), and GRANULE_FLATTEN, how those
// passes are compiled.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "granule/analysis/frame.hpp"
#include "granule/contact/packed.hpp"
#include "granule/core/lanes.hpp"

// The pair loop is fully inlined in optimised builds: GCC otherwise keeps the tangential law
// out of line and every ContactGeometry goes through memory (docs/performance.md, "The pair loop
// fully inlined"). Not under AddressSanitizer, where the flattened loop makes GCC 12 take over
// ten times longer to compile a test file (measured: > 10 min instead of 63 s).
#if defined(__OPTIMIZE__) && !defined(__SANITIZE_ADDRESS__)
#define GRANULE_FLATTEN [[gnu::flatten]]
#else
#define GRANULE_FLATTEN
#endif
// For the per-particle passes' lambdas (simulation/integrate.hpp): out of line, their running
// maximum went through memory from one block of particles to the next.
#if defined(__GNUC__)
#define GRANULE_ALWAYS_INLINE __attribute__((always_inline))
#else
#define GRANULE_ALWAYS_INLINE
#endif

namespace granule::simulation_parts {

// Per-layer accumulators of one force evaluation (summed in layer order afterwards, so the
// sums do not depend on the number of threads).
template <class D>
struct LayerAccumulator {
  std::size_t contacts = 0;
  std::size_t bad_row = std::numeric_limits<std::size_t>::max();
  std::size_t bad_partner = 0;
  double bad_overlap = 0.0;
  bool bad_wall = false;
  std::size_t missing_wall_features = 0;
  std::vector<typename D::Vec> body_force;
  std::vector<typename D::AngVec> body_torque;
  std::vector<typename D::Vec> wall_force;  // beside body_force: the same contacts, per wall
  std::vector<typename D::AngVec> wall_torque;
  std::vector<analysis::ContactRecord<D>> records;
};

// Work arrays of the packed pair loop, one per thread (process_layer_packed): the layer's
// list entries that touch and the row of each.
struct PairWork {
  std::vector<std::uint32_t> entries, rows;
  std::vector<double> separation[2];  ///< 2D: x_i - x_j of the touching pairs (TouchScanInput)
};

// Wall contacts queued for the packed law (process_layer_packed): W at a time, one parameter
// set per pack.
template <class D, class State>
struct WallQueue {
  contact::GeometryLanes lanes;
  State* state[lane_width];
  State scratch[lane_width];  ///< histories of contacts without a slot (dropped after the law)
  std::uint32_t i[lane_width], wall[lane_width];
  typename D::Vec arm[lane_width];  ///< contact point - body origin
  std::size_t count = 0;
  std::size_t params = 0;
};

}  // namespace granule::simulation_parts
