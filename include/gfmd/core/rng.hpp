// Portable pseudo-random numbers: xoshiro256** (Blackman & Vigna) seeded by SplitMix64.
//
// The output depends only on the seed, never on the platform, compiler or standard
// library: only 64-bit unsigned integer arithmetic (defined modulo 2^64) is used, and
// the conversion to a double in [0, 1) is our own, (next_u64() >> 11) * 2^-53, which is
// exact. std:: distributions are deliberately not used (their output is
// implementation-defined).
//
// Seeding: the four state words are four consecutive outputs of SplitMix64 started from
// the seed (state x = seed; each output: x += 0x9E3779B97F4A7C15, then the SplitMix64
// finaliser of x). SplitMix64 is a bijection of its counter, so the state is never all
// zero.
#pragma once

#include <array>
#include <cstdint>

namespace gfmd {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& w : s_) w = splitmix64(x);
  }

  // Next 64 random bits (xoshiro256**).
  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5u, 7) * 9u;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  // Uniform double in [0, 1) with 53 random bits: (next_u64() >> 11) * 2^-53.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

  // One SplitMix64 step: advances x and returns the mixed output (public so that tests
  // can check it against the reference values).
  static std::uint64_t splitmix64(std::uint64_t& x) {
    x += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = x;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

 private:
  static std::uint64_t rotl(std::uint64_t v, int k) { return (v << k) | (v >> (64 - k)); }
  std::array<std::uint64_t, 4> s_{};
};

}  // namespace gfmd
