/// End-to-end tests of glTF textures: a quad with a 2 x 2 checker base colour texture (a PNG in a
/// data: URI, a JPEG file beside the glTF file) renders the same bits as the same scene in
/// penumbra's JSON naming the image file; corrupt embedded images are errors naming the image.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "../image/temp_dir.h"
#include "../scene/gltf_test_util.h"
#include "penumbra/core/error.h"
#include "penumbra/image/jpeg.h"
#include "penumbra/image/png.h"
#include "penumbra/render/world.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

using nlohmann::json;
using test::region_mean;
using test::render_desc;

// A 2 x 2 checker: red and white on the top row, white and blue below (row 0 is the top).
RgbImage checker() {
  RgbImage img(2, 2, Rgb(1.0f));
  img.at(0, 0) = Rgb(0.8f, 0.1f, 0.1f);
  img.at(1, 1) = Rgb(0.1f, 0.1f, 0.8f);
  return img;
}

// A quad in the z = 0 plane from (-1, -1) to (1, 1), uvs with glTF's top-left origin.
const std::vector<float> kQuad = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
const std::vector<float> kGltfUv = {0, 1, 1, 1, 1, 0, 0, 0};
const std::vector<uint32_t> kQuadIdx = {0, 1, 2, 0, 2, 3};

const json kRender = {{"resolution", {16, 16}}, {"spp", 4}, {"integrator", "raycast:mode=albedo"}};
const json kCamera = {{"type", "pinhole"},
                      {"position", {0, 0, 3}},
                      {"look_at", {0, 0, 0}},
                      {"up", {0, 1, 0}},
                      {"vfov", 40}};

// The glTF file: the quad with a material whose base colour texture is image 0 = `image`,
// mirrored along s and clamped along t, times baseColorFactor (1, 0.5, 1).
SceneDesc gltf_scene(const json& image, const std::string& base_dir) {
  test::GltfBuilder b;
  const int pos = b.floats(kQuad, "VEC3", 3);
  const int uv = b.floats(kGltfUv, "VEC2", 2);
  const int idx = b.indices(kQuadIdx);
  const json doc = b.doc({{"scenes", {{{"nodes", {0}}}}},
                          {"nodes", {{{"mesh", 0}}}},
                          {"meshes",
                           {{{"primitives",
                              {{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}},
                                {"indices", idx},
                                {"material", 0}}}}}}},
                          {"materials",
                           {{{"pbrMetallicRoughness",
                              {{"baseColorFactor", {1, 0.5, 1, 1}},
                               {"metallicFactor", 0},
                               {"baseColorTexture", {{"index", 0}}}}}}}},
                          {"textures", {{{"source", 0}, {"sampler", 0}}}},
                          {"samplers", {{{"wrapS", 33648}, {"wrapT", 33071}}}},
                          {"images", {image}}});
  SceneDesc s = parse_gltf_scene(doc.dump(), "quad.gltf", base_dir);
  s.camera = SceneParams(kCamera, "quad.gltf", "/camera");
  s.lights.clear();
  return s;
}

// The same quad in penumbra's JSON, its texture the image file `file`.
SceneDesc json_scene(const std::string& file) {
  json uvs = json::array();
  for (size_t i = 0; i < kGltfUv.size(); i += 2) uvs.push_back({kGltfUv[i], 1 - kGltfUv[i + 1]});
  json positions = json::array();
  for (size_t i = 0; i < kQuad.size(); i += 3)
    positions.push_back({kQuad[i], kQuad[i + 1], kQuad[i + 2]});
  const json doc = {{"camera", kCamera},
                    {"render", kRender},
                    {"materials",
                     {{"checker",
                       {{"type", "diffuse"},
                        {"albedo",
                         {{"type", "image"},
                          {"file", file},
                          {"wrap", {"mirror", "clamp"}},
                          {"factor", {1, 0.5, 1}}}}}}}},
                    {"shapes",
                     {{{"type", "mesh"},
                       {"material", "checker"},
                       {"positions", positions},
                       {"uvs", uvs},
                       {"indices", {{0, 1, 2}, {0, 2, 3}}}}}}};
  return test::scene_from_text(doc.dump());
}

RgbImage render_twin(SceneDesc g, const SceneDesc& j) {
  g.render = j.render;
  return render_desc(g, 2);
}

TEST(GltfTextureRender, CheckerQuadFromADataUriPngRendersLikeItsJsonTwin) {
  const test::TempDir dir;
  const std::string png = encode_png(checker());
  std::ofstream(dir.file("checker.png"), std::ios::binary) << png;
  const std::vector<uint8_t> bytes(png.begin(), png.end());
  const SceneDesc g =
      gltf_scene({{"uri", "data:image/png;base64," + test::base64(bytes)}}, dir.path().string());
  for (const std::string& w : g.warnings)  // only the camera and lights it lacks
    EXPECT_TRUE(w.find("texture") == std::string::npos && w.find("image") == std::string::npos &&
                w.find("sampler") == std::string::npos)
        << w;
  ASSERT_EQ(g.images.size(), 1u);
  const SceneDesc j = json_scene(dir.file("checker.png"));
  const RgbImage a = render_twin(g, j), b = render_desc(j, 2);
  ASSERT_EQ(a.width(), 16);
  EXPECT_EQ(test::differing_values(a, b), 0u);
  // The texture is there, upright: red (times the factor) at the top left, blue at the bottom
  // right, white (1, 0.5, 1) elsewhere.
  const Rgb top_left = region_mean(a, 4, 4, 6, 6), bottom_right = region_mean(a, 10, 10, 12, 12);
  const Rgb top_right = region_mean(a, 10, 4, 12, 6);
  EXPECT_GT(top_left.r, 3 * top_left.b);
  EXPECT_GT(bottom_right.b, 3 * bottom_right.r);
  EXPECT_NEAR(top_right.g, 0.5f * top_right.r, 0.05f);
}

TEST(GltfTextureRender, CheckerQuadFromAJpegFileRendersLikeItsJsonTwin) {
  const test::TempDir dir;
  std::ofstream(dir.file("checker.jpg"), std::ios::binary) << encode_jpeg(checker(), 100);
  const SceneDesc g = gltf_scene({{"uri", "checker.jpg"}}, dir.path().string());
  ASSERT_EQ(g.images.size(), 1u);
  EXPECT_EQ(g.images[0].mime_type, "image/jpeg");
  const SceneDesc j = json_scene(dir.file("checker.jpg"));
  const RgbImage a = render_twin(g, j), b = render_desc(j, 2);
  EXPECT_EQ(test::differing_values(a, b), 0u);
  const Rgb top_left = region_mean(a, 4, 4, 6, 6);
  EXPECT_GT(top_left.r, 3 * top_left.b);
}

TEST(GltfTextureRender, CorruptEmbeddedPngAndJpegAreErrorsNamingTheImage) {
  for (const std::string& bytes :
       {std::string("\x89PNG\r\n\x1a\n", 8) + "corrupt", std::string("\xFF\xD8\xFF\x01xx", 6)}) {
    const std::vector<uint8_t> v(bytes.begin(), bytes.end());
    const SceneDesc g =
        gltf_scene({{"uri", "data:application/octet-stream;base64," + test::base64(v)},
                    {"mimeType", bytes[0] == '\x89' ? "image/png" : "image/jpeg"}},
                   "");
    std::string e;
    try {
      World w(g, "bvh");
    } catch (const InputError& err) {
      e = err.what();
    }
    EXPECT_EQ(e.rfind("quad.gltf:/materials/0/albedo/file: cannot read the texture: "
                      "quad.gltf#/images/0",
                      0),
              0u)
        << e;
  }
}

}  // namespace
}  // namespace penumbra
