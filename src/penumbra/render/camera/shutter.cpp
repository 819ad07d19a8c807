#include "penumbra/render/camera/shutter.h"

#include <fmt/format.h>

namespace penumbra {

Shutter Shutter::read(const SceneParams& params) {
  // Finiteness is checked by the JSON reader (every number of a scene file must be finite).
  const Vec2 v = params.get_vec2("shutter", {0.0f, 0.0f});
  if (!(v.x <= v.y))
    params.fail("shutter",
                fmt::format("the shutter must open before it closes: [open, close] with open <= "
                            "close, got [{}, {}]",
                            v.x, v.y));
  return {v.x, v.y};
}

}  // namespace penumbra
