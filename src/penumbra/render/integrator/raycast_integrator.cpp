#include "penumbra/render/integrator/raycast_integrator.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/render/film.h"
#include "penumbra/render/material/material.h"
#include "penumbra/render/render_job.h"
#include "penumbra/render/sampling.h"

namespace penumbra {

RaycastIntegrator::RaycastIntegrator(const World& world, const ParamList& params) : world_(world) {
  const std::string mode = params.get_string("mode", "eyelight");
  if (mode == "normal") mode_ = Mode::kNormal;
  else if (mode == "albedo") mode_ = Mode::kAlbedo;
  else if (mode == "eyelight") mode_ = Mode::kEyelight;
  else if (mode == "cost") mode_ = Mode::kCost;
  else throw Error("raycast: unknown mode '" + mode + "' (valid: normal, albedo, eyelight, cost)");
  if (mode_ == Mode::kCost) {
    const std::string cost = params.get_string("cost", "both");
    if (cost == "nodes") cost_ = Cost::kNodes;
    else if (cost == "prims") cost_ = Cost::kPrims;
    else if (cost == "both") cost_ = Cost::kBoth;
    else throw Error("raycast: unknown cost '" + cost + "' (valid: nodes, prims, both)");
    scale_ = params.get_real("scale", 0.0, 0.0, 1e12);
    raw_ = params.get_flag("raw");
    const std::string rays = params.get_string("rays", "camera");
    if (rays == "camera")
      rays_ = Rays::kCamera;
    else if (rays == "bounce")
      rays_ = Rays::kBounce;
    else if (rays == "shadow")
      rays_ = Rays::kShadow;
    else
      throw Error("raycast: unknown rays '" + rays + "' (valid: camera, bounce, shadow)");
    if (rays_ == Rays::kShadow) {
      if (world.lights().empty())
        throw Error("raycast: rays=shadow needs a light in the scene, and it has none");
      lights_ = std::make_unique<LightSampler>(world.lights(), "power");
    }
  }
  params.check_all_used();
}

std::string RaycastIntegrator::name() const {
  switch (mode_) {
    case Mode::kNormal:
      return "raycast:mode=normal";
    case Mode::kAlbedo:
      return "raycast:mode=albedo";
    case Mode::kCost: {
      std::string s = "raycast:mode=cost";
      if (cost_ != Cost::kBoth) s += cost_ == Cost::kNodes ? ",cost=nodes" : ",cost=prims";
      if (rays_ != Rays::kCamera) s += rays_ == Rays::kBounce ? ",rays=bounce" : ",rays=shadow";
      if (scale_ > 0) s += fmt::format(",scale={}", scale_);
      if (raw_) s += ",raw=true";
      return s;
    }
    case Mode::kEyelight:
    default:
      return "raycast";
  }
}

TraversalCost RaycastIntegrator::secondary_cost(const Ray& ray, Sampler& sampler,
                                                RayCounter& counter) const {
  TraversalCost c;
  SurfaceInteraction si;
  if (!world_.intersect(ray, si, counter)) return c;
  ++counter.rays;
  if (rays_ == Rays::kBounce) {
    Vec3 d = si.to_world(sample_cosine_hemisphere(sampler.get_2d()));
    if (dot(d, si.ng) * dot(si.wo, si.ng) < 0.0f) d = -d;  // the side the camera sees
    Hit hit;
    world_.closest_hit_cost(si.spawn_ray(d, ray.time), hit, c);
    return c;
  }
  const float u_light = sampler.get_1d();
  const Vec2 u = sampler.get_2d();
  const SampledLight picked = lights_->sample(u_light);
  if (!picked.light) return c;
  const LightSample ls = picked.light->sample_li(si.p, u);
  if (!(ls.pdf > 0.0f)) return c;
  world_.occluded_cost(si.shadow_ray(ls, ray.time), c);
  return c;
}

Rgb RaycastIntegrator::li(const Ray& ray, Sampler& sampler, RayCounter& counter) const {
  if (mode_ == Mode::kCost) {
    TraversalCost c;
    if (rays_ == Rays::kCamera) {
      Hit hit;
      world_.closest_hit_cost(ray, hit, c);
      ++counter.rays;
    } else {
      c = secondary_cost(ray, sampler, counter);
    }
    const double n = cost_ == Cost::kNodes   ? double(c.nodes)
                     : cost_ == Cost::kPrims ? double(c.prims)
                                             : double(c.nodes + c.prims);
    return Rgb(float(n));
  }
  SurfaceInteraction si;
  if (!world_.intersect(ray, si, counter)) return world_.escaped(ray);
  MaterialScratch scratch;
  si.material = &si.material->at(si, scratch);  // textures evaluated at the hit
  switch (mode_) {
    case Mode::kNormal:
      return {0.5f * (si.ns.x + 1.0f), 0.5f * (si.ns.y + 1.0f), 0.5f * (si.ns.z + 1.0f)};
    case Mode::kAlbedo:
      return si.emitted.is_black() ? si.material->albedo() : si.emitted;
    case Mode::kEyelight:
    default:
      if (!si.emitted.is_black()) return si.emitted;
      return si.material->albedo() * std::fabs(dot(si.ns, si.wo));
  }
}

RenderStats RaycastIntegrator::render(RenderJob& job) {
  RenderStats stats = SamplingIntegrator::render(job);
  if (mode_ != Mode::kCost || raw_ || stats.spp_done == 0) return stats;
  const double scale = colour_costs(*job.film);
  const char* what = cost_ == Cost::kNodes   ? "node visits"
                     : cost_ == Cost::kPrims ? "primitive tests"
                                             : "node visits + primitive tests";
  const char* rays = rays_ == Rays::kCamera   ? "per camera ray"
                     : rays_ == Rays::kBounce ? "of the bounce ray from each camera hit"
                                              : "of the shadow ray from each camera hit";
  stats.note =
      fmt::format("cost view: {} {}, colour bar 0 (bottom) to {:g} (top)", what, rays, scale);
  return stats;
}

Rgb heat_colour(float x) {
  // Our own control points, evenly spaced: dark to bright, hue turning from blue through red to
  // yellow, so that equal steps of cost read as steps of brightness.
  static constexpr std::array<Rgb, 6> kStops = {Rgb(0.0f, 0.0f, 0.0f),  Rgb(0.10f, 0.05f, 0.45f),
                                                Rgb(0.55f, 0.05f, 0.55f), Rgb(0.90f, 0.20f, 0.15f),
                                                Rgb(1.0f, 0.75f, 0.05f),  Rgb(1.0f, 1.0f, 1.0f)};
  if (!(x > 0.0f)) return kStops.front();  // also a NaN
  if (x >= 1.0f) return kStops.back();
  const float f = x * float(kStops.size() - 1);
  const auto i = size_t(f);
  const float t = f - float(i);
  return kStops[i] * (1.0f - t) + kStops[i + 1] * t;
}

double RaycastIntegrator::colour_costs(Film& film) const {
  const RgbImage mean = film.resolve();
  const int w = film.width(), h = film.height();
  double scale = scale_;
  if (!(scale > 0)) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) scale = std::max(scale, double(mean.at(x, y).r));
    if (!(scale > 0)) scale = 1;  // nothing was counted: every pixel black
  }
  // The colour bar: the rightmost columns (a 40th of the width, at least 4 pixels) when the image
  // is wide enough to keep most of the picture, after a black column.
  const int bar = w >= 32 ? std::max(4, w / 40) : 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Rgb c;
      if (bar > 0 && x >= w - bar) {
        c = heat_colour(h > 1 ? float(h - 1 - y) / float(h - 1) : 1.0f);
      } else if (bar > 0 && x == w - bar - 1) {
        c = Rgb(0.0f);
      } else {
        c = heat_colour(float(double(mean.at(x, y).r) / scale));
      }
      film.set_pixel(x, y, c, film.samples(x, y));
    }
  return scale;
}

}  // namespace penumbra
