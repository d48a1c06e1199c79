#pragma once
// Tangential spring-dashpot with history and a Coulomb limit (Cundall & Strack 1979).
//
//   xi  <- project(xi, n) + v_t dt                 (history: tangential displacement [m])
//   F_t = -k_t xi - gamma_t v_t,      |F_t| <= mu_s |F_n|
//
// Stiffness policies:
//   MindlinStiffness: k_t = 8 G* sqrt(R* delta),  gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*),
//                     S_t = 8 G* sqrt(R* delta)   (000 eq. B3-B6, 001 eq. A9-A11; Mindlin 1949)
//   LinearStiffness:  k_t = r k_n (r = tangential_stiffness_ratio, 2/7 by default so normal and
//                     tangential periods match for solid spheres), gamma_t = 2 xi sqrt(m* k_t).
// Truncation (what the Coulomb limit acts on) is an explicit choice:
//   Truncation::Total      the total force (spring + damping) is limited to mu |F_n| and the
//                          spring is reset so that -k_t xi - gamma_t v_t equals the limited
//                          force: the correction of paper 001 section 2.2 (as LAMMPS granular).
//   Truncation::SpringOnly legacy LIGGGHTS 3.8: only |k_t xi| is compared with mu |F_n|; when
//                          sliding the spring is rescaled and damping dropped, when sticking
//                          spring + damping may exceed the limit (001 section 2.2).
// HistoryRotation chooses whether projection keeps the spring length (see history.hpp).
#include <cmath>
#include <numbers>
#include <string>

#include "granule/contact/geometry.hpp"
#include "granule/contact/tangential/history.hpp"

namespace granule::contact {

enum class Truncation { Total, SpringOnly };
enum class HistoryRotation { ProjectKeepLength, Project };

struct MindlinStiffness {
  static std::string signature() { return "Mindlin"; }
  struct Params {
    double G_eff = 0.0;    ///< [Pa]
    double damping = 0.0;  ///< -2 sqrt(5/6) beta [-]
  };
  static Params make(const PairMaterial& p) {
    return {p.G_eff, -2.0 * std::sqrt(5.0 / 6.0) * p.beta()};
  }
  /// Returns k_t [N/m]; writes gamma_t [N s/m].
  template <class D>
  static double eval(const Params& p, const ContactGeometry<D>& g, const NormalResult&,
                     double& gamma_t) {
    const double kt = 8.0 * p.G_eff * std::sqrt(g.r_eff * g.overlap);
    gamma_t = p.damping * std::sqrt(kt * g.m_eff);
    return kt;
  }
};

struct LinearStiffness {
  static std::string signature() { return "Linear"; }
  struct Params {
    double k_t = 0.0;  ///< [N/m]
    double xi = 0.0;   ///< damping ratio [-]
  };
  static Params make(const PairMaterial& p) {
    const double l = std::log(p.restitution);
    return {p.kt_ratio * p.k_n_linear, -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi)};
  }
  template <class D>
  static double eval(const Params& p, const ContactGeometry<D>& g, const NormalResult&,
                     double& gamma_t) {
    gamma_t = 2.0 * p.xi * std::sqrt(g.m_eff * p.k_t);
    return p.k_t;
  }
};

template <class Stiffness, Truncation Trunc = Truncation::Total,
          HistoryRotation Rot = HistoryRotation::ProjectKeepLength>
struct SpringTangential {
  static std::string signature() {
    return "SpringTangential<" + Stiffness::signature() +
           (Trunc == Truncation::Total ? ",Total" : ",SpringOnly") +
           (Rot == HistoryRotation::ProjectKeepLength ? ",KeepLength>" : ",Project>");
  }
  struct Params {
    typename Stiffness::Params stiffness;
    double mu_s = 0.0;  ///< [-]
  };
  template <class D>
  struct State {
    typename D::Vec xi = D::zero();  ///< tangential spring displacement [m]
  };
  static Params make(const PairMaterial& p) { return {Stiffness::make(p), p.mu_s}; }

  template <class D>
  static typename D::Vec eval(const Params& p, const ContactGeometry<D>& g, const NormalResult& nr,
                              State<D>& s) {
    using Vec = typename D::Vec;
    project_history(s.xi, g.n, Rot == HistoryRotation::ProjectKeepLength);
    s.xi += g.vt * g.dt;
    double gamma_t = 0.0;
    const double kt = Stiffness::eval(p.stiffness, g, nr, gamma_t);
    const double limit = p.mu_s * std::abs(nr.fn);
    const Vec spring = -kt * s.xi;
    const Vec damp = -gamma_t * g.vt;
    if constexpr (Trunc == Truncation::Total) {
      Vec ft = spring + damp;
      const double f2 = ft.squaredNorm();
      if (f2 > limit * limit) {
        ft *= limit / std::sqrt(f2);
        s.xi = kt > 0.0 ? Vec(-(ft - damp) / kt) : Vec(D::zero());
      }
      return ft;
    } else {
      const double f2 = spring.squaredNorm();
      if (f2 > limit * limit) {
        const double ratio = limit / std::sqrt(f2);
        s.xi *= ratio;
        return spring * ratio;
      }
      return spring + damp;
    }
  }
  /// Energy stored in the tangential spring, k_t |xi|^2 / 2 [J].
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>& g, const NormalResult& nr,
                       const State<D>& s) {
    double gamma_t = 0.0;
    return 0.5 * Stiffness::eval(p.stiffness, g, nr, gamma_t) * s.xi.squaredNorm();
  }
  template <class D>
  static void reverse(State<D>& s) {
    reverse_history(s.xi);
  }
};

/// Hertz-Mindlin tangential spring, corrected truncation (001 section 2.2).
using MindlinTangential = SpringTangential<MindlinStiffness, Truncation::Total>;
/// Hertz-Mindlin tangential spring as in LIGGGHTS 3.8 (limit on the spring force only).
using MindlinTangentialLegacy = SpringTangential<MindlinStiffness, Truncation::SpringOnly>;
/// Linear tangential spring-dashpot with Coulomb limit.
using LinearTangential = SpringTangential<LinearStiffness, Truncation::Total>;

}  // namespace granule::contact
