#pragma once
/// Cameras turn a point on the film (in pixels) into a ray.
#include <memory>

#include "penumbra/core/ray.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// What a camera needs to generate one ray: the film position and samples for the lens and time.
struct CameraSample {
  Vec2 film;       ///< film position in pixels, (0,0) = top-left corner of the image
  Vec2 lens;       ///< uniform sample in [0,1)^2 for the aperture (unused by a pinhole)
  float time = 0;  ///< uniform sample in [0,1) for the shutter
};

/// A camera: maps film samples to world-space rays.
class Camera {
 public:
  virtual ~Camera() = default;
  /// The primary ray for `s` (direction normalised).
  virtual Ray generate_ray(const CameraSample& s) const = 0;
};

}  // namespace penumbra
