/// Tests of the pbrt reader's scene-wide options (camera, film, sampler, filter, integrator),
/// shapes and Include/Import, through parse_pbrt_scene and load_scene.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <variant>

#include <zlib.h>

#include "../image/temp_dir.h"
#include "pbrt_test_util.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

using test::has_warning;
using test::pbrt_error;
using test::pbrt_scene;

TEST(PbrtOptions, DefaultsArePbrtV4s) {
  const SceneDesc s = pbrt_scene("WorldBegin\n");
  EXPECT_EQ(s.render.width, 1280);
  EXPECT_EQ(s.render.height, 720);
  EXPECT_EQ(s.render.spp, 16);
  EXPECT_EQ(s.render.sampler, "sobol");
  EXPECT_EQ(s.render.integrator, "path");
  EXPECT_EQ(s.render.max_depth, 5);
  EXPECT_EQ(s.render.filter, "gaussian:radius=1.5,sigma=0.5");
  EXPECT_EQ(s.camera.type(), "pinhole");
  EXPECT_FLOAT_EQ(s.camera.get_float("vfov", 0), 90.0f);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(PbrtOptions, FilmSamplerFilterIntegratorMapped) {
  const SceneDesc s = pbrt_scene(
      "Film \"rgb\" \"integer xresolution\" 320 \"integer yresolution\" 200 "
      "\"string filename\" \"out.exr\"\n"
      "Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 3 \"bool jitter\" false\n"
      "PixelFilter \"mitchell\" \"float xradius\" 1.5 \"float yradius\" 1.5 \"float B\" 0.5\n"
      "Integrator \"path\" \"integer maxdepth\" 7\nWorldBegin\n");
  EXPECT_EQ(s.render.width, 320);
  EXPECT_EQ(s.render.height, 200);
  EXPECT_EQ(s.render.spp, 6);
  EXPECT_EQ(s.render.sampler, "regular");
  EXPECT_EQ(s.render.filter, "mitchell:radius=1.5,b=0.5,c=0.333333");
  EXPECT_EQ(s.render.max_depth, 7);
  EXPECT_TRUE(has_warning(s, "test.pbrt:1:1: Film filename \"out.exr\" ignored"));
}

TEST(PbrtOptions, NearestTypesAreWarnedAboutNamingBoth) {
  const SceneDesc s = pbrt_scene(
      "Sampler \"halton\" \"integer pixelsamples\" 8\nPixelFilter \"triangle\"\n"
      "Integrator \"bdpt\" \"integer maxdepth\" 3\nPixelFilter \"box\" \"float xradius\" 1\n"
      "WorldBegin\n");
  EXPECT_EQ(s.render.spp, 8);
  EXPECT_EQ(s.render.sampler, "sobol");
  EXPECT_TRUE(
      has_warning(s, "test.pbrt:1:1: Sampler \"halton\" rendered with penumbra's \"sobol\""));
  EXPECT_EQ(s.render.integrator, "path");
  EXPECT_TRUE(
      has_warning(s, "test.pbrt:3:1: Integrator \"bdpt\" rendered with penumbra's \"path\""));
  // The second PixelFilter replaces the first, with a warning; its radii differ: the larger.
  EXPECT_EQ(s.render.filter, "box:radius=1");
  EXPECT_TRUE(has_warning(s, "test.pbrt:4:1: PixelFilter given again"));
  EXPECT_TRUE(has_warning(s, "PixelFilter radii 1 and 0.5 differ"));
}

TEST(PbrtOptions, FovIsOfTheShorterAxis) {
  const SceneDesc wide = pbrt_scene(
      "Film \"rgb\" \"integer xresolution\" 200 \"integer yresolution\" 100\n"
      "Camera \"perspective\" \"float fov\" 30\nWorldBegin\n");
  EXPECT_FLOAT_EQ(wide.camera.get_float("vfov", 0), 30.0f);
  const SceneDesc tall = pbrt_scene(
      "Film \"rgb\" \"integer xresolution\" 100 \"integer yresolution\" 200\n"
      "Camera \"perspective\" \"float fov\" 30\nWorldBegin\n");
  // tan(vfov / 2) = tan(15 deg) * 200 / 100.
  const double expected =
      2 * std::atan(2 * std::tan(15 * std::numbers::pi / 180)) * 180 / std::numbers::pi;
  EXPECT_NEAR(tall.camera.get_float("vfov", 0), expected, 1e-4);
}

TEST(PbrtOptions, LensRadiusMakesAThinLens) {
  const SceneDesc s = pbrt_scene(
      "LookAt 0 1 -4  0 1 0  0 1 0\n"
      "Camera \"perspective\" \"float lensradius\" 0.05 \"float focaldistance\" 4\nWorldBegin\n");
  EXPECT_EQ(s.camera.type(), "thin_lens");
  EXPECT_FLOAT_EQ(s.camera.get_float("aperture_radius", 0), 0.05f);
  EXPECT_FLOAT_EQ(s.camera.get_float("focus_distance", 0), 4.0f);
  EXPECT_EQ(s.camera.get_vec3("position", {}), Vec3(0, 1, -4));
  const Vec3 dir = normalize(s.camera.get_vec3("look_at", {}) - Vec3(0, 1, -4));
  EXPECT_EQ(dir, Vec3(0, 0, 1));
  EXPECT_EQ(s.camera.get_vec3("up", {}), Vec3(0, 1, 0));
}

TEST(PbrtOptions, UnsupportedCameraIsAnError) {
  EXPECT_EQ(pbrt_error("Camera \"orthographic\"\nWorldBegin"),
            "test.pbrt:1:1: Camera \"orthographic\" is not supported (penumbra has pinhole and "
            "thin-lens perspective cameras)");
}

TEST(PbrtShapes, TriangleMeshWithNormalsAndUvs) {
  const SceneDesc s = pbrt_scene(
      "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0]\n"
      "  \"integer indices\" [0 1 2  0 2 3] \"normal N\" [0 0 1 0 0 1 0 0 1 0 0 1]\n"
      "  \"point2 uv\" [0 0 1 0 1 1 0 1] \"float alpha\" 0.5 \"vector3 S\" [1 0 0 1 0 0 1 0 0 1 0 "
      "0]\n");
  ASSERT_EQ(s.shapes.size(), 1u);
  const auto& m = std::get<TriangleMesh>(s.shapes[0].geometry);
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(m.normals[3], Vec3(0, 0, 1));
  EXPECT_EQ(m.uvs[2].x, 1.0f);
  EXPECT_EQ(m.uvs[2].y, 1.0f);
  EXPECT_EQ(s.shapes[0].material, "pbrt-default");
  EXPECT_TRUE(has_warning(s, "test.pbrt:2:1: \"alpha\" (cut-outs) is not supported"));
  EXPECT_TRUE(has_warning(s, "test.pbrt:4:51: unused parameter \"vector3 S\""));
}

TEST(PbrtShapes, MeshErrors) {
  EXPECT_EQ(pbrt_error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]"),
            "test.pbrt:2:1: Shape \"trianglemesh\" needs \"integer indices\" (optional only with "
            "exactly 3 vertices)");
  EXPECT_EQ(
      pbrt_error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
                 "  \"integer indices\" [0 1 3]"),
      "test.pbrt:3:3: vertex index 3 out of range or not an integer (the mesh has 3 vertices)");
  EXPECT_EQ(pbrt_error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
                       "  \"normal N\" [0 0 1]"),
            "test.pbrt:3:3: \"N\" has 1 normals for 3 positions");
  EXPECT_EQ(pbrt_error("WorldBegin\nShape \"trianglemesh\""),
            "test.pbrt:2:1: Shape \"trianglemesh\" needs \"point3 P\"");
  // Fuzz finding: an index of 2.4e59 was converted to int64_t for the message (undefined).
  EXPECT_EQ(pbrt_error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
                       "  \"integer indices\" [0 1 2.44444e59]"),
            "test.pbrt:3:3: vertex index 2.44444e+59 out of range or not an integer (the mesh has "
            "3 vertices)");
}

TEST(PbrtShapes, BilinearMeshIsTwoTrianglesPerPatch) {
  const SceneDesc s = pbrt_scene(
      "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0]\n"
      "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1]\n");
  const auto& m = std::get<TriangleMesh>(s.shapes[0].geometry);
  // (p00, p10, p01, p11) -> (p00, p10, p11), (p00, p11, p01): front side dp/du x dp/dv = +z.
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 3, 0, 3, 2}));
  EXPECT_FALSE(has_warning(s, "test.pbrt:2:1"));
  EXPECT_TRUE(has_warning(s, "test.pbrt:3:1: 1 of 1 bilinear patches are not planar"));
}

TEST(PbrtShapes, SphereAndItsLimits) {
  const SceneDesc s = pbrt_scene(
      "WorldBegin\nShape \"sphere\" \"float radius\" 2.5\n"
      "Scale 2 2 2\nShape \"sphere\" \"float zmax\" 0.5\n");
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(std::get<SphereData>(s.shapes[0].geometry).radius, 2.5f);
  EXPECT_TRUE(has_warning(s, "test.pbrt:4:1: partial spheres"));
  EXPECT_EQ(pbrt_error("WorldBegin\nScale 1 2 1\nShape \"sphere\""),
            "test.pbrt:3:1: a sphere's transform must be a similarity (rotations, translations, "
            "uniform scales): penumbra has no ellipsoids");
}

TEST(PbrtShapes, DiskIsTessellatedFacingPlusZ) {
  const SceneDesc s = pbrt_scene(
      "WorldBegin\nShape \"disk\" \"float radius\" 2 \"float height\" 1\n"
      "Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1 \"float phimax\" 90\n");
  const auto& full = std::get<TriangleMesh>(s.shapes[0].geometry);
  ASSERT_EQ(full.triangle_count(), 64u);
  double area = 0;
  for (size_t t = 0; t < full.indices.size(); t += 3) {
    const Vec3 a = full.positions[full.indices[t]], b = full.positions[full.indices[t + 1]],
               c = full.positions[full.indices[t + 2]];
    const Vec3 n = cross(b - a, c - a);
    EXPECT_GT(n.z, 0.0f);
    EXPECT_EQ(a.z, 1.0f);
    area += 0.5 * length(n);
  }
  // A regular 64-gon inscribed in the circle of radius 2.
  EXPECT_NEAR(area, 0.5 * 64 * 4 * std::sin(2 * std::numbers::pi / 64), 1e-4);
  const auto& ring = std::get<TriangleMesh>(s.shapes[1].geometry);
  EXPECT_EQ(ring.triangle_count(), 2u * 16u);
  EXPECT_TRUE(has_warning(s, "test.pbrt:2:1: disk tessellated into 64 triangles"));
}

TEST(PbrtShapes, UnsupportedShapesAreSkippedWithAWarning) {
  const SceneDesc s =
      pbrt_scene("WorldBegin\nShape \"cylinder\" \"float radius\" 1\nShape \"sphere\"\n");
  EXPECT_EQ(s.shapes.size(), 1u);
  EXPECT_TRUE(has_warning(s, "test.pbrt:2:1: Shape \"cylinder\" is not supported; skipped"));
  EXPECT_FALSE(has_warning(s, "unused"));
}

TEST(PbrtShapes, MediaAndOptionsAreWarnedAbout) {
  const SceneDesc s = pbrt_scene(
      "Option \"bool disablepixeljitter\" true\nColorSpace \"aces2065-1\"\n"
      "WorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n"
      "MediumInterface \"fog\" \"\"\nWorldEnd\n");
  EXPECT_TRUE(has_warning(s, "test.pbrt:1:8: Option \"bool disablepixeljitter\" ignored"));
  EXPECT_TRUE(has_warning(s, "test.pbrt:2:1: ColorSpace \"aces2065-1\" not supported"));
  EXPECT_TRUE(has_warning(s, "test.pbrt:4:1: MakeNamedMedium: participating media"));
  EXPECT_TRUE(has_warning(s, "test.pbrt:5:1: MediumInterface"));
  EXPECT_TRUE(has_warning(s, "test.pbrt:6:1: WorldEnd is not a pbrt-v4 directive"));
}

TEST(PbrtInclude, RelativeToTheIncludingFile) {
  const test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "sub");
  test::write_bytes(dir.file("main.pbrt"),
                    "Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 32\n"
                    "WorldBegin\nInclude \"sub/a.pbrt\"\nShape \"sphere\"\n");
  test::write_bytes(dir.file("sub/a.pbrt"), "# in sub/\nImport \"b.pbrt\"\nTranslate 1 0 0\n");
  test::write_bytes(dir.file("sub/b.pbrt"), "Shape \"sphere\" \"float radius\" 3\n");
  const SceneDesc s = load_scene(dir.file("main.pbrt"));
  EXPECT_EQ(s.render.width, 64);
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(std::get<SphereData>(s.shapes[0].geometry).radius, 3.0f);
  // The included file's Translate stays in force (Include is textual).
  EXPECT_EQ(s.shapes[1].to_world.point({0, 0, 0}), Vec3(-1, 0, 0));  // mirrored world
  // An error inside an included file names that file.
  test::write_bytes(dir.file("sub/b.pbrt"), "\n  Shape \"sphere\" \"float radius\" [1 2]\n");
  try {
    load_scene(dir.file("main.pbrt"));
    FAIL();
  } catch (const InputError& e) {
    const std::string expected = (dir.path() / "sub/b.pbrt").lexically_normal().string() +
                                 ":2:18: parameter \"float radius\" takes one value, got 2";
    EXPECT_EQ(e.what(), expected);
  }
  EXPECT_NE(pbrt_error("Include \"missing.pbrt\"", dir.path().string()).find("file not found"),
            std::string::npos);
}

TEST(PbrtInclude, SelfInclusionIsStopped) {
  const test::TempDir dir;
  test::write_bytes(dir.file("loop.pbrt"), "Include \"loop.pbrt\"\n");
  EXPECT_THROW(load_scene(dir.file("loop.pbrt")), InputError);
}

TEST(PbrtShapes, PlyMeshThroughThePlyReader) {
  const test::TempDir dir;
  test::write_bytes(dir.file("quad.ply"),
                    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                    "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  test::write_bytes(dir.file("s.pbrt"),
                    "WorldBegin\nShape \"plymesh\" \"string filename\" \"quad.ply\"\n"
                    "Shape \"plymesh\" \"string filename\" \"nope.ply\"\n");
  try {
    load_scene(dir.file("s.pbrt"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":3:1: PLY file not found: "), std::string::npos);
  }
  test::write_bytes(dir.file("s.pbrt"),
                    "WorldBegin\nShape \"plymesh\" \"string filename\" \"quad.ply\"\n");
  const SceneDesc s = load_scene(dir.file("s.pbrt"));
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[0].geometry).indices,
            (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  // The same file gzip-compressed, as pbrt-v4 scenes often ship their meshes.
  const std::string ply = test::read_bytes(dir.file("quad.ply"));
  gzFile gz = gzopen(dir.file("quad.ply.gz").c_str(), "wb");
  ASSERT_NE(gz, nullptr);
  ASSERT_EQ(gzwrite(gz, ply.data(), unsigned(ply.size())), int(ply.size()));
  gzclose(gz);
  test::write_bytes(dir.file("gz.pbrt"),
                    "WorldBegin\nShape \"plymesh\" \"string filename\" \"quad.ply.gz\"\n");
  const SceneDesc g = load_scene(dir.file("gz.pbrt"));
  ASSERT_EQ(g.shapes.size(), 1u);
  EXPECT_EQ(std::get<TriangleMesh>(g.shapes[0].geometry).positions[2], Vec3(1, 1, 0));
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

TEST(PbrtOptions, MoreMappings) {
  const SceneDesc s = test::pbrt_scene(
      "Sampler \"independent\" \"integer pixelsamples\" 3 \"integer seed\" 7\n"
      "PixelFilter \"gaussian\" \"float sigma\" 0.25 \"float xradius\" 1 \"float yradius\" 1\n"
      "Integrator \"sppm\" \"integer maxdepth\" 4\nAccelerator \"kdtree\"\nWorldBegin\n");
  EXPECT_EQ(s.render.sampler, "independent");
  EXPECT_EQ(s.render.spp, 3);
  EXPECT_EQ(s.render.seed, 7u);
  EXPECT_EQ(s.render.filter, "gaussian:radius=1,sigma=0.25");
  EXPECT_EQ(s.render.integrator, "sppm");
  EXPECT_EQ(s.render.max_depth, 4);
  EXPECT_EQ(s.render.accel, "kdtree");
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(PbrtSyntax, UnclosedBlocksAndDeprecatedDirectives) {
  const SceneDesc s = test::pbrt_scene(
      "WorldBegin\nTransformBegin\nTransformEnd\nAttributeBegin\nShape \"sphere\"\n");
  EXPECT_TRUE(test::has_warning(s, "test.pbrt:2:1: TransformBegin is deprecated"));
  EXPECT_TRUE(test::has_warning(s, "test.pbrt:4:1: AttributeBegin without AttributeEnd"));
  EXPECT_EQ(test::pbrt_error("WorldBegin\nWorldBegin"), "test.pbrt:2:1: WorldBegin given twice");
  EXPECT_EQ(test::pbrt_error("WorldBegin\nObjectBegin \"a\"\n"),
            "test.pbrt:2:1: ObjectBegin without ObjectEnd");
}

TEST(PbrtInclude, FallsBackToTheMainFilesDirectory) {
  // pbrt-v4 resolves names against the main file's folder; an included file in sub/ may name a
  // file next to the main one.
  const test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "sub");
  test::write_bytes(dir.file("main.pbrt"), "WorldBegin\nInclude \"sub/a.pbrt\"\n");
  test::write_bytes(dir.file("sub/a.pbrt"), "Include \"shapes.pbrt\"\n");
  test::write_bytes(dir.file("shapes.pbrt"), "Shape \"sphere\"\n");
  EXPECT_EQ(load_scene(dir.file("main.pbrt")).shapes.size(), 1u);
  // A gzip-compressed include (pbrt-v4 reads *.pbrt.gz).
  const std::string text = "Shape \"sphere\" \"float radius\" 4\n";
  gzFile gz = gzopen(dir.file("sub/shapes.pbrt.gz").c_str(), "wb");
  ASSERT_NE(gz, nullptr);
  ASSERT_EQ(gzwrite(gz, text.data(), unsigned(text.size())), int(text.size()));
  gzclose(gz);
  test::write_bytes(dir.file("sub/a.pbrt"), "Include \"shapes.pbrt.gz\"\n");
  const SceneDesc s = load_scene(dir.file("main.pbrt"));
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(std::get<SphereData>(s.shapes[0].geometry).radius, 4.0f);
}

}  // namespace
}  // namespace penumbra
