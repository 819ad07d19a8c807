#include "penumbra/render/material/mirror_material.h"

#include <cmath>

namespace penumbra {

MirrorMaterial::MirrorMaterial(const SceneParams& params) {
  reflectance_ = params.get_rgb("reflectance", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(reflectance_[c] >= 0.0f && reflectance_[c] <= 1.0f))
      params.fail("reflectance", "must lie in [0, 1]");
  params.check_all_used();
}

int MirrorMaterial::specular_lobes(Vec3 wo, SpecularLobe out[2]) const {
  out[0] = {{-wo.x, -wo.y, wo.z}, reflectance_};
  return 1;
}

std::optional<BsdfSample> MirrorMaterial::sample(Vec3 wo, float, Vec2) const {
  const Vec3 wi{-wo.x, -wo.y, wo.z};
  const float c = std::fabs(cos_theta(wi));
  if (!(c > 0.0f)) return std::nullopt;
  return BsdfSample{wi, reflectance_ / c, 1.0f, true};
}

}  // namespace penumbra
