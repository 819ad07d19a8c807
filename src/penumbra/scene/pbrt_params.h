#pragma once
/// Parameter lists of the pbrt-v4 scene format: `"type name" value` or `"type name" [values]`,
/// as many as follow a directive. Parsing checks the type and the number of values; lookups check
/// the type a reader expects and mark the parameter used, so the unused ones can be reported
/// afterwards (pbrt's habit, kept here as warnings).
#include <optional>
#include <string>
#include <vector>

#include "penumbra/core/vec.h"
#include "penumbra/scene/pbrt_tokenizer.h"

namespace penumbra {

/// One parameter: its type (normalised: "point" is "point3", "vector" "vector3", "normal"
/// "normal3", "color" "rgb"), name and values (numbers, or strings, or booleans).
struct PbrtParam {
  std::string type, name;
  std::vector<double> numbers;
  std::vector<std::string> strings;
  std::vector<bool> bools;
  PbrtLoc loc;  ///< the place of the "type name" string
  mutable bool used = false;
  /// Number of values of any kind.
  size_t size() const { return numbers.size() + strings.size() + bools.size(); }
  /// `"type name"`, for messages.
  std::string declaration() const { return "\"" + type + " " + name + "\""; }
};

/// The parameter list of one directive.
class PbrtParams {
 public:
  /// Reads the parameters that follow in `tok` (while the next token is a string). Throws
  /// InputError at FILE:LINE:COLUMN for a malformed declaration, an unknown type, a value of the
  /// wrong kind or count, a repeated name, or unbalanced brackets.
  static PbrtParams parse(PbrtTokenizer& tok);

  /// The parameter called `name` (marked used) or nullptr. When present with a type not in
  /// `types` (a space-separated list), throws InputError naming both.
  const PbrtParam* find(const std::string& name, const std::string& types) const;
  /// True when a parameter of that name is present (not marked used).
  bool has(const std::string& name) const;

  /// Single values; an absent parameter gives `fallback`; more than one value is an error.
  double get_float(const std::string& name, double fallback) const;
  int get_int(const std::string& name, int fallback) const;
  bool get_bool(const std::string& name, bool fallback) const;
  std::string get_string(const std::string& name, const std::string& fallback) const;
  /// A point3/vector3/normal3 with exactly 3 values.
  std::optional<Vec3> get_vec3(const std::string& name) const;
  /// All values of an array of `types` (empty when absent).
  std::vector<double> get_numbers(const std::string& name, const std::string& types) const;
  /// Triples of a point3/vector3/normal3 array.
  std::vector<Vec3> get_vec3s(const std::string& name, const std::string& types) const;
  /// Pairs of a point2/vector2 array (or a float array of even length, as pbrt-v3 wrote uv).
  std::vector<Vec2> get_vec2s(const std::string& name) const;

  /// Appends "FILE:LINE:COLUMN: unused parameter "type name" (WHAT)" for each parameter no
  /// lookup asked for.
  void report_unused(std::vector<std::string>& warnings, const std::string& what) const;
  const std::vector<PbrtParam>& all() const { return params_; }
  /// Adds a parameter (for tests and for defaults filled in by the parser).
  void add(PbrtParam p) { params_.push_back(std::move(p)); }

 private:
  std::vector<PbrtParam> params_;
};

/// One directive's object: its type string ("sphere", "diffuse", ...), parameters and place.
struct PbrtEntity {
  std::string type;
  PbrtParams params;
  PbrtLoc loc;
  /// `Directive "type"`, for messages.
  std::string what(const std::string& directive) const { return directive + " \"" + type + "\""; }
};

/// Appends "LOC: message" to `warnings`.
void pbrt_warn(std::vector<std::string>& warnings, const PbrtLoc& loc, const std::string& message);

/// Parses a whole word as a finite number (strtod syntax); false when it is not one.
bool pbrt_parse_number(const std::string& text, double& value);
/// Parses a word as a number; throws InputError at `t` otherwise.
double pbrt_number(const PbrtToken& t);
/// A number for messages ("%g").
std::string pbrt_format_number(double v);

}  // namespace penumbra
