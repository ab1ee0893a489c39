// Deterministic mutations of scene files and command lines for the fuzz test.
//
// A scene mutation takes one built-in scene's JSON and changes one thing:
// a number replaced by an extreme token (1e309, -1e309, NaN, "nan", 0, -1,
// 1e19, 1e-320, ...), a value replaced by one of another type, a field
// deleted, renamed with a typo, duplicated or added, an array shortened,
// lengthened or emptied, or the file truncated. Tokens that no JSON value can
// hold (1e309, NaN, a duplicated key) are spliced into the dumped text.
// A command-line mutation takes one base command and changes one argument:
// a value replaced (NaN, negative, huge, empty, text), an option misspelt,
// duplicated or left without its value, or an unknown option added.
// Every list is built in a fixed order and sampled with a named seed, so the
// same cases run every time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace furnace::fuzz {

struct SceneMutation {
  std::string scene;        // built-in scene name (file stem)
  std::string kind;         // operator, e.g. "number", "rename", "truncate"
  std::string description;  // "disk_occluder /objects/1/emission := 1e309"
  std::string text;         // the mutated file
};

// Every mutation of one scene file's text (in a fixed order).
std::vector<SceneMutation> scene_mutations(const std::string& scene, const std::string& text);

// `count` of `all`, chosen by `seed`: round-robin over the operator kinds
// (each kind shuffled), so that rare kinds are not swamped by numbers.
// `skip` cases of the same order are passed over first (disjoint samples).
std::vector<SceneMutation> sample(const std::vector<SceneMutation>& all, size_t count, size_t skip, uint64_t seed);

struct CommandLine {
  std::string description;        // what was changed
  std::vector<std::string> args;  // after the program name
  std::string named;              // an option or value a one-line error must name ("" = any)
};

// Every mutation of one base command line (`args`: the subcommand, then
// options as "--name value" pairs or flags), in a fixed order. Options in
// `bounding` bound the command's work (--spp, --seeds, ...) and are never
// dropped: without them a valid command may legitimately run for minutes.
std::vector<CommandLine> command_mutations(const std::vector<std::string>& args,
                                           const std::vector<std::string>& bounding);

// The shell-quoted form of one argument.
std::string shell_quote(const std::string& arg);

// A SplitMix64 stream: small, fast and the same on every platform.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, n).
  size_t below(size_t n) { return size_t(next() % n); }

 private:
  uint64_t state_;
};

}  // namespace furnace::fuzz
