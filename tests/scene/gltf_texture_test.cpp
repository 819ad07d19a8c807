/// glTF textures: the base colour texture becomes an image texture naming an EmbeddedImage, read
/// from a data: URI, a .glb bufferView or a file inside the glTF file's folder; samplers' wrap
/// modes; what is not read is a warning; bad images are errors naming the JSON path.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "gltf_test_util.h"
#include "penumbra/core/error.h"
#include "penumbra/scene/scene_writer.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfBuilder;
using test::has_warning;
using test::load_gltf;

// Stand-ins for image files: nothing is decoded by the importer, only the signature is looked at.
const std::string kPngBytes = std::string("\x89PNG\r\n\x1a\n", 8) + "not really a png";
const std::string kJpegBytes = std::string("\xFF\xD8\xFF\xE0", 4) + "not really a jpeg";

std::vector<uint8_t> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

// One triangle with material 0 = `material`, plus `rest` (textures, images, samplers).
json textured_doc(GltfBuilder& b, const json& material, const json& rest) {
  json doc = b.doc({{"scenes", {{{"nodes", {0}}}}},
                    {"nodes", {{{"mesh", 0}}}},
                    {"meshes", {test::triangle_mesh(b)}},
                    {"materials", {material}}});
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  for (const auto& [key, value] : rest.items()) doc[key] = value;
  return doc;
}

json diffuse_with_texture(const json& texture_info = {{"index", 0}}) {
  return {{"pbrMetallicRoughness",
           {{"baseColorFactor", {0.5, 0.25, 1, 1}},
            {"metallicFactor", 0},
            {"baseColorTexture", texture_info}}}};
}

json data_uri_images(const std::string& mime, const std::string& bytes) {
  return {{"textures", {{{"source", 0}}}},
          {"images", {{{"uri", "data:" + mime + ";base64," + test::base64(bytes_of(bytes))}}}}};
}

std::string error_of(const json& doc, const std::string& base_dir = "") {
  try {
    parse_gltf_scene(doc.dump(), "model.gltf", base_dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(GltfTexture, DataUriBaseColorTextureBecomesAnEmbeddedImageTimesTheFactor) {
  GltfBuilder b;
  const SceneDesc s =
      load_gltf(textured_doc(b, diffuse_with_texture(), data_uri_images("image/png", kPngBytes)));
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].name, "model.gltf#/images/0");
  EXPECT_EQ(s.images[0].mime_type, "image/png");
  EXPECT_EQ(*s.images[0].bytes, kPngBytes);
  const json albedo = s.materials[0].params.json()["albedo"];
  EXPECT_EQ(albedo, json({{"type", "image"},
                          {"file", "model.gltf#/images/0"},
                          {"wrap", {"repeat", "repeat"}},
                          {"factor", {0.5, 0.25, 1}}}));
  EXPECT_FALSE(has_warning(s, "textures are not read"));
}

TEST(GltfTexture, MetallicBaseColorTextureFeedsTheConductorReflectance) {
  GltfBuilder b;
  json material = diffuse_with_texture();
  material["pbrMetallicRoughness"]["metallicFactor"] = 1;
  const SceneDesc s =
      load_gltf(textured_doc(b, material, data_uri_images("image/jpeg", kJpegBytes)));
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].mime_type, "image/jpeg");
  const json& p = s.materials[0].params.json();
  EXPECT_EQ(p["type"], "conductor");
  EXPECT_EQ(p["reflectance"]["file"], "model.gltf#/images/0");
  EXPECT_EQ(p["reflectance"]["factor"], json({0.5, 0.25, 1}));
}

TEST(GltfTexture, TransmissiveMaterialKeepsItsFactorWithAWarning) {
  GltfBuilder b;
  json material = diffuse_with_texture();
  material["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}};
  const SceneDesc s = load_gltf(textured_doc(b, material, data_uri_images("image/png", kPngBytes)));
  EXPECT_TRUE(s.images.empty());
  EXPECT_TRUE(has_warning(s, "/materials/0/pbrMetallicRoughness/baseColorTexture: not read"));
}

TEST(GltfTexture, ExternalUriIsPercentDecodedAndReadInsideTheFolder) {
  const fs::path dir = fs::path(::testing::TempDir()) / "penumbra_gltf_tex_ext";
  fs::create_directories(dir / "inner");
  std::ofstream(dir / "inner" / "my tex.png", std::ios::binary) << kPngBytes;
  std::ofstream(dir / "outside.png", std::ios::binary) << kPngBytes;
  GltfBuilder b;
  json doc =
      textured_doc(b, diffuse_with_texture(),
                   {{"textures", {{{"source", 0}}}}, {"images", {{{"uri", "my%20tex.png"}}}}});
  const SceneDesc s = parse_gltf_scene(doc.dump(), "model.gltf", (dir / "inner").string());
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(*s.images[0].bytes, kPngBytes);
  EXPECT_EQ(s.images[0].mime_type, "image/png");
  // Climbing out of the folder, an absolute path and a missing file are errors at the image's uri.
  for (const std::string& uri :
       {std::string("../outside.png"), (dir / "outside.png").string(), std::string("gone.png")}) {
    doc["images"][0]["uri"] = uri;
    const std::string e = error_of(doc, (dir / "inner").string());
    EXPECT_EQ(e.rfind("model.gltf:/images/0/uri: ", 0), 0u) << uri << ": " << e;
  }
  fs::remove_all(dir);
}

// A .glb of `doc` whose buffer 0 is the BIN chunk `bin`.
std::string glb(json doc, const std::vector<uint8_t>& bin) {
  doc["buffers"] = json::array({{{"byteLength", bin.size()}}});
  std::string text = doc.dump();
  while (text.size() % 4) text += ' ';
  std::string b(bin.begin(), bin.end());
  while (b.size() % 4) b += '\0';
  const auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string body = u32(uint32_t(text.size())) + "JSON" + text + u32(uint32_t(b.size())) +
                           std::string("BIN\0", 4) + b;
  return "glTF" + u32(2) + u32(uint32_t(12 + body.size())) + body;
}

// A triangle and an image in one BIN chunk: the image is bufferView `image_view`.
json glb_doc(GltfBuilder& b, std::vector<uint8_t>& bin, size_t image_bytes) {
  json doc = textured_doc(b, diffuse_with_texture(),
                          {{"textures", {{{"source", 0}}}},
                           {"images", {{{"bufferView", 2}, {"mimeType", "image/png"}}}}});
  bin = b.data();
  const size_t offset = bin.size();
  bin.insert(bin.end(), kPngBytes.begin(), kPngBytes.end());
  doc.erase("buffers");
  doc["bufferViews"].push_back(
      {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", image_bytes}});
  return doc;
}

TEST(GltfTexture, GlbBufferViewImageIsEmbedded) {
  GltfBuilder b;
  std::vector<uint8_t> bin;
  const json doc = glb_doc(b, bin, kPngBytes.size());
  const SceneDesc s = parse_gltf_scene(glb(doc, bin), "model.glb", "");
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].name, "model.glb#/images/0");
  EXPECT_EQ(*s.images[0].bytes, kPngBytes);
  EXPECT_EQ(s.materials[0].params.json()["albedo"]["file"], "model.glb#/images/0");
}

TEST(GltfTexture, ImageBufferViewBeyondItsBufferOrOutOfRangeNamesTheJsonPath) {
  GltfBuilder b;
  std::vector<uint8_t> bin;
  json doc = glb_doc(b, bin, kPngBytes.size() + 4096);
  std::string e;
  try {
    parse_gltf_scene(glb(doc, bin), "model.glb", "");
  } catch (const InputError& err) {
    e = err.what();
  }
  EXPECT_EQ(e.rfind("model.glb:/bufferViews/2: byteOffset ", 0), 0u) << e;
  EXPECT_NE(e.find("(used by /images/0)"), std::string::npos) << e;
  doc["images"][0]["bufferView"] = 9;
  e.clear();
  try {
    parse_gltf_scene(glb(doc, bin), "model.glb", "");
  } catch (const InputError& err) {
    e = err.what();
  }
  EXPECT_EQ(e.rfind("model.glb:/images/0/bufferView: ", 0), 0u) << e;
}

TEST(GltfTexture, BadBase64NamesTheImageUri) {
  GltfBuilder b;
  json doc = textured_doc(b, diffuse_with_texture(), data_uri_images("image/png", kPngBytes));
  doc["images"][0]["uri"] = "data:image/png;base64,!!!!";
  EXPECT_EQ(error_of(doc), "model.gltf:/images/0/uri: bad data: URI (not valid base64 data)");
}

TEST(GltfTexture, BadTextureSamplerAndSourceIndicesNameTheJsonPath) {
  GltfBuilder b;
  json doc = textured_doc(b, diffuse_with_texture({{"index", 3}}),
                          data_uri_images("image/png", kPngBytes));
  EXPECT_EQ(
      error_of(doc).rfind(
          "model.gltf:/materials/0/pbrMetallicRoughness/baseColorTexture/index: texture 3", 0),
      0u)
      << error_of(doc);
  doc["materials"][0] = diffuse_with_texture();
  doc["textures"][0]["source"] = 5;
  EXPECT_EQ(error_of(doc).rfind("model.gltf:/textures/0/source: image 5 out of range", 0), 0u)
      << error_of(doc);
  doc["textures"][0] = {{"source", 0}, {"sampler", 2}};
  EXPECT_EQ(error_of(doc).rfind("model.gltf:/textures/0/sampler: sampler 2 out of range", 0), 0u)
      << error_of(doc);
}

TEST(GltfTexture, SamplerWrapModesMapPerAxis) {
  GltfBuilder b;
  json rest = data_uri_images("image/png", kPngBytes);
  rest["textures"][0]["sampler"] = 0;
  rest["samplers"] = {{{"wrapS", 33648}, {"wrapT", 33071}, {"magFilter", 9728}}};
  const SceneDesc s = load_gltf(textured_doc(b, diffuse_with_texture(), rest));
  EXPECT_EQ(s.materials[0].params.json()["albedo"]["wrap"], json({"mirror", "clamp"}));
  EXPECT_TRUE(has_warning(s, "/samplers/0/magFilter: NEAREST filtering not supported"));
  rest["samplers"][0] = json::object();  // the defaults: REPEAT
  const SceneDesc d = load_gltf(textured_doc(b, diffuse_with_texture(), rest));
  EXPECT_EQ(d.materials[0].params.json()["albedo"]["wrap"], json({"repeat", "repeat"}));
}

TEST(GltfTexture, WhatIsNotReadIsAWarningAndTheFactorsAreUsed) {
  GltfBuilder b;
  // texCoord 1: the texture is not used.
  SceneDesc s = load_gltf(textured_doc(b, diffuse_with_texture({{"index", 0}, {"texCoord", 1}}),
                                       data_uri_images("image/png", kPngBytes)));
  EXPECT_TRUE(has_warning(s, "baseColorTexture/texCoord: texCoord 1 not read"));
  EXPECT_TRUE(s.materials[0].params.json()["albedo"].is_array());
  // webp (a data: URI tinygltf does not decode, and a file) and a texture without a source.
  for (const json& image : {json{{"uri", "data:image/webp;base64,AAAA"}}, json{{"uri", "t.webp"}},
                            json{{"uri", "t.ktx2"}}}) {
    json rest = data_uri_images("image/png", kPngBytes);
    rest["images"][0] = image;
    s = load_gltf(textured_doc(b, diffuse_with_texture(), rest));
    EXPECT_TRUE(has_warning(s, "model.gltf:/images/0: image/")) << image;
    EXPECT_TRUE(s.materials[0].params.json()["albedo"].is_array()) << image;
  }
  json rest = data_uri_images("image/png", kPngBytes);
  rest["textures"][0] = {{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}};
  s = load_gltf(textured_doc(b, diffuse_with_texture(), rest));
  EXPECT_TRUE(has_warning(s, "model.gltf:/textures/0: no PNG or JPEG source"));
  // KHR_texture_transform, the other textures and alpha: warnings, the base colour texture used.
  json material = diffuse_with_texture(
      {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {2, 2}}}}}}});
  material["normalTexture"] = {{"index", 0}};
  material["occlusionTexture"] = {{"index", 0}};
  material["emissiveTexture"] = {{"index", 0}};
  material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
  material["alphaMode"] = "MASK";
  s = load_gltf(textured_doc(b, material, data_uri_images("image/png", kPngBytes)));
  EXPECT_TRUE(has_warning(s,
                          "baseColorTexture/extensions/KHR_texture_transform: "
                          "KHR_texture_transform ignored"));
  EXPECT_TRUE(has_warning(s,
                          "/materials/0: textures are not read (metallicRoughnessTexture, "
                          "normalTexture, occlusionTexture, emissiveTexture): factors used"));
  EXPECT_TRUE(has_warning(s, "/materials/0/alphaMode: MASK ignored: opaque (alpha is dropped)"));
  EXPECT_EQ(s.materials[0].params.json()["albedo"]["type"], "image");
}

TEST(GltfTexture, ImagesAreReadOnceAndOnlyWhenUsed) {
  GltfBuilder b;
  json rest = data_uri_images("image/png", kPngBytes);
  rest["images"].push_back({{"uri", "/etc/passwd"}});  // never used: never read
  json doc = textured_doc(b, diffuse_with_texture(), rest);
  doc["materials"].push_back(diffuse_with_texture());
  const SceneDesc s = load_gltf(doc);
  EXPECT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.materials[1].params.json()["albedo"]["file"], "model.gltf#/images/0");
}

TEST(GltfTexture, ConvertWritesEmbeddedImagesAsFilesThatTheTexturesName) {
  GltfBuilder b;
  json rest = data_uri_images("image/jpeg", kJpegBytes);
  const SceneDesc s = load_gltf(textured_doc(b, diffuse_with_texture(), rest));
  const std::vector<SceneFile> files = write_scene_json(s, "out.json", "out-meshes");
  const auto image = std::find_if(files.begin(), files.end(), [](const SceneFile& f) {
    return f.path == "out-meshes/image-0.jpg";
  });
  ASSERT_NE(image, files.end());
  EXPECT_EQ(image->bytes, kJpegBytes);
  const json scene = json::parse(files[0].bytes);
  EXPECT_EQ(scene["materials"]["gltf/0"]["albedo"]["file"], "out-meshes/image-0.jpg");
}

}  // namespace
}  // namespace penumbra
