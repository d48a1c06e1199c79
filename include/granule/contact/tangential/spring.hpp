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
//   Potential          (default for the Mindlin stiffness) the total tangential displacement is
//                      the history, xi <- R(xi) + v_t dt, F_s = -k_t(delta) xi, and the pair's
//                      elastic forces derive from one potential,
//                        V(delta, xi) = V_n(delta) + k_t(delta) |xi|^2 / 2,
//                      so the normal force carries the coupling term dV/ddelta - V_n' =
//                      k_t'(delta) |xi|^2 / 2 (normal_coupling below; ContactModel adds it).
//                      Under JKR the slots see delta_H = a(delta)^2 / R*, not delta, and
//                      ContactModel multiplies the term by d delta_H / d delta
//                      (JkrCohesion::elastic_overlap_slope), the chain rule of k_t(delta_H).
//                      Without that term the spring creates k_t' |xi|^2/2 d(delta) of energy
//                      while the contact loads (TotalDisplacement); with it the law is
//                      hyperelastic: conservative while it sticks, dissipative while it slides
//                      (the path-independence requirement of Elata & Berryman 1996). The term is
//                      small: at full mobilisation |xi| = mu F_n / k_t it is
//                      mu^2 E*/(24 G*) of the Hertz force for Mindlin (0.16 % at mu = 0.092,
//                      nu = 0.23). It reproduces Chung & Ooi (2011) Test 4 at every angle
//                      (tests/contact/test_oblique_impact.cpp); the incremental form below does
//                      not below ~10 deg (docs/physics.md, "Tangential laws").
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
//                      The rescale also scales the increments made while the contact was
//                      smaller than it is now, which Mindlin & Deresiewicz keep until the contact
//                      shrinks below the size at which they were made: in the micro-slip regime
//                      the force is released too early (Chung & Ooi Test 4 at 5 deg: rebound
//                      spin 2.5x, tangential restitution 0.86 against 0.95). Kept as the named
//                      policy MindlinTangentialIncremental (HertzMindlinIncremental).
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
enum class SpringHistory { Potential, IncrementalForce, TotalDisplacement };

struct MindlinStiffness {
  static std::string signature() { return "Mindlin"; }
  /// k_t changes with the overlap: the displacement history with the normal coupling term of
  /// its potential (SpringHistory::Potential) is conservative and follows Chung & Ooi (2011).
  static constexpr SpringHistory default_history = SpringHistory::Potential;
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
  /// dk_t/d(delta) from k_t: k_t ~ sqrt(delta), so dk_t/d(delta) = k_t / (2 delta) [N/m^2].
  template <class D>
  static typename D::Real dkt_ddelta(const ContactGeometry<D>& g, const typename D::Real& kt) {
    return kt / (2.0 * g.overlap);
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
  /// k_t does not depend on the overlap.
  template <class D>
  static typename D::Real dkt_ddelta(const ContactGeometry<D>&, const typename D::Real&) {
    return typename D::Real(0.0);
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
  /// The displacement history with the normal coupling of its potential.
  static constexpr bool potential = History == SpringHistory::Potential;
  /// ContactModel adds normal_coupling to F_n only for this form (the others compile nothing).
  static constexpr bool couples_normal = potential;
  static constexpr bool needs_twist = Rot == HistoryRotation::ProjectKeepLengthTwist;
  /// The force form and the potential form with total truncation are written over D::Real
  /// (core/lanes.hpp); the other variants are scalar only.
  static constexpr bool lanes = (force_history || potential) && Trunc == Truncation::Total;

  /// Checkpoints carry this name. A token changes whenever the update it names changes, so
  /// that older checkpoints of a changed law are refused: the force form adds
  /// ",IncrementalForce", the potential form ",Potential" (the displacement form adds nothing, so LIGGGHTS 3.8 checkpoints,
  /// whose law is unchanged, still load), and Total truncation with the implicit relaxation is
  /// ",TotalImplicit".
  static std::string signature() {
    return "SpringTangential<" + Stiffness::signature() + (force_history ? ",IncrementalForce" : "") +
           (potential ? ",Potential" : "") +
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

  /// k_t and gamma_t of this step, computed once and handed to normal_coupling and eval
  /// (ContactModel does so for couples_normal laws; the stiffness does not depend on F_n).
  template <class D>
  struct Stiff {
    typename D::Real kt;       ///< [N/m]
    typename D::Real gamma_t;  ///< [N s/m]
  };
  template <class D>
  static Stiff<D> stiffness(const Params& p, const ContactGeometry<D>& g, const NormalResultOf<D>& nr) {
    Stiff<D> k;
    k.gamma_t = 0.0;
    k.kt = Stiffness::eval(p.stiffness, g, nr, k.gamma_t);
    return k;
  }

  template <class D>
  static typename D::Vec eval(const Params& p, const ContactGeometry<D>& g, const NormalResultOf<D>& nr,
                              State<D>& s) {
    return eval(p, g, nr, s, stiffness(p, g, nr));
  }
  /// The same with k_t and gamma_t from stiffness(p, g, nr).
  template <class D>
  static typename D::Vec eval(const Params& p, const ContactGeometry<D>& g, const NormalResultOf<D>& nr,
                              State<D>& s, const Stiff<D>& k) {
    using std::abs;
    using std::sqrt;
    using Vec = typename D::Vec;
    using R = typename D::Real;
    const R gamma_t = k.gamma_t;
    const R kt = k.kt;
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
        const R f2 = ft.squaredNorm();
        const auto sliding = f2 > limit * limit;
        where_assign(sliding, ft, [&]() -> Vec { return ft * (limit / sqrt(f2)); });
        where_assign(sliding, s.xi, [&]() -> Vec {
          // kt > 0 in contact (Mindlin: delta > 0); a zero linear stiffness keeps no spring.
          const auto stiff = kt > 0.0;
          const R c = select(gamma_t > 0.0 && stiff, gamma_t / (kt * g.dt + gamma_t), R(0.0));
          const Vec xi_lim = -ft * select(stiff, 1.0 / kt, R(0.0));
          return xi_lim + c * (xi_old - xi_lim);
        });
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
  /// Normal force of the potential form, k_t'(delta) |xi|^2 / 2 [N] (repulsive > 0); zero for
  /// the other forms. ContactModel::evaluate adds it to F_n before the tangential and rolling
  /// laws, so that their Coulomb limits use the whole normal force; xi is therefore this step's
  /// history as the stick update gives it, xi + v_t dt (the carry R keeps the length and turns
  /// xi within the tangent plane, so |R(xi) + v_t dt| = |xi + v_t dt| to first order in the
  /// step's rotation), and no longer than the Coulomb limit allows, mu |F_n| / k_t with F_n
  /// before the term. While the contact sticks this is the xi of the force (the pair then
  /// conserves energy to the integration error: tests/contact/test_oblique_impact.cpp); while
  /// it slides the two differ by the term's own share of F_n, at most mu^2 E*/(24 G*).
  /// k: this step's stiffness(p, g, nr), which eval then takes too (one evaluation of k_t).
  template <class D>
  static typename D::Real normal_coupling(const Params& p, const ContactGeometry<D>& g,
                                          const NormalResultOf<D>& nr, const State<D>& s, const Stiff<D>& k) {
    using R = typename D::Real;
    if constexpr (potential) {
      using std::abs;
      const R kt = k.kt;
      const R x2 = (s.xi + g.vt * g.dt).squaredNorm();
      const R cap = p.mu_s * abs(nr.fn) / kt;
      return 0.5 * Stiffness::dkt_ddelta(g, kt) * select(x2 < cap * cap, x2, cap * cap);
    } else {
      return R(0.0);
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

/// Hertz-Mindlin tangential spring: displacement history with the normal coupling of its
/// potential (conservative while sticking), corrected truncation (001 section 2.2) with implicit
/// relaxation, history turned with the contact.
using MindlinTangential = SpringTangential<MindlinStiffness>;
/// The same with the force history and its unloading rescale (Thornton et al. 2013; LAMMPS
/// mindlin_rescale/force): passive too, but it releases the force too early in the micro-slip
/// regime (Chung & Ooi Test 4 below ~10 deg; docs/physics.md).
using MindlinTangentialIncremental = SpringTangential<MindlinStiffness, Truncation::Total,
                                                      HistoryRotation::ProjectKeepLengthTwist,
                                                      SpringHistory::IncrementalForce>;
/// Hertz-Mindlin tangential spring as in LIGGGHTS 3.8: displacement history F_s = -k_t(delta) xi,
/// limit on the spring force only, no twist rotation.
using MindlinTangentialLegacy = SpringTangential<MindlinStiffness, Truncation::SpringOnly,
                                                 HistoryRotation::ProjectKeepLength,
                                                 SpringHistory::TotalDisplacement>;
/// Linear tangential spring-dashpot with Coulomb limit (displacement history: k_t is constant).
using LinearTangential = SpringTangential<LinearStiffness>;

}  // namespace granule::contact
