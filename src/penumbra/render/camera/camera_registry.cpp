#include "penumbra/render/camera/camera_registry.h"

#include <functional>

#include "penumbra/core/registry.h"
#include "penumbra/render/camera/pinhole_camera.h"
#include "penumbra/render/camera/thin_lens_camera.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Camera>(const SceneParams&, int, int)>;

/// Every camera type, written out explicitly: a new one is one line here.
const Registry<Factory>& registry() {
  static const Registry<Factory> all = {
      {"pinhole", "",
       [](const SceneParams& p, int w, int h) { return std::make_unique<PinholeCamera>(p, w, h); }},
      {"thin_lens", "",
       [](const SceneParams& p, int w, int h) {
         return std::make_unique<ThinLensCamera>(p, w, h);
       }},
  };
  return all;
}

}  // namespace

std::vector<std::string> camera_types() { return registry().names(); }

std::unique_ptr<Camera> make_camera(const SceneParams& params, int width, int height) {
  if (const Factory* make = registry().find(params.type())) return (*make)(params, width, height);
  params.fail("type", registry().unknown_name_message("camera type", params.type()));
}

}  // namespace penumbra
