#include "penumbra/render/camera/pinhole_camera.h"

#include <cmath>
#include <numbers>

#include "penumbra/core/error.h"

namespace penumbra {

PinholeCamera::PinholeCamera(const SceneParams& params, int width, int height) {
  const Vec3 position = params.require_vec3("position");
  const Vec3 target = params.require_vec3("look_at");
  const Vec3 up = params.get_vec3("up", {0, 1, 0});
  const float vfov = params.get_float("vfov", 45.0f);
  if (!(vfov > 0.0f && vfov < 180.0f)) params.fail("vfov", "must lie in (0, 180) degrees");
  shutter_ = Shutter::read(params);
  params.check_all_used();
  try {
    init(position, target, up, vfov, width, height);
  } catch (const Error& e) {
    params.fail("look_at", e.what());
  }
}

PinholeCamera::PinholeCamera(Vec3 position, Vec3 look_at, Vec3 up, float vfov_deg, int width,
                             int height) {
  init(position, look_at, up, vfov_deg, width, height);
}

void PinholeCamera::init(Vec3 position, Vec3 target, Vec3 up, float vfov_deg, int width,
                         int height) {
  // The camera frame: columns right, up, forward of look_at's camera-to-world matrix.
  const Transform to_world = look_at(position, target, up);
  eye_ = position;
  right_ = normalize(to_world.vector({1, 0, 0}));
  up_ = normalize(to_world.vector({0, 1, 0}));
  forward_ = normalize(to_world.vector({0, 0, 1}));
  tan_half_ = static_cast<float>(std::tan(double(vfov_deg) * std::numbers::pi / 360.0));
  aspect_ = float(width) / float(height);
  inv_w_ = 1.0f / float(width);
  inv_h_ = 1.0f / float(height);
}

Vec3 PinholeCamera::camera_direction(Vec2 film) const {
  return {tan_half_ * aspect_ * (2.0f * film.x * inv_w_ - 1.0f),
          tan_half_ * (1.0f - 2.0f * film.y * inv_h_), 1.0f};
}

Ray PinholeCamera::generate_ray(const CameraSample& s) const {
  Ray r;
  r.o = eye_;
  r.d = normalize(to_world(camera_direction(s.film)));
  r.time = shutter_.time(s.time);
  return r;
}

}  // namespace penumbra
