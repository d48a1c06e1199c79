#pragma once
// Pass 1 of the packed pair loop (contact/packed.hpp) for one cell layer of the neighbour list:
// which entries touch (|x_i - x_j| < r_i + r_j), listed in entry order with their rows, and
// which entries' history slots must move (a pair that starts touching takes one, one that
// separates gives it back).
//
// With AVX-512 the layer's entries are scanned 8 at a time as one stream, across row ends: the
// rows are first written out per entry, then each block of 8 reads both particles' positions
// through the lane transposes (core/lane_transpose.hpp), and the touching entries are packed
// together with one compress instruction. (Scanning row by row, 8 lanes for rows of 3 to 4
// entries in scene B, was 5 % slower than one entry at a time.) Elsewhere one entry at a time.
// Both sum the squared distance as x*x + (y*y + z*z), the order of Eigen's squaredNorm; a pair
// touching to within a rounding error may still come out differently where the compiler fuses
// multiply-adds differently in the two.
#include <bit>
#include <cstddef>
#include <cstdint>

#include "granule/core/lane_transpose.hpp"
#include "granule/core/lanes.hpp"

namespace granule::contact {

/// What a scan reads: 3-vector positions and radii by particle slot, the list's rows and
/// partners, and its history slots (nullptr for a model without history).
struct TouchScanInput {
  const double* x;
  const double* radius;
  const std::uint32_t* row_begin;
  const std::uint32_t* nbr;
  const std::uint32_t* slot;
  std::uint32_t no_slot;  ///< the slot value of an entry without history (PairList::kNone)
};

/// One entry at a time: lists the touching entries of rows [r0, r1) in `touching` (entry
/// index) and `rows` (its row) and returns their number; calls `move_slot(e, touch)` in entry
/// order for each entry whose history slot must change.
template <class MoveSlot>
inline std::size_t scan_rows_scalar(const TouchScanInput& in, std::uint32_t r0, std::uint32_t r1,
                                    std::uint32_t* touching, std::uint32_t* rows, MoveSlot&& move_slot) {
  std::size_t nt = 0;
  for (std::uint32_t i = r0; i < r1; ++i) {
    const double* const xi = in.x + 3 * static_cast<std::size_t>(i);
    const double ri = in.radius[i];
    for (std::uint32_t e = in.row_begin[i]; e < in.row_begin[i + 1]; ++e) {
      const std::uint32_t j = in.nbr[e];
      const double* const xj = in.x + 3 * static_cast<std::size_t>(j);
      const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
      const double rs = ri + in.radius[j];
      const bool touch = dx * dx + (dy * dy + dz * dz) < rs * rs;
      // Slots move only where the touch changed since the last step: a predictable branch.
      if (in.slot != nullptr && touch == (in.slot[e] == in.no_slot)) move_slot(e, touch);
      // Every entry is written at the count, which only a touching one advances.
      touching[nt] = e;
      rows[nt] = i;
      nt += touch;
    }
  }
  return nt;
}

#if defined(__AVX512F__) && defined(__AVX512VL__)
inline constexpr bool kPackedTouchScan = lane_width == 8;
#else
inline constexpr bool kPackedTouchScan = false;
#endif

/// As scan_rows_scalar, 8 entries at a time where the machine has AVX-512. `touching` and
/// `rows` need room for all entries of the rows plus 8.
template <class MoveSlot>
inline std::size_t scan_rows(const TouchScanInput& in, std::uint32_t r0, std::uint32_t r1,
                             std::uint32_t* touching, std::uint32_t* rows, MoveSlot&& move_slot) {
#if defined(__AVX512F__) && defined(__AVX512VL__)
  if constexpr (kPackedTouchScan) {
    const std::uint32_t e0 = in.row_begin[r0], e1 = in.row_begin[r1];
    if (e0 == e1) return 0;
    // The row of every entry, 8 at a time (a row's last store runs into the next row's part,
    // which that row's stores then overwrite).
    for (std::uint32_t i = r0; i < r1; ++i) {
      const __m256i row = _mm256_set1_epi32(static_cast<int>(i));
      for (std::uint32_t e = in.row_begin[i]; e < in.row_begin[i + 1]; e += 8)
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(rows + (e - e0)), row);
    }
    const __m256i lane_index = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    std::size_t nt = 0;
    // The output is written over the row list: block b's output ends at or before its own
    // input's end, and the blocks after it read only beyond that.
    for (std::uint32_t e = e0; e < e1; e += 8) {
      const std::uint32_t count = e1 - e < 8 ? e1 - e : 8;
      const __mmask8 valid = static_cast<__mmask8>((1u << count) - 1u);
      const std::uint32_t* ip = rows + (e - e0);
      const std::uint32_t* jp = in.nbr + e;
      // The layer's last block: its lanes past the end repeat its last entry.
      std::uint32_t i_tail[8], j_tail[8];
      if (count < 8) {
        for (std::uint32_t l = 0; l < 8; ++l) {
          i_tail[l] = ip[l < count ? l : count - 1];
          j_tail[l] = jp[l < count ? l : count - 1];
        }
        ip = i_tail;
        jp = j_tail;
      }
      const double* rec_i[8];
      const double* rec_j[8];
      for (std::uint32_t l = 0; l < 8; ++l) {
        rec_i[l] = in.x + 3 * static_cast<std::size_t>(ip[l]);
        rec_j[l] = in.x + 3 * static_cast<std::size_t>(jp[l]);
      }
      Lane xi[3], xj[3];
      transpose_in<3>(rec_i, xi);
      transpose_in<3>(rec_j, xj);
      const Lane rs =
          gather_lanes<GatherBy::registers>(in.radius, ip) + gather_lanes<GatherBy::registers>(in.radius, jp);
      const __m256i iv = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ip));
      const Lane dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
      const Lane d2 = dx * dx + (dy * dy + dz * dz);
      const __mmask8 touch =
          _mm512_cmp_pd_mask(static_cast<__m512d>(d2), static_cast<__m512d>(rs * rs), _CMP_LT_OQ) & valid;
      if (in.slot != nullptr) {
        const __m256i s = _mm256_maskz_loadu_epi32(valid, in.slot + e);
        const __mmask8 none =
            _mm256_mask_cmpeq_epi32_mask(valid, s, _mm256_set1_epi32(static_cast<int>(in.no_slot)));
        // A lane's slot moves where touch == none (touching without one, or apart with one).
        for (unsigned change = static_cast<unsigned>(~(touch ^ none)) & valid; change != 0; change &= change - 1) {
          const unsigned l = static_cast<unsigned>(std::countr_zero(change));
          move_slot(e + l, ((touch >> l) & 1u) != 0);
        }
      }
      const __m256i entries = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(e)), lane_index);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(touching + nt), _mm256_maskz_compress_epi32(touch, entries));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(rows + nt), _mm256_maskz_compress_epi32(touch, iv));
      nt += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(touch)));
    }
    return nt;
  }
#endif
  return scan_rows_scalar(in, r0, r1, touching, rows, static_cast<MoveSlot&&>(move_slot));
}

}  // namespace granule::contact
