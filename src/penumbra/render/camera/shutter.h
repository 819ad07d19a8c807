#pragma once
/// The camera's shutter: the interval of scene time over which one image is exposed.
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// A shutter open over [open, close] in scene time, the time in which moving shapes go from their
/// "transform" (time 0) to their "transform_end" (time 1; see PrimitiveSet). Every camera ray
/// gets a time uniform over the interval, from the sampler's time dimension, so a moving shape
/// blurs along its path: motion blur (Cook, Porter, Carpenter 1984, "Distributed Ray Tracing").
/// The default [0, 0] exposes one instant, time 0: no blur.
struct Shutter {
  float open = 0, close = 0;

  /// The ray time for a uniform sample u in [0, 1): open + (close - open) u, never past close.
  float time(float u) const {
    const float t = open + (close - open) * u;
    return t < close ? t : close;
  }
  /// Reads "shutter": [open, close] (finite numbers, open <= close) from `params`; default [0, 0].
  static Shutter read(const SceneParams& params);
};

}  // namespace penumbra
