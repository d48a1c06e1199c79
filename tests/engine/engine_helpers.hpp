#pragma once
// Shared set-up for the engine tests (tests/engine/test_*.cpp): a reference material, seeded
// random polydisperse packings, touching-pair sets (from recorded contacts and from positions
// with the minimum-image convention) and per-id views of a simulation's particles.
// Everything is deterministic: the random generator is std::mt19937_64 with a fixed seed, and
// the distributions are written out here (the standard library's distributions are not
// specified bit-for-bit across implementations).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <granule/granule.hpp>

namespace granule::test {

/// A soft glass-like material: E = 1e7 Pa keeps contacts soft so time steps stay long.
inline Material soft_material(double restitution = 1.0, double friction = 0.0) {
  Material m;
  m.name = "soft";
  m.youngs_modulus = 1.0e7;  // [Pa]
  m.poisson_ratio = 0.3;     // [-]
  m.density = 2500.0;        // [kg/m^3]
  m.restitution = restitution;
  m.friction = friction;
  m.normal_stiffness = 1.0e4;  // [N/m] (linear laws only)
  return m;
}

/// Uniform double in [a, b) from 53 random bits (portable, unlike uniform_real_distribution).
inline double uniform(std::mt19937_64& rng, double a, double b) {
  const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return a + (b - a) * u;
}

template <class D>
struct SphereSpec {
  typename D::Vec x;
  double r = 0.0;  ///< [m]
};

/// Random sequential addition of `n` spheres with radii log-uniform in [r_min, r_max] (the first
/// two are exactly r_max and r_min, so the size ratio is r_max / r_min). A candidate is rejected
/// if it overlaps an earlier sphere by more than `max_overlap` x the smaller radius (minimum image
/// on periodic axes); on non-periodic axes centres stay `r` inside the domain. `placed` are
/// spheres put first, as given (e.g. pairs engineered to overlap through a periodic face).
template <class D>
std::vector<SphereSpec<D>> random_packing(std::uint64_t seed, const Domain<D>& dom, std::size_t n,
                                          double r_min, double r_max, double max_overlap,
                                          std::vector<SphereSpec<D>> placed = {},
                                          std::size_t max_attempts = 200000) {
  using Vec = typename D::Vec;
  std::mt19937_64 rng(seed);
  std::vector<SphereSpec<D>> out = std::move(placed);
  std::size_t attempts = 0;
  while (out.size() < n && attempts < max_attempts) {
    ++attempts;
    double r = r_min * std::pow(r_max / r_min, uniform(rng, 0.0, 1.0));
    if (attempts == 1) r = r_max;
    if (attempts == 2) r = r_min;
    Vec x;
    for (int k = 0; k < D::dim; ++k) {
      const double margin = dom.periodic[k] ? 0.0 : r;
      x[k] = uniform(rng, dom.lo[k] + margin, dom.hi[k] - margin);
    }
    bool ok = true;
    for (const auto& s : out) {
      const double dist = dom.minimum_image(x, s.x).norm();
      if (r + s.r - dist > max_overlap * std::min(r, s.r)) {
        ok = false;
        break;
      }
    }
    if (ok) out.push_back({x, r});
  }
  return out;
}

using IdPair = std::pair<std::uint64_t, std::uint64_t>;
using PairSet = std::set<IdPair>;

inline IdPair ordered(std::uint64_t a, std::uint64_t b) { return a < b ? IdPair{a, b} : IdPair{b, a}; }

/// Unordered id pairs of the particle-particle contacts recorded in a frame.
template <class D>
PairSet pairs_from_frame(const analysis::Frame<D>& fr) {
  PairSet s;
  for (const auto& c : fr.contacts)
    if (c.j != analysis::ContactRecord<D>::kWall) s.insert(ordered(fr.id[c.i], fr.id[c.j]));
  return s;
}

/// Ground truth: pairs with |minimum-image distance| < r_i + r_j, by testing every pair.
/// `ambiguous` counts pairs within a relative 1e-9 of touching, whose classification could
/// depend on round-off (tests require none, so the comparison is well defined).
template <class D>
PairSet pairs_from_positions(const analysis::Frame<D>& fr, const Domain<D>& dom,
                             std::size_t* ambiguous = nullptr, std::size_t* across_faces = nullptr) {
  PairSet s;
  std::size_t amb = 0, across = 0;
  for (std::size_t i = 0; i < fr.size(); ++i) {
    for (std::size_t j = i + 1; j < fr.size(); ++j) {
      const typename D::Vec d = dom.minimum_image(fr.x[i], fr.x[j]);
      const double dist = d.norm();
      const double rs = fr.radius[i] + fr.radius[j];
      if (std::abs(dist - rs) < 1e-9 * rs) ++amb;
      if (dist < rs) {
        s.insert(ordered(fr.id[i], fr.id[j]));
        if ((fr.x[i] - fr.x[j] - d).norm() > 0.0) ++across;
      }
    }
  }
  if (ambiguous) *ambiguous = amb;
  if (across_faces) *across_faces = across;
  return s;
}

/// Positions indexed by stable id (unwrapped with the periodic image counters when `unwrap`).
template <class Sim>
std::vector<typename Sim::Vec> positions_by_id(const Sim& sim, bool unwrap = true) {
  using Vec = typename Sim::Vec;
  const auto& p = sim.particles();
  std::uint64_t max_id = 0;
  for (std::size_t i = 0; i < p.owned(); ++i) max_id = std::max(max_id, p.id[i]);
  std::vector<Vec> out(p.owned() ? max_id + 1 : 0, Vec::Zero());
  const Vec L = sim.config().domain.length();
  for (std::size_t i = 0; i < p.owned(); ++i) {
    Vec x = p.x[i];
    if (unwrap) x += (p.image[i].template cast<double>().array() * L.array()).matrix();
    out[p.id[i]] = x;
  }
  return out;
}

/// Velocities indexed by stable id.
template <class Sim>
std::vector<typename Sim::Vec> velocities_by_id(const Sim& sim) {
  using Vec = typename Sim::Vec;
  const auto& p = sim.particles();
  std::uint64_t max_id = 0;
  for (std::size_t i = 0; i < p.owned(); ++i) max_id = std::max(max_id, p.id[i]);
  std::vector<Vec> out(p.owned() ? max_id + 1 : 0, Vec::Zero());
  for (std::size_t i = 0; i < p.owned(); ++i) out[p.id[i]] = p.v[i];
  return out;
}

/// Largest |a_k - b_k| over two equally long lists of vectors.
template <class Vec>
double max_difference(const std::vector<Vec>& a, const std::vector<Vec>& b) {
  double m = 0.0;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) m = std::max(m, (a[k] - b[k]).norm());
  return a.size() == b.size() ? m : std::numeric_limits<double>::infinity();
}

/// Total momentum sum m v of the real particles [kg m/s], and sum |m v| in `scale`.
template <class Sim>
typename Sim::Vec total_momentum(const Sim& sim, double* scale = nullptr) {
  using Vec = typename Sim::Vec;
  const auto& p = sim.particles();
  Vec P = Vec::Zero();
  double s = 0.0;
  for (std::size_t i = 0; i < p.owned(); ++i) {
    P += p.mass[i] * p.v[i];
    s += p.mass[i] * p.v[i].norm();
  }
  if (scale) *scale = s;
  return P;
}

/// A domain [0, L]^d with the given periodic flags.
template <class D>
Domain<D> box_domain(const typename D::Vec& length, bool periodic_all, int periodic_axis = -1) {
  Domain<D> d;
  d.lo = D::Vec::Zero();
  d.hi = length;
  for (int k = 0; k < D::dim; ++k) d.periodic[k] = periodic_all || k == periodic_axis;
  return d;
}

}  // namespace granule::test
