#pragma once
// Constant-stiffness spring-dashpot-slider (SDS) rolling resistance, after LAMMPS pair granular
// `rolling sds k_roll gamma_roll mu_roll` (Luding 2008; Wang et al. 2015 for the rolling
// velocity). LAMMPS writes it as a pseudo-force on the rolling displacement
//   v_roll = R* (omega_i - omega_j) x n,  xi_roll += v_roll dt,
//   F_roll = -k_roll xi_roll - gamma_roll v_roll,  |F_roll| <= mu_roll F_n,   M_i = R* n x F_roll,
// with xi_roll truncated at the limit, xi_roll = -(mu_roll F_n F_roll/|F_roll| + gamma_roll v_roll)
// / k_roll, as the tangential spring. Since n x (w x n) is the tangential part w_t of w, the
// same law on the rolling angle theta (theta += w_t dt, in the tangent plane) reads
//   M = -K theta - C w_t,  |M| <= M_m = mu_r R* |F_n|,   K = k_roll R*^2,  C = gamma_roll R*^2,
// and on overflow M = M_m M/|M| and theta = -(M + C w_t)/K. Unlike EPSD (epsd.hpp) the stiffness
// is a constant k_roll [N/m] (not from k_n), the dashpot stays on when the contact slides and the
// limit applies to spring + dashpot together, and twisting (w . n) is not resisted.
// Here the dashpot is given as the damping ratio eta_r of the rolling oscillation,
// C = eta_r 2 sqrt(I_r K) with the rolling inertia I_r of Ai et al. (2011) eq. 14 (for a sphere
// on a wall I_r = I + m r^2, the inertia about the contact point); LAMMPS' gamma_roll = C / R*^2.
// The history turns with the pair as EPSD's rolling part does (history.hpp rotate_history).
#include <cmath>

#include <string>

#include "granule/contact/geometry.hpp"
#include "granule/contact/tangential/history.hpp"
#include "granule/core/error.hpp"

namespace granule::contact {

struct SdsRolling {
  static std::string signature() { return "SdsRolling"; }
  struct Params {
    double mu_r = 0.0;    ///< mu_roll [-]
    double k_roll = 0.0;  ///< [N/m]
    double eta_r = 0.0;   ///< damping ratio [-]
  };
  /// Rolling angle theta [rad]: 2D the scalar about z, 3D a vector in the tangent plane.
  template <class D>
  struct State {
    typename D::AngVec theta = D::zero_ang();
  };
  static constexpr bool needs_inertia = true;
  static constexpr bool needs_twist = true;  ///< theta turns with the pair about n
  static constexpr bool lanes = true;        ///< eval is written over D::Real (core/lanes.hpp)
  static Params make(const PairMaterial& p) { return {p.mu_r, p.k_roll, p.rolling_damping}; }
  /// Refuses a pair that can touch with rolling friction and no rolling spring (the slider would
  /// divide by 0); the engine calls it when the run starts (ContactModel::validate).
  static void validate(const PairMaterial& p, const std::string& where) {
    require(!(p.mu_r > 0.0) || (p.k_roll > 0.0 && std::isfinite(p.k_roll)), where, "rolling_stiffness", p.k_roll,
            "(0, inf) N/m when rolling_friction > 0 (k_roll of the SDS rolling law; Material::rolling_stiffness "
            "or set_pair)");
  }

  /// K = k_roll R*^2 [N m/rad].
  template <class R>
  static R stiffness(const Params& p, const R& r_eff) {
    return p.k_roll * r_eff * r_eff;
  }
  /// C = eta_r 2 sqrt(I_r K) [N m s/rad].
  template <class R>
  static R damping(const Params& p, const R& kr, const R& i_roll) {
    using std::sqrt;
    return p.eta_r * 2.0 * sqrt(i_roll * kr);
  }
  /// K and C on the rolling part of omega_i - omega_j (Simulation::rolling_stability_limit).
  template <class D>
  static SpringDashpot spring_dashpot(const Params& p, const ContactGeometry<D>& g, const NormalResult&) {
    const double kr = stiffness(p, static_cast<double>(g.r_eff));
    return {kr, damping(p, kr, static_cast<double>(g.i_roll))};
  }

  template <class D>
  static typename D::AngVec eval(const Params& p, const ContactGeometry<D>& g,
                                 const NormalResultOf<D>& nr, State<D>& s) {
    using std::abs;
    using std::sqrt;
    using R = typename D::Real;
    using AngVec = typename D::AngVec;
    const R kr = stiffness(p, g.r_eff);
    const R cr = damping(p, kr, g.i_roll);
    const R m_max = p.mu_r * g.r_eff * abs(nr.fn);
    AngVec w, w_damp;
    if constexpr (D::dim == 3) {
      rotate_history(s.theta, g);
      w = g.omega_rel - g.omega_rel.dot(g.n) * g.n;
      w_damp = g.omega_rel_damp - g.omega_rel_damp.dot(g.n) * g.n;
    } else {
      w = g.omega_rel;
      w_damp = g.omega_rel_damp;
    }
    s.theta += g.dt * w;
    AngVec m = -kr * s.theta - cr * w_damp;
    R m2;
    if constexpr (D::dim == 3) {
      m2 = m.squaredNorm();
    } else {
      m2 = m * m;
    }
    // Slider: M held at the limit and theta set back to what gives it (kr > 0 wherever m != 0).
    const auto slides = m2 > m_max * m_max;
    where_assign(slides, m, [&]() -> AngVec { return m * (m_max / sqrt(m2)); });
    where_assign(slides, s.theta, [&]() -> AngVec { return (-1.0 / kr) * (m + cr * w_damp); });
    return m;
  }
  /// Energy stored in the rolling spring, K |theta|^2 / 2 [J].
  template <class D>
  static double energy(const Params& p, const ContactGeometry<D>& g, const NormalResult&, const State<D>& s) {
    const double kr = stiffness(p, static_cast<double>(g.r_eff));
    if constexpr (D::dim == 3) {
      return 0.5 * kr * s.theta.squaredNorm();
    } else {
      return 0.5 * kr * s.theta * s.theta;
    }
  }
  /// Seen from j, omega_i - omega_j changes sign and so does theta.
  template <class D>
  static void reverse(State<D>& s) {
    reverse_history(s.theta);
  }
};

}  // namespace granule::contact
