#include "penumbra/render/integrator/path_lanes.h"

#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>
#include <type_traits>
#include <typeinfo>

#include "penumbra/core/lanes.h"
#include "penumbra/render/camera/pinhole_camera.h"
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
/// The largest float below 1 (LightSampler's and AreaLight::pick's bound on a remainder).
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
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
[[gnu::always_inline]] inline V3 cosine_hemisphere(F8 ux, F8 uy) {
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

/// True for the light units the lanes sample themselves: triangles and parallelograms.
bool planar(const AreaLight::Unit& u) {
  return u.kind == AreaLight::UnitKind::kTriangle || u.kind == AreaLight::UnitKind::kParallelogram;
}

/// True for the material the lanes shade themselves: an untextured diffuse one.
bool plain_diffuse(const Material& m) {
  return typeid(m) == typeid(DiffuseMaterial) && !m.textured();
}

/// power_heuristic(1, f_pdf, 1, g_pdf) lane by lane.
F8 power_heuristic(F8 f, F8 g) {
  const F8 ff = f * f, sum = ff + g * g;
  const F8 w = sum > 0.0f ? ff / sum : splat(0.0f);
  return lanes::abs(ff) == std::numeric_limits<float>::infinity() ? splat(1.0f) : w;
}

}  // namespace

std::unique_ptr<PathLanes> PathLanes::make(const PathIntegrator& path, const World& world,
                                           bool force) {
  if (world.has_instances() || world.shape_count() > kShapeMask) return nullptr;
  if (!force) {
    // Half of the primitives plain diffuse triangles (a proxy for the share of hits, which is
    // not known before the render), and every sampled light an area light of planar units.
    const PrimitiveSet& prims = world.primitives();
    size_t plain = 0;
    for (uint32_t id = 0; id < prims.size(); ++id)
      plain +=
          world.plain_triangle(id) && plain_diffuse(world.shape_material(prims.origin(id).shape));
    if (2 * plain < prims.size()) return nullptr;
    for (const Light* light : path.light_sampler_.lights()) {
      const auto* area = dynamic_cast<const AreaLight*>(light);
      if (!area) return nullptr;
      for (size_t i = 0; i < area->unit_count(); ++i)
        if (!planar(area->unit(i))) return nullptr;
    }
  }
  return std::unique_ptr<PathLanes>(new PathLanes(path, world));
}

PathLanes::PathLanes(const PathIntegrator& path, const World& world) : path_(path), world_(world) {
  for (size_t s = 0; s < world.shape_count(); ++s)
    for (int c = 0; c < 3; ++c) albedo_[c].push_back(world.shape_material(uint32_t(s)).albedo()[c]);
  // The only light's units, when they are all planar: picked and sampled eight at once.
  const auto& lights = path.light_sampler_.lights();
  const auto* area = lights.size() == 1 ? dynamic_cast<const AreaLight*>(lights[0]) : nullptr;
  if (area && area->unit_count() > 0) {
    auto t = std::make_unique<PlanarUnits>();
    for (size_t i = 0; i < area->unit_count(); ++i) {
      const AreaLight::Unit& u = area->unit(i);
      if (!planar(u)) {
        t.reset();
        break;
      }
      t->cdf.push_back(area->unit_cdf(i)), t->cdf_lo.push_back(area->unit_cdf_lo(i));
      t->inv_pmf.push_back(area->unit_inv_pmf(i)), t->pmf.push_back(area->unit_pmf(i));
      t->area.push_back(u.area);
      for (int a = 0; a < 3; ++a) {
        t->o[a].push_back(u.o[a]), t->e1[a].push_back(u.e1[a]), t->e2[a].push_back(u.e2[a]);
        t->n[a].push_back(u.n[a]);
      }
      t->triangle.push_back(u.kind == AreaLight::UnitKind::kTriangle ? 1.0f : 0.0f);
    }
    if (t) t->radiance = area->radiance(), t->two_sided = area->two_sided();
    units_ = std::move(t);
  }
  const PrimitiveSet& prims = world.primitives();
  prim_info_.resize(prims.size());
  for (uint32_t id = 0; id < prims.size(); ++id) {
    const uint32_t shape = prims.origin(id).shape;
    const bool diffuse = plain_diffuse(world.shape_material(shape));
    prim_info_[id] = shape | (diffuse ? 0 : kOther) |
                     (world.shape_flips_normal(shape) ? kFlip : 0) |
                     (diffuse && world.plain_triangle(id) ? kPlain : 0);
  }
}

void PathLanes::render_tile(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
                            RayCounter& counter) const {
  // As PathIntegrator::li: one type test buys inlined sampler calls.
  if (typeid(*job.sampler) == typeid(SobolSampler))
    run<SobolSampler>(job, x0, y0, x1, y1, first, count, counter);
  else
    run<Sampler>(job, x0, y0, x1, y1, first, count, counter);
}

/// A vertex of each lane's path, as the light sample needs it.
struct PathLanes::Vertex {
  V3 p, p_error, ng, ns;
  V3 f;           ///< the diffuse BSDF's value, albedo / pi
  F8 wo_z;        ///< cosine of the outgoing direction with ns
  F8 ul_x, ul_y;  ///< the light pair
};

/// Each lane's light and unit, picked lane by lane: planar units for the lanes' own sample,
/// other units sampled by AreaLight::sample_li in their lane.
struct PathLanes::LightLanes {
  LightLanes() {
    for (int l = 0; l < kWidth; ++l) area.v[l] = 1.0f;
  }
  lanes::V3Buf o, e1, e2, n, li, wi;
  lanes::F8Buf area, rest, unit_pmf, pick_pmf, dist, pdf;
  lanes::I8Buf triangle, two_sided;
  unsigned planar = 0;  ///< lanes with a planar unit
  unsigned scalar = 0;  ///< lanes with a light sample from sample_li (wi, dist, pdf, li)
  unsigned delta = 0;   ///< of those, samples of delta lights (no MIS weight)
  unsigned far = 0;     ///< of those, samples at infinite distance (an unbounded shadow ray)
};

void PathLanes::pick_light(Vec2 u, Vec3 p, int l, LightLanes& ll) const {
  // PathIntegrator::sample_light's pick and AreaLight::sample_li's, step by step.
  float rest = u.x;
  const SampledLight picked = path_.light_sampler_.sample(u.x, &rest);
  if (!picked.light || !(picked.pmf > 0.0f)) return;
  ll.pick_pmf.v[l] = picked.pmf;
  // An area light's triangle or parallelogram unit: sampled in the lanes.
  const auto* area = picked.light->kind() == LightKind::kArea
                         ? dynamic_cast<const AreaLight*>(picked.light)
                         : nullptr;
  if (area && area->unit_count() > 0) {
    const AreaLight::Picked pk = area->pick(rest);
    const AreaLight::Unit& unit = area->unit(pk.unit);
    if (planar(unit)) {
      ll.planar |= 1u << l;
      ll.o.set(l, unit.o), ll.e1.set(l, unit.e1), ll.e2.set(l, unit.e2), ll.n.set(l, unit.n);
      ll.area.v[l] = unit.area, ll.rest.v[l] = pk.u, ll.unit_pmf.v[l] = area->unit_pmf(pk.unit);
      ll.triangle.v[l] = unit.kind == AreaLight::UnitKind::kTriangle ? -1 : 0;
      ll.two_sided.v[l] = area->two_sided() ? -1 : 0;
      const Rgb r = area->radiance();
      ll.li.set(l, {r.r, r.g, r.b});
      return;
    }
  }
  // Any other light (spheres, rectangles by solid angle, points, spots, the sun, environments):
  // its own sample_li in this lane.
  const LightSample ls = picked.light->sample_li(p, {rest, u.y});
  if (ls.li.is_black() || !(ls.pdf > 0.0f)) return;
  ll.scalar |= 1u << l;
  if (ls.delta) ll.delta |= 1u << l;
  if (std::isinf(ls.distance)) ll.far |= 1u << l;
  ll.wi.set(l, ls.wi), ll.dist.v[l] = ls.distance, ll.pdf.v[l] = ls.pdf;
  ll.li.set(l, {ls.li.r, ls.li.g, ls.li.b});
}

V3 PathLanes::light_contribution(const Vertex& vx, unsigned alive, LightLanes& ll, const Ray* ray,
                                 RayCounter& counter) const {
  // The unit and the point on it: AreaLight::sample_area, then sample_li's density by area.
  V3 o, e1, e2, n, li;
  F8 area, rest, unit_pmf, pick_pmf;
  I8 triangle, two_sided, planar;
  if (units_) {
    // One light (LightSampler::sample's remainder min(u, 1 - eps), probability 1) and
    // AreaLight::pick's branch-free search, eight lanes at once.
    const PlanarUnits& t = *units_;
    const F8 u = vx.ul_x < kOneMinusEpsilon ? vx.ul_x : splat(kOneMinusEpsilon);
    I8 k{};
    for (size_t len = t.cdf.size(); len > 1;) {
      const size_t half = len / 2;
      k += (lanes::gather(t.cdf.data(), k + int32_t(half - 1)) <= u) & int32_t(half);
      len -= half;
    }
    if (t.cdf.size() > 1) {
      k += (lanes::gather(t.cdf.data(), k) <= u) & 1;
      k = k < int32_t(t.cdf.size() - 1) ? k : I8{} + int32_t(t.cdf.size() - 1);
    }
    // One unit (a quad light): its values splat, not gathered (a gather of eight floats costs
    // about as much as eight loads, and AVX2 machines without fast gathers more).
    const bool one = t.cdf.size() == 1;
    const auto at = [&](const std::vector<float>& a) {
      return one ? splat(a[0]) : lanes::gather(a.data(), k);
    };
    const F8 r = (u - at(t.cdf_lo)) * at(t.inv_pmf);
    rest = r < 0.0f ? splat(0.0f) : (kOneMinusEpsilon < r ? splat(kOneMinusEpsilon) : r);
    o = {at(t.o[0]), at(t.o[1]), at(t.o[2])};
    e1 = {at(t.e1[0]), at(t.e1[1]), at(t.e1[2])};
    e2 = {at(t.e2[0]), at(t.e2[1]), at(t.e2[2])};
    n = {at(t.n[0]), at(t.n[1]), at(t.n[2])};
    area = at(t.area), unit_pmf = at(t.pmf), pick_pmf = splat(1.0f);
    triangle = at(t.triangle) != 0.0f;
    two_sided = I8{} - int32_t(t.two_sided);
    li = {splat(t.radiance.r), splat(t.radiance.g), splat(t.radiance.b)};
    planar = mask_of(alive);
  } else {
    o = ll.o.load(), e1 = ll.e1.load(), e2 = ll.e2.load(), n = ll.n.load(), li = ll.li.load();
    area = ll.area.load(), rest = ll.rest.load(), unit_pmf = ll.unit_pmf.load();
    pick_pmf = ll.pick_pmf.load();
    triangle = ll.triangle.load(), two_sided = ll.two_sided.load();
    planar = mask_of(ll.planar);
  }
  const F8 sq = lanes::sqrt(rest);
  const V3 q = lanes::select(triangle, o + e1 * (1.0f - sq) + e2 * (vx.ul_y * sq),
                             o + e1 * rest + e2 * vx.ul_y);
  const V3 d = q - vx.p;
  const F8 dist2 = lanes::dot(d, d);
  F8 dist = lanes::sqrt(dist2);
  V3 wi = d * (1.0f / dist);
  const F8 cos_l = lanes::dot(n, -wi);
  const I8 side = two_sided ? (cos_l != 0.0f) : (cos_l > 0.0f);
  const F8 c = lanes::abs(cos_l);
  const F8 area_pdf = c > 0.0f ? dist2 / (c * area) : splat(0.0f);
  F8 pdf = unit_pmf * area_pdf;
  I8 ok = planar & (dist > 0.0f) & side & (area_pdf > 0.0f) & lanes::is_finite(area_pdf);
  for_lanes(ll.scalar, [&](int l) {
    wi.set(l, ll.wi.lane(l)), dist[l] = ll.dist.v[l], pdf[l] = ll.pdf.v[l], ok[l] = -1;
    li.set(l, ll.li.lane(l));
  });
  // The BSDF at the light's direction, and the shadow ray (SurfaceInteraction::spawn_ray_to).
  const F8 cos_s = lanes::dot(wi, vx.ns);
  const I8 same = vx.wo_z * cos_s > 0.0f;
  const V3 f = lanes::select(same, vx.f, V3{}) * lanes::abs(cos_s);
  ok &= ~is_black(f);
  const V3 target = vx.p + wi * dist;
  const V3 so = lanes::offset_ray_origin(vx.p, vx.p_error, vx.ng, target - vx.p);
  const V3 sd = target - so;
  unsigned lit = 0;
  for_lanes(lanes::bits(ok) & alive, [&](int l) {
    Ray r;
    r.time = ray[l].time;
    if (ll.far >> l & 1) {  // SurfaceInteraction::spawn_ray towards an infinitely far light
      r.d = wi.lane(l);
      r.o = offset_ray_origin(vx.p.lane(l), vx.p_error.lane(l), vx.ng.lane(l), r.d);
    } else {
      r.o = so.lane(l), r.d = sd.lane(l), r.tmax = 1.0f - 1e-4f;
    }
    if (!world_.occluded(r, counter)) lit |= 1u << l;
  });
  // PathIntegrator::sample_light's weight: the power heuristic against the BSDF's density.
  const F8 light_pdf = pick_pmf * pdf;
  const V3 fl = f * li;
  // Delta lights and the other strategies: unweighted (the divisions only where needed).
  if (path_.strategy_ != PathIntegrator::Strategy::kMis)
    return lanes::select(mask_of(lit), fl / light_pdf, V3{});
  V3 contribution =
      fl *
      (power_heuristic(light_pdf, same ? lanes::abs(cos_s) * kInvPi : splat(0.0f)) / light_pdf);
  if (ll.delta) contribution = lanes::select(mask_of(ll.delta), fl / light_pdf, contribution);
  return lanes::select(mask_of(lit), contribution, V3{});
}

template <class S>
void PathLanes::run(RenderJob& job, int x0, int y0, int x1, int y1, int first, int count,
                    RayCounter& counter) const {
  using lanes::F8Buf;
  using lanes::I8Buf;
  using lanes::V3Buf;
  const PathIntegrator& path = path_;
  const PrimitiveSet& prims = world_.primitives();
  const LightSampler& light_sampler = path.light_sampler_;
  const bool nee = !light_sampler.lights().empty();
  Film& film = *job.film;
  const int64_t total = int64_t(x1 - x0) * (y1 - y0) * count;

  // Per lane: a sampler, the path's ray and state.
  std::unique_ptr<Sampler> owned[kWidth];
  S* sampler[kWidth];
  for (int l = 0; l < kWidth; ++l)
    owned[l] = job.sampler->clone(), sampler[l] = static_cast<S*>(owned[l].get());
  Ray ray[kWidth];
  V3 beta{}, radiance{}, from{};
  F8 bsdf_pdf{}, eta_scale = splat(1.0f);
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
  int cx = x0, cy = y0, ci = first;  ///< the pixel and index of sample `next`
  const auto* pinhole = typeid(*job.camera) == typeid(PinholeCamera)
                            ? static_cast<const PinholeCamera*>(job.camera.get())
                            : nullptr;
  const Vec3 eye = pinhole ? pinhole->eye() : Vec3{}, right = pinhole ? pinhole->right() : Vec3{};
  const Vec3 up = pinhole ? pinhole->up() : Vec3{}, forward = pinhole ? pinhole->forward() : Vec3{};
  V3Buf camera_dir;
  F8Buf camera_u;
  // Lane values written lane by lane, declared once per tile: lanes that do not write them keep
  // earlier, real values, which nothing reads. (Declared in the loop, their zero-initialisation
  // was a memset per step: 11 % of the lanes' own time in perf.)
  Hit hit[kWidth];
  V3Buf v0, v1, v2, dir, albedo;
  for (int l = 0; l < kWidth; ++l)
    v1.set(l, {1, 0, 0}), v2.set(l, {0, 1, 0}), dir.set(l, {0, 0, 1});
  F8Buf hu, hv, ul_x, ul_y, ub_x, ub_y, u_rr;
  I8Buf flip;
  LightLanes lights;
  // Lane l's path as PathIntegrator keeps it, for the scalar steps done in a lane.
  const auto state = [&](int l) {
    PathIntegrator::PathState st;
    st.ray = ray[l], st.radiance = rgb(radiance, l), st.beta = rgb(beta, l);
    st.specular = specular[l] != 0, st.bsdf_pdf = bsdf_pdf[l], st.from = from.lane(l);
    st.eta_scale = eta_scale[l];
    return st;
  };

  // A Sobol' sampler's numbers are computed eight lanes at once (SobolLanes), each lane's
  // next pairs, instead of by each lane's sampler sixteen consecutive pairs at a time, about half
  // of which a short path never draws. Each lane's next pair and pending 1D number
  // (SobolSampler's state) live in the lanes then, and go to its sampler and back around a
  // scalar vertex. A number is always pending: the camera leaves one (its time pair's second),
  // and every vertex draws two 1D numbers (lobe and roulette), so the first takes the pending
  // one and the second opens a pair whose other number stays pending (the mixed world's tests
  // fail if a vertex ever breaks that).
  constexpr bool kPairs = std::is_same_v<S, SobolSampler>;
  std::optional<SobolLanes> sobol;
  if constexpr (kPairs) sobol.emplace(*sampler[0]);
  lanes::U8 next_pair{};
  F8 pending_u{};
  // RenderJob::camera_ray from the sampler's numbers (pixel, lens, time), with the sampler's type
  // known; a pinhole camera's rays are finished eight at once below.
  const auto start_camera_ray = [&](int l, Vec2 u_pixel, Vec2 u_lens, float u_time,
                                    Pending& pending) {
    const CameraSample cs =
        job.camera_sample(pending.x, pending.y, u_pixel, u_lens, u_time, pending.weight);
    if (pinhole)
      camera_dir.set(l, pinhole->camera_direction(cs.film)), camera_u.v[l] = cs.time;
    else
      ray[l] = job.camera->generate_ray(cs);
  };

  for (;;) {
    // Idle lanes take the next samples: pixel by pixel, sample index rising.
    unsigned started = 0;
    for (unsigned idle = ~active & 0xffu; idle && next < total && next < flushed + kWindow;
         idle &= idle - 1) {
      const int l = __builtin_ctz(idle);
      Pending& pending = window[size_t(next % kWindow)];
      pending = {Rgb{}, 0.0f, cx, cy, false};
      S& s = *sampler[l];
      s.start_pixel_sample(cx, cy, ci);
      if constexpr (kPairs) {
        sobol->set(l, s);  // its camera's numbers come eight at once below
      } else {
        // In the order of RenderJob::camera_ray (a call's arguments have none).
        const Vec2 u_pixel = s.get_pixel_2d(), u_lens = s.get_2d();
        start_camera_ray(l, u_pixel, u_lens, s.get_1d(), pending);
      }
      ordinal[l] = next++;
      started |= 1u << l;
      // The next sample: index, then pixel along the row, then row (no 64-bit divisions).
      if (++ci == first + count) {
        ci = first;
        if (++cx == x1) cx = x0, ++cy;
      }
    }
    if constexpr (kPairs) {
      if (started) {
        // The camera's pairs: pixel, time (whose second number stays pending: the first
        // vertex's lobe number) and lens (a pinhole camera reads none). Their n lanes, a few
        // per step, share vectors: pair j of the r-th lane is entry j n + r.
        const int n = __builtin_popcount(started), per = pinhole ? 2 : 3;
        constexpr uint32_t kCameraPair[3] = {0, 2, 1};
        alignas(32) uint32_t entry_lane[3 * kWidth] = {}, entry_pair[3 * kWidth] = {};
        int r = 0;
        for_lanes(started, [&](int l) {
          for (int j = 0; j < per; ++j) {
            entry_lane[j * n + r] = uint32_t(l);
            entry_pair[j * n + r] = SobolSampler::kFirstPair + kCameraPair[j];
          }
          ++r;
        });
        alignas(32) float ux[3 * kWidth], uy[3 * kWidth];
        for (int e = 0; e < per * n; e += kWidth) {
          lanes::U8 el, ep;
          F8 x, y;
          std::memcpy(&el, entry_lane + e, sizeof el);
          std::memcpy(&ep, entry_pair + e, sizeof ep);
          sobol->compute(el, ep, x, y);
          std::memcpy(ux + e, &x, sizeof x);
          std::memcpy(uy + e, &y, sizeof y);
        }
        F8Buf time_y;
        r = 0;
        for_lanes(started, [&](int l) {
          start_camera_ray(l, {ux[r], uy[r]}, pinhole ? Vec2{} : Vec2{ux[2 * n + r], uy[2 * n + r]},
                           ux[n + r], window[size_t(ordinal[l] % kWindow)]);
          time_y.v[l] = uy[n + r];
          ++r;
        });
        const I8 fresh = mask_of(started);
        next_pair = fresh ? lanes::U8{} + (SobolSampler::kFirstPair + 3) : next_pair;
        pending_u = fresh ? time_y.load() : pending_u;
      }
    }
    if (started && pinhole) {
      // PinholeCamera::generate_ray: the direction to world space, normalised; the shutter time.
      const V3 c = camera_dir.load();
      const V3 d = lanes::normalize(V3{splat(right.x), splat(right.y), splat(right.z)} * c.x +
                                    V3{splat(up.x), splat(up.y), splat(up.z)} * c.y +
                                    V3{splat(forward.x), splat(forward.y), splat(forward.z)} * c.z);
      const Shutter& sh = pinhole->shutter();
      const F8 t = sh.open + (sh.close - sh.open) * camera_u.load();
      const F8 time = t < sh.close ? t : splat(sh.close);
      for_lanes(started, [&](int l) {
        ray[l] = Ray{};
        ray[l].o = eye, ray[l].d = d.lane(l), ray[l].time = time[l];
      });
    }
    if (started) {
      const I8 fresh = mask_of(started);
      beta = lanes::select(fresh, V3{splat(1.0f), splat(1.0f), splat(1.0f)}, beta);
      radiance = lanes::select(fresh, V3{}, radiance);
      from = lanes::select(fresh, V3{}, from);
      bsdf_pdf = fresh ? splat(0.0f) : bsdf_pdf;
      eta_scale = fresh ? splat(1.0f) : eta_scale;
      specular = fresh | specular;
      depth = fresh ? I8{} : depth;
      active |= started;
    }
    if (!active) break;

    // Closest hits, one ray at a time, in a loop that also gathers what the lanes' interaction
    // needs.
    unsigned alive = 0, scalar_si = 0, other = 0, other_cont = 0;
    for_lanes(active, [&](int l) {
      if (!world_.closest_hit(ray[l], hit[l], counter)) return;
      alive |= 1u << l;
      const uint32_t id = hit[l].prim, info = prim_info_[id];
      const uint32_t shape = info & kShapeMask;
      albedo.set(l, {albedo_[0][shape], albedo_[1][shape], albedo_[2][shape]});
      dir.set(l, ray[l].d);
      if (!(info & kPlain)) {
        scalar_si |= 1u << l;
        if (info & kOther) other |= 1u << l;
        return;
      }
      const Vec3* v = prims.triangle(id);
      v0.set(l, v[0]), v1.set(l, v[1]), v2.set(l, v[2]);
      hu.v[l] = hit[l].u, hv.v[l] = hit[l].v, flip.v[l] = info & kFlip ? -1 : 0;
    });

    // A ray that left ends its path with the environment's radiance, weighted against light
    // sampling (PathIntegrator::trace's first step). Outside the loop above, which it slowed.
    if (!world_.infinite_lights().empty())
      for_lanes(active & ~alive, [&](int l) {
        PathIntegrator::PathState st = state(l);
        path.add_escaped(st);
        set_rgb(radiance, l, st.radiance);
      });

    // The surface interactions: plain triangles eight at once (World::local_interaction's
    // operations), others by the scalar code in their lane.
    const V3 tv0 = v0.load(), tv1 = v1.load(), tv2 = v2.load();
    const F8 u = hu.load(), v = hv.load();
    const F8 b0 = 1.0f - u - v;
    V3 p = tv0 * b0 + tv1 * u + tv2 * v;
    V3 p_error =
        (lanes::abs(tv0 * b0) + lanes::abs(tv1 * u) + lanes::abs(tv2 * v)) * splat(gamma(7));
    V3 ng = lanes::normalize(lanes::cross(tv1 - tv0, tv2 - tv0));
    ng = lanes::select(flip.load(), -ng, ng);
    V3 ns = ng, ss, ts;
    lanes::orthonormal_basis(ns, ss, ts);
    V3 wo = lanes::normalize(-dir.load());
    for_lanes(scalar_si, [&](int l) {
      SurfaceInteraction si;
      world_.interaction(ray[l], hit[l], si);
      p.set(l, si.p), p_error.set(l, si.p_error), ng.set(l, si.ng), ns.set(l, si.ns);
      ss.set(l, si.ss), ts.set(l, si.ts), wo.set(l, si.wo);
      // Emission of an area light the path hit, weighted against light sampling.
      const bool emits = !si.emitted.is_black();
      if (!emits && !(other >> l & 1)) return;
      PathIntegrator::PathState st = state(l);
      if (emits) {
        path.add_emitted(si, st);
        set_rgb(radiance, l, st.radiance);
      }
      if (!(other >> l & 1)) return;
      // Another material: the rest of the vertex is PathIntegrator's, in this lane.
      alive &= ~(1u << l);
      if (path.max_depth_ >= 0 && depth[l] >= path.max_depth_) return;
      if constexpr (kPairs) sampler[l]->resume(next_pair[l], true, pending_u[l]);
      const bool goes = path.scatter(si, depth[l], *sampler[l], st, counter);
      if constexpr (kPairs)
        next_pair[l] = sampler[l]->next_pair(), pending_u[l] = sampler[l]->pending();
      set_rgb(radiance, l, st.radiance);
      if (!goes) return;
      other_cont |= 1u << l;
      ray[l] = st.ray, set_rgb(beta, l, st.beta), specular[l] = st.specular ? -1 : 0;
      bsdf_pdf[l] = st.bsdf_pdf, from.set(l, st.from), eta_scale[l] = st.eta_scale, ++depth[l];
    });
    if (path.max_depth_ >= 0)
      for_lanes(alive, [&](int l) {
        if (depth[l] >= path.max_depth_) alive &= ~(1u << l);
      });

    // The vertex's numbers, in the scalar code's order: light pair, lobe, BSDF pair, roulette.
    // Without a table of planar units, the light and its unit are picked here too.
    lights.planar = lights.scalar = lights.delta = lights.far = 0;
    F8 u_light_x, u_light_y, u_bsdf_x, u_bsdf_y, u_roulette;
    if constexpr (kPairs) {
      // The same numbers, eight lanes at once: the light pair, the pending number (the lobe's),
      // the BSDF pair, and a pair whose first number is the roulette's and whose second stays
      // pending.
      F8 ux[3], uy[3];
      sobol->compute3(next_pair, ux, uy);
      const int b = nee ? 1 : 0;  // the BSDF pair
      u_light_x = ux[0], u_light_y = uy[0];
      u_bsdf_x = ux[b], u_bsdf_y = uy[b], u_roulette = ux[b + 1];
      const I8 a = mask_of(alive);
      next_pair = a ? next_pair + uint32_t(b + 2) : next_pair;
      pending_u = a ? uy[b + 1] : pending_u;
      if (nee && !units_)
        for_lanes(alive, [&](int l) { pick_light({ux[0][l], uy[0][l]}, p.lane(l), l, lights); });
    } else {
      for_lanes(alive, [&](int l) {
        S& s = *sampler[l];
        if (nee) {
          const Vec2 ul = s.get_2d();
          ul_x.v[l] = ul.x, ul_y.v[l] = ul.y;
          if (!units_) pick_light(ul, p.lane(l), l, lights);
        }
        (void)s.get_1d();  // the lobe number: a diffuse BSDF has one lobe
        const Vec2 ub = s.get_2d();
        ub_x.v[l] = ub.x, ub_y.v[l] = ub.y;
        u_rr.v[l] = s.get_1d();
      });
      u_light_x = ul_x.load(), u_light_y = ul_y.load();
      u_bsdf_x = ub_x.load(), u_bsdf_y = ub_y.load(), u_roulette = u_rr.load();
    }
    const I8 alive_v = mask_of(alive);

    // The diffuse BSDF's sample (DiffuseMaterial::sample in the shading frame).
    const F8 wo_z = lanes::dot(wo, ns);
    V3 wl = cosine_hemisphere(u_bsdf_x, u_bsdf_y);
    wl.z = wo_z < 0.0f ? -wl.z : wl.z;
    const I8 same = wo_z * wl.z > 0.0f;
    const F8 bs_pdf = same ? lanes::abs(wl.z) * kInvPi : splat(0.0f);
    const V3 f_diffuse = albedo.load() * splat(kInvPi);
    const V3 bs_f = lanes::select(same, f_diffuse, V3{});

    if (nee) {
      const Vertex vertex{p, p_error, ng, ns, f_diffuse, wo_z, u_light_x, u_light_y};
      const V3 c = light_contribution(vertex, alive, lights, ray, counter);
      radiance = lanes::select(alive_v, radiance + beta * c, radiance);
    }

    // The continuation: throughput, the next ray, Russian roulette.
    I8 go = alive_v & (bs_pdf > 0.0f) & ~is_black(bs_f);
    const V3 w = ss * wl.x + ts * wl.y + ns * wl.z;
    const V3 nb = beta * (bs_f * (lanes::abs(lanes::dot(w, ns)) / bs_pdf));
    const F8 mc = lanes::max_component(nb);
    go &= (mc > 0.0f) & lanes::is_finite(mc);
    const F8 r = mc * eta_scale;  // eta^2 of the refractions in other lanes' vertices so far
    F8 rr = r;
    if (path.rr_exponent_ == 0.5f)
      rr = lanes::sqrt(r);
    else if (path.rr_exponent_ != 1.0f)
      for (int l = 0; l < kWidth; ++l) rr[l] = std::pow(r[l], path.rr_exponent_);
    const I8 roulette = (depth + 1 >= path.rr_depth_) & (rr < 1.0f);
    const F8 q = lanes::max(splat(0.05f), 1.0f - rr);
    go &= ~(roulette & (u_roulette < q));
    beta = lanes::select(go, lanes::select(roulette, nb / (1.0f - q), nb), beta);
    specular = go ? I8{} : specular;
    bsdf_pdf = go ? bs_pdf : bsdf_pdf;
    from = lanes::select(go, p, from);
    depth = go ? depth + 1 : depth;
    const V3 next_o = lanes::offset_ray_origin(p, p_error, ng, w);
    const unsigned cont = lanes::bits(go) | other_cont;
    for_lanes(lanes::bits(go), [&](int l) {
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
