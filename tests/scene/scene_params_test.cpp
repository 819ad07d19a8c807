/// Tests of SceneParams: getters with fallbacks, type and length errors naming the JSON path,
/// required keys, and check_all_used.
#include "penumbra/scene/scene_params.h"

#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"

namespace penumbra {
namespace {

SceneParams params(const std::string& json_text) {
  return SceneParams(nlohmann::json::parse(json_text), "cornell.json", "/materials/white");
}

// The message of the InputError that `f` throws ("" and a failure when none).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(SceneParams, GettersReturnValuesOrFallbacks) {
  const SceneParams p = params(R"({"type": "diffuse", "albedo": [0.1, 0.2, 0.3], "grey": 0.5,
      "f": 2.5, "i": -7, "b": true, "s": "text", "v": [1, 2, 3]})");
  EXPECT_EQ(p.type(), "diffuse");
  EXPECT_EQ(p.file(), "cornell.json");
  EXPECT_EQ(p.path(), "/materials/white");
  EXPECT_EQ(p.get_rgb("albedo", Rgb(0)), Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(p.get_rgb("grey", Rgb(0)), Rgb(0.5f));
  EXPECT_EQ(p.get_float("f", 0), 2.5f);
  EXPECT_EQ(p.require_float("f"), 2.5f);
  EXPECT_EQ(p.get_float("i", 0), -7.0f);
  EXPECT_EQ(p.get_int("i", 0), -7);
  EXPECT_TRUE(p.get_bool("b", false));
  EXPECT_EQ(p.get_string("s", ""), "text");
  EXPECT_EQ(p.get_vec3("v", Vec3(0)), Vec3(1, 2, 3));
  EXPECT_EQ(p.require_vec3("v"), Vec3(1, 2, 3));
  // Absent keys give the fallback.
  EXPECT_EQ(p.get_float("missing", 4.5f), 4.5f);
  EXPECT_EQ(p.get_int("missing", 9), 9);
  EXPECT_FALSE(p.get_bool("missing", false));
  EXPECT_EQ(p.get_string("missing", "x"), "x");
  EXPECT_EQ(p.get_vec3("missing", Vec3(7)), Vec3(7));
  EXPECT_EQ(p.get_rgb("missing", Rgb(3)), Rgb(3));
  EXPECT_TRUE(p.has("albedo"));
  EXPECT_FALSE(p.has("missing"));
}

TEST(SceneParams, WrongTypesNameTheJsonPath) {
  const SceneParams p = params(
      R"({"type": "diffuse", "albedo": [1, 2], "s": 3, "b": "yes", "i": 2.5, "f": "1",
          "v": [1, "2", 3], "big": 1e39})");
  EXPECT_EQ(error_of([&] { p.get_rgb("albedo", Rgb(0)); }),
            "cornell.json:/materials/white/albedo: expected a number or an array of 3 numbers");
  EXPECT_EQ(error_of([&] { p.get_vec3("albedo", Vec3(0)); }),
            "cornell.json:/materials/white/albedo: expected an array of 3 numbers");
  EXPECT_EQ(error_of([&] { p.get_vec3("v", Vec3(0)); }),
            "cornell.json:/materials/white/v/1: expected a number");
  EXPECT_EQ(error_of([&] { p.get_string("s", ""); }),
            "cornell.json:/materials/white/s: expected a string");
  EXPECT_EQ(error_of([&] { p.get_bool("b", false); }),
            "cornell.json:/materials/white/b: expected true or false");
  EXPECT_NE(error_of([&] { p.get_int("i", 0); }).find("/materials/white/i: expected an integer"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { p.get_float("f", 0); }),
            "cornell.json:/materials/white/f: expected a number");
  EXPECT_EQ(error_of([&] { p.get_float("big", 0); }),
            "cornell.json:/materials/white/big: number out of single-precision range");
}

TEST(SceneParams, RequiredKeysAndFail) {
  const SceneParams p = params(R"({"type": "dielectric"})");
  EXPECT_EQ(error_of([&] { p.require_float("ior"); }),
            "cornell.json:/materials/white: missing required key \"ior\"");
  EXPECT_EQ(error_of([&] { p.require_vec3("axis"); }),
            "cornell.json:/materials/white: missing required key \"axis\"");
  EXPECT_EQ(error_of([&] { p.fail("ior", "must be at least 1"); }),
            "cornell.json:/materials/white/ior: must be at least 1");
}

TEST(SceneParams, CheckAllUsedReportsTheFirstUnreadKey) {
  const SceneParams p = params(R"({"type": "diffuse", "albedo": 0.5, "albedoo": 0.5})");
  p.get_rgb("albedo", Rgb(0));
  EXPECT_TRUE(p.has("albedoo"));  // has() does not count as a use
  const std::string what = error_of([&] { p.check_all_used(); });
  EXPECT_EQ(what.rfind("cornell.json:/materials/white/albedoo: unknown key", 0), 0u) << what;
  EXPECT_NE(what.find("albedo, type"), std::string::npos) << what;  // the known keys
  p.get_float("albedoo", 0);
  EXPECT_NO_THROW(p.check_all_used());
  // "type" never needs reading; a key asked for but absent is fine.
  const SceneParams q = params(R"({"type": "mirror"})");
  q.get_rgb("reflectance", Rgb(1));
  EXPECT_NO_THROW(q.check_all_used());
  EXPECT_NO_THROW(SceneParams().check_all_used());
}

TEST(SceneParams, ConstructorNeedsAnObjectWithAType) {
  EXPECT_EQ(error_of([] { params("[1, 2]"); }),
            "cornell.json:/materials/white: expected an object with a \"type\"");
  EXPECT_EQ(error_of([] { params(R"({"albedo": 1})"); }),
            "cornell.json:/materials/white: missing required key \"type\"");
  EXPECT_EQ(error_of([] { params(R"({"type": ""})"); }),
            "cornell.json:/materials/white/type: must not be empty");
  EXPECT_EQ(error_of([] { params(R"({"type": ["diffuse"]})"); }),
            "cornell.json:/materials/white/type: expected a string");
}

}  // namespace
}  // namespace penumbra
