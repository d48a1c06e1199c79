#pragma once
// Frictionless contacts: no tangential force and no per-contact history.
#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct NoTangential {
  static std::string signature() { return "NoTangential"; }
  struct Params {};
  template <class D>
  using State = NoState<D>;
  static constexpr bool lanes = true;  ///< written over D::Real (core/lanes.hpp)
  static Params make(const PairMaterial&) { return {}; }
  template <class D>
  static typename D::Vec eval(const Params&, const ContactGeometry<D>&, const NormalResultOf<D>&,
                              State<D>&) {
    return D::zero();
  }
  template <class D>
  static double energy(const Params&, const ContactGeometry<D>&, const NormalResult&, const State<D>&) {
    return 0.0;
  }
  template <class D>
  static void reverse(State<D>&) {}
};

}  // namespace granule::contact
