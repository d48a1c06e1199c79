#pragma once
// History hooks shared by the sub-models that carry a vector per contact.
//
// project_history: as the contact normal turns, a tangential spring stored in the world frame
// must stay in the current tangent plane. We remove its normal component and, when
// `keep_length` is set, restore its previous length (Luding 2008, "Cohesive, frictional powders:
// contact models for tension", section 2.2.3: the spring is rotated, not shortened). Without it
// the spring slowly loses length in rolling/rotating contacts (LAMMPS hooke/history behaviour).
//
// reverse_history: the history of pair (i, j) seen from j is the negative of that seen from i;
// used when a rebuild stores the pair in the other particle's row.
#include <cmath>

#include "granule/core/dimension.hpp"

namespace granule::contact {

template <class Vec>
inline void project_history(Vec& s, const Vec& n, bool keep_length) {
  const double before2 = s.squaredNorm();
  s -= s.dot(n) * n;
  if (keep_length) {
    const double after2 = s.squaredNorm();
    if (after2 > 0.0) s *= std::sqrt(before2 / after2);
  }
}

template <class Vec>
inline void reverse_history(Vec& s) {
  s = -s;
}
inline void reverse_history(double& s) { s = -s; }

}  // namespace granule::contact
