#pragma once
/// Materials: the BSDF at a surface point, in the local shading frame (z = shading normal, pointing
/// to the side the surface's front faces). Directions wo (towards the viewer) and wi (towards the
/// light) point away from the surface.
#include <cstddef>
#include <cstdint>
#include <new>
#include <optional>
#include <utility>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"

namespace penumbra {

struct SurfaceInteraction;

/// Room for the material that a textured material becomes at one surface point, so that looking
/// up textures allocates nothing (as pbrt-v4's Material::GetBxDF returns its BxDF by value). An
/// integrator keeps one on its stack per hit. As in pbrt-v4's ScratchBuffer, destructors are never
/// run: what is built here must own no resources (materials holding colours and textures do not).
/// So an unused scratch costs nothing.
class MaterialScratch {
 public:
  /// Constructs a T here, over whatever was here before, and returns it.
  template <class T, class... Args>
  const T& emplace(Args&&... args) {
    static_assert(sizeof(T) <= kBytes && alignof(T) <= kAlign, "MaterialScratch is too small");
    return *new (bytes_) T(std::forward<Args>(args)...);
  }

 private:
  static constexpr size_t kBytes = 160, kAlign = 16;
  alignas(kAlign) std::byte bytes_[kBytes];
};

/// Which quantity a path carries: radiance from the camera, or importance from the lights
/// (photons, light paths). Non-symmetric scattering (refraction's 1/eta^2) depends on it
/// (Veach 1997, "Robust Monte Carlo Methods for Light Transport Simulation", chapter 5).
enum class TransportMode : uint8_t { kRadiance, kImportance };

/// Lobe flags of a BSDF or of one sampled direction (pbrt-v4's BxDFFlags): the side of the
/// scattering and how concentrated it is.
enum BsdfFlags : uint8_t {
  kBsdfNone = 0,
  kBsdfReflection = 1 << 0,
  kBsdfTransmission = 1 << 1,
  kBsdfDiffuse = 1 << 2,
  kBsdfGlossy = 1 << 3,
  kBsdfSpecular = 1 << 4,
};
constexpr BsdfFlags operator|(BsdfFlags a, BsdfFlags b) { return BsdfFlags(uint8_t(a) | uint8_t(b)); }

/// A direction drawn from a BSDF with its value and density.
struct BsdfSample {
  Vec3 wi;
  Rgb f;          ///< BSDF value (for a delta lobe: its coefficient, the lobe's weight / |cos|,
                  ///< so that f |cos| / pdf is the weight over the lobe's probability)
  float pdf = 0;  ///< solid-angle density (for a delta lobe: its discrete probability)
  BsdfFlags flags = kBsdfNone;  ///< the one lobe this direction came from
  float eta = 1;  ///< relative index of refraction (index on wi's side / on wo's side) of a
                  ///< transmission; 1 for reflection
  /// True for a perfectly specular (delta) direction.
  bool is_specular() const { return (flags & kBsdfSpecular) != 0; }
  bool is_transmission() const { return (flags & kBsdfTransmission) != 0; }
};

/// One perfectly specular direction and its throughput weight (f |cos| / probability = the
/// factor applied to the radiance arriving along wi).
struct SpecularLobe {
  Vec3 wi;
  Rgb weight;
};

/// A material's scattering behaviour. Implementations are immutable and thread-safe.
class Material {
 public:
  virtual ~Material() = default;
  /// BSDF value of the non-specular part for the pair (wo, wi), for transport `mode`.
  virtual Rgb eval(Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::kRadiance) const = 0;
  /// Solid-angle density with which `sample` picks wi given wo (non-specular part).
  virtual float pdf(Vec3 wo, Vec3 wi) const = 0;
  /// Draws wi given wo with the uniform samples (uc, u); none when the sample is rejected.
  virtual std::optional<BsdfSample> sample(Vec3 wo, float uc, Vec2 u,
                                           TransportMode mode = TransportMode::kRadiance) const = 0;
  /// Writes the specular (delta) directions for wo into `out` (at most 2), weighted for
  /// radiance; returns how many.
  virtual int specular_lobes(Vec3 wo, SpecularLobe out[2]) const = 0;
  /// The lobes this material has.
  virtual BsdfFlags flags() const = 0;
  /// True when `eval` can be non-zero (direct lighting by shadow rays is worth doing).
  bool has_non_specular() const { return (flags() & (kBsdfDiffuse | kBsdfGlossy)) != 0; }
  /// True when the non-specular part is glossy (concentrated, not diffuse): distribution ray
  /// tracing then also follows directions sampled from the BSDF, weighted against light sampling.
  bool is_glossy() const { return (flags() & kBsdfGlossy) != 0; }
  /// True when every lobe is a delta lobe (no direct lighting, no MIS).
  bool is_specular() const { return !has_non_specular(); }
  /// A representative reflectance, for debugging views.
  virtual Rgb albedo() const = 0;
  /// True when a parameter is textured (at() then builds a copy per surface point).
  bool textured() const { return textured_; }
  /// This material at surface point `si`: itself, or, when a parameter is textured, a copy with
  /// the textures evaluated at `si`, built in `scratch` (which must outlive the use).
  const Material& at(const SurfaceInteraction& si, MaterialScratch& scratch) const {
    return textured_ ? resolve(si, scratch) : *this;
  }

 protected:
  /// Builds the material with this one's textures evaluated at `si` (called when textured_).
  virtual const Material& resolve(const SurfaceInteraction&, MaterialScratch&) const {
    return *this;
  }
  /// Set by a material with a non-constant texture; untextured materials skip the lookup.
  bool textured_ = false;
};

/// Cosine of a local-frame direction with the normal.
constexpr float cos_theta(Vec3 w) { return w.z; }
/// True when both local directions lie on the same side of the surface.
constexpr bool same_hemisphere(Vec3 a, Vec3 b) { return a.z * b.z > 0.0f; }

}  // namespace penumbra
