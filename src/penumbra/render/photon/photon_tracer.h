#pragma once
/// Photon tracing: rays leave the lights in proportion to their power and scatter through the
/// scene by the BSDFs in the adjoint (importance) direction until Russian roulette absorbs them
/// (Jensen 1996, "Global Illumination using Photon Maps"; the adjoint BSDF and shading normals
/// after Veach 1997, "Robust Monte Carlo Methods for Light Transport Simulation", chapter 5).
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "penumbra/render/light/light_sampler.h"
#include "penumbra/render/photon/photon.h"
#include "penumbra/render/surface_interaction.h"
#include "penumbra/render/world.h"

namespace penumbra {

/// A photon arriving at a non-specular surface.
struct PhotonHit {
  const SurfaceInteraction* si = nullptr;  ///< where it landed (si->wo points back along it)
  Rgb power;      ///< flux it carries: the light's power share divided by the photons emitted
  int depth = 0;  ///< bounces before this hit: 0 for light arriving straight from a light
  bool caustic = false;  ///< every bounce so far was specular and there was at least one
};

/// Which photons a map keeps.
enum class PhotonStore : uint8_t {
  kAll,       ///< every non-specular hit (the global map)
  kCaustic,   ///< only caustic hits (light, one or more specular bounces, then this hit); paths
              ///< stop at their first non-specular hit
  kIndirect,  ///< every non-specular hit but the first (depth >= 1): what SPPM gathers
};

/// Photons traced into a map.
struct PhotonBatch {
  std::vector<Photon> photons;  ///< stored photons, in the order of the emitted photon's index
  /// Per photon, the unit geometric normal on the side it arrived from (when asked for).
  std::vector<OctDirection> normals;
  uint64_t emitted = 0;  ///< photons emitted (paths traced)
  uint64_t rays = 0;     ///< rays traced
};

/// Traces photons through a world. Immutable and thread-safe once made.
class PhotonTracer {
 public:
  /// Photons leave `world`'s lights chosen with `light_strategy` ("power" or "uniform"); paths
  /// scatter at most max_depth times (-1: unbounded; Russian roulette ends them). Throws Error
  /// for an unknown strategy.
  PhotonTracer(const World& world, int max_depth, const std::string& light_strategy = "power");

  /// Traces photon `index` of the set seeded by `seed` (its random numbers depend only on
  /// (index, seed)); the power of each hit is divided by `emitted`, the number of photons in the
  /// set. Calls on_hit at each non-specular hit; a false return ends the path. Returns the rays
  /// traced.
  uint64_t trace(uint64_t index, uint64_t seed, uint64_t emitted,
                 const std::function<bool(const PhotonHit&)>& on_hit) const;

  /// Traces photons [0, n) of the set seeded by `seed` on all cores and keeps those that `what`
  /// names, in index order, so the batch is the same at any thread count. Stops early (returning
  /// what is done, with emitted = n still) when `cancel` turns true; `progress` (may be empty)
  /// receives the fraction done, from worker threads. With `normals`, the batch also keeps each
  /// photon's surface normal, on the side it arrived from (for irradiance estimates at photons).
  PhotonBatch trace_batch(uint64_t n, uint64_t seed, PhotonStore what,
                          const std::atomic<bool>* cancel = nullptr,
                          const std::function<void(double)>& progress = {},
                          bool normals = false) const;

  /// True when the world has a light that emits power.
  bool has_lights() const;
  /// The world traced.
  const World& world() const { return world_; }

 private:
  const World& world_;
  int max_depth_;
  LightSampler sampler_;
  float origin_error_ = 0;  ///< error bound of points sampled on area lights (per axis)
};

}  // namespace penumbra
