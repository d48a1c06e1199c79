#pragma once
// DMT adhesion (Derjaguin, Muller & Toporov 1975; Johnson, Contact Mechanics 1985, sec. 5.5;
// the LAMMPS granular "dmt" normal model): the Hertz contact plus a constant pull
//   F = F_Hertz - 2 pi w R*,   w = 2 gamma (Dupre, like surfaces),
// acting while the particles overlap (the contact breaks at delta = 0, pull-off 2 pi w R*).
// 3D spheres only.
#include <numbers>
#include <string>

#include "granule/contact/geometry.hpp"

namespace granule::contact {

struct DmtCohesion {
  static std::string signature() { return "DmtCohesion"; }
  struct Params {
    double w = 0.0;  ///< work of adhesion 2 gamma [J/m^2]
  };
  static Params make(const PairMaterial& p, double /*thickness*/) { return {2.0 * p.surface_energy}; }
  static constexpr bool lanes = true;  ///< eval is written over D::Real (core/lanes.hpp)

  /// Attractive force magnitude 2 pi w R* [N].
  template <class D>
  static typename D::Real eval(const Params& p, const ContactGeometry<D>& g) {
    static_assert(D::dim == 3, "DmtCohesion: DMT is a law of spheres (3D)");
    return (2.0 * std::numbers::pi * p.w) * g.r_eff;
  }
  /// Potential of the pull, -2 pi w R* delta while overlapping, 0 apart (continuous at touch) [J].
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>& g) {
    return g.overlap > 0.0 ? -(2.0 * std::numbers::pi * p.w) * g.r_eff * g.overlap : 0.0;
  }
};

}  // namespace granule::contact
