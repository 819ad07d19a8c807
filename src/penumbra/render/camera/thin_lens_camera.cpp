#include "penumbra/render/camera/thin_lens_camera.h"

#include "penumbra/render/sampling.h"

namespace penumbra {

SceneParams ThinLensCamera::pinhole_params(const SceneParams& params) {
  // Mark the lens keys as read, so the pinhole part's check of unused keys accepts them.
  params.get_float("aperture_radius", 0.0f);
  params.get_float("focus_distance", 0.0f);
  return params;
}

ThinLensCamera::ThinLensCamera(const SceneParams& params, int width, int height)
    : pinhole_(pinhole_params(params), width, height),
      aperture_(params.get_float("aperture_radius", 0.1f)),
      focus_distance_(params.require_float("focus_distance")) {
  if (!(aperture_ >= 0.0f)) params.fail("aperture_radius", "must be non-negative");
  if (!(focus_distance_ > 0.0f)) params.fail("focus_distance", "must be positive");
}

Ray ThinLensCamera::generate_ray(const CameraSample& s) const {
  // The point of the focal plane (camera z = focus distance) on the pinhole ray, and a point of
  // the lens disc.
  const Vec3 focus = pinhole_.camera_direction(s.film) * focus_distance_;
  const Vec2 disc = sample_concentric_disk(s.lens);
  const Vec3 lens{disc.x * aperture_, disc.y * aperture_, 0.0f};
  Ray r;
  r.o = pinhole_.eye() + pinhole_.to_world(lens);
  r.d = normalize(pinhole_.to_world(focus - lens));
  r.time = pinhole_.shutter().time(s.time);
  return r;
}

}  // namespace penumbra
