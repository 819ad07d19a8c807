#pragma once
/// `photon`: Jensen's two-pass photon mapping (Jensen 1996, "Global Illumination using Photon
/// Maps"), with final gathering and precomputed irradiance (Christensen 1999, "Faster Photon Map
/// Global Illumination").
#include <memory>
#include <string>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/light/light_sampler.h"
#include "penumbra/render/photon/photon_map.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Two photon maps are traced before the first pass: the caustic map (photons that reached a
/// non-specular surface through one or more specular bounces) and the global map (every
/// non-specular hit). A camera path follows specular surfaces; at its first non-specular point x
/// the radiance is split so that each light path is counted once:
/// - direct light by shadow rays (light sampling, as `path` does with strategy nee);
/// - caustics (light, specular bounces, x) from the caustic map, estimated at x;
/// - the rest by final gathering: `gather` rays drawn from the BSDF at x follow specular
///   surfaces to a non-specular point y, whose outgoing radiance comes from the global map:
///   the BSDF at y times the precomputed irradiance nearest y (for diffuse y) or a full
///   radiance estimate.
/// Biased (density estimation blurs light over the search disc) but consistent as photons grow
/// and the radius shrinks.
///
/// Parameters (defaults in brackets): photons [200000] emitted for the global map,
/// caustic_photons [200000] emitted for the caustic map, k [100] and caustic_k [50] photons per
/// estimate, max_radius and caustic_max_radius [5% and 1% of the scene's diagonal] the largest
/// search radius, gather [1] final-gather rays per camera sample (so rays per pixel = spp x
/// gather), irradiance [true] precomputing irradiance at the hits of a quarter as many photons
/// again, show [none;
/// global, caustic] to display a map's density estimate at the first non-specular hit,
/// max_depth [the scene's, else unbounded] bounces of photons and of specular chains.
class PhotonIntegrator final : public SamplingIntegrator {
 public:
  enum class Show { kNone, kGlobal, kCaustic };
  PhotonIntegrator(const World& world, const ParamList& params, const RenderSettings& settings);
  std::string name() const override;
  void preprocess(RenderJob& job) override;
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;

  /// The maps (empty before preprocess).
  const PhotonMap& global_map() const { return global_; }
  const PhotonMap& caustic_map() const { return caustic_; }
  /// Precomputed irradiance points (empty unless `irradiance`).
  size_t irradiance_points() const { return irradiance_.size(); }

 private:
  /// A precomputed irradiance estimate at a photon's position.
  struct IrradiancePoint {
    Vec3 p;
    OctDirection n;  ///< the surface normal on the side the photons came from
    Rgb e;           ///< irradiance (W / m^2)
  };

  /// Radiance leaving the non-specular point si towards si.wo from the global map.
  Rgb global_radiance(const SurfaceInteraction& si, const Material& m) const;
  /// Indirect light at the non-specular point si by one final-gather ray.
  Rgb gather(const SurfaceInteraction& si, const Material& m, float time, Sampler& sampler,
             RayCounter& counter) const;

  const World& world_;
  uint64_t global_photons_, caustic_photons_;
  DensityQuery global_query_, caustic_query_;
  int gather_rays_;
  bool use_irradiance_;
  Show show_;
  int max_depth_;  ///< -1: unbounded
  uint64_t seed_;
  LightSampler light_sampler_;
  PhotonMap global_, caustic_;
  PointKdTree<IrradiancePoint> irradiance_;
};

}  // namespace penumbra
