#pragma once
// Pass 1 of the packed pair loop (contact/packed.hpp) for one cell layer of the neighbour list:
// which entries touch (|x_i - x_j| < r_i + r_j), listed in entry order with their rows, and
// which entries' history slots must move (a pair that starts touching takes one, one that
// separates gives it back).
//
// With AVX-512 or AVX2 the layer's entries are scanned W at a time (8 or 4) as one stream,
// across row ends: the rows are first written out per entry (or read from the caller's per-entry
// rows, TouchScanInput::entry_row), then each block of W reads both
// particles' positions through the lane transposes (core/lane_transpose.hpp), and the touching
// entries are packed together (one compress instruction with AVX-512; a lane permutation from
// a 16-entry table with AVX2). (Scanning row by row, 8 lanes for rows of 3 to 4 entries in
// scene B, was 5 % slower than one entry at a time; the stream with AVX2 made scene B 10-13 %
// faster on a Zen 3 machine, probably because rows of varying length end in a mispredicted
// branch; that VM has no branch counters to confirm it.) Elsewhere one entry at a time.
// Both sum the squared distance as x*x + (y*y + z*z) (2D: x*x + y*y), the order of Eigen's squaredNorm; a pair
// touching to within a rounding error may still come out differently where the compiler fuses
// multiply-adds differently in the two.
#include <bit>
#include <cstddef>
#include <cstdint>

#include "granule/core/lane_transpose.hpp"
#include "granule/core/lanes.hpp"

namespace granule::contact {

/// What a scan reads: positions (Dim doubles each) and radii by particle slot, the list's rows and
/// partners, and its history slots (nullptr for a model without history).
struct TouchScanInput {
  const double* x;
  const double* radius;
  const std::uint32_t* row_begin;
  const std::uint32_t* nbr;
  const std::uint32_t* slot;
  std::uint32_t no_slot;  ///< the slot value of an entry without history (PairList::kNone)
  /// r_i + r_j per entry (and 8 doubles of room after the last), or nullptr: the scan then adds
  /// the radii itself. (The 2D engine keeps it with the per-pair constants: one load per block
  /// instead of 16 scattered ones.)
  const double* reach = nullptr;
  /// The row of every entry (and 8 of room after the last), or nullptr: the scan then writes
  /// the rows out per entry itself, into `rows`, at the start of every scan. (The 2D engine
  /// keeps it with the per-pair constants: the write-out, and the blocks' reads of rows just
  /// written, were 6 % of a 2D step on a Zen 3, measured inside one run on 2026-12-07.)
  const std::uint32_t* entry_row = nullptr;
  /// Output, if set (2D engine): x_i - x_j of each touching entry, axis by axis (separation[k]
  /// for axis k, Dim arrays with the room of `touching`), at the entry's place in `touching`. The
  /// packed geometry reads it instead of gathering both positions again; the same subtraction,
  /// so the same bits.
  double* separation[3] = {nullptr, nullptr, nullptr};
};

/// One entry at a time: lists the touching entries of rows [r0, r1) in `touching` (entry
/// index) and `rows` (its row) and returns their number; calls `move_slot(e, touch)` in entry
/// order for each entry whose history slot must change. Dim: 3 (spheres) or 2 (disks).
template <int Dim = 3, class MoveSlot>
inline std::size_t scan_rows_scalar(const TouchScanInput& in, std::uint32_t r0, std::uint32_t r1,
                                    std::uint32_t* touching, std::uint32_t* rows, MoveSlot&& move_slot) {
  std::size_t nt = 0;
  for (std::uint32_t i = r0; i < r1; ++i) {
    const double* const xi = in.x + Dim * static_cast<std::size_t>(i);
    const double ri = in.radius[i];
    for (std::uint32_t e = in.row_begin[i]; e < in.row_begin[i + 1]; ++e) {
      const std::uint32_t j = in.nbr[e];
      const double* const xj = in.x + Dim * static_cast<std::size_t>(j);
      const double dx = xi[0] - xj[0], dy = xi[1] - xj[1];
      const double rs = in.reach != nullptr ? in.reach[e] : ri + in.radius[j];
      double d2;
      if constexpr (Dim == 3) {
        const double dz = xi[2] - xj[2];
        d2 = dx * dx + (dy * dy + dz * dz);
      } else {
        d2 = dx * dx + dy * dy;
      }
      const bool touch = d2 < rs * rs;
      // Slots move only where the touch changed since the last step: a predictable branch.
      if (in.slot != nullptr && touch == (in.slot[e] == in.no_slot)) move_slot(e, touch);
      // Every entry is written at the count, which only a touching one advances.
      touching[nt] = e;
      rows[nt] = i;
      if (in.separation[0] != nullptr) {
        in.separation[0][nt] = dx;
        in.separation[1][nt] = dy;
        if constexpr (Dim == 3) in.separation[2][nt] = xi[2] - xj[2];
      }
      nt += touch;
    }
  }
  return nt;
}

namespace detail {

// What the stream scan needs of the instruction set, on packs of W entry indices: load them,
// number them, compare W doubles to a bit mask, and store the lanes of a bit mask packed
// together (compress).
#if defined(__AVX512F__) && defined(__AVX512VL__)
inline constexpr bool kStreamScan = lane_width == 8;
using IndexPack = __m256i;
inline IndexPack load_indices(const std::uint32_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
inline IndexPack index_run(std::uint32_t e) {
  return _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(e)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}
inline unsigned less_bits(const Lane& a, const Lane& b) {
  return _mm512_cmp_pd_mask(static_cast<__m512d>(a), static_cast<__m512d>(b), _CMP_LT_OQ);
}
/// Bit l: p[l] == v, for the first `count` lanes (no read past them).
inline unsigned equal_bits(const std::uint32_t* p, std::uint32_t count, std::uint32_t v) {
  const __mmask8 valid = static_cast<__mmask8>((1u << count) - 1u);
  const __m256i s = _mm256_maskz_loadu_epi32(valid, p);
  return _mm256_mask_cmpeq_epi32_mask(valid, s, _mm256_set1_epi32(static_cast<int>(v)));
}
inline void store_compressed(std::uint32_t* out, IndexPack v, unsigned bits) {
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_maskz_compress_epi32(static_cast<__mmask8>(bits), v));
}
// (Compress in a register, then a full store: the memory form is slow on Zen 4.)
inline void store_compressed(double* out, const Lane& v, unsigned bits) {
  _mm512_storeu_pd(out, _mm512_maskz_compress_pd(static_cast<__mmask8>(bits), static_cast<__m512d>(v)));
}
#elif defined(__AVX2__)
inline constexpr bool kStreamScan = lane_width == 4;
using IndexPack = __m128i;
inline IndexPack load_indices(const std::uint32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
inline IndexPack index_run(std::uint32_t e) {
  return _mm_add_epi32(_mm_set1_epi32(static_cast<int>(e)), _mm_setr_epi32(0, 1, 2, 3));
}
inline unsigned less_bits(const Lane& a, const Lane& b) {
  return static_cast<unsigned>(
      _mm256_movemask_pd(_mm256_cmp_pd(static_cast<__m256d>(a), static_cast<__m256d>(b), _CMP_LT_OQ)));
}
inline unsigned equal_bits(const std::uint32_t* p, std::uint32_t count, std::uint32_t v) {
  const __m128i s =
      count == 4 ? load_indices(p)
                 : _mm_maskload_epi32(reinterpret_cast<const int*>(p),
                                      _mm_cmpgt_epi32(_mm_set1_epi32(static_cast<int>(count)), _mm_setr_epi32(0, 1, 2, 3)));
  const __m128i eq = _mm_cmpeq_epi32(s, _mm_set1_epi32(static_cast<int>(v)));
  return static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(eq))) & ((1u << count) - 1u);
}
// AVX2 has no compress: for each 4-bit mask, the lanes to move to the front (a table of 256 B).
struct CompressOrder {
  alignas(16) std::int32_t lane[16][4];
};
inline constexpr CompressOrder kCompressOrder = [] {
  CompressOrder t{};
  for (unsigned m = 0; m < 16; ++m) {
    unsigned k = 0;
    for (unsigned l = 0; l < 4; ++l)
      if (((m >> l) & 1u) != 0) t.lane[m][k++] = static_cast<std::int32_t>(l);
  }
  return t;
}();
inline void store_compressed(std::uint32_t* out, IndexPack v, unsigned bits) {
  const __m128i order = _mm_load_si128(reinterpret_cast<const __m128i*>(kCompressOrder.lane[bits]));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_castps_si128(_mm_permutevar_ps(_mm_castsi128_ps(v), order)));
}
// Doubles: the same order as pairs of 32-bit lanes (2l, 2l + 1) (a table of 512 B).
struct CompressOrder64 {
  alignas(32) std::int32_t lane[16][8];
};
inline constexpr CompressOrder64 kCompressOrder64 = [] {
  CompressOrder64 t{};
  for (unsigned m = 0; m < 16; ++m)
    for (unsigned k = 0; k < 4; ++k) {
      t.lane[m][2 * k] = 2 * kCompressOrder.lane[m][k];
      t.lane[m][2 * k + 1] = 2 * kCompressOrder.lane[m][k] + 1;
    }
  return t;
}();
inline void store_compressed(double* out, const Lane& v, unsigned bits) {
  const __m256i order = _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompressOrder64.lane[bits]));
  _mm256_storeu_pd(out, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(static_cast<__m256d>(v)), order)));
}
#else
inline constexpr bool kStreamScan = false;
#endif

}  // namespace detail

inline constexpr bool kPackedTouchScan = detail::kStreamScan;

/// As scan_rows_scalar, W entries at a time where the machine has AVX2 or AVX-512. `touching`,
/// `rows` and the separation arrays need room for all entries of the rows plus 8.
template <int Dim = 3, class MoveSlot>
inline std::size_t scan_rows(const TouchScanInput& in, std::uint32_t r0, std::uint32_t r1,
                             std::uint32_t* touching, std::uint32_t* rows, MoveSlot&& move_slot) {
#if defined(__AVX2__) || defined(__AVX512F__)
  if constexpr (kPackedTouchScan) {
    constexpr std::uint32_t W = lane_width;
    const std::uint32_t e0 = in.row_begin[r0], e1 = in.row_begin[r1];
    if (e0 == e1) return 0;
    // The row of every entry, unless the caller has them (TouchScanInput::entry_row): 8 at a
    // time (a row's last store runs into the next row's part, which that row's stores then
    // overwrite). Every row stores its first 8 even when it is empty (the next row, starting at
    // the same entry, overwrites them; the last ones fall in the 8 entries of room): whether a
    // row is empty is an unpredictable branch in a sparse bed (2D disks: 2.4 entries per row),
    // which cost 2-3 % of a step.
    for (std::uint32_t i = r0; in.entry_row == nullptr && i < r1; ++i) {
      const __m256i row = _mm256_set1_epi32(static_cast<int>(i));
      const std::uint32_t b = in.row_begin[i], end = in.row_begin[i + 1];
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(rows + (b - e0)), row);
      for (std::uint32_t e = b + 8; e < end; e += 8)
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(rows + (e - e0)), row);
    }
    std::size_t nt = 0;
    // Without entry_row the output is written over the row list: block b's output ends at or
    // before its own input's end, and the blocks after it read only beyond that.
    for (std::uint32_t e = e0; e < e1; e += W) {
      const std::uint32_t count = e1 - e < W ? e1 - e : W;
      const unsigned valid = (1u << count) - 1u;
      const std::uint32_t* ip = in.entry_row != nullptr ? in.entry_row + e : rows + (e - e0);
      const std::uint32_t* jp = in.nbr + e;
      // The layer's last block: its lanes past the end repeat its last entry.
      std::uint32_t i_tail[W], j_tail[W];
      if (count < W) {
        for (std::uint32_t l = 0; l < W; ++l) {
          i_tail[l] = ip[l < count ? l : count - 1];
          j_tail[l] = jp[l < count ? l : count - 1];
        }
        ip = i_tail;
        jp = j_tail;
      }
      const double* rec_i[W];
      const double* rec_j[W];
      for (std::uint32_t l = 0; l < W; ++l) {
        rec_i[l] = in.x + Dim * static_cast<std::size_t>(ip[l]);
        rec_j[l] = in.x + Dim * static_cast<std::size_t>(jp[l]);
      }
      Lane xi[Dim], xj[Dim];
      transpose_in<Dim>(rec_i, xi);
      transpose_in<Dim>(rec_j, xj);
      // (The lanes of the layer's last block past its end read the room after the last entry;
      // `valid` drops them.)
      const Lane rs = in.reach != nullptr ? Lane(in.reach + e, stdx::element_aligned)
                                          : gather_lanes<GatherBy::registers>(in.radius, ip) +
                                                gather_lanes<GatherBy::registers>(in.radius, jp);
      const detail::IndexPack iv = detail::load_indices(ip);
      const Lane dx = xi[0] - xj[0], dy = xi[1] - xj[1];
      Lane d2, dz = 0.0;
      if constexpr (Dim == 3) {
        dz = xi[2] - xj[2];
        d2 = dx * dx + (dy * dy + dz * dz);
      } else {
        d2 = dx * dx + dy * dy;
      }
      const unsigned touch = detail::less_bits(d2, rs * rs) & valid;
      if (in.separation[0] != nullptr) {
        detail::store_compressed(in.separation[0] + nt, dx, touch);
        detail::store_compressed(in.separation[1] + nt, dy, touch);
        if constexpr (Dim == 3) detail::store_compressed(in.separation[2] + nt, dz, touch);
      }
      if (in.slot != nullptr) {
        const unsigned none = detail::equal_bits(in.slot + e, count, in.no_slot);
        // A lane's slot moves where touch == none (touching without one, or apart with one).
        for (unsigned change = ~(touch ^ none) & valid; change != 0; change &= change - 1) {
          const unsigned l = static_cast<unsigned>(std::countr_zero(change));
          move_slot(e + l, ((touch >> l) & 1u) != 0);
        }
      }
      detail::store_compressed(touching + nt, detail::index_run(e), touch);
      detail::store_compressed(rows + nt, iv, touch);
      nt += static_cast<std::size_t>(std::popcount(touch));
    }
    return nt;
  }
#endif
  return scan_rows_scalar<Dim>(in, r0, r1, touching, rows, static_cast<MoveSlot&&>(move_slot));
}

}  // namespace granule::contact
