#pragma once
// No cohesion.
#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct NoCohesion {
  static std::string signature() { return "NoCohesion"; }
  struct Params {};
  static Params make(const PairMaterial&, double /*thickness*/) { return {}; }
  template <class D>
  static double eval(const Params&, const ContactGeometry<D>&) {
    return 0.0;
  }
};

}  // namespace granule::contact
