#include "penumbra/render/material/mirror_material.h"

#include <cmath>

#include "penumbra/render/texture/texture_params.h"

namespace penumbra {

MirrorMaterial::MirrorMaterial(const SceneParams& params,
                               const std::vector<EmbeddedImage>* embedded) {
  reflectance_texture_ = read_texture(params, "reflectance", Rgb(1.0f), 0.0f, 1.0f, embedded);
  textured_ = !reflectance_texture_.is_constant();
  reflectance_ = reflectance_texture_.eval(TextureQuery{});  // the colour itself when constant
  params.check_all_used();
}

const Material& MirrorMaterial::resolve(const SurfaceInteraction& si,
                                        MaterialScratch& scratch) const {
  return scratch.emplace<MirrorMaterial>(reflectance_texture_.eval(si));
}

int MirrorMaterial::specular_lobes(Vec3 wo, SpecularLobe out[2]) const {
  out[0] = {{-wo.x, -wo.y, wo.z}, reflectance_};
  return 1;
}

std::optional<BsdfSample> MirrorMaterial::sample(Vec3 wo, float, Vec2, TransportMode) const {
  const Vec3 wi{-wo.x, -wo.y, wo.z};
  const float c = std::fabs(cos_theta(wi));
  if (!(c > 0.0f)) return std::nullopt;
  return BsdfSample{wi, reflectance_ / c, 1.0f, kBsdfSpecular | kBsdfReflection};
}

}  // namespace penumbra
