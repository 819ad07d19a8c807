// Names of registered parts (accelerator, integrator, sampler, filter) that a scene file gets
// wrong are reported with the file and the JSON path of the setting (issue #18).
#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"
#include "penumbra/render/render_job.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

/// The message of the error that building a render of a small scene with `render` throws.
std::string job_error(const std::string& render) {
  const SceneDesc desc = parse_scene(
      R"({"camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
          "render": {"resolution": [8, 8], )" +
          render + R"(},
          "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
          "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})",
      "scene.json", "");
  try {
    RenderJob job(desc);
  } catch (const InputError& e) {
    return e.what();
  } catch (const Error& e) {
    return std::string("(not an InputError) ") + e.what();
  }
  return "(no error)";
}

TEST(RenderJobMessages, UnknownAcceleratorNamesFileAndPath) {
  const std::string m = job_error(R"("accel": "octopus")");
  EXPECT_EQ(m.rfind("scene.json:/render/accel: unknown acceleration structure 'octopus'", 0), 0u)
      << m;
  EXPECT_NE(job_error(R"("accel": "grid:bogus=1")").find("scene.json:/render/accel: "),
            std::string::npos);
}

TEST(RenderJobMessages, UnknownIntegratorNamesFileAndPath) {
  const std::string m = job_error(R"("integrator": "pathh")");
  EXPECT_EQ(m.rfind("scene.json:/render/integrator: unknown integrator 'pathh'", 0), 0u) << m;
}

TEST(RenderJobMessages, UnknownSamplerNamesFileAndPath) {
  const std::string m = job_error(R"("sampler": "halton")");
  EXPECT_EQ(m.rfind("scene.json:/render/sampler: unknown sampler 'halton'", 0), 0u) << m;
}

TEST(RenderJobMessages, UnknownFilterNamesFileAndPath) {
  const std::string m = job_error(R"("filter": "sinc")");
  EXPECT_EQ(m.rfind("scene.json:/render/filter: unknown filter 'sinc'", 0), 0u) << m;
}

TEST(RenderJobMessages, ValidNamesBuild) {
  EXPECT_EQ(
      job_error(R"("accel": "grid", "integrator": "path", "sampler": "sobol", "filter": "tent")"),
      "(no error)");
}

}  // namespace
}  // namespace penumbra
