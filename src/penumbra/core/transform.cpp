#include "penumbra/core/transform.h"

#include <cmath>
#include <numbers>
#include <utility>

#include "penumbra/core/error.h"

namespace penumbra {

Mat4 Mat4::identity() {
  Mat4 r;
  for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
  return r;
}

Mat4 Mat4::operator*(const Mat4& b) const {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += m[i][k] * b.m[k][j];
      r.m[i][j] = s;
    }
  return r;
}

Mat4 transpose(const Mat4& a) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

Mat4 inverse(const Mat4& a) {
  Mat4 w = a, r = Mat4::identity();
  for (int col = 0; col < 4; ++col) {
    // Partial pivoting: the row with the largest magnitude in this column.
    int pivot = col;
    for (int row = col + 1; row < 4; ++row)
      if (std::fabs(w.m[row][col]) > std::fabs(w.m[pivot][col])) pivot = row;
    if (std::fabs(w.m[pivot][col]) < 1e-300) throw Error("singular transform matrix");
    std::swap(w.m[col], w.m[pivot]);
    std::swap(r.m[col], r.m[pivot]);
    const double inv_p = 1.0 / w.m[col][col];
    for (int j = 0; j < 4; ++j) w.m[col][j] *= inv_p, r.m[col][j] *= inv_p;
    // Eliminate the column from every other row.
    for (int row = 0; row < 4; ++row) {
      if (row == col) continue;
      const double f = w.m[row][col];
      if (f == 0.0) continue;
      for (int j = 0; j < 4; ++j) w.m[row][j] -= f * w.m[col][j], r.m[row][j] -= f * r.m[col][j];
    }
  }
  return r;
}

Vec3 Transform::point(Vec3 p) const {
  const auto& m = m_.m;
  double out[4];
  for (int i = 0; i < 4; ++i) out[i] = m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3];
  if (out[3] != 1.0) out[0] /= out[3], out[1] /= out[3], out[2] /= out[3];
  return {float(out[0]), float(out[1]), float(out[2])};
}

Vec3 Transform::vector(Vec3 v) const {
  const auto& m = m_.m;
  return {float(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z),
          float(m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z),
          float(m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z)};
}

Vec3 Transform::normal(Vec3 n) const {
  const auto& mi = inv_.m;  // inverse transpose: column i of the inverse
  return {float(mi[0][0] * n.x + mi[1][0] * n.y + mi[2][0] * n.z),
          float(mi[0][1] * n.x + mi[1][1] * n.y + mi[2][1] * n.z),
          float(mi[0][2] * n.x + mi[1][2] * n.y + mi[2][2] * n.z)};
}

Bounds3 Transform::bounds(const Bounds3& b) const {
  Bounds3 r;
  if (b.empty()) return r;
  for (int c = 0; c < 8; ++c)
    r.extend(point({(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z}));
  return r;
}

bool Transform::swaps_handedness() const {
  const auto& m = m_.m;
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return det < 0;
}

Transform translate(Vec3 d) {
  Mat4 m = Mat4::identity(), inv = Mat4::identity();
  m.m[0][3] = d.x, m.m[1][3] = d.y, m.m[2][3] = d.z;
  inv.m[0][3] = -d.x, inv.m[1][3] = -d.y, inv.m[2][3] = -d.z;
  return {m, inv};
}

Transform scale(Vec3 s) {
  if (s.x == 0 || s.y == 0 || s.z == 0) throw Error("scale factor of zero is not invertible");
  Mat4 m = Mat4::identity(), inv = Mat4::identity();
  for (int i = 0; i < 3; ++i) m.m[i][i] = s[i], inv.m[i][i] = 1.0 / s[i];
  return {m, inv};
}

Transform rotate(float degrees, Vec3 axis) {
  const double len = std::sqrt(double(axis.x) * axis.x + double(axis.y) * axis.y + double(axis.z) * axis.z);
  if (!(len > 0)) throw Error("rotation axis has zero length");
  const double x = axis.x / len, y = axis.y / len, z = axis.z / len;
  const double th = degrees * std::numbers::pi / 180.0, c = std::cos(th), s = std::sin(th);
  // Rodrigues' rotation formula as a matrix.
  Mat4 m = Mat4::identity();
  m.m[0][0] = x * x + (1 - x * x) * c, m.m[0][1] = x * y * (1 - c) - z * s, m.m[0][2] = x * z * (1 - c) + y * s;
  m.m[1][0] = x * y * (1 - c) + z * s, m.m[1][1] = y * y + (1 - y * y) * c, m.m[1][2] = y * z * (1 - c) - x * s;
  m.m[2][0] = x * z * (1 - c) - y * s, m.m[2][1] = y * z * (1 - c) + x * s, m.m[2][2] = z * z + (1 - z * z) * c;
  return {m, transpose(m)};  // a rotation's inverse is its transpose
}

Transform look_at(Vec3 eye, Vec3 target, Vec3 up) {
  const Vec3 fwd = target - eye;
  if (!(length(fwd) > 0)) throw Error("look_at: eye and target coincide");
  const Vec3 f = normalize(fwd);
  const Vec3 r = cross(f, normalize(up));
  if (!(length(r) > 0)) throw Error("look_at: up vector is parallel to the viewing direction");
  const Vec3 right = normalize(r);
  const Vec3 u = cross(right, f);
  // Columns: camera +x (image right), +y (image up), +z (forward), origin.
  Mat4 m = Mat4::identity();
  for (int i = 0; i < 3; ++i) m.m[i][0] = right[i], m.m[i][1] = u[i], m.m[i][2] = f[i], m.m[i][3] = eye[i];
  return Transform(m);
}

}  // namespace penumbra
