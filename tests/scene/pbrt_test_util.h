#pragma once
// Shared helpers of the pbrt reader tests: parsing text, catching the error message.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"
#include "penumbra/scene/pbrt_parser.h"

namespace penumbra::test {

/// Parses pbrt text as "test.pbrt" in `dir`.
inline SceneDesc pbrt_scene(const std::string& text, const std::string& dir = "") {
  return parse_pbrt_scene(text, "test.pbrt", dir);
}

/// The message of the InputError that parsing `text` throws ("" and a failure when none).
inline std::string pbrt_error(const std::string& text, const std::string& dir = "") {
  try {
    pbrt_scene(text, dir);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for: " << text;
  return "";
}

/// True when some warning contains `part`.
inline bool has_warning(const SceneDesc& s, const std::string& part) {
  for (const std::string& w : s.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace penumbra::test
