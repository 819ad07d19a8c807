/// Malformed glTF files give an InputError naming the file and the JSON path, never a crash, a
/// hang or an unbounded allocation; buffers are read only from the glTF file's own folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "gltf_test_util.h"
#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"

namespace penumbra {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::load_gltf;

// The message of the InputError that loading `text` throws ("" when none).
std::string error_of(const std::string& text, const std::string& base_dir = "") {
  try {
    parse_gltf_scene(text, "model.gltf", base_dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

json one_node_doc(GltfBuilder& b, const json& mesh) {
  return b.doc({{"scenes", {{{"nodes", {0}}}}}, {"nodes", {{{"mesh", 0}}}}, {"meshes", {mesh}}});
}

TEST(GltfError, IndexOutOfRangeNamesThePrimitive) {
  GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int idx = b.indices({0, 1, 900});
  const json mesh = {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}}};
  EXPECT_EQ(error_of(one_node_doc(b, mesh).dump()),
            "model.gltf:/meshes/0/primitives/0/indices: index 900 out of range (3 vertices)");
}

TEST(GltfError, AccessorCountBeyondItsBufferViewIsRefusedBeforeAllocating) {
  GltfBuilder b;
  const json mesh = test::triangle_mesh(b);
  b.accessors()[0]["count"] = 4000000000ull;  // 48 GB of positions from a 36-byte view
  const std::string e = error_of(one_node_doc(b, mesh).dump());
  EXPECT_NE(e.find("model.gltf:/accessors/0/count: count 4000000000 with stride 12"),
            std::string::npos)
      << e;
}

TEST(GltfError, BufferViewBeyondItsBufferNamesTheBufferView) {
  GltfBuilder b;
  json doc = one_node_doc(b, test::triangle_mesh(b));
  doc["bufferViews"][0]["byteLength"] = 4096;
  const std::string e = error_of(doc.dump());
  EXPECT_NE(e.find("model.gltf:/bufferViews/0"), std::string::npos) << e;
}

TEST(GltfError, WrongComponentTypeNamesTheAccessor) {
  GltfBuilder b;
  const json mesh = test::triangle_mesh(b);
  b.accessors()[0]["componentType"] = 5123;  // unsigned short positions
  const std::string e = error_of(one_node_doc(b, mesh).dump());
  EXPECT_NE(e.find("model.gltf:/accessors/0/"), std::string::npos) << e;
}

TEST(GltfError, MissingAccessorNamesTheAttribute) {
  GltfBuilder b;
  json mesh = test::triangle_mesh(b);
  mesh["primitives"][0]["attributes"]["NORMAL"] = 7;
  EXPECT_EQ(error_of(one_node_doc(b, mesh).dump()),
            "model.gltf:/meshes/0/primitives/0/attributes/NORMAL: accessor 7 out of range (2 "
            "accessors)");
}

TEST(GltfError, CycleInTheNodeGraphNamesANode) {
  GltfBuilder b;
  const json doc = b.doc({{"scenes", {{{"nodes", {0}}}}},
                          {"nodes", {{{"mesh", 0}}, {{"children", {2}}}, {{"children", {1}}}}},
                          {"meshes", {test::triangle_mesh(b)}}});
  const std::string e = error_of(doc.dump());
  EXPECT_NE(e.find("the node graph has a cycle through this node"), std::string::npos) << e;
  EXPECT_NE(e.find("model.gltf:/nodes/"), std::string::npos) << e;
}

TEST(GltfError, SelfParentAndTwoParentsAreErrors) {
  GltfBuilder b;
  const json self = b.doc({{"scenes", {{{"nodes", {0}}}}}, {"nodes", {{{"children", {0}}}}}});
  EXPECT_NE(error_of(self.dump()).find("cycle"), std::string::npos);
  const json two = b.doc({{"scenes", {{{"nodes", {0, 1}}}}},
                          {"nodes", {{{"children", {2}}}, {{"children", {2}}}, json::object()}}});
  EXPECT_EQ(error_of(two.dump()),
            "model.gltf:/nodes/1/children/0: node 2 already has parent node 0 (the node graph "
            "must be a forest)");
}

TEST(GltfError, DeepChainOfNodesDoesNotOverflowTheStack) {
  GltfBuilder b;
  json nodes = json::array();
  const int n = 200000;
  for (int i = 0; i < n; ++i)
    nodes.push_back(i + 1 < n ? json{{"children", {i + 1}}} : json{{"mesh", 0}});
  const SceneDesc s = load_gltf(b.doc(
      {{"scenes", {{{"nodes", {0}}}}}, {"nodes", nodes}, {"meshes", {test::triangle_mesh(b)}}}));
  EXPECT_EQ(s.shapes.size(), 1u);
}

TEST(GltfError, DeeplyNestedExtrasAreRefused) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  const std::string text = R"({"asset": {"version": "2.0"}, "extras": )" + deep + "}";
  EXPECT_NE(error_of(text).find("nested deeper than 256 levels"), std::string::npos);
}

// A .glb of `json_text` and `bin` (each padded to 4 bytes).
std::string glb(std::string json_text, std::vector<uint8_t> bin) {
  while (json_text.size() % 4) json_text += ' ';
  while (bin.size() % 4) bin.push_back(0);
  std::string out;
  const auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  out += "glTF";
  u32(2);
  u32(uint32_t(12 + 8 + json_text.size() + (bin.empty() ? 0 : 8 + bin.size())));
  u32(uint32_t(json_text.size()));
  u32(0x4E4F534A);
  out += json_text;
  if (!bin.empty()) {
    u32(uint32_t(bin.size()));
    u32(0x004E4942);
    out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
  }
  return out;
}

TEST(GltfError, GlbLoadsAndEveryTruncationIsAnError) {
  GltfBuilder b;
  json doc = one_node_doc(b, test::triangle_mesh(b));
  doc["buffers"][0].erase("uri");  // the GLB's BIN chunk
  const std::string file = glb(doc.dump(), b.data());
  const SceneDesc s = parse_gltf_scene(file, "model.glb", "");
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[0].geometry).positions.size(), 3u);
  for (size_t n = 0; n < file.size(); n += 7) {
    try {
      parse_gltf_scene(file.substr(0, n), "model.glb", "");
      ADD_FAILURE() << "a .glb cut at byte " << n << " loaded";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("model.glb", 0), 0u) << e.what();
    }
  }
}

TEST(GltfError, ExternalBuffersOnlyFromTheFilesFolder) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / "penumbra_gltf_ext";
  fs::create_directories(dir / "inner");
  GltfBuilder b;
  json doc = one_node_doc(b, test::triangle_mesh(b));
  {
    std::ofstream out(dir / "mesh.bin", std::ios::binary);
    out.write(reinterpret_cast<const char*>(b.data().data()), std::streamsize(b.data().size()));
  }
  doc["buffers"][0]["uri"] = "../mesh.bin";
  EXPECT_NE(error_of(doc.dump(), (dir / "inner").string()), "");  // climbs out of the folder
  doc["buffers"][0]["uri"] = (dir / "mesh.bin").string();         // absolute
  EXPECT_NE(error_of(doc.dump(), (dir / "inner").string()), "");
  doc["buffers"][0]["uri"] = "mesh.bin";
  const SceneDesc s = parse_gltf_scene(doc.dump(), "model.gltf", dir.string());
  EXPECT_EQ(s.shapes.size(), 1u);
  fs::remove_all(dir);
}

TEST(GltfError, ImagesNoTextureUsesAreNeverRead) {
  GltfBuilder b;
  json doc = one_node_doc(b, test::triangle_mesh(b));
  doc["images"] = {{{"uri", "/etc/passwd"}}, {{"uri", "data:image/png;base64,AAAA"}}};
  const SceneDesc s = load_gltf(doc);
  EXPECT_EQ(s.shapes.size(), 1u);
}

TEST(GltfError, SyntaxErrorsNameTheFile) {
  const std::string e = error_of("{\"asset\": ");
  EXPECT_EQ(e.rfind("model.gltf: ", 0), 0u) << e;
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

TEST(GltfError, OverflowingTransformNamesTheNode) {
  test::GltfBuilder b;
  nlohmann::json nodes = nlohmann::json::array();
  for (int i = 0; i < 40; ++i)  // 1e10^40 overflows a double
    nodes.push_back(i + 1 < 40
                        ? nlohmann::json{{"scale", {1e10, 1e10, 1e10}}, {"children", {i + 1}}}
                        : nlohmann::json{{"scale", {1e10, 1e10, 1e10}}, {"mesh", 0}});
  const std::string text =
      b.doc(
           {{"scenes", {{{"nodes", {0}}}}}, {"nodes", nodes}, {"meshes", {test::triangle_mesh(b)}}})
          .dump();
  try {
    parse_gltf_scene(text, "model.gltf", "");
    ADD_FAILURE() << "loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.gltf:/nodes/"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
}

TEST(GltfError, CopiesOfAnEmissiveMeshAreBoundedByTheMemoryLimit) {
  test::GltfBuilder b;
  nlohmann::json mesh = test::triangle_mesh(b);
  mesh["primitives"][0]["material"] = 0;
  nlohmann::json nodes = nlohmann::json::array(), roots = nlohmann::json::array();
  for (int i = 0; i < 1000; ++i) nodes.push_back({{"mesh", 0}}), roots.push_back(i);
  const std::string text = b.doc({{"scenes", {{{"nodes", roots}}}},
                                  {"nodes", nodes},
                                  {"materials", {{{"emissiveFactor", {1, 1, 1}}}}},
                                  {"meshes", {mesh}}})
                               .dump();
  const ScopedMemoryLimit limit(4096);  // far below 1000 copies of the triangle
  EXPECT_THROW(parse_gltf_scene(text, "model.gltf", ""), Error);
}

}  // namespace
}  // namespace penumbra
