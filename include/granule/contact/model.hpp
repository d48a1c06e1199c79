#pragma once
// ContactModel composes one sub-model per slot and fixes the order in which they run:
//
//   normal -> cohesion -> tangential -> rolling
//
// The tangential and rolling laws see the normal force including cohesion (their limits use
// |F_n| as in paper 001 eq. A12 and A14) and, for a tangential law whose potential depends on
// the overlap (couples_normal), that law's normal term. Each slot is a policy with
//   Params  make(const PairMaterial&)          precomputed once per material pair
//   State<D>                                    per-contact history (empty struct if none)
//   eval(Params, ContactGeometry<D>, ...)       a few lines of maths, no branching on options
// A model whose slots are all stateless has an empty State and the neighbour list then stores no
// history at all. See docs/adding_a_contact_law.md for the slot contracts.
#include <string>
#include <type_traits>

#include "granule/contact/cohesion/dmt.hpp"
#include "granule/contact/cohesion/jkr.hpp"
#include "granule/contact/cohesion/none.hpp"
#include "granule/contact/cohesion/sjkr.hpp"
#include "granule/contact/geometry.hpp"
#include "granule/contact/normal/hertz.hpp"
#include "granule/contact/normal/linear.hpp"
#include "granule/contact/normal/non_tensile.hpp"
#include "granule/contact/rolling/constant_torque.hpp"
#include "granule/contact/rolling/epsd.hpp"
#include "granule/contact/rolling/none.hpp"
#include "granule/contact/rolling/sds.hpp"
#include "granule/contact/tangential/incremental_coulomb.hpp"
#include "granule/contact/tangential/none.hpp"
#include "granule/contact/tangential/spring.hpp"

namespace granule::contact {

namespace detail {
/// A tangential or rolling law that turns its history about the normal declares
/// `static constexpr bool needs_twist = true`; the engine then fills ContactGeometry::twist.
template <class Law>
constexpr bool needs_twist() {
  if constexpr (requires { Law::needs_twist; }) {
    return Law::needs_twist;
  } else {
    return false;
  }
}
/// A slot law whose eval is written over D::Real declares `static constexpr bool lanes = true`.
/// A tangential law whose elastic force derives from a potential that also depends on the
/// overlap declares `static constexpr bool couples_normal = true`, `stiffness(Params, g, nr)`
/// (what the law computes from the geometry, e.g. k_t and gamma_t: evaluated once per contact
/// and step), `normal_coupling(Params, g, nr, State, stiffness)`, the normal force of that
/// potential, and `eval(Params, g, nr, State, stiffness)`.
template <class Law>
constexpr bool couples_normal() {
  if constexpr (requires { Law::couples_normal; }) {
    return Law::couples_normal;
  } else {
    return false;
  }
}
/// A cohesion law whose contacts last to a negative overlap once formed (JKR) declares
/// `static constexpr bool tensile = true`, `separation(Params, r_eff)`, the pull-off distance,
/// `elastic_overlap(Params, overlap, r_eff)`, the overlap every slot sees, and
/// `elastic_overlap_slope(Params, elastic_overlap, r_eff)`, its derivative in the real overlap
/// (the chain-rule factor of a couples_normal tangential law's normal term).
template <class Law>
constexpr bool tensile() {
  if constexpr (requires { Law::tensile; }) {
    return Law::tensile;
  } else {
    return false;
  }
}
/// History of a tensile model: the contact has formed (touched), so it lasts to -delta_c.
struct Formed {
  bool formed = false;
};
/// (Not NoState: two members of one empty type would take a byte.)
struct NotTensile {};
/// A slot law that cannot work with some pair properties declares
/// `static void validate(const PairMaterial&, const std::string& where)` (throws InvalidParameter).
template <class Law>
void validate(const PairMaterial& p, const std::string& where) {
  if constexpr (requires { Law::validate(p, where); }) Law::validate(p, where);
}
template <class Law>
constexpr bool lanes() {
  if constexpr (requires { Law::lanes; }) {
    return Law::lanes;
  } else {
    return false;
  }
}
}  // namespace detail

template <class Normal, class Tangential = NoTangential, class Rolling = NoRolling,
          class Cohesion = NoCohesion>
struct ContactModel {
  using NormalLaw = Normal;
  using TangentialLaw = Tangential;
  using RollingLaw = Rolling;
  using CohesionLaw = Cohesion;

  static_assert(!(Normal::hertzian && std::is_same_v<Tangential, LinearTangential>),
                "ContactModel<HertzNormal, LinearTangential>: the linear tangential spring takes "
                "k_t from the linear normal stiffness; use MindlinTangential with HertzNormal");

  struct Params {
    typename Normal::Params normal;
    typename Tangential::Params tangential;
    typename Rolling::Params rolling;
    typename Cohesion::Params cohesion;
  };

  /// Contacts last to a negative overlap, down to -pull_off_separation, once formed (JKR).
  /// False for every other law: the engine's tensile code is then compiled out.
  static constexpr bool tensile = detail::tensile<Cohesion>();
  static_assert(!tensile || Normal::hertzian, "ContactModel: a tensile cohesion law (JKR) replaces the Hertz force");

  template <class D>
  struct State {
    [[no_unique_address]] typename Tangential::template State<D> tangential;
    [[no_unique_address]] typename Rolling::template State<D> rolling;
    [[no_unique_address]] std::conditional_t<tensile, detail::Formed, detail::NotTensile> contact;
  };

  /// True when contacts carry history (the neighbour list then stores one State per entry).
  template <class D>
  static constexpr bool has_state = !std::is_empty_v<State<D>>;
  /// True when the tangential law reports its spring-dashpot (coupling rotation and
  /// translation in the rolling stability limit).
  template <class D>
  static constexpr bool tangential_dashpot =
      requires(const typename Tangential::Params& t, const ContactGeometry<D>& g, const NormalResult& nr) {
        Tangential::spring_dashpot(t, g, nr);
      };
  /// True when the rolling law has a rotational spring-dashpot whose stability limits dt (EPSD).
  template <class D>
  static constexpr bool rolling_dashpot =
      requires(const typename Rolling::Params& r, const ContactGeometry<D>& g, const NormalResult& nr) {
        Rolling::spring_dashpot(r, g, nr);
      };
  static constexpr bool needs_rolling_inertia = Rolling::needs_inertia;
  /// True when a law turns its history about n (3D: ContactGeometry::twist must be filled).
  static constexpr bool needs_twist = detail::needs_twist<Tangential>() || detail::needs_twist<Rolling>();
  /// True when every slot's eval is written over D::Real, so that the engine may evaluate W
  /// contacts at once (Dim3Lanes, core/lanes.hpp).
  static constexpr bool lanes = detail::lanes<Normal>() && detail::lanes<Tangential>() &&
                                detail::lanes<Rolling>() && detail::lanes<Cohesion>();

  /// Names the composition; checkpoints refuse to load into a different model.
  static std::string signature() {
    return "ContactModel<" + Normal::signature() + "," + Tangential::signature() + "," +
           Rolling::signature() + "," + Cohesion::signature() + ">";
  }

  /// thickness: out-of-plane thickness of 2D disks [m] (used by 2D cohesion).
  static Params make(const PairMaterial& p, double thickness = 1.0) {
    return {Normal::make(p), Tangential::make(p), Rolling::make(p), Cohesion::make(p, thickness)};
  }

  /// Separation at which a formed contact breaks, |delta_c| [m] (0 unless tensile).
  static double pull_off_separation(const Params& p, double r_eff) {
    if constexpr (tensile) {
      return Cohesion::separation(p.cohesion, r_eff);
    } else {
      return 0.0;
    }
  }
  /// Refuses pair properties a slot cannot work with; the engine calls it for every pair of
  /// materials that can touch when the run starts (make must not throw: it also runs for pairs
  /// of wall materials, which never touch).
  static void validate(const PairMaterial& p, const std::string& where) {
    detail::validate<Normal>(p, where);
    detail::validate<Tangential>(p, where);
    detail::validate<Rolling>(p, where);
    detail::validate<Cohesion>(p, where);
  }

  template <class D>
  static ContactForce<D> evaluate(const Params& p, const ContactGeometry<D>& g, State<D>& s) {
    if constexpr (tensile) {
      // Every slot sees the Hertzian overlap of the contact radius (cohesion/jkr.hpp), > 0 also
      // while the formed contact is stretched to a negative overlap.
      s.contact.formed = true;
      ContactGeometry<D> elastic = g;
      elastic.overlap = Cohesion::elastic_overlap(p.cohesion, g.overlap, g.r_eff);
      return compose(p, elastic, s);
    } else {
      return compose(p, g, s);
    }
  }

 private:
  template <class D>
  static ContactForce<D> compose(const Params& p, const ContactGeometry<D>& g, State<D>& s) {
    NormalResultOf<D> nr = Normal::eval(p.normal, g);
    nr.fn -= Cohesion::eval(p.cohesion, g);
    typename D::Vec ft;
    if constexpr (detail::couples_normal<Tangential>()) {
      // The normal force of the tangential spring's potential, from the history as the last
      // step left it, so that the Coulomb limits below see the whole normal force. The
      // spring's stiffness (Mindlin: k_t and gamma_t) is computed once for both calls.
      const auto k = Tangential::stiffness(p.tangential, g, nr);
      if constexpr (tensile) {
        // g.overlap is delta_H = a(delta)^2 / R* (evaluate): the potential k_t(delta_H) |xi|^2/2
        // pushes with its delta_H-derivative times d delta_H / d delta (cohesion/jkr.hpp).
        nr.fn += Tangential::normal_coupling(p.tangential, g, nr, s.tangential, k) *
                 Cohesion::elastic_overlap_slope(p.cohesion, g.overlap, g.r_eff);
      } else {
        nr.fn += Tangential::normal_coupling(p.tangential, g, nr, s.tangential, k);
      }
      ft = Tangential::eval(p.tangential, g, nr, s.tangential, k);
    } else {
      ft = Tangential::eval(p.tangential, g, nr, s.tangential);
    }
    const typename D::AngVec mr = Rolling::eval(p.rolling, g, nr, s.rolling);
    ContactForce<D> f;
    f.fn = nr.fn;
    f.ft = ft;
    f.force = nr.fn * g.n + ft;
    const typename D::AngVec nxft = D::cross(g.n, ft);
    f.torque_i = -g.arm_i * nxft + mr;
    f.torque_j = -g.arm_j * nxft - mr;
    return f;
  }

 public:
  /// Energy stored in the contact: the potential of the elastic normal force (normal spring and
  /// cohesion, zero for a separated pair, so that its derivative by the overlap is the elastic
  /// F_n) + the tangential and rolling springs [J]. A tensile cohesion law (JKR) replaces the
  /// Hertz force, and its energy is the whole normal potential (cohesion/jkr.hpp: it jumps at
  /// touch and at the break, where the engine's force jumps too).
  template <class D>
  static double stored_energy(const Params& p, const ContactGeometry<D>& gt, const State<D>& s) {
    ContactGeometry<D> g = gt;
    if constexpr (tensile) g.overlap = Cohesion::elastic_overlap(p.cohesion, gt.overlap, gt.r_eff);
    NormalResult nr = Normal::eval(p.normal, g);
    nr.fn -= Cohesion::eval(p.cohesion, g);
    double normal = Cohesion::energy(p.cohesion, g);
    if constexpr (!tensile) normal += Normal::elastic_energy(p.normal, g.overlap, g.r_eff);
    return normal + Tangential::energy(p.tangential, g, nr, s.tangential) +
           Rolling::energy(p.rolling, g, nr, s.rolling);
  }

  /// History of (i, j) turned into the history of (j, i).
  template <class D>
  static void reverse(State<D>& s) {
    Tangential::reverse(s.tangential);
    Rolling::reverse(s.rolling);
  }
};

// The blessed combinations used by the examples and benchmarks.
using LinearFrictionless = ContactModel<LinearNormal>;
using LinearSpringDashpot = ContactModel<LinearNormal, LinearTangential>;
using HertzFrictionless = ContactModel<HertzNormal>;
using HertzMindlin = ContactModel<HertzNormal, MindlinTangential>;
using HertzMindlinLegacy = ContactModel<HertzNormal, MindlinTangentialLegacy>;
/// Hertz-Mindlin with the force history and unloading rescale (the default until 2026-12-06).
using HertzMindlinIncremental = ContactModel<HertzNormal, MindlinTangentialIncremental>;
/// Hertz-Mindlin whose normal force never pulls (LAMMPS limit_damping; normal/non_tensile.hpp).
using HertzMindlinNonTensile = ContactModel<NonTensile<HertzNormal>, MindlinTangential>;
using HertzMindlinEpsd = ContactModel<HertzNormal, MindlinTangential, EpsdRolling>;
/// Hertz-Mindlin with the constant-stiffness SDS rolling law of LAMMPS (rolling/sds.hpp).
using HertzMindlinSds = ContactModel<HertzNormal, MindlinTangential, SdsRolling>;
using HertzMindlinEpsdSjkr = ContactModel<HertzNormal, MindlinTangential, EpsdRolling, SjkrCohesion>;
/// Hertz-Mindlin with JKR adhesion and its hysteresis (cohesion/jkr.hpp; scalar pair loop).
using HertzMindlinJkr = ContactModel<HertzNormal, MindlinTangential, NoRolling, JkrCohesion>;
/// Hertz-Mindlin with DMT adhesion, a constant pull 2 pi w R* while overlapping (cohesion/dmt.hpp).
using HertzMindlinDmt = ContactModel<HertzNormal, MindlinTangential, NoRolling, DmtCohesion>;
/// Paper 002: linear normal law, incremental regularised Coulomb friction, rolling friction.
using LinearCoulombRolling = ContactModel<LinearNormal, IncrementalCoulombTangential, EpsdRolling>;

}  // namespace granule::contact
