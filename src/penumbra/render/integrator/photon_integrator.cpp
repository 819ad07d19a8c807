#include "penumbra/render/integrator/photon_integrator.h"

#include <atomic>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/integrator/direct_lighting.h"
#include "penumbra/render/integrator/scatter.h"
#include "penumbra/render/photon/photon_tracer.h"
#include "penumbra/render/render_job.h"

namespace penumbra {

namespace {

/// Specular bounces followed when max_depth is unbounded: each keeps at most the weight it had,
/// so this only cuts paths trapped between mirrors.
constexpr int kMaxSpecularChain = 64;
/// Irradiance is precomputed at as many points as a 1 / kIrradianceStride of the global photons
/// would give (Christensen 1999 uses a quarter of the photons).
constexpr size_t kIrradianceStride = 4;
/// Precomputed irradiance is used at a point when the estimate's normal lies within about 25
/// degrees of the point's.
constexpr float kIrradianceNormalCos = 0.9f;

PhotonIntegrator::Show parse_show(const std::string& s) {
  if (s == "none") return PhotonIntegrator::Show::kNone;
  if (s == "global") return PhotonIntegrator::Show::kGlobal;
  if (s == "caustic") return PhotonIntegrator::Show::kCaustic;
  throw Error("photon: unknown show '" + s + "' (valid: none, global, caustic)");
}

const char* show_name(PhotonIntegrator::Show s) {
  return s == PhotonIntegrator::Show::kGlobal    ? "global"
         : s == PhotonIntegrator::Show::kCaustic ? "caustic"
                                                 : "none";
}

/// thread_local scratch for the kd-tree queries of one thread: li is const and runs on many.
std::vector<KdNeighbor>& query_scratch() {
  thread_local std::vector<KdNeighbor> v;
  return v;
}

}  // namespace

PhotonIntegrator::PhotonIntegrator(const World& world, const ParamList& params,
                                   const RenderSettings& settings)
    : world_(world),
      global_photons_(uint64_t(params.get_int("photons", 200000, 0, 1ll << 32))),
      caustic_photons_(uint64_t(params.get_int("caustic_photons", 200000, 0, 1ll << 32))),
      gather_rays_(int(params.get_int("gather", 1, 0, 1 << 16))),
      use_irradiance_(params.has("irradiance") ? params.get_flag("irradiance") : true),
      show_(parse_show(params.get_string("show", "none"))),
      max_depth_(int(params.get_int("max_depth", settings.max_depth.value_or(-1), -1, 1 << 20))),
      seed_(settings.seed),
      light_sampler_(world.lights(), "power") {
  const float diag = length(world.bounds().diagonal());
  const float scale = std::isfinite(diag) && diag > 0.0f ? diag : 1.0f;
  global_query_.k = int(params.get_int("k", 100, 1, 1 << 16));
  global_query_.max_radius = float(params.get_real("max_radius", 0.05 * scale, 1e-30, 1e30));
  caustic_query_.k = int(params.get_int("caustic_k", 50, 1, 1 << 16));
  caustic_query_.max_radius =
      float(params.get_real("caustic_max_radius", 0.01 * scale, 1e-30, 1e30));
  params.check_all_used();
}

std::string PhotonIntegrator::name() const {
  std::string s = fmt::format("photon:photons={},caustic_photons={},k={},caustic_k={},gather={}",
                              global_photons_, caustic_photons_, global_query_.k, caustic_query_.k,
                              gather_rays_);
  s += fmt::format(",max_radius={:g},caustic_max_radius={:g}", global_query_.max_radius,
                   caustic_query_.max_radius);
  if (!use_irradiance_) s += ",irradiance=false";
  if (show_ != Show::kNone) s += fmt::format(",show={}", show_name(show_));
  if (max_depth_ >= 0) s += fmt::format(",max_depth={}", max_depth_);
  return s;
}

void PhotonIntegrator::preprocess(RenderJob& job) {
  const PhotonTracer tracer(world_, max_depth_);
  // A map beyond the memory limit is refused naming the parameter that sized it.
  const auto named = [](const char* param, uint64_t n, const auto& trace) {
    try {
      return trace();
    } catch (const Error& e) {
      throw Error(fmt::format("photon: {}={}: {}", param, n, e.what()));
    }
  };
  // The caustic map, then the global map with the surface normals of the photons that will
  // carry precomputed irradiance.
  job.report_preprocess("caustic photons", 0.0);
  PhotonBatch caustic = named("caustic_photons", caustic_photons_, [&] {
    return tracer.trace_batch(caustic_photons_, hash_combine(seed_, 0xca05), PhotonStore::kCaustic,
                              job.options.cancel,
                              [&](double f) { job.report_preprocess("caustic photons", f); });
  });
  caustic_ = PhotonMap(std::move(caustic.photons));
  if (job.cancelled()) return;
  job.report_preprocess("global photons", 0.0);
  PhotonBatch global = named("photons", global_photons_, [&] {
    return tracer.trace_batch(global_photons_, hash_combine(seed_, 0x610b), PhotonStore::kAll,
                              job.options.cancel,
                              [&](double f) { job.report_preprocess("global photons", f); });
  });
  global_ = PhotonMap(std::move(global.photons));
  if (job.cancelled() || !use_irradiance_) return;
  // Where irradiance is precomputed: the hits of a separate, smaller set of photons, so that the
  // points are distributed like the photons but independent of them. At the map's own photons,
  // a point in a locally sparse patch would have a large Voronoi cell (be the nearest point for
  // many lookups) and a low estimate: a bias of about -1/k, measured -1.0% at k = 50.
  const PhotonBatch sites = named("photons", global_photons_, [&] {
    return tracer.trace_batch(global_photons_ / kIrradianceStride, hash_combine(seed_, 0x5173),
                              PhotonStore::kAll, job.options.cancel, {}, true);
  });
  std::vector<IrradiancePoint> points;
  points.reserve(sites.photons.size());
  for (size_t i = 0; i < sites.photons.size(); ++i)
    points.push_back({sites.photons[i].p, sites.normals[i], {}});
  if (job.cancelled() || points.empty()) return;

  // Irradiance at each point, from the whole map.
  job.report_preprocess("irradiance", 0.0);
  std::atomic<size_t> done{0};
  parallel_for_range(
      points.size(),
      [&](size_t a, size_t b) {
        if (job.cancelled()) return;
        for (size_t i = a; i < b; ++i)
          points[i].e =
              global_.irradiance(points[i].p, points[i].n.decode(), global_query_, query_scratch());
        const size_t n = done.fetch_add(b - a) + (b - a);
        job.report_preprocess("irradiance", double(n) / double(points.size()));
      },
      1024);
  irradiance_ = PointKdTree<IrradiancePoint>(std::move(points));
}

Rgb PhotonIntegrator::global_radiance(const SurfaceInteraction& si, const Material& m) const {
  const BsdfFlags flags = m.flags();
  const bool lambertian = (flags & kBsdfDiffuse) && !(flags & (kBsdfGlossy | kBsdfTransmission));
  if (use_irradiance_ && lambertian && !irradiance_.empty()) {
    const Vec3 n = face_forward(si.ng, si.wo);
    std::vector<KdNeighbor>& nb = query_scratch();
    const float r = global_query_.max_radius;
    irradiance_.nearest(si.p, 1, r * r, nb, [&](const IrradiancePoint& ip) {
      return dot(ip.n.decode(), n) >= kIrradianceNormalCos;
    });
    if (!nb.empty()) {
      // A Lambertian BSDF is constant: its value towards the normal is its value everywhere.
      const Vec3 wo = si.to_local(si.wo);
      const Rgb f = m.eval(wo, {0.0f, 0.0f, wo.z >= 0.0f ? 1.0f : -1.0f});
      return f * irradiance_.points()[nb[0].index].e;
    }
  }
  return global_.radiance(si, m, global_query_, query_scratch());
}

Rgb PhotonIntegrator::gather(const SurfaceInteraction& si, const Material& m, float time,
                             Sampler& sampler, RayCounter& counter) const {
  Rgb beta(1.0f);
  Ray ray;
  ray.time = time;
  if (!scatter(si, m, sampler, beta, ray)) return {};
  const int limit = max_depth_ >= 0 ? max_depth_ : kMaxSpecularChain;
  for (int depth = 1;; ++depth) {
    // Light reached without another non-specular bounce is direct light or a caustic at si:
    // the shadow rays and the caustic map count it.
    SurfaceInteraction y;
    if (!world_.intersect(ray, y, counter)) return {};
    MaterialScratch scratch;
    const Material& my = y.material->at(y, scratch);
    if (my.has_non_specular()) return beta * global_radiance(y, my);
    if (depth >= limit || !scatter(y, my, sampler, beta, ray)) return {};
  }
}

Rgb PhotonIntegrator::li(const Ray& camera_ray, Sampler& sampler, RayCounter& counter) const {
  Rgb radiance, beta(1.0f);
  Ray ray = camera_ray;
  const int limit = max_depth_ >= 0 ? max_depth_ : kMaxSpecularChain;
  for (int depth = 0;; ++depth) {
    // Seen directly or through specular surfaces: emission counts fully.
    SurfaceInteraction si;
    if (!world_.intersect(ray, si, counter)) {
      radiance += beta * world_.escaped(ray);
      break;
    }
    radiance += beta * si.emitted;
    MaterialScratch scratch;
    const Material& m = si.material->at(si, scratch);
    const Vec3 wo = si.to_local(si.wo);
    if (m.has_non_specular()) {
      // The first non-specular point: the split of Jensen's method.
      if (show_ == Show::kGlobal)
        return radiance + beta * global_.radiance(si, m, global_query_, query_scratch());
      if (show_ == Show::kCaustic)
        return radiance + beta * caustic_.radiance(si, m, caustic_query_, query_scratch());
      Rgb l = estimate_direct(world_, light_sampler_, si, m, wo, ray.time, sampler, counter);
      if (!caustic_.empty()) l += caustic_.radiance(si, m, caustic_query_, query_scratch());
      if (gather_rays_ > 0) {
        Rgb indirect;
        for (int g = 0; g < gather_rays_; ++g)
          indirect += gather(si, m, ray.time, sampler, counter);
        l += indirect / float(gather_rays_);
      }
      return radiance + beta * l;
    }
    // A specular surface: follow the sampled lobe.
    if (depth >= limit || !scatter(si, m, sampler, beta, ray)) break;
  }
  return radiance;
}

}  // namespace penumbra
