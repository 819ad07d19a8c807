#pragma once
/// The scene-wide options of a pbrt-v4 file (the directives before WorldBegin): Camera, Film,
/// Sampler, PixelFilter, Integrator and Accelerator, mapped to penumbra's camera record and
/// render settings.
#include <optional>
#include <string>
#include <vector>

#include "penumbra/core/transform.h"
#include "penumbra/scene/pbrt_params.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// The option directives as read (each absent until given) and the camera's transform.
struct PbrtOptions {
  std::optional<PbrtEntity> camera, film, sampler, filter, integrator, accelerator;
  /// pbrt's camera-to-world transform: the inverse of the CTM at the Camera directive (its start
  /// transform when the CTM is animated).
  Transform camera_to_world;
  /// TransformTimes: the scene times of the start and the end transforms (pbrt's defaults).
  double start_time = 0, end_time = 1;
};

/// True when pbrt's picture of the scene is the mirror image of the one penumbra's camera takes
/// from the same camera transform: pbrt's image x axis is camera +x, penumbra's is
/// cross(forward, up), which is camera -x for a transform that keeps handedness. The importer then
/// mirrors the whole world (x -> -x) so the pictures agree.
bool pbrt_camera_mirrors(const Transform& camera_to_world);

/// Fills `scene.camera` and `scene.render` from `options`. The camera gets a "shutter": pbrt's
/// shutteropen and shutterclose (default 0, 1; swapped with a warning when reversed) in penumbra's
/// time, where moving shapes are at their start transform at 0 and at their end transform at 1:
/// t' = (t - start_time) / (end_time - start_time). `world_from_pbrt` takes pbrt's world
/// space to penumbra's (the mirror or the identity). Warnings go to `scene.warnings`; a camera
/// that cannot be represented is an InputError at its directive.
void map_pbrt_options(const PbrtOptions& options, const Transform& world_from_pbrt,
                      SceneDesc& scene);

}  // namespace penumbra
