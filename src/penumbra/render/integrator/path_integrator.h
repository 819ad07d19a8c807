#pragma once
/// `path`: unidirectional path tracing, the unbiased solution of the rendering equation (Kajiya
/// 1986, "The Rendering Equation"; next-event estimation and multiple importance sampling after
/// Veach 1997, "Robust Monte Carlo Methods for Light Transport Simulation", chapter 9).
#include <memory>
#include <string>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/integrator/path_lanes.h"
#include "penumbra/render/light/light_sampler.h"

namespace penumbra {

/// Follows one path per camera sample: at each hit the BSDF picks the next direction, the
/// throughput keeps the absorption so far, and the path ends when it leaves the scene, at
/// max_depth bounces, or by Russian roulette (from rr_depth bounces on, with the survival
/// probability min(0.95, (max beta eta^2)^rr_exponent) when that is below 1; eta^2 undoes the
/// radiance scaling of refraction, so radiance compressed into glass does not end paths early).
///
/// Strategies for the light a path reaches:
/// - `mis` (default): at every non-specular vertex one light sample with a shadow ray
///   (next-event estimation), and emission found by the BSDF-sampled continuation; the two
///   weighted by the power heuristic (Veach, Guibas 1995).
/// - `nee`: light sampling only; emission that a BSDF-sampled ray finds counts only when seen
///   directly or through specular bounces.
/// - `bsdf`: the lecture's naive path tracer, which finds extended lights only by hitting them
///   (point and directional lights, which no ray can hit, are still sampled by shadow rays).
/// All three converge to the same image. Specular chains (mirrors, smooth glass) are followed
/// exactly: no light sampling there, and emission seen through them counts fully.
///
/// Parameters: strategy (mis, nee, bsdf), max_depth (bounces; default unbounded: -1, or the
/// scene's / --max-depth when given), rr_depth (default 3), rr_exponent (default 0.5, Cycles'
/// square root; 1 is pbrt-v4's and Mitsuba 3's survival by the throughput itself), light_sampler
/// (power, uniform), lanes (auto, on, off: shading eight paths at once, below).
///
/// With `lanes=auto` (the default) eight paths are shaded at once, one per vector lane, where
/// that was measured faster (PathLanes: mostly plain diffuse triangles, area lights of triangles
/// and parallelograms, no instances); `lanes=on` shades in lanes wherever they can serve (any
/// world without instances, unknown parts by the scalar code in their lane), `lanes=off` never.
/// The lanes compute the same floats: the image is the same to the bit in every mode.
class PathIntegrator final : public SamplingIntegrator {
 public:
  enum class Strategy { kMis, kNee, kBsdf };
  PathIntegrator(const World& world, const ParamList& params, int max_depth);
  std::string name() const override;
  ~PathIntegrator() override;
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;
  /// By the lanes where they serve the world, else one sample at a time.
  void render_tile(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
                   RayCounter& counter) const override;
  /// True when tiles are shaded eight paths at once.
  bool uses_lanes() const { return lanes_ != nullptr; }

 private:
  /// li for a sampler of static type S: with the final SobolSampler its calls are inlined (four
  /// per bounce; an indirect call cost more than the batched value it returns).
  template <class S>
  Rgb trace(const Ray& ray, S& sampler, RayCounter& counter) const;
  /// A path between two vertices.
  struct PathState {
    Ray ray;               ///< the ray to trace next
    Rgb radiance;          ///< gathered so far
    Rgb beta{1.0f};        ///< throughput
    bool specular = true;  ///< the last bounce was specular (or there was none)
    float bsdf_pdf = 0;    ///< density of the last BSDF-sampled direction
    Vec3 from;             ///< the vertex it left
    float eta_scale = 1;   ///< the product of eta^2 over the refractions so far
  };
  /// A ray that left the scene: the infinite lights' radiance along st.ray, weighted against
  /// light sampling, added to st.radiance.
  void add_escaped(PathState& st) const;
  /// The emission of the area light at `si` towards the path, weighted likewise.
  void add_emitted(const SurfaceInteraction& si, PathState& st) const;
  /// A vertex's work after its emission: the light sample, the BSDF's continuation, the next
  /// ray and Russian roulette. False when the path ends there.
  template <class S>
  bool scatter(const SurfaceInteraction& si, int depth, S& sampler, PathState& st,
               RayCounter& counter) const;
  /// One light sample's contribution at a non-specular vertex (without the path throughput),
  /// from the vertex's light pair u.
  Rgb sample_light(const SurfaceInteraction& si, const Material& m, Vec3 wo, float time, Vec2 u,
                   RayCounter& counter) const;
  /// The MIS weight of emission `light` reached by a BSDF sample of density bsdf_pdf from
  /// `from` in direction wi (hit: the point on an area light).
  float emission_weight(const Light& light, float bsdf_pdf, Vec3 from, Vec3 wi,
                        const LightPoint& hit) const;

  const World& world_;
  Strategy strategy_;
  int max_depth_;  ///< -1: unbounded
  int rr_depth_;
  float rr_exponent_;  ///< survival probability = (max beta eta^2)^rr_exponent, in (0, 1]
  LightSampler light_sampler_;
  enum class Lanes { kAuto, kOn, kOff };
  static Lanes parse_lanes(const std::string& s);
  Lanes lanes_mode_ = Lanes::kAuto;  ///< the `lanes` parameter
  std::unique_ptr<PathLanes> lanes_;

  friend class PathLanes;  // shares the parameters, the light sampler and emission_weight
};

}  // namespace penumbra
