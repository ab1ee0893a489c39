// Exact answers for dielectric (glass) scenes in a constant environment,
// written from the definitions (Walter et al. 2007; Veach 1997 ch. 5),
// independently of renderer/dielectric.cpp: the Fresnel forms of
// analytic/fresnel.h, the microfacet terms and the refraction computed here.
//
// Two kinds of scene, no emitter, no point light, a constant environment of
// radiance L, every object a dielectric of albedo a (a constant factor on
// both lobes):
//
// 1. One smooth sphere, every camera ray starting outside it. A ray meeting
//    it at incidence θ reflects with R = F(cos θ, η) or enters; inside, every
//    chord meets the surface again at the refracted angle θt, where the
//    reflectance is again R (Fresnel symmetry F(θi; η) = F(θt; 1/η)); no
//    total internal reflection. A path that leaves after k internal
//    reflections crossed in and out once: the radiance convention's
//    factors 1/η² and η² cancel, so both conventions give
//       L_px = L·[a R + a² T² Σ_{k=0}^{K} (aR)^k],  T = 1 − R,
//    K = S − 3 for a depth limit of S segments (the camera segment, then
//    in, k internal reflections, out: 3 + k segments), K = ∞ unlimited;
//    = L·(1 − T·R^{K+1}) at a = 1, L exactly at unlimited depth. S = 1: 0;
//    S = 2: aRL. Every path returns L·a^n or 0. Direct lighting (one
//    bounce, the interior non-emitting): a R L.
// 2. Planar dielectrics (smooth or rough), all in one plane: a ray scattered
//    by one leaves the plane and meets nothing else (every path has at most
//    two segments), so direct lighting is all there is:
//       L_px = a L (E_R + s E_T)   for S ≥ 2 (0 for S = 1),
//    or, under a sky on one side (a lat-long map constant on each hemisphere
//    of the plane, which must be z = const: radiance L_v on the viewer's
//    side, L_f on the far side), L_px = a (L_v E_R + s L_f E_T): the sky
//    seen by reflection alone, or by transmission alone;
//    E_R, E_T the interface's directional albedos of reflection and
//    transmission at the view (below), s = 1/η′² in the radiance convention
//    (η′ the far side's index relative to the camera's side), 1 in none.
//
// The directional albedos at cos θo = μ, roughness α (0: smooth):
//  - smooth: E_R = R(μ), E_T = 1 − R(μ) (0 and 1 under total internal reflection);
//  - rough: over the visible normals m of ωo, density D_ωo(m) = G1(ωo)
//    max(0, ωo·m) D(m)/μ, the weight of each lobe, as the renderer's sampler
//    draws them (m, then reflection with probability F(ωo·m)):
//      E_R = ∫ D_ωo(m) F(ωo·m) [ωr below the horizon ? 0 : G2(ωo, ωr)/G1(ωo)] dm,
//      E_T = ∫ D_ωo(m) (1 − F(ωo·m)) [ωt above the horizon or TIR ? 0 : G2(ωo, ωt)/G1(ωo)] dm,
//    which equal ∫ f_r cos and ∫ f_t |cos| (f_t in the adjoint form) by the
//    change of variables ωi ↔ m (the Jacobians cancel against the densities).
//    Computed in the coordinates (w, φ), tan²θm = α² w/(1 − w), where
//    D(m) cos θm dωm = dw dφ/(2π): the GGX peak becomes flat, and the
//    integrand is G1(ωo)·max(0, ωo·m)/(μ cos θm)·(lobe terms), by nested
//    adaptive Gauss–Kronrod quadrature (core/adaptive_quadrature.h's rule,
//    E_R, E_T and E[w²] on one set of nodes) over φ ∈ [0, π] (symmetric)
//    and v = √(1 − w) ∈ [0, 1], each cut wherever its integrand is not
//    smooth (φ where a lobe meets the horizon, at the visible normals' rim
//    and at total internal reflection; v where such a cut enters the φ
//    range), each piece in a variable that smooths a square-root end.
// The second moment of one BSDF sample of unit radiance, E[w²]:
//  - smooth: a²(R + T s²);
//  - rough: a²∫ D_ωo(m)[F (G2/G1)² 1_R + (1 − F)(s G2/G1)² 1_T] dm;
// under a sky on one side, the two lobes' shares weighted by L_v² and L_f²
// (dielectric_interface_lobe_moments).
//
// Domain: η in [scene_limits::kMinDielectricEta, kMaxDielectricEta], η ≠ 1,
// α = 0 or in [kMinGgxAlpha, 1], μ in (0, 1]. Accuracy: the quadrature's
// tolerance kGlassQuadratureTolerance, relative to each value (the smooth
// forms are exact to round-off); measured against 50-digit values
// (tests/analytic/glass_precision_test.cpp, η 1.5, 1/1.5 and 1 ± 1e-4, α
// 0.01 to 1, views from normal to μ 0.05 and at the critical angle): within
// a few ε, far inside the tolerance (Gauss–Kronrod's estimate is pessimistic).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// The stated relative error bound of a rough interface's values (`furnace
// analytic` prints it), and the nested quadrature's tolerance.
inline constexpr double kGlassQuadratureTolerance = 1e-11;

struct InterfaceAlbedo {
  double reflection = 0;     // E_R
  double transmission = 0;   // E_T, unscaled
  double second_moment = 0;  // E[w²] of one BSDF sample, albedo 1, with the convention's s
};

// At cos θo = mu on the side where the far side's index relative to the
// viewer's is eta, for the dielectric's α and shadowing (its eta unused).
InterfaceAlbedo dielectric_interface_albedo(const Dielectric& d, double eta, double mu,
                                            TransportConvention convention);

// InterfaceAlbedo::second_moment split by lobe: the reflected samples' share
// and the transmitted ones' (with s²); they sum to it.
struct InterfaceLobeMoments {
  double reflection = 0, transmission = 0;
};
InterfaceLobeMoments dielectric_interface_lobe_moments(const Dielectric& d, double eta, double mu,
                                                       TransportConvention convention);

// The environment an interface sees: radiance `view` on the viewer's side,
// `far` on the far side, and how the renderer's light sampler draws it:
// cosine-weighted on either side for a constant environment (p_l =
// |cos θi|/(2π)), or by a lat-long map's texels, which for a map constant
// on each hemisphere is uniform on each side in proportion to its radiance
// (p_l = L_side/(2π(L_view + L_far))).
struct InterfaceEnvironment {
  double view = 1, far = 1;
  bool map = false;
};

// E[Y²] of the MIS strategies and of light sampling alone at the interface of
// dielectric_interface_albedo, under a constant environment of radiance 1
// (albedo 1), as the renderer draws them: light samples cosine-weighted on
// either side (p_l = |cos θi|/(2π)), BSDF samples by visible normals then
// the lobe by F (p_b = D_ωo(m)·F·J, or 1 − F). Multi-sample MIS (one sample
// of each, heuristic exponent β): E[(Y_l + Y_b)²] = E[Y_l²] + E[Y_b²] +
// 2·E[Y_l]·E[Y_b]; one-sample MIS (the BSDF with probability
// kOneSampleBsdfProbability = c): ∫ (f·|cos|·s)²/(c·p_b + (1 − c)·p_l).
// Each integral is taken as an expectation over the BSDF sampler
// (f·|cos θi| = w·p_b), on the albedo's nodes and cuts. A smooth interface:
// the light sample's f is 0 and the BSDF sample's weight 1, so balance and
// power are the bsdf strategy's E[Y²], one-sample that over c; light
// sampling alone cannot find the delta lobe (light stays 0: not modelled).
inline constexpr double kMinMisEtaRatio = 1.0001;
struct InterfaceMisMoments {
  double balance = 0, power = 0, one_sample = 0;
  double light = 0;  // light sampling alone (rough only)
  double mean = 0;   // E[Y] as integrated with them (= E_R + s·E_T; a check)
  // Error bounds: each integral within kGlassQuadratureTolerance of itself
  // (0 for a smooth interface), propagated through the sums and products.
  double balance_bound = 0, power_bound = 0, one_sample_bound = 0, light_bound = 0;
};
// Under `environment` (default: constant, radiance 1) the moments are in its
// radiance squared; `mean` is E[Y] = L_v·E_R + s·L_f·E_T.
// Domain: a rough interface's moments need η ∉ (1/kMinMisEtaRatio,
// kMinMisEtaRatio), else furnace::Error is thrown (verify then tests such a
// case without a variance model). Measured against 50-digit values
// (tests/analytic/glass_precision_test.cpp, MisAtTheDomainsEdge): within
// 6e-16 at η 1.0001, 1/1.0001, 1.00001 and 1/1.00001 (α 1, μ 0.2), within
// 5.4e-15 at 1.0001 and 1/1.0001 with α 0.1, μ 0.9; at 1.000001 power
// missed by 3.0e-12 (> 1e-13, inside the stated 1e-11): the transmission's
// MIS weights turn in a band of microfacets near the visible normals' rim
// whose width falls as |η − 1| does. The margin below 1.0001 is kept.
InterfaceMisMoments dielectric_interface_mis_moments(const Dielectric& d, double eta, double mu,
                                                     TransportConvention convention,
                                                     const InterfaceEnvironment& environment = {});

// The environment seen at a planar interface of a glass scene (kind 2) by a
// viewer on the side `view_normal` points to: the constant environment's
// radiance on both sides, or a sky on one side's two hemisphere radiances.
// Throws furnace::Error when the environment is neither (glass_scene_refusal
// says so first).
InterfaceEnvironment interface_environment(const Scene& scene, const Vec3& view_normal);

// The convention's factor s on transmitted radiance for relative index eta.
double transmission_scale(double eta, TransportConvention convention);

// Whether the scene is one of the two kinds above, or, when it has an
// emitter, of the third kind (planar lights behind rough glass, black
// environment: glass_light.h); the reason it is not, otherwise.
std::optional<std::string> glass_scene_refusal(const Scene& scene);
bool has_dielectric(const Scene& scene);

// Per pixel centre (row-major): the radiance of kind 1 or 2 for paths of at
// most max_segments segments. `direct_only`: the direct-lighting reference
// (one bounce). Throws furnace::Error naming the scene and the reason when
// the scene is neither kind.
std::vector<double> glass_reference_image(const Scene& scene, int max_segments, TransportConvention convention,
                                          bool direct_only);

// E[Y²] per pixel centre of the direct strategy `strategy` on a glass
// scene: in kinds 1 and 2 bsdf (the sphere: a²L²R, a reflection seeing L),
// the MIS strategies (dielectric_interface_mis_moments; on the sphere bsdf's,
// over c for one-sample) and light sampling alone at rough interfaces;
// every direct strategy but the hemisphere ones in kind 3 (lights behind
// rough glass, glass_light.h, under `selection`); throws furnace::Error for
// another strategy, and for light sampling alone at a smooth interface.
std::vector<double> glass_second_moment_image(const Scene& scene, Strategy strategy, TransportConvention convention,
                                              LightSelection selection = LightSelection::kUniform);

}  // namespace furnace::analytic
