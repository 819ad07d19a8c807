#pragma once
/// The parameters of one scene object (a material, light, camera...), read by the class that the
/// object's type names. Every getter marks its key as used; `check_all_used` reports the rest, so a
/// misspelt key is an error, never silently ignored.
#include <cstdint>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// A JSON object of parameters with the file and JSON path it came from (for error messages).
class SceneParams {
 public:
  SceneParams() = default;
  /// Wraps `object` (must be a JSON object) found at `json_path` (e.g. "/materials/glass") of
  /// `file`.
  SceneParams(nlohmann::json object, std::string file, std::string json_path);

  /// The object's "type" string (always required, marked used).
  const std::string& type() const { return type_; }
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  /// The whole object, "type" included (for writing a scene back out).
  const nlohmann::json& json() const { return object_; }
  bool has(const std::string& key) const;

  float get_float(const std::string& key, float fallback) const;
  /// Float that must be present.
  float require_float(const std::string& key) const;
  int64_t get_int(const std::string& key, int64_t fallback) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  Vec3 get_vec3(const std::string& key, Vec3 fallback) const;
  Vec3 require_vec3(const std::string& key) const;
  /// Pair of numbers `[a, b]`.
  Vec2 get_vec2(const std::string& key, Vec2 fallback) const;
  /// RGB triple; a single number s is accepted as (s, s, s).
  Rgb get_rgb(const std::string& key, Rgb fallback) const;
  /// The raw JSON value of `key` (marked used), or nullptr when absent: for values a class parses
  /// itself, such as a colour that may be a texture object.
  const nlohmann::json* get_json(const std::string& key) const { return lookup(key); }

  /// Throws InputError for a value out of range: "FILE:/path/key: MESSAGE".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  /// Throws InputError naming the first key that no getter asked for.
  void check_all_used() const;

 private:
  const nlohmann::json* lookup(const std::string& key) const;

  nlohmann::json object_;
  std::string file_, path_, type_;
  mutable std::set<std::string> used_;
};

}  // namespace penumbra
