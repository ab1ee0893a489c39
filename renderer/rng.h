// Counter-based random numbers: every (seed, pixel, sample) triple owns an
// independent stream, so an image is bit-identical whatever the thread count
// or the order in which pixels are scheduled.
//
// The stream key is a 64-bit hash of the triple (SplitMix64 finaliser,
// Steele et al. 2014); draws are SplitMix64 outputs of key + k·γ, a
// Weyl sequence through a bijective mixer (passes BigCrush per Steele et al.).
#pragma once

#include <cstdint>

namespace furnace {

inline constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class Rng {
 public:
  Rng(uint64_t seed, uint64_t pixel, uint64_t sample) : state_(mix64(pixel_key(seed, pixel) + sample)) {}
  // The part of the stream key shared by every sample of a pixel, so a pixel's
  // loop hashes it once: for_sample(pixel_key(seed, pixel), s) is the stream
  // Rng(seed, pixel, s).
  static constexpr uint64_t pixel_key(uint64_t seed, uint64_t pixel) { return mix64(mix64(seed ^ kSeedSalt) ^ pixel); }
  static Rng for_sample(uint64_t pixel_key, uint64_t sample) { return Rng(mix64(pixel_key + sample)); }

  uint64_t next_u64() {
    state_ += kGamma;
    return mix64(state_);
  }
  // Uniform in [0, 1): the top 53 bits, so every value is exactly representable
  // and 1.0 is never returned.
  double next_double() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

 private:
  explicit Rng(uint64_t state) : state_(state) {}
  static constexpr uint64_t kGamma = 0x9e3779b97f4a7c15ULL;    // 2^64 / golden ratio, odd
  static constexpr uint64_t kSeedSalt = 0x5851f42d4c957f2dULL;  // keeps seed 0 away from state 0
  uint64_t state_;
};

}  // namespace furnace
