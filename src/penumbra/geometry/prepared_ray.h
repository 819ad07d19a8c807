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

  /// Prepares `r` (its direction need not be normalised, but must not be zero). Inlined into
  /// every traversal: a call stored the result to memory for the traversal to load back, and
  /// on the million-ray benchmarks the setup was a tenth of a small mesh's instructions per ray.
  [[gnu::always_inline]] explicit PreparedRay(const Ray& r) : ray(r) {
    inv_dir = {1.0f / r.d.x, 1.0f / r.d.y, 1.0f / r.d.z};
    for (int i = 0; i < 3; ++i) neg[i] = std::signbit(r.d[i]) ? 1 : 0;
    // Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1): permute so
    // that z is the dominant direction axis, keeping the winding by swapping x and y if needed.
    // Integer arithmetic on the comparisons and small tables, not branches: incoherent rays
    // would mispredict them. kz is max_dimension(|d|) (ties as it breaks them).
    const Vec3 ad = abs(r.d);
    const int xy = ad.x > ad.y, xz = ad.x > ad.z, yz = ad.y > ad.z;
    kz = 2 - 2 * (xy & xz) - ((xy ^ 1) & yz);
    // (kx, ky) by kz and whether d[kz] < 0, from a table: `flip ? y : x` compiled to a branch
    // that half of the incoherent rays mispredicted.
    static constexpr int kPerm[3][2][2] = {{{1, 2}, {2, 1}}, {{2, 0}, {0, 2}}, {{0, 1}, {1, 0}}};
    const int flip = neg[kz];
    kx = kPerm[kz][flip][0];
    ky = kPerm[kz][flip][1];
    sz = inv_dir[kz];
    sx = r.d[kx] * sz;
    sy = r.d[ky] * sz;
  }
};

}  // namespace penumbra
