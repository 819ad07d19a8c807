#pragma once
/// `sppm`: stochastic progressive photon mapping (Hachisuka, Jensen 2009, "Stochastic Progressive
/// Photon Mapping"; the per-pixel statistics of Hachisuka, Ogaki, Jensen 2008, "Progressive
/// Photon Mapping"), structured after pbrt-v4's SPPMIntegrator.
#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/light/light_sampler.h"
#include "penumbra/render/photon/sphere_hash_grid.h"
#include "penumbra/render/surface_interaction.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// Each pass traces one camera path per pixel to its first diffuse point (through specular and
/// glossy surfaces, so depth of field, motion blur and glossy reflections work), with direct
/// light by shadow rays along the way; then it traces a batch of photons and adds every photon
/// that lands within a visible point's radius to that pixel's statistics. Between passes each
/// pixel's radius shrinks and its flux is rescaled by the progressive rule
///   N' = N + alpha M,  r' = r sqrt(N' / (N + M)),  tau' = (tau + Phi) r'^2 / r^2,
/// so the estimate L = Ld / passes + tau / (photons emitted pi r^2) converges to the radiance
/// (biased at any finite pass count, consistent as passes grow). Memory is fixed: one visible
/// point and its statistics per pixel, and one pass's photon deposits.
///
/// Parameters (defaults in brackets): photons [the number of pixels] per pass, radius [2 pixel
/// footprints at the distance of each pixel's first visible point] the initial radius,
/// alpha [2/3], max_depth [the scene's, else unbounded with Russian roulette] bounces of camera
/// and photon paths, rr_depth [3]. --spp sets the number of passes.
class SppmIntegrator final : public Integrator {
 public:
  SppmIntegrator(const World& world, const ParamList& params, const RenderSettings& settings);
  std::string name() const override;
  RenderStats render(RenderJob& job) override;

 private:
  /// One pixel: its statistics over passes and the visible point of the current pass.
  struct Pixel {
    double ld[3] = {0, 0, 0};   ///< sum over passes of direct and seen emission
    double tau[3] = {0, 0, 0};  ///< flux, rescaled to the current radius
    double n = 0;               ///< accumulated photon count N
    float radius = 0;  ///< 0 until the pixel's first visible point sets it
    // This pass's visible point, when the camera path found one.
    bool has_vp = false;
    SurfaceInteraction vp;      ///< the point (its material is resolved again per photon)
    Vec3 vp_wo;                 ///< the direction to the camera in vp's shading frame
    Rgb beta;                   ///< throughput from the camera to it
    double phi[3] = {0, 0, 0};  ///< this pass's photon flux through the BSDF
    uint32_t m = 0;             ///< this pass's photons
  };
  /// A photon's contribution to one pixel, kept per pass so pixels sum them in photon order.
  struct Deposit {
    uint32_t pixel;
    Rgb phi;
  };

  /// Traces the camera path of pixel (x, y) for pass `pass`.
  void camera_path(RenderJob& job, Sampler& sampler, int x, int y, int pass, Pixel& px,
                   RayCounter& counter) const;
  /// The photon pass: deposits of `photons` photons into the visible points.
  void photon_pass(RenderJob& job, int pass, uint64_t& rays);
  /// The progressive update of every pixel after a photon pass, and the film's new estimate.
  void update_pixels(RenderJob& job, int passes_done);

  const World& world_;
  uint64_t photons_per_pass_;  ///< 0: the number of pixels
  float initial_radius_;       ///< 0: from each pixel's footprint
  float alpha_;
  int max_depth_;  ///< -1: unbounded
  int rr_depth_;
  uint64_t seed_;
  LightSampler light_sampler_;
  std::vector<Pixel> pixels_;
  int width_ = 0;
  SphereHashGrid grid_;
  std::vector<std::vector<Deposit>> deposits_;  ///< per photon chunk, reused between passes
  uint64_t photons_emitted_ = 0;
};

}  // namespace penumbra
