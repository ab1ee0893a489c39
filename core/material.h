// Materials: a common part (the albedo) plus one struct per BSDF type that
// owns its own parameters: their defaults, how the scene file spells them,
// their ranges and how they are shown (Mitsuba's "a plugin parses its own
// parameters", with the completeness checked at compile time).
//
// The one list of types is the variant BsdfParameters below, in the order of
// the enumerator BsdfType and its vocabulary table kBsdfTypeTable (the words
// the loader accepts). A new type is an enumerator, its table row and its
// struct (kType, fields(), parse()) added to the variant; the static_asserts
// below refuse a table and a variant that disagree, and every layer that
// must decide what the new type does has one std::visit(overloaded{...})
// with one case per alternative, which then fails to compile
// (docs/extending.md lists them).
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "core/error.h"

namespace furnace {

enum class BsdfType { kLambertian, kMirror, kPhong, kGgx, kDielectric };

// The vocabulary of material types: the scene file's word for each ("type"
// of a material: the loader parses these and every message that names a
// type uses them) and the properties other layers decide by without a
// branch on the type.
struct BsdfTypeInfo {
  // Every column is given: a row that forgets one does not compile.
  constexpr BsdfTypeInfo(BsdfType type, const char* name, bool albedo_scales_reflection, bool glossy,
                         bool keeps_energy_at_unit_albedo)
      : type(type),
        name(name),
        albedo_scales_reflection(albedo_scales_reflection),
        glossy(glossy),
        keeps_energy_at_unit_albedo(keeps_energy_at_unit_albedo) {}
  BsdfType type;
  const char* name;
  // The albedo multiplies the whole BSDF (Lambertian ρ/π, a mirror's ρ·δ,
  // Phong's lobe albedo, GGX's constant factor, a dielectric's factor on
  // both its lobes), so albedo 0 is black (Material::reflects).
  bool albedo_scales_reflection;
  // A lobe that analytic/ integrates over the lights toward a view direction
  // (a glossy receiver, analytic/receiver.h), rather than a Lambertian
  // receiver's irradiance times ρ/π or a delta lobe's mirrored ray.
  bool glossy;
  // At albedo 1 it reflects all the light arriving from every direction
  // (Lambertian, an ideal mirror; not a microfacet lobe, which loses the
  // light its model sends below the horizon), so a closed enclosure of such
  // objects that emits has infinite radiance at unlimited depth (path_length.h).
  // (A smooth dielectric keeps it too, but only a rough one would need this
  // column to be false, and a column cannot tell them apart: false, which
  // leaves such a scene to the segment bound, which refuses it as well.)
  bool keeps_energy_at_unit_albedo;
};
inline constexpr std::array<BsdfTypeInfo, 5> kBsdfTypeTable = {{
    //                        albedo scales, glossy, keeps energy at albedo 1
    {BsdfType::kLambertian, "lambertian", true, false, true},
    {BsdfType::kMirror, "mirror", true, false, true},
    {BsdfType::kPhong, "phong", true, true, false},
    {BsdfType::kGgx, "ggx", true, true, false},
    {BsdfType::kDielectric, "dielectric", true, false, false},
}};
// Every enumerator 0 … kBsdfTypeTable.size() − 1 has exactly one row, in order.
constexpr bool bsdf_table_in_enumerator_order() {
  for (size_t v = 0; v < kBsdfTypeTable.size(); ++v)
    if (kBsdfTypeTable[v].type != BsdfType(v)) return false;
  return true;
}
static_assert(bsdf_table_in_enumerator_order(), "kBsdfTypeTable needs one row per BsdfType, in enumerator order");
// The type's row; a value that is no enumerator of BsdfType (cast from an
// integer) is an internal error.
const BsdfTypeInfo& bsdf_type_info(BsdfType type);
// The type's word.
inline const char* bsdf_type_name(BsdfType type) { return bsdf_type_info(type).name; }

// The Smith masking-shadowing term G2 of a microfacet BSDF, from the
// one-direction Λ(ω) of its distribution (Heitz 2014, "Understanding the
// masking-shadowing function in microfacet-based BRDFs"):
//  - separable: G2 = G1(ωo)·G1(ωi), G1 = 1/(1 + Λ) (Cycles 3.4, Mitsuba 3);
//  - height-correlated: G2 = 1/(1 + Λ(ωo) + Λ(ωi)) (pbrt-v4, Cycles ≥ 3.5).
// The two agree when either direction is the normal (Λ = 0 there).
enum class MicrofacetShadowing { kSeparable, kHeightCorrelated };
struct MicrofacetShadowingInfo {
  MicrofacetShadowing shadowing;
  const char* name;
};
inline constexpr std::array<MicrofacetShadowingInfo, 2> kMicrofacetShadowingTable = {{
    {MicrofacetShadowing::kSeparable, "separable"},
    {MicrofacetShadowing::kHeightCorrelated, "height_correlated"},
}};
static_assert(kMicrofacetShadowingTable[0].shadowing == MicrofacetShadowing(0) &&
                  kMicrofacetShadowingTable[1].shadowing == MicrofacetShadowing(1),
              "kMicrofacetShadowingTable lists the enumerators in order");
inline const char* microfacet_shadowing_name(MicrofacetShadowing s) {
  return kMicrofacetShadowingTable[static_cast<size_t>(s)].name;
}

namespace scene_limits {
// Normalised Phong exponent n: the BSDF chi-square tests cover n ≤ 1000; 1e4
// (lobe width ≈ 1/√n = 0.01 rad) is ten times that; a sharper lobe is a mirror.
inline constexpr double kMaxPhongExponent = 1e4;
// GGX roughness α: the references are exact and the renderer free of NaN,
// Inf and zero pdfs with non-zero f down to this (tests/renderer/ggx_test.cpp,
// tests/analytic/ggx_test.cpp); a smoother surface is a mirror.
inline constexpr double kMinGgxAlpha = 1e-3;
// A dielectric's relative index η (inside over outside): from an air bubble
// in germanium to germanium in air. η = 1 (an index-matched, invisible
// interface) is refused: the object does nothing but cost rays.
inline constexpr double kMinDielectricEta = 0.25;
inline constexpr double kMaxDielectricEta = 4.0;
// A conductor's complex index n + ik: each part in [0, kMaxConductorIndex],
// not both 0 (measured metals have n < 10 and k < 20 in the visible).
inline constexpr double kMaxConductorIndex = 100.0;
}  // namespace scene_limits

// One of a material type's own parameters, as the scene file names it: a
// number, or (when `word` is set) one word of a vocabulary.
struct MaterialField {
  const char* name;
  double number = 0;
  const char* word = nullptr;
};

// What a material type reads its own fields through. core/scene.cpp
// implements it over the material's JSON object: every failure is a
// furnace::Error naming the file, the field's path and the value.
class MaterialFieldReader {
 public:
  virtual ~MaterialFieldReader() = default;
  virtual bool has(const std::string& field) const = 0;
  // A required number in [lo, hi].
  virtual double number_in(const std::string& field, double lo, double hi) const = 0;
  // A required string, one of `words`: its index there.
  virtual size_t word_in(const std::string& field, const std::vector<const char*>& words) const = 0;
  // A required object: a reader of its fields.
  virtual std::unique_ptr<MaterialFieldReader> object(const std::string& field) const = 0;
  // Refuses the field's value with the reason (`what` completes "field 'x' …").
  [[noreturn]] virtual void refuse(const std::string& field, const std::string& what) const = 0;
  // Refuses every field of this object that no call above asked about (the
  // material's own object is checked by the loader; a nested object by its parser).
  virtual void reject_unknown_fields() const = 0;
};

// Lambertian: f = ρ/π.
struct Lambertian {
  static constexpr BsdfType kType = BsdfType::kLambertian;
  std::vector<MaterialField> fields() const { return {}; }
  static Lambertian parse(const MaterialFieldReader&) { return {}; }
};

// Ideal mirror of reflectance ρ: f = ρ·δ(ωi − reflect(ωo))/cos θi.
struct Mirror {
  static constexpr BsdfType kType = BsdfType::kMirror;
  std::vector<MaterialField> fields() const { return {}; }
  static Mirror parse(const MaterialFieldReader&) { return {}; }
};

// Normalised Phong (Lafortune & Willems 1994), f = ρ·(n+2)/(2π)·cos^n α:
// "exponent" n in [0, kMaxPhongExponent], 1 when absent.
struct Phong {
  static constexpr BsdfType kType = BsdfType::kPhong;
  double exponent = 1;
  std::vector<MaterialField> fields() const { return {{"exponent", exponent}}; }
  static Phong parse(const MaterialFieldReader& r) {
    Phong m;
    if (r.has("exponent")) m.exponent = r.number_in("exponent", 0, scene_limits::kMaxPhongExponent);
    return m;
  }
};

// The "shadowing" field of a microfacet material: height_correlated when absent.
inline MicrofacetShadowing parse_shadowing(const MaterialFieldReader& r) {
  if (!r.has("shadowing")) return MicrofacetShadowing::kHeightCorrelated;
  return MicrofacetShadowing(
      r.word_in("shadowing", {kMicrofacetShadowingTable[0].name, kMicrofacetShadowingTable[1].name}));
}

// A conductor's complex index of refraction n + ik relative to the outside
// (core/fresnel.h's fresnel_conductor).
struct ConductorIndex {
  double eta = 0;  // n
  double k = 1;
};

// Isotropic Trowbridge–Reitz (GGX) microfacet reflection,
// f = ρ·F(ωo·h)·D·G2/(4 cos θo cos θi): "alpha", the roughness α of
// D(m) = α²/(π cos⁴θm (α² + tan²θm)²), required, in [kMinGgxAlpha, 1];
// "shadowing", the Smith form of G2, height_correlated when absent;
// "fresnel", absent for F ≡ 1, or {"eta": n, "k": k}, the exact
// unpolarised Fresnel reflectance of a conductor of index n + ik.
struct Ggx {
  static constexpr BsdfType kType = BsdfType::kGgx;
  double alpha = 1;
  MicrofacetShadowing shadowing = MicrofacetShadowing::kHeightCorrelated;
  std::optional<ConductorIndex> fresnel = std::nullopt;
  std::vector<MaterialField> fields() const {
    std::vector<MaterialField> out{{"alpha", alpha}, {"shadowing", 0, microfacet_shadowing_name(shadowing)}};
    if (fresnel) {
      out.push_back({"fresnel.eta", fresnel->eta});
      out.push_back({"fresnel.k", fresnel->k});
    }
    return out;
  }
  static Ggx parse(const MaterialFieldReader& r) {
    Ggx m;
    m.alpha = r.number_in("alpha", scene_limits::kMinGgxAlpha, 1.0);
    m.shadowing = parse_shadowing(r);
    if (r.has("fresnel")) {
      const std::unique_ptr<MaterialFieldReader> f = r.object("fresnel");
      ConductorIndex index;
      index.eta = f->number_in("eta", 0.0, scene_limits::kMaxConductorIndex);
      index.k = f->number_in("k", 0.0, scene_limits::kMaxConductorIndex);
      if (index.eta == 0 && index.k == 0) f->refuse("k", "must be above 0 when eta is 0 (an index of 0 is no material)");
      f->reject_unknown_fields();
      m.fresnel = index;
    }
    return m;
  }
};

// A dielectric interface (glass): exact unpolarised Fresnel (core/fresnel.h)
// chooses between reflection and refraction. "eta": the index behind the
// front normal (inside a sphere) relative to the index in front of it,
// required, in [kMinDielectricEta, kMaxDielectricEta] and not 1; "alpha": 0
// or absent for a smooth interface (delta lobes), else the GGX roughness in
// [kMinGgxAlpha, 1] of a rough one (Walter et al. 2007); "shadowing" as GGX's.
// Radiance crossing the interface is scaled by the transport convention
// (core/strategy.h's TransportConvention). The albedo is a constant factor
// on both lobes (1 for clear glass).
struct Dielectric {
  static constexpr BsdfType kType = BsdfType::kDielectric;
  double eta = 1.5;
  double alpha = 0;
  MicrofacetShadowing shadowing = MicrofacetShadowing::kHeightCorrelated;
  bool smooth() const { return alpha == 0; }
  std::vector<MaterialField> fields() const {
    return {{"eta", eta}, {"alpha", alpha}, {"shadowing", 0, microfacet_shadowing_name(shadowing)}};
  }
  static Dielectric parse(const MaterialFieldReader& r);  // material.cpp
};

// The per-type parameters, one alternative per BsdfType in enumerator order.
using BsdfParameters = std::variant<Lambertian, Mirror, Phong, Ggx, Dielectric>;

template <size_t... I>
constexpr bool alternatives_in_enumerator_order(std::index_sequence<I...>) {
  return ((std::variant_alternative_t<I, BsdfParameters>::kType == BsdfType(I)) && ...);
}
static_assert(std::variant_size_v<BsdfParameters> == kBsdfTypeTable.size(),
              "BsdfParameters needs one alternative per row of kBsdfTypeTable");
static_assert(alternatives_in_enumerator_order(std::make_index_sequence<std::variant_size_v<BsdfParameters>>()),
              "BsdfParameters lists its alternatives in BsdfType's order, each with its kType");

struct Material {
  // Lambertian reflectance ρ, mirror reflectance, Phong lobe albedo, or the
  // GGX constant factor on f (the table's albedo_scales_reflection).
  double albedo = 0;
  BsdfParameters bsdf;

  // Whether it reflects any light: not when its albedo scales the whole
  // reflection and is 0 (an exporter may write such an object as a black
  // diffuse surface).
  bool reflects() const { return !info().albedo_scales_reflection || albedo > 0; }

  // The alternative's index is its BsdfType and its table row (the
  // static_asserts above).
  BsdfType type() const { return BsdfType(bsdf.index()); }
  const BsdfTypeInfo& info() const { return kBsdfTypeTable[bsdf.index()]; }
  // The type's own parameters, when the material is of that type.
  template <class T>
  const T* as() const {
    return std::get_if<T>(&bsdf);
  }
  // The type's own fields (its struct's fields()).
  std::vector<MaterialField> fields() const;
  // Every field of the material as the scene file names them, type and
  // albedo first: "type \"ggx\", albedo 0.8, alpha 0.3, shadowing \"separable\"".
  std::string text() const;
};

// The default parameters of the type (its struct's defaults).
BsdfParameters default_parameters(BsdfType type);
// Reads the type's own fields (its struct's parse()).
BsdfParameters parse_parameters(BsdfType type, const MaterialFieldReader& reader);

}  // namespace furnace
