#pragma once
// Shared helpers of the contact-law physics tests (tests/contact/test_*.cpp): unit vectors,
// masses, a reference integrator of the one-contact Hertz ODE, crossing-time interpolation and a
// hand-built ContactGeometry for direct ContactModel<...>::evaluate calls.
//
// The reference ODE (Hertz 1882 with the damping of Tsuji et al. 1992 in the form of
// LIGGGHTS / paper 001 eq. A1-A5):
//   m* x'' = -(4/3 E* sqrt(R*) x^3/2 + gamma(x) x'),
//   gamma(x) = 2 sqrt(5/6) |beta| sqrt(2 E* sqrt(R* x) m*),   x = overlap [m].
// It is integrated by classical RK4 with a fixed, tiny step; the end of contact (x = 0) is found
// by cubic Hermite interpolation inside the last step.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "granule/boundaries/geometry/plane.hpp"
#include "granule/contact/geometry.hpp"
#include "granule/core/dimension.hpp"
#include "granule/materials/material.hpp"
#include "granule/simulation.hpp"

namespace granule::contact_test {

/// Unit vector along axis k.
template <class D>
typename D::Vec unit(int k) {
  return D::Vec::Unit(k);
}

/// Unit vector along the last axis ("up": y for disks, z for spheres).
template <class D>
typename D::Vec up() {
  return D::Vec::Unit(D::dim - 1);
}

/// Mass of a particle of radius r [m], density rho [kg/m^3]; 2D disks of thickness t [m].
template <class D>
double mass_of(double rho, double r, double thickness) {
  return rho * D::volume(r, thickness);
}

/// Moment of inertia k m r^2 (sphere 2/5, disk 1/2) [kg m^2].
template <class D>
double inertia_of(double m, double r) {
  return D::inertia_factor * m * r * r;
}

/// Component of an angular vector about the axis perpendicular to the x-"up" plane: in 2D the
/// scalar itself; in 3D the y component (rolling in +x on a floor with normal +z has omega_y > 0).
inline double spin_about_rolling_axis(double w) { return -w; }
inline double spin_about_rolling_axis(const Eigen::Vector3d& w) { return w.y(); }

/// Angular vector that makes a particle of radius r roll without slip at speed v along +x on a
/// floor whose normal is "up" (2D: omega_z = -v/r; 3D: omega_y = v/r).
template <class D>
typename D::AngVec rolling_omega(double v, double r) {
  if constexpr (D::dim == 2) {
    return -v / r;
  } else {
    return Eigen::Vector3d(0.0, v / r, 0.0);
  }
}

/// Linear interpolation of the time where f crosses zero between (t0, f0) and (t1, f1).
inline double zero_crossing(double t0, double f0, double t1, double f1) {
  return t0 + (t1 - t0) * f0 / (f0 - f1);
}

/// Restitution coefficient e -> beta = ln e / sqrt(ln^2 e + pi^2) (paper 001 eq. A5).
inline double beta_of(double e) {
  const double l = std::log(e);
  return l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
}

/// Exact elastic Hertz collision: delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) and
/// t_c = 2 (delta_max / v) int_0^1 (1 - s^(5/2))^(-1/2) ds = c (m*^2/(E*^2 R* v))^(1/5),
/// int_0^1 (1 - s^a)^(-1/2) ds = Gamma(1/a) Gamma(1/2) / (a Gamma(1/a + 1/2)), a = 5/2
/// (Johnson 1985, section 11.4; the constant is 2.8683).
inline double hertz_max_overlap_exact(double m_eff, double E_eff, double r_eff, double v) {
  return std::pow(15.0 * m_eff * v * v / (16.0 * E_eff * std::sqrt(r_eff)), 0.4);
}
inline double hertz_duration_integral() {
  const double a = 2.5;
  return std::tgamma(1.0 / a) * std::sqrt(std::numbers::pi) / (a * std::tgamma(1.0 / a + 0.5));
}
inline double hertz_duration_exact(double m_eff, double E_eff, double r_eff, double v) {
  return 2.0 * hertz_max_overlap_exact(m_eff, E_eff, r_eff, v) / v * hertz_duration_integral();
}

struct HertzOdeResult {
  double restitution = 0.0;  ///< separation speed / impact speed [-]
  double duration = 0.0;     ///< contact time [s]
  double max_overlap = 0.0;  ///< [m]
};

/// RK4 integration of the one-contact damped Hertz ODE above from x = 0, x' = v until x returns
/// to 0. `steps_per_elastic_time` fixes h = t_c(elastic) / steps. `non_tensile`: the force is
/// clipped at zero (contact/normal/non_tensile.hpp); once it reaches zero on the way out the
/// particle flies free, so the speed at x = 0 is the separation speed.
inline HertzOdeResult integrate_hertz_ode(double m_eff, double E_eff, double r_eff, double beta,
                                          double v, int steps_per_elastic_time, bool non_tensile = false) {
  const double kh = 4.0 / 3.0 * E_eff * std::sqrt(r_eff);
  const double cd = 2.0 * std::sqrt(5.0 / 6.0) * std::abs(beta) * std::sqrt(2.0 * E_eff * std::sqrt(r_eff) * m_eff);
  auto acc = [&](double x, double u) {
    if (x <= 0.0) return 0.0;
    const double f = kh * x * std::sqrt(x) + cd * std::sqrt(std::sqrt(x)) * u;
    return -(non_tensile ? std::max(f, 0.0) : f) / m_eff;
  };
  const double h = hertz_duration_exact(m_eff, E_eff, r_eff, v) / steps_per_elastic_time;
  double x = 0.0, u = v, t = 0.0;
  HertzOdeResult r;
  for (long k = 0; k < 100L * steps_per_elastic_time; ++k) {
    const double k1x = u, k1u = acc(x, u);
    const double k2x = u + 0.5 * h * k1u, k2u = acc(x + 0.5 * h * k1x, u + 0.5 * h * k1u);
    const double k3x = u + 0.5 * h * k2u, k3u = acc(x + 0.5 * h * k2x, u + 0.5 * h * k2u);
    const double k4x = u + h * k3u, k4u = acc(x + h * k3x, u + h * k3u);
    const double xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    const double un = u + h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
    r.max_overlap = std::max(r.max_overlap, xn);
    if (k > 0 && xn <= 0.0 && un < 0.0) {
      // Cubic Hermite on [t, t + h] for x; bisection for its root; u is then interpolated.
      auto herm = [&](double s) {
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * x + (s3 - 2 * s2 + s) * h * u + (-2 * s3 + 3 * s2) * xn +
               (s3 - s2) * h * un;
      };
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (herm(mid) > 0.0 ? lo : hi) = mid;
      }
      const double s = 0.5 * (lo + hi);
      r.duration = t + s * h;
      r.restitution = -(u + s * (un - u)) / v;
      return r;
    }
    x = xn;
    u = un;
    t += h;
  }
  return r;
}

/// A particle-particle contact geometry built by hand with the same kinematics as
/// Simulation::pair_geometry: centres x_i, x_j, radii, masses, velocities, angular velocities.
template <class D>
contact::ContactGeometry<D> make_pair_geometry(const typename D::Vec& xi, const typename D::Vec& xj,
                                               double ri, double rj, double mi, double mj,
                                               const typename D::Vec& vi, const typename D::Vec& vj,
                                               const typename D::AngVec& wi,
                                               const typename D::AngVec& wj, double dt) {
  contact::ContactGeometry<D> g;
  const typename D::Vec d = xi - xj;
  g.distance = d.norm();
  g.n = d / g.distance;
  g.overlap = ri + rj - g.distance;
  g.r_i = ri;
  g.r_j = rj;
  g.arm_i = ri - 0.5 * g.overlap;
  g.arm_j = rj - 0.5 * g.overlap;
  g.r_eff = ri * rj / (ri + rj);
  g.m_eff = mi * mj / (mi + mj);
  g.v_rel = vi - vj - (g.arm_i * D::cross(wi, g.n) + g.arm_j * D::cross(wj, g.n));
  g.vn = g.v_rel.dot(g.n);
  g.vt = g.v_rel - g.vn * g.n;
  g.omega_rel = wi - wj;
  g.damp_at_kinematic_velocity();
  const double k1 = D::inertia_factor + 1.0;
  g.i_roll = 1.0 / (1.0 / (k1 * mi * ri * ri) + 1.0 / (k1 * mj * rj * rj));
  g.dt = dt;
  if constexpr (D::dim == 3) g.twist = 0.5 * (wi + wj).dot(g.n) * dt;  // mean twist angle
  return g;
}

/// What a head-on collision run through the engine measured.
struct CollisionMeasure {
  double duration = 0.0;     ///< contact time (overlap > 0) [s]
  double max_overlap = 0.0;  ///< [m]
  double restitution = 0.0;  ///< relative normal separation speed / impact speed [-]
  long steps = 0;            ///< steps taken
};

/// Head-on collision through Simulation<D, Model, VerletList, Integrator>: two equal particles of
/// radius r approaching at relative speed v along x (wall = false), or one particle falling at v
/// onto a plane wall with normal "up" made of the same material (wall = true). No gravity.
/// dt = t_ref / steps, with t_ref a reference contact time supplied by the caller. The contact
/// starts at the exact time gap / v, gap = (3 + phase) v dt, i.e. at `phase` of the 4th step;
/// its end is interpolated linearly on the overlap between two steps. `allow_large_time_step`
/// passes a dt above the engine's limit (to show what such a step does).
template <class D, class Model, class Integrator = integrators::VelocityVerlet>
CollisionMeasure run_head_on(const Material& mat, double r, double v, bool wall, double t_ref,
                             int steps, double thickness = 1.0, double phase = 0.3,
                             bool allow_large_time_step = false) {
  using Vec = typename D::Vec;
  SimulationConfig<D> cfg;
  cfg.allow_large_time_step = allow_large_time_step;
  cfg.domain.lo = Vec::Constant(-20.0 * r);
  cfg.domain.hi = Vec::Constant(20.0 * r);
  cfg.dt = t_ref / steps;
  cfg.thickness = thickness;
  Simulation<D, Model, neighbours::VerletList, Integrator> sim(cfg);
  const auto pm = sim.add_material(mat);
  const double gap = (3.0 + phase) * v * cfg.dt;  // contact starts inside the 4th step
  std::uint64_t a = 0, b = 0;
  Vec ax;
  if (wall) {
    ax = up<D>();
    sim.add_wall(geometry::PlaneShape<D>(Vec::Zero(), ax), sim.add_wall_material(mat));
    a = sim.add_particle(Vec((r + gap) * ax), r, pm, Vec(-v * ax));
  } else {
    ax = unit<D>(0);
    a = sim.add_particle(Vec((r + 0.5 * gap) * ax), r, pm, Vec(-0.5 * v * ax));
    b = sim.add_particle(Vec(-(r + 0.5 * gap) * ax), r, pm, Vec(0.5 * v * ax));
  }
  auto& p = sim.particles();
  auto overlap = [&] {
    const Vec xa = p.x[sim.index_of(a)];
    return wall ? r - xa.dot(ax) : 2.0 * r - (xa - p.x[sim.index_of(b)]).norm();
  };
  auto rel_speed = [&] {
    const Vec va = p.v[sim.index_of(a)];
    return wall ? va.dot(ax) : (va - p.v[sim.index_of(b)]).dot(ax);
  };
  CollisionMeasure m;
  double prev = overlap();
  bool touched = false;
  for (long k = 0; k < 100L * steps; ++k) {
    sim.step();
    const double o = overlap();
    m.max_overlap = std::max(m.max_overlap, o);
    if (o > 0.0) touched = true;
    if (touched && o <= 0.0) {
      const double t_end = zero_crossing(sim.time() - cfg.dt, prev, sim.time(), o);
      m.duration = t_end - gap / v;
      break;
    }
    prev = o;
  }
  sim.run(3);  // free flight: the velocity no longer changes
  m.restitution = rel_speed() / v;
  m.steps = static_cast<long>(sim.step_count());
  return m;
}

}  // namespace granule::contact_test
