// The one place analytic/ picks a material's receiver model (receiver.h):
// a glossy material (the table's `glossy` column, core/material.h) is a
// Receiver built here by one visit over the material types; everything the
// model answers (the reflected radiance, every direct strategy's E[Y²], a
// sphere's reflectance, the directional albedo) is written once below for
// any Receiver. A Lambertian receiver keeps its closed forms (reference.h,
// moments.h); a mirror, a delta lobe, has no receiver model.
//
// Units: radiance W·m⁻²·sr⁻¹, second moments its square; reflectances and
// albedos dimensionless (per unit emitted radiance).
#pragma once

#include <memory>

#include "analytic/receiver.h"
#include "core/scene.h"
#include "core/strategy.h"

namespace furnace::analytic {

// The receiver model of `material` at a point with unit normal n seen from
// the unit direction wo (n·ωo > 0): PhongReceiver (phong.h), GgxReceiver
// (ggx.h); nullptr for a material that is not glossy.
std::unique_ptr<Receiver> glossy_receiver(const Material& material, const Vec3& n, const Vec3& wo);

// The receiver of object `receiver` of the scene at n, wo. Throws
// furnace::Error naming the scene for an object that is not glossy or a
// viewer below its horizon.
std::unique_ptr<Receiver> glossy_receiver(const Scene& scene, const Vec3& n, const Vec3& wo, size_t receiver);

// Radiance reflected toward `wo` at point p of the glossy object `receiver`
// (normal n facing wo), direct lighting only, for the lights the receiver
// model solves (receiver_lights, receiver.h). Throws furnace::Error naming
// the scene and the configuration for anything else.
double glossy_reflected_radiance(const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& wo, size_t receiver);

// E[Y²] of the direct strategy's single-sample estimator of that radiance (Y
// the reflected part only, emission excluded), under the given light
// selection. Throws furnace::Error for a path tracer or an unsupported
// configuration.
double glossy_second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& wo,
                            size_t receiver, LightSelection selection = LightSelection::kUniform);

// ∫_{cone ∩ n·ω>0} f·(n·ω) dω over the cone of a sphere of radius R whose
// centre is at `center` relative to the receiving point (|center| > R): the
// reflected radiance per unit emitted radiance, unoccluded.
double sphere_reflectance(const Receiver& receiver, const Vec3& center, double radius);

// ∫_{n·ω>0} f·(n·ω) dω: the directional albedo, the reflected radiance per
// unit radiance of an unblocked constant environment.
double directional_albedo(const Receiver& receiver);

}  // namespace furnace::analytic
