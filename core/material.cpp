#include "core/material.h"

#include <fmt/format.h>

namespace furnace {

namespace {

// The alternative of BsdfParameters at index `type`, made by `make`
// (called with a null pointer of the alternative's type).
template <class Make, size_t... I>
BsdfParameters alternative(BsdfType type, Make make, std::index_sequence<I...>) {
  BsdfParameters out;
  const bool found = ((size_t(type) == I ? (out = make(static_cast<std::variant_alternative_t<I, BsdfParameters>*>(nullptr)),
                                            true)
                                         : false) ||
                      ...);
  if (!found) bsdf_type_info(type);  // an internal error: no enumerator
  return out;
}
constexpr auto kAlternatives = std::make_index_sequence<std::variant_size_v<BsdfParameters>>();

}  // namespace

const BsdfTypeInfo& bsdf_type_info(BsdfType type) {
  for (const BsdfTypeInfo& info : kBsdfTypeTable)
    if (info.type == type) return info;
  const std::string what = fmt::format("BsdfType value {} is no enumerator of BsdfType", static_cast<int>(type));
  check_failed(what.c_str(), __FILE__, __LINE__);
}

std::vector<MaterialField> Material::fields() const {
  return std::visit([](const auto& p) { return p.fields(); }, bsdf);
}

std::string Material::text() const {
  std::string out = fmt::format("type \"{}\", albedo {}", bsdf_type_name(type()), albedo);
  for (const MaterialField& f : fields())
    out += f.word ? fmt::format(", {} \"{}\"", f.name, f.word) : fmt::format(", {} {}", f.name, f.number);
  return out;
}

Dielectric Dielectric::parse(const MaterialFieldReader& r) {
  Dielectric m;
  m.eta = r.number_in("eta", scene_limits::kMinDielectricEta, scene_limits::kMaxDielectricEta);
  if (m.eta == 1)
    r.refuse("eta", "must not be 1: an index-matched interface is invisible (remove the object instead)");
  if (r.has("alpha")) {
    m.alpha = r.number_in("alpha", 0.0, 1.0);
    if (m.alpha != 0 && m.alpha < scene_limits::kMinGgxAlpha)
      r.refuse("alpha", fmt::format("must be 0 (smooth) or in [{:g}, 1], got {:g}", scene_limits::kMinGgxAlpha,
                                    m.alpha));
  }
  m.shadowing = parse_shadowing(r);
  return m;
}

BsdfParameters default_parameters(BsdfType type) {
  return alternative(type, [](auto* t) { return BsdfParameters(std::decay_t<decltype(*t)>{}); }, kAlternatives);
}

BsdfParameters parse_parameters(BsdfType type, const MaterialFieldReader& reader) {
  return alternative(type, [&](auto* t) { return BsdfParameters(std::decay_t<decltype(*t)>::parse(reader)); },
                     kAlternatives);
}

}  // namespace furnace
