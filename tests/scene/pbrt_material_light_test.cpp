/// Tests of the pbrt reader's materials, textures, area lights and light sources: each mapped to
/// the penumbra record with the right values, the nearest ones with a warning.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pbrt_test_util.h"
#include "penumbra/scene/pbrt_spectra.h"

namespace penumbra {
namespace {

using nlohmann::json;
using test::has_warning;
using test::pbrt_error;
using test::pbrt_scene;

// The material of the one shape that `world` ends with.
const SceneParams& material_of(const SceneDesc& s) {
  for (const MaterialDesc& m : s.materials)
    if (m.name == s.shapes.back().material) return m.params;
  ADD_FAILURE() << "no material " << s.shapes.back().material;
  return s.materials.front().params;
}

SceneDesc world(const std::string& text) {
  return pbrt_scene("WorldBegin\n" + text);
}

TEST(PbrtMaterials, DiffuseAndTheDefault) {
  const SceneDesc s = world(
      "Shape \"sphere\"\nMaterial \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\nShape "
      "\"sphere\"\n");
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].material, "pbrt-default");
  const SceneParams& m = material_of(s);
  EXPECT_EQ(m.type(), "diffuse");
  EXPECT_EQ(m.get_rgb("albedo", {}), Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(s.materials[0].params.get_rgb("albedo", {}), Rgb(0.5f));
}

TEST(PbrtMaterials, ConductorNamedSpectraAndRoughness) {
  // Default eta/k: copper; roughness 0.01 remapped: alpha = sqrt(0.01) = 0.1, ours sqrt(alpha).
  const SceneDesc s = world(
      "Material \"conductor\" \"float roughness\" 0.01\nShape \"sphere\"\n"
      "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\n"
      "  \"float roughness\" 0.04 \"bool remaproughness\" false\nShape \"sphere\"\n"
      "Material \"conductor\" \"rgb reflectance\" [0.5 0.5 0.5]\nShape \"sphere\"\n");
  const auto mat = [&](size_t i) -> const SceneParams& {
    for (const MaterialDesc& m : s.materials)
      if (m.name == s.shapes[i].material) return m.params;
    return s.materials[0].params;
  };
  EXPECT_EQ(mat(0).type(), "conductor");
  EXPECT_NEAR(mat(0).get_float("roughness", 0), std::sqrt(0.1), 1e-6);
  EXPECT_NEAR(mat(0).get_rgb("eta", {}).g, 0.9240334f, 1e-6);  // copper (Tungsten's table)
  EXPECT_NEAR(mat(0).get_rgb("k", {}).r, 3.9129485f, 1e-6);
  EXPECT_NEAR(mat(1).get_float("roughness", 0), 0.2, 1e-6);    // alpha = 0.04 unremapped
  EXPECT_NEAR(mat(1).get_rgb("eta", {}).b, 1.4424786f, 1e-6);  // gold
  // reflectance r: eta 1, k = 2 sqrt(r / (1 - r)) = 2, whose normal-incidence Fresnel is r.
  EXPECT_EQ(mat(2).get_rgb("eta", {}), Rgb(1.0f));
  EXPECT_NEAR(mat(2).get_rgb("k", {}).r, 2.0f, 1e-6);
  const float k = mat(2).get_rgb("k", {}).r;
  EXPECT_NEAR(k * k / (4 + k * k), 0.5f, 1e-6);
}

TEST(PbrtMaterials, DielectricsSmoothRoughAndNamedGlass) {
  const SceneDesc s = world(
      "Material \"dielectric\" \"float eta\" 1.33\nShape \"sphere\"\n"
      "Material \"dielectric\" \"float roughness\" 0.0625\nShape \"sphere\"\n"
      "Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"\nShape \"sphere\"\n"
      "Material \"thindielectric\"\nShape \"sphere\"\n");
  std::vector<const SceneParams*> m;
  for (const ShapeDesc& sh : s.shapes)
    for (const MaterialDesc& d : s.materials)
      if (d.name == sh.material) m.push_back(&d.params);
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m[0]->type(), "dielectric");
  EXPECT_FLOAT_EQ(m[0]->get_float("ior", 0), 1.33f);
  EXPECT_EQ(m[1]->type(), "rough_dielectric");
  EXPECT_FLOAT_EQ(m[1]->get_float("ior", 0), 1.5f);
  EXPECT_FLOAT_EQ(m[1]->get_float("roughness", 0), 0.5f);  // alpha = sqrt(0.0625) = 0.25
  EXPECT_FLOAT_EQ(m[2]->get_float("ior", 0), 1.5168f);
  EXPECT_TRUE(has_warning(s, "test.pbrt:6:23: \"glass-BK7\" taken at 587.6 nm"));
  EXPECT_EQ(m[3]->type(), "dielectric");
  EXPECT_TRUE(
      has_warning(s, "test.pbrt:8:1: material \"thindielectric\" rendered as \"dielectric\""));
}

TEST(PbrtMaterials, SpectrumValues) {
  const SceneDesc s = world(
      "Material \"diffuse\" \"spectrum reflectance\" [0.25]\nShape \"sphere\"\n"
      "Material \"diffuse\" \"spectrum reflectance\" [400 0.2 500 0.4 600 0.6]\n"
      "Shape \"sphere\"\n");
  std::vector<const SceneParams*> m;
  for (const ShapeDesc& sh : s.shapes)
    for (const MaterialDesc& d : s.materials)
      if (d.name == sh.material) m.push_back(&d.params);
  EXPECT_EQ(m[0]->get_rgb("albedo", {}), Rgb(0.25f));
  // Rising towards long wavelengths: reddish.
  const Rgb rising = m[1]->get_rgb("albedo", {});
  EXPECT_GT(rising.r, rising.g);
  EXPECT_GT(rising.g, rising.b);
  EXPECT_NEAR(rising.g, 0.4f, 0.1f);
  // A flat reflectance is exactly grey; a light's spectrum is normalised to luminance 1.
  const Rgb flat = sampled_spectrum_rgb({400, 0.3, 700, 0.3}, false);
  EXPECT_NEAR(flat.r, 0.3f, 1e-6);
  EXPECT_NEAR(flat.g, 0.3f, 1e-6);
  EXPECT_NEAR(flat.b, 0.3f, 1e-6);
  const Rgb light = sampled_spectrum_rgb({300, 5, 900, 5}, true);
  EXPECT_NEAR(0.2126 * light.r + 0.7152 * light.g + 0.0722 * light.b, 1.0, 1e-3);
  EXPECT_TRUE(s.warnings.empty());
  EXPECT_EQ(pbrt_error("WorldBegin\nMaterial \"diffuse\" \"spectrum reflectance\" [500 1 400 1]"),
            "test.pbrt:2:20: parameter \"spectrum reflectance\": wavelengths must increase");
  EXPECT_EQ(pbrt_error("WorldBegin\nMaterial \"diffuse\" \"spectrum reflectance\" \"unobtainium\""),
            "test.pbrt:2:20: spectrum \"unobtainium\": named spectra other than metal-*-eta/k and "
            "stdillum-* and spectrum files are not supported");
}

TEST(PbrtMaterials, NearestMaterialsAreWarnedAbout) {
  const SceneDesc s = world(
      "Material \"coateddiffuse\" \"rgb reflectance\" [0.2 0.4 0.6] \"float roughness\" 0.1\n"
      "Shape \"sphere\"\n");
  const SceneParams& m = material_of(s);
  EXPECT_EQ(m.type(), "diffuse");
  EXPECT_EQ(m.get_rgb("albedo", {}), Rgb(0.2f, 0.4f, 0.6f));
  EXPECT_TRUE(has_warning(s, "test.pbrt:2:1: material \"coateddiffuse\" rendered as \"diffuse\""));
  EXPECT_FALSE(has_warning(s, "unused"));
  EXPECT_EQ(pbrt_error("WorldBegin\nMaterial \"plastic\""),
            "test.pbrt:2:1: unknown material \"plastic\" (pbrt-v4 has: coateddiffuse, "
            "coatedconductor, conductor, dielectric, diffuse, diffusetransmission, hair, "
            "interface, measured, mix, subsurface, thindielectric)");
}

TEST(PbrtMaterials, NamedMaterialsMayBeUsedBeforeTheyAreDefined) {
  const SceneDesc s = world(
      "NamedMaterial \"red\"\nShape \"sphere\"\n"
      "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0 0]\n"
      "AttributeBegin\nMaterial \"conductor\"\nAttributeEnd\nShape \"sphere\"\n");
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].material, "red");
  EXPECT_EQ(s.shapes[1].material, "red");  // AttributeEnd restored the material
  EXPECT_EQ(material_of(s).get_rgb("albedo", {}), Rgb(0.8f, 0, 0));
  EXPECT_EQ(pbrt_error("WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                       "MakeNamedMaterial \"a\" \"string type\" \"diffuse\""),
            "test.pbrt:3:1: named material \"a\" redefined");
}

TEST(PbrtMaterials, InterfaceShapesAreNotSurfaces) {
  const SceneDesc s = world("Material \"interface\"\nShape \"sphere\"\n");
  EXPECT_TRUE(s.shapes.empty());
  EXPECT_TRUE(has_warning(s, "test.pbrt:2:1: material \"interface\" marks medium boundaries"));
}

TEST(PbrtTextures, ConstantAndCheckerboardFeedMaterials) {
  const SceneDesc s = world(
      "Texture \"c\" \"spectrum\" \"constant\" \"rgb value\" [0.3 0.2 0.1]\n"
      "Texture \"k\" \"spectrum\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 4\n"
      "  \"rgb tex1\" [1 1 1] \"rgb tex2\" [0 0 0]\n"
      "Texture \"img\" \"spectrum\" \"marble\" \"float scale\" 2\n"
      "Material \"diffuse\" \"texture reflectance\" \"c\"\nShape \"sphere\"\n"
      "Material \"diffuse\" \"texture reflectance\" \"k\"\nShape \"sphere\"\n");
  std::vector<const SceneParams*> m;
  for (const ShapeDesc& sh : s.shapes)
    for (const MaterialDesc& d : s.materials)
      if (d.name == sh.material) m.push_back(&d.params);
  EXPECT_EQ(m[0]->get_rgb("albedo", {}), Rgb(0.3f, 0.2f, 0.1f));
  const json* k = m[1]->get_json("albedo");
  ASSERT_TRUE(k && k->is_object());
  EXPECT_EQ((*k)["type"], "checkerboard");
  EXPECT_EQ((*k)["scale"], json::array({8.0, 4.0}));
  EXPECT_EQ((*k)["colors"][1], json::array({0.0, 0.0, 0.0}));
  EXPECT_TRUE(has_warning(s, "test.pbrt:5:1: Texture class \"marble\" is not supported"));
  // An imagemap's file must exist (its mapping is tested with a real file in test_render).
  EXPECT_EQ(pbrt_error("WorldBegin\nTexture \"i\" \"spectrum\" \"imagemap\" \"string filename\" "
                       "\"a.png\""),
            "test.pbrt:2:1: image not found: a.png");
  EXPECT_EQ(pbrt_error("WorldBegin\nMaterial \"diffuse\" \"texture reflectance\" \"nope\""),
            "test.pbrt:2:20: unknown texture \"nope\"");
}

TEST(PbrtLights, AreaLightsEmitFromTheShapesOfTheirBlock) {
  const SceneDesc s = world(
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4 3 2] \"float scale\" 2\n"
      "  \"bool twosided\" true\nShape \"sphere\"\nAttributeEnd\nShape \"sphere\"\n");
  ASSERT_EQ(s.shapes.size(), 2u);
  ASSERT_TRUE(s.shapes[0].emission.has_value());
  EXPECT_EQ(*s.shapes[0].emission, Rgb(8, 6, 4));
  EXPECT_TRUE(s.shapes[0].two_sided_emission);
  EXPECT_FALSE(s.shapes[1].emission.has_value());
}

TEST(PbrtLights, PointDistantInfiniteAndSkippedOnes) {
  const SceneDesc s = pbrt_scene(
      "Scale -1 1 1\nCamera \"perspective\"\nWorldBegin\n"
      "AttributeBegin\nTranslate 0 1 0\n"
      "LightSource \"point\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [1 0 0]\n"
      "AttributeEnd\n"
      "LightSource \"distant\" \"point3 from\" [0 10 0] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n"
      "LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n"
      "LightSource \"goniometric\" \"string filename\" \"g.exr\"\n");
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type(), "point");
  EXPECT_EQ(s.lights[0].get_vec3("position", {}), Vec3(1, 1, 0));
  EXPECT_EQ(s.lights[0].get_rgb("intensity", {}), Rgb(2, 4, 6));
  EXPECT_EQ(s.lights[1].type(), "directional");
  EXPECT_EQ(s.lights[1].get_vec3("direction", {}), Vec3(0, -10, 0));  // travels from -> to
  EXPECT_EQ(s.lights[1].get_rgb("irradiance", {}), Rgb(3));
  EXPECT_EQ(s.lights[2].type(), "environment");
  EXPECT_EQ(s.lights[2].get_rgb("radiance", {}), Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_TRUE(has_warning(s, "test.pbrt:10:1: LightSource \"goniometric\" is not supported"));
  // A map must exist (its mapping is tested with a real file in test_render).
  EXPECT_EQ(pbrt_error("WorldBegin\nLightSource \"infinite\" \"string filename\" \"sky.exr\""),
            "test.pbrt:2:1: infinite light map not found: sky.exr");
}

TEST(PbrtLights, SpotMapsPositionAxisAnglesThroughTheWorldMirror) {
  // A plain camera: the importer mirrors the world (x negated, docs/pbrt-import.md).
  const SceneDesc s = pbrt_scene(
      "Camera \"perspective\"\nWorldBegin\nAttributeBegin\nTranslate 0 1 0\n"
      "LightSource \"spot\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [1 0 0]\n"
      "  \"point3 to\" [2 0 1] \"float coneangle\" 40 \"float conedeltaangle\" 10\n"
      "AttributeEnd\nLightSource \"spot\"\n");
  ASSERT_EQ(s.lights.size(), 2u);
  const SceneParams& a = s.lights[0];
  EXPECT_EQ(a.type(), "spot");
  EXPECT_EQ(a.get_vec3("position", {}), Vec3(-1, 1, 0));
  EXPECT_EQ(a.get_vec3("direction", {}), Vec3(-1, 0, 1));  // to - from, mirrored
  EXPECT_EQ(a.get_rgb("intensity", {}), Rgb(2, 4, 6));
  EXPECT_EQ(a.get_float("cone_angle", 0), 40.0f);
  EXPECT_EQ(a.get_float("cone_delta", 0), 10.0f);
  // pbrt-v4's defaults: at the origin aimed along +z, 30 and 5 degrees, white.
  const SceneParams& b = s.lights[1];
  EXPECT_EQ(b.get_vec3("position", {1, 1, 1}), Vec3(0, 0, 0));
  EXPECT_EQ(b.get_vec3("direction", {}), Vec3(0, 0, 1));
  EXPECT_EQ(b.get_float("cone_angle", 0), 30.0f);
  EXPECT_EQ(b.get_float("cone_delta", 0), 5.0f);
  EXPECT_EQ(b.get_rgb("intensity", {}), Rgb(1));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

TEST(PbrtLights, SpotPowerNormalisesOverTheConeAndBadAnglesAreErrors) {
  const SceneDesc s = world(
      "LightSource \"spot\" \"rgb I\" [1 2 3] \"float power\" 100 \"float coneangle\" 50\n"
      "  \"float conedeltaangle\" 20\n");
  // pbrt-v4: luminance(I) = power / k_e, k_e = 2 pi ((1 - cos_start) + (cos_start - cos_end) / 2).
  const double cs = std::cos(30 * std::numbers::pi / 180),
               ce = std::cos(50 * std::numbers::pi / 180);
  const double k_e = 2 * std::numbers::pi * ((1 - cs) + (cs - ce) / 2);
  const Rgb i = s.lights[0].get_rgb("intensity", {});
  EXPECT_NEAR(0.2126 * i.r + 0.7152 * i.g + 0.0722 * i.b, 100 / k_e, 1e-3);
  EXPECT_NEAR(i.g / i.r, 2.0, 1e-5);  // the colour is kept
  EXPECT_EQ(pbrt_error("WorldBegin\nLightSource \"spot\" \"float coneangle\" 0"),
            "test.pbrt:2:1: spot light: \"coneangle\" must be in (0, 180] degrees");
  EXPECT_EQ(pbrt_error("WorldBegin\nLightSource \"spot\" \"float conedeltaangle\" 40"),
            "test.pbrt:2:1: spot light: \"conedeltaangle\" must be in [0, coneangle] degrees");
  EXPECT_EQ(pbrt_error("WorldBegin\nLightSource \"spot\" \"point3 to\" [0 0 0]"),
            "test.pbrt:2:1: spot light: \"from\" and \"to\" coincide");
}

TEST(PbrtLights, PowerAndBlackbody) {
  const SceneDesc s = world("LightSource \"point\" \"blackbody I\" 6500 \"float power\" 100\n");
  // pbrt normalises the spectrum to luminance 1 and sets power / (4 pi).
  const Rgb i = s.lights[0].get_rgb("intensity", {});
  EXPECT_NEAR(0.2126 * i.r + 0.7152 * i.g + 0.0722 * i.b, 100 / (4 * std::numbers::pi), 1e-4);
  // A 6500 K blackbody is nearly white in sRGB (D65 is 6504 K with a different spectrum);
  // 2700 K is orange.
  const Rgb d65ish = blackbody_rgb(6500);
  EXPECT_NEAR(0.2126 * d65ish.r + 0.7152 * d65ish.g + 0.0722 * d65ish.b, 1.0, 0.02);
  EXPECT_NEAR(d65ish.r, 1.0, 0.1);
  EXPECT_NEAR(d65ish.b, 1.0, 0.1);
  const Rgb warm = blackbody_rgb(2700);
  EXPECT_GT(warm.r, warm.g);
  EXPECT_GT(warm.g, warm.b);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

TEST(PbrtMaterials, MixAndCoatedConductorTakeTheNearest) {
  const SceneDesc s = test::pbrt_scene(
      "WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.1 "
      "0.2 "
      "0.3]\nMakeNamedMaterial \"b\" \"string type\" \"conductor\"\n"
      "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"a\" \"b\"] "
      "\"float amount\" 0.3\nNamedMaterial \"m\"\nShape \"sphere\"\n"
      "Material \"coatedconductor\" \"spectrum conductor.eta\" \"metal-Ag-eta\" "
      "\"spectrum conductor.k\" \"metal-Ag-k\" \"float interface.roughness\" 0.1\n"
      "Shape \"sphere\"\n");
  std::vector<const SceneParams*> m;
  for (const ShapeDesc& sh : s.shapes)
    for (const MaterialDesc& d : s.materials)
      if (d.name == sh.material) m.push_back(&d.params);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0]->type(), "diffuse");
  EXPECT_EQ(m[0]->get_rgb("albedo", {}), Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_TRUE(test::has_warning(s, "test.pbrt:4:1: material \"mix\" rendered as its first"));
  EXPECT_EQ(m[1]->type(), "conductor");
  EXPECT_NEAR(m[1]->get_rgb("k", {}).r, 4.8283433f, 1e-6);  // silver
  EXPECT_EQ(m[1]->get_float("roughness", 1), 0.0f);         // the coating's roughness is dropped
  EXPECT_TRUE(test::has_warning(s, "test.pbrt:7:1: material \"coatedconductor\" rendered as"));
  EXPECT_FALSE(test::has_warning(s, "unused"));
}

TEST(PbrtLights, IlluminanceAndBlackbodyAreaLights) {
  const SceneDesc s = test::pbrt_scene(
      "WorldBegin\nLightSource \"distant\" \"rgb L\" [1 1 1] \"float illuminance\" 5\n"
      "LightSource \"infinite\" \"rgb L\" [2 2 2] \"float illuminance\" 3.14159265\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 2700 \"float scale\" 3\n"
      "Shape \"sphere\"\nAttributeEnd\n");
  EXPECT_EQ(s.lights[0].get_rgb("irradiance", {}), Rgb(5.0f));
  const Rgb env = s.lights[1].get_rgb("radiance", {});
  EXPECT_NEAR(env.g, 1.0f, 1e-6);  // E = pi L, normalised to luminance
  const Rgb e = *s.shapes[0].emission;
  EXPECT_NEAR(0.2126 * e.r + 0.7152 * e.g + 0.0722 * e.b, 3.0, 0.06);
  EXPECT_GT(e.r, e.b);
}

}  // namespace
}  // namespace penumbra
