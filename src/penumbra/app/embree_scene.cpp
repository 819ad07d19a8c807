#include "penumbra/app/embree_scene.h"

#include "penumbra/core/error.h"

#ifdef PENUMBRA_HAVE_EMBREE
#include <algorithm>
#include <atomic>
#include <vector>

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include "penumbra/core/timer.h"
#endif

namespace penumbra::app {

#ifdef PENUMBRA_HAVE_EMBREE

bool have_embree() {
  return true;
}

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<float> vertices;  ///< positions with the padding Embree's 16-byte loads need
  std::atomic<long long> bytes{0};
  double build_ms = 0;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  void check(const char* what) const {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw Error(fmt::format("embree: {} failed (error {})", what, int(e)));
  }
};

namespace {
bool monitor(void* user, ssize_t bytes, bool) {
  static_cast<std::atomic<long long>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
  return true;
}
}  // namespace

EmbreeScene::EmbreeScene(const TriangleMesh& mesh, int threads, bool robust)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.device = rtcNewDevice(fmt::format("threads={}", threads).c_str());
  if (!m.device) throw Error("embree: cannot create a device");
  rtcSetDeviceMemoryMonitorFunction(m.device, monitor, &m.bytes);
  // Embree reads the last vertex with a 16-byte load: one float of padding.
  m.vertices.resize(3 * mesh.positions.size() + 1);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    m.vertices[3 * i] = mesh.positions[i].x;
    m.vertices[3 * i + 1] = mesh.positions[i].y;
    m.vertices[3 * i + 2] = mesh.positions[i].z;
  }
  const Timer timer;
  m.scene = rtcNewScene(m.device);
  if (robust) rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.vertices.data(),
                             0, 3 * sizeof(float), mesh.positions.size());
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(),
                             0, 3 * sizeof(uint32_t), mesh.triangle_count());
  rtcCommitGeometry(geom);
  rtcAttachGeometry(m.scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(m.scene);
  m.check("scene build");
  m.build_ms = timer.elapsed_ms();
}

EmbreeScene::~EmbreeScene() = default;

double EmbreeScene::build_ms() const {
  return impl_->build_ms;
}
size_t EmbreeScene::bytes() const {
  return size_t(std::max(0LL, impl_->bytes.load()));
}
bool EmbreeScene::robust() const {
  return (rtcGetSceneFlags(impl_->scene) & RTC_SCENE_FLAG_ROBUST) != 0;
}

bool EmbreeScene::intersect(const Ray& ray, Hit& hit) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  alignas(16) RTCRayHit rh;
  rh.ray = {ray.o.x, ray.o.y, ray.o.z,  ray.tmin, ray.d.x, ray.d.y,
            ray.d.z, 0.0f,    ray.tmax, ~0u,      0,       0};
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  hit = Hit{};
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit = {rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID};
  return true;
}

bool EmbreeScene::occluded(const Ray& ray) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  alignas(16) RTCRay r = {ray.o.x, ray.o.y, ray.o.z,  ray.tmin, ray.d.x, ray.d.y,
                          ray.d.z, 0.0f,    ray.tmax, ~0u,      0,       0};
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0.0f;  // Embree sets tfar to -inf on occlusion
}

namespace {
/// Rays per call of Embree's stream API.
constexpr size_t kStreamChunk = 256;
RTCRay to_embree(const Ray& ray) {
  return {ray.o.x, ray.o.y, ray.o.z,  ray.tmin, ray.d.x, ray.d.y,
          ray.d.z, 0.0f,    ray.tmax, ~0u,      0,       0};
}
/// A stream query's context, coherent or not.
RTCIntersectContext stream_context(bool coherent) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags =
      coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return ctx;
}
}  // namespace

void EmbreeScene::intersect_stream(std::span<const Ray> rays, std::span<Hit> hits,
                                   bool coherent) const {
  RTCIntersectContext ctx = stream_context(coherent);
  alignas(64) RTCRayHit rh[kStreamChunk];
  for (size_t begin = 0; begin < rays.size(); begin += kStreamChunk) {
    const size_t n = std::min(kStreamChunk, rays.size() - begin);
    for (size_t i = 0; i < n; ++i) {
      rh[i].ray = to_embree(rays[begin + i]);
      rh[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect1M(impl_->scene, &ctx, rh, unsigned(n), sizeof(RTCRayHit));
    for (size_t i = 0; i < n; ++i) {
      Hit& hit = hits[begin + i];
      hit = Hit{};
      if (rh[i].hit.geomID != RTC_INVALID_GEOMETRY_ID)
        hit = {rh[i].ray.tfar, rh[i].hit.u, rh[i].hit.v, rh[i].hit.primID};
    }
  }
}

void EmbreeScene::occluded_stream(std::span<const Ray> rays, std::span<uint8_t> out,
                                  bool coherent) const {
  RTCIntersectContext ctx = stream_context(coherent);
  alignas(64) RTCRay r[kStreamChunk];
  for (size_t begin = 0; begin < rays.size(); begin += kStreamChunk) {
    const size_t n = std::min(kStreamChunk, rays.size() - begin);
    for (size_t i = 0; i < n; ++i) r[i] = to_embree(rays[begin + i]);
    rtcOccluded1M(impl_->scene, &ctx, r, unsigned(n), sizeof(RTCRay));
    for (size_t i = 0; i < n; ++i) out[begin + i] = r[i].tfar < 0.0f;
  }
}

#else

bool have_embree() {
  return false;
}
struct EmbreeScene::Impl {};
EmbreeScene::EmbreeScene(const TriangleMesh&, int, bool) {
  throw Error("this penumbra was built without Embree");
}
EmbreeScene::~EmbreeScene() = default;
double EmbreeScene::build_ms() const {
  return 0;
}
size_t EmbreeScene::bytes() const {
  return 0;
}
bool EmbreeScene::robust() const {
  return false;
}
bool EmbreeScene::intersect(const Ray&, Hit&) const {
  return false;
}
bool EmbreeScene::occluded(const Ray&) const {
  return false;
}
void EmbreeScene::intersect_stream(std::span<const Ray>, std::span<Hit>, bool) const {}
void EmbreeScene::occluded_stream(std::span<const Ray>, std::span<uint8_t>, bool) const {}

#endif

}  // namespace penumbra::app
