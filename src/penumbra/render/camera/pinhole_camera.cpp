#include "penumbra/render/camera/pinhole_camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "penumbra/core/error.h"

namespace penumbra {

PinholeCamera::PinholeCamera(const SceneParams& params, int width, int height) {
  const Vec3 position = params.require_vec3("position");
  const Vec3 target = params.require_vec3("look_at");
  const Vec3 up = params.get_vec3("up", {0, 1, 0});
  const float vfov = params.get_float("vfov", 45.0f);
  if (!(vfov > 0.0f && vfov < 180.0f)) params.fail("vfov", "must lie in (0, 180) degrees");
  shutter_ = Shutter::read(params);
  std::optional<std::array<double, 4>> window;
  if (const nlohmann::json* j = params.get_json("screen_window")) {
    std::vector<double> w;
    if (j->is_array())
      for (const nlohmann::json& v : *j)
        if (v.is_number() && std::abs(v.get<double>()) <= 1e6) w.push_back(v.get<double>());
    if (w.size() != 4 || j->size() != 4)
      params.fail("screen_window", "must be four numbers [x0, x1, y0, y1] within ±1e6");
    if (!(w[0] < w[1] && w[2] < w[3]))
      params.fail("screen_window", "must have x0 < x1 and y0 < y1");
    window = std::array<double, 4>{w[0], w[1], w[2], w[3]};
  }
  params.check_all_used();
  try {
    init(position, target, up, vfov, width, height);
  } catch (const Error& e) {
    params.fail("look_at", e.what());
  }
  if (window)
    set_window(static_cast<float>(std::tan(double(vfov) * std::numbers::pi / 360.0)), *window);
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
  const float tan_half = static_cast<float>(std::tan(double(vfov_deg) * std::numbers::pi / 360.0));
  const float aspect = float(width) / float(height);
  kx_ = tan_half * aspect;
  ky_ = tan_half;
  ox_ = oy_ = 0.0f;
  inv_w_ = 1.0f / float(width);
  inv_h_ = 1.0f / float(height);
}

void PinholeCamera::set_window(float tan_half, const std::array<double, 4>& w) {
  kx_ = static_cast<float>(double(tan_half) * 0.5 * (w[1] - w[0]));
  ox_ = static_cast<float>(double(tan_half) * 0.5 * (w[1] + w[0]));
  ky_ = static_cast<float>(double(tan_half) * 0.5 * (w[3] - w[2]));
  oy_ = static_cast<float>(double(tan_half) * 0.5 * (w[3] + w[2]));
}

Ray PinholeCamera::generate_ray(const CameraSample& s) const {
  Ray r;
  r.o = eye_;
  r.d = normalize(to_world(camera_direction(s.film)));
  r.time = shutter_.time(s.time);
  return r;
}

}  // namespace penumbra
