#include "test_scenes.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/transform.h"
#include "penumbra/geometry/sphere_direction.h"
#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra::test {

namespace {

Vec3 random_vec(Pcg32& rng) {
  return {rng.next_float(), rng.next_float(), rng.next_float()};
}

Vec3 random_dir(Pcg32& rng) {
  return sample_uniform_sphere({rng.next_float(), rng.next_float()});
}

/// Appends one triangle as its own mesh (identity transform keeps coordinates exact).
void add_triangle(PrimitiveSet& prims, Vec3 a, Vec3 b, Vec3 c) {
  TriangleMesh m;
  m.positions = {a, b, c};
  m.indices = {0, 1, 2};
  prims.add_mesh(m, Transform(), 0);
}

/// Appends the 12 triangles of an axis-aligned box.
void add_box(TriangleMesh& m, Vec3 lo, Vec3 hi) {
  const auto base = static_cast<uint32_t>(m.positions.size());
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  const uint32_t faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& f : faces)
    for (uint32_t k : {f[0], f[1], f[2], f[0], f[2], f[3]}) m.indices.push_back(base + k);
}

}  // namespace

TestScene random_soup(int n, uint64_t seed) {
  TestScene s{"random_soup", {}};
  Pcg32 rng(seed, 1);
  TriangleMesh m;
  for (int i = 0; i < n; ++i) {
    const Vec3 c = random_vec(rng);
    const float size = 0.01f + 0.2f * rng.next_float() * rng.next_float();
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(c + (random_vec(rng) - Vec3(0.5f)) * size);
      m.indices.push_back(static_cast<uint32_t>(m.positions.size() - 1));
    }
  }
  s.prims.add_mesh(m, Transform(), 0);
  return s;
}

TestScene coplanar_grid(int nx, int ny) {
  TestScene s{"coplanar_grid", {}};
  for (int layer = 0; layer < 2; ++layer) {
    TriangleMesh m;
    const float off = layer * 0.5f;
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.positions.push_back({i + off, j + off, float(layer)});
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const auto v = static_cast<uint32_t>(j * (nx + 1) + i);
        const uint32_t w = nx + 1;
        for (uint32_t k : {v, v + 1, v + w + 1, v, v + w + 1, v + w}) m.indices.push_back(k);
      }
    s.prims.add_mesh(m, Transform(), layer);
  }
  return s;
}

TestScene room_with_boxes(int boxes, uint64_t seed, Vec3 offset) {
  TestScene s{"room_with_boxes", {}};
  Pcg32 rng(seed, 2);
  TriangleMesh m;
  add_box(m, Vec3(0.0f), Vec3(10.0f));
  for (int i = 0; i < boxes; ++i) {
    // Integer and half-integer coordinates: many boxes share planes exactly.
    const Vec3 lo(float(rng.next_bounded(18)) * 0.5f, float(rng.next_bounded(18)) * 0.5f,
                  float(rng.next_bounded(18)) * 0.5f);
    const Vec3 size(0.5f * float(1 + rng.next_bounded(3)), 0.5f * float(1 + rng.next_bounded(3)),
                    0.5f * float(1 + rng.next_bounded(3)));
    add_box(m, lo, min(lo + size, Vec3(10.0f)));
  }
  s.prims.add_mesh(m, translate(offset), 0);
  return s;
}

TestScene thin_and_large(uint64_t seed) {
  TestScene s{"thin_and_large", {}};
  Pcg32 rng(seed, 3);
  for (int i = 0; i < 300; ++i) {  // needles: length ~1, width 1e-5
    const Vec3 a = random_vec(rng) * 4.0f, d = random_dir(rng);
    add_triangle(s.prims, a, a + d, a + d + random_dir(rng) * 1e-5f);
  }
  for (int i = 0; i < 300; ++i) {  // tiny
    const Vec3 a = random_vec(rng) * 4.0f;
    add_triangle(s.prims, a, a + random_dir(rng) * 1e-4f, a + random_dir(rng) * 1e-4f);
  }
  for (int i = 0; i < 30; ++i) {  // huge, crossing everything
    const Vec3 c = random_vec(rng) * 4.0f;
    add_triangle(s.prims, c + random_dir(rng) * 1e4f, c + random_dir(rng) * 1e4f,
                 c + random_dir(rng) * 1e4f);
  }
  for (int i = 0; i < 300; ++i) {  // ordinary
    const Vec3 a = random_vec(rng) * 4.0f;
    add_triangle(s.prims, a, a + random_dir(rng) * 0.3f, a + random_dir(rng) * 0.3f);
  }
  return s;
}

TestScene mixed_shapes(uint64_t seed) {
  TestScene s{"mixed_shapes", {}};
  Pcg32 rng(seed, 4);
  for (int i = 0; i < 300; ++i)
    s.prims.add_sphere({random_vec(rng) * 5.0f, 0.02f + 0.3f * rng.next_float()}, 1);
  for (int i = 0; i < 300; ++i)
    s.prims.add_quad({random_vec(rng) * 5.0f, random_dir(rng) * 0.5f, random_dir(rng) * 0.5f}, 2);
  // Axis-aligned quads on shared planes.
  for (int i = 0; i < 50; ++i)
    s.prims.add_quad({Vec3(float(rng.next_bounded(5)), float(rng.next_bounded(5)), 2.0f),
                      Vec3(1, 0, 0), Vec3(0, 1, 0)},
                     2);
  for (int i = 0; i < 400; ++i) {
    const Vec3 a = random_vec(rng) * 5.0f;
    add_triangle(s.prims, a, a + random_dir(rng) * 0.4f, a + random_dir(rng) * 0.4f);
  }
  return s;
}

TestScene coincident_surfaces(uint64_t seed, bool shapes) {
  TestScene s{shapes ? "coincident_shapes" : "coincident_triangles", {}};
  Pcg32 rng(seed, 9);
  struct Item {
    int kind;  // 0 triangle (a, b, c), 1 sphere (centre a), 2 parallelogram (corner a, edges b, c)
    Vec3 a, b, c;
    float radius;  // spheres
  };
  std::vector<Item> items;
  const auto triangle = [&](Vec3 a, Vec3 b, Vec3 c) {
    items.push_back({0, a, b, c, 0.0f});
    items.push_back({0, a, b, c, 0.0f});
    if (rng.next_bounded(2)) items.push_back({0, b, c, a, 0.0f});
  };
  const TestScene room = room_with_boxes(20, seed);
  for (uint32_t id = 0; id < room.prims.size(); ++id) {
    const Vec3* v = room.prims.triangle(id);
    triangle(v[0], v[1], v[2]);
  }
  for (int i = 0; i < 300; ++i) {
    const Vec3 a = random_vec(rng) * 10.0f;
    triangle(a, a + random_dir(rng), a + random_dir(rng));
  }
  if (shapes) {
    for (int i = 0; i < 100; ++i) {
      const Vec3 centre = random_vec(rng) * 10.0f;
      const Item sphere{1, centre, {}, {}, 0.1f + rng.next_float()};
      const Item quad{2, random_vec(rng) * 10.0f, random_dir(rng), random_dir(rng), 0.0f};
      for (int k = 0; k < 2; ++k) items.push_back(sphere), items.push_back(quad);
    }
  }
  for (size_t i = items.size(); i > 1; --i)
    std::swap(items[i - 1], items[rng.next_bounded(uint32_t(i))]);
  for (const Item& it : items) {
    if (it.kind == 0)
      add_triangle(s.prims, it.a, it.b, it.c);
    else if (it.kind == 1)
      s.prims.add_sphere({it.a, it.radius}, 1);
    else
      s.prims.add_quad({it.a, it.b, it.c}, 2);
  }
  return s;
}

bool referenced_by_structures(const PrimitiveSet& prims, uint32_t id) {
  return !prims.prim_bounds(id).empty() && !never_hit(prims, id);
}

TestScene degenerate_triangles(uint64_t seed) {
  TestScene s{"degenerate_triangles", {}};
  Pcg32 rng(seed, 5);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 1000; ++i) {
    const Vec3 a = random_vec(rng) * 3.0f, b = a + random_dir(rng) * 0.3f;
    const Vec3 c = a + random_dir(rng) * 0.3f;
    switch (rng.next_bounded(6)) {
      case 0:  // repeated vertex
        add_triangle(s.prims, a, a, c);
        break;
      case 1:  // collinear
        add_triangle(s.prims, a, b, a + (b - a) * 2.0f);
        break;
      case 2:  // a NaN vertex
        add_triangle(s.prims, a, b, Vec3(c.x, nan, c.z));
        break;
      case 3:  // an infinite vertex
        add_triangle(s.prims, a, Vec3(kInfinity, b.y, b.z), c);
        break;
      default:
        add_triangle(s.prims, a, b, c);
    }
  }
  return s;
}

TestScene large_triangles(int n, int small, uint64_t seed, bool slivers) {
  TestScene s{slivers ? "slivers" : "large_triangles", {}};
  Pcg32 rng(seed, slivers ? 7 : 3);
  TriangleMesh m;
  const auto random_point = [&] {
    return Vec3(rng.next_float(), rng.next_float(), rng.next_float());
  };
  const auto near = [&](Vec3 p) { return p + (random_point() - Vec3(0.5f)) * 0.01f; };
  for (int i = 0; i < n + small; ++i) {
    Vec3 v[3];
    if (slivers) {
      v[0] = random_point();
      v[1] = i < n ? random_point() : near(v[0]);
      v[2] = near(v[0]);
    } else {
      const Vec3 c = random_point();
      for (Vec3& p : v) p = i < n ? random_point() : near(c);
    }
    for (const Vec3& p : v) {
      m.positions.push_back(p);
      m.indices.push_back(static_cast<uint32_t>(m.positions.size() - 1));
    }
  }
  s.prims.add_mesh(m, Transform(), 0);
  return s;
}

void trace_both(const Accelerator& a, const Accelerator& b, const std::vector<Ray>& rays,
                TraversalCost& cost_a, TraversalCost& cost_b) {
  for (const Ray& ray : rays) {
    Hit ha, hb;
    a.intersect_cost(ray, ha, cost_a);
    b.intersect_cost(ray, hb, cost_b);
    ASSERT_EQ(ha.valid(), hb.valid());
    if (ha.valid()) {
      ASSERT_EQ(ha.t, hb.t);
    }
  }
}

double extra_stat(const Accelerator& acc, const std::string& key) {
  for (const auto& [k, v] : acc.stats().extra)
    if (k == key) return v;
  ADD_FAILURE() << acc.name() << " reports no " << key;
  return 0.0;
}

TestScene torus(int rings, int sides) {
  TestScene s{"torus", {}};
  TriangleMesh m;
  const float R = 1.0f, r = 0.35f, two_pi = 2.0f * std::numbers::pi_v<float>;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const float u = two_pi * float(i) / float(rings), v = two_pi * float(j) / float(sides);
      m.positions.push_back({(R + r * std::cos(v)) * std::cos(u),
                             (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const auto at = [&](int a, int b) { return uint32_t((a % rings) * sides + (b % sides)); };
      for (uint32_t k :
           {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)})
        m.indices.push_back(k);
    }
  s.prims.add_mesh(m, rotate(30.0f, Vec3(1, 2, 3)), 0);  // rotated: no axis-aligned structure
  return s;
}

namespace {

/// A random motion: the end transform of a primitive near `c` that starts at the identity, a
/// turn of up to `turn` degrees about `c`, a scale in [0.8, 1.2] about it and a translation of up
/// to `reach` along each axis.
Transform random_motion(Pcg32& rng, Vec3 c, float reach, float turn) {
  const Vec3 d = (random_vec(rng) - Vec3(0.5f)) * (2.0f * reach);
  const float s = 0.8f + 0.4f * rng.next_float();
  return translate(c + d) * rotate(turn * rng.next_float(), random_dir(rng)) * scale(Vec3(s)) *
         translate(-c);
}

/// Appends one triangle moving from (a, b, c) to its image under `end`.
void add_moving_triangle(PrimitiveSet& prims, Vec3 a, Vec3 b, Vec3 c, const Transform& end) {
  TriangleMesh m;
  m.positions = {a, b, c};
  m.indices = {0, 1, 2};
  prims.add_moving_mesh(m, Transform(), end, 0);
}

}  // namespace

TestScene moving_soup(int n, uint64_t seed) {
  TestScene s{"moving_soup", {}};
  Pcg32 rng(seed, 7);
  for (int i = 0; i < n; ++i) {
    const Vec3 c = random_vec(rng);
    const float size = 0.01f + 0.2f * rng.next_float() * rng.next_float();
    Vec3 v[3];
    for (Vec3& p : v) p = c + (random_vec(rng) - Vec3(0.5f)) * size;
    const Transform end = i % 5 == 4 ? Transform() : random_motion(rng, c, 0.1f, 40.0f);
    add_moving_triangle(s.prims, v[0], v[1], v[2], end);
  }
  return s;
}

TestScene moving_shapes(uint64_t seed) {
  TestScene s{"moving_shapes", {}};
  Pcg32 rng(seed, 8);
  for (int i = 0; i < 200; ++i) {
    const SphereData a{random_vec(rng) * 5.0f, 0.02f + 0.3f * rng.next_float()};
    SphereData b = a;
    if (i % 6 != 5) b.center = a.center + (random_vec(rng) - Vec3(0.5f)) * 1.0f;
    if (i % 3 == 0) b.radius = a.radius * (0.5f + rng.next_float());
    s.prims.add_moving_sphere(a, b, 1);
  }
  for (int i = 0; i < 200; ++i) {
    const QuadData a{random_vec(rng) * 5.0f, random_dir(rng) * 0.5f, random_dir(rng) * 0.5f};
    QuadData b = a;
    if (i % 6 != 5)
      b = {a.p + (random_vec(rng) - Vec3(0.5f)) * 1.0f, random_dir(rng) * 0.5f,
           random_dir(rng) * 0.5f};
    s.prims.add_moving_quad(a, b, 2);
  }
  for (int i = 0; i < 300; ++i) {
    const Vec3 a = random_vec(rng) * 5.0f;
    const Transform end = i % 6 == 5 ? Transform() : random_motion(rng, a, 0.5f, 90.0f);
    add_moving_triangle(s.prims, a, a + random_dir(rng) * 0.4f, a + random_dir(rng) * 0.4f, end);
  }
  return s;
}

TestScene static_and_moving(uint64_t seed) {
  TestScene s = room_with_boxes(40, seed);
  s.name = "static_and_moving";
  Pcg32 rng(seed, 9);
  for (int i = 0; i < 200; ++i) {  // fast movers: across a third of the room
    const Vec3 a = random_vec(rng) * 10.0f;
    add_moving_triangle(s.prims, a, a + random_dir(rng) * 0.8f, a + random_dir(rng) * 0.8f,
                        random_motion(rng, a, 3.0f, 30.0f));
  }
  for (int i = 0; i < 100; ++i) {
    const SphereData a{random_vec(rng) * 10.0f, 0.1f + 0.4f * rng.next_float()};
    s.prims.add_moving_sphere(a, {a.center + random_dir(rng) * 2.0f, a.radius}, 1);
  }
  for (int i = 0; i < 100; ++i) {  // axis-aligned quads sliding in their own plane
    const QuadData a{Vec3(float(rng.next_bounded(10)), float(rng.next_bounded(10)), 5.0f),
                     Vec3(1, 0, 0), Vec3(0, 1, 0)};
    s.prims.add_moving_quad(a, {a.p + Vec3(float(rng.next_bounded(3)), 0, 0), a.e1, a.e2}, 2);
  }
  return s;
}

void set_random_times(std::vector<Ray>& rays, uint64_t seed) {
  Pcg32 rng(seed, 10);
  for (Ray& r : rays) {
    const uint32_t k = rng.next_bounded(20);
    r.time = k == 0 ? 0.0f : k == 1 ? 1.0f : k == 2 ? -0.5f : k == 3 ? 1.5f : rng.next_float();
  }
}

Vec3 point_on(const PrimitiveSet& prims, uint32_t id, float u1, float u2) {
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      const Vec3* p = prims.triangle(id);
      if (u1 + u2 > 1.0f) u1 = 1.0f - u1, u2 = 1.0f - u2;
      return p[0] + (p[1] - p[0]) * u1 + (p[2] - p[0]) * u2;
    }
    case PrimKind::kSphere: {
      const SphereData& sp = prims.sphere(id);
      return sp.center + sample_uniform_sphere({u1, u2}) * sp.radius;
    }
    case PrimKind::kQuad: {
      const QuadData& q = prims.quad(id);
      return q.p + q.e1 * u1 + q.e2 * u2;
    }
  }
  return {};
}

TestScene scaled(const TestScene& scene, float scale, Vec3 offset) {
  TestScene s{fmt::format("{} x {:g} + ({:g}, {:g}, {:g})", scene.name, scale, offset.x, offset.y,
                          offset.z),
              {}};
  const PrimitiveSet& in = scene.prims;
  const auto map = [&](Vec3 p) { return p * scale + offset; };
  for (uint32_t id = 0; id < in.size(); ++id) {
    switch (in.kind(id)) {
      case PrimKind::kTriangle: {
        const Vec3* v = in.triangle(id);
        add_triangle(s.prims, map(v[0]), map(v[1]), map(v[2]));
        break;
      }
      case PrimKind::kSphere: {
        const SphereData& d = in.sphere(id);
        s.prims.add_sphere({map(d.center), d.radius * scale}, 1);
        break;
      }
      case PrimKind::kQuad: {
        const QuadData& q = in.quad(id);
        s.prims.add_quad({map(q.p), q.e1 * scale, q.e2 * scale}, 2);
        break;
      }
    }
  }
  return s;
}

TestScene float_range_extent(uint64_t seed) {
  TestScene s = random_soup(500, seed);
  s.name = "soup with triangles near the float range";
  constexpr float kBig = 3.0e38f;
  add_triangle(s.prims, Vec3(-kBig, -kBig, -kBig), Vec3(kBig, -kBig, -kBig), Vec3(0, kBig, 0));
  add_triangle(s.prims, Vec3(-kBig, 5, 5), Vec3(kBig, 5, 5), Vec3(0, 6, kBig));
  add_triangle(s.prims, Vec3(0.2f, 0.2f, kBig), Vec3(0.8f, 0.2f, kBig), Vec3(0.5f, 0.9f, kBig));
  // Within the accepted magnitude: huge, but hit like any other.
  constexpr float kLimit = kMaxCoordinate;
  add_triangle(s.prims, Vec3(-kLimit, -kLimit, 2), Vec3(kLimit, -kLimit, 2), Vec3(0, kLimit, 2));
  s.prims.add_sphere({Vec3(0.5f, 0.5f, -0.5f * kLimit), 0.25f * kLimit}, 1);
  return s;
}

std::vector<Ray> mixed_rays(const PrimitiveSet& prims, size_t n, uint64_t seed) {
  Pcg32 rng(seed, 6);
  const Bounds3 b = prims.bounds();
  const Vec3 lo = b.lo - b.diagonal() * 0.1f, ext = b.diagonal() * 1.2f;
  // Ids of primitives with finite bounds, to start rays on and to take coordinates from.
  std::vector<uint32_t> valid;
  for (uint32_t i = 0; i < prims.size(); ++i)
    if (!prims.prim_bounds(i).empty()) valid.push_back(i);
  const auto some_point = [&] {
    return point_on(prims, valid[rng.next_bounded(uint32_t(valid.size()))], rng.next_float(),
                    rng.next_float());
  };
  const auto some_corner = [&] {  // an exact vertex / box corner coordinate source
    const Bounds3 pb = prims.prim_bounds(valid[rng.next_bounded(uint32_t(valid.size()))]);
    return rng.next_float() < 0.5f ? pb.lo : pb.hi;
  };
  std::vector<Ray> rays(n);
  for (size_t i = 0; i < n; ++i) {
    Ray& r = rays[i];
    switch (i % 5) {
      case 0:  // random origin and direction
      case 1:
        r.o = lo + ext * random_vec(rng);
        r.d = random_dir(rng);
        break;
      case 2:  // starting on a surface
        r.o = some_point();
        r.d = random_dir(rng);
        break;
      case 3: {  // a zero direction component; the origin on a plane of that axis
        r.o = lo + ext * random_vec(rng);
        r.d = random_dir(rng);
        const int axis = int(rng.next_bounded(3));
        r.d[axis] = rng.next_float() < 0.5f ? 0.0f : -0.0f;
        r.o[axis] = some_corner()[axis];
        break;
      }
      default: {  // axis-parallel, through exact vertex coordinates on the other two axes
        const int axis = int(rng.next_bounded(3));
        const Vec3 c = some_corner();
        r.o = lo + ext * random_vec(rng);
        for (int k = 0; k < 3; ++k)
          if (k != axis && rng.next_float() < 0.7f) r.o[k] = c[k];
        r.d = Vec3(0.0f);
        r.d[axis] = rng.next_float() < 0.5f ? 1.0f : -1.0f;
      }
    }
  }
  return rays;
}

}  // namespace penumbra::test

namespace penumbra::test {

std::vector<std::string> structure_names() {
  std::vector<std::string> names;
  for (const auto& info : accelerator_list())
    if (info.name != "brute") names.push_back(info.name);
  return names;
}

std::string structure_test_name(const std::string& name) {
  std::string s = name;
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

}  // namespace penumbra::test
