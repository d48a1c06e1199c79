#pragma once
// Incremental regularised Coulomb friction (paper 002 section 2.3, after Cundall & Strack 1979
// and Radjai & Dubois 2011): the tangential force itself is the history,
//
//   F_t <- R(F_t) - k_t v_t dt,        |F_t| <= mu_s |F_n|  (rescaled when exceeded)
//   k_t = r k_n  with k_n the normal law's secant stiffness and r the material's
//   tangential_stiffness_ratio (002 uses r = 1/2).
// R: the force follows the contact frame -- projected onto the new tangent plane with its length
// kept, then turned about n by the mean twist angle of the step (history.hpp).
// There is no tangential dashpot: dissipation comes from sliding and from the normal law.
// 2D evaluates the same law as one number along the tangent (eval).
#include <cmath>

#include <string>

#include "granule/contact/geometry.hpp"
#include "granule/contact/tangential/history.hpp"

namespace granule::contact {

struct IncrementalCoulombTangential {
  /// "<KeepLengthTwist>": the history follows the twist about n too (older checkpoints refused).
  static std::string signature() { return "IncrementalCoulombTangential<KeepLengthTwist>"; }
  static constexpr bool needs_twist = true;
  struct Params {
    double ratio = 0.5;  ///< k_t / k_n [-]
    double mu_s = 0.0;   ///< [-]
  };
  template <class D>
  struct State {
    typename D::Vec ft = D::zero();  ///< tangential force on i [N]
  };
  static Params make(const PairMaterial& p) { return {p.kt_ratio, p.mu_s}; }

  static constexpr bool lanes = true;  ///< eval is written over D::Real (core/lanes.hpp)
  template <class D>
  static typename D::Vec eval(const Params& p, const ContactGeometry<D>& g, const NormalResultOf<D>& nr,
                              State<D>& s) {
    using std::abs;
    using std::sqrt;
    using R = typename D::Real;
    if constexpr (D::dim == 2) {
      // 2D: the tangent line is one-dimensional, spanned by t = z x n = (-n_y, n_x), and so are
      // the history after its rotation (sign(F_t . t) |F_t| t, history.hpp), the increment
      // (v_t = (v_t . t) t) and the limit. The law is then one number f along t: the rotated
      // length, the increment, and a clamp to [-mu |F_n|, mu |F_n|] -- one square root and no
      // division, where the vector form needs two of each on its chain (measured: the packed
      // 2D law's longest chain, bench_scene_pull_out_2d). The same force to rounding.
      R f = tangent_length_2d<D>(s.ft, g.n);
      f -= p.ratio * nr.kn * g.dt * D::cross(g.n, g.vt);
      const R limit = p.mu_s * abs(nr.fn);
      f = select(f > limit, limit, select(f < -limit, R(-limit), f));
      s.ft = D::cross(f, g.n);  // f t
      return s.ft;
    } else {
      using V = typename D::Vec;
      rotate_history<D>(s.ft, g);
      s.ft -= p.ratio * nr.kn * g.dt * g.vt;
      const R limit = p.mu_s * abs(nr.fn);
      const R f2 = s.ft.squaredNorm();
      blend_assign(f2 > limit * limit, s.ft, [&]() -> V { return s.ft * R(limit / sqrt(f2)); });
      return s.ft;
    }
  }
  /// Energy stored in the tangential spring, |F_t|^2 / (2 k_t) [J].
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>&, const NormalResult& nr,
                       const State<D>& s) {
    const double kt = p.ratio * nr.kn;
    return kt > 0.0 ? 0.5 * s.ft.squaredNorm() / kt : 0.0;
  }
  template <class D>
  static void reverse(State<D>& s) {
    reverse_history(s.ft);
  }
};

}  // namespace granule::contact
