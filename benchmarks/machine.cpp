// Machine ceilings for the roofline estimate in docs/performance.md: clock rate, scalar and
// AVX-512 FMA throughput, scalar sqrt and division throughput, and a STREAM-like triad bandwidth.
// Apart from gather/transpose_vec3 nothing of granule is timed here; these numbers put the
// contact-kernel timings in proportion.
//
//   clock/dependent_add     a chain of dependent integer adds (1 cycle each on x86-64 cores
//                           since the Pentium Pro): items_per_second = core clock [Hz]
//   flops/scalar_fma        8 independent chains of scalar vfmadd231sd (2 flops each)
//   flops/avx512_fma        12 independent chains of 512-bit FMAs (16 flops each), if compiled
//                           with AVX-512 (GRANULE_NATIVE on an AVX-512 machine)
//   latency/sqrt_throughput 8 independent scalar square roots per round: items = sqrt/s
//   latency/div_throughput  8 independent scalar divisions (by 3.0) per round: items = div/s
//   latency/avx_sqrt_throughput, latency/avx_div_throughput
//                           the same with 256-bit vectors (4 doubles; AVX builds): items =
//                           doubles/s -- the packed contact law's square roots and divisions
//                           on an AVX2 machine (the width of its packs there)
//   stream/triad            a[i] = b[i] + s c[i] over 3 x 32 MiB (above every cache level),
//                           bytes_per_second counts 24 B per element (STREAM convention,
//                           McCalpin 1995; write-allocate traffic not counted); 1 thread
//                           timed by CPU time, 2 threads by wall time
//   gather/avx512_gather    8 doubles gathered by one vgatherdpd from random particles of a
//                           480 KB array of 3-vectors (the partner data of a packed pair loop
//                           in a layer's working set); items = gathered doubles/s
//   gather/scalar_copy      the same doubles loaded one at a time and stored into a chunk, as
//                           the packed pair loop did until 2026-12-03 (and still does for radii
//                           and inverse masses)
//   gather/transpose_vec3   all 3 doubles of each 3-vector into packs by masked loads and
//                           transposes (core/lane_transpose.hpp, what the packed pair loop does
//                           now); items = doubles/s. Through a buffer where the build has
//                           neither AVX2 nor AVX-512.
#include <benchmark/benchmark.h>

#include <granule/core/lane_transpose.hpp>

#include <cstdint>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif
#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace {

void bm_dependent_add(benchmark::State& st) {
  constexpr std::int64_t kAdds = 1 << 20;
  for (auto _ : st) {
    std::uint64_t x = 0;
    for (std::int64_t i = 0; i < kAdds; i += 8) {
#if defined(__x86_64__)
      asm volatile(
          "add $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\t"
          "add $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\tadd $1, %0"
          : "+r"(x));
#else
      for (int k = 0; k < 8; ++k) {
        x += 1;
        benchmark::DoNotOptimize(x);
      }
#endif
    }
    benchmark::DoNotOptimize(x);
  }
  st.SetItemsProcessed(st.iterations() * kAdds);
}

#if defined(__x86_64__)
void bm_scalar_fma(benchmark::State& st) {
  constexpr std::int64_t kRounds = 1 << 16;
  double a0 = 1, a1 = 1, a2 = 1, a3 = 1, a4 = 1, a5 = 1, a6 = 1, a7 = 1;
  const double b = 0.999999, c = 1e-7;
  for (auto _ : st) {
    for (std::int64_t i = 0; i < kRounds; ++i) {
      asm volatile(
          "vfmadd231sd %9, %8, %0\n\tvfmadd231sd %9, %8, %1\n\t"
          "vfmadd231sd %9, %8, %2\n\tvfmadd231sd %9, %8, %3\n\t"
          "vfmadd231sd %9, %8, %4\n\tvfmadd231sd %9, %8, %5\n\t"
          "vfmadd231sd %9, %8, %6\n\tvfmadd231sd %9, %8, %7"
          : "+x"(a0), "+x"(a1), "+x"(a2), "+x"(a3), "+x"(a4), "+x"(a5), "+x"(a6), "+x"(a7)
          : "x"(b), "x"(c));
    }
  }
  benchmark::DoNotOptimize(a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7);
  st.SetItemsProcessed(st.iterations() * kRounds * 8 * 2);  // flops
}

void bm_sqrt(benchmark::State& st) {
  constexpr std::int64_t kRounds = 1 << 14;
  double x0 = 2, x1 = 3, x2 = 5, x3 = 7, x4 = 11, x5 = 13, x6 = 17, x7 = 19;
  for (auto _ : st) {
    for (std::int64_t i = 0; i < kRounds; ++i) {
      double y0, y1, y2, y3, y4, y5, y6, y7;
      asm volatile(
          "vsqrtsd %8, %8, %0\n\tvsqrtsd %9, %9, %1\n\tvsqrtsd %10, %10, %2\n\t"
          "vsqrtsd %11, %11, %3\n\tvsqrtsd %12, %12, %4\n\tvsqrtsd %13, %13, %5\n\t"
          "vsqrtsd %14, %14, %6\n\tvsqrtsd %15, %15, %7"
          : "=&x"(y0), "=&x"(y1), "=&x"(y2), "=&x"(y3), "=&x"(y4), "=&x"(y5), "=&x"(y6), "=&x"(y7)
          : "x"(x0), "x"(x1), "x"(x2), "x"(x3), "x"(x4), "x"(x5), "x"(x6), "x"(x7));
      benchmark::DoNotOptimize(y0 + y1 + y2 + y3 + y4 + y5 + y6 + y7);
    }
  }
  st.SetItemsProcessed(st.iterations() * kRounds * 8);
}

void bm_div(benchmark::State& st) {
  constexpr std::int64_t kRounds = 1 << 14;
  double x0 = 2, x1 = 3, x2 = 5, x3 = 7, x4 = 11, x5 = 13, x6 = 17, x7 = 19;
  const double den = 3.0;
  for (auto _ : st) {
    for (std::int64_t i = 0; i < kRounds; ++i) {
      double y0, y1, y2, y3, y4, y5, y6, y7;
      asm volatile(
          "vdivsd %16, %8, %0\n\tvdivsd %16, %9, %1\n\tvdivsd %16, %10, %2\n\t"
          "vdivsd %16, %11, %3\n\tvdivsd %16, %12, %4\n\tvdivsd %16, %13, %5\n\t"
          "vdivsd %16, %14, %6\n\tvdivsd %16, %15, %7"
          : "=&x"(y0), "=&x"(y1), "=&x"(y2), "=&x"(y3), "=&x"(y4), "=&x"(y5), "=&x"(y6), "=&x"(y7)
          : "x"(x0), "x"(x1), "x"(x2), "x"(x3), "x"(x4), "x"(x5), "x"(x6), "x"(x7), "m"(den));
      benchmark::DoNotOptimize(y0 + y1 + y2 + y3 + y4 + y5 + y6 + y7);
    }
  }
  st.SetItemsProcessed(st.iterations() * kRounds * 8);
}
#endif

#if defined(__AVX__)
// Eight 256-bit operations per round on inputs the compiler cannot see through (so it can
// neither hoist nor drop them) and results it must keep: independent, so this is throughput.
template <class Op>
void avx_throughput(benchmark::State& st, Op op) {
  constexpr std::int64_t kRounds = 1 << 12;
  __m256d x[8];
  for (int k = 0; k < 8; ++k) x[k] = _mm256_set1_pd(2.0 + k);
  const __m256d den = _mm256_set1_pd(3.0);
  for (auto _ : st) {
    for (std::int64_t i = 0; i < kRounds; ++i) {
      for (auto& a : x) {
        asm volatile("" : "+x"(a));
        __m256d y = op(a, den);
        asm volatile("" : : "x"(y));
      }
    }
  }
  st.SetItemsProcessed(st.iterations() * kRounds * 8 * 4);
}

void bm_avx_sqrt(benchmark::State& st) {
  avx_throughput(st, [](__m256d a, __m256d) { return _mm256_sqrt_pd(a); });
}

void bm_avx_div(benchmark::State& st) {
  avx_throughput(st, [](__m256d a, __m256d d) { return _mm256_div_pd(a, d); });
}
#endif

#if defined(__AVX512F__)
void bm_avx512_fma(benchmark::State& st) {
  constexpr std::int64_t kRounds = 1 << 14;
  __m512d acc[12];
  for (auto& a : acc) a = _mm512_set1_pd(1.0);
  const __m512d b = _mm512_set1_pd(0.999999), c = _mm512_set1_pd(1e-7);
  for (auto _ : st) {
    for (std::int64_t i = 0; i < kRounds; ++i) {
      for (auto& a : acc) {
        a = _mm512_fmadd_pd(a, b, c);
        asm volatile("" : "+v"(a));
      }
    }
  }
  alignas(64) double lanes[8];
  double sum = 0.0;
  for (auto& a : acc) {
    _mm512_store_pd(lanes, a);
    for (double l : lanes) sum += l;
  }
  benchmark::DoNotOptimize(sum);
  st.SetItemsProcessed(st.iterations() * kRounds * 12 * 16);  // flops
}
#endif

void bm_triad(benchmark::State& st) {
  const std::size_t n = std::size_t(32) << 17;  // 4 Mi doubles = 32 MiB per array
#ifdef _OPENMP
  omp_set_num_threads(static_cast<int>(st.range(0)));
#endif
  std::vector<double> a(n), b(n, 1.0), c(n, 2.0);
  // First touch by the threads that use the data.
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) a[i] = 0.0;
  const double s = 3.0;
  for (auto _ : st) {
    double* pa = a.data();
    const double* pb = b.data();
    const double* pc = c.data();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    benchmark::ClobberMemory();
  }
  benchmark::DoNotOptimize(a[n / 2]);
  st.SetBytesProcessed(static_cast<std::int64_t>(st.iterations()) * static_cast<std::int64_t>(n * 24));
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
}

// Random particle indices (times 3: 3-vectors) into a 20 000-particle array, 2 x 3 doubles each.
struct GatherData {
  std::vector<double> a;
  std::vector<std::int32_t> idx;
  GatherData() : a(3 * 20000, 1.0), idx(1 << 14) {
    std::uint64_t r = 12345;
    for (auto& i : idx) {
      r = r * 6364136223846793005ULL + 1442695040888963407ULL;  // (Knuth's MMIX LCG)
      i = static_cast<std::int32_t>((r >> 33) % 20000) * 3;
    }
  }
};

#if defined(__AVX512F__)
void bm_avx512_gather(benchmark::State& st) {
  const GatherData d;
  __m512d s0 = _mm512_setzero_pd(), s1 = _mm512_setzero_pd();
  for (auto _ : st) {
    for (std::size_t q = 0; q < d.idx.size(); q += 8) {
      const __m256i vi = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&d.idx[q]));
      // (The masked form with a zero source: the plain intrinsic trips GCC 12's
      // -Wmaybe-uninitialized on its internal source operand.)
      s0 = _mm512_add_pd(s0, _mm512_mask_i32gather_pd(_mm512_setzero_pd(), 0xff, vi, d.a.data(), 8));
      s1 = _mm512_add_pd(s1, _mm512_mask_i32gather_pd(_mm512_setzero_pd(), 0xff, vi, d.a.data() + 1, 8));
    }
  }
  benchmark::DoNotOptimize(s0);
  benchmark::DoNotOptimize(s1);
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(2 * d.idx.size()));
}
#endif

void bm_scalar_copy(benchmark::State& st) {
  const GatherData d;
  alignas(64) double chunk[2][64] = {};
  for (auto _ : st) {
    for (std::size_t q = 0; q < d.idx.size(); ++q) {
      chunk[0][q % 64] = d.a[d.idx[q]];
      chunk[1][q % 64] = d.a[d.idx[q] + 1];
    }
    benchmark::DoNotOptimize(chunk);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(2 * d.idx.size()));
}

void bm_transpose_vec3(benchmark::State& st) {
  const GatherData d;
  std::vector<std::uint32_t> particle(d.idx.size());
  for (std::size_t q = 0; q < d.idx.size(); ++q) particle[q] = static_cast<std::uint32_t>(d.idx[q] / 3);
  granule::LaneVec3 s{granule::Lane(0.0), granule::Lane(0.0), granule::Lane(0.0)};
  for (auto _ : st) {
    for (std::size_t q = 0; q + granule::lane_width <= particle.size(); q += granule::lane_width)
      s += granule::gather_vec3_lanes(d.a.data(), &particle[q]);
  }
  benchmark::DoNotOptimize(s.x[0] + s.y[0] + s.z[0]);
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(3 * particle.size()));
  st.counters["lanes"] = static_cast<double>(granule::lane_width);
}

BENCHMARK(bm_dependent_add)->Name("clock/dependent_add");
#if defined(__x86_64__)
BENCHMARK(bm_scalar_fma)->Name("flops/scalar_fma");
BENCHMARK(bm_sqrt)->Name("latency/sqrt_throughput");
BENCHMARK(bm_div)->Name("latency/div_throughput");
#endif
#if defined(__AVX__)
BENCHMARK(bm_avx_sqrt)->Name("latency/avx_sqrt_throughput");
BENCHMARK(bm_avx_div)->Name("latency/avx_div_throughput");
#endif
#if defined(__AVX512F__)
BENCHMARK(bm_avx512_fma)->Name("flops/avx512_fma");
BENCHMARK(bm_avx512_gather)->Name("gather/avx512_gather");
#endif
BENCHMARK(bm_scalar_copy)->Name("gather/scalar_copy");
BENCHMARK(bm_transpose_vec3)->Name("gather/transpose_vec3");
// One thread: CPU time (robust to other load on the machine); two threads: wall time.
BENCHMARK(bm_triad)->Name("stream/triad")->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(bm_triad)->Name("stream/triad")->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
