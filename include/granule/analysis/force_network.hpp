#pragma once
// Force-network statistics of a Frame.
//
//  * Per contact: normal force fn (signed, positive = repulsive), tangential magnitude |ft| and
//    branch vector, for particle pairs, wall contacts or both.
//  * PDF of fn / ⟨fn⟩ as a probability-density histogram (histogram.hpp), and the number of
//    "very strong" forces fn > k ⟨fn⟩; paper 000 section V / fig. 8 uses k = 6 and counts
//    normal forces between particles (ContactKind::ParticlePair, the default).
//  * Friction mobilisation per contact (paper 002 section 4, fig. 12–13; Radjai et al. 1998):
//      μ* = |ft| / (μ fn),
//    1 at the Coulomb threshold. Undefined, hence skipped and counted, when fn ≤ 0 or μ ≤ 0.
//    Reported with its histogram and mean separately for the bulk (particle pairs) and for the
//    wall contacts, as 002 fig. 13 does.
//  * Coordination number Z: mean number of contacts per particle, 2C/N with C pair contacts
//    (walls optionally counted once per wall contact). With RattlerRule::ThorntonMechanical the
//    mechanical coordination number of Thornton (2000, Géotechnique 50:43, eq. 1) is returned:
//      Z_m = (Σ_i c_i − N_1) / (N − N_0 − N_1),
//    N_0, N_1 the numbers of particles with zero and one contact (c_i: contacts of particle i):
//    particles that carry no force chain (rattlers with < 2 contacts) are removed together with
//    the single contact end of each one-contact particle. Every contact record counts (also
//    cohesive ones with fn ≤ 0).
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "granule/analysis/frame.hpp"
#include "granule/analysis/frame_checks.hpp"
#include "granule/analysis/histogram.hpp"
#include "granule/core/error.hpp"

namespace granule::analysis {

/// Which contacts a statistic uses.
enum class ContactKind {
  ParticlePair,  ///< j is a particle
  Wall,          ///< j == kWall
  Any            ///< both
};

/// Per-contact force data of the selected contacts, in frame.contacts order.
template <class D>
struct ContactForceList {
  using Vec = typename D::Vec;
  std::vector<std::size_t> contact;  ///< index into frame.contacts
  std::vector<double> fn;            ///< normal force, positive = repulsive [N]
  std::vector<double> ft;            ///< |tangential force| [N]
  std::vector<Vec> branch;           ///< branch vector [m]
  std::vector<bool> wall;            ///< true for a wall contact
  std::size_t size() const { return fn.size(); }
};

namespace detail_fn {
template <class D>
bool selected(const ContactRecord<D>& c, ContactKind kind) {
  const bool wall = c.j == ContactRecord<D>::kWall;
  return kind == ContactKind::Any || (kind == ContactKind::Wall) == wall;
}
}  // namespace detail_fn

/// Normal / tangential force magnitudes and branch vectors of the selected contacts.
template <class D>
ContactForceList<D> contact_forces(const Frame<D>& frame, ContactKind kind = ContactKind::Any) {
  granule::detail::check_frame(frame, "contact_forces");
  ContactForceList<D> out;
  for (std::size_t k = 0; k < frame.contacts.size(); ++k) {
    const auto& c = frame.contacts[k];
    if (!detail_fn::selected(c, kind)) continue;
    out.contact.push_back(k);
    out.fn.push_back(c.fn);
    out.ft.push_back(c.ft.norm());
    out.branch.push_back(c.branch);
    out.wall.push_back(c.j == ContactRecord<D>::kWall);
  }
  return out;
}

/// ⟨fn⟩ over the selected contacts [N] (NaN when there is none).
template <class D>
double mean_normal_force(const Frame<D>& frame, ContactKind kind = ContactKind::ParticlePair) {
  double s = 0.0;
  std::size_t n = 0;
  for (const auto& c : frame.contacts) {
    if (!detail_fn::selected(c, kind)) continue;
    s += c.fn;
    ++n;
  }
  return n > 0 ? s / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

/// PDF of fn / ⟨fn⟩ with its normalising mean.
struct ForcePdf {
  Histogram histogram;  ///< density of fn / ⟨fn⟩ on the given edges
  double mean_fn = 0.0; ///< ⟨fn⟩ [N]
};

/// Histogram (unit integral when the edges cover all samples) of fn / ⟨fn⟩ over the selected
/// contacts. Throws InvalidParameter if there is no contact or ⟨fn⟩ ≤ 0.
template <class D>
ForcePdf normal_force_pdf(const Frame<D>& frame, const std::vector<double>& edges,
                          ContactKind kind = ContactKind::ParticlePair) {
  ForcePdf out;
  out.mean_fn = mean_normal_force(frame, kind);
  require(out.mean_fn > 0.0, "normal_force_pdf", "mean normal force", out.mean_fn,
          "(0, inf) (needs at least one selected contact)");
  std::vector<double> x;
  for (const auto& c : frame.contacts)
    if (detail_fn::selected(c, kind)) x.push_back(c.fn / out.mean_fn);
  out.histogram = make_histogram(x, edges);
  return out;
}

/// Number of selected contacts with fn > k ⟨fn⟩ ("very strong forces", paper 000: k = 6).
template <class D>
std::size_t count_strong_forces(const Frame<D>& frame, double k = 6.0,
                                ContactKind kind = ContactKind::ParticlePair) {
  require_non_negative(k, "count_strong_forces", "k");
  const double mean = mean_normal_force(frame, kind);
  if (!(mean > 0.0)) return 0;
  std::size_t n = 0;
  for (const auto& c : frame.contacts)
    if (detail_fn::selected(c, kind) && c.fn > k * mean) ++n;
  return n;
}

/// μ* = |ft| / (μ fn) values of one group of contacts with their distribution.
struct MobilisationStats {
  std::vector<double> mu_star;   ///< per contact with fn > 0 and μ > 0 [-]
  std::vector<std::size_t> contact;  ///< index into frame.contacts of each value
  Histogram histogram;           ///< density of μ* on the given edges
  double mean = std::numeric_limits<double>::quiet_NaN();  ///< mean μ* (NaN if none)
  std::size_t skipped = 0;       ///< contacts of the group with fn ≤ 0 or μ ≤ 0
  std::size_t sliding = 0;       ///< contacts with μ* ≥ 1 − slip_tolerance
};

/// μ* statistics split as in paper 002 fig. 13.
struct FrictionMobilisation {
  MobilisationStats bulk;  ///< particle–particle contacts
  MobilisationStats wall;  ///< particle–wall contacts
  MobilisationStats all;   ///< both
};

/// Friction mobilisation μ* = |ft| / (μ fn) of every contact, split into bulk and wall groups.
/// `wall_indices`, when not empty, restricts the wall group to those walls (contacts with other
/// walls, e.g. an intruder, are then left out of every group).
template <class D>
FrictionMobilisation friction_mobilisation(const Frame<D>& frame, const std::vector<double>& edges,
                                           const std::vector<std::uint32_t>& wall_indices = {},
                                           double slip_tolerance = 1e-9) {
  granule::detail::check_frame(frame, "friction_mobilisation");
  require_non_negative(slip_tolerance, "friction_mobilisation", "slip_tolerance");
  FrictionMobilisation out;
  auto add = [&](MobilisationStats& s, double value, std::size_t k, bool ok) {
    if (!ok) {
      ++s.skipped;
      return;
    }
    s.mu_star.push_back(value);
    s.contact.push_back(k);
    if (value >= 1.0 - slip_tolerance) ++s.sliding;
  };
  for (std::size_t k = 0; k < frame.contacts.size(); ++k) {
    const auto& c = frame.contacts[k];
    const bool wall = c.j == ContactRecord<D>::kWall;
    if (wall && !wall_indices.empty() &&
        std::find(wall_indices.begin(), wall_indices.end(), c.wall) == wall_indices.end())
      continue;
    const bool ok = c.fn > 0.0 && c.mu > 0.0;
    const double value = ok ? c.ft.norm() / (c.mu * c.fn) : 0.0;
    add(wall ? out.wall : out.bulk, value, k, ok);
    add(out.all, value, k, ok);
  }
  for (MobilisationStats* s : {&out.bulk, &out.wall, &out.all}) {
    s->histogram = make_histogram(s->mu_star, edges);
    if (!s->mu_star.empty()) {
      double sum = 0.0;
      for (double v : s->mu_star) sum += v;
      s->mean = sum / static_cast<double>(s->mu_star.size());
    }
  }
  return out;
}

/// How coordination_number treats particles with fewer than two contacts.
enum class RattlerRule {
  KeepAll,            ///< Z = Σ c_i / N
  ThorntonMechanical  ///< Z_m = (Σ c_i − N_1) / (N − N_0 − N_1)  (Thornton 2000)
};

/// Coordination number and the counts it was computed from.
struct CoordinationNumber {
  double z = 0.0;              ///< coordination number [-]
  std::size_t particles = 0;   ///< N
  std::size_t contact_ends = 0;  ///< Σ c_i (2 per pair contact, 1 per counted wall contact)
  std::size_t n0 = 0;          ///< particles with no contact
  std::size_t n1 = 0;          ///< particles with exactly one contact
};

/// Mean contacts per particle. Wall contacts count towards c_i only when `count_walls`.
template <class D>
CoordinationNumber coordination_number(const Frame<D>& frame,
                                       RattlerRule rule = RattlerRule::KeepAll,
                                       bool count_walls = false) {
  granule::detail::check_frame(frame, "coordination_number");
  CoordinationNumber out;
  out.particles = frame.size();
  std::vector<std::size_t> ci(frame.size(), 0);
  for (const auto& c : frame.contacts) {
    if (c.j == ContactRecord<D>::kWall) {
      if (count_walls) ++ci[c.i];
    } else {
      ++ci[c.i];
      ++ci[c.j];
    }
  }
  for (std::size_t n : ci) {
    out.contact_ends += n;
    if (n == 0) ++out.n0;
    if (n == 1) ++out.n1;
  }
  if (rule == RattlerRule::KeepAll) {
    out.z = out.particles > 0 ? static_cast<double>(out.contact_ends) / out.particles : 0.0;
  } else {
    const std::size_t kept = out.particles - out.n0 - out.n1;
    out.z = kept > 0 ? static_cast<double>(out.contact_ends - out.n1) / static_cast<double>(kept)
                     : 0.0;
  }
  return out;
}

}  // namespace granule::analysis
