#pragma once
/// Per-ray values computed once before traversal: reciprocal direction, direction signs and the
/// shear constants of the watertight triangle test.
#include <cmath>

#include "penumbra/core/ray.h"

namespace penumbra {

/// A ray with the values every box and triangle test of one traversal shares.
struct PreparedRay {
  Ray ray;
  Vec3 inv_dir;      ///< 1/d per axis; +-inf for a zero component (IEEE division)
  int neg[3];        ///< 1 where the direction component is negative
  int kx, ky, kz;    ///< watertight test: kz = axis of largest |d|, (kx, ky) the others
  float sx, sy, sz;  ///< watertight test: shear constants

  /// Prepares `r` (its direction need not be normalised, but must not be zero).
  explicit PreparedRay(const Ray& r) : ray(r) {
    inv_dir = {1.0f / r.d.x, 1.0f / r.d.y, 1.0f / r.d.z};
    for (int i = 0; i < 3; ++i) neg[i] = std::signbit(r.d[i]) ? 1 : 0;
    // Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1): permute so
    // that z is the dominant direction axis, keeping the winding by swapping x and y if needed.
    // Written with selects rather than branches: incoherent rays would mispredict them.
    const Vec3 ad = abs(r.d);
    kz = max_dimension(ad);
    const int x = kz == 2 ? 0 : kz + 1, y = x == 2 ? 0 : x + 1;
    const bool flip = neg[kz] != 0;
    kx = flip ? y : x;
    ky = flip ? x : y;
    sz = inv_dir[kz];
    sx = r.d[kx] * sz;
    sy = r.d[ky] * sz;
  }
};

}  // namespace penumbra
