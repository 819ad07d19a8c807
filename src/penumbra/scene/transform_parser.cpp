#include "penumbra/scene/transform_parser.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

using nlohmann::json;

namespace {

// Length of column i of the linear part of m.
double column_length(const Mat4& a, int i) {
  return std::sqrt(a.m[0][i] * a.m[0][i] + a.m[1][i] * a.m[1][i] + a.m[2][i] * a.m[2][i]);
}

double det3(const Mat4& a) {
  const auto& m = a.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Transform parse_scale(const json& v, const JsonPlace& place) {
  const Vec3 s = v.is_number() ? Vec3(json_float(v, place)) : json_vec3(v, place);
  if (s.x == 0 || s.y == 0 || s.z == 0) place.fail("scale factors must not be zero");
  return scale(s);
}

Transform parse_rotate(const json& v, const JsonPlace& place) {
  if (!v.is_object()) place.fail("expected an object {\"angle\": degrees, \"axis\": [x, y, z]}");
  json_check_keys(v, place, {"angle", "axis"}, "a rotation");
  const float angle = json_float(json_require(v, place, "angle"), place.key("angle"));
  const Vec3 axis = json_vec3(json_require(v, place, "axis"), place.key("axis"));
  if (axis == Vec3(0.0f)) place.key("axis").fail("rotation axis must not be zero");
  return rotate(angle, axis);
}

Transform parse_matrix(const json& v, const JsonPlace& place) {
  if (!v.is_array() || v.size() != 16) place.fail("expected an array of 16 numbers (row-major)");
  Mat4 m;
  for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = json_number(v[i], place.index(i));
  if (m.m[3][0] != 0 || m.m[3][1] != 0 || m.m[3][2] != 0 || m.m[3][3] != 1)
    place.fail("bottom row must be [0, 0, 0, 1] (affine transforms only)");
  // Singular, or so close to it that the inverse is meaningless.
  const double norms = column_length(m, 0) * column_length(m, 1) * column_length(m, 2);
  if (!(std::fabs(det3(m)) > 1e-12 * norms)) place.fail("matrix is singular (not invertible)");
  return Transform(m);
}

}  // namespace

Transform parse_transform(const json& ops, const JsonPlace& place) {
  if (!ops.is_array()) place.fail("expected an array of transform operations");
  Transform to_world;
  for (size_t i = 0; i < ops.size(); ++i) {
    const JsonPlace op_place = place.index(i);
    const json& op = ops[i];
    if (!op.is_object() || op.size() != 1)
      op_place.fail("expected an object with one key: translate, scale, rotate or matrix");
    const std::string& name = op.begin().key();
    const json& value = op.begin().value();
    const JsonPlace at = op_place.key(name);
    Transform t;
    if (name == "translate") {
      t = translate(json_vec3(value, at));
    } else if (name == "scale") {
      t = parse_scale(value, at);
    } else if (name == "rotate") {
      t = parse_rotate(value, at);
    } else if (name == "matrix") {
      t = parse_matrix(value, at);
    } else {
      at.fail("unknown transform operation (expected translate, scale, rotate or matrix)");
    }
    to_world = t * to_world;  // later operations apply after earlier ones
  }
  return to_world;
}

bool is_similarity(const Transform& t, double tolerance) {
  const Mat4& m = t.matrix();
  const double len[3] = {column_length(m, 0), column_length(m, 1), column_length(m, 2)};
  const double s = std::max({len[0], len[1], len[2]});
  if (!(s > 0)) return false;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(len[i] - s) > tolerance * s) return false;
    for (int j = i + 1; j < 3; ++j) {
      const double d = m.m[0][i] * m.m[0][j] + m.m[1][i] * m.m[1][j] + m.m[2][i] * m.m[2][j];
      if (std::fabs(d) > tolerance * s * s) return false;
    }
  }
  return true;
}

}  // namespace penumbra
