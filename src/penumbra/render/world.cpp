#include "penumbra/render/world.h"

#include <chrono>
#include <cmath>
#if defined(__x86_64__)
#include <x86intrin.h>
#endif
#include <numbers>

#include <fmt/format.h>

#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/render/light/area_light.h"
#include "penumbra/render/light/environment_light.h"
#include "penumbra/render/light/light_registry.h"
#include "penumbra/render/material/material_registry.h"

namespace penumbra {

void World::check_magnitudes(const std::string& file, const ShapeDesc& sd,
                             const PrimitiveSet& prims, uint32_t first) const {
  // A primitive whose box is empty has a NaN or infinite coordinate, or one beyond
  // kMaxCoordinate, in world space (at either end of its motion): refused here, rather than
  // left out by every structure and silently invisible.
  for (uint32_t id = first; id < prims.size(); ++id) {
    if (!prims.prim_bounds(id).empty()) continue;
    const auto vec = [](Vec3 v) { return fmt::format("({:g}, {:g}, {:g})", v.x, v.y, v.z); };
    std::string what;
    switch (prims.kind(id)) {
      case PrimKind::kTriangle: {
        const Vec3* v = prims.triangle(id);
        const Vec3* e = prims.triangle_end(id);
        what = fmt::format("triangle {} has world-space vertices {}, {}, {}",
                           prims.origin(id).local, vec(v[0]), vec(v[1]), vec(v[2]));
        if (prims.moving(id))
          what += fmt::format(" (at time 1: {}, {}, {})", vec(e[0]), vec(e[1]), vec(e[2]));
        break;
      }
      case PrimKind::kSphere: {
        const SphereData& a = prims.sphere(id);
        const SphereData& b = prims.sphere_end(id);
        what = fmt::format("the sphere has world-space centre {} and radius {:g}", vec(a.center),
                           a.radius);
        if (prims.moving(id))
          what += fmt::format(" (at time 1: {}, {:g})", vec(b.center), b.radius);
        break;
      }
      case PrimKind::kQuad: {
        const QuadData& q = prims.quad(id);
        what = fmt::format("the quad has world-space origin {} and edges {}, {}", vec(q.p),
                           vec(q.e1), vec(q.e2));
        break;
      }
    }
    throw InputError(file, sd.path,
                     fmt::format("{}: a coordinate is NaN, infinite or beyond +-{:g}, the largest "
                                 "magnitude penumbra traces exactly",
                                 what, kMaxCoordinate));
  }
}

World::World(const SceneDesc& desc, const std::string& accel_spec) {
  background_ = desc.render.background;
  // Materials by name.
  std::vector<std::string> names;
  for (const auto& m : desc.materials) {
    materials_.push_back(make_material(m.params, &desc.images));
    names.push_back(m.name);
  }
  for (const auto& l : desc.lights) lights_.push_back(make_light(l));

  // Shapes to world-space primitives.
  for (size_t s = 0; s < desc.shapes.size(); ++s) {
    const ShapeDesc& sd = desc.shapes[s];
    const auto shape = static_cast<uint32_t>(s);
    const uint32_t first = prims_.size();
    shapes_.push_back(add_shape(desc, sd, shape, names, prims_));
    if (sd.emission && !sd.emission->is_black())
      emitters_.push_back(
          {shape, first, prims_.size() - first, *sd.emission, sd.two_sided_emission});
  }
  // Instanced objects (their shapes numbered after the scene's) and the top level.
  build_instances(desc, accel_spec, names);
  bounds_ = join(prims_.bounds(), instanced_.bounds());
  // Too small a scene loses its hits to float underflow (see kMinSceneExtent).
  const Bounds3& extent = bounds_;
  if (!extent.empty()) {
    const float diagonal = length(extent.diagonal());
    if (diagonal > 0.0f && diagonal < kMinSceneExtent)
      throw InputError(desc.file, "/shapes",
                       fmt::format("the scene's extent (bounding-box diagonal) is {:g}, below "
                                   "{:g}, the smallest penumbra traces exactly: scale it up",
                                   diagonal, kMinSceneExtent));
  }

  // Area lights of the emissive shapes, then the background as a constant environment.
  first_area_light_ = lights_.size();
  for (const Emitter& e : emitters_) {
    lights_.push_back(std::make_unique<AreaLight>(*this, e));
    shapes_[e.shape].area_light = lights_.back().get();
  }
  if (!background_.is_black())
    lights_.push_back(std::make_unique<EnvironmentLight>(RgbImage{}, background_));
  for (const auto& light : lights_) {
    light->preprocess(bounds_);
    light_list_.push_back(light.get());
    if (light->kind() == LightKind::kInfinite) infinite_lights_.push_back(light.get());
  }

  accel_ = make_accelerator(accel_spec);
  accel_->build(prims_);
}

World::ShapeInfo World::add_shape(const SceneDesc& desc, const ShapeDesc& sd, uint32_t shape,
                                  const std::vector<std::string>& names, PrimitiveSet& prims) {
  ShapeInfo info;
  for (size_t m = 0; m < names.size(); ++m)
    if (names[m] == sd.material) info.material = materials_[m].get();
  if (!info.material)
    throw InputError(desc.file, sd.path + "/material", "unknown material '" + sd.material + "'");
  info.emission = sd.emission;
  info.two_sided = sd.two_sided_emission;
  info.flip_normal = sd.to_world.swaps_handedness();
  const uint32_t first = prims.size();
  // A moving shape (to_world_end set) goes from to_world at time 0 to to_world_end at time 1.
  if (sd.to_world_end && sd.emission && !sd.emission->is_black())
    throw InputError(desc.file, sd.path + "/transform_end", "a moving shape cannot be emissive");
  const Transform& end = sd.to_world_end ? *sd.to_world_end : sd.to_world;
  if (const auto* sphere = std::get_if<SphereData>(&sd.geometry)) {
    const auto world_sphere = [&](const Transform& m) {
      return SphereData{m.point(sphere->center), sphere->radius * length(m.vector({1, 0, 0}))};
    };
    info.flip_normal = false;  // a sphere's front is always outside
    if (sd.to_world_end)
      prims.add_moving_sphere(world_sphere(sd.to_world), world_sphere(end), shape);
    else
      prims.add_sphere(world_sphere(sd.to_world), shape);
  } else if (const auto* quad = std::get_if<QuadData>(&sd.geometry)) {
    const auto world_quad = [&](const Transform& m) {
      return QuadData{m.point(quad->p), m.vector(quad->e1), m.vector(quad->e2)};
    };
    if (sd.to_world_end)
      prims.add_moving_quad(world_quad(sd.to_world), world_quad(end), shape);
    else
      prims.add_quad(world_quad(sd.to_world), shape);
  } else {
    const auto& mesh = std::get<TriangleMesh>(sd.geometry);
    if (sd.to_world_end)
      prims.add_moving_mesh(mesh, sd.to_world, end, shape);
    else
      prims.add_mesh(mesh, sd.to_world, shape);
    if (!mesh.normals.empty() || !mesh.uvs.empty()) {
      TriangleMesh attrs;
      attrs.indices = mesh.indices;
      attrs.uvs = mesh.uvs;
      for (const Vec3& n : mesh.normals) attrs.normals.push_back(normalize(sd.to_world.normal(n)));
      info.mesh = static_cast<int>(meshes_.size());
      meshes_.push_back(std::move(attrs));
      if (sd.to_world_end && !mesh.normals.empty()) {
        // A moving mesh's shading normals at time 1 too (interpolated at the hit's time).
        TriangleMesh ends;
        for (const Vec3& n : mesh.normals) ends.normals.push_back(normalize(end.normal(n)));
        info.mesh_end = static_cast<int>(meshes_.size());
        meshes_.push_back(std::move(ends));
      }
    }
  }
  check_magnitudes(desc.file, sd, prims, first);
  return info;
}

void World::build_instances(const SceneDesc& desc, const std::string& accel_spec,
                            const std::vector<std::string>& names) {
  if (desc.instances.empty()) return;  // objects without instances cost nothing
  // Each object's shapes in object space, numbered after the scene's shapes, under one
  // bottom-level structure of the scene's kind, built once.
  std::vector<InstancedObject> objects;
  for (const ObjectDesc& od : desc.objects) {
    auto prims = std::make_unique<PrimitiveSet>();
    for (const ShapeDesc& sd : od.shapes) {
      if (sd.to_world_end)
        throw InputError(desc.file, sd.path + "/transform_end", "shapes of an object cannot move");
      if (sd.emission && !sd.emission->is_black())
        throw InputError(desc.file, sd.path + "/emission",
                         "shapes of an object cannot be emissive (area lights in instances are "
                         "not supported)");
      const auto shape = static_cast<uint32_t>(shapes_.size());
      shapes_.push_back(add_shape(desc, sd, shape, names, *prims));
    }
    auto accel = make_accelerator(accel_spec);
    accel->build(*prims);
    objects.push_back({accel.get(), prims.get()});
    object_prims_.push_back(std::move(prims));
    object_accels_.push_back(std::move(accel));
  }
  std::vector<Instance> instances;
  instances.reserve(desc.instances.size());
  for (const InstanceDesc& id : desc.instances) {
    if (id.object >= objects.size())
      throw InputError(desc.file, id.path + "/object", "unknown object");
    // The instance's world box must stay within the magnitudes traced exactly.
    const Bounds3 b = instance_bounds(id.to_world, objects[id.object].prims->bounds());
    const Vec3 m = max(abs(b.lo), abs(b.hi));
    if (!b.empty() && !(std::max(m.x, std::max(m.y, m.z)) <= kMaxCoordinate))
      throw InputError(desc.file, id.path + "/transform",
                       fmt::format("the instance reaches a world coordinate beyond +-{:g}, the "
                                   "largest magnitude penumbra traces exactly",
                                   kMaxCoordinate));
    instances.push_back({id.object, id.to_world});
  }
  instanced_.build(std::move(objects), std::move(instances));
}

size_t World::geometry_bytes() const {
  size_t bytes = prims_.bytes() + accel_->stats().bytes;
  for (const auto& p : object_prims_) bytes += p->bytes();
  for (const auto& a : object_accels_) bytes += a->stats().bytes;
  return bytes + instanced_.stats().bytes;
}

Rgb World::escaped(const Ray& ray) const {
  Rgb l;
  for (const Light* light : infinite_lights_) l += light->le(ray);
  return l;
}

Vec3 World::area_normal(uint32_t prim) const {
  // Emitters never move (the loader rejects moving emissive shapes): the time-0 geometry.
  Vec3 n;
  if (prims_.kind(prim) == PrimKind::kTriangle) {
    const Vec3* p = prims_.triangle(prim);
    n = cross(p[1] - p[0], p[2] - p[0]) * 0.5f;
  } else if (prims_.kind(prim) == PrimKind::kQuad) {
    n = cross(prims_.quad(prim).e1, prims_.quad(prim).e2);
  }
  return shapes_[prims_.origin(prim).shape].flip_normal ? -n : n;
}

uint64_t tick_count() {
#if defined(__x86_64__)
  return __rdtsc();
#else
  return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::steady_clock::now().time_since_epoch())
                      .count());
#endif
}

namespace {
/// One ray in kTimedEvery is timed and counts for kTimedEvery: reading the clock around every
/// ray would cost a few percent of a cheap traversal itself. A prime stride does not fall in step
/// with the rays of a path (camera, shadow, continuation, ...).
constexpr uint64_t kTimedEvery = 17;
}  // namespace

bool World::closest_hit(const Ray& ray, Hit& hit) const {
  const bool found = accel_->intersect(ray, hit);
  if (!has_instances()) return found;  // one predictable branch: the single-level path as before
  // Instances on (tmin, the scene's own closest hit): only a strictly closer one replaces it.
  Ray rest = ray;
  if (found) rest.tmax = hit.t;
  Hit h;
  if (!instanced_.intersect(rest, h)) return found;
  hit = h;
  return true;
}

bool World::closest_hit_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  const bool found = accel_->intersect_cost(ray, hit, cost);
  if (!has_instances()) return found;
  Ray rest = ray;
  if (found) rest.tmax = hit.t;
  Hit h;
  if (!instanced_.intersect_cost(rest, h, cost)) return found;
  hit = h;
  return true;
}

bool World::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  return accel_->occluded_cost(ray, cost) ||
         (has_instances() && instanced_.occluded_cost(ray, cost));
}

bool World::closest_hit(const Ray& ray, Hit& hit, RayCounter& counter) const {
  if (++counter.rays % kTimedEvery != 0) return closest_hit(ray, hit);
  const uint64_t t0 = tick_count();
  const bool found = closest_hit(ray, hit);
  counter.traversal_ticks += (tick_count() - t0) * kTimedEvery;
  return found;
}

bool World::intersect(const Ray& ray, SurfaceInteraction& si, RayCounter& counter) const {
  Hit hit;
  if (!closest_hit(ray, hit, counter)) return false;
  interaction(ray, hit, si);
  return true;
}

bool World::occluded(const Ray& ray, RayCounter& counter) const {
  const auto blocked = [&] {
    return accel_->occluded(ray) || (has_instances() && instanced_.occluded(ray));
  };
  if (++counter.rays % kTimedEvery != 0) return blocked();
  const uint64_t t0 = tick_count();
  const bool b = blocked();
  counter.traversal_ticks += (tick_count() - t0) * kTimedEvery;
  return b;
}

void World::interaction(const Ray& ray, const Hit& hit, SurfaceInteraction& si) const {
  if (hit.instance == kNoInstance) {
    local_interaction(prims_, ray, hit, si);
    si.instance = kNoInstance;
    return;
  }
  // A hit in an instance: the interaction in object space, along the ray carried there as the
  // top level carried it (the same t reaches the same point), then mapped to world space.
  const Instance& inst = instanced_.instances()[hit.instance];
  const Transform& m = inst.to_world;
  const Transform to_object = m.inverted();
  Ray local = ray;
  local.o = to_object.point(ray.o);
  local.d = to_object.vector(ray.d);
  local_interaction(*object_prims_[inst.object], local, hit, si);
  si.instance = hit.instance;
  const Vec3 p = si.p, e = si.p_error;
  si.p = m.point(p);
  // The error of p: the object-space error carried by |M| plus the rounding of the map itself,
  // and of the map back into object space that a ray leaving p goes through (pbrt-v3 section
  // 3.9.5, conservatively: gamma(3) of each magnitude).
  const auto& a = m.matrix().m;
  const auto abs_linear = [&](Vec3 v) {
    const auto row = [&](int i) {
      return float(std::abs(a[i][0]) * v.x + std::abs(a[i][1]) * v.y + std::abs(a[i][2]) * v.z);
    };
    return Vec3(row(0), row(1), row(2));
  };
  si.p_error = abs_linear(e + abs(p) * gamma(3)) * (1.0f + gamma(3)) + abs(si.p) * gamma(3);
  // Normals by the inverse transpose, which keeps them on the same side of the surface (a
  // mirroring transform included); the shading normal faces the geometric one again.
  const Vec3 ng = si.ng, ns = si.ns;
  si.ng = normalize(m.normal(ng));
  si.ns = ns == ng ? si.ng : face_forward(normalize(m.normal(ns)), si.ng);
  si.wo = normalize(-ray.d);
  orthonormal_basis(si.ns, si.ss, si.ts);
}

void World::local_interaction(const PrimitiveSet& prims, const Ray& ray, const Hit& hit,
                              SurfaceInteraction& si) const {
  const uint32_t id = hit.prim;
  const PrimOrigin& origin = prims.origin(id);
  const ShapeInfo& shape = shapes_[origin.shape];
  // Computed in locals and stored once at the end: written into si as they came, the frame was
  // read back from memory for the next step (si may alias the mesh arrays read in between), and
  // its fields went out in narrow stores that the caller's wider loads could not be forwarded
  // from.
  Vec3 p, p_error, ng;
  Vec2 uv = {hit.u, hit.v};
  const Vec3 wo = normalize(-ray.d);
  // The primitive's geometry at the ray's time (its only geometry when it is static).
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      // A static triangle's vertices are read in place: copying them through triangle_at's
      // out-parameter cost a store-to-load forwarding stall per hit.
      Vec3 moved[3];
      const Vec3* v = prims.triangle(id);
      if (prims.moving(id)) prims.triangle_at(id, ray.time, moved), v = moved;
      const float b0 = 1.0f - hit.u - hit.v;
      p = v[0] * b0 + v[1] * hit.u + v[2] * hit.v;
      // Error of a barycentric combination (pbrt-v3 section 3.9.4).
      p_error = (abs(v[0] * b0) + abs(v[1] * hit.u) + abs(v[2] * hit.v)) * gamma(7);
      ng = normalize(cross(v[1] - v[0], v[2] - v[0]));
      break;
    }
    case PrimKind::kSphere: {
      const SphereData sp = prims.sphere_at(id, ray.time);
      const Vec3 d = ray.at(hit.t) - sp.center;
      // Reproject onto the surface; the error is then a few ulps of p (pbrt-v3 section 3.9.4).
      p = sp.center + d * (sp.radius / length(d));
      p_error = abs(p) * gamma(5);
      ng = normalize(p - sp.center);
      const float phi = std::atan2(ng.y, ng.x);
      uv = {phi * 0.5f * std::numbers::inv_pi_v<float> + 0.5f,
            std::acos(std::clamp(ng.z, -1.0f, 1.0f)) * std::numbers::inv_pi_v<float>};
      break;
    }
    case PrimKind::kQuad: {
      const QuadData q = prims.quad_at(id, ray.time);
      p = q.p + q.e1 * hit.u + q.e2 * hit.v;
      p_error = (abs(q.p) + abs(q.e1 * hit.u) + abs(q.e2 * hit.v)) * gamma(6);
      ng = normalize(cross(q.e1, q.e2));
      break;
    }
  }
  if (shape.flip_normal) ng = -ng;
  Vec3 ns = ng;
  if (shape.mesh >= 0) {
    // Interpolated shading normal and uvs of the triangle's vertices.
    const TriangleMesh& m = meshes_[size_t(shape.mesh)];
    const uint32_t* idx = &m.indices[3 * size_t(origin.local)];
    const float b0 = 1.0f - hit.u - hit.v;
    if (!m.normals.empty()) {
      Vec3 n = m.normals[idx[0]] * b0 + m.normals[idx[1]] * hit.u + m.normals[idx[2]] * hit.v;
      if (shape.mesh_end >= 0) {  // a moving mesh: the normal interpolated to the ray's time
        const std::vector<Vec3>& e = meshes_[size_t(shape.mesh_end)].normals;
        const Vec3 n1 = e[idx[0]] * b0 + e[idx[1]] * hit.u + e[idx[2]] * hit.v;
        n = motion_lerp(motion_time(ray.time), n, n1);
      }
      if (dot(n, n) > 0.0f && is_finite(n)) ns = face_forward(normalize(n), ng);
    }
    if (!m.uvs.empty())
      uv = m.uvs[idx[0]] * b0 + m.uvs[idx[1]] * hit.u + m.uvs[idx[2]] * hit.v;
  }
  Vec3 ss, ts;
  orthonormal_basis(ns, ss, ts);
  si.p = p;
  si.p_error = p_error;
  si.ng = ng;
  si.ns = ns;
  si.ss = ss;
  si.ts = ts;
  si.uv = uv;
  si.wo = wo;
  si.t = hit.t;
  si.prim = id;
  si.shape = origin.shape;
  si.material = shape.material;
  // Emission leaves the front side (the geometric normal's) unless the emitter is two-sided.
  si.area_light = shape.area_light;
  si.emitted = shape.area_light ? shape.area_light->l(LightPoint{p, ng, id}, wo) : Rgb{};
}

}  // namespace penumbra
