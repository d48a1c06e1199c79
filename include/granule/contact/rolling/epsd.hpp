#pragma once
// Elastic-plastic spring-dashpot (EPSD) rolling resistance: paper 001 eq. A13-A15, after Ai,
// Chen, Rotter & Ooi (2011), model C, and Iwashita & Oda (1998).
//
//   M_k <- M_k - k_r w_r dt,        |M_k| <= M_m = mu_r R* |F_n|   (rescaled: full mobilisation)
//   M_d  = -C_r w_r  while |M_k| < M_m,  0 once fully mobilised    (001 eq. A15)
//   k_r  = c k_n mu_r^2 R*^2,       C_r = eta_r 2 sqrt(I_r k_r)
// with w_r = omega_i - omega_j (the whole relative rotation, so twisting is resisted too, as
// 001 section A states), k_n the normal law's secant stiffness, c = 2.25 (Ai et al. 2011 eq. 13;
// 001 eq. A14 prints 2.55 -- see docs/physics.md), eta_r the rolling damping ratio and I_r the
// rolling inertia 1/I_r = 1/(I_i + m_i r_i^2) + 1/(I_j + m_j r_j^2) (Ai et al. 2011 eq. 14).
//
// History frame: M_k has a rolling part in the tangent plane and (3D) a twisting part along n,
// stored apart -- m_roll and the scalar m_twist, M_k = m_roll + m_twist n. Under a rigid rotation
// of the pair both parts must turn with the contact (frame indifference, Luding 2008 section
// 2.2.3). The twisting part does so by construction (it is measured along the current n); the
// rolling part is carried like the tangential spring (history.hpp rotate_history: projected onto
// the new tangent plane, turned about n by the step's twist angle, length kept) -- exact for a
// rotation about n, first order in the step angle for a tilt of n, as for the tangential spring.
// A single world-frame vector would stay fixed in space (tests/contact/test_history_objectivity.cpp).
#include <cmath>

#include <string>
#include <type_traits>

#include "granule/contact/geometry.hpp"
#include "granule/contact/tangential/history.hpp"

namespace granule::contact {

struct EpsdRolling {
  static std::string signature() { return "EpsdRolling(roll+twist)"; }
  struct Params {
    double mu_r = 0.0;    ///< [-]
    double factor = 2.25; ///< c in k_r = c k_n mu_r^2 R*^2 [-]
    double eta_r = 0.0;   ///< damping ratio [-]
  };
  /// 2D: the rolling spring torque about z (nothing twists about an in-plane normal).
  template <class D>
  struct PlaneState {
    typename D::Real m_roll = 0.0;  ///< spring torque on i [N m]
  };
  /// 3D: spring torque on i, M_k = m_roll + m_twist n.
  template <class D>
  struct SpaceState {
    typename D::Vec m_roll = D::zero();  ///< rolling part, in the tangent plane [N m]
    typename D::Real m_twist = 0.0;      ///< twisting part along n [N m]
  };
  template <class D>
  struct State : std::conditional_t<D::dim == 2, PlaneState<D>, SpaceState<D>> {};
  static constexpr bool needs_inertia = true;
  static constexpr bool needs_twist = true;  ///< the rolling part turns with the pair about n
  static constexpr bool lanes = true;  ///< eval is written over D::Real (core/lanes.hpp)
  static Params make(const PairMaterial& p) {
    return {p.mu_r, p.rolling_stiffness_factor, p.rolling_damping};
  }

  /// k_r = c k_n mu_r^2 R*^2 [N m / rad] from the normal law's k_n [N/m] and R* [m].
  template <class R>
  static R stiffness(const Params& p, const R& kn, const R& r_eff) {
    return p.factor * kn * p.mu_r * p.mu_r * r_eff * r_eff;
  }
  /// C_r = eta_r 2 sqrt(I_r k_r) [N m s / rad].
  template <class R>
  static R damping(const Params& p, const R& kr, const R& i_roll) {
    using std::sqrt;
    return p.eta_r * 2.0 * sqrt(i_roll * kr);
  }
  /// k_r and C_r, which act on the relative rotation omega_i - omega_j.
  template <class D>
  static SpringDashpot spring_dashpot(const Params& p, const ContactGeometry<D>& g, const NormalResult& nr) {
    const double kr = stiffness(p, nr.kn, g.r_eff);
    return {kr, damping(p, kr, g.i_roll)};
  }

  template <class D>
  static typename D::AngVec eval(const Params& p, const ContactGeometry<D>& g,
                                 const NormalResultOf<D>& nr, State<D>& s) {
    using std::abs;
    using std::sqrt;
    using R = typename D::Real;
    using AngVec = typename D::AngVec;
    const R kr = stiffness(p, nr.kn, g.r_eff);
    const R m_max = p.mu_r * g.r_eff * abs(nr.fn);
    // Increment, then the limit: fully mobilised, the spring is held at the limit and there is
    // no damping (001 eq. A15).
    if constexpr (D::dim == 2) {
      // 2D: M is one number, and holding it at the limit is a clamp to [-M_max, M_max] (the 3D
      // scaling by M_max / |M|, the same to rounding, without its division).
      s.m_roll -= kr * g.dt * g.omega_rel;
      const auto mobilised = abs(s.m_roll) >= m_max;
      s.m_roll = select(s.m_roll > m_max, m_max, select(s.m_roll < -m_max, R(-m_max), s.m_roll));
      AngVec m = s.m_roll;
      where_assign(!mobilised, m, [&]() -> AngVec { return m - damping(p, kr, g.i_roll) * g.omega_rel_damp; });
      return m;
    } else {
      rotate_history(s.m_roll, g);
      const R w_n = g.omega_rel.dot(g.n);
      s.m_roll -= (kr * g.dt) * (g.omega_rel - w_n * g.n);
      s.m_twist -= kr * g.dt * w_n;
      const R m2 = s.m_roll.squaredNorm() + s.m_twist * s.m_twist;
      const auto mobilised = m2 >= m_max * m_max;
      R scale = 1.0;
      where_assign(mobilised, scale, [&]() -> R {
        R limited = 0.0;
        where_assign(m2 > 0.0, limited, [&]() -> R { return m_max / sqrt(m2); });
        return limited;
      });
      s.m_roll = s.m_roll * scale;
      s.m_twist = s.m_twist * scale;
      AngVec m = s.m_roll + s.m_twist * g.n;
      where_assign(!mobilised, m, [&]() -> AngVec {
        const R cr = damping(p, kr, g.i_roll);
        return m - cr * g.omega_rel_damp;
      });
      return m;
    }
  }
  /// Energy stored in the rolling spring, |M_k|^2 / (2 k_r) [J].
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>& g, const NormalResult& nr,
                       const State<D>& s) {
    const double kr = stiffness(p, nr.kn, g.r_eff);
    return kr > 0.0 ? 0.5 * squared_norm<D>(s) / kr : 0.0;
  }
  /// |M_k|^2 [N^2 m^2].
  template <class D>
  static double squared_norm(const State<D>& s) {
    if constexpr (D::dim == 3) {
      return s.m_roll.squaredNorm() + s.m_twist * s.m_twist;
    } else {
      return s.m_roll * s.m_roll;
    }
  }
  /// Seen from j the spring torque is -M_k and the normal -n: the rolling part changes sign,
  /// the twisting part (M_k . n) does not.
  template <class D>
  static void reverse(State<D>& s) {
    reverse_history(s.m_roll);
  }
};

}  // namespace granule::contact
