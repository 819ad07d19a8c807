#pragma once
/// The thin-lens camera: depth of field.
#include "penumbra/render/camera/pinhole_camera.h"

namespace penumbra {

/// A thin lens of radius `aperture_radius` (world units) focused on the plane at `focus_distance`
/// along the viewing direction (Cook, Porter, Carpenter 1984, "Distributed Ray Tracing"; Kolb,
/// Mitchell, Hanrahan 1995). A ray starts at a uniformly sampled point of the lens disc and passes
/// through the point of the focal plane that the pinhole ray of the same film position meets, so
/// points on the focal plane are sharp and a point at depth z blurs into a disc of diameter
/// aperture_radius |1/z - 1/focus_distance| H / tan(vfov/2) pixels (the circle of confusion).
/// Parameters: those of pinhole (shutter included), plus aperture_radius (default 0.1) and
/// focus_distance (required).
class ThinLensCamera final : public Camera {
 public:
  ThinLensCamera(const SceneParams& params, int width, int height);
  Ray generate_ray(const CameraSample& s) const override;

 private:
  static SceneParams pinhole_params(const SceneParams& params);

  PinholeCamera pinhole_;
  float aperture_, focus_distance_;
};

}  // namespace penumbra
