#pragma once
// No cohesion.
#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct NoCohesion {
  struct Params {};
  static Params make(const PairMaterial&, double /*thickness*/) { return {}; }
  template <class D>
  static double eval(const Params&, const ContactGeometry<D>&) {
    return 0.0;
  }
};

}  // namespace granule::contact
