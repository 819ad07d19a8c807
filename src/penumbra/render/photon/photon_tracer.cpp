#include "penumbra/render/photon/photon_tracer.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/core/memory_limit.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/render/material/material.h"

namespace penumbra {

namespace {

/// Photons per chunk of trace_batch: fixed, so the split (and with it the batch) does not depend
/// on the thread count; large enough that a chunk's vector and task overhead do not matter.
constexpr uint64_t kChunk = 4096;

/// True when every channel of c is finite.
bool finite(Rgb c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

/// The emitted ray, its origin moved off an area light's surface: sample_le puts the origin on
/// the surface itself, where the first intersection finds the emitter again at t ~ 0 for about
/// half the rays from spheres and tilted quads. `error` bounds the rounding of a sampled surface
/// point per axis (see PhotonTracer::origin_error_).
Ray leave_light(const LightLeSample& le, float error) {
  Ray ray = le.ray;
  if (dot(le.n, le.n) > 0.0f) {
    const float e = std::fmax(error, gamma(8) * max_component(abs(ray.o)));
    ray.o = offset_ray_origin(ray.o, Vec3{e, e, e}, le.n, ray.d);
  }
  return ray;
}

}  // namespace

PhotonTracer::PhotonTracer(const World& world, int max_depth, const std::string& light_strategy)
    : world_(world), max_depth_(max_depth), sampler_(world.lights(), light_strategy) {
  // A point sampled on a primitive (p + u e1 + v e2, c + r n, a barycentric sum) is rounded
  // relative to its operands, not to itself: near the world's origin a point far smaller than the
  // primitive's coordinates still carries their error. They all lie in the scene's bounds.
  const Bounds3& b = world.bounds();
  if (b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z) {
    const float extent = std::fmax(max_component(abs(b.lo)), max_component(abs(b.hi)));
    if (std::isfinite(extent)) origin_error_ = gamma(8) * extent;
  }
}

bool PhotonTracer::has_lights() const {
  for (const Light* l : sampler_.lights())
    if (l->power().max_channel() > 0.0f) return true;
  return false;
}

uint64_t PhotonTracer::trace(uint64_t index, uint64_t seed, uint64_t emitted,
                             const std::function<bool(const PhotonHit&)>& on_hit) const {
  if (sampler_.lights().empty() || emitted == 0) return 0;
  // The photon's own generator: its numbers depend only on (index, seed).
  Pcg32 rng(hash_combine(seed, index), hash_combine(index, 0x70686f746f6eull));
  RayCounter counter;

  // Emission: a light by the sampler, then a ray from it (Jensen 1996, section 2.1); the photon
  // carries the light's power over its probability and the number of photons.
  const float u_light = rng.next_float();
  const Vec2 u_pos{rng.next_float(), rng.next_float()};
  const Vec2 u_dir{rng.next_float(), rng.next_float()};
  const float time = rng.next_float();
  const SampledLight picked = sampler_.sample(u_light);
  if (!picked.light || !(picked.pmf > 0.0f)) return 0;
  const LightLeSample le = picked.light->sample_le(u_pos, u_dir, time);
  Rgb power = le.beta() / (picked.pmf * float(emitted));
  if (power.is_black() || !finite(power) || !(power.max_channel() > 0.0f)) return 0;
  Ray ray = leave_light(le, origin_error_);

  bool specular_chain = true;  // every bounce so far was specular
  for (int depth = 0;; ++depth) {
    SurfaceInteraction si;
    if (!world_.intersect(ray, si, counter) || !si.material) break;
    MaterialScratch scratch;
    const Material& m = si.material->at(si, scratch);  // textures evaluated at the hit

    // Store at non-specular surfaces; the caller may end the path here.
    if (m.has_non_specular()) {
      const PhotonHit hit{&si, power, depth, depth >= 1 && specular_chain};
      if (!on_hit(hit)) break;
    }
    if (max_depth_ >= 0 && depth >= max_depth_) break;

    // Scatter by the BSDF in the adjoint direction: wo points back to where the photon came from.
    const float uc = rng.next_float();
    const Vec2 u{rng.next_float(), rng.next_float()};
    const float u_rr = rng.next_float();
    const Vec3 wo_local = si.to_local(si.wo);
    const auto bs = m.sample(wo_local, uc, u, TransportMode::kImportance);
    if (!bs || bs->f.is_black() || !(bs->pdf > 0.0f)) break;
    const Vec3 wi = si.to_world(bs->wi);
    // f |wi.ns| / pdf times the shading-normal correction of importance transport,
    // |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997, section 5.3): the |wi.ns| cancel.
    const float wo_ng = std::fabs(dot(si.wo, si.ng));
    if (!(wo_ng > 0.0f)) break;
    const float scale =
        std::fabs(cos_theta(wo_local)) * std::fabs(dot(wi, si.ng)) / (wo_ng * bs->pdf);
    Rgb next = power * bs->f * scale;
    if (!finite(next) || !(next.max_channel() > 0.0f)) break;

    // Russian roulette on the largest channel, so that survivors keep the power they had
    // (Jensen 1996, section 2.1.2): survive with q = min(1, max(next) / max(power)).
    const float q = std::min(1.0f, next.max_channel() / power.max_channel());
    if (!(u_rr < q)) break;
    if (q < 1.0f) next = next / q;
    power = next;

    specular_chain = specular_chain && bs->is_specular();
    ray = si.spawn_ray(wi, time);
  }
  return counter.rays;
}

PhotonBatch PhotonTracer::trace_batch(uint64_t n, uint64_t seed, PhotonStore what,
                                      const std::atomic<bool>* cancel,
                                      const std::function<void(double)>& progress,
                                      bool normals) const {
  PhotonBatch batch;
  batch.emitted = n;
  if (n == 0 || sampler_.lights().empty()) return batch;
  const size_t chunks = size_t((n + kChunk - 1) / kChunk);
  std::vector<std::vector<Photon>> found(chunks);
  std::vector<std::vector<OctDirection>> found_normals(normals ? chunks : 0);
  std::vector<uint64_t> rays(chunks, 0);
  std::atomic<size_t> done{0};
  // The photons stored so far, bounded by the memory limit: a photon that bounces keeps being
  // stored, so the count emitted does not bound the map. Counted twice, for the chunks and the
  // batch they are copied into.
  const double bytes_per_photon =
      2.0 * double(sizeof(Photon) + (normals ? sizeof(OctDirection) : 0));
  std::atomic<uint64_t> stored{0};
  std::atomic<bool> over{false};

  parallel_for(chunks, [&](size_t c) {
    if (cancel && cancel->load(std::memory_order_relaxed)) return;
    if (over.load(std::memory_order_relaxed)) return;
    std::vector<Photon>& out = found[c];
    // What a map keeps; a caustic map ends each path at its first non-specular hit.
    const auto keep = [&](const PhotonHit& h) {
      const bool store = what == PhotonStore::kAll ||
                         (what == PhotonStore::kCaustic && h.caustic) ||
                         (what == PhotonStore::kIndirect && h.depth >= 1);
      if (store) {
        out.push_back({h.si->p, OctDirection::encode(h.si->wo), h.power});
        if (normals)
          found_normals[c].push_back(OctDirection::encode(face_forward(h.si->ng, h.si->wo)));
      }
      return what != PhotonStore::kCaustic;
    };
    const uint64_t begin = uint64_t(c) * kChunk, end = std::min(n, begin + kChunk);
    for (uint64_t i = begin; i < end; ++i) rays[c] += trace(i, seed, n, keep);
    const uint64_t now = stored.fetch_add(out.size(), std::memory_order_relaxed) + out.size();
    if (double(now) * bytes_per_photon > double(memory_limit())) over.store(true);
    const size_t finished = done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (progress) progress(double(finished) / double(chunks));
  });

  if (over.load()) {
    check_memory(double(stored.load()) * bytes_per_photon,
                 fmt::format("the photon map of {} photons emitted ({} stored before it stopped)",
                             n, stored.load()),
                 "emit fewer photons");
  }
  // Chunks in index order: the same photons in the same order at any thread count.
  size_t total = 0;
  for (const auto& f : found) total += f.size();
  batch.photons.reserve(total);
  if (normals) batch.normals.reserve(total);
  for (size_t c = 0; c < chunks; ++c) {
    batch.photons.insert(batch.photons.end(), found[c].begin(), found[c].end());
    if (normals)
      batch.normals.insert(batch.normals.end(), found_normals[c].begin(), found_normals[c].end());
    batch.rays += rays[c];
  }
  return batch;
}

}  // namespace penumbra
