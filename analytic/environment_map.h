// An image-based environment's contribution at a receiving point, exact for
// the piecewise-constant lat-long map of core/environment_map.h (texel (i, j)
// = L_ij on θ ∈ [θ_i, θ_{i+1}] = [iπ/H, (i+1)π/H], φ ∈ [φ_j, φ_{j+1}] = [2πj/W,
// 2π(j+1)/W], z up). Nothing blocks the map: the scene-level callers
// (environment.cpp, moments.cpp) refuse scenes with blockers above the horizon.
//
// Per texel, with n·ω = n_z cos θ + sin θ·g(φ), g(φ) = n_x cos φ + n_y sin φ,
// and dω = sin θ dθ dφ:
//   K₁ = ∫_texel max(n·ω, 0) dω,   K₂ = ∫_texel max(n·ω, 0)² dω.
// Texels wholly above n's horizon plane (min of n·ω over the texel ≥ 0,
// interior extrema in φ and θ included) in closed form:
//   K₁ = n_z Δφ (sin²θ₁ − sin²θ₀)/2 + G₁·(Δθ/2 − (sin 2θ₁ − sin 2θ₀)/4),
//   K₂ = n_z² Δφ (cos³θ₀ − cos³θ₁)/3 + 2 n_z G₁ (sin³θ₁ − sin³θ₀)/3
//        + G₂·((cos θ₀ − cos θ₁) − (cos³θ₀ − cos³θ₁)/3),
//   G₁ = ∫g dφ = n_x (sin φ₁ − sin φ₀) − n_y (cos φ₁ − cos φ₀),
//   G₂ = ∫g² dφ = (n_x² + n_y²) Δφ/2 + (n_x² − n_y²)(sin 2φ₁ − sin 2φ₀)/4 + n_x n_y (sin²φ₁ − sin²φ₀);
// wholly below (max ≤ 0): 0; straddling texels: the same θ integrals in closed
// form between the texel's row edges clipped to the interval where n·ω > 0
// (one interval of θ ∈ [0, π] for each φ), integrated over φ by adaptive
// Gauss–Kronrod (Boost.Math), split where the horizon curve crosses a row
// edge so every piece is smooth (absolute tolerance kMapQuadratureTolerance
// times the texel's solid angle, a bound of the integral).
// Units: sr (K₁, K₂ and the sums below are per unit map value).
#pragma once

#include "core/environment_map.h"
#include "core/scene.h"

namespace furnace::analytic {

// Tolerance of the φ quadrature over straddling texels, relative to the
// texel's ∫ sin θ dθ dφ (its solid angle, a bound of the integral).
inline constexpr double kMapQuadratureTolerance = 1e-13;

// ∫_texel max(n·ω, 0)^power dω for power 1 or 2; `n` unit.
double texel_cosine_integral(int i, int j, int width, int height, const Vec3& n, int power);
// Ω_ij = Δφ·(cos θ_i − cos θ_{i+1}), written as 2Δφ·sin(θ_mid)·sin(Δθ/2).
double texel_solid_angle(int i, int width, int height);

// Σ_ij L_ij^value_power · ∫_texel max(n·ω, 0)^cos_power dω.
double map_cosine_integral(const LatLongMap& map, const Vec3& n, int cos_power, int value_power);
// E/L_scale = Σ L_ij K₁: irradiance per unit environment radiance (W·m⁻² per W·m⁻²·sr⁻¹).
double map_irradiance(const LatLongMap& map, const Vec3& n);
// Σ L_ij·Ω_ij: the map's integral over the sphere (sr).
double map_solid_angle_integral(const LatLongMap& map);

// Whether a light-sampling estimator counts the environment among its lights:
// positive radiance, and, with a map, some texel above 0 (the renderer's LightSet).
bool environment_is_light(const Environment& environment);

// Second moments E[Y²] of the single-sample irradiance estimators at unit
// normal n under an unblocked map environment of scale R (Y = L·cos/p):
//   uniform hemisphere, p = 1/(2π):      E[Y²] = 2π R² Σ L_ij² K₂,ij;
//   cosine, p = cos θ/π:                 E[Y²] = π R² Σ L_ij² K₁,ij;
//   map importance sampling chosen with pmf 1/K among K lights, p = L_ij/(K·S),
//   S = Σ L·Ω:  Y = K R S cos₊,           E[Y²] = K R² S Σ L_ij K₂,ij.
double map_uniform_hemisphere_moment(const Environment& environment, const Vec3& n);
double map_cosine_moment(const Environment& environment, const Vec3& n);
double map_light_sampling_moment(const Environment& environment, const Vec3& n, size_t light_count);

}  // namespace furnace::analytic
