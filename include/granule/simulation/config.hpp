#pragma once
// SimulationConfig: what a Simulation is built with (domain, gravity, dt, skin, and the
// checks' settings). Included by granule/simulation.hpp, the header to include.
#include <cmath>
#include <cstdint>
#include <string>

#include "granule/core/error.hpp"
#include "granule/neighbours/domain.hpp"

namespace granule {

template <class D>
struct SimulationConfig {
  using Vec = typename D::Vec;
  Domain<D> domain;                 ///< simulation box (periodic flags per axis)
  Vec gravity = Vec::Zero();        ///< [m/s^2]
  double dt = 0.0;                  ///< time step [s]
  double skin = -1.0;               ///< Verlet skin [m]; < 0: 0.1 x largest diameter (VerletList)
  double thickness = 1.0;           ///< out-of-plane thickness of 2D disks [m]
  /// The step may be at most this fraction of the critical time (Rayleigh time for Hertz
  /// contacts, collision time for linear ones); see docs/physics.md, "time step".
  double time_step_safety = 0.2;
  bool allow_large_time_step = false;  ///< explicit override of the time-step check
  /// Refuse a dt above rolling_stability_limit() (EPSD, SDS rolling dashpots) when the run
  /// starts (before any contact: above rolling_limit_estimate()), when dt changes and every
  /// stability_check_interval steps (allow_large_time_step also turns it off). The limit is conservative: 0.45-0.95 of the measured onset of instability
  /// for one contact, 0.56-0.59 on a settled bed (docs/physics.md, "Time step").
  bool check_rolling_stability = true;
  /// Steps between those checks; 0 = only when the run starts or dt changes.
  std::uint64_t stability_check_interval = 1000;
  /// An overlap above this fraction of the smaller radius stops the run as unstable.
  double max_overlap_ratio = 0.5;
  /// Evaluate particle pairs W at a time in SIMD lanes where the model allows it (3D, every
  /// slot written over D::Real, velocity Verlet-type dashpots; docs/architecture.md, "Packed
  /// contacts"). The results agree with the one-at-a-time loop to rounding; false selects that
  /// loop (tests compare the two).
  bool packed_contacts = true;

  /// Refuses a configuration no run can start from, naming the field and its valid range.
  void validate() const {
    domain.validate();
    const std::string where = "SimulationConfig";
    require(dt > 0.0 && std::isfinite(dt), where, "dt", dt, "(0, inf) s");
    require(thickness > 0.0 && std::isfinite(thickness), where, "thickness", thickness, "(0, inf) m");
    require(time_step_safety > 0.0 && time_step_safety <= 1.0, where, "time_step_safety", time_step_safety,
            "(0, 1]");
    require(max_overlap_ratio > 0.0 && max_overlap_ratio <= 1.0, where, "max_overlap_ratio",
            max_overlap_ratio, "(0, 1]");
    for (int k = 0; k < D::dim; ++k)
      require(std::isfinite(gravity[k]), where, "gravity[" + std::to_string(k) + "]", gravity[k], "finite");
  }
};

}  // namespace granule
