#pragma once
// Transposes between W records of N doubles (one record per contact, wherever it lives) and
// N packs of W lanes (one pack per double): how the packed pair loop reads particle data and
// contact histories and writes the histories back.
//
// Record l is `rec[l]`: a particle's position (3 doubles, inside an array of 3-vectors) or a
// history in its pool. With AVX-512 (W = 8) or AVX2 (W = 4) the records are read four doubles
// at a time with one (masked) load each and transposed in registers: 8 loads and 12 shuffles
// per four doubles of 8 contacts, against 32 scalar loads and 32 scalar stores through a buffer,
// which is what the other widths (and this header without those instruction sets) still do.
// Masked loads and stores touch only the record's own doubles (no read past an array's end);
// with AVX2 a block of three doubles is read and written as two plus one instead.
// The lane order and the values are those of the buffer copy: results are bitwise identical.
#include <cstddef>
#include <cstdint>

#if defined(__AVX2__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "granule/core/lanes.hpp"

namespace granule {

namespace detail {

/// Through a buffer: any width, any N. out[k] lane l = rec[l][k].
template <std::size_t N>
inline void transpose_in_copy(const double* const* rec, Lane* out) {
  alignas(Lane) double lanes[N][lane_width];
  for (std::size_t l = 0; l < lane_width; ++l)
    for (std::size_t k = 0; k < N; ++k) lanes[k][l] = rec[l][k];
  for (std::size_t k = 0; k < N; ++k) out[k] = Lane(lanes[k], stdx::vector_aligned);
}

template <std::size_t N>
inline void transpose_out_copy(const Lane* in, double* const* rec, std::size_t valid) {
  alignas(Lane) double lanes[N][lane_width];
  for (std::size_t k = 0; k < N; ++k) in[k].copy_to(lanes[k], stdx::vector_aligned);
  for (std::size_t l = 0; l < valid; ++l)
    for (std::size_t k = 0; k < N; ++k) rec[l][k] = lanes[k][l];
}

#if defined(__AVX512F__) && defined(__AVX512VL__)
inline constexpr bool kTransposeInRegisters = lane_width == 8;

// (GCC 12's plain forms of these start from an undefined register and warn with
// -Wmaybe-uninitialized; the masked forms with an all-ones mask are the same instructions.)
inline __m512d unpacklo(__m512d a, __m512d b) { return _mm512_mask_unpacklo_pd(a, 0xFF, a, b); }
inline __m512d unpackhi(__m512d a, __m512d b) { return _mm512_mask_unpackhi_pd(a, 0xFF, a, b); }
/// (lo | hi)
inline __m512d pair(__m256d lo, __m256d hi) {
  const __m512d a = _mm512_castpd256_pd512(lo);  // upper half undefined until the insert
  return _mm512_mask_insertf64x4(a, 0xFF, a, hi, 1);
}
/// Half h (0: lower, 1: upper).
template <int h>
inline __m256d half(__m512d a) { return _mm512_mask_extractf64x4_pd(_mm256_setzero_pd(), 0xF, a, h); }
// Columns [c, c + m) of 8 records (m <= 4) -> out[0..m).
inline void transpose_in_block(const double* const* rec, std::size_t c, std::size_t m, Lane* out) {
  if (m == 2) {
    // Two columns (a 2D position or velocity): one 16-byte load per record, records 0 2 4 6
    // and 1 3 5 7 side by side, then one unpack per column (the masked 32-byte loads cost
    // 4 % of a 2D step).
    const auto two = [&](std::size_t l) { return _mm_loadu_pd(rec[l] + c); };
    const auto four = [&](std::size_t a) {  // (records a, a + 2, a + 4, a + 6)
      return pair(_mm256_set_m128d(two(a + 2), two(a)), _mm256_set_m128d(two(a + 6), two(a + 4)));
    };
    const __m512d even = four(0), odd = four(1);
    out[0] = Lane(unpacklo(even, odd));
    out[1] = Lane(unpackhi(even, odd));
    return;
  }
  const __mmask8 mask = static_cast<__mmask8>((1u << m) - 1u);
  __m256d r[8];
  for (std::size_t l = 0; l < 8; ++l) r[l] = _mm256_maskz_loadu_pd(mask, rec[l] + c);
  const __m512d z0 = pair(r[0], r[4]), z1 = pair(r[1], r[5]), z2 = pair(r[2], r[6]), z3 = pair(r[3], r[7]);
  // t0 = (r0.0 r1.0 r0.2 r1.2 | r4.0 r5.0 r4.2 r5.2), t1 the same with .1 and .3; t2, t3 for 2, 3, 6, 7.
  const __m512d t0 = unpacklo(z0, z1), t1 = unpackhi(z0, z1);
  const __m512d t2 = unpacklo(z2, z3), t3 = unpackhi(z2, z3);
  const __m512i even = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i odd = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
  out[0] = Lane(_mm512_permutex2var_pd(t0, even, t2));
  if (m > 1) out[1] = Lane(_mm512_permutex2var_pd(t1, even, t3));
  if (m > 2) out[2] = Lane(_mm512_permutex2var_pd(t0, odd, t2));
  if (m > 3) out[3] = Lane(_mm512_permutex2var_pd(t1, odd, t3));
}

// in[0..m) -> columns [c, c + m) of the first `valid` records (the inverse of the above).
inline void transpose_out_block(const Lane* in, double* const* rec, std::size_t c, std::size_t m,
                                std::size_t valid) {
  const __m512d zero = _mm512_setzero_pd();
  const __m512d row0 = static_cast<__m512d>(in[0]);
  const __m512d row1 = m > 1 ? static_cast<__m512d>(in[1]) : zero;
  const __m512d row2 = m > 2 ? static_cast<__m512d>(in[2]) : zero;
  const __m512d row3 = m > 3 ? static_cast<__m512d>(in[3]) : zero;
  const __m512i even = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i odd = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
  const __m512d t0 = _mm512_permutex2var_pd(row0, even, row2), t2 = _mm512_permutex2var_pd(row0, odd, row2);
  const __m512d t1 = _mm512_permutex2var_pd(row1, even, row3), t3 = _mm512_permutex2var_pd(row1, odd, row3);
  // z_k = (record k | record k + 4)
  const __m512d z[4] = {unpacklo(t0, t1), unpackhi(t0, t1), unpacklo(t2, t3), unpackhi(t2, t3)};
  const __mmask8 mask = static_cast<__mmask8>((1u << m) - 1u);
  for (std::size_t l = 0; l < valid; ++l) {
    const __m256d r = l < 4 ? half<0>(z[l]) : half<1>(z[l - 4]);
    if (m == 4) {
      _mm256_storeu_pd(rec[l] + c, r);
    } else {
      _mm256_mask_storeu_pd(rec[l] + c, mask, r);
    }
  }
}
#elif defined(__AVX2__)
inline constexpr bool kTransposeInRegisters = lane_width == 4;

inline __m256i avx2_mask(std::size_t m) {
  return _mm256_setr_epi64x(m > 0 ? -1 : 0, m > 1 ? -1 : 0, m > 2 ? -1 : 0, m > 3 ? -1 : 0);
}

// Three columns (a position, a velocity) are read as two plus one doubles per record, not with
// the masked load: scenes B and A 20k ran 1.5-3 % faster on a Zen 3 VM. The stores do the
// same (neutral on A 20k within the noise, +1 %).
inline void transpose_in_block(const double* const* rec, std::size_t c, std::size_t m, Lane* out) {
  if (m == 2) {  // (records 0 2 | 1 3, one unpack per column)
    const auto two = [&](std::size_t a, std::size_t b) {
      return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(rec[a] + c)), _mm_loadu_pd(rec[b] + c), 1);
    };
    const __m256d even = two(0, 2), odd = two(1, 3);
    out[0] = Lane(_mm256_unpacklo_pd(even, odd));
    out[1] = Lane(_mm256_unpackhi_pd(even, odd));
    return;
  }
  if (m == 3) {
    const auto two = [&](std::size_t a, std::size_t b) {  // (rec a 0 1 | rec b 0 1)
      return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(rec[a] + c)), _mm_loadu_pd(rec[b] + c), 1);
    };
    const auto third = [&](std::size_t a, std::size_t b) { return _mm_loadh_pd(_mm_load_sd(rec[a] + c + 2), rec[b] + c + 2); };
    const __m256d p02 = two(0, 2), p13 = two(1, 3);
    out[0] = Lane(_mm256_unpacklo_pd(p02, p13));
    out[1] = Lane(_mm256_unpackhi_pd(p02, p13));
    out[2] = Lane(_mm256_set_m128d(third(2, 3), third(0, 1)));
    return;
  }
  __m256d r[4];
  if (m == 4) {
    for (std::size_t l = 0; l < 4; ++l) r[l] = _mm256_loadu_pd(rec[l] + c);
  } else {
    const __m256i mask = avx2_mask(m);
    for (std::size_t l = 0; l < 4; ++l) r[l] = _mm256_maskload_pd(rec[l] + c, mask);
  }
  // t0 = (r0.0 r1.0 r0.2 r1.2), t1 = (r0.1 r1.1 r0.3 r1.3); t2, t3 the same for records 2, 3.
  const __m256d t0 = _mm256_unpacklo_pd(r[0], r[1]), t1 = _mm256_unpackhi_pd(r[0], r[1]);
  const __m256d t2 = _mm256_unpacklo_pd(r[2], r[3]), t3 = _mm256_unpackhi_pd(r[2], r[3]);
  out[0] = Lane(_mm256_permute2f128_pd(t0, t2, 0x20));
  if (m > 1) out[1] = Lane(_mm256_permute2f128_pd(t1, t3, 0x20));
  if (m > 2) out[2] = Lane(_mm256_permute2f128_pd(t0, t2, 0x31));
  if (m > 3) out[3] = Lane(_mm256_permute2f128_pd(t1, t3, 0x31));
}

inline void transpose_out_block(const Lane* in, double* const* rec, std::size_t c, std::size_t m,
                                std::size_t valid) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d row0 = static_cast<__m256d>(in[0]);
  const __m256d row1 = m > 1 ? static_cast<__m256d>(in[1]) : zero;
  const __m256d row2 = m > 2 ? static_cast<__m256d>(in[2]) : zero;
  const __m256d row3 = m > 3 ? static_cast<__m256d>(in[3]) : zero;
  const __m256d t0 = _mm256_permute2f128_pd(row0, row2, 0x20), t2 = _mm256_permute2f128_pd(row0, row2, 0x31);
  const __m256d t1 = _mm256_permute2f128_pd(row1, row3, 0x20), t3 = _mm256_permute2f128_pd(row1, row3, 0x31);
  const __m256d r[4] = {_mm256_unpacklo_pd(t0, t1), _mm256_unpackhi_pd(t0, t1),
                        _mm256_unpacklo_pd(t2, t3), _mm256_unpackhi_pd(t2, t3)};
  if (m == 4) {
    for (std::size_t l = 0; l < valid; ++l) _mm256_storeu_pd(rec[l] + c, r[l]);
  } else if (m == 3) {
    for (std::size_t l = 0; l < valid; ++l) {
      _mm_storeu_pd(rec[l] + c, _mm256_castpd256_pd128(r[l]));
      _mm_store_sd(rec[l] + c + 2, _mm256_extractf128_pd(r[l], 1));
    }
  } else {
    const __m256i mask = avx2_mask(m);
    for (std::size_t l = 0; l < valid; ++l) _mm256_maskstore_pd(rec[l] + c, mask, r[l]);
  }
}
#else
inline constexpr bool kTransposeInRegisters = false;
#endif

}  // namespace detail

/// out[k] lane l = rec[l][k] for k < N: W records of N doubles to N packs.
template <std::size_t N>
inline void transpose_in(const double* const* rec, Lane* out) {
#if defined(__AVX2__) || defined(__AVX512F__)
  if constexpr (detail::kTransposeInRegisters) {
    for (std::size_t c = 0; c < N; c += 4) detail::transpose_in_block(rec, c, N - c < 4 ? N - c : 4, out + c);
    return;
  }
#endif
  detail::transpose_in_copy<N>(rec, out);
}

/// rec[l][k] = in[k] lane l for k < N and the first `valid` records: N packs to W records.
template <std::size_t N>
inline void transpose_out(const Lane* in, double* const* rec, std::size_t valid) {
#if defined(__AVX2__) || defined(__AVX512F__)
  if constexpr (detail::kTransposeInRegisters) {
    for (std::size_t c = 0; c < N; c += 4)
      detail::transpose_out_block(in + c, rec, c, N - c < 4 ? N - c : 4, valid);
    return;
  }
#endif
  detail::transpose_out_copy<N>(in, rec, valid);
}

/// How gather_lanes fills a pack. The AVX-512 gather instruction was slower than both (7 % of
/// the touch scan; see also bench_machine's gather/*).
enum class GatherBy {
  /// 8 scalar stores and one vector load. The geometry pass of the packed pair loop was 1-2.5 %
  /// faster this way on scene B (twice measured, performance.md "Gathers of one double"),
  /// probably because it has fewer shuffle micro-ops beside the transposes' and the law's
  /// arithmetic hides the load's wait on the stores.
  buffer,
  /// With AVX-512, scalar loads straight into halves and quarters of the pack (other builds: as
  /// buffer). The touch scan compares at once and has nothing to hide the wait behind.
  registers,
};

/// Lane l = base[idx[l]]: one double per record (radii, inverse masses).
template <GatherBy By = GatherBy::buffer>
inline Lane gather_lanes(const double* base, const std::uint32_t* idx) {
#if defined(__AVX512F__) && defined(__AVX512VL__)
  if constexpr (By == GatherBy::registers && detail::kTransposeInRegisters) {
    const auto two = [&](int l) { return _mm_loadh_pd(_mm_load_sd(base + idx[l]), base + idx[l + 1]); };
    const __m256d lo = _mm256_set_m128d(two(2), two(0)), hi = _mm256_set_m128d(two(6), two(4));
    return Lane(detail::pair(lo, hi));
  }
#endif
  alignas(Lane) double lanes[lane_width];
  for (std::size_t l = 0; l < lane_width; ++l) lanes[l] = base[idx[l]];
  return Lane(lanes, stdx::vector_aligned);
}

/// Lanes of a 3-vector: lane l = the 3 doubles at base + 3 idx[l] (an array of 3-vectors).
inline LaneVec3 gather_vec3_lanes(const double* base, const std::uint32_t* idx) {
  const double* rec[lane_width];
  for (std::size_t l = 0; l < lane_width; ++l) rec[l] = base + 3 * static_cast<std::size_t>(idx[l]);
  Lane out[3];
  transpose_in<3>(rec, out);
  return {out[0], out[1], out[2]};
}

}  // namespace granule
