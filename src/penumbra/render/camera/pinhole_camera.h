#pragma once
/// The pinhole camera: every ray starts at the eye.
#include <array>

#include "penumbra/core/transform.h"
#include "penumbra/render/camera/camera.h"
#include "penumbra/render/camera/shutter.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Pinhole camera with a vertical field of view. Film point (sx, sy) in [0,W)x[0,H) maps to the
/// direction normalize(forward + t (2 sx/W - 1) a right + t (1 - 2 sy/H) up), t = tan(vfov/2),
/// a = W/H, with right = forward x up: the convention of the Cornell box reference data.
/// Parameters: position, look_at, up (default (0,1,0)), vfov (degrees, default 45), shutter
/// ([open, close] in scene time, default [0, 0]: see Shutter), screen_window ([x0, x1, y0, y1],
/// the part of the image plane z = 1 that the film covers, in units of t: x from x0 t at the
/// left edge to x1 t at the right, y from y1 t at the top to y0 t at the bottom; default
/// [-a, a, -1, 1]; an off-centre window shifts the view without turning the camera, as pbrt's
/// screenwindow and a view camera's lens shift do).
class PinholeCamera final : public Camera {
 public:
  PinholeCamera(const SceneParams& params, int width, int height);
  /// A camera from its placement directly (for tests and benchmarks).
  PinholeCamera(Vec3 position, Vec3 look_at, Vec3 up, float vfov_deg, int width, int height);
  Ray generate_ray(const CameraSample& s) const override;
  /// Camera-space direction through film point `film` (unnormalised, z = 1): +x right, +y up.
  /// Inline: path's lanes call it per camera sample.
  Vec3 camera_direction(Vec2 film) const {
    // With the default window (ox_ = oy_ = 0) this is t a (2 sx/W - 1), t (1 - 2 sy/H).
    return {kx_ * (2.0f * film.x * inv_w_ - 1.0f) + ox_,
            ky_ * (1.0f - 2.0f * film.y * inv_h_) + oy_, 1.0f};
  }
  /// Camera-space vector to world space.
  Vec3 to_world(Vec3 v) const { return right_ * v.x + up_ * v.y + forward_ * v.z; }
  Vec3 eye() const { return eye_; }
  /// The camera frame in world space: to_world maps x, y, z to these.
  Vec3 right() const { return right_; }
  Vec3 up() const { return up_; }
  Vec3 forward() const { return forward_; }
  /// The shutter interval that ray times are drawn from.
  const Shutter& shutter() const { return shutter_; }
  /// Replaces the shutter (cameras built from their placement start with [0, 0]).
  void set_shutter(const Shutter& s) { shutter_ = s; }

 private:
  void init(Vec3 position, Vec3 look_at, Vec3 up, float vfov_deg, int width, int height);
  /// Sets the film's window of the image plane: [x0, x1, y0, y1] in units of tan(vfov/2).
  void set_window(float tan_half, const std::array<double, 4>& w);

  Vec3 eye_, forward_, right_, up_;
  Shutter shutter_;
  /// camera_direction's x = kx_ (2 sx/W - 1) + ox_, y = ky_ (1 - 2 sy/H) + oy_.
  float kx_ = 1, ox_ = 0, ky_ = 1, oy_ = 0, inv_w_ = 1, inv_h_ = 1;
};

}  // namespace penumbra
