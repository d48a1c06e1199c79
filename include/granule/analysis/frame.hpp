#pragma once
// A Frame is a self-contained snapshot of a simulation: particles and contacts at one instant.
// Every analysis in granule::analysis reads a Frame, so the same measurement runs on the live
// simulation (Simulation::frame()) and on a state read back from a checkpoint.
#include <cstdint>
#include <limits>
#include <vector>

#include "granule/core/dimension.hpp"

namespace granule::analysis {

/// One contact as seen by analysis. The force is the one exerted ON particle i.
/// For a particle-wall contact, j == kWall and `wall` names the wall.
template <class D>
struct ContactRecord {
  using Vec = typename D::Vec;
  static constexpr std::uint32_t kWall = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t i = 0;        ///< index of the first particle in the frame
  std::uint32_t j = kWall;    ///< index of the second particle, or kWall
  std::uint32_t wall = 0;     ///< wall index when j == kWall
  Vec normal = Vec::Zero();   ///< unit normal, pointing from j (or the wall) towards i
  Vec branch = Vec::Zero();   ///< vector from the centre of i to the centre of j (periodic
                              ///< images resolved); for walls: from i to the contact point
  Vec contact_point = Vec::Zero();  ///< [m]
  double overlap = 0.0;       ///< [m]
  double fn = 0.0;            ///< normal force on i along `normal` (positive = repulsive) [N]
  Vec ft = Vec::Zero();       ///< tangential force on i [N]
  double mu = 0.0;            ///< sliding friction coefficient of the pair [-]
};

template <class D>
struct Frame {
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  double time = 0.0;                 ///< [s]
  double thickness = 1.0;            ///< out-of-plane thickness of 2D disks [m] (unused in 3D)
  std::vector<Vec> x;                ///< positions [m]
  std::vector<Vec> v;                ///< velocities [m/s]
  std::vector<AngVec> omega;         ///< angular velocities [rad/s]
  std::vector<double> radius;        ///< [m]
  std::vector<double> mass;          ///< [kg]
  std::vector<std::uint64_t> id;     ///< stable particle ids
  std::vector<std::uint32_t> group;  ///< group labels
  std::vector<ContactRecord<D>> contacts;
  Vec box_lo = Vec::Zero();          ///< domain lower corner [m]
  Vec box_hi = Vec::Zero();          ///< domain upper corner [m]
  Eigen::Matrix<bool, D::dim, 1> periodic = Eigen::Matrix<bool, D::dim, 1>::Constant(false);
  // (After the fields above, so that designated initialisers of a Frame stay valid.)
  std::vector<Vec> force;            ///< total force on each particle at the last evaluation [N]
  std::vector<AngVec> torque;        ///< total torque about its centre [N m]

  std::size_t size() const { return x.size(); }
};

}  // namespace granule::analysis
