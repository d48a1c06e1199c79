#pragma once
// Consistency checks and small helpers shared by the analyses that read a Frame: array sizes,
// contact indices, periodic minimum image and the total force of a contact.
#include <cmath>
#include <cstddef>
#include <string>

#include "granule/analysis/frame.hpp"
#include "granule/core/error.hpp"

namespace granule::detail {

/// Throws InvalidParameter (naming `where`) unless the per-particle arrays used by the analyses
/// (x, v, radius, mass) have the same length, masses and radii are positive, the 2D thickness is
/// positive, periodic axes have a positive box length, and every contact refers to existing
/// particles.
template <class D>
void check_frame(const analysis::Frame<D>& f, const std::string& where) {
  const double n = static_cast<double>(f.x.size());
  require(f.v.size() == f.x.size(), where, "frame.v.size()", static_cast<double>(f.v.size()),
          "frame.x.size() = " + to_text(n));
  require(f.radius.size() == f.x.size(), where, "frame.radius.size()",
          static_cast<double>(f.radius.size()), "frame.x.size() = " + to_text(n));
  require(f.mass.size() == f.x.size(), where, "frame.mass.size()",
          static_cast<double>(f.mass.size()), "frame.x.size() = " + to_text(n));
  if constexpr (D::dim == 2) require_positive(f.thickness, where, "frame.thickness");
  for (int a = 0; a < D::dim; ++a) {
    if (f.periodic[a]) {
      require(f.box_hi[a] > f.box_lo[a] && std::isfinite(f.box_hi[a] - f.box_lo[a]), where,
              "box length on periodic axis " + std::to_string(a), f.box_hi[a] - f.box_lo[a],
              "(0, inf)");
    }
  }
  for (std::size_t i = 0; i < f.x.size(); ++i) {
    if (!(f.radius[i] > 0.0) || !(f.mass[i] > 0.0)) {
      require(f.radius[i] > 0.0, where, "frame.radius[" + std::to_string(i) + "]", f.radius[i],
              "(0, inf)");
      require(f.mass[i] > 0.0, where, "frame.mass[" + std::to_string(i) + "]", f.mass[i],
              "(0, inf)");
    }
  }
  using Contact = analysis::ContactRecord<D>;
  for (std::size_t k = 0; k < f.contacts.size(); ++k) {
    const Contact& c = f.contacts[k];
    require(c.i < f.x.size(), where, "frame.contacts[" + std::to_string(k) + "].i", c.i,
            "[0, " + to_text(n) + ")");
    require(c.j == Contact::kWall || c.j < f.x.size(), where,
            "frame.contacts[" + std::to_string(k) + "].j", c.j,
            "[0, " + to_text(n) + ") or kWall");
  }
}

/// Applies the minimum-image convention to a difference vector on the frame's periodic axes.
template <class D>
typename D::Vec min_image(typename D::Vec d, const analysis::Frame<D>& f) {
  for (int a = 0; a < D::dim; ++a) {
    if (f.periodic[a]) {
      const double length = f.box_hi[a] - f.box_lo[a];
      d[a] -= length * std::round(d[a] / length);
    }
  }
  return d;
}

/// Total force exerted on particle i by the contact: fn · normal + ft [N].
template <class D>
typename D::Vec contact_force(const analysis::ContactRecord<D>& c) {
  return c.fn * c.normal + c.ft;
}

/// Volume of particle i (3D sphere; 2D disk times the frame thickness) [m^3].
template <class D>
double particle_volume(const analysis::Frame<D>& f, std::size_t i) {
  return D::volume(f.radius[i], f.thickness);
}

}  // namespace granule::detail
