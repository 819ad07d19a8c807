#include "penumbra/scene/scene_params.h"

#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/scene/json_value.h"

namespace penumbra {

namespace {

// The place of parameter `key` of `params`.
JsonPlace place_of(const SceneParams& params, const std::string& key) {
  return JsonPlace{params.file(), params.path()}.key(key);
}

}  // namespace

SceneParams::SceneParams(nlohmann::json object, std::string file, std::string json_path)
    : object_(std::move(object)), file_(std::move(file)), path_(std::move(json_path)) {
  const JsonPlace place{file_, path_};
  if (!object_.is_object()) place.fail("expected an object with a \"type\"");
  type_ = json_string(json_require(object_, place, "type"), place.key("type"));
  if (type_.empty()) place.key("type").fail("must not be empty");
}

bool SceneParams::has(const std::string& key) const {
  return json_find(object_, key) != nullptr;
}

const nlohmann::json* SceneParams::lookup(const std::string& key) const {
  used_.insert(key);  // asked for: a known key, whether present or not
  return json_find(object_, key);
}

float SceneParams::get_float(const std::string& key, float fallback) const {
  const nlohmann::json* v = lookup(key);
  return v ? json_float(*v, place_of(*this, key)) : fallback;
}

float SceneParams::require_float(const std::string& key) const {
  const nlohmann::json* v = lookup(key);
  if (!v) JsonPlace{file_, path_}.fail("missing required key \"" + key + "\"");
  return json_float(*v, place_of(*this, key));
}

int64_t SceneParams::get_int(const std::string& key, int64_t fallback) const {
  const nlohmann::json* v = lookup(key);
  return v ? json_int(*v, place_of(*this, key), INT64_MIN, INT64_MAX) : fallback;
}

bool SceneParams::get_bool(const std::string& key, bool fallback) const {
  const nlohmann::json* v = lookup(key);
  return v ? json_bool(*v, place_of(*this, key)) : fallback;
}

std::string SceneParams::get_string(const std::string& key, const std::string& fallback) const {
  const nlohmann::json* v = lookup(key);
  return v ? json_string(*v, place_of(*this, key)) : fallback;
}

Vec3 SceneParams::get_vec3(const std::string& key, Vec3 fallback) const {
  const nlohmann::json* v = lookup(key);
  return v ? json_vec3(*v, place_of(*this, key)) : fallback;
}

Vec3 SceneParams::require_vec3(const std::string& key) const {
  const nlohmann::json* v = lookup(key);
  if (!v) JsonPlace{file_, path_}.fail("missing required key \"" + key + "\"");
  return json_vec3(*v, place_of(*this, key));
}

Vec2 SceneParams::get_vec2(const std::string& key, Vec2 fallback) const {
  const nlohmann::json* v = lookup(key);
  return v ? json_vec2(*v, place_of(*this, key)) : fallback;
}

Rgb SceneParams::get_rgb(const std::string& key, Rgb fallback) const {
  const nlohmann::json* v = lookup(key);
  return v ? json_rgb(*v, place_of(*this, key)) : fallback;
}

void SceneParams::fail(const std::string& key, const std::string& message) const {
  place_of(*this, key).fail(message);
}

void SceneParams::check_all_used() const {
  std::vector<std::string> known(used_.begin(), used_.end());
  known.push_back("type");
  json_check_keys(object_, JsonPlace{file_, path_}, known, "type \"" + type_ + "\"");
}

}  // namespace penumbra
