#pragma once
// Seeded pseudo-random numbers that are identical on every platform and standard library:
// xoshiro256** 1.0 (Blackman & Vigna, "Scrambled linear pseudorandom number generators",
// ACM TOMS 47(4), 2021), seeded by four outputs of splitmix64 (Steele, Lea & Flood,
// OOPSLA 2014), as the xoshiro authors recommend. Written here rather than taken from
// <random> because the std distributions are implementation-defined.
//   next:     result = rotl(s1 * 5, 7) * 9;  t = s1 << 17;  s2 ^= s0; s3 ^= s1; s1 ^= s2;
//             s0 ^= s3; s2 ^= t; s3 = rotl(s3, 45)
//   uniform:  (next >> 11) * 2^-53, in [0, 1) with 53 random bits
//   normal:   Box & Muller (1958): r = sqrt(-2 ln u1), z0 = r cos(2 pi u2), z1 = r sin(2 pi u2),
//             u1 = 1 - uniform() in (0, 1]; z1 is kept for the next call.
// The integer and uniform streams are bit-identical everywhere. Normal deviates go through
// std::log, std::cos and std::sin, which IEEE 754 does not require to be correctly rounded;
// common libms (glibc, musl, MSVC) agree to the last bit in practice but this is not a
// guarantee. The full state (including a pending normal deviate) is a RandomState, six
// 64-bit words, so a checkpoint can store and restore it exactly.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "granule/core/error.hpp"

namespace granule::scene {

/// Generator state: s0..s3 of xoshiro256**, a flag (0/1) for a pending normal deviate, and
/// that deviate's bit pattern.
using RandomState = std::array<std::uint64_t, 6>;

/// One step of splitmix64: advances `state` and returns the next output.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  state += 0x9e3779b97f4a7c15ull;
  std::uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/// xoshiro256** with uniform and normal deviates; see the file comment.
class RandomGenerator {
 public:
  using result_type = std::uint64_t;

  explicit RandomGenerator(std::uint64_t seed = 0) { reseed(seed); }

  /// Restarts the sequence from `seed`.
  void reseed(std::uint64_t seed) {
    std::uint64_t sm = seed;
    for (auto& w : s_) w = splitmix64(sm);
    has_spare_ = false;
    spare_ = 0.0;
  }

  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }

  /// Next 64 random bits.
  result_type operator()() {
    const std::uint64_t result = std::rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = std::rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>((*this)() >> 11) * 0x1.0p-53; }
  /// Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }

  /// Uniform integer in [0, n), n >= 1, without modulo bias (rejection below 2^64 mod n).
  std::uint64_t below(std::uint64_t n) {
    require(n >= 1, "scene::RandomGenerator::below", "n", static_cast<double>(n), "[1, 2^64)");
    const std::uint64_t threshold = (0 - n) % n;
    while (true) {
      const std::uint64_t x = (*this)();
      if (x >= threshold) return x % n;
    }
  }

  /// Standard normal deviate (Box-Muller, second value cached).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double phi = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(phi);
    has_spare_ = true;
    return r * std::cos(phi);
  }
  /// Normal deviate with the given mean and standard deviation.
  double normal(double mean, double sd) { return mean + sd * normal(); }

  /// The complete state.
  RandomState state() const {
    return {s_[0], s_[1], s_[2], s_[3], has_spare_ ? 1ull : 0ull, std::bit_cast<std::uint64_t>(spare_)};
  }
  /// Restores a state returned by state(). The all-zero xoshiro state is refused.
  void set_state(const RandomState& st) {
    require(st[0] != 0 || st[1] != 0 || st[2] != 0 || st[3] != 0, "scene::RandomGenerator::set_state",
            "s0|s1|s2|s3", 0.0, "not all zero");
    require(st[4] <= 1, "scene::RandomGenerator::set_state", "pending-normal flag", static_cast<double>(st[4]),
            "{0, 1}");
    for (int k = 0; k < 4; ++k) s_[k] = st[k];
    has_spare_ = st[4] == 1;
    spare_ = std::bit_cast<double>(st[5]);
  }

 private:
  std::array<std::uint64_t, 4> s_{};
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace granule::scene
