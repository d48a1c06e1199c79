#pragma once
// GatheredParticles: the real particles of a run in global-id order, as Simulation::gather()
// returns them (on rank 0 of a distributed run, from every rank; in one process, its own).
// The base of distributed analysis, output and checkpoints (docs/mpi.md).
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "granule/particles/particle_store.hpp"

namespace granule {

template <class D>
struct GatheredParticles {
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  using Image = typename ParticleStore<D>::Image;
  std::vector<std::uint64_t> id;
  std::vector<Vec> x, v, f;
  std::vector<AngVec> omega, torque;
  std::vector<double> radius, mass;
  std::vector<std::uint32_t> material, group;
  std::vector<Motion> motion;
  std::vector<Image> image;

  std::size_t size() const { return id.size(); }

  /// Appends the real particles of a store.
  void append(const ParticleStore<D>& p) {
    for (std::size_t i = 0; i < p.owned(); ++i) {
      id.push_back(p.id[i]); x.push_back(p.x[i]); v.push_back(p.v[i]); f.push_back(p.f[i]);
      omega.push_back(p.omega[i]); torque.push_back(p.torque[i]); radius.push_back(p.radius[i]);
      mass.push_back(p.mass[i]); material.push_back(p.material[i]); group.push_back(p.group[i]);
      motion.push_back(p.motion[i]); image.push_back(p.image[i]);
    }
  }

  /// Puts the particles in id order.
  void sort_by_id() {
    std::vector<std::size_t> perm(id.size());
    std::iota(perm.begin(), perm.end(), std::size_t{0});
    std::sort(perm.begin(), perm.end(), [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
    auto apply = [&](auto& a) {
      auto out = a;
      for (std::size_t k = 0; k < perm.size(); ++k) out[k] = a[perm[k]];
      a.swap(out);
    };
    apply(id); apply(x); apply(v); apply(f); apply(omega); apply(torque); apply(radius); apply(mass);
    apply(material); apply(group); apply(motion); apply(image);
  }
};

}  // namespace granule
