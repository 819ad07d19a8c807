/// Tests of textures: checkerboard parity at known points and on cell edges, zone plate values at
/// known radii, the uv that quads, spheres and triangles hand to textures, and textured materials.
#include "penumbra/render/texture/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "penumbra/render/material/diffuse_material.h"
#include "penumbra/render/material/material_registry.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

using test::render_desc;
using test::scene_from_text;

const Rgb kEven{0.1f, 0.2f, 0.3f}, kOdd{0.9f, 0.8f, 0.7f};

Rgb at_uv(const Texture& t, float u, float v) {
  return t.eval(TextureQuery{{}, {u, v}});
}
Rgb at_p(const Texture& t, Vec3 p) {
  return t.eval(TextureQuery{p, {}});
}

TEST(Texture, ConstantIsItsColour) {
  const Texture t = Texture::constant(kOdd);
  EXPECT_TRUE(t.is_constant());
  EXPECT_EQ(at_uv(t, 0.3f, 0.7f), kOdd);
  EXPECT_EQ(at_p(t, {1e6f, -3, 2}), kOdd);
}

// Scale (4, 2): cells are 1/4 wide in u and 1/2 high in v; cell (i, j) is even when i + j is.
TEST(Texture, CheckerboardParityAtKnownPoints) {
  const Texture t = Texture::checkerboard({4, 2}, kEven, kOdd);
  EXPECT_FALSE(t.is_constant());
  EXPECT_EQ(at_uv(t, 0.1f, 0.1f), kEven);    // (0, 0)
  EXPECT_EQ(at_uv(t, 0.3f, 0.1f), kOdd);     // (1, 0)
  EXPECT_EQ(at_uv(t, 0.3f, 0.6f), kEven);    // (1, 1)
  EXPECT_EQ(at_uv(t, 0.1f, 0.6f), kOdd);     // (0, 1)
  EXPECT_EQ(at_uv(t, 0.9f, 0.9f), kEven);    // (3, 1)
  EXPECT_EQ(at_uv(t, -0.1f, 0.1f), kOdd);    // (-1, 0): negative cells alternate too
  EXPECT_EQ(at_uv(t, -0.3f, -0.1f), kOdd);   // (-2, -1)
  EXPECT_EQ(at_uv(t, -0.3f, -0.6f), kEven);  // (-2, -2)
}

// Cells are half-open [i, i + 1): a point on an edge belongs to the cell above it.
TEST(Texture, CheckerboardEdgesBelongToTheUpperCell) {
  const Texture t = Texture::checkerboard({4, 4}, kEven, kOdd);
  EXPECT_EQ(at_uv(t, 0.25f, 0.1f), kOdd);  // u s = 1 exactly: cell 1
  EXPECT_EQ(at_uv(t, std::nextafter(0.25f, 0.0f), 0.1f), kEven);
  EXPECT_EQ(at_uv(t, 0.0f, 0.0f), kEven);
  EXPECT_EQ(at_uv(t, std::nextafter(0.0f, -1.0f), 0.0f), kOdd);
  EXPECT_EQ(at_uv(t, 0.5f, 0.5f), kEven);  // (2, 2)
}

TEST(Texture, SolidCheckerboardUsesWorldPosition) {
  const Texture t = Texture::checkerboard_3d(2.0f, kEven, kOdd);
  EXPECT_EQ(at_p(t, {0.25f, 0.25f, 0.25f}), kEven);  // (0, 0, 0)
  EXPECT_EQ(at_p(t, {0.75f, 0.25f, 0.25f}), kOdd);   // (1, 0, 0)
  EXPECT_EQ(at_p(t, {0.75f, 0.75f, 0.25f}), kEven);  // (1, 1, 0)
  EXPECT_EQ(at_p(t, {0.75f, 0.75f, 0.75f}), kOdd);   // (1, 1, 1)
  EXPECT_EQ(at_p(t, {-0.25f, 0.25f, 0.25f}), kOdd);  // (-1, 0, 0)
  EXPECT_EQ(at_p(t, {-0.25f, -0.25f, 0.25f}), kEven);
  EXPECT_EQ(t.eval(TextureQuery{{0.25f, 0.25f, 0.25f}, {0.9f, 0.1f}}), kEven);  // uv ignored
}

// c0 + (c1 - c0) (1 + cos(k r^2)) / 2: c1 at the centre, c0 where k r^2 = pi, the mean at pi / 2.
TEST(Texture, ZonePlateAtKnownRadii) {
  const float k = 100.0f;
  const Vec2 c{0.4f, 0.6f};
  const Texture t = Texture::zone_plate(k, c, kEven, kOdd);
  auto expect_rgb = [](Rgb a, Rgb b) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], 1e-5f);
  };
  expect_rgb(at_uv(t, c.x, c.y), kOdd);
  const float r_dark = std::sqrt(std::numbers::pi_v<float> / k);
  expect_rgb(at_uv(t, c.x + r_dark, c.y), kEven);
  expect_rgb(at_uv(t, c.x, c.y - r_dark), kEven);
  const float r_mean = std::sqrt(0.5f * std::numbers::pi_v<float> / k);
  expect_rgb(at_uv(t, c.x + r_mean * 0.6f, c.y + r_mean * 0.8f), (kEven + kOdd) * 0.5f);
  // The second bright ring: k r^2 = 2 pi.
  const float r_ring = std::sqrt(2.0f * std::numbers::pi_v<float> / k);
  expect_rgb(at_uv(t, c.x - r_ring, c.y), kOdd);
  EXPECT_NEAR(Texture::zone_plate_intensity(3.0, std::numbers::pi / 9.0), 0.75, 1e-15);
}

// The surface interaction at the closest hit of `ray` in `world`.
SurfaceInteraction hit(const World& world, Vec3 o, Vec3 d) {
  Ray ray;
  ray.o = o;
  ray.d = d;
  SurfaceInteraction si;
  RayCounter counter;
  EXPECT_TRUE(world.intersect(ray, si, counter));
  return si;
}

// Quads: (u, v) along (edge1, edge2); spheres: u = phi / 2 pi + 1/2 (phi = atan2(y, x) of the
// normal), v = theta / pi (theta from +z); triangles: barycentric (b1, b2) unless the mesh has uvs.
TEST(Texture, SurfaceParametersOfQuadsSpheresAndTriangles) {
  const auto desc = scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
    "materials": {"m": {"type": "diffuse"}},
    "shapes": [
      {"type": "quad", "origin": [0, 0, 0], "edge1": [2, 0, 0], "edge2": [0, 4, 0], "material": "m"},
      {"type": "sphere", "center": [10, 0, 0], "radius": 1, "material": "m"},
      {"type": "mesh", "material": "m", "positions": [[20, 0, 0], [22, 0, 0], [20, 2, 0]],
       "indices": [[0, 1, 2]]},
      {"type": "mesh", "material": "m", "positions": [[30, 0, 0], [32, 0, 0], [30, 2, 0]],
       "uvs": [[0.5, 0.5], [1, 0.5], [0.5, 0]], "indices": [[0, 1, 2]]}]})");
  const World world(desc, "bvh");
  const float eps = 1e-5f;
  SurfaceInteraction si = hit(world, {0.6f, 2.8f, -1}, {0, 0, 1});  // 0.3 e1 + 0.7 e2
  EXPECT_NEAR(si.uv.x, 0.3f, eps);
  EXPECT_NEAR(si.uv.y, 0.7f, eps);
  si = hit(world, {15, 0, 0}, {-1, 0, 0});  // normal +x: phi = 0, theta = pi / 2
  EXPECT_NEAR(si.uv.x, 0.5f, eps);
  EXPECT_NEAR(si.uv.y, 0.5f, eps);
  si = hit(world, {10, 5, 0}, {0, -1, 0});  // normal +y: phi = pi / 2
  EXPECT_NEAR(si.uv.x, 0.75f, eps);
  EXPECT_NEAR(si.uv.y, 0.5f, eps);
  si = hit(world, {10, 0, -5}, {0, 0, 1});  // normal -z: theta = pi
  EXPECT_NEAR(si.uv.y, 1.0f, 1e-3f);
  si = hit(world, {20.5f, 1.0f, -1}, {0, 0, 1});  // b1 = 0.25, b2 = 0.5
  EXPECT_NEAR(si.uv.x, 0.25f, eps);
  EXPECT_NEAR(si.uv.y, 0.5f, eps);
  si = hit(world, {30.5f, 1.0f, -1}, {0, 0, 1});  // 0.25 (0.5, 0.5) + 0.25 (1, 0.5) + 0.5 (0.5, 0)
  EXPECT_NEAR(si.uv.x, 0.625f, eps);
  EXPECT_NEAR(si.uv.y, 0.25f, eps);
}

// A textured material becomes, at each point, the untextured material with the texture's value;
// an untextured one is itself (the exact path of plain colours).
TEST(Texture, MaterialsResolveTheirTexturesAtTheHit) {
  const auto plain = make_material(SceneParams(
      nlohmann::json::parse(R"({"type": "diffuse", "albedo": [0.2, 0.4, 0.6]})"), "t.json", "/m"));
  SurfaceInteraction si;
  MaterialScratch scratch;
  EXPECT_EQ(&plain->at(si, scratch), plain.get());
  const auto checks = make_material(SceneParams(nlohmann::json::parse(R"({"type": "diffuse",
      "albedo": {"type": "checkerboard", "scale": 2, "colors": [[0.1, 0.2, 0.3], [0.9, 0.8, 0.7]]}})"),
                                                "t.json", "/m"));
  si.uv = {0.25f, 0.25f};
  EXPECT_EQ(checks->at(si, scratch).albedo(), kEven);
  EXPECT_EQ(checks->at(si, scratch).eval({0, 0, 1}, {0, 0, 1}),
            kEven * std::numbers::inv_pi_v<float>);
  si.uv = {0.75f, 0.25f};
  EXPECT_EQ(checks->at(si, scratch).albedo(), kOdd);
  const auto mirror = make_material(SceneParams(nlohmann::json::parse(R"({"type": "mirror",
      "reflectance": {"type": "checkerboard", "scale": 2, "colors": [0.25, 0.5]}})"),
                                                "t.json", "/m"));
  SpecularLobe lobes[2];
  ASSERT_EQ(mirror->at(si, scratch).specular_lobes({0, 0, 1}, lobes), 1);
  EXPECT_EQ(lobes[0].weight, Rgb(0.5f));
}

// The raycast albedo view of a checkerboard quad filling a 4 x 4 image, one check per pixel, with
// pixel centres sampled: exactly the parity pattern. A colour written as a constant texture
// object renders bit-identically to the plain colour.
TEST(Texture, RenderedCheckerboardAndConstantTextureObject) {
  const std::string scene = R"({
    "camera": {"type": "pinhole", "position": [0, 0, -1], "look_at": [0, 0, 0], "vfov": 90},
    "render": {"resolution": [4, 4], "spp": 1, "sampler": "regular",
               "integrator": "raycast:mode=albedo"},
    "materials": {"m": {"type": "diffuse", "albedo": ALBEDO}},
    "shapes": [{"type": "quad", "origin": [1, 1, 0], "edge1": [-2, 0, 0], "edge2": [0, -2, 0],
                "material": "m"}]})";
  auto with = [&](const std::string& albedo) {
    std::string s = scene;
    s.replace(s.find("ALBEDO"), 6, albedo);
    return render_desc(scene_from_text(s), 2);
  };
  const RgbImage checks = with(R"({"type": "checkerboard", "scale": 4, "colors": [0.25, 0.75]})");
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_EQ(checks.at(x, y).g, (x + y) % 2 ? 0.75f : 0.25f) << x << y;
  const RgbImage a = with("[0.3, 0.5, 0.7]");
  const RgbImage b = with(R"({"type": "constant", "color": [0.3, 0.5, 0.7]})");
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_EQ(a.at(x, y), b.at(x, y));
}

// Every integrator sees the texture: each pixel of a textured render equals, bit for bit, the same
// pixel of a render with that pixel's colour everywhere (the sample streams do not depend on it).
TEST(Texture, EveryIntegratorShadesWithTheTexture) {
  const std::string scene = R"({
    "camera": {"type": "pinhole", "position": [0, 0, -1], "look_at": [0, 0, 0], "vfov": 90},
    "render": {"resolution": [4, 4], "spp": 4, "sampler": "jittered", "integrator": "INTEGRATOR"},
    "materials": {"m": {"type": "diffuse", "albedo": ALBEDO}},
    "lights": [{"type": "point", "position": [0.3, 0.2, -2], "intensity": 5}],
    "shapes": [{"type": "quad", "origin": [1, 1, 0], "edge1": [-2, 0, 0], "edge2": [0, -2, 0],
                "material": "m"}]})";
  auto with = [&](const std::string& integrator, const std::string& albedo) {
    std::string s = scene;
    s.replace(s.find("INTEGRATOR"), 10, integrator);
    s.replace(s.find("ALBEDO"), 6, albedo);
    return render_desc(scene_from_text(s), 2);
  };
  for (const char* integrator : {"raycast", "whitted", "distribution"}) {
    const RgbImage checks =
        with(integrator, R"({"type": "checkerboard", "scale": 2, "colors": [0.25, 0.75]})");
    const RgbImage even = with(integrator, "0.25"), odd = with(integrator, "0.75");
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        const bool is_odd = (x / 2 + y / 2) % 2;  // 2 x 2 checks over 4 x 4 pixels
        EXPECT_EQ(checks.at(x, y), (is_odd ? odd : even).at(x, y)) << integrator << x << y;
      }
  }
}

}  // namespace
}  // namespace penumbra
