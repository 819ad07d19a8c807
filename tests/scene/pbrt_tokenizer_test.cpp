/// Tests of the pbrt tokenizer and parameter lists: comments anywhere, strings with spaces and
/// escapes, multi-line and bare values, and every syntax error at its FILE:LINE:COLUMN.
#include "penumbra/scene/pbrt_tokenizer.h"

#include <gtest/gtest.h>

#include "pbrt_test_util.h"
#include "penumbra/core/error.h"
#include "penumbra/scene/pbrt_params.h"

namespace penumbra {
namespace {

using Kind = PbrtToken::Kind;
using test::pbrt_error;
using test::pbrt_scene;

TEST(PbrtTokenizer, WordsStringsBracketsAndPlaces) {
  PbrtTokenizer t("Shape \"sphere\"  [ 1 -2.5e1 ]\n  # comment \"not a string\"\n\tWorldBegin",
                  "f.pbrt");
  PbrtToken a = t.next();
  EXPECT_EQ(a.kind, Kind::kWord);
  EXPECT_EQ(a.text, "Shape");
  EXPECT_EQ(a.loc.str(), "f.pbrt:1:1");
  PbrtToken b = t.next();
  EXPECT_EQ(b.kind, Kind::kString);
  EXPECT_EQ(b.text, "sphere");
  EXPECT_EQ(b.loc.column, 7);
  EXPECT_EQ(t.next().kind, Kind::kOpen);
  EXPECT_EQ(t.next().text, "1");
  EXPECT_EQ(t.next().text, "-2.5e1");
  EXPECT_EQ(t.next().kind, Kind::kClose);
  EXPECT_EQ(t.peek().text, "WorldBegin");
  PbrtToken w = t.next();
  EXPECT_EQ(w.loc.line, 3);
  EXPECT_EQ(w.loc.column, 2);
  EXPECT_EQ(t.next().kind, Kind::kEnd);
  EXPECT_EQ(t.next().kind, Kind::kEnd);
}

TEST(PbrtTokenizer, CommentEndsAWordAndBracketsNeedNoSpaces) {
  PbrtTokenizer t("[1 2]#x\n3#y", "f");
  EXPECT_EQ(t.next().kind, Kind::kOpen);
  EXPECT_EQ(t.next().text, "1");
  EXPECT_EQ(t.next().text, "2");
  EXPECT_EQ(t.next().kind, Kind::kClose);
  EXPECT_EQ(t.next().text, "3");
  EXPECT_EQ(t.next().kind, Kind::kEnd);
}

TEST(PbrtTokenizer, StringsKeepSpacesAndResolveEscapes) {
  PbrtTokenizer t(R"("a b  c" "q\"x\\y\tz" "# not a comment")", "f");
  EXPECT_EQ(t.next().text, "a b  c");
  EXPECT_EQ(t.next().text, "q\"x\\y\tz");
  EXPECT_EQ(t.next().text, "# not a comment");
}

TEST(PbrtTokenizer, UnterminatedStringIsAnErrorAtItsQuote) {
  PbrtTokenizer t("Shape\n  \"sphere\n\"", "f.pbrt");
  t.next();
  try {
    t.next();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "f.pbrt:2:3: unterminated string (a string must close on the line it opens)");
  }
}

TEST(PbrtTokenizer, UnknownEscapeIsAnError) {
  PbrtTokenizer t("\"a\\qb\"", "f.pbrt");
  EXPECT_THROW(t.next(), InputError);
}

// Parameters of one directive, as PbrtParams reads them from `text`.
PbrtParams params(const std::string& text) {
  PbrtTokenizer t(text, "p.pbrt");
  return PbrtParams::parse(t);
}

std::string params_error(const std::string& text) {
  try {
    params(text);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << text;
  return "";
}

TEST(PbrtParams, BareValuesBracketsMultiLineAndComments) {
  const PbrtParams p = params(
      "\"float fov\" 45 \"integer n\" [ 3 ]\n"
      "\"point3 P\" [ 0 0 0   # first\n 1 0 0\n # between\n 0 1 0 ]\n"
      "\"string name\" \"with spaces\" \"bool a\" true \"bool b\" \"false\" \"bool c\" [ true ]\n"
      "\"rgb col\" [.5 .25 1] \"spectrum s\" \"metal-Cu-eta\" \"texture t\" \"checks\"\n"
      "Shape");
  EXPECT_EQ(p.get_float("fov", 0), 45);
  EXPECT_EQ(p.get_int("n", 0), 3);
  const std::vector<Vec3> P = p.get_vec3s("P", "point3");
  ASSERT_EQ(P.size(), 3u);
  EXPECT_EQ(P[2], Vec3(0, 1, 0));
  EXPECT_EQ(p.get_string("name", ""), "with spaces");
  EXPECT_TRUE(p.get_bool("a", false));
  EXPECT_FALSE(p.get_bool("b", true));
  EXPECT_TRUE(p.get_bool("c", false));
  EXPECT_EQ(p.get_numbers("col", "rgb"), (std::vector<double>{0.5, 0.25, 1}));
  EXPECT_EQ(p.find("s", "spectrum")->strings[0], "metal-Cu-eta");
  EXPECT_EQ(p.find("t", "texture")->strings[0], "checks");
  EXPECT_EQ(p.get_float("absent", 7), 7);
}

TEST(PbrtParams, OldSpellingsOfTypesAreNormalised) {
  const PbrtParams p = params("\"point from\" [1 2 3] \"normal N\" [0 0 1] \"color L\" [1 1 1]");
  EXPECT_EQ(p.get_vec3("from"), Vec3(1, 2, 3));
  EXPECT_EQ(p.find("N", "normal3")->type, "normal3");
  EXPECT_EQ(p.find("L", "rgb")->type, "rgb");
}

TEST(PbrtParams, UnusedParametersAreReportedWithTheirPlace) {
  const PbrtParams p = params("\"float fov\" 45\n  \"float radius\" 2");
  p.get_float("fov", 0);
  std::vector<std::string> w;
  p.report_unused(w, "Camera \"perspective\"");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0], "p.pbrt:2:3: unused parameter \"float radius\" (Camera \"perspective\")");
}

TEST(PbrtParams, ErrorsNameFileLineColumnAndProblem) {
  EXPECT_EQ(params_error("\"flot fov\" 45"),
            "p.pbrt:1:1: unknown parameter type \"flot\" in \"flot fov\" (valid: blackbody, bool, "
            "float, integer, normal3, point2, point3, rgb, spectrum, string, texture, vector2, "
            "vector3 (and point, vector, normal, color))");
  EXPECT_EQ(params_error("\n  \"point3 P\" [0 0 0 1]"),
            "p.pbrt:2:3: parameter \"point3 P\" needs a multiple of 3 values, got 4");
  EXPECT_EQ(params_error("\"rgb L\" [1 1"),
            "p.pbrt:1:9: unbalanced '[': no matching ']' before the end of the file");
  EXPECT_EQ(params_error("\"rgb L\" [1 [1 1]"), "p.pbrt:1:12: unbalanced '[': lists do not nest");
  EXPECT_EQ(params_error("\"integer n\" 2.5"),
            "p.pbrt:1:13: parameter \"integer n\": expected an integer, got 2.5");
  EXPECT_EQ(params_error("\"float x\" \"a\""),
            "p.pbrt:1:11: parameter \"float x\": expected a number, got \"a\"");
  EXPECT_EQ(params_error("\"float x\" [1 abc]"), "p.pbrt:1:14: expected a number, got abc");
  EXPECT_EQ(params_error("\"float\" 1"),
            "p.pbrt:1:1: expected a parameter declaration \"type name\", got \"float\"");
  EXPECT_EQ(params_error("\"float x\" 1 \"float x\" 2"),
            "p.pbrt:1:13: parameter \"x\" given twice (first at p.pbrt:1:1)");
  EXPECT_EQ(params_error("\"float x\" []"), "p.pbrt:1:1: parameter \"float x\" has no values");
  EXPECT_EQ(params_error("\"bool b\" yes"),
            "p.pbrt:1:10: parameter \"bool b\": expected true or false, got yes");
  EXPECT_EQ(params_error("\"blackbody L\" [6500 1]"),
            "p.pbrt:1:1: parameter \"blackbody L\" takes one temperature in kelvin, got 2 values");
}

TEST(PbrtParams, LookupOfTheWrongTypeOrCountIsAnError) {
  const PbrtParams p = params("\"integer fov\" 45 \"float r\" [1 2]");
  try {
    p.get_float("fov", 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "p.pbrt:1:1: parameter \"fov\" has type integer, expected float");
  }
  EXPECT_THROW(p.get_float("r", 0), InputError);
}

// Directive-level errors through the whole parser.
TEST(PbrtSyntax, DirectiveErrorsNameTheirPlace) {
  EXPECT_EQ(pbrt_error("WorldBegin\nAttributeEnd"),
            "test.pbrt:2:1: AttributeEnd without a matching AttributeBegin");
  EXPECT_EQ(pbrt_error("WorldBegin\n  Sphere"), "test.pbrt:2:3: unknown directive Sphere");
  EXPECT_EQ(pbrt_error("Translate 1 2 Shape"),
            "test.pbrt:1:15: Translate takes 3 numbers, got Shape");
  EXPECT_EQ(pbrt_error("Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"),
            "test.pbrt:1:11: unbalanced '[': no matching ']' before the end of the file");
  EXPECT_EQ(pbrt_error("WorldBegin ]"), "test.pbrt:1:12: unbalanced ']' outside a parameter list");
  EXPECT_EQ(pbrt_error("\"float fov\" 45"),
            "test.pbrt:1:1: expected a directive, got \"float fov\"");
  EXPECT_EQ(pbrt_error("Shape \"sphere\""),
            "test.pbrt:1:1: Shape is only allowed after WorldBegin");
  EXPECT_EQ(pbrt_error("WorldBegin\nCamera \"perspective\""),
            "test.pbrt:2:1: Camera is not allowed after WorldBegin");
  EXPECT_EQ(pbrt_error("WorldBegin\nTransformBegin\nAttributeEnd"),
            "test.pbrt:3:1: AttributeEnd closes the TransformBegin at test.pbrt:2:1");
  EXPECT_EQ(pbrt_error("WorldBegin\nShape \"sphere\" \"float radius\" [1 2]"),
            "test.pbrt:2:16: parameter \"float radius\" takes one value, got 2");
  EXPECT_EQ(pbrt_error("WorldBegin\nShape \"cube\""),
            "test.pbrt:2:1: unknown Shape \"cube\" (pbrt-v4 has: bilinearmesh, curve, cylinder, "
            "disk, loopsubdiv, plymesh, sphere, trianglemesh)");
  EXPECT_EQ(pbrt_error("WorldBegin\nNamedMaterial \"nope\"\nShape \"sphere\""),
            "test.pbrt:2:1: NamedMaterial: unknown material \"nope\"");
}

TEST(PbrtSyntax, CommentsBetweenDirectiveAndParameters) {
  const SceneDesc s = pbrt_scene(
      "Camera # the camera\n \"perspective\" # its type\n \"float fov\" # the field\n [ 30 ]\n"
      "Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 20\n"
      "WorldBegin\nShape \"sphere\" # no parameters follow\n");
  EXPECT_FLOAT_EQ(s.camera.get_float("vfov", 0), 30.0f);
  EXPECT_EQ(s.render.width, 40);
  EXPECT_EQ(s.shapes.size(), 1u);
}

}  // namespace
}  // namespace penumbra
