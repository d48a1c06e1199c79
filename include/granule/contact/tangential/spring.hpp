#pragma once
// Tangential spring-dashpot with history and a Coulomb limit (Cundall & Strack 1979).
//
//   F_t = F_s - gamma_t v_t,      |F_t| <= mu_s |F_n|
//
// Stiffness policies:
//   MindlinStiffness: k_t = 8 G* sqrt(R* delta),  gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*),
//                     S_t = 8 G* sqrt(R* delta)   (000 eq. B3-B6, 001 eq. A9-A11; Mindlin 1949)
//   LinearStiffness:  k_t = r k_n (r = tangential_stiffness_ratio, 2/7 by default so normal and
//                     tangential periods match for solid spheres), gamma_t = 2 xi sqrt(m* k_t).
//
// How the spring force F_s is carried from step to step (SpringHistory):
//   IncrementalForce   the spring force is the history and only its increment sees the current
//                      stiffness (Thornton, Cummins & Cleary 2013, Powder Technol. 233, eq. 18;
//                      LAMMPS granular "mindlin/force"):
//                        F_s <- R(F_s) - k_t v_t dt,
//                      and when the stiffness falls (unloading: the contact area shrinks) the
//                      carried force is first scaled with it, F_s <- F_s k_t / k_t,old, which keeps
//                      the elastic displacement F_s / k_t (LAMMPS "mindlin_rescale/force"). Stored
//                      energy |F_s|^2 / (2 k_t). With E = |F_s|^2/(2 k_t) and P = -F_s . v_t the
//                      power the relative motion puts into the spring,
//                        dE/dt - P = -|k_t'| |F_s|^2 / (2 k_t^2) <= 0
//                      when loading (no rescale) and when unloading (with the rescale): the spring
//                      is passive. State: F_s and k_t,old (the stiffness of the last step).
//   TotalDisplacement  the total tangential displacement is the history, xi <- R(xi) + v_t dt,
//                      F_s = -k_t xi. Exact for a constant k_t (LinearStiffness, and its smaller
//                      state). With the Mindlin k_t(delta) it creates energy while the contact
//                      loads, dE/dt - P = k_t' |xi|^2 / 2 > 0 (the path-dependence problem of
//                      Elata & Berryman 1996; tests/contact measure +2.6 % of the impact energy at
//                      25 deg): kept only as the LIGGGHTS 3.8 behaviour (MindlinTangentialLegacy).
// R is how the history follows the contact frame (HistoryRotation, history.hpp):
//   ProjectKeepLengthTwist  projection onto the new tangent plane, previous length restored,
//                           then rotation about n by the mean twist angle of the step: frame
//                           indifferent (tests/contact/test_history_objectivity.cpp). Default.
//   ProjectKeepLength       the same without the twist rotation (LIGGGHTS 3.8).
//   Project                 plain projection, the spring shortens (LAMMPS hooke/history).
// Truncation (what the Coulomb limit acts on):
//   Total       the total force (spring + damping) is limited to F_lim = mu_s |F_n|: the force
//               returned is the trial force scaled to length F_lim (001 section 2.2). The
//               spring-dashpot element (k_t, gamma_t in parallel, in series with the slider) is
//               then relaxed implicitly to carry exactly that force: with F_s,old the history
//               after R (and the unloading rescale) but before this step's increment, the
//               backward-Euler step of the element, -k_t xi_new - gamma_t (xi_new - xi_old)/dt =
//               F_lim, gives
//                 F_s,new = F_lim + c (F_s,old - F_lim),   c = gamma_t / (k_t dt + gamma_t)
//               (xi = -F_s / k_t for the displacement form). Without a dashpot c = 0 and the
//               spring takes F_lim; at dt = 0 (set-up) c = 1 and the spring is unchanged. The
//               former reset F_s = F_lim + gamma_t v_t (LAMMPS granular; Luding 2008 eq. 17) let the
//               dashpot keep the whole relative velocity although the slider slips, and loaded
//               the spring with energy no work had put in whenever gamma_t |v_t| > F_lim.
//   SpringOnly  legacy LIGGGHTS 3.8: only |F_s| is compared with mu |F_n|; when sliding the
//               spring is rescaled to the limit and damping dropped, when sticking spring +
//               damping may exceed the limit (001 section 2.2).
#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>

#include "granule/contact/geometry.hpp"
#include "granule/contact/tangential/history.hpp"

namespace granule::contact {

enum class Truncation { Total, SpringOnly };
enum class HistoryRotation { ProjectKeepLengthTwist, ProjectKeepLength, Project };
enum class SpringHistory { IncrementalForce, TotalDisplacement };

struct MindlinStiffness {
  static std::string signature() { return "Mindlin"; }
  /// k_t changes with the overlap: only the force form is energy consistent.
  static constexpr SpringHistory default_history = SpringHistory::IncrementalForce;
  struct Params {
    double G_eff = 0.0;    ///< [Pa]
    double damping = 0.0;  ///< -2 sqrt(5/6) beta [-]
  };
  static Params make(const PairMaterial& p) {
    return {p.G_eff, -2.0 * std::sqrt(5.0 / 6.0) * p.beta()};
  }
  /// Returns k_t [N/m]; writes gamma_t [N s/m].
  template <class D>
  static typename D::Real eval(const Params& p, const ContactGeometry<D>& g, const NormalResultOf<D>&,
                               typename D::Real& gamma_t) {
    using std::sqrt;
    const typename D::Real kt = 8.0 * p.G_eff * sqrt(g.r_eff * g.overlap);
    gamma_t = p.damping * sqrt(kt * g.m_eff);
    return kt;
  }
};

struct LinearStiffness {
  static std::string signature() { return "Linear"; }
  /// Constant k_t: the displacement form is exact and needs no stored stiffness.
  static constexpr SpringHistory default_history = SpringHistory::TotalDisplacement;
  struct Params {
    double k_t = 0.0;  ///< [N/m]
    double xi = 0.0;   ///< damping ratio [-]
  };
  static Params make(const PairMaterial& p) {
    const double l = std::log(p.restitution);
    return {p.kt_ratio * p.k_n_linear, -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi)};
  }
  template <class D>
  static typename D::Real eval(const Params& p, const ContactGeometry<D>& g, const NormalResultOf<D>&,
                               typename D::Real& gamma_t) {
    using std::sqrt;
    gamma_t = 2.0 * p.xi * sqrt(g.m_eff * p.k_t);
    return typename D::Real(p.k_t);
  }
};

template <class D>
struct SpringForceState {
  typename D::Vec fs = D::zero();    ///< spring force on i [N]
  typename D::Real kt_old = 0.0;     ///< k_t of the last step [N/m] (0: new contact)
};

template <class D>
struct SpringDisplacementState {
  typename D::Vec xi = D::zero();  ///< total tangential spring displacement [m]
};

template <class Stiffness, Truncation Trunc = Truncation::Total,
          HistoryRotation Rot = HistoryRotation::ProjectKeepLengthTwist,
          SpringHistory History = Stiffness::default_history>
struct SpringTangential {
  using StiffnessLaw = Stiffness;
  static constexpr bool force_history = History == SpringHistory::IncrementalForce;
  static constexpr bool needs_twist = Rot == HistoryRotation::ProjectKeepLengthTwist;
  /// The force form with total truncation is written over D::Real (core/lanes.hpp); the
  /// other variants are scalar only.
  static constexpr bool lanes = force_history && Trunc == Truncation::Total;

  /// Checkpoints carry this name. A token changes whenever the update it names changes, so
  /// that older checkpoints of a changed law are refused: the force form adds
  /// ",IncrementalForce" (the displacement form adds nothing, so LIGGGHTS 3.8 checkpoints,
  /// whose law is unchanged, still load), and Total truncation with the implicit relaxation is
  /// ",TotalImplicit".
  static std::string signature() {
    return "SpringTangential<" + Stiffness::signature() + (force_history ? ",IncrementalForce" : "") +
           (Trunc == Truncation::Total ? ",TotalImplicit" : ",SpringOnly") +
           (Rot == HistoryRotation::ProjectKeepLengthTwist ? ",KeepLengthTwist>"
            : Rot == HistoryRotation::ProjectKeepLength    ? ",KeepLength>"
                                                           : ",Project>");
  }
  struct Params {
    typename Stiffness::Params stiffness;
    double mu_s = 0.0;  ///< [-]
  };
  template <class D>
  struct State : std::conditional_t<force_history, SpringForceState<D>, SpringDisplacementState<D>> {};
  static Params make(const PairMaterial& p) { return {Stiffness::make(p), p.mu_s}; }

  /// The history follows the contact frame (R above).
  template <class D>
  static void follow_contact(typename D::Vec& x, const ContactGeometry<D>& g) {
    if constexpr (needs_twist) {
      rotate_history<D>(x, g);
    } else {
      project_history(x, g.n, Rot == HistoryRotation::ProjectKeepLength);
    }
  }

  /// k_t and gamma_t, which act on the slip velocity at the contact point.
  template <class D>
  static SpringDashpot spring_dashpot(const Params& p, const ContactGeometry<D>& g, const NormalResult& nr) {
    double gamma_t = 0.0;
    const double kt = Stiffness::eval(p.stiffness, g, nr, gamma_t);
    return {kt, gamma_t};
  }

  template <class D>
  static typename D::Vec eval(const Params& p, const ContactGeometry<D>& g, const NormalResultOf<D>& nr,
                              State<D>& s) {
    using std::abs;
    using std::sqrt;
    using Vec = typename D::Vec;
    using R = typename D::Real;
    R gamma_t = 0.0;
    const R kt = Stiffness::eval(p.stiffness, g, nr, gamma_t);
    const R limit = p.mu_s * abs(nr.fn);
    const Vec damp = -gamma_t * g.vt_damp;
    if constexpr (force_history) {
      follow_contact<D>(s.fs, g);
      // Unloading: keep F_s / k_t.
      where_assign(kt < s.kt_old, s.fs, [&]() -> Vec { return s.fs * (kt / s.kt_old); });
      s.kt_old = kt;
      const Vec fs_old = s.fs;
      s.fs -= (kt * g.dt) * g.vt;
      if constexpr (Trunc == Truncation::Total) {
        Vec ft = s.fs + damp;
        const R f2 = ft.squaredNorm();
        const auto sliding = f2 > limit * limit;
        where_assign(sliding, ft, [&]() -> Vec { return ft * (limit / sqrt(f2)); });
        where_assign(sliding, s.fs, [&]() -> Vec {
          const R c = select(gamma_t > 0.0, gamma_t / (kt * g.dt + gamma_t), R(0.0));
          return ft + c * (fs_old - ft);
        });
        return ft;
      } else {
        const double f2 = s.fs.squaredNorm();
        if (f2 > limit * limit) {
          s.fs *= limit / std::sqrt(f2);
          return s.fs;
        }
        return s.fs + damp;
      }
    } else {
      follow_contact<D>(s.xi, g);
      if constexpr (Trunc == Truncation::Total) {
        const Vec xi_old = s.xi;
        s.xi += g.vt * g.dt;
        Vec ft = -kt * s.xi + damp;
        const double f2 = ft.squaredNorm();
        if (f2 > limit * limit) {
          ft *= limit / std::sqrt(f2);
          if (kt > 0.0) {
            const double c = gamma_t > 0.0 ? gamma_t / (kt * g.dt + gamma_t) : 0.0;
            const Vec xi_lim = -ft / kt;
            s.xi = xi_lim + c * (xi_old - xi_lim);
          } else {
            s.xi = D::zero();
          }
        }
        return ft;
      } else {
        s.xi += g.vt * g.dt;
        const Vec spring = -kt * s.xi;
        const double f2 = spring.squaredNorm();
        if (f2 > limit * limit) {
          const double ratio = limit / std::sqrt(f2);
          s.xi *= ratio;
          return spring * ratio;
        }
        return spring + damp;
      }
    }
  }
  /// Energy stored in the tangential spring, |F_s|^2 / (2 k_t) = k_t |xi|^2 / 2 [J].
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>& g, const NormalResult& nr,
                       const State<D>& s) {
    double gamma_t = 0.0;
    const double kt = Stiffness::eval(p.stiffness, g, nr, gamma_t);
    if constexpr (force_history) {
      return kt > 0.0 ? 0.5 * s.fs.squaredNorm() / kt : 0.0;
    } else {
      return 0.5 * kt * s.xi.squaredNorm();
    }
  }
  template <class D>
  static void reverse(State<D>& s) {
    if constexpr (force_history) {
      reverse_history(s.fs);  // k_t,old is the same seen from either side
    } else {
      reverse_history(s.xi);
    }
  }
};

/// Hertz-Mindlin tangential spring: force history with unloading rescale, corrected truncation
/// (001 section 2.2) with implicit relaxation, history turned with the contact.
using MindlinTangential = SpringTangential<MindlinStiffness>;
/// Hertz-Mindlin tangential spring as in LIGGGHTS 3.8: displacement history F_s = -k_t(delta) xi,
/// limit on the spring force only, no twist rotation.
using MindlinTangentialLegacy = SpringTangential<MindlinStiffness, Truncation::SpringOnly,
                                                 HistoryRotation::ProjectKeepLength,
                                                 SpringHistory::TotalDisplacement>;
/// Linear tangential spring-dashpot with Coulomb limit (displacement history: k_t is constant).
using LinearTangential = SpringTangential<LinearStiffness>;

}  // namespace granule::contact
