// The three error tiers of furnace:
//  1. bad user input  -> throw furnace::Error with a full sentence naming
//     file, field and value; the CLI prints it and exits non-zero;
//  2. internal invariants -> FURNACE_CHECK (always on) / FURNACE_DCHECK (debug);
//  3. numerical runaway on a path -> counted by the integrator, not thrown.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace furnace {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& sentence) : std::runtime_error(sentence) {}
};

// FURNACE_CHECK's failure: prints the condition and where, then aborts.
// Header-only, so libraries on core/'s numerics alone (stats/) can check too.
[[noreturn]] inline void check_failed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "furnace: internal check failed: %s at %s:%d\n", condition, file, line);
  std::abort();
}

}  // namespace furnace

#define FURNACE_CHECK(cond) \
  do { if (!(cond)) ::furnace::check_failed(#cond, __FILE__, __LINE__); } while (0)

#ifdef NDEBUG
#define FURNACE_DCHECK(cond) do { (void)sizeof(cond); } while (0)
#else
#define FURNACE_DCHECK(cond) FURNACE_CHECK(cond)
#endif
