#include "core/provenance.h"

#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "core/error.h"

#ifndef FURNACE_VERSION
#error "FURNACE_VERSION must be defined (core/CMakeLists.txt passes the project VERSION)"
#endif

namespace furnace {

namespace {

// FNV-1a 64-bit parameters (Fowler, Noll & Vo; IETF draft-eastlake-fnv).
constexpr uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ull;
constexpr uint64_t kFnvPrime = 0x100000001b3ull;

// Header attribute name of each field.
struct Field {
  const char* name;
  std::string ImageProvenance::*member;
};
constexpr Field kFields[] = {
    {"furnace.scene", &ImageProvenance::scene},
    {"furnace.scene_hash", &ImageProvenance::scene_hash},
    {"furnace.strategy", &ImageProvenance::strategy},
    {"furnace.spp", &ImageProvenance::spp},
    {"furnace.seed", &ImageProvenance::seed},
    {"furnace.max_depth", &ImageProvenance::max_depth},
    {"furnace.light_selection", &ImageProvenance::light_selection},
    {"furnace.defect", &ImageProvenance::defect},
    {"furnace.convention", &ImageProvenance::convention},
    {"furnace.version", &ImageProvenance::version},
};

}  // namespace

uint64_t fnv1a_64(std::string_view bytes) {
  uint64_t hash = kFnvOffsetBasis;
  for (const char c : bytes) {
    hash ^= uint64_t(static_cast<unsigned char>(c));
    hash *= kFnvPrime;
  }
  return hash;
}

std::string file_content_hash(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("cannot read file '{}' to hash its content.", path.string()));
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(fmt::format("cannot read file '{}' to hash its content.", path.string()));
  return fmt::format("fnv1a64:{:016x}", fnv1a_64(bytes));
}

std::string furnace_version() { return FURNACE_VERSION; }

std::map<std::string, std::string> ImageProvenance::attributes() const {
  std::map<std::string, std::string> out;
  for (const Field& f : kFields)
    if (!(this->*f.member).empty()) out[f.name] = this->*f.member;
  return out;
}

ImageProvenance ImageProvenance::from_attributes(const std::map<std::string, std::string>& attributes) {
  ImageProvenance p;
  for (const Field& f : kFields)
    if (const auto a = attributes.find(f.name); a != attributes.end()) p.*f.member = a->second;
  return p;
}

}  // namespace furnace
