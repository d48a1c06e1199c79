#pragma once
// The vocabulary every contact law speaks. One ContactGeometry is built per touching pair (or
// particle-wall pair) and handed, read-only, to the sub-models in the order fixed by
// ContactModel::evaluate: normal -> cohesion -> tangential -> rolling.
//
// Conventions: `n` is the unit normal pointing from j (or the wall) towards i; overlap > 0 in
// contact; v_rel is the velocity of i relative to j at the contact point, so vn = v_rel . n is
// negative while the pair approaches. Forces returned are those acting ON i.
//
// dt is the time the laws advance their history by. The engine's set-up evaluation (forces for
// the first half kick, before any time has passed) hands dt = 0: every law must then be well
// defined and add no increment (docs/physics.md, "Set-up evaluation").
#include <limits>

#include "granule/core/dimension.hpp"
#include "granule/core/lanes.hpp"
#include "granule/materials/pair_material.hpp"

namespace granule::contact {

template <class D>
struct ContactGeometry {
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  using Real = typename D::Real;  ///< double, or a pack of lanes (core/lanes.hpp)
  Vec n;                ///< unit normal, j -> i
  Real overlap;       ///< delta [m]
  Real distance;      ///< centre distance [m]; +inf for a wall (flat-contact limit)
  Real r_i, r_j;      ///< radii [m]; r_j = +inf for a wall
  Real arm_i, arm_j;  ///< distances from the centres of i and j to the contact point [m]
  Real r_eff;         ///< R* [m]
  Real m_eff;         ///< m* [kg]
  Vec v_rel;            ///< relative velocity at the contact point [m/s]
  Real vn;            ///< v_rel . n [m/s]
  Vec vt;               ///< tangential part of v_rel [m/s]
  AngVec omega_rel;     ///< omega_i - omega_j [rad/s]
  Real i_roll;        ///< rolling inertia I_r, 1/I_r = sum 1/(I + m r^2) (Ai et al. 2011)
                        ///< [kg m^2]; filled only when the rolling model asks for it
  Real dt;            ///< time step the history advances by [s] (0 in the set-up evaluation)
  /// 3D: mean twist angle of the step about n, theta = (omega_i + omega_j)/2 . n dt (wall:
  /// (omega_i + Omega_wall)/2 . n dt) [rad]: the angle the tangent plane turns about the normal
  /// with the pair. Filled only when a law asks for it (needs_twist); always 0 in 2D, where
  /// nothing turns about the in-plane normal.
  Real twist = 0.0;
  /// Velocities the dissipative terms (normal and tangential dashpots, rolling viscosity) act
  /// on. The default integrator hands the same values as vn, vt and omega_rel (call
  /// damp_at_kinematic_velocity()); integrators::VelocityVerletPredictedDamping hands the
  /// relative velocity predicted for the end of the step (integrators/).
  Real vn_damp;       ///< [m/s]
  Vec vt_damp;          ///< [m/s]
  AngVec omega_rel_damp;  ///< [rad/s]

  /// Dashpots see the same relative velocity as the springs (velocity Verlet).
  void damp_at_kinematic_velocity() {
    vn_damp = vn;
    vt_damp = vt;
    omega_rel_damp = omega_rel;
  }
};

/// What the normal law hands to the later sub-models (R: double or Lane).
template <class R>
struct NormalResultT {
  R fn = 0.0;          ///< total normal force along n on i (repulsive > 0) [N]
  R fn_elastic = 0.0;  ///< elastic part [N]
  R kn = 0.0;          ///< secant normal stiffness fn_elastic / overlap [N/m]
};
using NormalResult = NormalResultT<double>;
template <class D>
using NormalResultOf = NormalResultT<typename D::Real>;

/// A sub-model's linear spring and dashpot at the current state, for the engine's time-step
/// limit (Simulation::rolling_stability_limit): stiffness [N/m or N m/rad], damping
/// [N s/m or N m s/rad].
struct SpringDashpot {
  double stiffness = 0.0;
  double damping = 0.0;
};

/// Total force of one contact. Torques include the lever arm of the tangential force and the
/// rolling torque; torque_j is the torque on j (walls ignore it).
template <class D>
struct ContactForce {
  typename D::Vec force = D::zero();              ///< force on i [N]; j receives -force
  typename D::AngVec torque_i = D::zero_ang();    ///< [N m]
  typename D::AngVec torque_j = D::zero_ang();    ///< [N m]
  typename D::Real fn = 0.0;                      ///< normal force magnitude (signed) [N]
  typename D::Vec ft = D::zero();                 ///< tangential force on i [N]
};

/// Slot for a sub-model without per-contact history.
template <class D>
struct NoState {};

}  // namespace granule::contact
