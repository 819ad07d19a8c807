#pragma once
/// pbrt-v4 lights as penumbra lights and emissive shapes.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/core/color.h"
#include "penumbra/core/transform.h"
#include "penumbra/scene/pbrt_params.h"

namespace penumbra {

/// The emission an AreaLightSource gives the shapes after it.
struct PbrtAreaLight {
  Rgb radiance;
  bool two_sided = false;
};

/// The light record (a JSON object with "type") of a LightSource: point, distant, infinite with
/// a constant radiance or an equal-area octahedral map (its "filename" resolved in
/// `search_dirs`); spot, goniometric and projection are reported and skipped (nullopt).
/// `to_world` is the CTM in penumbra's world.
std::optional<nlohmann::json> map_pbrt_light(const PbrtEntity& light, const Transform& to_world,
                                             const std::vector<std::string>& search_dirs,
                                             std::vector<std::string>& warnings);

/// The emission of an `AreaLightSource "diffuse"` (other types are InputErrors).
PbrtAreaLight map_pbrt_area_light(const PbrtEntity& light, std::vector<std::string>& warnings);

}  // namespace penumbra
