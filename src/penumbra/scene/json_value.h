#pragma once
/// Reading JSON values with errors that name the file and the JSON path (RFC 6901 pointer) of the
/// bad value: the conversions shared by SceneParams and the scene loader, and the JSON text parser
/// (syntax errors at line:column, duplicate keys rejected).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// A place in a JSON file: the file name and a JSON pointer ("" is the root, "/shapes/3/radius").
struct JsonPlace {
  std::string file;
  std::string path;

  /// The place of member `key` of the object here.
  JsonPlace key(std::string_view key) const;
  /// The place of element `index` of the array here.
  JsonPlace index(size_t index) const;
  /// Throws InputError "FILE:PATH: problem".
  [[noreturn]] void fail(const std::string& problem) const;
};

/// `key` escaped for a JSON pointer: '~' becomes "~0" and '/' becomes "~1".
std::string json_pointer_escape(std::string_view key);

/// Parses JSON text. Throws InputError "FILE:LINE:COLUMN: problem" for a syntax error (line and
/// column counted from 1, the column in bytes) and "FILE:/path/key: duplicate key" for an object
/// that repeats a key (the JSON standard leaves that undefined; we never pick one silently).
nlohmann::json parse_json(const std::string& text, const std::string& file);

/// Throws for the first member of `object` whose name is not in `known`:
/// "FILE:/path/member: unknown key (CONTEXT takes: a, b, c)".
void json_check_keys(const nlohmann::json& object, const JsonPlace& place,
                     const std::vector<std::string>& known, const std::string& context);
/// The member `key` of `object`, or nullptr when absent (or `object` is not an object).
const nlohmann::json* json_find(const nlohmann::json& object, const std::string& key);
/// The member `key` of `object`; throws "FILE:PATH: missing required key \"key\"" when absent.
const nlohmann::json& json_require(const nlohmann::json& object, const JsonPlace& place,
                                   const std::string& key);

/// A finite number.
double json_number(const nlohmann::json& v, const JsonPlace& place);
/// A finite number that fits in a float.
float json_float(const nlohmann::json& v, const JsonPlace& place);
/// An integer in [lo, hi] (a number with an integral value, such as 2.0, is accepted).
int64_t json_int(const nlohmann::json& v, const JsonPlace& place, int64_t lo, int64_t hi);
/// An integer in [0, 2^64 - 1].
uint64_t json_uint64(const nlohmann::json& v, const JsonPlace& place);
/// true or false.
bool json_bool(const nlohmann::json& v, const JsonPlace& place);
/// A string.
std::string json_string(const nlohmann::json& v, const JsonPlace& place);
/// An array of 2 finite floats.
Vec2 json_vec2(const nlohmann::json& v, const JsonPlace& place);
/// An array of 3 finite floats.
Vec3 json_vec3(const nlohmann::json& v, const JsonPlace& place);
/// An array of 3 finite floats, or one number s standing for (s, s, s).
Rgb json_rgb(const nlohmann::json& v, const JsonPlace& place);
/// An RGB triple as json_rgb, with no negative channel (radiance, background).
Rgb json_radiance(const nlohmann::json& v, const JsonPlace& place);
/// An array (of any length); throws "expected an array" otherwise.
const nlohmann::json& json_array(const nlohmann::json& v, const JsonPlace& place);

}  // namespace penumbra
