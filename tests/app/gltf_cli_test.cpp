/// End-to-end tests of `penumbra render model.gltf` / `model.glb`: the glTF reader is chosen by
/// extension, its warnings are printed, and its errors name FILE:/json/path and exit non-zero.
#include <gtest/gtest.h>

#include "../scene/gltf_test_util.h"
#include "cli_fixture.h"
#include "penumbra/image/image_io.h"
#include "penumbra/image/png.h"

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

// A textured triangle (a 2 x 2 PNG in a data: URI) converted to JSON: the image is written beside
// the scene, and the JSON scene renders the same pixels as the glTF file.
TEST_F(GltfCli, ConvertWritesEmbeddedImagesThatTheJsonSceneRenders) {
  RgbImage checker(2, 2, Rgb(1.0f));
  checker.at(0, 0) = Rgb(0.9f, 0.1f, 0.1f);
  checker.at(1, 1) = Rgb(0.1f, 0.1f, 0.9f);
  const std::string png = encode_png(checker);
  test::GltfBuilder b;
  json mesh = test::triangle_mesh(b);
  mesh["primitives"][0]["attributes"]["TEXCOORD_0"] = b.floats({0, 1, 1, 1, 0, 0}, "VEC2", 2);
  mesh["primitives"][0]["material"] = 0;
  const json doc = b.doc(
      {{"scenes", {{{"nodes", {0}}}}},
       {"nodes", {{{"mesh", 0}}}},
       {"meshes", {mesh}},
       {"materials",
        {{{"pbrMetallicRoughness",
           {{"metallicFactor", 0}, {"baseColorTexture", {{"index", 0}}}}}}}},
       {"textures", {{{"source", 0}}}},
       {"images", {{{"uri", "data:image/png;base64," + test::base64({png.begin(), png.end()})}}}}});
  write("tex.gltf", doc.dump());
  ASSERT_EQ(run("convert " + path("tex.gltf") + " -q -o " + path("tex.json")), 0) << err_;
  EXPECT_EQ(read_image(path("tex-meshes/image-0.png")), decode_png(png, "checker.png"));
  const std::string flags = " --resolution 24x24 --spp 1 --integrator raycast:mode=albedo -q -o ";
  ASSERT_EQ(run("render " + path("tex.gltf") + flags + path("a.pfm")), 0) << err_;
  ASSERT_EQ(run("render " + path("tex.json") + flags + path("b.pfm")), 0) << err_;
  const RgbImage a = read_image(path("a.pfm")), c = read_image(path("b.pfm"));
  EXPECT_EQ(a, c);
  // The texture shows: some pixel is much redder than it is blue, another much bluer.
  bool red = false, blue = false;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      red = red || a.at(x, y).r > 3 * a.at(x, y).b;
      blue = blue || a.at(x, y).b > 3 * a.at(x, y).r;
    }
  EXPECT_TRUE(red && blue);
}

}  // namespace
}  // namespace penumbra
