// Direct lighting through a rough dielectric interface (glass_light.h): the
// transmission as a Receiver, the mirror map of the lights, and the scenes.
#include "analytic/glass_light.h"

#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "analytic/fresnel.h"
#include "analytic/ggx.h"
#include "analytic/glass.h"
#include "analytic/occlusion.h"
#include "analytic/receiver_integrals.h"
#include "analytic/reference.h"
#include "core/error.h"

namespace furnace::analytic {

GlassTransmissionReceiver::GlassTransmissionReceiver(const Vec3& n, const Vec3& wo, double albedo, double eta,
                                                     double alpha, MicrofacetShadowing shadowing,
                                                     TransportConvention convention)
    : ReceiverModel(n, wo),
      albedo(albedo),
      eta(eta),
      alpha(alpha),
      shadowing(shadowing),
      convention(convention),
      mu_o_(dot(n, wo)),
      sin_o_(std::sqrt((1 - dot(n, wo)) * (1 + dot(n, wo)))),
      lambda_o_(ggx_lambda(alpha, dot(n, wo))),
      scale_(transmission_scale(eta, convention)) {
  FURNACE_CHECK(eta > 0 && eta != 1 && alpha > 0 && mu_o_ > 0);
}

BsdfValue GlassTransmissionReceiver::at(double cos_theta, double cos_alpha) const {
  return at_direction(cos_theta, cos_alpha, 1 - cos_alpha);
}

BsdfValue GlassTransmissionReceiver::at_direction(double cos_theta, double cos_alpha, double gap) const {
  BsdfValue value;
  const double mu_i = cos_theta;
  const double sigma = eta < 1 ? 1.0 : -1.0;  // sign(1 − η): m = σH/|H|
  // |H|² = 1 + η² − 2η cos α as a sum of non-negative terms.
  const double h2 = (eta - 1) * (eta - 1) + 2 * eta * gap;
  const double h = std::sqrt(h2);
  const double n_m_h = sigma * (mu_o_ - eta * mu_i);          // |H|·n·m
  const double o_m_h = sigma * ((1 - eta) + eta * gap);       // |H|·ωo·m = σ(1 − η cos α)
  const double i_m_h = sigma * ((eta - 1) + gap);             // |H|·ωi·m = σ(η − cos α)
  if (!(n_m_h > 0) || !(o_m_h > 0) || !(i_m_h < 0)) return value;  // not a refraction pair
  const double wo_m = o_m_h / h;
  const double f = fresnel_dielectric_reference(wo_m, eta);
  if (!(f < 1)) return value;
  // |H⊥|² = (sin θo − η sin θi)² + 2η(cos(θo − θi) − cos α), with
  // cos(θo − θi) − cos α = (1 − cos α) − |u_o − u_i|²/2 (u the unit vectors (sin, cos)).
  const double sin_i = std::sqrt((1 - mu_i) * (1 + mu_i));
  const double dmu = mu_o_ - mu_i, dsin = sin_o_ - sin_i;
  const double across = sin_o_ - eta * sin_i;
  const double h_perp2 = std::fmax(across * across + 2 * eta * (gap - 0.5 * (dmu * dmu + dsin * dsin)), 0.0);
  const double alpha2 = alpha * alpha;
  const double denom = alpha2 * n_m_h * n_m_h + h_perp2;
  const double d = alpha2 * h2 * h2 / (kPi * denom * denom);
  const double jacobian = eta * eta * (-i_m_h) / (h2 * h);  // η²|ωi·m|/|H|², |ωi·m| = |i_m_h|/|H|
  const double lambda_i = ggx_lambda(alpha, mu_i);
  const double g1o = 1 / (1 + lambda_o_);
  double g2 = 0, g2_squared_over_g1o = 0;
  switch (shadowing) {
    case MicrofacetShadowing::kSeparable:
      g2 = g1o / (1 + lambda_i);
      g2_squared_over_g1o = g1o / ((1 + lambda_i) * (1 + lambda_i));
      break;
    case MicrofacetShadowing::kHeightCorrelated: {
      const double sum = 1 + lambda_o_ + lambda_i;
      g2 = 1 / sum;
      g2_squared_over_g1o = (1 + lambda_o_) / (sum * sum);
      break;
    }
  }
  const double common = (1 - f) * d * wo_m * jacobian / mu_o_;  // (1 − F)·D·(ωo·m)·J/μo
  value.f_cos = albedo * scale_ * common * g2;
  value.pdf_solid_angle = common * g1o;
  value.f_cos2_over_pdf = albedo * albedo * scale_ * scale_ * common * g2_squared_over_g1o;
  return value;
}

Vec3 GlassTransmissionReceiver::lobe_centre() const {
  // Snell's direction of ωo at m = n, mirrored above: tangent part r⊥/η, height cos θt.
  const double sin_t = sin_o_ / eta;
  if (!(sin_t < 1)) return mirror();
  const Vec3 r = mirror();
  const Vec3 r_across = r - n * dot(r, n);
  return normalize(r_across / eta + n * std::sqrt((1 - sin_t) * (1 + sin_t)));
}

std::vector<SupportEdge> GlassTransmissionReceiver::support_edges() const {
  std::vector<SupportEdge> edges{{mirror(), std::fmin(eta, 1 / eta)}};
  if (mu_o_ / eta < 1) edges.push_back({n, mu_o_ / eta});
  return edges;
}

std::vector<double> GlassTransmissionReceiver::parameters() const {
  return {double(BsdfType::kDielectric), albedo, eta, alpha, double(shadowing), double(convention)};
}

Material GlassTransmissionReceiver::material() const { return Material{albedo, Dielectric{eta, alpha, shadowing}}; }

template class ReceiverModel<GlassTransmissionReceiver>;

namespace {

[[noreturn]] void refuse(const Scene& scene, const std::string& reason) {
  throw Error(fmt::format("scene '{}' ({}) has no exact glass reference: {}.", scene.name, scene.source, reason));
}

// The interface's plane (that of the first dielectric).
Plane interface_plane(const Scene& scene) {
  for (const Object& o : scene.objects)
    if (o.material.as<Dielectric>()) return *plane_of(o.shape);
  FURNACE_CHECK(false && "a glass light scene has a dielectric");
  return {};
}

// The lights on the far side of the interface seen from p (viewer's normal
// n), mirrored through the tangent plane to the viewer's side.
std::vector<ReceiverLight> mirrored_lights(const Scene& scene, const Vec3& p, const Vec3& n, size_t receiver,
                                           LightSelection selection) {
  const std::string who = fmt::format("a point of the glass '{}'", scene.objects[receiver].name);
  std::vector<ReceiverLight> lights = receiver_lights(scene, p, -n, receiver, selection, who);
  const auto mirror = [&](const Vec3& v) { return v - n * (2 * dot(v, n)); };
  for (ReceiverLight& light : lights) {
    FURNACE_CHECK(light.planar && "glass_light_scene_refusal admits planar lights only");
    light.planar->s = mirror(light.planar->s);
    light.planar->t = mirror(light.planar->t);
    light.planar->toward_receiver = mirror(light.planar->toward_receiver);
  }
  return lights;
}

GlassTransmissionReceiver receiver_at(const Scene& scene, const Vec3& p, const Vec3& wo, size_t receiver,
                                      TransportConvention convention) {
  const Object& o = scene.objects[receiver];
  const Dielectric* d = o.material.as<Dielectric>();
  if (!d || d->smooth() || !is_planar(o.shape))
    refuse(scene, fmt::format("object '{}' is not a rough planar dielectric", o.name));
  const Vec3 front = plane_of(o.shape)->normal;
  const double cos_front = dot(wo, front);
  if (cos_front == 0) refuse(scene, fmt::format("the view lies in the plane of '{}'", o.name));
  const bool in_front = cos_front > 0;
  return GlassTransmissionReceiver(in_front ? front : -front, wo, o.material.albedo, in_front ? d->eta : 1 / d->eta,
                                   d->alpha, d->shadowing, convention);
}

}  // namespace

bool has_glass_light(const Scene& scene) {
  if (!has_dielectric(scene)) return false;
  for (const Object& o : scene.objects)
    if (o.is_emitter()) return true;
  return false;
}

std::optional<std::string> glass_light_scene_refusal(const Scene& scene) {
  if (!scene.point_lights.empty()) return "it has point lights";
  if (scene.environment.radiance > 0 || scene.environment.map)
    return "its environment shines beside a light (only a black environment is solved with lights)";
  if (scene.closed) return "it is closed";
  if (!has_glass_light(scene)) return "it has no dielectric and emitter";
  const Plane plane = interface_plane(scene);
  const double camera_side = dot(scene.camera.center - plane.point, plane.normal);
  if (camera_side == 0) return "its camera lies in the glass's plane";
  const Vec3 far = camera_side > 0 ? -plane.normal : plane.normal;  // unit, toward the far side
  for (const Object& o : scene.objects) {
    if (const Dielectric* d = o.material.as<Dielectric>()) {
      if (d->smooth()) return fmt::format("its glass '{}' is smooth beside a light", o.name);
      const std::optional<Plane> own = plane_of(o.shape);
      if (!own) return fmt::format("its glass '{}' is a sphere beside a light", o.name);
      const double scale = std::fmax(1.0, max_abs_component(own->point));
      if (length(cross(own->normal, plane.normal)) > 1e-13 ||
          std::fabs(dot(own->point - plane.point, plane.normal)) > 1e-13 * scale)
        return fmt::format("object '{}' is not in the plane of the first glass", o.name);
      continue;
    }
    if (!is_planar(o.shape)) return fmt::format("object '{}' is a sphere (only planar lights and occluders)", o.name);
    if (o.material.albedo != 0)
      return fmt::format("object '{}' has albedo {} (light it reflected back through the glass is not modelled)",
                         o.name, o.material.albedo);
    if (!(height_range(o.shape, plane.point, far).lo > 0))
      return fmt::format("object '{}' is not wholly on the far side of the glass from the camera", o.name);
  }
  return std::nullopt;
}

double glass_light_radiance(const Scene& scene, const Vec3& p, const Vec3& wo, size_t receiver,
                            TransportConvention convention) {
  if (auto reason = glass_light_scene_refusal(scene)) refuse(scene, *reason);
  const GlassTransmissionReceiver model = receiver_at(scene, p, wo, receiver, convention);
  return reflected_radiance(model, mirrored_lights(scene, p, model.n, receiver, LightSelection::kUniform));
}

double glass_light_second_moment(Strategy strategy, const Scene& scene, const Vec3& p, const Vec3& wo,
                                 size_t receiver, TransportConvention convention, LightSelection selection) {
  if (auto reason = glass_light_scene_refusal(scene)) refuse(scene, *reason);
  if (is_path_tracer(strategy))
    refuse(scene, fmt::format("the path tracer '{}' has no single-sample variance model", strategy_name(strategy)));
  // The renderer's hemisphere strategies draw about the viewer's normal only:
  // they never reach a light behind the glass, and their mean is not this one.
  if (strategy == Strategy::kUniformHemisphere || strategy == Strategy::kCosineHemisphere)
    refuse(scene, fmt::format("strategy '{}' samples only the viewer's hemisphere, never the lights behind the glass",
                              strategy_name(strategy)));
  const GlassTransmissionReceiver model = receiver_at(scene, p, wo, receiver, convention);
  return receiver_second_moment(strategy, model, mirrored_lights(scene, p, model.n, receiver, selection));
}

namespace {

// f(hit, wo) at every pixel centre whose ray meets a glass first; 0 where it
// meets nothing (the environment is black).
template <class PerHit>
std::vector<double> glass_light_image(const Scene& scene, PerHit per_hit) {
  if (auto reason = glass_light_scene_refusal(scene)) refuse(scene, *reason);
  const Camera& camera = scene.camera;
  std::vector<double> image(size_t(camera.width_px) * size_t(camera.height_px));
  for (int py = 0; py < camera.height_px; ++py)
    for (int px = 0; px < camera.width_px; ++px) {
      const Camera::Ray ray = camera.pixel_center_ray(px, py);
      const std::optional<Hit> hit = intersect(scene, ray.origin, ray.direction);
      double value = 0;
      if (hit) {
        if (!scene.objects[hit->object_index].material.as<Dielectric>())
          refuse(scene, fmt::format("the ray of pixel ({}, {}) meets '{}' before any glass", px, py,
                                    scene.objects[hit->object_index].name));
        value = per_hit(hit->point, -normalize(ray.direction), hit->object_index);
      }
      image[size_t(py) * camera.width_px + px] = value;
    }
  return image;
}

}  // namespace

std::vector<double> glass_light_reference_image(const Scene& scene, int max_segments, TransportConvention convention) {
  if (max_segments < 1) throw Error(fmt::format("max_segments must be at least 1, got {}.", max_segments));
  return glass_light_image(scene, [&](const Vec3& p, const Vec3& wo, size_t index) {
    // Camera, interface, light: two segments.
    return max_segments < 2 ? 0.0 : glass_light_radiance(scene, p, wo, index, convention);
  });
}

std::vector<double> glass_light_second_moment_image(const Scene& scene, Strategy strategy,
                                                    TransportConvention convention, LightSelection selection) {
  return glass_light_image(scene, [&](const Vec3& p, const Vec3& wo, size_t index) {
    return glass_light_second_moment(strategy, scene, p, wo, index, convention, selection);
  });
}

}  // namespace furnace::analytic
