#pragma once
/// The transform directives of pbrt-v4 as matrices. Each returns the matrix that the directive
/// multiplies onto the current transformation matrix from the right (CTM = CTM * M), except
/// pbrt_matrix for `Transform`, which replaces it. Numbers are taken as the directive lists them.
#include <vector>

#include "penumbra/core/transform.h"
#include "penumbra/scene/pbrt_tokenizer.h"

namespace penumbra {

/// `Translate x y z`.
Transform pbrt_translate(const std::vector<double>& v);
/// `Scale x y z` (a zero factor is an InputError at `loc`: the matrix has no inverse).
Transform pbrt_scale(const std::vector<double>& v, const PbrtLoc& loc);
/// `Rotate angle x y z`: `angle` degrees about the axis, as the rotation matrix of a right-handed
/// frame (pbrt writes the same matrix; in its left-handed view it looks clockwise).
Transform pbrt_rotate(const std::vector<double>& v, const PbrtLoc& loc);
/// `LookAt ex ey ez lx ly lz ux uy uz`: the world-to-camera transform of a camera at e looking at
/// l, whose camera +x is normalize(cross(up, dir)), +y cross(dir, +x) and +z dir (pbrt's
/// left-handed camera frame).
Transform pbrt_look_at(const std::vector<double>& v, const PbrtLoc& loc);
/// `Transform [m00 ... m33]` / `ConcatTransform`: 16 numbers given column by column (the first
/// four are the first column; the translation is numbers 12, 13, 14), i.e. the transpose of a
/// row-major reading. A singular matrix is an InputError.
Transform pbrt_matrix(const std::vector<double>& v, const PbrtLoc& loc);

/// The angle in radians of the turn from `a`'s rotation to `b`'s, where each transform's rotation
/// is the orthogonal factor of the polar decomposition of its linear part (pbrt-v4's
/// AnimatedTransform interpolates that factor by slerp, the rest linearly). 0 when the two differ
/// only by translation and scale; then moving every vertex on a straight line, as penumbra does,
/// is exactly pbrt's motion.
double pbrt_rotation_between(const Transform& a, const Transform& b);

}  // namespace penumbra
