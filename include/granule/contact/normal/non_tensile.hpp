#pragma once
// NonTensile<Normal>: the normal force of a normal law clipped at zero, F_n <- max(F_n, 0), so
// that its dashpot never pulls the particles together (LAMMPS granular `limit_damping`,
// LIGGGHTS `limitForce`). The clip acts in the normal slot, before cohesion: a cohesion law
// still attracts. The tangential and rolling Coulomb limits then use the clipped force (they
// read F_n from the normal slot), so in the tensile tail of an impact, where the dashpot of the
// plain law pulls, they allow no friction at all. Without the wrapper the limits use |F_n| of
// the tensile force (docs/physics.md, "Normal laws").
//
// The damping coefficient is the plain law's, so the contact ends earlier and the realised
// restitution is higher than the material's e: for HertzNormal it is a function of e alone
// (the damping is scale-free, gamma ~ delta^1/4), 0.2 -> 0.325, 0.5 -> 0.553, 0.8 -> 0.808
// (tests/contact/test_restitution.cpp, against the clipped one-contact ODE).
// hertz_restitution_for_clipped(e) is the material restitution to give so that the clipped
// Hertz law realises e: it inverts the fit of Thornton, Cummins & Cleary (2013, Powder Technol.
// 233, 30-46), which maps e to the damping ratio of a Hertz contact whose force may not pull, gamma = sqrt(1 / (1 - (1 + e)^2 exp(alpha)) - 1), alpha = e (h1 + e (h2 + ... h10)),
// with their gamma = sqrt(5/6) |beta| in granule's form (the dashpot 2 gamma sqrt(m* S_n),
// S_n = 2 E* sqrt(R* delta)); measured against the clipped ODE to 3e-4 in e over 0.2-0.9.
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "granule/contact/geometry.hpp"
#include "granule/core/error.hpp"

namespace granule::contact {

template <class Normal>
struct NonTensile {
  using Base = Normal;
  static std::string signature() { return "NonTensile<" + Normal::signature() + ">"; }
  using Params = typename Normal::Params;
  static constexpr bool hertzian = Normal::hertzian;
  static constexpr bool lanes = Normal::lanes;

  static Params make(const PairMaterial& p) { return Normal::make(p); }

  template <class D>
  static NormalResultOf<D> eval(const Params& p, const ContactGeometry<D>& g) {
    using R = typename D::Real;
    NormalResultOf<D> r = Normal::template eval<D>(p, g);
    where_assign(r.fn < 0.0, r.fn, [&]() -> R { return R(0.0); });
    return r;
  }

  static double elastic_energy(const Params& p, double overlap, double r_eff) {
    return Normal::elastic_energy(p, overlap, r_eff);
  }
};

/// Material restitution that makes NonTensile<HertzNormal> realise the restitution e in (0, 1]
/// (the fit of Thornton, Cummins & Cleary 2013; see the top of this file).
inline double hertz_restitution_for_clipped(double e) {
  if (!(e > 0.0 && e <= 1.0)) {
    throw InvalidParameter("hertz_restitution_for_clipped: the restitution must lie in (0, 1], got " +
                           std::to_string(e));
  }
  if (e == 1.0) return 1.0;
  constexpr double h[] = {-6.918798, -16.41105, 146.8049, -796.4559, 2928.711,
                          -7206.864, 11494.29,  -11342.18, 6276.757,  -1489.915};
  double poly = 0.0;
  for (int k = 9; k >= 0; --k) poly = h[k] + e * poly;
  const double alpha = e * poly;
  const double gamma = std::sqrt(1.0 / (1.0 - (1.0 + e) * (1.0 + e) * std::exp(alpha)) - 1.0);
  // granule: gamma = sqrt(5/6) |beta|, beta = ln e_in / sqrt(ln^2 e_in + pi^2).
  const double beta = gamma / std::sqrt(5.0 / 6.0);
  if (!(beta < 1.0)) {
    throw InvalidParameter("hertz_restitution_for_clipped: no material restitution realises e = " +
                           std::to_string(e) + " with a clipped Hertz force (below the fit's range)");
  }
  return std::exp(-std::numbers::pi * beta / std::sqrt(1.0 - beta * beta));
}

}  // namespace granule::contact
