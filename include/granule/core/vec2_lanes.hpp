#pragma once
// Packs over arrays of 2-vectors, for the 2D engine's per-particle passes (the kicks and the
// drift, simulation/integrate.hpp): W particles at a time, their 2-vectors (positions,
// velocities, forces) as two packs in memory order -- pack 0 holds x0 y0 x1 y1 ... of the first
// W/2 particles, pack 1 those of the others -- and their scalars (inverse masses, the angular
// velocity about z) as one pack. A particle's scalar is spread to both lanes of its vector, so
// that every lane computes what the one-particle code computes for that component: the results
// are those of the scalar loop, bit for bit.
// Used only with AVX2 or AVX-512 (kVec2Lanes), where the spread is one permutation; elsewhere
// the passes stay one particle at a time (the generic forms below only keep that code compiling).
#include <cstddef>
#include <cstdint>

#if defined(__AVX2__) || defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "granule/core/lanes.hpp"

namespace granule {

#if defined(__AVX512F__)
inline constexpr bool kVec2Lanes = lane_width == 8;
#elif defined(__AVX2__)
inline constexpr bool kVec2Lanes = lane_width == 4;
#else
inline constexpr bool kVec2Lanes = false;
#endif

namespace vec2_lanes {

#if defined(__AVX512F__)
/// Lanes (s0 s0 s1 s1 ...) of the first half of s (Half 0) or of the second (Half 1).
template <int Half>
inline Lane spread(const Lane& s) {
  const __m512i idx = Half == 0 ? _mm512_setr_epi64(0, 0, 1, 1, 2, 2, 3, 3) : _mm512_setr_epi64(4, 4, 5, 5, 6, 6, 7, 7);
  return Lane(_mm512_permutexvar_pd(idx, static_cast<__m512d>(s)));
}
/// Lanes (a1 a0 a3 a2 ...): each vector's y where its x is, and x where y is.
inline Lane swap_pairs(const Lane& a) { return Lane(_mm512_permute_pd(static_cast<__m512d>(a), 0x55)); }
/// a with its odd lanes (the y of each vector) set to zero.
inline Lane even_lanes(const Lane& a) { return Lane(_mm512_maskz_mov_pd(0x55, static_cast<__m512d>(a))); }
/// W floats, widened.
inline Lane load_floats(const float* p) { return Lane(_mm512_cvtps_pd(_mm256_loadu_ps(p))); }
#elif defined(__AVX2__)
template <int Half>
inline Lane spread(const Lane& s) {
  return Lane(_mm256_permute4x64_pd(static_cast<__m256d>(s), Half == 0 ? 0x50 : 0xFA));
}
inline Lane swap_pairs(const Lane& a) { return Lane(_mm256_permute_pd(static_cast<__m256d>(a), 0x5)); }
inline Lane even_lanes(const Lane& a) {
  return Lane(_mm256_blend_pd(static_cast<__m256d>(a), _mm256_setzero_pd(), 0xA));
}
inline Lane load_floats(const float* p) { return Lane(_mm256_cvtps_pd(_mm_loadu_ps(p))); }
#else
template <int Half>
inline Lane spread(const Lane& s) {
  return Lane([&](auto l) { return s[Half * lane_width / 2 + l / 2]; });
}
inline Lane swap_pairs(const Lane& a) { return Lane([&](auto l) { return a[l ^ 1]; }); }
inline Lane even_lanes(const Lane& a) { return Lane([&](auto l) { return l % 2 == 0 ? a[l] : 0.0; }); }
inline Lane load_floats(const float* p) { return Lane([&](auto l) { return static_cast<double>(p[l]); }); }
#endif

}  // namespace vec2_lanes

}  // namespace granule
