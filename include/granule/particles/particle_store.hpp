#pragma once
// Particle storage as a structure of arrays. Index i is the particle's current slot: slots are
// permuted when the neighbour search re-sorts particles spatially, so code that must follow a
// particle over time uses its stable `id` (Simulation::index_of(id)).
//
// Slots [0, owned) are real particles; slots [owned, size) are ghosts, rebuilt with the neighbour
// list and refreshed every step: first the periodic images of this store's own particles
// (ghost_owner, ghost_shift: local_ghosts() of them), then, in a distributed run (docs/mpi.md),
// copies of other ranks' particles (remote ghosts: no owner slot here).
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"

namespace granule {

/// How a particle moves.
enum class Motion : std::uint8_t {
  Free = 0,        ///< integrated from forces and torques
  Frozen = 1,      ///< never moves (rough floors); acts as an immovable contact partner
  Prescribed = 2,  ///< velocity imposed by its group's velocity function (pistons, shakers)
};

template <class D>
class ParticleStore {
 public:
  using Vec = typename D::Vec;
  using AngVec = typename D::AngVec;
  using Image = Eigen::Matrix<int, D::dim, 1>;

  std::vector<Vec> x;               ///< position [m]
  std::vector<Vec> v;               ///< velocity [m/s]
  std::vector<Vec> f;               ///< force [N]
  std::vector<AngVec> omega;        ///< angular velocity [rad/s]
  std::vector<AngVec> torque;       ///< torque [N m]
  std::vector<double> radius;       ///< [m]
  std::vector<double> mass;         ///< [kg]
  std::vector<double> inv_mass;     ///< 1/m for free particles, 0 for frozen/prescribed [1/kg]
  std::vector<double> inv_inertia;  ///< 1/I for free particles, 0 otherwise [1/(kg m^2)]
  std::vector<std::uint32_t> material;
  std::vector<std::uint32_t> group;
  std::vector<std::uint64_t> id;
  std::vector<Motion> motion;
  std::vector<Image> image;         ///< periodic image counters (unwrapped = x + image * L)
  std::vector<std::uint32_t> ghost_owner;  ///< for ghost slot owned+k: slot of its owner
  std::vector<Image> ghost_shift;          ///< for ghost slot owned+k: image shift in box lengths

  std::size_t owned() const { return owned_; }
  std::size_t size() const { return x.size(); }
  std::size_t ghosts() const { return x.size() - owned_; }
  /// Ghosts that image a particle of this store (the first ghosts; the rest are remote).
  std::size_t local_ghosts() const { return ghost_owner.size(); }
  /// The slot whose particle slot j shows: j for a real particle or a remote ghost, the owner's
  /// slot for a periodic image.
  std::size_t source(std::size_t j) const {
    return j < owned_ || j - owned_ >= ghost_owner.size() ? j : ghost_owner[j - owned_];
  }

  /// Declares how many leading slots are real particles (used when restoring a checkpoint).
  void set_owned(std::size_t n) { owned_ = n; }

  /// Appends a real particle; returns its slot. Must not be called while ghosts exist.
  std::size_t add(const Vec& pos, const Vec& vel, double r, double m, std::uint32_t mat,
                  std::uint32_t grp, std::uint64_t pid) {
    x.push_back(pos);
    v.push_back(vel);
    f.push_back(D::zero());
    omega.push_back(D::zero_ang());
    torque.push_back(D::zero_ang());
    radius.push_back(r);
    mass.push_back(m);
    inv_mass.push_back(1.0 / m);
    inv_inertia.push_back(1.0 / (D::inertia_factor * m * r * r));
    material.push_back(mat);
    group.push_back(grp);
    id.push_back(pid);
    motion.push_back(Motion::Free);
    image.push_back(Image::Zero());
    owned_ = x.size();
    return owned_ - 1;
  }

  /// Sets the motion mode of slot i (updates the inverse mass and inertia used by contacts).
  void set_motion(std::size_t i, Motion m) {
    motion[i] = m;
    if (m == Motion::Free) {
      inv_mass[i] = 1.0 / mass[i];
      inv_inertia[i] = 1.0 / (D::inertia_factor * mass[i] * radius[i] * radius[i]);
    } else {
      inv_mass[i] = 0.0;
      inv_inertia[i] = 0.0;
    }
  }

  /// Removes all ghost slots.
  void clear_ghosts() { resize_all(owned_); ghost_owner.clear(); ghost_shift.clear(); }

  /// Returns the spare capacity of the arrays when it exceeds a quarter of their size (ghosts
  /// are appended one by one, so a rebuild can leave the arrays at twice the slots in use).
  void trim_capacity() {
    auto trim = [](auto& a) {
      if (a.capacity() > a.size() + a.size() / 4 + 64) a.shrink_to_fit();
    };
    trim(x); trim(v); trim(f); trim(omega); trim(torque); trim(radius); trim(mass); trim(inv_mass);
    trim(inv_inertia); trim(material); trim(group); trim(id); trim(motion); trim(image);
    trim(ghost_owner); trim(ghost_shift);
  }

  /// Appends a ghost image of owned slot o shifted by `shift` (box lengths) * `box`.
  void add_ghost(std::uint32_t o, const Image& shift, const Vec& box) {
    x.push_back(x[o] + (shift.template cast<double>().array() * box.array()).matrix());
    v.push_back(v[o]);
    f.push_back(D::zero());
    omega.push_back(omega[o]);
    torque.push_back(D::zero_ang());
    radius.push_back(radius[o]);
    mass.push_back(mass[o]);
    inv_mass.push_back(inv_mass[o]);
    inv_inertia.push_back(inv_inertia[o]);
    material.push_back(material[o]);
    group.push_back(group[o]);
    id.push_back(id[o]);
    motion.push_back(motion[o]);
    image.push_back(image[o]);
    ghost_owner.push_back(o);
    ghost_shift.push_back(shift);
  }

  /// Appends a copy of another rank's particle (a remote ghost: after every local ghost).
  /// `img` is the image counter as seen here: the owner's less the shift it was sent with.
  void add_remote_ghost(const Vec& pos, const Vec& vel, const AngVec& w, double r, double m, double im,
                        double iI, std::uint32_t mat, std::uint32_t grp, std::uint64_t pid, Motion mo,
                        const Image& img) {
    x.push_back(pos); v.push_back(vel); f.push_back(D::zero()); omega.push_back(w);
    torque.push_back(D::zero_ang()); radius.push_back(r); mass.push_back(m); inv_mass.push_back(im);
    inv_inertia.push_back(iI); material.push_back(mat); group.push_back(grp); id.push_back(pid);
    motion.push_back(mo); image.push_back(img);
  }

  /// Reorders the real particles: new slot k holds old slot perm[k]. Ghosts must be cleared.
  void permute(const std::vector<std::uint32_t>& perm) {
    permute_one(x, perm); permute_one(v, perm); permute_one(f, perm);
    permute_one(omega, perm); permute_one(torque, perm); permute_one(radius, perm);
    permute_one(mass, perm); permute_one(inv_mass, perm); permute_one(inv_inertia, perm);
    permute_one(material, perm); permute_one(group, perm); permute_one(id, perm);
    permute_one(motion, perm); permute_one(image, perm);
  }

  /// Removes the real particles for which keep[i] is false (ghosts must be cleared).
  void remove_if_not(const std::vector<bool>& keep) {
    std::vector<std::uint32_t> perm;
    perm.reserve(owned_);
    for (std::size_t i = 0; i < owned_; ++i)
      if (keep[i]) perm.push_back(static_cast<std::uint32_t>(i));
    permute(perm);
    owned_ = perm.size();
  }

 private:
  template <class T>
  static void permute_one(std::vector<T>& a, const std::vector<std::uint32_t>& perm) {
    std::vector<T> out(perm.size());
    for (std::size_t k = 0; k < perm.size(); ++k) out[k] = a[perm[k]];
    a.swap(out);
  }
  void resize_all(std::size_t n) {
    x.resize(n); v.resize(n); f.resize(n); omega.resize(n); torque.resize(n); radius.resize(n);
    mass.resize(n); inv_mass.resize(n); inv_inertia.resize(n); material.resize(n);
    group.resize(n); id.resize(n); motion.resize(n); image.resize(n);
  }
  std::size_t owned_ = 0;
};

}  // namespace granule
