#pragma once
// Prescribed kinematics: factories for the functions of time that Body::velocity,
// Body::angular_velocity and Simulation::prescribe_group_velocity take, so that a piston, an
// intruder, a turntable or a shaker is one line instead of a hand-written lambda.
//
//   body.velocity = kinematics::piecewise_linear({0.0, 1e-3, 0.1}, {Vec(0, 0, 0), Vec(0, 0, -u), Vec(0, 0, -u)});
//   body.angular_velocity = kinematics::spin(Vec(0, 0, 1), 2.0);
//   sim.prescribe_group_velocity(g, kinematics::sinusoidal_displacement(Vec(0, 0, A), f, 0.0, t0, 1.0));
//
// The engine drifts bodies and prescribed particles with the midpoint velocity of each step,
// x(t + dt) = x(t) + dt V(t + dt/2). Over a step lying inside one linear piece this is the exact
// integral, so constant and piecewise-linear velocities give the exact displacement when every
// knot (and every start time) falls on a step boundary. For a sinusoid of angular frequency w the
// midpoint rule overestimates each step's displacement by the same factor
// (w dt / 2) / sin(w dt / 2) = 1 + (w dt)^2 / 24 + O((w dt)^4), so the displacement stays in phase
// and its amplitude is A (1 + (w dt)^2 / 24): second order in dt.
//
// Value types: V is a position-like vector (Eigen) or a double (2D angular velocity).
#include <algorithm>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "granule/core/error.hpp"

namespace granule::kinematics {

namespace detail {

// Eigen expressions (e.g. -u * up) are stored as their plain vector type.
template <class V>
struct plain {
  using type = V;
};
template <class V>
  requires requires { typename V::PlainObject; }
struct plain<V> {
  using type = typename V::PlainObject;
};
template <class V>
using plain_t = typename plain<std::decay_t<V>>::type;

template <class V>
V zero() {
  if constexpr (std::is_arithmetic_v<V>) {
    return V(0);
  } else {
    return V::Zero();
  }
}

template <class V>
void require_finite_value(const V& v, const std::string& where, const std::string& name) {
  if constexpr (std::is_arithmetic_v<V>) {
    granule::require_finite(static_cast<double>(v), where, name);
  } else {
    granule::require(v.allFinite(), where, name + " (max |component|)", v.cwiseAbs().maxCoeff(),
                     "finite numbers");
  }
}

}  // namespace detail

/// V(t) = value for all t.
template <class V>
auto constant(const V& value) -> std::function<detail::plain_t<V>(double)> {
  using P = detail::plain_t<V>;
  const P v = value;
  detail::require_finite_value(v, "kinematics::constant", "value");
  return [v](double) { return v; };
}

/// V(t) = 0 for t < t0, f(t) for t >= t0 (f is not shifted: it sees the absolute time). Put t0
/// on a step boundary: a step straddling t0 moves for the whole step or not at all, depending on
/// which side of t0 its midpoint falls.
template <class F>
auto starting_at(double t0, F f) {
  using P = detail::plain_t<std::invoke_result_t<F&, double>>;
  std::function<P(double)> g(std::move(f));
  granule::require_finite(t0, "kinematics::starting_at", "t0");
  granule::require(static_cast<bool>(g), "kinematics::starting_at", "f", 0.0, "a callable of time");
  return std::function<P(double)>([t0, g](double t) { return t < t0 ? detail::zero<P>() : P(g(t)); });
}

/// Velocity through the points (t_k, V_k), linear in between, V_0 before t_0 and V_{n-1} after
/// t_{n-1}. Needs n >= 1 points, strictly increasing finite times and finite values. On a knot
/// it returns V_k exactly (each piece is [t_k, t_{k+1})).
template <class V>
auto piecewise_linear(std::vector<double> times, std::vector<V> values) -> std::function<V(double)> {
  const std::string where = "kinematics::piecewise_linear";
  const std::size_t n = times.size();
  granule::require(n >= 1, where, "times.size()", static_cast<double>(n), "[1, inf)");
  granule::require(values.size() == n, where, "values.size()", static_cast<double>(values.size()),
                   "{" + std::to_string(n) + "} (= times.size())");
  for (std::size_t k = 0; k < n; ++k) {
    // Appended rather than "times[" + to_string(k): GCC 12 warns (-Wrestrict, a false positive)
    // on operator+(const char*, string&&) once this is inlined (-O3).
    std::string tk = "times[";
    tk += std::to_string(k);
    tk += ']';
    granule::require_finite(times[k], where, tk);
    if (k > 0) {
      std::string range = "(";
      range += granule::detail::to_text(times[k - 1]);
      range += ", inf) (strictly increasing times)";
      granule::require(times[k] > times[k - 1], where, tk, times[k], range);
    }
    detail::require_finite_value(values[k], where, "values[" + std::to_string(k) + "]");
  }
  return [times = std::move(times), values = std::move(values)](double t) -> V {
    if (!(t > times.front())) return values.front();
    if (t >= times.back()) return values.back();
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
    const double s = (t - times[k]) / (times[k + 1] - times[k]);
    return V(values[k] + s * (values[k + 1] - values[k]));
  };
}

/// Braced lists of values: piecewise_linear({0.0, 1.0}, {Vec(0, 0), Vec(1, 0)}).
template <class V>
auto piecewise_linear(std::vector<double> times, std::initializer_list<V> values) {
  return piecewise_linear(std::move(times), std::vector<detail::plain_t<V>>(values.begin(), values.end()));
}

/// The velocity of the displacement u(t) = A sin(w (t - t0) + phase) - A sin(phase), w = 2 pi f:
/// V(t) = w A cos(w (t - t0) + phase) for t0 <= t < t0 + periods / f, and 0 outside, so u starts
/// at 0 and, after a whole number of periods, is back at 0 (a tap). The velocity jumps by
/// w A cos(phase) at t0, like the virtual bender of paper 001 (section 2.6). periods may be inf
/// (a shaker that never stops).
template <class V>
auto sinusoidal_displacement(const V& amplitude, double frequency, double phase = 0.0, double t0 = 0.0,
                             double periods = std::numeric_limits<double>::infinity())
    -> std::function<detail::plain_t<V>(double)> {
  using P = detail::plain_t<V>;
  const std::string where = "kinematics::sinusoidal_displacement";
  const P a = amplitude;
  detail::require_finite_value(a, where, "amplitude");
  granule::require_positive(frequency, where, "frequency");
  granule::require_finite(phase, where, "phase");
  granule::require_finite(t0, where, "t0");
  granule::require(periods > 0.0, where, "periods", periods, "(0, inf]");
  const double w = 2.0 * std::numbers::pi * frequency;
  const double t_end = t0 + periods / frequency;
  return [a, w, phase, t0, t_end](double t) -> P {
    if (t < t0 || t >= t_end) return detail::zero<P>();
    return P((w * std::cos(w * (t - t0) + phase)) * a);
  };
}

/// Constant rotation at omega [rad/s] about `axis` (3D; any non-zero length): Omega = axis/|axis| omega.
inline std::function<Eigen::Vector3d(double)> spin(const Eigen::Vector3d& axis, double omega) {
  const double len = axis.norm();
  granule::require(len > 0.0 && std::isfinite(len), "kinematics::spin", "|axis|", len, "(0, inf)");
  granule::require_finite(omega, "kinematics::spin", "omega");
  const Eigen::Vector3d w = axis / len * omega;
  return [w](double) { return w; };
}

/// Rotation about `axis` at a rate omega(t) (e.g. a piecewise_linear spin-up).
inline std::function<Eigen::Vector3d(double)> spin(const Eigen::Vector3d& axis, std::function<double(double)> omega) {
  const double len = axis.norm();
  granule::require(len > 0.0 && std::isfinite(len), "kinematics::spin", "|axis|", len, "(0, inf)");
  granule::require(static_cast<bool>(omega), "kinematics::spin", "omega", 0.0, "a callable of time");
  const Eigen::Vector3d u = axis / len;
  return [u, omega = std::move(omega)](double t) { return Eigen::Vector3d(u * omega(t)); };
}

/// 2D: rotation about z at omega [rad/s] (the angular velocity is a scalar).
inline std::function<double(double)> spin(double omega) {
  granule::require_finite(omega, "kinematics::spin", "omega");
  return [omega](double) { return omega; };
}

}  // namespace granule::kinematics
