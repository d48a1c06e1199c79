#pragma once
// Per-particle virial stress and bulk average stress.
//
// Per particle, as LIGGGHTS / LAMMPS compute stress/atom (paper 001 eq. 8), in units of
// pressure × volume [N m]:
//   S_ab = −[ m v_a v_b + ½ Σ_pairs (r1_a F1_b + r2_a F2_b) ]
// For a pair contact with branch b = r_j − r_i and force F on i (−F on j),
// r1 ⊗ F1 + r2 ⊗ F2 = (r_i − r_j) ⊗ F, so each of i and j receives the contact part
//   S^c = ½ b ⊗ F.
// A wall contact has no partner to share with: particle i receives the whole Love–Weber term
//   S^c = b_w ⊗ F,  b_w = contact point − r_i
// (Love 1927; Christoffersen, Mehrabadi & Nemat-Nasser 1981), so that Σ_i S^c_i is the contact
// virial Σ_c b_c ⊗ F_c of the whole assembly, the same quantity the coarse-grained contact stress
// integrates to (coarse_graining.hpp). The kinetic part is S^k = −m (v − v_ref) ⊗ (v − v_ref);
// v_ref = 0 reproduces eq. 8 literally, a mean-flow velocity gives the fluctuation part.
//
// Bulk average over a region of volume V (3D: box volume; 2D: box area × frame thickness):
//   σ = (1/V) Σ_{i: r_i in region} S_i   [Pa].
// Sign: tension positive, compression negative (as LIGGGHTS). Index order: first index spatial
// (branch / velocity), second the force; with tangential forces S^c need not be symmetric, and
// LIGGGHTS reports the components (xx, yy, zz, xy, xz, yz) of exactly this tensor.
#include <cstddef>
#include <string>
#include <vector>

#include "granule/analysis/frame.hpp"
#include "granule/analysis/frame_checks.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

/// Per-particle virial, split into kinetic and contact parts [N m].
template <class D>
struct ParticleVirial {
  using Mat = typename D::Mat;
  std::vector<Mat> kinetic;  ///< −m v' ⊗ v'  [N m]
  std::vector<Mat> contact;  ///< ½ Σ b ⊗ F (pairs) + Σ b_w ⊗ F (walls)  [N m]
  /// Kinetic + contact part of particle i [N m].
  Mat total(std::size_t i) const { return kinetic[i] + contact[i]; }
  std::size_t size() const { return kinetic.size(); }
};

/// Volume-averaged stress of a region, split into kinetic and contact parts [Pa].
template <class D>
struct BulkStress {
  using Mat = typename D::Mat;
  Mat kinetic = Mat::Zero();  ///< [Pa]
  Mat contact = Mat::Zero();  ///< [Pa]
  double volume = 0.0;        ///< averaging volume [m^3]
  std::size_t particles = 0;  ///< particles whose centre lies in the region
  Mat total() const { return kinetic + contact; }
  /// Mean normal stress −tr(σ)/D, positive in compression [Pa].
  double pressure() const { return -total().trace() / D::dim; }
};

/// Per-particle virial of every particle of the frame (paper 001 eq. 8, LIGGGHTS stress/atom).
template <class D>
ParticleVirial<D> particle_virial(const Frame<D>& frame,
                                  const typename D::Vec& reference_velocity = D::Vec::Zero(),  // [m/s]
                                  bool include_walls = true) {
  using Mat = typename D::Mat;
  using Vec = typename D::Vec;
  granule::detail::check_frame(frame, "particle_virial");
  ParticleVirial<D> out;
  out.kinetic.resize(frame.size());
  out.contact.assign(frame.size(), Mat::Zero());
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const Vec dv = frame.v[i] - reference_velocity;
    out.kinetic[i] = -frame.mass[i] * dv * dv.transpose();
  }
  for (const auto& c : frame.contacts) {
    const Mat bf = c.branch * granule::detail::contact_force(c).transpose();
    if (c.j == ContactRecord<D>::kWall) {
      if (include_walls) out.contact[c.i] += bf;
    } else {
      out.contact[c.i] += 0.5 * bf;
      out.contact[c.j] += 0.5 * bf;
    }
  }
  return out;
}

/// Average stress of the particles whose centres lie in the box [lo, hi) (per axis), divided by
/// the box volume (2D: area × frame thickness) [Pa].
template <class D>
BulkStress<D> average_stress(const Frame<D>& frame,
                             const typename D::Vec& lo,  // [m]
                             const typename D::Vec& hi,  // [m]
                             const typename D::Vec& reference_velocity = D::Vec::Zero(),  // [m/s]
                             bool include_walls = true) {
  for (int a = 0; a < D::dim; ++a) {
    require(hi[a] > lo[a], "average_stress", "hi[" + std::to_string(a) + "] - lo", hi[a] - lo[a],
            "(0, inf)");
  }
  const ParticleVirial<D> s = particle_virial(frame, reference_velocity, include_walls);
  BulkStress<D> out;
  out.volume = (hi - lo).prod() * (D::dim == 2 ? frame.thickness : 1.0);
  for (std::size_t i = 0; i < frame.size(); ++i) {
    if ((frame.x[i].array() < lo.array()).any() || (frame.x[i].array() >= hi.array()).any())
      continue;
    out.kinetic += s.kinetic[i];
    out.contact += s.contact[i];
    ++out.particles;
  }
  out.kinetic /= out.volume;
  out.contact /= out.volume;
  return out;
}

/// Average stress of all particles over a given volume V (e.g. a periodic cell) [Pa].
template <class D>
BulkStress<D> average_stress(const Frame<D>& frame, double volume,  // [m^3]
                             const typename D::Vec& reference_velocity = D::Vec::Zero(),  // [m/s]
                             bool include_walls = true) {
  require_positive(volume, "average_stress", "volume");
  const ParticleVirial<D> s = particle_virial(frame, reference_velocity, include_walls);
  BulkStress<D> out;
  out.volume = volume;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    out.kinetic += s.kinetic[i];
    out.contact += s.contact[i];
  }
  out.particles = frame.size();
  out.kinetic /= volume;
  out.contact /= volume;
  return out;
}

}  // namespace granule::analysis
