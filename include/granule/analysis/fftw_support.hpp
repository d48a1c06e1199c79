#pragma once
// Thin RAII layer over FFTW3 (link with -lfftw3) for the analysis toolkit.
//
// FFTW's planner (fftw_plan_*, fftw_destroy_plan) is not thread-safe; fftw_execute_* on an
// existing plan is. Every plan here is created and destroyed under one process-wide mutex,
// always outside OpenMP regions, and uses FFTW_ESTIMATE (no timing runs, deterministic plans).
// Execution with other arrays goes through the new-array execute functions, which require the
// same sizes and alignment: FftwBuffer allocates with fftw_malloc, so all buffers qualify.
#include <fftw3.h>

#include <initializer_list>
#include <cstddef>
#include <mutex>
#include <new>
#include <utility>
#include <vector>

namespace granule::detail {

/// The one mutex that serialises FFTW planner calls in the process.
inline std::mutex& fftw_planner_mutex() {
  static std::mutex m;
  return m;
}

/// A buffer of T (double or fftw_complex) allocated with fftw_malloc (SIMD-aligned).
template <class T>
class FftwBuffer {
 public:
  FftwBuffer() = default;
  explicit FftwBuffer(std::size_t n) : size_(n) {
    data_ = static_cast<T*>(fftw_malloc(sizeof(T) * (n > 0 ? n : 1)));
    if (data_ == nullptr) throw std::bad_alloc();
  }
  FftwBuffer(const FftwBuffer&) = delete;
  FftwBuffer& operator=(const FftwBuffer&) = delete;
  FftwBuffer(FftwBuffer&& o) noexcept { swap(o); }
  FftwBuffer& operator=(FftwBuffer&& o) noexcept {
    swap(o);
    return *this;
  }
  ~FftwBuffer() {
    if (data_ != nullptr) fftw_free(data_);
  }
  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  void swap(FftwBuffer& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
  }
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

/// An FFTW plan whose creation and destruction hold the planner mutex.
class FftwPlan {
 public:
  FftwPlan() = default;
  FftwPlan(const FftwPlan&) = delete;
  FftwPlan& operator=(const FftwPlan&) = delete;
  FftwPlan(FftwPlan&& o) noexcept : plan_(std::exchange(o.plan_, nullptr)) {}
  FftwPlan& operator=(FftwPlan&& o) noexcept {
    std::swap(plan_, o.plan_);
    return *this;
  }
  ~FftwPlan() {
    if (plan_ != nullptr) {
      std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      fftw_destroy_plan(plan_);
    }
  }

  /// Real-to-complex plan of a rank-d array with row-major dimensions `dims` (last fastest).
  static FftwPlan r2c(const std::vector<int>& dims, double* in, fftw_complex* out) {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    return FftwPlan(fftw_plan_dft_r2c(static_cast<int>(dims.size()), dims.data(), in, out,
                                      FFTW_ESTIMATE));
  }
  /// Complex-to-real plan (unnormalised inverse of r2c). Destroys the input array's contents.
  static FftwPlan c2r(const std::vector<int>& dims, fftw_complex* in, double* out) {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    return FftwPlan(fftw_plan_dft_c2r(static_cast<int>(dims.size()), dims.data(), in, out,
                                      FFTW_ESTIMATE));
  }

  /// Executes a r2c plan on new arrays of the planned size (thread-safe).
  void execute_r2c(double* in, fftw_complex* out) const { fftw_execute_dft_r2c(plan_, in, out); }
  /// Executes a c2r plan on new arrays of the planned size (thread-safe).
  void execute_c2r(fftw_complex* in, double* out) const { fftw_execute_dft_c2r(plan_, in, out); }
  bool valid() const { return plan_ != nullptr; }

 private:
  explicit FftwPlan(fftw_plan p) : plan_(p) {
    if (plan_ == nullptr) throw std::bad_alloc();
  }
  fftw_plan plan_ = nullptr;
};

/// Smallest n' ≥ n whose prime factors are all in {2, 3, 5, 7} (fast FFTW sizes).
inline int fftw_good_size(int n) {
  if (n <= 1) return 1;
  for (int m = n;; ++m) {
    int r = m;
    for (int p : {2, 3, 5, 7}) {
      while (r % p == 0) r /= p;
    }
    if (r == 1) return m;
  }
}

}  // namespace granule::detail
