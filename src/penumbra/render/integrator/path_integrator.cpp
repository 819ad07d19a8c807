#include "penumbra/render/integrator/path_integrator.h"

#include <algorithm>
#include <cmath>
#include <typeinfo>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/render/material/material.h"
#include "penumbra/render/sampler/sobol_sampler.h"
#include "penumbra/render/sampling.h"

namespace penumbra {

namespace {

PathIntegrator::Strategy parse_strategy(const std::string& s) {
  if (s == "mis") return PathIntegrator::Strategy::kMis;
  if (s == "nee") return PathIntegrator::Strategy::kNee;
  if (s == "bsdf") return PathIntegrator::Strategy::kBsdf;
  throw Error("path: unknown strategy '" + s + "' (valid: mis, nee, bsdf)");
}

const char* strategy_name(PathIntegrator::Strategy s) {
  switch (s) {
    case PathIntegrator::Strategy::kNee:
      return "nee";
    case PathIntegrator::Strategy::kBsdf:
      return "bsdf";
    case PathIntegrator::Strategy::kMis:
    default:
      return "mis";
  }
}

/// The lights a path samples by shadow rays: all of them, or only delta lights for `bsdf`.
std::vector<const Light*> sampled_lights(const World& world, PathIntegrator::Strategy s) {
  std::vector<const Light*> out;
  for (const Light* l : world.lights())
    if (s != PathIntegrator::Strategy::kBsdf || l->is_delta()) out.push_back(l);
  return out;
}

}  // namespace

PathIntegrator::Lanes PathIntegrator::parse_lanes(const std::string& s) {
  if (s == "auto") return Lanes::kAuto;
  if (s == "on") return Lanes::kOn;
  if (s == "off") return Lanes::kOff;
  throw Error("path: unknown lanes '" + s + "' (valid: auto, on, off)");
}

PathIntegrator::PathIntegrator(const World& world, const ParamList& params, int max_depth)
    : world_(world),
      strategy_(parse_strategy(params.get_string("strategy", "mis"))),
      max_depth_(static_cast<int>(params.get_int("max_depth", max_depth, -1, 1 << 30))),
      rr_depth_(static_cast<int>(params.get_int("rr_depth", 3, 0, 1 << 30))),
      rr_exponent_(static_cast<float>(params.get_real("rr_exponent", 0.5, 1e-3, 1.0))),
      light_sampler_(sampled_lights(world, strategy_), params.get_string("light_sampler", "power")),
      lanes_mode_(parse_lanes(params.get_string("lanes", "auto"))) {
  params.check_all_used();
  if (lanes_mode_ != Lanes::kOff) lanes_ = PathLanes::make(*this, world, lanes_mode_ == Lanes::kOn);
}

PathIntegrator::~PathIntegrator() = default;

void PathIntegrator::render_tile(RenderJob& job, int x0, int y0, int x1, int y1, int first,
                                 int count, RayCounter& counter) const {
  if (lanes_)
    lanes_->render_tile(job, x0, y0, x1, y1, first, count, counter);
  else
    SamplingIntegrator::render_tile(job, x0, y0, x1, y1, first, count, counter);
}

std::string PathIntegrator::name() const {
  std::string s = fmt::format("path:strategy={}", strategy_name(strategy_));
  if (max_depth_ >= 0) s += fmt::format(",max_depth={}", max_depth_);
  if (rr_depth_ != 3) s += fmt::format(",rr_depth={}", rr_depth_);
  if (rr_exponent_ != 0.5f) s += fmt::format(",rr_exponent={}", rr_exponent_);
  if (light_sampler_.strategy() != "power") s += ",light_sampler=" + light_sampler_.strategy();
  if (lanes_mode_ != Lanes::kAuto) s += lanes_mode_ == Lanes::kOn ? ",lanes=on" : ",lanes=off";
  return s;
}

float PathIntegrator::emission_weight(const Light& light, float bsdf_pdf, Vec3 from, Vec3 wi,
                                      const LightPoint& hit) const {
  if (strategy_ == Strategy::kBsdf) return 1.0f;
  if (strategy_ == Strategy::kNee) return 0.0f;
  const float light_pdf = light_sampler_.pmf(&light) * light.pdf_li(from, wi, hit);
  return power_heuristic(1.0f, bsdf_pdf, 1.0f, light_pdf);
}

Rgb PathIntegrator::sample_light(const SurfaceInteraction& si, const Material& m, Vec3 wo,
                                 float time, Vec2 u, RayCounter& counter) const {
  // One pair: the light from its first number, whose unused part, stretched back to [0, 1),
  // then places the sample on that light (as Mitsuba 3's sample_emitter_direction reuses it):
  // a dimension less per vertex, and the pair stays stratified over lights and points together.
  // The remainder in a variable of its own: written through a pointer into u.x, then read back
  // with u.y as one 8-byte load, it could not be forwarded from the two stores (a stall).
  float u_rest = u.x;
  const SampledLight picked = light_sampler_.sample(u.x, &u_rest);
  if (!picked.light || !(picked.pmf > 0.0f)) return {};
  const LightSample ls = picked.light->sample_li(si.p, {u_rest, u.y});
  if (ls.li.is_black() || !(ls.pdf > 0.0f)) return {};
  const Vec3 wi = si.to_local(ls.wi);
  const Rgb f = m.eval(wo, wi) * std::fabs(dot(ls.wi, si.ns));
  if (f.is_black()) return {};
  if (world_.occluded(si.shadow_ray(ls, time), counter)) return {};
  const float light_pdf = picked.pmf * ls.pdf;
  if (ls.delta || strategy_ != Strategy::kMis) return f * ls.li / light_pdf;
  return f * ls.li * (power_heuristic(1.0f, light_pdf, 1.0f, m.pdf(wo, wi)) / light_pdf);
}

Rgb PathIntegrator::li(const Ray& ray, Sampler& sampler, RayCounter& counter) const {
  // One type test per camera sample buys inlined sampler calls for the rest of the path.
  if (typeid(sampler) == typeid(SobolSampler))
    return trace(ray, static_cast<SobolSampler&>(sampler), counter);
  return trace(ray, sampler, counter);
}

template <class S>
Rgb PathIntegrator::trace(const Ray& camera_ray, S& sampler, RayCounter& counter) const {
  PathState st;
  st.ray = camera_ray;
  // One interaction for the whole path: World::intersect writes every field of it at each hit,
  // and declared in the loop its zero-initialisation (a 144-byte memset call) ran per bounce,
  // 2.7 % of a Cornell box render in perf.
  SurfaceInteraction si;
  for (int depth = 0;; ++depth) {
    if (!world_.intersect(st.ray, si, counter)) {
      add_escaped(st);
      break;
    }
    if (!si.emitted.is_black()) add_emitted(si, st);
    if (max_depth_ >= 0 && depth >= max_depth_) break;
    if (!scatter(si, depth, sampler, st, counter)) break;
  }
  return st.radiance;
}

void PathIntegrator::add_escaped(PathState& st) const {
  for (const Light* light : world_.infinite_lights()) {
    const Rgb le = light->le(st.ray);
    if (le.is_black()) continue;
    const float w =
        st.specular ? 1.0f : emission_weight(*light, st.bsdf_pdf, st.from, st.ray.d, {});
    st.radiance += st.beta * le * w;
  }
}

void PathIntegrator::add_emitted(const SurfaceInteraction& si, PathState& st) const {
  const float w = st.specular ? 1.0f
                              : emission_weight(*si.area_light, st.bsdf_pdf, st.from, st.ray.d,
                                                si.light_point());
  st.radiance += st.beta * si.emitted * w;
}

template <class S>
bool PathIntegrator::scatter(const SurfaceInteraction& si, int depth, S& sampler, PathState& st,
                             RayCounter& counter) const {
  MaterialScratch scratch;
  const Material& m = si.material->at(si, scratch);  // textures evaluated at the hit
  const Vec3 wo = si.to_local(si.wo);
  // The vertex's numbers in their fixed order: the light pair (drawn where a light is
  // sampled, whether or not the sample is used, so that every such vertex takes the same
  // dimensions), the lobe number, the BSDF pair, the roulette number.
  const bool nee = m.has_non_specular() && !light_sampler_.lights().empty();
  const Vec2 u_light = nee ? sampler.get_2d() : Vec2{};
  const float uc = sampler.get_1d();
  const Vec2 u = sampler.get_2d();
  const float u_rr = sampler.get_1d();
  // The continuation sampled from the BSDF before the light: its chain of dependent
  // operations (the concentric map's polynomials, a square root) then runs beside the light
  // sample's set-up instead of after the shadow ray.
  const auto bs = m.sample(wo, uc, u, TransportMode::kRadiance);
  // Next-event estimation at non-specular vertices.
  if (nee) st.radiance += st.beta * sample_light(si, m, wo, st.ray.time, u_light, counter);
  if (!bs || bs->f.is_black() || !(bs->pdf > 0.0f)) return false;
  const Vec3 wi = si.to_world(bs->wi);
  st.beta *= bs->f * (std::fabs(dot(wi, si.ns)) / bs->pdf);
  if (!(st.beta.max_channel() > 0.0f) || !std::isfinite(st.beta.max_channel())) return false;
  st.specular = bs->is_specular();
  st.bsdf_pdf = bs->pdf;
  st.from = si.p;
  if (bs->is_transmission()) st.eta_scale *= bs->eta * bs->eta;
  // The next ray written field by field, as si.spawn_ray(wi, ray.time) would make it: a whole
  // Ray assigned from a temporary was copied with one 32-byte load over the temporary's
  // narrower stores, which cannot be forwarded (perf put 10 % of the loop's samples on the
  // instruction after it; paired timings could not tell the gain from noise).
  st.ray.o = offset_ray_origin(si.p, si.p_error, si.ng, wi);
  st.ray.d = wi;
  st.ray.tmin = 0.0f;
  st.ray.tmax = kInfinity;

  // Russian roulette on the throughput, undoing refraction's radiance scaling (pbrt-v4), with
  // the survival probability (max beta eta^2)^rr_exponent: the square root by default, as
  // Cycles does, which ends dim paths later than pbrt's and Mitsuba's exponent 1 and on the
  // Cornell box gives 18 % less MSE for 9 % more time (docs/rendering.md).
  const float r = st.beta.max_channel() * st.eta_scale;
  const float rr = rr_exponent_ == 0.5f   ? std::sqrt(r)
                   : rr_exponent_ == 1.0f ? r
                                          : std::pow(r, rr_exponent_);
  if (depth + 1 >= rr_depth_ && rr < 1.0f) {
    const float q = std::max(0.05f, 1.0f - rr);
    if (u_rr < q) return false;
    st.beta = st.beta / (1.0f - q);
  }
  return true;
}

// The lanes' scalar vertices (path_lanes.cpp) use these two.
template bool PathIntegrator::scatter<SobolSampler>(const SurfaceInteraction&, int, SobolSampler&,
                                                    PathState&, RayCounter&) const;
template bool PathIntegrator::scatter<Sampler>(const SurfaceInteraction&, int, Sampler&, PathState&,
                                               RayCounter&) const;

}  // namespace penumbra
