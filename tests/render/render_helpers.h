#pragma once
// Shared helpers of the render tests: scenes from JSON text, and rendering them in memory.
#include <memory>
#include <string>

#include "penumbra/core/parallel.h"
#include "penumbra/render/camera/camera_registry.h"
#include "penumbra/render/film.h"
#include "penumbra/render/integrator/integrator_registry.h"
#include "penumbra/render/render_job.h"
#include "penumbra/render/renderer.h"
#include "penumbra/render/filter/filter.h"
#include "penumbra/render/sampler/sampler_registry.h"
#include "penumbra/render/world.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::test {

/// Renders `desc` with its own settings on `threads` workers (0 = all).
inline RgbImage render_desc(const SceneDesc& desc, int threads = 0) {
  const ThreadLimit limit(threads);
  RenderJob job(desc);
  job.run();
  return job.film->resolve();
}

/// Parses scene JSON text (meshes relative to the repository root).
inline SceneDesc scene_from_text(const std::string& json) {
  return parse_scene(json, "test.json", PENUMBRA_SOURCE_DIR);
}

/// Loads a bundled scene from scenes/.
inline SceneDesc bundled_scene(const std::string& name) {
  return load_scene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name);
}

}  // namespace penumbra::test
