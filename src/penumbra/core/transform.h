#pragma once
/// Affine transforms as 4x4 matrices with their inverses: translate, rotate, scale, look-at.
#include <array>

#include "penumbra/core/bounds.h"
#include "penumbra/core/ray.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// A row-major 4x4 matrix of double (double keeps inverses of composed transforms accurate).
struct Mat4 {
  std::array<std::array<double, 4>, 4> m{};
  /// The identity matrix.
  static Mat4 identity();
  Mat4 operator*(const Mat4& b) const;
  bool operator==(const Mat4&) const = default;
};

/// Inverse by Gauss-Jordan elimination with partial pivoting; throws Error when singular.
Mat4 inverse(const Mat4& a);
/// Transposed matrix.
Mat4 transpose(const Mat4& a);

/// An invertible affine transform with its inverse kept alongside.
class Transform {
 public:
  /// The identity.
  Transform() : m_(Mat4::identity()), inv_(Mat4::identity()) {}
  /// A transform from its matrix (inverted here; throws Error when singular).
  explicit Transform(const Mat4& m) : m_(m), inv_(inverse(m)) {}
  Transform(const Mat4& m, const Mat4& inv) : m_(m), inv_(inv) {}

  const Mat4& matrix() const { return m_; }
  const Mat4& inverse_matrix() const { return inv_; }
  /// The inverse transform.
  Transform inverted() const { return {inv_, m_}; }
  /// Composition: (a * b)(p) = a(b(p)).
  Transform operator*(const Transform& b) const { return {m_ * b.m_, b.inv_ * inv_}; }

  /// Transforms a point (w = 1).
  Vec3 point(Vec3 p) const;
  /// Transforms a direction (w = 0).
  Vec3 vector(Vec3 v) const;
  /// Transforms a surface normal by the inverse transpose (not normalised).
  Vec3 normal(Vec3 n) const;
  /// Transforms a box conservatively (the box of its eight transformed corners).
  Bounds3 bounds(const Bounds3& b) const;
  /// True when the transform flips orientation (negative determinant of the linear part).
  bool swaps_handedness() const;
  bool is_identity() const { return m_ == Mat4::identity(); }

 private:
  Mat4 m_;
  Mat4 inv_;
};

/// Translation by d.
Transform translate(Vec3 d);
/// Scale by s per axis (throws Error for a zero factor).
Transform scale(Vec3 s);
/// Rotation by `degrees` around `axis` (right-handed, axis need not be unit length).
Transform rotate(float degrees, Vec3 axis);
/// Camera-to-world transform of a camera at `eye` looking at `target` with `up`: camera +z is the
/// viewing direction, +y image up, +x image right (a left-handed camera frame, as in pbrt).
Transform look_at(Vec3 eye, Vec3 target, Vec3 up);

}  // namespace penumbra
