#pragma once
/// Reading a material parameter that is either a colour or a texture object from a scene file.
#include <string>
#include <vector>

#include "penumbra/render/texture/texture.h"
#include "penumbra/scene/scene_desc.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// The texture types a scene file may name, in the order the error messages list them.
inline constexpr const char* kTextureTypes = "constant, checkerboard, zone_plate, image";

/// Reads parameter `key` of `params`: absent gives the constant `fallback`; a colour ([r, g, b]
/// or one number) gives a constant texture; an object with a "type" gives that texture:
///   {"type": "constant", "color": C}
///   {"type": "checkerboard", "scale": S or [Su, Sv], "colors": [C0, C1], "space": "uv"|"world"}
///   {"type": "zone_plate", "k": K, "center": [u, v], "colors": [C0, C1]}
///   {"type": "image", "file": F, "scale": S or [Su, Sv], "offset": [du, dv],
///    "wrap": W or [Ws, Wt] (repeat, clamp, black, mirror), "factor": C}
/// An image "file" that names one of `embedded` (a SceneDesc's images) decodes its bytes; any
/// other is read from the disk (PNG, JPEG, EXR, PFM by extension). Every colour (and every
/// image pixel times the factor) must lie in [lo, hi] per channel. Errors name the JSON path of
/// the bad value ("FILE:/materials/floor/albedo/colors/1: ...").
Texture read_texture(const SceneParams& params, const std::string& key, Rgb fallback, float lo,
                     float hi, const std::vector<EmbeddedImage>* embedded = nullptr);

}  // namespace penumbra
