#include "analytic/glossy.h"

#include "analytic/ggx.h"
#include "analytic/phong.h"
#include "analytic/unsupported.h"
#include "core/error.h"
#include "core/overloaded.h"

namespace furnace::analytic {

std::unique_ptr<Receiver> glossy_receiver(const Material& material, const Vec3& n, const Vec3& wo) {
  const double albedo = material.albedo;
  std::unique_ptr<Receiver> out = std::visit(
      overloaded{[](const Lambertian&) -> std::unique_ptr<Receiver> { return nullptr; },  // closed forms
                 [](const Mirror&) -> std::unique_ptr<Receiver> { return nullptr; },      // a delta lobe
                 [&](const Phong& p) -> std::unique_ptr<Receiver> {
                   return std::make_unique<PhongReceiver>(n, wo, albedo, p.exponent);
                 },
                 [&](const Ggx& g) -> std::unique_ptr<Receiver> {
                   return std::make_unique<GgxReceiver>(n, wo, albedo, g.alpha, g.shadowing, g.fresnel);
                 },
                 // No receiver model transmits (yet): the dielectric's references are global.h's.
                 [](const Dielectric&) -> std::unique_ptr<Receiver> { return nullptr; }},
      material.bsdf);
  FURNACE_CHECK((out != nullptr) == material.info().glossy && "the table's glossy column names the receivers");
  return out;
}

namespace {

// The receiver of a glossy object, or a refusal naming the scene.
std::unique_ptr<Receiver> receiver_of(const Scene& scene, const Vec3& n, const Vec3& wo, size_t receiver) {
  const Object& object = scene.objects[receiver];
  std::unique_ptr<Receiver> model = glossy_receiver(object.material, n, wo);
  if (!model)
    unsupported_configuration(scene, "the receiver '" + object.name + "' (" + bsdf_type_name(object.material.type()) +
                                         "), which is not glossy, as a glossy receiver");
  return model;
}

void require_viewer_above(const Scene& scene, const Receiver& model) {
  if (!(dot(model.n, model.wo) > 0)) unsupported_configuration(scene, model.name() + " seen from below its horizon");
}

}  // namespace

std::unique_ptr<Receiver> glossy_receiver(const Scene& scene, const Vec3& n, const Vec3& wo, size_t receiver) {
  std::unique_ptr<Receiver> model = receiver_of(scene, n, wo, receiver);
  require_viewer_above(scene, *model);
  return model;
}

double glossy_reflected_radiance(const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& wo, size_t receiver) {
  return receiver_reflected_radiance(scene, p, *glossy_receiver(scene, n, wo, receiver), receiver);
}

double glossy_second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& wo,
                            size_t receiver, LightSelection selection) {
  const std::unique_ptr<Receiver> model = receiver_of(scene, n, wo, receiver);
  if (is_path_tracer(strategy))
    unsupported_configuration(scene, "the path tracer '" + strategy_name(strategy) + "' over " + model->name());
  require_viewer_above(scene, *model);
  return receiver_second_moment(strategy, scene, p, *model, receiver, selection);
}

double sphere_reflectance(const Receiver& receiver, const Vec3& center, double radius) {
  return light_reflectance(receiver, ReceiverLight{false, center, radius, 1.0, 1.0});
}

double directional_albedo(const Receiver& receiver) {
  return light_reflectance(receiver, ReceiverLight{true, {}, 0, 1.0, 1.0});
}

}  // namespace furnace::analytic
