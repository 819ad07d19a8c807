/// End-to-end tests of `penumbra render model.gltf` / `model.glb`: the glTF reader is chosen by
/// extension, its warnings are printed, and its errors name FILE:/json/path and exit non-zero.
#include <gtest/gtest.h>

#include "../scene/gltf_test_util.h"
#include "cli_fixture.h"
#include "penumbra/image/image_io.h"

namespace penumbra {
namespace {

using nlohmann::json;

class GltfCli : public CliFixture {};

TEST_F(GltfCli, RendersAGltfWithDefaultCameraAndLightAndPrintsWarnings) {
  test::GltfBuilder b;
  const json doc = b.doc({{"scenes", {{{"nodes", {0}}}}},
                          {"nodes", {{{"mesh", 0}}}},
                          {"meshes", {test::triangle_mesh(b)}}});
  write("model.gltf", doc.dump());
  ASSERT_EQ(run("render " + path("model.gltf") + " --resolution 32x24 -q -o " + path("out.pfm")), 0)
      << err_;
  const RgbImage img = read_image(path("out.pfm"));
  EXPECT_EQ(img.width(), 32);
  EXPECT_EQ(img.height(), 24);
  EXPECT_NE(err_.find("warning: " + path("model.gltf") + ": no perspective camera"),
            std::string::npos)
      << err_;
  // Lit by the default environment: the centre pixel (on the triangle or the sky) is not black.
  EXPECT_GT(img.at(16, 12).g, 0.0f);
}

TEST_F(GltfCli, GlbExtensionInAnyCaseIsRead) {
  write("bad.GLB", "glTF\x02");
  EXPECT_NE(run("render " + path("bad.GLB") + " -q -o " + path("out.pfm")), 0);
  EXPECT_NE(err_.find(path("bad.GLB") + ": "), std::string::npos) << err_;
  EXPECT_EQ(err_.find("JSON"), std::string::npos) << err_;  // not read as a JSON scene
}

TEST_F(GltfCli, ErrorsNameTheJsonPathAndExitNonZero) {
  test::GltfBuilder b;
  const json doc = b.doc({{"scenes", {{{"nodes", {0}}}}},
                          {"nodes", {{{"mesh", 3}}}},
                          {"meshes", {test::triangle_mesh(b)}}});
  write("bad.gltf", doc.dump());
  EXPECT_NE(run("render " + path("bad.gltf") + " -q -o " + path("out.pfm")), 0);
  EXPECT_NE(err_.find(path("bad.gltf") + ":/nodes/0/mesh: mesh 3 out of range (1 meshes)"),
            std::string::npos)
      << err_;
}

}  // namespace
}  // namespace penumbra
