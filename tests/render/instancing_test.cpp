// Instanced scenes in the World (objects placed by instances under a two-level structure) against
// their flattened twins (every instance's shapes transformed into world space): the same hits,
// normals, occlusion and images; the memory of many copies; instances through every structure.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "penumbra/accel/registry.h"
#include "penumbra/core/rng.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// Floor, light and background, plus `objects` and `shapes` JSON (without brackets).
std::string scene_text(const std::string& objects, const std::string& shapes,
                       const std::string& integrator = "whitted") {
  return R"({
  "camera": {"type": "pinhole", "position": [0, 3, -9], "look_at": [0, 0.8, 0], "up": [0, 1, 0], "vfov": 45},
  "render": {"resolution": [64, 48], "spp": 2, "integrator": ")" +
         integrator + R"(", "background": [0.2, 0.25, 0.3]},
  "materials": {"clay": {"type": "diffuse", "albedo": [0.8, 0.7, 0.6]},
                "floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
                "metal": {"type": "mirror", "reflectance": [0.8, 0.8, 0.8]}},
  "lights": [{"type": "point", "position": [2, 6, -4], "intensity": [60, 60, 60]}],
  "objects": {)" +
         objects +
         R"(},
  "shapes": [
    {"type": "quad", "origin": [-6, 0, -6], "edge1": [0, 0, 12], "edge2": [12, 0, 0], "material": "floor"})" +
         (shapes.empty() ? "" : ",\n" + shapes) + "]}";
}

/// Two objects: a bunny and a bent quad with shading normals and uvs; the same with a sphere.
const std::string kThing = R"("thing": {"shapes": [
    {"type": "obj", "file": "scenes/meshes/bunny.obj", "material": "clay",
     "transform": [{"scale": 0.1}]},
    {"type": "mesh", "material": "metal", "positions": [[-1, 0, 1], [1, 0, 1], [1, 1.5, 1.3], [-1, 1.5, 1]],
     "indices": [[0, 1, 2], [0, 2, 3]], "normals": [[0, 0.3, -1], [0.3, 0, -1], [0, 0, -1], [-0.3, 0.2, -1]],
     "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]]}]},
  "ball_thing": {"shapes": [
    {"type": "obj", "file": "scenes/meshes/bunny.obj", "material": "clay",
     "transform": [{"scale": 0.1}]},
    {"type": "sphere", "center": [-1.2, 0.5, -0.3], "radius": 0.45, "material": "clay"}]})";

/// Instances: translated, rotated and uniformly scaled, non-uniformly scaled, mirrored. (The
/// flattened twin cannot express a sphere under a non-uniform scale, an ellipsoid: that one
/// places the object without the sphere.)
const std::string kInstances = R"(
    {"type": "instance", "object": "ball_thing", "transform": [{"translate": [-3, 0, 0]}]},
    {"type": "instance", "object": "thing", "transform": [{"scale": 0.8}, {"rotate": {"angle": 150, "axis": [0, 1, 0]}}, {"translate": [0.5, 0, 1]}]},
    {"type": "instance", "object": "ball_thing", "transform": [{"scale": 0.8}, {"rotate": {"angle": -70, "axis": [0.2, 1, 0]}}, {"translate": [0.5, 0.3, 3]}]},
    {"type": "instance", "object": "thing", "transform": [{"scale": [1.4, 0.7, 1]}, {"rotate": {"angle": 20, "axis": [1, 0, 0.2]}}, {"translate": [3, 0.8, 0]}]},
    {"type": "instance", "object": "ball_thing", "transform": [{"scale": [-1, 1, 1]}, {"rotate": {"angle": -40, "axis": [0, 1, 0]}}, {"translate": [0, 0, -3]}]},
    {"type": "instance", "object": "thing", "transform": [{"scale": [1, 1, -1.2]}, {"translate": [-2, 0, 3]}]})";

/// The flattened twin's shape index of an instanced World's hit on shape `shape` of `instance`
/// (flattened() appends each instance's object shapes in instance order).
uint32_t flat_shape(const SceneDesc& desc, uint32_t instance, uint32_t shape) {
  if (instance == kNoInstance) return shape;
  size_t before = desc.shapes.size(), object_first = desc.shapes.size();
  for (uint32_t i = 0; i < instance; ++i)
    before += desc.objects[desc.instances[i].object].shapes.size();
  for (uint32_t o = 0; o < desc.instances[instance].object; ++o)
    object_first += desc.objects[o].shapes.size();
  return uint32_t(before + (shape - object_first));
}

/// `desc` with every instance replaced by its object's shapes transformed into world space, in
/// instance order.
SceneDesc flattened(const SceneDesc& desc) {
  SceneDesc flat = desc;
  flat.objects.clear();
  flat.instances.clear();
  for (const InstanceDesc& inst : desc.instances)
    for (ShapeDesc s : desc.objects[inst.object].shapes) {
      s.to_world = inst.to_world * s.to_world;
      flat.shapes.push_back(std::move(s));
    }
  return flat;
}

/// Random rays into the scene's bounds from around it.
std::vector<Ray> scene_rays(const Bounds3& b, size_t n, uint64_t seed) {
  Pcg32 rng(seed, 9);
  const auto in = [&](const Bounds3& box) {
    return box.lo + box.diagonal() * Vec3(rng.next_float(), rng.next_float(), rng.next_float());
  };
  const Bounds3 around(b.lo - b.diagonal() * 0.3f, b.hi + b.diagonal() * 0.3f);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    r.o = in(around);
    r.d = in(b)-r.o;
    if (rng.next_float() < 0.5f) r.d = r.d * (0.1f + 3.0f * rng.next_float());  // any length
  }
  return rays;
}

/// The index within its shape of the primitive of `si`, in the scene's set or its instance's
/// object's.
uint32_t local_prim(const World& world, const SurfaceInteraction& si) {
  if (si.instance == kNoInstance) return world.primitives().origin(si.prim).local;
  const InstanceBvh& top = world.instances();
  return top.objects()[top.instances()[si.instance].object].prims->origin(si.prim).local;
}

TEST(Instancing, WorldHitsMatchTheFlattenedScene) {
  const SceneDesc desc = test::scene_from_text(scene_text(kThing, kInstances));
  ASSERT_EQ(desc.instances.size(), 6u);
  const World inst(desc, "bvh");
  const World flat(flattened(desc), "bvh");
  ASSERT_TRUE(inst.has_instances());
  EXPECT_FALSE(flat.has_instances());
  // The instanced bounds contain the flattened ones (they bound each instance's object box, not
  // its primitives, so a rotated instance's box is larger).
  const Bounds3 ib = inst.bounds(), fb = flat.bounds();
  EXPECT_TRUE(ib.contains(fb.lo) && ib.contains(fb.hi));
  EXPECT_LT(length(ib.diagonal()), 1.1f * length(fb.diagonal()));
  RayCounter counter;
  size_t hits = 0, mismatched = 0, instanced_hits = 0;
  const std::vector<Ray> rays = scene_rays(flat.bounds(), 30'000, 3);
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    SurfaceInteraction a, b;
    const bool fa = inst.intersect(ray, a, counter), fb = flat.intersect(ray, b, counter);
    EXPECT_EQ(inst.occluded(ray, counter), fa) << "ray " << i;
    if (fa != fb) {  // a ray grazing an edge
      ++mismatched;
      continue;
    }
    if (!fa) continue;
    ++hits;
    // Which shape and primitive.
    if (flat_shape(desc, a.instance, a.shape) != b.shape ||
        local_prim(inst, a) != flat.primitives().origin(b.prim).local) {
      ++mismatched;
      continue;
    }
    if (a.instance != kNoInstance) ++instanced_hits;
    const float scale = std::max(1.0f, length(ray.d) * b.t);
    EXPECT_NEAR(a.t, b.t, 2e-5f * std::max(1.0f, b.t)) << "ray " << i;
    EXPECT_LT(length(a.p - b.p), 1e-4f * scale) << "ray " << i;
    // The error bound covers the difference between the two computed points.
    const Vec3 d = abs(a.p - b.p);
    EXPECT_TRUE(d.x <= a.p_error.x + b.p_error.x + 1e-5f * scale &&
                d.y <= a.p_error.y + b.p_error.y + 1e-5f * scale &&
                d.z <= a.p_error.z + b.p_error.z + 1e-5f * scale)
        << "ray " << i;
    // Normals: the same side (mirrored instances included), the same direction.
    EXPECT_GT(dot(a.ng, b.ng), 0.9999f) << "ray " << i << " shape " << b.shape;
    EXPECT_GT(dot(a.ns, b.ns), 0.999f) << "ray " << i << " shape " << b.shape;
    EXPECT_NEAR(length(a.ng), 1.0f, 1e-5f);
    EXPECT_NEAR(dot(a.ss, a.ns), 0.0f, 1e-4f);
    EXPECT_NEAR(length(a.wo - b.wo), 0.0f, 1e-6f);
    if (flat.primitives().kind(b.prim) != PrimKind::kSphere) {  // spheres' uv: object space
      // Barycentrics of the bunny's small triangles (0.01 across) move with the rounding of
      // the object-space ray (1e-7 of the scene's size), relative to the triangle's size.
      EXPECT_NEAR(a.uv.x, b.uv.x, 1e-3f) << "ray " << i;
      EXPECT_NEAR(a.uv.y, b.uv.y, 1e-3f) << "ray " << i;
    }
  }
  EXPECT_GT(instanced_hits, rays.size() / 10);
  EXPECT_LE(mismatched, rays.size() / 1000);
}

TEST(Instancing, MirroredInstanceNormalsFaceOutward) {
  // A sphere mirrored by the instance: its geometric normal still points out of it, towards a
  // ray arriving from outside.
  const SceneDesc desc = test::scene_from_text(scene_text(
      R"("ball": {"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "clay"},
                             {"type": "mesh", "material": "clay", "positions": [[0, 0, -2], [1, 0, -2], [0, 1, -2]], "indices": [[0, 1, 2]]}]})",
      R"({"type": "instance", "object": "ball", "transform": [{"scale": [-1, 2, 1]}, {"translate": [0, 3, 0]}]})"));
  const World world(desc, "bvh");
  RayCounter counter;
  SurfaceInteraction si;
  Ray ray{{0, 3, -10}, {0, 0, 1}};
  ray.o.x = -0.3f, ray.o.y = 3.2f;
  ASSERT_TRUE(world.intersect(ray, si, counter));
  EXPECT_EQ(si.instance, 0u);
  // The triangle at z = -2 first: wound counter-clockwise seen from -z in object space, its front
  // normal is -z there; the mirror turns the winding over and the inverse transpose keeps the
  // normal the flattened twin has.
  const World flat(flattened(desc), "bvh");
  SurfaceInteraction fs;
  ASSERT_TRUE(flat.intersect(ray, fs, counter));
  EXPECT_GT(dot(si.ng, fs.ng), 0.9999f);
  ray.o.x = -0.5f, ray.o.y = 4.5f;  // misses the triangle, hits the ellipsoid
  ASSERT_TRUE(world.intersect(ray, si, counter));
  EXPECT_LT(dot(si.ng, ray.d), 0.0f);
  EXPECT_NEAR(si.p.z, -std::sqrt(1.0f - 0.25f - 0.5625f), 1e-5f);
}

TEST(Instancing, ImagesMatchTheFlattenedScene) {
  // The surfaces differ by rounding only. Whitted's rays are deterministic given the pixel
  // sample, so a value changes only where a camera, shadow or mirror ray grazes an edge: all but
  // a few agree to 1e-4. A path's bounce directions follow the shading frame continuously, so
  // every path moves a little, and the rare path that crosses an edge differently takes another
  // route (the same expectation, another sample): the means agree to the noise of those few
  // samples, bounded here by 1 % of the image's sum.
  for (const char* integrator : {"whitted", "path"}) {
    SceneDesc desc = test::scene_from_text(scene_text(kThing, kInstances, integrator));
    desc.render.spp = 4;
    const RgbImage a = test::render_desc(desc), b = test::render_desc(flattened(desc));
    double diff = 0, sum = 0;
    int differing = 0;
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x)
        for (int c = 0; c < 3; ++c) {
          const double d = std::abs(double(a.at(x, y)[c]) - b.at(x, y)[c]);
          diff += d, sum += b.at(x, y)[c];
          differing += d > 1e-4 * std::max(1.0, double(b.at(x, y)[c]));
        }
    std::printf("%s: mean relative difference %.2e, %d of %d values differ\n", integrator,
                diff / sum, differing, a.width() * a.height() * 3);
    EXPECT_GT(sum, 0.0) << integrator;
    if (std::string(integrator) == "whitted") {
      EXPECT_LT(diff, 1e-4 * sum);
      EXPECT_LE(differing, a.width() * a.height() * 3 / 50);
    } else {
      EXPECT_LT(diff, 1e-2 * sum);
    }
  }
}

TEST(Instancing, EveryStructureAsTheBottomLevelGivesTheSameHits) {
  const SceneDesc desc = test::scene_from_text(scene_text(kThing, kInstances));
  const World reference(desc, "brute");
  const std::vector<Ray> rays = scene_rays(reference.bounds(), 4000, 4);
  std::vector<Hit> ref(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) reference.closest_hit(rays[i], ref[i]);
  for (const AccelInfo& info : accelerator_list()) {
    const World world(desc, info.name);
    size_t errors = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      Hit h;
      const bool found = world.closest_hit(rays[i], h);
      errors +=
          found != ref[i].valid() ||
          (found && (h.t != ref[i].t || h.prim != ref[i].prim || h.instance != ref[i].instance));
    }
    EXPECT_LE(errors, rays.size() / 1000) << info.name;
  }
}

/// A UV sphere mesh of 2 * rings * sides triangles.
TriangleMesh ball(int rings, int sides) {
  TriangleMesh m;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const float th = std::numbers::pi_v<float> * float(i) / float(rings);
      const float ph = 2 * std::numbers::pi_v<float> * float(j) / float(sides);
      m.positions.push_back(
          {std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const uint32_t a = uint32_t(i * sides + j), b = uint32_t(i * sides + (j + 1) % sides);
      m.indices.insert(m.indices.end(),
                       {a, a + uint32_t(sides), b, b, a + uint32_t(sides), b + uint32_t(sides)});
    }
  return m;
}

TEST(Instancing, ThousandCopiesCostTheMemoryOfOne) {
  SceneDesc desc = test::scene_from_text(scene_text("", ""));
  ObjectDesc object;
  object.name = "ball";
  ShapeDesc shape;
  shape.geometry = ball(8, 8);  // 128 triangles
  shape.material = "clay";
  object.shapes.push_back(shape);
  desc.objects.push_back(object);
  for (int i = 0; i < 1000; ++i) {
    InstanceDesc inst;
    inst.to_world = translate({float(i % 10) * 3, float((i / 10) % 10) * 3, float(i / 100) * 3}) *
                    rotate(float(i) * 7.0f, {0.3f, 1, 0.1f});
    desc.instances.push_back(inst);
  }
  const World inst(desc, "bvh");
  const World flat(flattened(desc), "bvh");
  EXPECT_EQ(flat.primitives().size(), 1000u * 128u + 1u);
  EXPECT_EQ(inst.primitives().size(), 1u);  // the floor; the ball's triangles live in its object
  const double ratio = double(inst.geometry_bytes()) / double(flat.geometry_bytes());
  RecordProperty("instanced_bytes", std::to_string(inst.geometry_bytes()));
  RecordProperty("flattened_bytes", std::to_string(flat.geometry_bytes()));
  std::printf("1000 instances of 128 triangles: %zu bytes instanced, %zu flattened (%.2f%%)\n",
              inst.geometry_bytes(), flat.geometry_bytes(), 100 * ratio);
  EXPECT_LT(ratio, 0.05);
  // And they are there: a ray down the first column hits ten balls' worth of instance.
  RayCounter counter;
  SurfaceInteraction si;
  ASSERT_TRUE(inst.intersect(Ray{{0, -50, 0}, {0, 1, 0}}, si, counter));
  EXPECT_NE(si.instance, kNoInstance);
}

TEST(Instancing, SingleLevelScenesAreUnchanged) {
  const SceneDesc desc = test::scene_from_text(scene_text(kThing, ""));
  const World world(desc, "bvh");
  EXPECT_FALSE(world.has_instances());  // an object nobody places costs nothing
  EXPECT_EQ(world.geometry_bytes(), world.primitives().bytes() + world.accelerator().stats().bytes);
}

}  // namespace
}  // namespace penumbra
