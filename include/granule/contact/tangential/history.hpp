#pragma once
// History hooks shared by the sub-models that carry a vector per contact.
//
// project_history: as the contact normal turns, a tangential spring stored in the world frame
// must stay in the current tangent plane. We remove its normal component and, when
// `keep_length` is set, restore its previous length (Luding 2008, "Cohesive, frictional powders:
// contact models for tension", section 2.2.3: the spring is rotated, not shortened). Without it
// the spring slowly loses length in rolling/rotating contacts (LAMMPS hooke/history behaviour).
//
// rotate_history: projection only follows the tilt of the normal. A rotation of the pair
// about the normal itself (both particles spinning together about the line of centres) moves
// nothing relative to the contact -- omega x n = 0, v_t = 0 -- yet the tangent plane turns with
// the pair, so the history must turn with it or the force stays fixed in space (not frame
// indifferent; LAMMPS and LIGGGHTS share this gap). The plane turns by the mean twist angle of
// the step, theta = (omega_i + omega_j)/2 . n dt (ContactGeometry::twist; for a wall the body's
// angular velocity replaces omega_j). rotate_history projects, then adds tan(theta) n x x to the
// projected x -- which turns its direction by exactly atan(tan(theta)) = theta -- and restores the
// previous length, as project_history with keep_length does: an exactly length-preserving
// rotation, with no trig call and no division beyond the one the length restoration already
// had. tan(theta) is its Taylor polynomial to theta^7,
//   tan(theta) ~ theta (1 + theta^2/3 + 2 theta^4/15 + 17 theta^6/315),
// so the angle is off by 62/2835 theta^9 ~ 0.02 theta^9 per step (2e-11 rad at 0.1 rad per step;
// typical steps turn by < 1e-3 rad). theta = 0 (2D, or the set-up evaluation with dt = 0) leaves
// the direction unchanged.
//
// reverse_history: the history of pair (i, j) seen from j is the negative of that seen from i;
// used when a rebuild stores the pair in the other particle's row. (The twist rotation is
// consistent with it: n, theta and x all change sign, and so does the rotated x.)
#include <cmath>

#include "granule/contact/geometry.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/lanes.hpp"

namespace granule::contact {

template <class Vec>
inline void project_history(Vec& s, const Vec& n, bool keep_length) {
  using std::sqrt;
  const auto before2 = s.squaredNorm();
  s -= s.dot(n) * n;
  if (keep_length) {
    const auto after2 = s.squaredNorm();
    where_assign(after2 > 0.0, s, [&]() -> Vec { return s * sqrt(before2 / after2); });
  }
}

/// 2D: the signed length that x keeps along the tangent t = z x n = (-n_y, n_x) when it is
/// projected onto that line with its length restored: sign(x . t) |x| (x . t = n x x). One
/// square root, no division. A vector along n (n x x = 0) has no tangential part: 0. A NaN stays
/// NaN (the engine's checks must see it).
template <class D>
inline typename D::Real tangent_length_2d(const typename D::Vec& x, const typename D::Vec& n) {
  using std::sqrt;
  using R = typename D::Real;
  const R xt = D::cross(n, x);
  const R len = sqrt(x.squaredNorm());
  return select(xt < 0.0, R(-len), select(xt == 0.0, R(0.0), len));
}

/// Projects x onto the tangent plane of g.n, turns it about g.n by the twist angle g.twist of the
/// step (3D) and restores its previous length.
/// Written for a short dependency chain: n x P x = n x x, and since n x x is orthogonal to P x with
/// the same length, |P x + t n x x|^2 = (|x|^2 - (x.n)^2)(1 + t^2) -- the length factor is found
/// from scalars while the vector is being formed.
template <class D>
inline void rotate_history(typename D::Vec& x, const ContactGeometry<D>& g) {
  using std::sqrt;
  using R = typename D::Real;
  if constexpr (D::dim == 3) {
    const R before2 = x.squaredNorm();
    const R xn = x.dot(g.n);
    const R t2 = g.twist * g.twist;
    const R tan_twist = g.twist * (1.0 + t2 * (1.0 / 3.0 + t2 * (2.0 / 15.0 + t2 * (17.0 / 315.0))));
    const R after2 = (before2 - xn * xn) * (1.0 + tan_twist * tan_twist);
    R scale = 1.0;
    where_assign(after2 > 0.0, scale, [&]() -> R { return sqrt(before2 / after2); });
    x = scale * (x - xn * g.n + tan_twist * g.n.cross(x));
  } else {
    // 2D: the projection of x onto the tangent line with its length restored is
    // tangent_length_2d t. (Until 2026-12-07 this projected, then scaled by
    // sqrt(|x|^2 / |P x|^2), as 3D does with theta = 0: the same vector to rounding, but the
    // longest dependency chain of the packed 2D law.)
    x = D::cross(tangent_length_2d<D>(x, g.n), g.n);
  }
}

template <class Vec>
inline void reverse_history(Vec& s) {
  s = -s;
}
inline void reverse_history(double& s) { s = -s; }

}  // namespace granule::contact
