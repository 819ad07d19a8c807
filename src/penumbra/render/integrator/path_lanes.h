#pragma once
/// path's shading of eight paths at once, one per vector lane: the same estimator, the same
/// random numbers and the same floats as PathIntegrator's one-path-at-a-time code, with the work
/// between two traversals (the surface interaction, diffuse sampling, the area light's sample,
/// the MIS weights, the continuation) done for eight paths by one vector instruction each.
#include <cstdint>
#include <memory>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/core/lanes.h"
#include "penumbra/render/world.h"

namespace penumbra {

class PathIntegrator;
class RenderJob;

/// The lanes of one PathIntegrator. They can serve any world without instances, and do by
/// default where that was measured faster (see make): the Cornell box, interiors of diffuse
/// meshes lit by quads or triangles. A vertex of another material (glass, metal, textures) is
/// PathIntegrator::scatter's in its lane. Primitives other than static plain triangles
/// (spheres, quads, moving shapes, triangles with shading normals or uvs, emitters) take the
/// scalar surface interaction in their lane; lights other than an area light's triangle or
/// parallelogram unit (spheres, rectangles by solid angle, points, spots, the sun, environments)
/// their own sample_li; rays that leave collect the infinite lights there too. So any geometry and
/// light of such a world works.
class PathLanes {
 public:
  /// The lanes for `path` on `world`, or null: always with instances (the top level's hits
  /// carry no plain triangles' data), and unless `force`, where they were not measured faster
  /// (fewer than half of the primitives plain diffuse triangles, or a sampled light other than
  /// an area light of triangles and parallelograms: the scalar fallbacks in a lane cost a little
  /// more than alone, 3-7 % on rooms of quads and spheres or under an environment map).
  static std::unique_ptr<PathLanes> make(const PathIntegrator& path, const World& world,
                                         bool force);

  /// Renders samples [first, first + count) of every pixel of [x0, x1) x [y0, y1) and adds them
  /// to the job's film in the scalar loop's order (pixel by pixel, sample index rising), so the
  /// film gets the same bits.
  void render_tile(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
                   RayCounter& counter) const;

 private:
  PathLanes(const PathIntegrator& path, const World& world);
  struct Vertex;
  struct LightLanes;
  /// PathIntegrator::sample_light's pick of a light and unit for lane l at point p, with the
  /// light pair u: a planar unit's data for the lanes, or a scalar light sample.
  void pick_light(Vec2 u, Vec3 p, int l, LightLanes& ll) const;
  /// PathIntegrator::sample_light lane by lane: the light sample's contribution before the
  /// throughput at the lanes of `alive` (zero elsewhere), with their shadow rays traced.
  lanes::V3 light_contribution(const Vertex& vx, unsigned alive, LightLanes& ll, const Ray* ray,
                               RayCounter& counter) const;
  template <class S>
  void run(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
           RayCounter& counter) const;

  /// The units of the only light, when it is an area light of triangles and parallelograms:
  /// what AreaLight::pick and sample_li read, one array per field, for lanes that pick and sample
  /// eight units at once.
  struct PlanarUnits {
    std::vector<float> cdf, cdf_lo, inv_pmf, pmf, area;
    std::vector<float> o[3], e1[3], e2[3], n[3];
    std::vector<float> triangle;  ///< 1 for a triangle, 0 for a parallelogram
    Rgb radiance;
    bool two_sided = false;
  };

  const PathIntegrator& path_;
  const World& world_;
  std::unique_ptr<PlanarUnits> units_;  ///< null: lights are picked lane by lane
  /// Per shape: its diffuse material's albedo, one array per channel (three loads per hit
  /// straight into the lanes' buffers, where an Rgb went through the stack).
  std::vector<float> albedo_[3];
  /// Per primitive, in one word so that a hit costs one load: its shape (the low 29 bits), bit
  /// 29 a material other than an untextured diffuse one (the vertex is the scalar code's), bit
  /// 30 its shape's flip, bit 31 World::plain_triangle with a diffuse material.
  std::vector<uint32_t> prim_info_;
  static constexpr uint32_t kOther = 1u << 29, kFlip = 1u << 30, kPlain = 1u << 31,
                            kShapeMask = kOther - 1;
};

}  // namespace penumbra
