/// Allocations sized by a scene are checked against the memory limit before they are made: the
/// film, SPPM's visible points and deposits, photon maps, the dense form-factor matrix and the
/// hierarchy's links. Each is refused with the parameter named, and renders below the limit.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/render/render_job.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

/// A light inside a closed sphere: photons bounce and stay in it.
SceneDesc box_scene(const std::string& render) {
  return parse_scene(
      R"({"camera": {"type": "pinhole", "position": [0, 0, -1.5], "look_at": [0, 0, 0]},
          "render": {"spp": 1, )" +
          render + R"(},
          "materials": {"w": {"type": "diffuse", "albedo": 0.8}},
          "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 2, "material": "w"},
                     {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.2, "material": "w",
                      "emission": [4, 4, 4]}]})",
      "scene.json", "");
}

/// The message of what building and running the render throws, or "(no error)".
std::string render_error(const std::string& render) {
  try {
    RenderJob job(box_scene(render));
    job.run();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MemoryLimitRender, AFilmBeyondTheLimitIsRefusedNamingTheResolution) {
  const ScopedMemoryLimit limit(uint64_t(64) << 20);
  const std::string m = render_error(R"("resolution": [4096, 4096], "integrator": "raycast")");
  EXPECT_EQ(m.rfind("scene.json:/render/resolution: the film of 4096 x 4096 pixels needs ", 0), 0u)
      << m;
  EXPECT_NE(m.find("more than the memory limit of 64.0 MiB"), std::string::npos) << m;
  // Far below, the same scene renders.
  EXPECT_EQ(render_error(R"("resolution": [64, 64], "integrator": "raycast")"), "(no error)");
}

TEST(MemoryLimitRender, TheDefaultLimitRefusesTheLargestFilm) {
  const ScopedMemoryLimit none(0);
  set_memory_limit(0);
  // 65536 x 65536 pixels are several hundred GiB: a clear error, never std::bad_alloc.
  const std::string m = render_error(R"("resolution": [65536, 65536], "integrator": "raycast")");
  EXPECT_NE(m.find("/render/resolution: the film of 65536 x 65536 pixels"), std::string::npos) << m;
  EXPECT_NE(m.find("three quarters of this machine's"), std::string::npos) << m;
}

TEST(MemoryLimitRender, APhotonMapBeyondTheLimitIsRefusedNamingPhotons) {
  const ScopedMemoryLimit limit(uint64_t(4) << 20);  // about 75,000 stored photons
  const std::string m =
      render_error(R"("resolution": [8, 8], "integrator": "photon:photons=2000000")");
  // Refused while the map is traced (a photon that bounces is stored again: the count emitted
  // does not bound the map), so before anything is written.
  EXPECT_EQ(m.rfind("photon: photons=2000000: the photon map", 0), 0u) << m;
  EXPECT_NE(m.find("emit fewer photons"), std::string::npos) << m;
  EXPECT_EQ(render_error(
                R"("resolution": [8, 8], "integrator": "photon:photons=2000,caustic_photons=0")"),
            "(no error)");
}

TEST(MemoryLimitRender, SppmVisiblePointsAndDepositsAreBounded) {
  {
    // Above the film's 144 bytes per pixel, below SPPM's visible points.
    const ScopedMemoryLimit limit(uint64_t(200) << 20);
    const std::string m = render_error(R"("resolution": [1024, 1024], "integrator": "sppm")");
    EXPECT_NE(m.find("sppm: the visible points of 1024 x 1024 pixels"), std::string::npos) << m;
  }
  // A radius that covers every visible point: each photon deposits into all 64 pixels.
  const ScopedMemoryLimit limit(uint64_t(2) << 20);
  const std::string m =
      render_error(R"("resolution": [8, 8], "integrator": "sppm:photons=100000,radius=10")");
  EXPECT_NE(m.find("sppm: the photon deposits of pass 0 (photons=100000)"), std::string::npos) << m;
  EXPECT_EQ(render_error(R"("resolution": [8, 8], "integrator": "sppm:photons=1000,radius=0.1")"),
            "(no error)");
}

TEST(MemoryLimitRender, TheDenseFormFactorMatrixIsBoundedByTheLimit) {
  const ScopedMemoryLimit limit(uint64_t(1) << 20);  // 512 elements
  const std::string m = render_error(
      R"("resolution": [8, 8], "integrator": "radiosity:patch=0.1,rays=4,final_gather=false")");
  EXPECT_NE(m.find("radiosity: the dense form-factor matrix of "), std::string::npos) << m;
  EXPECT_NE(m.find("use a larger patch size"), std::string::npos) << m;
  EXPECT_EQ(
      render_error(
          R"("resolution": [8, 8], "integrator": "radiosity:patch=1,rays=4,final_gather=false")"),
      "(no error)");
}

TEST(MemoryLimitRender, HierarchicalLinksAreBoundedByTheLimit) {
  const ScopedMemoryLimit limit(uint64_t(4) << 20);
  const std::string m = render_error(
      R"("resolution": [8, 8], "integrator": "radiosity:hierarchy=true,epsilon=1e-12,patch=0.05,final_gather=false")");
  EXPECT_NE(m.find("hierarchical radiosity: a refinement to "), std::string::npos) << m;
  EXPECT_NE(m.find("raise epsilon"), std::string::npos) << m;
}

}  // namespace
}  // namespace penumbra
