#pragma once
/// The "transform" of a shape: a JSON array of operations applied to the object in the listed
/// order, composed into one object-to-world Transform.
///
///   [{"scale": 2}, {"rotate": {"angle": 90, "axis": [0, 1, 0]}}, {"translate": [1, 0, 0]}]
///
/// scales first, then rotates, then translates (to_world = T * R * S). Operations:
/// - {"translate": [x, y, z]}
/// - {"scale": s} or {"scale": [x, y, z]}: non-zero factors (negative ones mirror)
/// - {"rotate": {"angle": degrees, "axis": [x, y, z]}}: right-handed, axis of any non-zero length
/// - {"matrix": [16 numbers]}: row-major affine matrix (bottom row 0 0 0 1), invertible; it maps
///   column vectors, p' = M p, so the translation is the last column.
#include <nlohmann/json.hpp>

#include "penumbra/core/transform.h"
#include "penumbra/scene/json_value.h"

namespace penumbra {

/// Parses a transform array at `place`; throws InputError naming the bad operation's JSON path.
Transform parse_transform(const nlohmann::json& ops, const JsonPlace& place);

/// True when the linear part of `t` maps the unit axes to mutually orthogonal vectors of equal
/// length, within `tolerance` relative to that length: a rotation or reflection times a uniform
/// scale, which maps spheres to spheres.
bool is_similarity(const Transform& t, double tolerance = 1e-5);

}  // namespace penumbra
