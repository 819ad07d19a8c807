#include "penumbra/scene/pbrt_transforms.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "penumbra/core/error.h"

namespace penumbra {

namespace {
Vec3 vec3(const std::vector<double>& v, size_t at) {
  return {float(v[at]), float(v[at + 1]), float(v[at + 2])};
}

using Mat3 = std::array<std::array<double, 3>, 3>;

// The orthogonal factor R of the polar decomposition M = R S of an invertible 3x3 matrix, by
// Higham's iteration R <- (R + R^-T) / 2, which converges quadratically.
Mat3 polar_rotation(const Transform& t) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = t.matrix().m[i][j];
  for (int iter = 0; iter < 100; ++iter) {
    // The inverse transpose by cofactors: (R^-T)_ij = cof_ij / det.
    Mat3 c;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        c[i][j] = r[i1][j1] * r[i2][j2] - r[i1][j2] * r[i2][j1];
      }
    const double det = r[0][0] * c[0][0] + r[0][1] * c[0][1] + r[0][2] * c[0][2];
    if (!(std::abs(det) > 0)) break;
    double change = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double next = 0.5 * (r[i][j] + c[i][j] / det);
        change = std::max(change, std::abs(next - r[i][j]));
        r[i][j] = next;
      }
    if (change < 1e-15) break;
  }
  return r;
}
}  // namespace

// Translate, Scale and Rotate go through the same float constructors as the JSON loader's
// operations, so that the same numbers give the same bits in both formats.
Transform pbrt_translate(const std::vector<double>& v) {
  return translate(vec3(v, 0));
}

Transform pbrt_scale(const std::vector<double>& v, const PbrtLoc& loc) {
  if (v[0] == 0 || v[1] == 0 || v[2] == 0)
    loc.fail("Scale by zero: the transform would have no inverse");
  return scale(vec3(v, 0));
}

Transform pbrt_rotate(const std::vector<double>& v, const PbrtLoc& loc) {
  const Vec3 axis = vec3(v, 1);
  if (!(length(axis) > 0)) loc.fail("Rotate about a zero-length axis");
  return rotate(float(v[0]), axis);
}

Transform pbrt_look_at(const std::vector<double>& v, const PbrtLoc& loc) {
  const double e[3] = {v[0], v[1], v[2]};
  double d[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]};
  double up[3] = {v[6], v[7], v[8]};
  auto normalize3 = [](double a[3]) {
    const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (!(l > 0)) return false;
    for (int i = 0; i < 3; ++i) a[i] /= l;
    return true;
  };
  auto cross3 = [](const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
  };
  if (!normalize3(d)) loc.fail("LookAt: the eye and the look-at point coincide");
  if (!normalize3(up)) loc.fail("LookAt: the up vector is zero");
  double right[3], new_up[3];
  cross3(up, d, right);
  if (!normalize3(right)) loc.fail("LookAt: the up vector is parallel to the viewing direction");
  cross3(d, right, new_up);
  // Camera-to-world has columns right, up, direction and the eye; LookAt is its inverse.
  Mat4 m = Mat4::identity();
  for (int i = 0; i < 3; ++i) {
    m.m[i][0] = right[i];
    m.m[i][1] = new_up[i];
    m.m[i][2] = d[i];
    m.m[i][3] = e[i];
  }
  return Transform(m).inverted();
}

double pbrt_rotation_between(const Transform& a, const Transform& b) {
  const Mat3 ra = polar_rotation(a), rb = polar_rotation(b);
  // trace(Rb Ra^T) = 1 + 2 cos(angle).
  double trace = 0;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) trace += rb[i][k] * ra[i][k];
  return std::acos(std::clamp(0.5 * (trace - 1), -1.0, 1.0));
}

Transform pbrt_matrix(const std::vector<double>& v, const PbrtLoc& loc) {
  Mat4 m;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m.m[r][c] = v[size_t(4 * c + r)];
  if (m.m[3][0] != 0 || m.m[3][1] != 0 || m.m[3][2] != 0 || m.m[3][3] != 1)
    loc.fail(
        "the matrix is not affine (numbers 3, 7, 11, 15 must be 0, 0, 0, 1): projective "
        "transforms are not supported");
  try {
    return Transform(m);
  } catch (const Error& err) {
    loc.fail(std::string("the matrix has no inverse (") + err.what() + ")");
  }
}

}  // namespace penumbra
