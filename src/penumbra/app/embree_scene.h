#pragma once
/// An Embree 3 scene over a triangle mesh: the external reference accel-bench compares against.
/// Available only when built with PENUMBRA_HAVE_EMBREE (Debian's libembree-dev).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "penumbra/core/ray.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra::app {

/// True when this build can compare against Embree.
bool have_embree();

/// One Embree device and scene with a single triangle geometry sharing the mesh's buffers
/// (the mesh must outlive it); default build quality, single-ray rtcIntersect1/rtcOccluded1.
class EmbreeScene {
 public:
  /// Builds over `mesh` with `threads` build threads (0 = all); throws Error on Embree errors.
  /// `robust` sets RTC_SCENE_FLAG_ROBUST: conservative box tests and Embree's watertight
  /// (Pluecker) triangle test, the guarantees our own structures give; off, Embree's defaults.
  EmbreeScene(const TriangleMesh& mesh, int threads, bool robust = false);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Wall time of the build (buffers, geometry and scene commit).
  double build_ms() const;
  /// Bytes Embree allocated, as reported by its memory monitor.
  size_t bytes() const;
  /// True when the scene is in Embree's robust mode, as Embree reports the scene's flags.
  bool robust() const;
  /// Closest hit on [tmin, tmax]; fills t and prim (the triangle index) of `hit`.
  bool intersect(const Ray& ray, Hit& hit) const;
  /// True when anything is hit on [tmin, tmax].
  bool occluded(const Ray& ray) const;
  /// intersect of every ray, through Embree's stream API (rtcIntersect1M, 256 rays per call;
  /// `coherent` sets RTC_INTERSECT_CONTEXT_FLAG_COHERENT, else INCOHERENT).
  void intersect_stream(std::span<const Ray> rays, std::span<Hit> hits, bool coherent) const;
  /// occluded of every ray into `out` (1: occluded), through rtcOccluded1M.
  void occluded_stream(std::span<const Ray> rays, std::span<uint8_t> out, bool coherent) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::app
