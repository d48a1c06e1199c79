#pragma once
// Constant directional torque rolling resistance (model A of Ai et al. 2011, Zhou et al. 1999):
//
//   M_r = -mu_r R* |F_n| w_r / |w_r|,     w_r = rolling part of omega_i - omega_j
// (in 3D the twist component along n is removed). To avoid the chatter of the pure model when
// w_r -> 0, the torque is capped at what stops the relative rolling within one step,
// I_r |w_r| / dt, with the rolling inertia I_r of Ai et al. 2011 eq. 14. At dt = 0 (the engine's
// set-up evaluation) there is no step to overshoot and the cap is not applied.
#include <cmath>

#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct ConstantTorqueRolling {
  static std::string signature() { return "ConstantTorqueRolling"; }
  struct Params {
    double mu_r = 0.0;  ///< [-]
  };
  template <class D>
  using State = NoState<D>;
  static constexpr bool needs_inertia = true;
  static Params make(const PairMaterial& p) { return {p.mu_r}; }

  template <class D>
  static typename D::AngVec eval(const Params& p, const ContactGeometry<D>& g,
                                 const NormalResult& nr, State<D>&) {
    const typename D::AngVec wr = g.omega_rel - D::along(g.omega_rel, g.n);
    const double w = D::norm(wr);
    if (w <= 0.0) return D::zero_ang();
    const double full = p.mu_r * g.r_eff * std::abs(nr.fn);
    const double torque = g.dt > 0.0 ? std::min(full, g.i_roll * w / g.dt) : full;
    return wr * (-torque / w);
  }
  template <class D>
  static double energy(const Params&, const ContactGeometry<D>&, const NormalResult&, const State<D>&) {
    return 0.0;
  }
  template <class D>
  static void reverse(State<D>&) {}
};

}  // namespace granule::contact
