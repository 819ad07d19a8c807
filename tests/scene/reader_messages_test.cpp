// The readers' messages for inputs that are not what they claim (issue #18, "clear messages"):
// binary and UTF-16 files, huge tokens, PLY faces of fewer than three vertices, trailing data,
// empty files, special files.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/obj_reader.h"
#include "penumbra/scene/ply_reader.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

/// The message of the InputError that `read` throws ("(no error)" if none).
template <class Read>
std::string message_of(Read&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

#define EXPECT_CONTAINS(text, part)                          \
  EXPECT_NE(std::string(text).find(part), std::string::npos) \
      << "'" << (text) << "' lacks '" << (part) << "'"

/// Whether `s` has a byte below 0x20 or 0x7f.
bool has_control_byte(const std::string& s) {
  for (const char c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return true;
  }
  return false;
}

TEST(ObjMessages, Utf16FileIsNamedAsSuch) {
  std::string utf16 = "\xff\xfe";
  for (const char c : std::string("v 0 0 0\n")) utf16 += std::string{c, '\0'};
  const std::string m = message_of([&] { parse_obj(utf16, "u.obj"); });
  EXPECT_EQ(m, "u.obj: UTF-16 text: convert to UTF-8");
  std::string no_bom;
  for (const char c : std::string("v 0 0 0\n")) no_bom += std::string{c, '\0'};
  EXPECT_EQ(message_of([&] { parse_obj(no_bom, "u.obj"); }),
            "u.obj: UTF-16 text: convert to UTF-8");
}

TEST(ObjMessages, BinaryDataIsNamedByItsOffsetWithoutRawBytes) {
  const std::string binary = std::string("v 0 0 0\n\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 24);
  const std::string m = message_of([&] { parse_obj(binary, "b.obj"); });
  EXPECT_EQ(m, "b.obj: binary data at byte 14 (0x1a): expected text");
  EXPECT_FALSE(has_control_byte(m));
}

TEST(ObjMessages, HugeTokenIsQuotedAtMost40Bytes) {
  const std::string token(10'000'000, 'q');
  const std::string m = message_of([&] { parse_obj("v 0 0 " + token + "\n", "h.obj"); });
  EXPECT_CONTAINS(m, "h.obj:line 1: bad number '" + std::string(40, 'q') + "... (10000000 bytes)'");
  EXPECT_LT(m.size(), 120u);
  const std::string statement =
      message_of([&] { parse_obj(std::string(1000, 'k') + " 1\n", "h.obj"); });
  EXPECT_CONTAINS(statement, "unknown statement '" + std::string(40, 'k') + "... (1000 bytes)'");
}

TEST(ObjMessages, Utf8ByteOrderMarkIsSkipped) {
  EXPECT_EQ(
      parse_obj("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bom.obj").triangle_count(),
      1u);
}

TEST(ObjMessages, InvalidUtf8InATokenIsEscaped) {
  const std::string m = message_of([&] {
    parse_obj(
        "v 0 0 \xff\xfe"
        "1\n",
        "x.obj");
  });
  EXPECT_CONTAINS(m, "bad number '\\xff\\xfe1'");
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n";

TEST(PlyMessages, EmptyFileIsReportedAsEmpty) {
  EXPECT_EQ(message_of([] { parse_ply("", "e.ply"); }), "e.ply: empty file (0 bytes)");
}

TEST(PlyMessages, FaceOfTwoVerticesIsReportedAsSuchEvenAtTheEndOfTheFile) {
  // Before: "element 'face' declares 1 items of at least 8 bytes, but only ... follow".
  EXPECT_CONTAINS(message_of([&] { parse_ply(kPlyHead + "2 0 1\n", "f.ply"); }),
                  "f.ply:line 13: face with 2 vertices (needs at least 3)");
  EXPECT_CONTAINS(message_of([&] { parse_ply(kPlyHead + "0\n", "f.ply"); }),
                  "face with 0 vertices");
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty uchar x\n"
      "property uchar y\nproperty uchar z\nelement face 1\nproperty list uchar uchar "
      "vertex_indices\nend_header\n";
  const size_t face_at = binary.size() + 9;
  binary += std::string("\0\0\0\1\0\0\0\1\0\2\0\1", 12);
  EXPECT_CONTAINS(message_of([&] { parse_ply(binary, "f.ply"); }),
                  "f.ply:byte " + std::to_string(face_at) + ": face with 2 vertices");
}

TEST(PlyMessages, TrailingDataAfterTheLastElementIsAnError) {
  EXPECT_EQ(parse_ply(kPlyHead + "3 0 1 2\n \r\n\t", "t.ply").triangle_count(), 1u);  // spaces
  EXPECT_CONTAINS(message_of([&] { parse_ply(kPlyHead + "3 0 1 2\n3 0 1 2\n", "t.ply"); }),
                  "t.ply:line 14: trailing data after the last element: '3'");
  std::string binary =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty uchar x\n"
      "property uchar y\nproperty uchar z\nelement face 1\nproperty list uchar uchar "
      "vertex_indices\nend_header\n";
  binary += std::string("\0\0\0\1\0\0\0\1\0\3\0\1\2", 13);
  const size_t end = binary.size();
  EXPECT_CONTAINS(
      message_of([&] { parse_ply(binary + "junk", "t.ply"); }),
      "t.ply:byte " + std::to_string(end) + ": 4 bytes of trailing data after the last element");
}

TEST(PlyMessages, Utf16HeaderIsNamedAsSuch) {
  std::string utf16;
  for (const char c : std::string("ply\n")) utf16 += std::string{c, '\0'};
  EXPECT_EQ(message_of([&] { parse_ply(utf16, "u.ply"); }),
            "u.ply:line 1: UTF-16 text: convert to UTF-8");
}

TEST(PlyMessages, ControlBytesInHeaderWordsAreEscaped) {
  const std::string m =
      message_of([] { parse_ply("ply\nformat \x1b[2J 1.0\nend_header\n", "c.ply"); });
  EXPECT_FALSE(has_control_byte(m)) << m;
  EXPECT_CONTAINS(m, "c.ply:line 2: unknown format '\\x1b[2J'");
}

TEST(SpecialFiles, MeshAndSceneReadersRefuseDevZero) {
  EXPECT_CONTAINS(message_of([] { read_obj("/dev/zero"); }), "not a regular file");
  EXPECT_CONTAINS(message_of([] { read_ply("/dev/zero"); }), "not a regular file");
  EXPECT_CONTAINS(message_of([] { load_scene("/dev/zero"); }), "not a regular file");
  EXPECT_CONTAINS(message_of([] { load_scene("/"); }), "is a directory");
}

TEST(SceneMessages, Utf16SceneIsNamedAsSuch) {
  std::string utf16 = "\xfe\xff";
  for (const char c : std::string("{}")) utf16 += std::string{'\0', c};
  EXPECT_EQ(message_of([&] { parse_scene(utf16, "u.json", ""); }),
            "u.json: UTF-16 text: convert to UTF-8");
}

TEST(SceneMessages, ControlCharactersInKeysAreEscapedInThePath) {
  const std::string m = message_of([] {
    parse_scene(R"({"camera": {"type": "pinhole"}, "shapes": [], "\u001b[2J": 1})", "k.json", "");
  });
  EXPECT_CONTAINS(m, "k.json:/\\x1b[2J: unknown key");
  EXPECT_FALSE(has_control_byte(m));
}

}  // namespace
}  // namespace penumbra
