#include "penumbra/render/integrator/sppm_integrator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/timer.h"
#include "penumbra/render/integrator/direct_lighting.h"
#include "penumbra/render/integrator/scatter.h"
#include "penumbra/render/photon/photon_tracer.h"
#include "penumbra/render/render_job.h"

namespace penumbra {

namespace {

/// Photons per chunk of a photon pass: chunks, not threads, own deposits, so the sums are the
/// same at any thread count.
constexpr uint64_t kChunk = 4096;
/// A photon counts for a visible point only on the same surface: geometric normals within 60
/// degrees (a photon on a wall meeting the floor does not light the floor; the test vanishes
/// as the radius shrinks, so it adds no bias in the limit).
constexpr float kSurfaceCos = 0.5f;
/// Camera paths that never reach a diffuse point end here when max_depth is unbounded.
constexpr int kMaxCameraDepth = 64;
/// The default initial radius, in pixel footprints at the visible point's distance.
constexpr float kFootprints = 2.0f;

/// The angle between the camera rays through the centres of pixel (x, y) and its neighbour:
/// the angular size of the pixel.
float pixel_angle(const RenderJob& job, int x, int y) {
  CameraSample a, b;
  a.film = {float(x) + 0.5f, float(y) + 0.5f};
  b.film = {float(x) + (x + 1 < job.film->width() ? 1.5f : -0.5f), float(y) + 0.5f};
  a.lens = b.lens = {0.5f, 0.5f};
  const Vec3 da = normalize(job.camera->generate_ray(a).d);
  const Vec3 db = normalize(job.camera->generate_ray(b).d);
  return 2.0f * std::asin(std::min(1.0f, 0.5f * penumbra::length(da - db)));
}

}  // namespace

SppmIntegrator::SppmIntegrator(const World& world, const ParamList& params,
                               const RenderSettings& settings)
    : world_(world),
      photons_per_pass_(uint64_t(params.get_int("photons", 0, 0, 1ll << 32))),
      initial_radius_(float(params.get_real("radius", 0.0, 0.0, 1e30))),
      alpha_(float(params.get_real("alpha", 2.0 / 3.0, 1e-3, 1.0))),
      max_depth_(int(params.get_int("max_depth", settings.max_depth.value_or(-1), -1, 1 << 20))),
      rr_depth_(int(params.get_int("rr_depth", 3, 0, 1 << 20))),
      seed_(settings.seed),
      light_sampler_(world.lights(), "power") {
  params.check_all_used();
  check_memory(
      double(settings.width) * double(settings.height) * double(sizeof(Pixel)),
      fmt::format("sppm: the visible points of {} x {} pixels", settings.width, settings.height),
      "lower the resolution");
}

std::string SppmIntegrator::name() const {
  std::string s = initial_radius_ > 0.0f
                      ? fmt::format("sppm:radius={:g},alpha={:g}", initial_radius_, alpha_)
                      : fmt::format("sppm:alpha={:g}", alpha_);
  if (photons_per_pass_ > 0) s += fmt::format(",photons={}", photons_per_pass_);
  if (max_depth_ >= 0) s += fmt::format(",max_depth={}", max_depth_);
  if (rr_depth_ != 3) s += fmt::format(",rr_depth={}", rr_depth_);
  return s;
}

void SppmIntegrator::camera_path(RenderJob& job, Sampler& sampler, int x, int y, int pass,
                                 Pixel& px, RayCounter& counter) const {
  float weight = 0.0f;
  Ray ray = job.camera_ray(sampler, x, y, pass, weight);
  Rgb beta(weight), ld;
  float length = 0.0f;   // of the path so far, for the initial radius
  bool specular = true;  // emission counts only where no shadow ray could have found it
  const int limit = max_depth_ >= 0 ? max_depth_ : kMaxCameraDepth;
  px.has_vp = false;
  for (int depth = 0;; ++depth) {
    SurfaceInteraction si;
    if (!world_.intersect(ray, si, counter)) {
      if (specular) ld += beta * world_.escaped(ray);
      break;
    }
    if (specular) ld += beta * si.emitted;
    length += si.t * std::sqrt(dot(ray.d, ray.d));
    MaterialScratch scratch;
    const Material& m = si.material->at(si, scratch);
    const Vec3 wo = si.to_local(si.wo);
    if (m.has_non_specular()) {
      ld += beta * estimate_direct(world_, light_sampler_, si, m, wo, ray.time, sampler, counter);
      // The visible point: the first diffuse point, or a glossy one where the path must end.
      if ((m.flags() & kBsdfDiffuse) || depth + 1 >= limit) {
        if (depth < limit) {
          px.vp = si;
          px.vp_wo = wo;
          px.beta = beta;
          px.has_vp = true;
          // The first visible point sets the radius: kFootprints pixel footprints at the
          // distance the path travelled, so the blur is about the same on screen everywhere.
          if (px.radius == 0.0f) {
            px.radius = initial_radius_ > 0.0f ? initial_radius_
                                               : kFootprints * length * pixel_angle(job, x, y);
            // A degenerate footprint (a visible point at the lens) falls back to the scene's
            // size over the image's.
            if (!(px.radius > 0.0f) || !std::isfinite(px.radius))
              px.radius = kFootprints * penumbra::length(world_.bounds().diagonal()) /
                          float(std::max(job.film->width(), job.film->height()));
          }
        }
        break;
      }
    }
    if (depth >= limit) break;
    const auto bs = scatter(si, m, sampler, beta, ray);
    if (!bs) break;
    specular = bs->is_specular();
    // Russian roulette on glossy chains (specular ones keep weight <= 1 and end at the limit).
    const float u_rr = sampler.get_1d();
    if (!specular && depth + 1 >= rr_depth_ && beta.max_channel() < 1.0f) {
      const float q = std::max(0.05f, 1.0f - beta.max_channel());
      if (u_rr < q) break;
      beta = beta / (1.0f - q);
    }
  }
  for (int c = 0; c < 3; ++c) px.ld[c] += ld[c];
}

void SppmIntegrator::photon_pass(RenderJob& job, int pass, uint64_t& rays) {
  // The visible points in a hash grid, each with its current radius.
  std::vector<Vec3> centres(pixels_.size());
  std::vector<float> radii(pixels_.size(), 0.0f);
  for (size_t i = 0; i < pixels_.size(); ++i)
    if (pixels_[i].has_vp) centres[i] = pixels_[i].vp.p, radii[i] = pixels_[i].radius;
  grid_.build(centres, radii);

  const PhotonTracer tracer(world_, max_depth_);
  const uint64_t n = photons_per_pass_ > 0 ? photons_per_pass_ : uint64_t(pixels_.size());
  const size_t chunks = size_t((n + kChunk - 1) / kChunk);
  deposits_.resize(chunks);
  const uint64_t seed = hash_combine(seed_, uint64_t(pass));
  std::atomic<uint64_t> traced{0};
  // The deposits of a pass grow with the photons and with how many visible points each photon
  // finds (the radius): bounded by the memory limit.
  std::atomic<uint64_t> deposited{0};
  std::atomic<bool> over{false};
  parallel_for(chunks, [&](size_t c) {
    std::vector<Deposit>& out = deposits_[c];
    out.clear();
    if (job.cancelled() || over.load(std::memory_order_relaxed)) return;
    uint64_t r = 0;
    const uint64_t end = std::min(n, uint64_t(c + 1) * kChunk);
    for (uint64_t i = uint64_t(c) * kChunk; i < end; ++i)
      r += tracer.trace(i, seed, 1, [&](const PhotonHit& h) {
        if (h.depth == 0) return true;  // direct light: the camera pass's shadow rays count it
        const Vec3 p = h.si->p;
        const auto [b, e] = grid_.candidates(p);
        for (const uint32_t* it = b; it != e; ++it) {
          const Pixel& px = pixels_[*it];
          const Vec3 d = px.vp.p - p;
          if (dot(d, d) > px.radius * px.radius) continue;
          if (std::fabs(dot(px.vp.ng, h.si->ng)) < kSurfaceCos) continue;
          MaterialScratch scratch;
          const Material& m = px.vp.material->at(px.vp, scratch);
          const Rgb f = m.eval(px.vp_wo, px.vp.to_local(h.si->wo));
          if (!f.is_black()) out.push_back({*it, h.power * f});
        }
        return true;
      });
    traced.fetch_add(r, std::memory_order_relaxed);
    const uint64_t now = deposited.fetch_add(out.size(), std::memory_order_relaxed) + out.size();
    if (double(now) * sizeof(Deposit) > double(memory_limit())) over.store(true);
  });
  if (over.load())
    check_memory(double(deposited.load()) * sizeof(Deposit),
                 fmt::format("sppm: the photon deposits of pass {} (photons={})", pass, n),
                 "use fewer photons per pass or a smaller radius");
  rays += traced.load();
  photons_emitted_ += n;
  // Deposits summed per pixel in chunk order, so in photon order.
  for (const std::vector<Deposit>& chunk : deposits_)
    for (const Deposit& d : chunk) {
      Pixel& px = pixels_[d.pixel];
      for (int ch = 0; ch < 3; ++ch) px.phi[ch] += d.phi[ch];
      ++px.m;
    }
}

void SppmIntegrator::update_pixels(RenderJob& job, int passes_done) {
  Film& film = *job.film;
  const double np = double(photons_emitted_);
  parallel_for_range(
      pixels_.size(),
      [&](size_t a, size_t b) {
        for (size_t i = a; i < b; ++i) {
          Pixel& px = pixels_[i];
          if (px.m > 0) {
            // The progressive radius reduction (Hachisuka et al. 2008, equations 7-9).
            const double n_new = px.n + double(alpha_) * double(px.m);
            const double r_new = double(px.radius) * std::sqrt(n_new / (px.n + double(px.m)));
            const double scale = (r_new * r_new) / (double(px.radius) * double(px.radius));
            for (int c = 0; c < 3; ++c)
              px.tau[c] = (px.tau[c] + double(px.beta[c]) * px.phi[c]) * scale;
            px.n = n_new;
            px.radius = float(r_new);
          }
          for (double& v : px.phi) v = 0.0;
          px.m = 0;
          const double area = std::numbers::pi * double(px.radius) * double(px.radius);
          Rgb l;
          for (int c = 0; c < 3; ++c)
            l[c] = float(px.ld[c] / passes_done +
                         (np > 0 && area > 0 ? px.tau[c] / (np * area) : 0.0));
          film.set_pixel(int(i % size_t(width_)), int(i / size_t(width_)), l,
                         uint32_t(passes_done));
        }
      },
      256);
}

RenderStats SppmIntegrator::render(RenderJob& job) {
  const RenderOptions& opt = job.options;
  if (opt.target_error > 0)
    throw Error(
        "sppm: a target error needs a per-pixel variance, which sppm does not estimate "
        "(use --spp or --time-limit)");
  RenderStats stats;
  Film& film = *job.film;
  width_ = film.width();
  stats.spp_target = job.sampler->samples_per_pixel();
  pixels_.assign(size_t(film.width()) * size_t(film.height()), Pixel{});
  photons_emitted_ = 0;

  const int ts = std::max(1, opt.tile_size);
  const int nx = (film.width() + ts - 1) / ts, ny = (film.height() + ts - 1) / ts;
  const size_t tiles = size_t(nx) * size_t(ny);
  stats.tiles_total = tiles;
  std::atomic<uint64_t> rays{0}, traversal{0}, busy{0};
  const Timer timer;
  double last_checkpoint = 0.0;
  for (int pass = 0; pass < stats.spp_target; ++pass) {
    if (opt.time_limit_s > 0 && pass > 0 &&
        timer.elapsed_s() * double(pass + 1) / double(pass) > opt.time_limit_s) {
      stats.stop = StopReason::kTimeLimit;
      break;
    }
    // Camera pass: a visible point per pixel.
    std::atomic<size_t> tiles_done{0};
    parallel_for(tiles, [&](size_t tile) {
      if (job.cancelled()) return;
      const uint64_t start = tick_count();
      auto s = job.sampler->clone();
      RayCounter counter;
      const int x0 = int(tile % size_t(nx)) * ts, y0 = int(tile / size_t(nx)) * ts;
      for (int y = y0; y < std::min(y0 + ts, film.height()); ++y)
        for (int x = x0; x < std::min(x0 + ts, film.width()); ++x)
          camera_path(job, *s, x, y, pass, pixels_[size_t(y) * size_t(width_) + size_t(x)],
                      counter);
      rays.fetch_add(counter.rays, std::memory_order_relaxed);
      traversal.fetch_add(counter.traversal_ticks, std::memory_order_relaxed);
      busy.fetch_add(tick_count() - start, std::memory_order_relaxed);
      const size_t done = tiles_done.fetch_add(1) + 1;
      if (opt.on_progress) {
        RenderProgress p;
        p.spp_done = pass;
        p.spp_target = stats.spp_target;
        p.fraction = (double(pass) + 0.5 * double(done) / double(tiles)) / stats.spp_target;
        p.elapsed_s = timer.elapsed_s();
        p.rays = rays.load(std::memory_order_relaxed);
        opt.on_progress(p);
      }
    });
    stats.tiles_done = tiles_done.load();
    if (job.cancelled()) {
      stats.stop = StopReason::kCancelled;
      break;
    }
    // Photon pass, then the progressive update and the film's new estimate.
    uint64_t photon_rays = 0;
    photon_pass(job, pass, photon_rays);
    rays.fetch_add(photon_rays);
    if (job.cancelled()) {
      stats.stop = StopReason::kCancelled;
      break;
    }
    update_pixels(job, pass + 1);
    stats.spp_done = pass + 1;
    ++stats.passes;
    if (opt.on_progress) {
      RenderProgress p;
      p.spp_done = stats.spp_done;
      p.spp_target = stats.spp_target;
      p.fraction = double(stats.spp_done) / stats.spp_target;
      p.elapsed_s = timer.elapsed_s();
      p.rays = rays.load();
      opt.on_progress(p);
    }
    if (opt.checkpoint_s > 0 && opt.on_checkpoint && stats.spp_done < stats.spp_target &&
        timer.elapsed_s() - last_checkpoint >= opt.checkpoint_s) {
      opt.on_checkpoint(film, stats.spp_done);
      last_checkpoint = timer.elapsed_s();
    }
  }
  stats.camera_rays = uint64_t(film.width()) * uint64_t(film.height()) * uint64_t(stats.spp_done);
  stats.rays = rays.load();
  stats.traversal_share = busy.load() ? double(traversal.load()) / double(busy.load()) : 0.0;
  stats.seconds = timer.elapsed_s();
  return stats;
}

}  // namespace penumbra
