#pragma once
// No cohesion.
#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct NoCohesion {
  static std::string signature() { return "NoCohesion"; }
  struct Params {};
  static Params make(const PairMaterial&, double /*thickness*/) { return {}; }
  static constexpr bool lanes = true;  ///< written over D::Real (core/lanes.hpp)
  template <class D>
  static typename D::Real eval(const Params&, const ContactGeometry<D>&) {
    return typename D::Real(0.0);
  }
  /// Potential of the cohesive force [J]: none.
  template <class D>
  static double energy(const Params&, const ContactGeometry<D>&) {
    return 0.0;
  }
};

}  // namespace granule::contact
