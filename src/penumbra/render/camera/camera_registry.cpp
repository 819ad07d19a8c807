#include "penumbra/render/camera/camera_registry.h"

#include <functional>
#include <utility>

#include "penumbra/render/camera/pinhole_camera.h"
#include "penumbra/render/camera/thin_lens_camera.h"

namespace penumbra {

namespace {

using Factory = std::function<std::unique_ptr<Camera>(const SceneParams&, int, int)>;

/// Every camera type, written out explicitly: a new one is one line here.
const std::vector<std::pair<std::string, Factory>>& entries() {
  static const std::vector<std::pair<std::string, Factory>> all = {
      {"pinhole",
       [](const SceneParams& p, int w, int h) { return std::make_unique<PinholeCamera>(p, w, h); }},
      {"thin_lens", [](const SceneParams& p, int w,
                       int h) { return std::make_unique<ThinLensCamera>(p, w, h); }},
  };
  return all;
}

}  // namespace

std::vector<std::string> camera_types() {
  std::vector<std::string> names;
  for (const auto& [name, make] : entries()) names.push_back(name);
  return names;
}

std::unique_ptr<Camera> make_camera(const SceneParams& params, int width, int height) {
  for (const auto& [name, make] : entries())
    if (name == params.type()) return make(params, width, height);
  std::string valid;
  for (const auto& [name, make] : entries()) valid += (valid.empty() ? "" : ", ") + name;
  params.fail("type", "unknown camera type '" + params.type() + "' (valid: " + valid + ")");
}

}  // namespace penumbra
