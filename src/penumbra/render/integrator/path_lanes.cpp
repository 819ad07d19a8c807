#include "penumbra/render/integrator/path_lanes.h"

#include <cmath>
#include <numbers>
#include <typeinfo>

#include "penumbra/core/lanes.h"
#include "penumbra/render/integrator/path_integrator.h"
#include "penumbra/render/light/area_light.h"
#include "penumbra/render/material/diffuse_material.h"
#include "penumbra/render/render_job.h"
#include "penumbra/render/sampler/sobol_sampler.h"
#include "penumbra/render/sampling.h"

namespace penumbra {

namespace {

using lanes::F8;
using lanes::I8;
using lanes::kWidth;
using lanes::splat;
using lanes::V3;

constexpr float kInvPi = std::numbers::inv_pi_v<float>;
/// Samples in flight from the oldest unfinished one: a finished sample waits in this window
/// until every sample before it is done, then goes to the film in order. A path longer than the
/// window's worth of others only idles the lanes for a while.
constexpr int kWindow = 256;

/// Calls f(i) for each set bit i of m.
template <class F>
void for_lanes(unsigned m, F&& f) {
  for (; m; m &= m - 1) f(__builtin_ctz(m));
}

/// The lanes of bit mask m as a vector mask.
I8 mask_of(unsigned m) {
  const I8 bit = {1, 2, 4, 8, 16, 32, 64, 128};
  return (bit & int32_t(m)) != 0;
}

I8 is_black(const V3& c) {
  return (c.x == 0.0f) & (c.y == 0.0f) & (c.z == 0.0f);
}

Rgb rgb(const V3& v, int i) {
  return {v.x[i], v.y[i], v.z[i]};
}
void set_rgb(V3& v, int i, Rgb c) {
  v.x[i] = c.r, v.y[i] = c.g, v.z[i] = c.b;
}

/// sample_cosine_hemisphere lane by lane: the concentric map with sin_cos_quarter's polynomials.
V3 cosine_hemisphere(F8 ux, F8 uy) {
  constexpr float kPi4 = std::numbers::pi_v<float> / 4.0f;
  const F8 ox = 2.0f * ux - 1.0f, oy = 2.0f * uy - 1.0f;
  const I8 centre = (ox == 0.0f) & (oy == 0.0f);
  const I8 x_major = lanes::abs(ox) > lanes::abs(oy);
  const F8 r = x_major ? ox : oy, q = x_major ? oy : ox;
  const F8 a = kPi4 * (q / r);
  const F8 a2 = a * a;
  const F8 s =
      a *
      (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 + a2 * (1.0f / 362880)))));
  const F8 c =
      1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 +
                                                   a2 * (1.0f / 40320 + a2 * (-1.0f / 3628800)))));
  const F8 rc = r * c, rs = r * s;
  const F8 dx = centre ? splat(0.0f) : (x_major ? rc : rs);
  const F8 dy = centre ? splat(0.0f) : (x_major ? rs : rc);
  const F8 z = lanes::sqrt(lanes::max(splat(0.0f), 1.0f - dx * dx - dy * dy));
  return {dx, dy, z};
}

/// power_heuristic(1, f_pdf, 1, g_pdf) lane by lane.
F8 power_heuristic(F8 f, F8 g) {
  const F8 ff = f * f, sum = ff + g * g;
  const F8 w = sum > 0.0f ? ff / sum : splat(0.0f);
  return lanes::abs(ff) == std::numeric_limits<float>::infinity() ? splat(1.0f) : w;
}

}  // namespace

std::unique_ptr<PathLanes> PathLanes::make(const PathIntegrator& path, const World& world) {
  if (world.has_instances() || !world.infinite_lights().empty()) return nullptr;
  for (size_t s = 0; s < world.shape_count(); ++s) {
    const Material& m = world.shape_material(uint32_t(s));
    if (typeid(m) != typeid(DiffuseMaterial) || m.textured()) return nullptr;
  }
  for (const Light* light : path.light_sampler_.lights())
    if (!dynamic_cast<const AreaLight*>(light)) return nullptr;
  return std::unique_ptr<PathLanes>(new PathLanes(path, world));
}

PathLanes::PathLanes(const PathIntegrator& path, const World& world) : path_(path), world_(world) {
  for (size_t s = 0; s < world.shape_count(); ++s)
    albedo_.push_back(world.shape_material(uint32_t(s)).albedo());
  const PrimitiveSet& prims = world.primitives();
  plain_.resize(prims.size());
  for (uint32_t id = 0; id < prims.size(); ++id)
    plain_[id] = uint8_t((world.plain_triangle(id) ? 1 : 0) |
                         (world.shape_flips_normal(prims.origin(id).shape) ? 2 : 0));
}

void PathLanes::render_tile(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
                            RayCounter& counter) const {
  // As PathIntegrator::li: one type test buys inlined sampler calls.
  if (typeid(*job.sampler) == typeid(SobolSampler))
    run<SobolSampler>(job, x0, y0, x1, y1, first, count, counter);
  else
    run<Sampler>(job, x0, y0, x1, y1, first, count, counter);
}

template <class S>
void PathLanes::run(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
                    RayCounter& counter) const {
  const PathIntegrator& path = path_;
  const PrimitiveSet& prims = world_.primitives();
  const LightSampler& light_sampler = path.light_sampler_;
  const bool nee = !light_sampler.lights().empty();
  const bool mis = path.strategy_ == PathIntegrator::Strategy::kMis;
  Film& film = *job.film;
  const int width = x1 - x0;
  const int64_t total = int64_t(width) * (y1 - y0) * count;

  // Per lane: a sampler, the path's ray and state.
  std::unique_ptr<Sampler> owned[kWidth];
  S* sampler[kWidth];
  for (int l = 0; l < kWidth; ++l)
    owned[l] = job.sampler->clone(), sampler[l] = static_cast<S*>(owned[l].get());
  Ray ray[kWidth];
  V3 beta{}, radiance{}, from{};
  F8 bsdf_pdf{};
  I8 specular{}, depth{};
  int64_t ordinal[kWidth] = {};
  unsigned active = 0;
  // The samples in flight, by ordinal modulo kWindow.
  struct Pending {
    Rgb l;
    float weight = 0;
    int x = 0, y = 0;
    bool done = false;
  };
  std::vector<Pending> window(kWindow);
  int64_t next = 0, flushed = 0;
  // Per-step lane values, declared once per tile: set lane by lane where a lane needs them and
  // left from earlier steps elsewhere (idle lanes compute on old values that nothing reads).
  // Declared in the loop, their zero-initialisation was a memset per step: perf put 11 % of the
  // lanes' own time on it.
  Hit hit[kWidth];
  V3 v0{}, v1{splat(1.0f), {}, {}}, v2{{}, splat(1.0f), {}}, dir{{}, {}, splat(1.0f)}, albedo{};
  F8 hu{}, hv{};
  I8 flip{};
  F8 ul_x{}, ul_y{}, ub_x{}, ub_y{}, u_rr{};
  V3 o{}, e1{}, e2{}, n{}, li{}, s_wi{};
  F8 unit_area = splat(1.0f), u_rest{}, unit_pmf{}, pick_pmf{}, s_dist{}, s_pdf{};
  I8 triangle{}, two_sided{};

  for (;;) {
    // Idle lanes take the next samples: pixel by pixel, sample index rising.
    for (unsigned idle = ~active & 0xffu; idle && next < total && next < flushed + kWindow;
         idle &= idle - 1) {
      const int l = __builtin_ctz(idle);
      const int64_t pixel = next / count;
      const int x = x0 + int(pixel % width), y = y0 + int(pixel / width);
      Pending& pending = window[size_t(next % kWindow)];
      pending = {Rgb{}, 0.0f, x, y, false};
      ray[l] = job.camera_ray(*sampler[l], x, y, first + int(next % count), pending.weight);
      beta.set(l, Vec3(1.0f)), radiance.set(l, Vec3{}), from.set(l, Vec3{});
      bsdf_pdf[l] = 0.0f, specular[l] = -1, depth[l] = 0;
      ordinal[l] = next++;
      active |= 1u << l;
    }
    if (!active) break;

    // Closest hits, one ray at a time; a ray that leaves ends its path (no infinite lights).
    unsigned alive = 0;
    for_lanes(active, [&](int l) {
      if (world_.closest_hit(ray[l], hit[l], counter)) alive |= 1u << l;
    });

    // The surface interactions: plain triangles eight at once (World::local_interaction's
    // operations; idle lanes keep a real triangle), others by the scalar code in their lane.
    unsigned scalar_si = 0;
    for_lanes(alive, [&](int l) {
      const uint32_t id = hit[l].prim;
      set_rgb(albedo, l, albedo_[prims.origin(id).shape]);
      dir.set(l, ray[l].d);
      const uint8_t kind = plain_[id];
      if (!(kind & 1)) {
        scalar_si |= 1u << l;
        return;
      }
      const Vec3* v = prims.triangle(id);
      v0.set(l, v[0]), v1.set(l, v[1]), v2.set(l, v[2]);
      hu[l] = hit[l].u, hv[l] = hit[l].v, flip[l] = kind & 2 ? -1 : 0;
    });
    const F8 b0 = 1.0f - hu - hv;
    V3 p = v0 * b0 + v1 * hu + v2 * hv;
    V3 p_error =
        (lanes::abs(v0 * b0) + lanes::abs(v1 * hu) + lanes::abs(v2 * hv)) * splat(gamma(7));
    V3 ng = lanes::normalize(lanes::cross(v1 - v0, v2 - v0));
    ng = lanes::select(flip, -ng, ng);
    V3 ns = ng, ss, ts;
    lanes::orthonormal_basis(ns, ss, ts);
    V3 wo = lanes::normalize(-dir);
    for_lanes(scalar_si, [&](int l) {
      SurfaceInteraction si;
      world_.interaction(ray[l], hit[l], si);
      p.set(l, si.p), p_error.set(l, si.p_error), ng.set(l, si.ng), ns.set(l, si.ns);
      ss.set(l, si.ss), ts.set(l, si.ts), wo.set(l, si.wo);
      // Emission of an area light the path hit, weighted against light sampling.
      if (!si.emitted.is_black()) {
        const float w = specular[l]
                            ? 1.0f
                            : path.emission_weight(*si.area_light, bsdf_pdf[l], from.lane(l),
                                                   ray[l].d, si.light_point());
        set_rgb(radiance, l, rgb(radiance, l) + rgb(beta, l) * si.emitted * w);
      }
    });
    if (path.max_depth_ >= 0)
      for_lanes(alive, [&](int l) {
        if (depth[l] >= path.max_depth_) alive &= ~(1u << l);
      });

    // The vertex's numbers, in the scalar code's order: light pair, lobe, BSDF pair, roulette.
    for_lanes(alive, [&](int l) {
      S& s = *sampler[l];
      if (nee) {
        const Vec2 u = s.get_2d();
        ul_x[l] = u.x, ul_y[l] = u.y;
      }
      (void)s.get_1d();  // the lobe number: a diffuse BSDF has one lobe
      const Vec2 u = s.get_2d();
      ub_x[l] = u.x, ub_y[l] = u.y;
      u_rr[l] = s.get_1d();
    });
    const I8 alive_v = mask_of(alive);

    // The diffuse BSDF's sample (DiffuseMaterial::sample in the shading frame).
    const F8 wo_z = lanes::dot(wo, ns);
    V3 wl = cosine_hemisphere(ub_x, ub_y);
    wl.z = wo_z < 0.0f ? -wl.z : wl.z;
    const I8 same = wo_z * wl.z > 0.0f;
    const F8 bs_pdf = same ? lanes::abs(wl.z) * kInvPi : splat(0.0f);
    const V3 f_diffuse = albedo * splat(kInvPi);
    const V3 bs_f = lanes::select(same, f_diffuse, V3{});

    if (nee) {
      // The light and its unit, lane by lane; planar units are sampled below, eight at once,
      // others (spheres, rectangles by solid angle) by AreaLight::sample_li in their lane.
      unsigned planar = 0, scalar_ls = 0;
      for_lanes(alive, [&](int l) {
        float rest = ul_x[l];
        const SampledLight picked = light_sampler.sample(ul_x[l], &rest);
        if (!picked.light || !(picked.pmf > 0.0f)) return;
        const auto& light = static_cast<const AreaLight&>(*picked.light);
        if (light.unit_count() == 0) return;
        pick_pmf[l] = picked.pmf;
        const AreaLight::Picked pk = light.pick(rest);
        const AreaLight::Unit& unit = light.unit(pk.unit);
        if (unit.kind == AreaLight::UnitKind::kTriangle ||
            unit.kind == AreaLight::UnitKind::kParallelogram) {
          planar |= 1u << l;
          o.set(l, unit.o), e1.set(l, unit.e1), e2.set(l, unit.e2), n.set(l, unit.n);
          unit_area[l] = unit.area, u_rest[l] = pk.u, unit_pmf[l] = light.unit_pmf(pk.unit);
          triangle[l] = unit.kind == AreaLight::UnitKind::kTriangle ? -1 : 0;
          two_sided[l] = light.two_sided() ? -1 : 0;
          set_rgb(li, l, light.radiance());
          return;
        }
        const LightSample ls = light.sample_li(p.lane(l), {rest, ul_y[l]});
        if (ls.li.is_black() || !(ls.pdf > 0.0f)) return;
        scalar_ls |= 1u << l;
        s_wi.set(l, ls.wi), s_dist[l] = ls.distance, s_pdf[l] = ls.pdf;
        set_rgb(li, l, ls.li);
      });
      // AreaLight::sample_area and sample_li's density by area.
      const F8 sq = lanes::sqrt(u_rest);
      const V3 q = lanes::select(triangle, o + e1 * (1.0f - sq) + e2 * (ul_y * sq),
                                 o + e1 * u_rest + e2 * ul_y);
      const V3 d = q - p;
      const F8 dist2 = lanes::dot(d, d);
      F8 dist = lanes::sqrt(dist2);
      V3 wi = d * (1.0f / dist);
      const F8 cos_l = lanes::dot(n, -wi);
      const I8 side = two_sided ? (cos_l != 0.0f) : (cos_l > 0.0f);
      const F8 c = lanes::abs(cos_l);
      const F8 area_pdf = c > 0.0f ? dist2 / (c * unit_area) : splat(0.0f);
      F8 pdf = unit_pmf * area_pdf;
      I8 ok =
          mask_of(planar) & (dist > 0.0f) & side & (area_pdf > 0.0f) & lanes::is_finite(area_pdf);
      for_lanes(scalar_ls, [&](int l) {
        wi.set(l, s_wi.lane(l)), dist[l] = s_dist[l], pdf[l] = s_pdf[l], ok[l] = -1;
      });
      // The BSDF at the light's direction, and the shadow ray (SurfaceInteraction::spawn_ray_to).
      const F8 cos_s = lanes::dot(wi, ns);
      const I8 same_l = wo_z * cos_s > 0.0f;
      const V3 f = lanes::select(same_l, f_diffuse, V3{}) * lanes::abs(cos_s);
      ok &= ~is_black(f);
      const V3 target = p + wi * dist;
      const V3 so = lanes::offset_ray_origin(p, p_error, ng, target - p);
      const V3 sd = target - so;
      unsigned lit = 0;
      for_lanes(lanes::bits(ok) & alive, [&](int l) {
        Ray r;
        r.o = so.lane(l), r.d = sd.lane(l), r.tmax = 1.0f - 1e-4f, r.time = ray[l].time;
        if (!world_.occluded(r, counter)) lit |= 1u << l;
      });
      const F8 light_pdf = pick_pmf * pdf;
      const V3 fl = f * li;
      const V3 contribution =
          mis ? fl *
                    (power_heuristic(light_pdf, same_l ? lanes::abs(cos_s) * kInvPi : splat(0.0f)) /
                     light_pdf)
              : fl / light_pdf;
      radiance = lanes::select(
          alive_v, radiance + beta * lanes::select(mask_of(lit), contribution, V3{}), radiance);
    }

    // The continuation: throughput, the next ray, Russian roulette.
    I8 go = alive_v & (bs_pdf > 0.0f) & ~is_black(bs_f);
    const V3 w = ss * wl.x + ts * wl.y + ns * wl.z;
    const V3 nb = beta * (bs_f * (lanes::abs(lanes::dot(w, ns)) / bs_pdf));
    const F8 r = lanes::max_component(nb);
    go &= (r > 0.0f) & lanes::is_finite(r);
    F8 rr = r;
    if (path.rr_exponent_ == 0.5f)
      rr = lanes::sqrt(r);
    else if (path.rr_exponent_ != 1.0f)
      for (int l = 0; l < kWidth; ++l) rr[l] = std::pow(r[l], path.rr_exponent_);
    const I8 roulette = (depth + 1 >= path.rr_depth_) & (rr < 1.0f);
    const F8 q = lanes::max(splat(0.05f), 1.0f - rr);
    go &= ~(roulette & (u_rr < q));
    beta = lanes::select(go, lanes::select(roulette, nb / (1.0f - q), nb), beta);
    specular = go ? I8{} : specular;
    bsdf_pdf = go ? bs_pdf : bsdf_pdf;
    from = lanes::select(go, p, from);
    depth = go ? depth + 1 : depth;
    const V3 next_o = lanes::offset_ray_origin(p, p_error, ng, w);
    const unsigned cont = lanes::bits(go);
    for_lanes(cont, [&](int l) {
      ray[l].o = next_o.lane(l), ray[l].d = w.lane(l);
      ray[l].tmin = 0.0f, ray[l].tmax = kInfinity;
    });

    // Finished paths wait in the window; the oldest finished ones go to the film in order.
    for_lanes(active & ~cont, [&](int l) {
      Pending& pending = window[size_t(ordinal[l] % kWindow)];
      pending.l = rgb(radiance, l);
      pending.done = true;
    });
    active = cont;
    for (; flushed < next && window[size_t(flushed % kWindow)].done; ++flushed) {
      const Pending& pending = window[size_t(flushed % kWindow)];
      film.add_sample(pending.x, pending.y, pending.l, pending.weight);
    }
  }
}

}  // namespace penumbra
