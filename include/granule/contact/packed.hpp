#pragma once
// Packed evaluation of particle-pair contacts (3D and 2D): W contacts through one law call.
//
// The engine's packed pair loop (Simulation, docs/architecture.md "Packed contacts") runs in
// three passes over a cell layer:
//   1. test every list entry of the layer for touch (no square root, no branch; 8 entries at a
//      time with AVX-512, contact/touch_scan.hpp); list the touching pairs (particle slots and
//      history slot) in a chunk, 64 pairs at a time;
//   2. packed: read the particle data of W contacts at a time straight from the particle
//      arrays into packs (core/lane_transpose.hpp), build ContactGeometry<Dim3Lanes>, read
//      their histories the same way, evaluate the model, write the histories back;
//   3. scalar: add the forces and torques to both particles, in the order of the entries
//      (a row's partners, and a particle's rows, may repeat within a pack).
// Wall contacts are found one at a time (the wall shapes and their features) and queued; their
// law runs W at a time through GeometryLanes.
// Only the pass-2 arithmetic is new code; the laws are the same templates as for one contact.
#include <array>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "granule/contact/geometry.hpp"
#include "granule/core/lane_transpose.hpp"
#include "granule/core/lanes.hpp"

namespace granule::contact {

/// Copies a contact history between its stored form (State<Dim3> or State<Dim2>, doubles) and
/// its packed form (State<Dim3Lanes> or State<Dim2Lanes>, one pack per double). Both are
/// aggregates of the same members in the same order, so the packed form is the stored one with
/// every double widened to a pack. The stored form may end in padding: a 2D history of an
/// Eigen::Vector2d (aligned to 16 bytes) and one double takes 32 bytes for its 3 doubles.
template <class Stored, class Packed>
struct PackedState {
  static constexpr std::size_t doubles = sizeof(Packed) / sizeof(Lane);
  // (Eigen's fixed-size vectors are plain arrays of doubles, but declare copy constructors, so
  // they are not formally trivially copyable; the checkpoints copy them as bytes too.)
  static_assert(sizeof(Packed) == doubles * sizeof(Lane), "a packed history must consist of packs");
  static_assert(sizeof(Stored) >= doubles * sizeof(double) &&
                    sizeof(Stored) - doubles * sizeof(double) < alignof(Stored),
                "the packed history must widen every double of the stored one to a pack (padding "
                "only at the end of the stored one)");

  /// With AVX2, a history of 3 doubles in a 32-byte record (2D: the tangential force and the
  /// rolling torque) moves as 4 doubles, one full load or store per record instead of two plus
  /// one; the padding is written as 0, which is what value-initialisation left there. (Zen 3,
  /// 2026-12-07: the 2D step 1.0-1.4 % faster, measured inside one run; on Zen 5's AVX-512 the
  /// whole-record move gave nothing, and AVX-512 reads 3 or 4 doubles alike, one masked load.)
  static constexpr std::size_t moved =
      lane_width == 4 && doubles == 3 && sizeof(Stored) == 4 * sizeof(double) ? 4 : doubles;

  static void load(Packed& out, const Stored* const* in) {
    const double* rec[lane_width];
    for (std::size_t l = 0; l < lane_width; ++l) rec[l] = reinterpret_cast<const double*>(in[l]);
    Lane lanes[moved];
    transpose_in<moved>(rec, lanes);
    std::memcpy(static_cast<void*>(&out), lanes, sizeof(Packed));
  }
  /// Writes back the first `valid` lanes.
  static void store(const Packed& in, Stored* const* out, std::size_t valid) {
    double* rec[lane_width];
    for (std::size_t l = 0; l < lane_width; ++l) rec[l] = reinterpret_cast<double*>(out[l]);
    Lane lanes[moved];
    std::memcpy(lanes, static_cast<const void*>(&in), sizeof(Packed));
    if constexpr (moved > doubles) lanes[doubles] = 0.0;
    transpose_out<moved>(lanes, rec, valid);
  }
};

/// 2D: what the packed geometry reads of one disk besides its position, in one 32-byte record:
/// one aligned load per disk of a pack instead of loads from three arrays (v, omega, radius).
/// The engine copies them from the particle store at the start of each packed force pass
/// (fill_disk_records), so nothing else has to keep them current. (Zen 3, 2026-12-07, the two
/// gathers alternated in one run: the step 3-4 % faster, the copy ~2 % of it.)
struct alignas(32) DiskRecord {
  double vx = 0.0, vy = 0.0, omega = 0.0, radius = 0.0;
};

/// out[i] = (v_i, omega_i, r_i) for i < n; v: n 2-vectors, omega and radius: n doubles. Exact
/// copies. With AVX2 (also under AVX-512) four disks at a time: 4 loads, 6 shuffles, 4 stores.
inline void fill_disk_records(const double* v, const double* omega, const double* radius, std::size_t n,
                              DiskRecord* out) {
  std::size_t i = 0;
#if defined(__AVX2__)
  for (; i + 4 <= n; i += 4) {
    const __m256d v01 = _mm256_loadu_pd(v + 2 * i), v23 = _mm256_loadu_pd(v + 2 * i + 4);
    const __m256d w = _mm256_loadu_pd(omega + i), r = _mm256_loadu_pd(radius + i);
    const __m256d wr02 = _mm256_unpacklo_pd(w, r), wr13 = _mm256_unpackhi_pd(w, r);  // (w0 r0 w2 r2), (w1 r1 w3 r3)
    double* const o = &out[i].vx;
    _mm256_store_pd(o, _mm256_permute2f128_pd(v01, wr02, 0x20));
    _mm256_store_pd(o + 4, _mm256_permute2f128_pd(v01, wr13, 0x21));
    _mm256_store_pd(o + 8, _mm256_permute2f128_pd(v23, wr02, 0x30));
    _mm256_store_pd(o + 12, _mm256_permute2f128_pd(v23, wr13, 0x31));
  }
#endif
  for (; i < n; ++i) out[i] = {v[2 * i], v[2 * i + 1], omega[i], radius[i]};
}

/// What the packed geometry reads of the particles: pointers to the store's arrays, indexed by
/// particle slot, ghosts included. Vectors are dim consecutive doubles each (3D: x, v, omega as
/// 3-vectors; 2D: x and v as 2-vectors, omega one double, its z component).
struct PackedParticles {
  const double* x;
  const double* v;
  const double* omega;
  const double* radius;
  const double* inv_mass;
  /// 2D, optional: v, omega and r of each disk as one record (the same values as the three
  /// arrays, which are then not read).
  const DiskRecord* disks = nullptr;
};

/// The terms of a pair's geometry that depend on its radii and inverse masses alone: R*, m* and
/// the rolling inertia I_r, 5 of the 7 divisions of a packed 2D geometry. The 2D engine keeps
/// them per neighbour-list entry, computed when the list is built or loaded
/// (Simulation::pair_constants_), and the packed geometry reads one record per contact.
/// The formulas below are the ones the packed geometry evaluates otherwise (same operations in
/// the same order: the same bits for doubles and for packs).
struct alignas(32) PairConstants {
  double r_eff = 0.0;
  double m_eff = 0.0;
  double i_roll = 0.0;  ///< 0 unless the rolling law needs it
  double unused = 0.0;  ///< (4 doubles: a record is one aligned 32-byte block)
};

/// R* = r_i r_j / (r_i + r_j), with rs = r_i + r_j (R: double or Lane).
template <class R>
inline R effective_radius(const R& r_i, const R& r_j, const R& rs) {
  return r_i * r_j / rs;
}
/// m* = 1 / (1/m_i + 1/m_j).
template <class R>
inline R effective_mass(const R& im_i, const R& im_j) {
  return 1.0 / (im_i + im_j);
}
/// I_r: 1/I_r = sum 1/(I + m r^2) = sum (1/m) / ((k + 1) r^2), k = inertia_factor (I = k m r^2).
template <class R>
inline R rolling_inertia(const R& r_i, const R& r_j, const R& im_i, const R& im_j, double inertia_factor) {
  const double k1 = inertia_factor + 1.0;
  return 1.0 / (im_i / (k1 * r_i * r_i) + im_j / (k1 * r_j * r_j));
}

/// Lanes of a 2-vector: lane l = the 2 doubles at base + 2 idx[l] (an array of 2-vectors).
inline LaneVec2 gather_vec2_lanes(const double* base, const std::uint32_t* idx) {
  const double* rec[lane_width];
  for (std::size_t l = 0; l < lane_width; ++l) rec[l] = base + 2 * static_cast<std::size_t>(idx[l]);
  Lane out[2];
  transpose_in<2>(rec, out);
  return {out[0], out[1]};
}

/// One chunk of touching pairs of dimension Dim (2 or 3): their particle slots and history
/// slots, and the results. Capacity: a multiple of the lane width.
template <std::size_t Capacity, int Dim = 3>
struct PairChunk {
  static_assert(Capacity % lane_width == 0);
  static_assert(Dim == 2 || Dim == 3);
  static constexpr std::size_t capacity = Capacity;
  using LD = std::conditional_t<Dim == 2, Dim2Lanes, Dim3Lanes>;
  // Inputs, listed in pass 1. (Until 2026-12-03 pass 1 also copied 16 doubles of particle data
  // per pair into the chunk; pass 2 now reads them from the particle arrays itself.)
  std::uint32_t i[Capacity], j[Capacity];
  std::uint32_t history[Capacity];  ///< history slot of each contact (PairList::slot)
  std::uint32_t entry[Capacity];    ///< list entry of each contact (filled for the per-pair constants)
  /// x_i - x_j of the chunk's contacts by axis (2D: from the touch scan, TouchScanInput::
  /// separation; the lanes past `count` hold finite leftovers, dropped), or null: gathered.
  const double* separation[Dim] = {};
  // Outputs of pass 2, rows of out: force on i (Dim rows from fx), torques on i and j (3 rows
  // each in 3D, from tix and tjx; one row each in 2D, the z component).
  static constexpr std::size_t ang = Dim == 3 ? 3 : 1;
  static constexpr std::size_t fx = 0, tix = Dim, tjx = Dim + ang, outs = Dim + 2 * ang;
  alignas(64) double out[outs][Capacity];
  std::size_t count = 0;
  std::size_t params = 0;  ///< index of the pair parameters every contact of the chunk shares

  bool full() const { return count == Capacity; }

  /// Fills the unused lanes of the last pack with copies of the last contact, so that pass 2
  /// computes on valid numbers everywhere (their results are dropped).
  void pad() {
    const std::size_t end = (count + lane_width - 1) / lane_width * lane_width;
    for (std::size_t c = count; c < end; ++c) {
      i[c] = i[count - 1];
      j[c] = j[count - 1];
      history[c] = history[count - 1];
      entry[c] = entry[count - 1];
    }
  }

  void store(std::size_t row, std::size_t k, const Lane& v) { v.copy_to(&out[row][k], stdx::vector_aligned); }
  void store_vec(std::size_t row, std::size_t k, const LaneVec3& v) {
    store(row, k, v.x);
    store(row + 1, k, v.y);
    store(row + 2, k, v.z);
  }
  void store_vec(std::size_t row, std::size_t k, const LaneVec2& v) {
    store(row, k, v.x);
    store(row + 1, k, v.y);
  }
  /// Force and torques of the W contacts starting at k.
  void store_force(std::size_t k, const ContactForce<LD>& cf) {
    store_vec(fx, k, cf.force);
    if constexpr (Dim == 3) {
      store_vec(tix, k, cf.torque_i);
      store_vec(tjx, k, cf.torque_j);
    } else {
      store(tix, k, cf.torque_i);
      store(tjx, k, cf.torque_j);
    }
  }

  /// Geometry of the W contacts starting at k (as Simulation::pair_geometry for one contact).
  /// `RollingInertia` and `Twist` say whether the model needs i_roll and the twist angle.
  /// With `Cached`, R*, m* and I_r are read from `constants` (indexed by list entry, `entry`
  /// filled), not computed.
  template <bool RollingInertia, bool Twist, bool Cached = false>
  void geometry(std::size_t k, const PackedParticles& p, double dt, ContactGeometry<LD>& g,
                const PairConstants* constants = nullptr) const {
    using std::sqrt;
    using V = typename LD::Vec;
    using AngV = typename LD::AngVec;
    // (2D: the gathers are most of what the geometry waits for; 3D keeps the buffer gathers,
    // measured faster there, see GatherBy.)
    constexpr GatherBy By = Dim == 2 ? GatherBy::registers : GatherBy::buffer;
    const std::uint32_t* const ik = &i[k];
    const std::uint32_t* const jk = &j[k];
    const auto vec = [](const double* base, const std::uint32_t* idx) -> V {
      if constexpr (Dim == 3) {
        return gather_vec3_lanes(base, idx);
      } else {
        return gather_vec2_lanes(base, idx);
      }
    };
    const auto ang_vec = [&](const std::uint32_t* idx) -> AngV {
      if constexpr (Dim == 3) {
        return gather_vec3_lanes(p.omega, idx);
      } else {
        return gather_lanes<By>(p.omega, idx);
      }
    };
    V d;
    if constexpr (Dim == 2) {
      if (separation[0] != nullptr) {
        d = {Lane(separation[0] + k, stdx::element_aligned), Lane(separation[1] + k, stdx::element_aligned)};
      } else {
        d = vec(p.x, ik) - vec(p.x, jk);
      }
    } else {
      d = vec(p.x, ik) - vec(p.x, jk);
    }
    Lane r_i, r_j;
    AngV w_i, w_j;
    V dv;
    if constexpr (Dim == 2) {
      if (p.disks != nullptr) {
        const double* rec[lane_width];
        Lane a[4], b[4];
        for (std::size_t l = 0; l < lane_width; ++l) rec[l] = &p.disks[ik[l]].vx;
        transpose_in<4>(rec, a);
        for (std::size_t l = 0; l < lane_width; ++l) rec[l] = &p.disks[jk[l]].vx;
        transpose_in<4>(rec, b);
        dv = {a[0] - b[0], a[1] - b[1]};
        w_i = a[2];
        w_j = b[2];
        r_i = a[3];
        r_j = b[3];
      }
    }
    if (Dim == 3 || p.disks == nullptr) {
      r_i = gather_lanes<By>(p.radius, ik);
      r_j = gather_lanes<By>(p.radius, jk);
      w_i = ang_vec(ik);
      w_j = ang_vec(jk);
      dv = vec(p.v, ik) - vec(p.v, jk);
    }
    const Lane rs = r_i + r_j;
    const Lane dist = sqrt(d.squaredNorm());
    const LaneMask apart = dist > 0.0;
    g.distance = dist;
    // Coincident centres (dist = 0) get the normal along the last axis (+z, 2D: +y), as in the
    // scalar geometry.
    if constexpr (Dim == 3) {
      g.n = {select(apart, d.x / dist, Lane(0.0)), select(apart, d.y / dist, Lane(0.0)),
             select(apart, d.z / dist, Lane(1.0))};
    } else {
      g.n = {select(apart, d.x / dist, Lane(0.0)), select(apart, d.y / dist, Lane(1.0))};
    }
    g.overlap = rs - dist;
    g.r_i = r_i;
    g.r_j = r_j;
    g.arm_i = r_i - 0.5 * g.overlap;
    g.arm_j = r_j - 0.5 * g.overlap;
    g.v_rel = dv - (g.arm_i * LD::cross(w_i, g.n) + g.arm_j * LD::cross(w_j, g.n));
    g.vn = g.v_rel.dot(g.n);
    g.vt = g.v_rel - g.vn * g.n;
    g.omega_rel = w_i - w_j;
    g.damp_at_kinematic_velocity();
    if constexpr (Cached) {
      const double* rec[lane_width];
      for (std::size_t l = 0; l < lane_width; ++l) rec[l] = &constants[entry[k + l]].r_eff;
      Lane c[3];
      transpose_in<RollingInertia ? 3 : 2>(rec, c);
      g.r_eff = c[0];
      g.m_eff = c[1];
      g.i_roll = RollingInertia ? c[2] : Lane(0.0);
    } else {
      g.r_eff = effective_radius(r_i, r_j, rs);
      const Lane im_i = gather_lanes(p.inv_mass, ik), im_j = gather_lanes(p.inv_mass, jk);
      g.m_eff = effective_mass(im_i, im_j);
      if constexpr (RollingInertia) {
        g.i_roll = rolling_inertia(r_i, r_j, im_i, im_j, LD::inertia_factor);
      } else {
        g.i_roll = 0.0;
      }
    }
    g.dt = dt;
    if constexpr (Twist && Dim == 3) {
      g.twist = 0.5 * (w_i + w_j).dot(g.n) * g.dt;
    } else {
      g.twist = 0.0;
    }
  }
};

/// W contact geometries built one at a time (ContactGeometry<Dim3>), stored lane by lane, for
/// one packed law call: the engine's wall contacts (the surface point of each wall shape, as
/// Simulation::wall_geometry; a wall has no second particle to read, so only the law is packed;
/// in scene B the scalar law took about 68 of the ~110 TSC cycles a wall contact cost) and the
/// kernel benchmarks' batches.
struct GeometryLanes {
  enum Field { nx, ny, nz, overlap, distance, r_i, r_j, arm_i, arm_j, r_eff, m_eff, vx, vy, vz, vn,
               vtx, vty, vtz, wx, wy, wz, i_roll, dt, twist, fields };
  alignas(64) double v[fields][lane_width];

  void set(std::size_t l, const ContactGeometry<Dim3>& g) {
    const double f[fields] = {g.n.x(), g.n.y(), g.n.z(), g.overlap, g.distance, g.r_i, g.r_j, g.arm_i,
                              g.arm_j, g.r_eff, g.m_eff, g.v_rel.x(), g.v_rel.y(), g.v_rel.z(), g.vn,
                              g.vt.x(), g.vt.y(), g.vt.z(), g.omega_rel.x(), g.omega_rel.y(), g.omega_rel.z(),
                              g.i_roll, g.dt, g.twist};
    for (std::size_t k = 0; k < fields; ++k) v[k][l] = f[k];
  }
  /// Lane `from` into lane `to` (padding of a part-filled pack).
  void copy_lane(std::size_t from, std::size_t to) {
    for (std::size_t k = 0; k < fields; ++k) v[k][to] = v[k][from];
  }
  /// The packed geometry, dashpots on the kinematic velocity (the packed loop's only case).
  ContactGeometry<Dim3Lanes> packed() const {
    const auto lane = [&](Field k) { return Lane(v[k], stdx::vector_aligned); };
    const auto lane3 = [&](Field k) { return LaneVec3{lane(k), lane(Field(k + 1)), lane(Field(k + 2))}; };
    ContactGeometry<Dim3Lanes> g;
    g.n = lane3(nx);
    g.overlap = lane(overlap);
    g.distance = lane(distance);
    g.r_i = lane(r_i);
    g.r_j = lane(r_j);
    g.arm_i = lane(arm_i);
    g.arm_j = lane(arm_j);
    g.r_eff = lane(r_eff);
    g.m_eff = lane(m_eff);
    g.v_rel = lane3(vx);
    g.vn = lane(vn);
    g.vt = lane3(vtx);
    g.omega_rel = lane3(wx);
    g.i_roll = lane(i_roll);
    g.dt = lane(dt);
    g.twist = lane(twist);
    g.damp_at_kinematic_velocity();
    return g;
  }
};

}  // namespace granule::contact
