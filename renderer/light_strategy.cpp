#include "renderer/light_strategy.h"

#include <cmath>
#include <limits>
#include <variant>

#include "renderer/sampling.h"
#include "renderer/spherical_sampling.h"

namespace furnace {

namespace {
// The density of cosine-weighted directions on both sides, |cos θ|/(2π) (sr⁻¹).
double two_sided_cosine_pdf(const Vec3& w_local) { return std::fabs(w_local.z) * (0.5 * kInvPi); }
}  // namespace

namespace {

// ---------------------------------------------------------------------------
// Sampling one emitter, by area or by solid angle. The choice of method is a
// function of (shape, viewpoint, mode) only, so sample() and pdf() agree.

// cos θ' at a light point: signed for one-sided lights (the back has no
// emission, so no density), absolute for two-sided ones.
double light_cosine(const Vec3& light_normal, const Vec3& wi, bool two_sided) {
  const double c = dot(light_normal, -wi);
  return two_sided ? std::fabs(c) : c;
}

// DEFECT(cone_sampling_float): the cone of a sphere as a single-precision
// renderer computes it, cos θmax = sqrtf(1 − sin²θmax) and 1 − cos θmax by
// subtraction in float: nothing is left of 1 − cos θmax below ~6e-8 (a sphere
// under ~4e-7 sr), and it is off by tens of percent up to ~1e-6 sr.
ConeAperture float_cone_aperture(double sin2_theta_max) {
  const float cos_theta_max = std::sqrt(1.0f - float(sin2_theta_max));
  return {double(cos_theta_max), double(1.0f - cos_theta_max)};
}

// DEFECT(grazing_emitter_cosine): the smallest cos θ' the area-to-solid-angle
// conversion uses, a firefly guard that changes the density only where the
// light is seen within 2.9° of edge-on.
constexpr double kDefectGrazingCosine = 0.05;

// The solid-angle method of `emitter` from p (LightStrategy::method_at has
// already sent area sampling, and a shading point on the emitter itself, to
// the area method).
EmitterMethod solid_angle_method(const Object& emitter, const Vec3& p, Defect defect) {
  const Shape& shape = emitter.shape;
  // A two-sided planar light seen from behind is sampled as its mirror-oriented twin.
  return std::visit(
      overloaded{
          [&](const Sphere& s) -> EmitterMethod {
            const Vec3 to_center = s.center - p;
            const double d2 = length_squared(to_center);
            const double r2 = s.radius * s.radius;
            if (!(d2 > r2)) return std::monostate{};  // inside or on the sphere: no cone, area sampling
            const Frame frame = Frame::from_normal(to_center / std::sqrt(d2));
            if (defect == Defect::kConeSamplingFloat)
              return ConeSetup{s, frame, float_cone_aperture(r2 / d2)};  // DEFECT(cone_sampling_float)
            return ConeSetup{s, frame, ConeAperture::from_sin2(r2 / d2)};
          },
          [&](const Triangle& t) -> EmitterMethod {
            const bool flip = emitter.two_sided && dot(p - t.p0, t.normal()) < 0;
            if (auto sampler = SphericalTriangleSampler::make(flip ? Triangle{t.p0, t.p2, t.p1} : t, p)) return *sampler;
            return std::monostate{};
          },
          [&](const Rectangle& r) -> EmitterMethod {
            const bool flip = emitter.two_sided && dot(p - r.corner, r.normal()) < 0;
            if (auto sampler = SphericalRectangleSampler::make(flip ? Rectangle{r.corner, r.edge_v, r.edge_u} : r, p))
              return *sampler;
            return std::monostate{};
          },
          // No exact solid-angle map of a disk is used: area sampling.
          [](const Disk&) -> EmitterMethod { return std::monostate{}; }},
      shape);
}

// Density in solid angle of direction wi from p reaching the emitter at
// (point, normal), under `method`, excluding the light selection pmf;
// `pdf_area` is the emitter's density in area (AreaSampler::pdf_area).
// The one helper both LightStrategy::sample and LightStrategy::pdf use.
double emitter_pdf_solid_angle(const EmitterMethod& method, const Object& emitter, double pdf_area, const Vec3& p,
                               const Vec3& wi, const Vec3& point, const Vec3& normal, Defect defect) {
  // The solid-angle methods exist only for viewpoints in front of the light
  // (method_at), so every direction they cover meets its emitting side;
  // no cos θ' test for them, which round-off would fail at a sphere's silhouette.
  return std::visit(overloaded{[&](std::monostate) {
                                 double cos_light = light_cosine(normal, wi, emitter.two_sided);
                                 // DEFECT(grazing_emitter_cosine): cos θ' raised to kDefectGrazingCosine where it is smaller.
                                 if (defect == Defect::kGrazingEmitterCosine && cos_light > 0)
                                   cos_light = std::fmax(cos_light, kDefectGrazingCosine);
                                 return solid_angle_pdf_from_area(pdf_area, length_squared(point - p), cos_light);
                               },
                               [&](const ConeSetup& cone) {
                                 return uniform_cone_pdf(cone.frame.local_from_world(wi), cone.aperture);
                               },
                               [](const SphericalTriangleSampler& tri) { return tri.pdf(); },
                               [](const SphericalRectangleSampler& rect) { return rect.pdf(); }},
                    method);
}

struct EmitterPoint {
  Vec3 point, normal;
  // The sampled direction itself, when the method samples directions (cone,
  // spherical triangle): recomputing it from `point` would add round-off that
  // can push rim samples of a tiny cone out of its support.
  std::optional<Vec3> direction;
};

// First intersection of p + t·w (t > 0) with the sphere, exact in double
// precision; the discriminant in the form r² − |oc − (oc·w)w|², which does not
// cancel for far-away spheres. False if the ray misses.
bool intersect_sphere(const Sphere& s, const Vec3& p, const Vec3& w, EmitterPoint& q) {
  const Vec3 oc = p - s.center;
  const double b = dot(oc, w);
  const Vec3 perpendicular = oc - w * b;
  const double disc = s.radius * s.radius - length_squared(perpendicular);
  const double root = std::sqrt(std::fmax(disc, 0.0));  // rim directions of the cone: round-off below 0
  const double t = -b - root;
  if (!(t > 0)) return false;
  const Vec3 n = scene_normalize(p + w * t - s.center);
  q = EmitterPoint{s.center + n * s.radius, n, w};
  return true;
}

bool intersect_plane(const Vec3& plane_point, const Vec3& normal, const Vec3& p, const Vec3& w, EmitterPoint& q) {
  const double denom = dot(w, normal);
  if (denom == 0) return false;
  const double t = dot(plane_point - p, normal) / denom;
  if (!(t > 0)) return false;
  q = EmitterPoint{p + w * t, normal, w};
  return true;
}

// A point on the emitter by `method` into `q`; `area` samples the emitter's
// shape. False if the method finds none. (get_if, not std::visit: visit's
// returned value went through memory, and reading it back stalled the light
// strategies' profile; EmitterMethod's four alternatives are all handled.)
bool sample_emitter_point(const EmitterMethod& method, const AreaSampler& area, const Vec3& p, double u1, double u2,
                          EmitterPoint& q) {
  static_assert(std::variant_size_v<EmitterMethod> == 4, "sample_emitter_point handles every EmitterMethod");
  if (std::holds_alternative<std::monostate>(method)) {
    const AreaSample a = area.sample(u1, u2);
    q.point = a.point;
    q.normal = a.normal;
    q.direction.reset();
    return true;
  }
  if (const auto* cone = std::get_if<ConeSetup>(&method)) {
    const Vec3 w = cone->frame.world_from_local(sample_uniform_cone(u1, u2, cone->aperture));
    return intersect_sphere(cone->sphere, p, w, q);
  }
  if (const auto* tri = std::get_if<SphericalTriangleSampler>(&method))
    return intersect_plane(tri->triangle.p0, tri->triangle.normal(), p, tri->sample(u1, u2), q);
  const auto& rect = std::get<SphericalRectangleSampler>(method);
  q.point = rect.sample_point(u1, u2);
  q.normal = area.normal_at(q.point);
  q.direction.reset();
  return true;
}

}  // namespace

const EmitterMethod& LightStrategy::method_at(size_t object, const ShadingContext& ctx, EmitterSetups& setups) const {
  // Area sampling, or a shading point on the emitter itself: by area (a
  // sphere cannot use its cone from its own surface; only a two-sided sphere
  // seen from inside sees itself, and area sampling covers that).
  static const EmitterMethod kByArea{};
  if (emitter_sampling == EmitterSampling::kArea || object == ctx.object) return kByArea;
  const Object& emitter = scene->scene().objects[object];
  if (setups.holds(ctx) && object < setups.ready_.size()) {
    if (!setups.ready_[object]) {
      setups.methods_[object] = solid_angle_method(emitter, ctx.point, defect);
      setups.ready_[object] = 1;
    }
    return setups.methods_[object];
  }
  setups.scratch_ = solid_angle_method(emitter, ctx.point, defect);
  return setups.scratch_;
}

std::optional<LightSample> LightStrategy::sample(const ShadingContext& ctx, const Uniform3& u,
                                                 EmitterSetups* setups) const {
  // Filled in place in the caller's optional (one named return value).
  std::optional<LightSample> result(std::in_place);
  if (!sample(ctx, u, setups, *result)) result.reset();
  return result;
}

bool LightStrategy::sample(const ShadingContext& ctx, const Uniform3& u, EmitterSetups* setups, LightSample& s) const {
  if (setups) return sample_into(ctx, u, *setups, s);
  EmitterSetups unbound;
  return sample_into(ctx, u, unbound, s);
}

bool LightStrategy::sample_into(const ShadingContext& ctx, const Uniform3& u, EmitterSetups& setups,
                                LightSample& s) const {
  if (lights->count() == 0) return false;
  const size_t light = lights->select(u[0]);
  s.selection_pmf = lights->pmf(light);
  const double pmf = s.selection_pmf;
  if (!(pmf > 0)) return false;  // a light of zero power is never chosen
  // DEFECT(power_selection_uniform_pmf): chosen by power, divided by the uniform pmf 1/K.
  const double pmf_in_weight = defect == Defect::kPowerSelectionUniformPmf ? 1.0 / double(lights->count()) : pmf;
  double pdf_for_weight = 0;
  if (lights->is_point_light(light)) {
    // A delta in position: the one direction to the light, Li = I/r².
    const PointLight& point = scene->scene().point_lights[lights->point_lights[light - lights->emitters.size()]];
    const Vec3 to_light = point.position - ctx.point;
    const double distance_squared = length_squared(to_light);
    if (!(distance_squared > 0)) return false;
    s.wi_world = to_light / std::sqrt(distance_squared);
    s.delta = true;
    s.radiance = point.intensity / distance_squared;
    s.shadow_origin = ray_origin(ctx.point, ctx.normal, s.wi_world, defect);  // DEFECT(ray_offset_1e4) inside
    const Vec3 segment = point.position - s.shadow_origin;
    s.shadow_t_max = scene_length(segment);
    if (!(s.shadow_t_max > 0)) return false;
    s.shadow_direction = segment / s.shadow_t_max;
    s.shadow_ends = RayEnds{ctx.object, RayEnds::kNone};  // no object to name for the end: the filter decides
    const Vec3 wi_local = ctx.frame.local_from_world(s.wi_world);
    s.weight = ctx.bsdf.eval(ctx.wo_local, wi_local) * std::fabs(wi_local.z) / pmf_in_weight;
    s.assume_visible = defect == Defect::kSkipShadowRay;  // DEFECT(skip_shadow_ray)
    return true;
  }
  if (lights->is_environment(light)) {
    double environment_pdf = 0;  // density in solid angle, selection pmf excluded
    if (const EnvironmentSampler* map = lights->environment_sampler.get()) {
      // An image-based environment: its texels by importance (environment_sampler.h);
      // directions below the horizon get weight 0 from the cosine below.
      const auto e = map->sample(u[1], u[2], defect);  // DEFECT(env_missing_sin_theta) inside
      if (!e) return false;
      s.wi_world = e->wi_world;
      environment_pdf = e->pdf_solid_angle;
    } else if (ctx.bsdf.transmits()) {
      // A constant environment behind a surface that transmits: cosine-weighted
      // directions on either side, each with probability 1/2 (u[1] picks the
      // side and is rescaled to drive the warp).
      const bool below = u[1] >= 0.5;
      const Vec3 w = sample_cosine_hemisphere(below ? 2.0 * u[1] - 1.0 : 2.0 * u[1], u[2]);
      const Vec3 wi_local = below ? Vec3{w.x, w.y, -w.z} : w;
      s.wi_world = ctx.frame.world_from_local(wi_local);
      environment_pdf = two_sided_cosine_pdf(wi_local);
    } else {
      // A constant environment: cosine-weighted directions (its exact density).
      const Vec3 wi_local = sample_cosine_hemisphere(u[1], u[2]);
      s.wi_world = ctx.frame.world_from_local(wi_local);
      environment_pdf = cosine_hemisphere_pdf(wi_local);
    }
    s.pdf_solid_angle = pmf * environment_pdf;
    s.radiance = environment_radiance(scene->scene().environment, s.wi_world);
    s.shadow_origin = ray_origin(ctx.point, ctx.normal, s.wi_world, defect);  // DEFECT(ray_offset_1e4) inside
    s.shadow_direction = s.wi_world;
    s.shadow_t_max = std::numeric_limits<double>::infinity();
    s.shadow_ends = RayEnds{ctx.object, RayEnds::kNone};
    pdf_for_weight = pmf_in_weight * environment_pdf;
  } else {
    const size_t object = lights->emitters[light];
    const Object& emitter = scene->scene().objects[object];
    const bool self = object == ctx.object;
    // A flat light cannot light its own points (they see it edge-on).
    if (self && is_planar(emitter.shape)) return false;
    const EmitterMethod& method = method_at(object, ctx, setups);
    const AreaSampler& area = lights->area_sampler(light);
    EmitterPoint q;
    if (!sample_emitter_point(method, area, ctx.point, u[1], u[2], q)) return false;
    const Vec3 to_light = q.point - ctx.point;
    const double distance_squared = length_squared(to_light);
    if (!(distance_squared > 0)) return false;
    const double distance = std::sqrt(distance_squared), inv_distance = 1.0 / distance;
    s.wi_world = q.direction ? *q.direction : to_light * inv_distance;
    const double emitter_pdf =
        emitter_pdf_solid_angle(method, emitter, area.pdf_area(), ctx.point, s.wi_world, q.point, q.normal, defect);
    s.pdf_solid_angle = pmf * emitter_pdf;
    s.radiance = emitter.emitted_radiance;
    pdf_for_weight = pmf_in_weight * emitter_pdf;
    // DEFECT(drop_light_cosine): area sampling converts to solid angle with r² only, forgetting 1/cos θ'.
    if (defect == Defect::kDropLightCosine && std::holds_alternative<std::monostate>(method) &&
        light_cosine(q.normal, s.wi_world, emitter.two_sided) > 0)
      pdf_for_weight = pmf_in_weight * solid_angle_pdf_from_area(area.pdf_area(), distance_squared, 1.0);
    // Shadow ray from the shading point to the light point (the intersection
    // filters keep it off both surfaces).
    s.shadow_origin = ray_origin(ctx.point, ctx.normal, s.wi_world, defect);  // DEFECT(ray_offset_1e4) inside
    if (s.shadow_origin == ctx.point) {
      // The segment is to_light: its length and direction are known already.
      s.shadow_t_max = distance;
      s.shadow_direction = q.direction ? to_light * inv_distance : s.wi_world;
    } else {
      const Vec3 segment = q.point - s.shadow_origin;
      s.shadow_t_max = scene_length(segment);
      s.shadow_direction = segment / s.shadow_t_max;
    }
    s.shadow_ends = RayEnds{ctx.object, object};
  }
  if (!(s.pdf_solid_angle > 0)) return false;  // back of a one-sided light, or a grazing point
  const Vec3 wi_local = ctx.frame.local_from_world(s.wi_world);
  s.weight = ctx.bsdf.eval(ctx.wo_local, wi_local) * std::fabs(wi_local.z) / pdf_in_weight(pdf_for_weight, defect);
  // DEFECT(skip_shadow_ray): every light sample is taken as visible.
  s.assume_visible = defect == Defect::kSkipShadowRay;
  return true;
}

double LightStrategy::pdf(const ShadingContext& ctx, const Vec3& wi_world, const std::optional<SurfaceHit>& hit,
                          EmitterSetups* setups) const {
  if (!setups) {
    EmitterSetups unbound;
    return pdf(ctx, wi_world, hit, &unbound);
  }
  if (lights->count() == 0) return 0.0;
  // Point lights are never found by a ray: only emitters and the environment have a density here.
  if (!hit) {
    if (!lights->environment) return 0.0;
    const double pmf = lights->pmf(lights->count() - 1);
    if (const EnvironmentSampler* map = lights->environment_sampler.get()) return pmf * map->pdf_solid_angle(wi_world);
    const Vec3 wi_local = ctx.frame.local_from_world(wi_world);
    return pmf * (ctx.bsdf.transmits() ? two_sided_cosine_pdf(wi_local) : cosine_hemisphere_pdf(wi_local));
  }
  const size_t light = lights->light_of_object(hit->object);
  const double pmf = lights->pmf(light);
  const Object& o = scene->scene().objects[hit->object];
  if (!o.is_emitter() || !(hit->front_facing || o.two_sided)) return 0.0;
  const bool self = hit->object == ctx.object;
  if (self && is_planar(o.shape)) return 0.0;  // as in sample()
  const EmitterMethod& method = method_at(hit->object, ctx, *setups);
  return pmf * emitter_pdf_solid_angle(method, o, lights->area_sampler(light).pdf_area(), ctx.point, wi_world,
                                       hit->point, hit->normal, defect);
}

double delta_light_mis_weight(const LightSample& s, double p_bsdf, Defect defect) {
  // DEFECT(point_light_mis_weighted): the delta sample weighed as if its density were its pmf.
  if (defect == Defect::kPointLightMisWeighted) return s.selection_pmf / (s.selection_pmf + p_bsdf);
  return 1.0;
}

bool light_visible(const EmbreeScene& scene, const LightSample& s, TraceCounters& counters) {
  if (s.assume_visible) return true;  // DEFECT(skip_shadow_ray)
  ++counters.rays;
  const RayArgs ray = shadow_ray(s);
  return !scene.occluded(ray.origin, ray.direction, ray.t_max, ray.ends);
}

}  // namespace furnace
