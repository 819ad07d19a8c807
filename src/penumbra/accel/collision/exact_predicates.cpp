#include "penumbra/accel/collision/exact_predicates.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace penumbra::collision {

namespace {

/// Unit roundoff of double.
constexpr double kEps = 0x1p-53;
/// Forward error bounds of the floating-point determinants relative to their permanents
/// (Shewchuk's ccwerrboundA and o3derrboundA), doubled: the compiler may contract the filter's
/// products into fused multiply-adds, which changes (and never worsens by more than this) the
/// error.
constexpr double kOrient2dBound = 2.0 * (3.0 + 16.0 * kEps) * kEps;
constexpr double kOrient3dBound = 2.0 * (7.0 + 56.0 * kEps) * kEps;

std::atomic<unsigned long long> g_fallbacks{0};

/// A nonoverlapping expansion: a sum of doubles in increasing order of magnitude, zeros
/// eliminated; its value is exact and its sign is that of the last (largest) component.
struct Expansion {
  static constexpr int kCap = 256;  ///< enough for orient3d: 3 * 2 * 2 * 16 components
  int n = 0;
  double e[kCap];

  Expansion() = default;
  // Copies only the components in use (the array is large, the expansions mostly short).
  Expansion(const Expansion& o) : n(o.n) { std::copy(o.e, o.e + o.n, e); }
  Expansion& operator=(const Expansion& o) {
    n = o.n;
    std::copy(o.e, o.e + o.n, e);
    return *this;
  }

  void push(double x) {
    if (x != 0.0) e[n++] = x;
  }
  int sign() const { return n == 0 ? 0 : (e[n - 1] > 0.0 ? 1 : -1); }
};

// Error-free transformations (Knuth; Dekker 1971; the product through a fused multiply-add).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}
inline void fast_two_sum(double a, double b, double& x, double& y) {  // needs |a| >= |b|
  x = a + b;
  y = b - (x - a);
}
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

/// a - b exactly, as an expansion of at most two components.
Expansion difference(double a, double b) {
  Expansion d;
  d.e[0] = a - b;
  const double bv = a - d.e[0], av = d.e[0] + bv;
  const double err = (a - av) + (bv - b);
  const double big = d.e[0];
  d.push(err);
  d.push(big);
  return d;
}

/// h = e + b (Shewchuk's Grow-Expansion with zero elimination).
void grow(const Expansion& e, double b, Expansion& h) {
  h.n = 0;
  double q = b;
  for (int i = 0; i < e.n; ++i) {
    double s, t;
    two_sum(q, e.e[i], s, t);
    h.push(t);
    q = s;
  }
  h.push(q);
}

/// h = e + f, by growing e with each component of f.
void add(const Expansion& e, const Expansion& f, Expansion& h) {
  Expansion tmp;
  h = e;
  for (int i = 0; i < f.n; ++i) {
    grow(h, f.e[i], tmp);
    h = tmp;
  }
}

/// h = e * b (Shewchuk's Scale-Expansion with zero elimination).
void scale(const Expansion& e, double b, Expansion& h) {
  h.n = 0;
  if (e.n == 0 || b == 0.0) return;
  double q, low;
  two_product(e.e[0], b, q, low);
  h.push(low);
  for (int i = 1; i < e.n; ++i) {
    double big, small, s;
    two_product(e.e[i], b, big, small);
    two_sum(q, small, s, low);
    h.push(low);
    fast_two_sum(big, s, q, low);
    h.push(low);
  }
  h.push(q);
}

/// h = e * f, as the sum of e scaled by each component of f.
void multiply(const Expansion& e, const Expansion& f, Expansion& h) {
  Expansion part, acc;
  h.n = 0;
  for (int i = 0; i < f.n; ++i) {
    scale(e, f.e[i], part);
    add(h, part, acc);
    h = acc;
  }
}

Expansion negated(Expansion e) {
  for (int i = 0; i < e.n; ++i) e.e[i] = -e.e[i];
  return e;
}

/// p * q - r * s exactly.
Expansion cross_term(const Expansion& p, const Expansion& q, const Expansion& r,
                     const Expansion& s) {
  Expansion pq, rs, out;
  multiply(p, q, pq);
  multiply(r, s, rs);
  add(pq, negated(rs), out);
  return out;
}

int orient3d_exact(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d) {
  g_fallbacks.fetch_add(1, std::memory_order_relaxed);
  const Expansion ux = difference(b.x, a.x), uy = difference(b.y, a.y), uz = difference(b.z, a.z);
  const Expansion vx = difference(c.x, a.x), vy = difference(c.y, a.y), vz = difference(c.z, a.z);
  const Expansion wx = difference(d.x, a.x), wy = difference(d.y, a.y), wz = difference(d.z, a.z);
  // Expansion along the first row: ux (vy wz - vz wy) + uy (vz wx - vx wz) + uz (vx wy - vy wx).
  Expansion t1, t2, t3, s12, det;
  multiply(cross_term(vy, wz, vz, wy), ux, t1);
  multiply(cross_term(vz, wx, vx, wz), uy, t2);
  multiply(cross_term(vx, wy, vy, wx), uz, t3);
  add(t1, t2, s12);
  add(s12, t3, det);
  return det.sign();
}

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  g_fallbacks.fetch_add(1, std::memory_order_relaxed);
  return cross_term(difference(bx, ax), difference(cy, ay), difference(by, ay), difference(cx, ax))
      .sign();
}

}  // namespace

int orient3d(const DVec3& a, const DVec3& b, const DVec3& c, const DVec3& d) {
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const double wx = d.x - a.x, wy = d.y - a.y, wz = d.z - a.z;
  const double p1 = vy * wz, p2 = vz * wy, p3 = vz * wx, p4 = vx * wz, p5 = vx * wy, p6 = vy * wx;
  const double det = ux * (p1 - p2) + uy * (p3 - p4) + uz * (p5 - p6);
  const double permanent = std::fabs(ux) * (std::fabs(p1) + std::fabs(p2)) +
                           std::fabs(uy) * (std::fabs(p3) + std::fabs(p4)) +
                           std::fabs(uz) * (std::fabs(p5) + std::fabs(p6));
  // Filter: the rounded determinant is farther from zero than its error bound.
  const double bound = kOrient3dBound * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  // Repeated points (shared mesh vertices) make a zero determinant: no need for the exact stage.
  if (d == a || d == b || d == c || a == b || b == c || c == a) return 0;
  return orient3d_exact(a, b, c, d);
}

PlaneOrientation::PlaneOrientation(const DVec3& a, const DVec3& b, const DVec3& c)
    : a_(a), b_(b), c_(c) {
  const DVec3 u = b - a, v = c - a;
  const double p1 = u.y * v.z, p2 = u.z * v.y, p3 = u.z * v.x, p4 = u.x * v.z, p5 = u.x * v.y,
               p6 = u.y * v.x;
  normal_ = {p1 - p2, p3 - p4, p5 - p6};
  permanent_ = {std::fabs(p1) + std::fabs(p2), std::fabs(p3) + std::fabs(p4),
                std::fabs(p5) + std::fabs(p6)};
}

int PlaneOrientation::operator()(const DVec3& d) const {
  // dot(d - a, (b - a) x (c - a)): the determinant of orient3d expanded along its last row, the
  // same form as there, so the same error bound holds.
  const DVec3 w = d - a_;
  const double det = w.x * normal_.x + w.y * normal_.y + w.z * normal_.z;
  const double permanent =
      std::fabs(w.x) * permanent_.x + std::fabs(w.y) * permanent_.y + std::fabs(w.z) * permanent_.z;
  const double bound = kOrient3dBound * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  if (d == a_ || d == b_ || d == c_ || a_ == b_ || b_ == c_ || c_ == a_) return 0;
  return orient3d_exact(a_, b_, c_, d);
}

int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double l = (bx - ax) * (cy - ay), r = (by - ay) * (cx - ax);
  const double det = l - r;
  const double bound = kOrient2dBound * (std::fabs(l) + std::fabs(r));
  if (det > bound) return 1;
  if (det < -bound) return -1;
  if ((ax == bx && ay == by) || (bx == cx && by == cy) || (cx == ax && cy == ay)) return 0;
  return orient2d_exact(ax, ay, bx, by, cx, cy);
}

unsigned long long exact_predicate_fallbacks() {
  return g_fallbacks.load();
}

}  // namespace penumbra::collision
