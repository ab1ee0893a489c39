// The random numbers the caller-facing tests (sampler_tests.h,
// estimator_tests.h) feed to a caller's sampler or estimator: one stream of
// uniforms in [0, 1) per named seed, the same on every platform
// (std::mt19937_64 is fully specified by the standard; the conversion to
// double below is ours, not std::uniform_real_distribution's, whose output is
// left to the implementation).
#pragma once

#include <array>
#include <cstdint>
#include <random>

namespace furnace::stats {

// The seed the tests use unless the caller names another.
inline constexpr uint64_t kDefaultTestSeed = 0x5eed'f0ce;

class UniformStream {
 public:
  explicit UniformStream(uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1): the top 53 bits, so every value is exactly
  // representable and 1.0 is never returned.
  double next() { return double(engine_() >> 11) * 0x1.0p-53; }
  std::array<double, 2> next2() {
    const double u1 = next();
    return {u1, next()};
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace furnace::stats
