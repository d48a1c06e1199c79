#pragma once
// No rolling resistance: no torque beyond the lever arm of the tangential force, no history.
#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct NoRolling {
  static std::string signature() { return "NoRolling"; }
  struct Params {};
  template <class D>
  using State = NoState<D>;
  static constexpr bool needs_inertia = false;
  static constexpr bool lanes = true;  ///< written over D::Real (core/lanes.hpp)
  static Params make(const PairMaterial&) { return {}; }
  template <class D>
  static typename D::AngVec eval(const Params&, const ContactGeometry<D>&, const NormalResultOf<D>&,
                                 State<D>&) {
    return D::zero_ang();
  }
  template <class D>
  static double energy(const Params&, const ContactGeometry<D>&, const NormalResult&, const State<D>&) {
    return 0.0;
  }
  template <class D>
  static void reverse(State<D>&) {}
};

}  // namespace granule::contact
