#include "penumbra/render/radiosity/radiosity_integrator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/timer.h"
#include "penumbra/render/integrator/direct_lighting.h"
#include "penumbra/render/material/diffuse_material.h"
#include "penumbra/render/radiosity/hierarchical_radiosity.h"
#include "penumbra/render/radiosity/radiosity_solution.h"
#include "penumbra/render/render_job.h"
#include "penumbra/render/sampling.h"

namespace penumbra {

namespace {

/// Corners average the radiosity of the elements of their shape around them whose normals lie
/// within about 30 degrees of their own: smooth across a flat or gently curved surface, sharp at
/// a crease and at the edge of a light.
constexpr float kSmoothCos = 0.85f;
/// A patch size larger than any scene: one top-level element per primitive.
constexpr float kCoarse = 1e30f;

std::string check_method(const std::string& name, const std::vector<std::string>& valid,
                         const char* what) {
  for (const std::string& v : valid)
    if (v == name) return name;
  std::string list;
  for (const std::string& v : valid) list += (list.empty() ? "" : ", ") + v;
  throw Error(fmt::format("radiosity: unknown {} '{}' (valid: {})", what, name, list));
}

}  // namespace

RadiosityIntegrator::RadiosityIntegrator(const World& world, const ParamList& params,
                                         const RenderSettings&)
    : world_(world), light_sampler_(world.lights(), "power") {
  // The patches are meshed from the scene's own primitives; instanced objects would block rays
  // without ever receiving or sending light.
  if (world.has_instances())
    throw Error(
        "radiosity: scenes with instanced objects are not supported (flatten the instances "
        "into ordinary shapes)");
  const float diag = length(world.bounds().diagonal());
  const float scale = std::isfinite(diag) && diag > 0.0f ? diag : 1.0f;
  patch_ = float(params.get_real("patch", scale / 25.0, 1e-30, 1e30));
  max_elements_ = size_t(params.get_int("max_elements", 200000, 1, 1ll << 32));
  ff_options_.method = check_method(params.get_string("form_factors", "raycast"),
                                    {"raycast", "hemicube"}, "form-factor method");
  ff_options_.rays = int(params.get_int("rays", 1024, 1, 1 << 24));
  ff_options_.resolution = int(params.get_int("resolution", 64, 2, 4096));
  solve_options_.method =
      check_method(params.get_string("solver", "gauss-seidel"), radiosity_solver_names(), "solver");
  solve_options_.tolerance = params.get_real("tolerance", 1e-4, 1e-12, 1.0);
  solve_options_.max_iterations = int(params.get_int("max_iterations", 1000, 1, 1 << 24));
  adapt_rounds_ = int(params.get_int("adapt", 0, 0, 16));
  adapt_threshold_ = params.get_real("adapt_threshold", 0.3, 1e-6, 1e6);
  budget_ = size_t(params.get_int("budget", 12000, 1, 1ll << 32));
  hierarchy_ = params.has("hierarchy") && params.get_flag("hierarchy");
  epsilon_ = params.get_real("epsilon", HierarchicalOptions{}.epsilon, 1e-12, 1.0);
  link_grid_ = int(params.get_int("link_grid", HierarchicalOptions{}.link_grid, 1, 64));
  clusters_ = check_method(params.get_string("clusters", "auto"), {"auto", "true", "false"},
                           "clusters setting");
  final_gather_ = params.has("final_gather") ? params.get_flag("final_gather") : true;
  gather_rays_ = int(params.get_int("gather", 1, 1, 1 << 16));
  solution_file_ = params.get_string("solution", "");
  const std::string show = params.get_string("show", "none");
  if (show != "none" && show != "elements")
    throw Error("radiosity: unknown show '" + show + "' (valid: none, elements)");
  show_elements_ = show == "elements";
  params.check_all_used();
}

RadiosityIntegrator::~RadiosityIntegrator() = default;

std::string RadiosityIntegrator::name() const {
  std::string s = fmt::format("radiosity:patch={:g}", patch_);
  if (!solution_file_.empty()) return s + ",solution=" + solution_file_;
  if (hierarchy_) {
    s += fmt::format(",hierarchy,epsilon={:g}", epsilon_);
    if (clusters_ != "auto") s += ",clusters=" + clusters_;
  } else {
    s += ",form_factors=" + ff_options_.method;
    s += ff_options_.method == "raycast" ? fmt::format(",rays={}", ff_options_.rays)
                                         : fmt::format(",resolution={}", ff_options_.resolution);
    s += ",solver=" + solve_options_.method;
    if (adapt_rounds_ > 0)
      s += fmt::format(",adapt={},adapt_threshold={:g},budget={}", adapt_rounds_, adapt_threshold_,
                       budget_);
  }
  s += final_gather_ ? fmt::format(",gather={}", gather_rays_) : ",final_gather=false";
  if (show_elements_) s += ",show=elements";
  return s;
}

void RadiosityIntegrator::preprocess(RenderJob& job) {
  solve(job);
}

void RadiosityIntegrator::solve(RenderJob& job) {
  report_ = {};
  ff_options_.seed = 0;
  hr_.reset();
  // The mesh, with a warning for every material it cannot represent exactly.
  const Timer mesh_timer;
  std::vector<std::string> warnings;
  // The display mesh (and, without the hierarchy, the solution's): elements about `patch`.
  mesh_ = RadiosityMesh::build(world_, patch_, max_elements_, &warnings);
  for (const std::string& w : warnings) job.warn("radiosity: " + w);
  for (const Light* l : world_.lights())
    if (l->kind() != LightKind::kArea) {
      job.warn(
          "radiosity: point, directional and environment lights are not in the radiosity "
          "solution (only emissive shapes are); they light the final gather's direct term");
      break;
    }
  report_.elements = mesh_.size();
  report_.mesh_seconds = mesh_timer.elapsed_s();
  const std::vector<RadiosityElement>& el = mesh_.elements();

  if (!solution_file_.empty()) {
    corners_ = read_radiosity_solution(solution_file_, mesh_, std::max(max_elements_, budget_));
    report_.elements = mesh_.size();
    b_.assign(el.size(), Rgb{});
    for (size_t e = 0; e < el.size(); ++e) {
      Rgb sum;
      for (int k = 0; k < el[e].corners; ++k) sum += corners_[4 * e + size_t(k)];
      b_[e] = sum / float(el[e].corners);
    }
    report_.loaded = true;
    return;
  }

  if (hierarchy_) {
    job.report_preprocess("hierarchical radiosity", 0.0);
    const auto visible = [this](Vec3 a, Vec3 b) {
      Ray r;
      r.o = a;
      r.d = b - a;
      r.tmin = 1e-4f;
      r.tmax = 1.0f - 1e-4f;
      RayCounter c;
      return world_.occluded(r, c) ? 0.0f : 1.0f;
    };
    // The hierarchy refines coarse top-level patches itself (each pair of facing top-level
    // patches costs a link): one per primitive, a merged triangle pair or a quad.
    const RadiosityMesh top = RadiosityMesh::build(world_, kCoarse, max_elements_);
    HierarchicalOptions ho;
    ho.epsilon = float(epsilon_);
    ho.tolerance = solve_options_.tolerance;
    // Leaves no smaller than a quarter of a patch: where patches touch (a block on the floor)
    // the oracle refines regardless, and leaves of the scene's area x 1e-5 made 7 million links
    // on the Cornell box.
    ho.min_area = 0.25f * patch_ * patch_;
    ho.link_grid = link_grid_;
    // Clustering: by default above HierarchicalOptions::cluster_min_patches top-level patches.
    ho.clusters = clusters_ != "false";
    if (clusters_ == "true") ho.cluster_min_patches = 0;
    hr_ = std::make_unique<HierarchicalRadiosity>(
        HierarchicalRadiosity::solve(top.elements(), top.vertices(), visible, ho));
    resample_hierarchy(top);
    const HierarchicalStats& st = hr_->stats();
    report_.solve_seconds = st.seconds;
    report_.links = st.links;
    report_.nodes = st.nodes;
    report_.hierarchy_bytes = st.memory_bytes;
    report_.top_patches = st.patches;
    report_.clusters = st.clusters;
    report_.leaves = st.leaves;
    report_.refine_seconds = st.refine_seconds;
    report_.gather_seconds = st.solve_seconds;
    report_.iterations = st.iterations;
    report_.residuals = hr_->changes();
  } else {
    solve_matrix(job);
    // Adaptive subdivision: split where neighbours differ, then form factors and solve again.
    for (int round = 0; round < adapt_rounds_ && !job.cancelled(); ++round) {
      const std::vector<uint32_t> split = adaptive_split();
      if (split.empty()) break;
      job.report_preprocess("adaptive subdivision", 0.0);
      mesh_.subdivide(split);
      // Fresh rays for every element: the ones kept were chosen for agreeing with their
      // neighbours, so their old estimates are biased (ray-cast counts are right-skewed, and the
      // bright outliers are the ones split); with the same rays the floor read 4.5 % dark.
      ff_options_.seed = round + 1;
      report_.elements = mesh_.size();
      report_.round_elements.push_back(mesh_.size());
      solve_matrix(job);
    }
  }
  average_corners();
}

void RadiosityIntegrator::solve_matrix(RenderJob& job) {
  const std::vector<RadiosityElement>& el = mesh_.elements();
  job.report_preprocess("form factors", 0.0);
  FormFactors ff = compute_form_factors(world_, mesh_, ff_options_);
  form_factor_diagnostics(mesh_, ff);
  report_.form_factor_seconds += ff.seconds;
  report_.matrix_bytes = ff.f.size() * sizeof(float);
  report_.reciprocity_error = ff.reciprocity_error;
  report_.min_row_sum = ff.min_row_sum;
  report_.max_row_sum = ff.max_row_sum;
  if (job.cancelled()) return;
  job.report_preprocess("radiosity solve", 0.0);
  RadiositySystem sys;
  sys.n = el.size();
  sys.f = ff.f.data();
  for (const RadiosityElement& e : el) {
    sys.rho.push_back(e.rho);
    sys.emission.push_back(e.emission);
    sys.area.push_back(e.area);
  }
  const SolveResult r = solve_radiosity(sys, solve_options_);
  b_ = r.b;
  if (!r.ambient.empty())
    for (size_t i = 0; i < b_.size(); ++i) b_[i] += r.ambient[i];
  // Ray casting's noise in each element's gathered radiosity, for adaptive_split: rho times the
  // standard deviation of the mean of `rays` draws of B_j with probabilities F_ij (Poisson).
  noise_.assign(el.size(), 0.0f);
  if (ff_options_.method == "raycast" && adapt_rounds_ > 0)
    parallel_for(el.size(), [&](size_t i) {
      double m2 = 0;
      const float* row = ff.f.data() + i * el.size();
      for (size_t j = 0; j < el.size(); ++j)
        if (row[j] > 0) m2 += double(row[j]) * double(b_[j].luminance()) * b_[j].luminance();
      noise_[i] = float(el[i].rho.max_channel() * std::sqrt(m2 / ff_options_.rays));
    });
  report_.solve_seconds += r.seconds;
  report_.iterations = r.iterations;
  report_.residuals = r.residuals;
  if (!r.converged)
    job.warn(
        fmt::format("radiosity: {} did not reach the tolerance {:g} in {} iterations "
                    "(residual {:g})",
                    solve_options_.method, solve_options_.tolerance, r.iterations,
                    r.residuals.empty() ? 0.0 : r.residuals.back()));
}

// The pieces to split: those where either side's radiosity differs from a neighbour's (an
// element of the same shape facing the same way that shares a corner), beyond three standard
// deviations of ray casting's noise in the two, by more than adapt_threshold times the mean
// radiosity of the lit, non-emitting elements. Largest difference first, as many as the element
// budget allows; pieces already at 1/64 of a patch's area stay (a shadow edge differs at every
// scale).
std::vector<uint32_t> RadiosityIntegrator::adaptive_split() const {
  const std::vector<RadiosityElement>& el = mesh_.elements();
  const std::vector<std::vector<uint32_t>> around = elements_around_vertices();
  double sum = 0, area = 0;
  for (size_t e = 0; e < el.size(); ++e)
    if (el[e].emission.is_black() && b_[e].luminance() > 0)
      sum += double(b_[e].luminance()) * el[e].area, area += el[e].area;
  if (!(area > 0)) return {};
  const double threshold = adapt_threshold_ * sum / area;
  const float min_area = patch_ * patch_ / 64.0f;
  std::vector<std::pair<float, uint32_t>> candidates;
  for (uint32_t f = 0; f < el.size(); f += 2) {
    if (el[f].area < min_area) continue;
    float g = 0;
    for (uint32_t side = f; side < f + 2; ++side)
      for (int k = 0; k < el[side].corners; ++k)
        for (uint32_t o : around[el[side].v[k]])
          if (o != side && smooth_neighbours(o, side))
            g = std::max(g, std::fabs(b_[o].luminance() - b_[side].luminance()) -
                                3.0f * std::hypot(noise_[o], noise_[side]));
    if (g > threshold) candidates.emplace_back(-g, f);
  }
  std::sort(candidates.begin(), candidates.end());
  const size_t room = budget_ > el.size() ? (budget_ - el.size()) / 6 : 0;
  if (candidates.size() > room) candidates.resize(room);
  std::vector<uint32_t> split;
  for (const auto& c : candidates) split.push_back(c.second);
  std::sort(split.begin(), split.end());
  return split;
}

// The display mesh's element radiosity from the hierarchy: gathered at the element's centroid
// through the links of the leaf there and its ancestors (HierarchicalRadiosity::gathered_at),
// in the top-level patch of the element's primitive and side. The display then interpolates
// corners as for the matrix, and the solution can be written and reused like any other.
void RadiosityIntegrator::resample_hierarchy(const RadiosityMesh& top) {
  const std::vector<RadiosityElement>& el = mesh_.elements();
  b_.assign(el.size(), Rgb{});
  parallel_for(
      el.size(),
      [&](size_t e) {
        const uint32_t t = top.locate(el[e].prim, el[e].centroid, el[e].normal);
        if (t != UINT32_MAX) b_[e] = hr_->gathered_at(t, el[e].centroid);
      },
      64);
}

std::vector<std::vector<uint32_t>> RadiosityIntegrator::elements_around_vertices() const {
  const std::vector<RadiosityElement>& el = mesh_.elements();
  std::vector<std::vector<uint32_t>> around(mesh_.vertices().size());
  for (uint32_t e = 0; e < el.size(); ++e)
    for (int k = 0; k < el[e].corners; ++k) around[el[e].v[k]].push_back(e);
  return around;
}

// Only within a shape (a light's radiosity must not bleed into the ceiling around it), and only
// elements facing the same way (creases stay sharp).
bool RadiosityIntegrator::smooth_neighbours(uint32_t a, uint32_t b) const {
  const std::vector<RadiosityElement>& el = mesh_.elements();
  const PrimitiveSet& prims = world_.primitives();
  return dot(el[a].normal, el[b].normal) >= kSmoothCos &&
         prims.origin(el[a].prim).shape == prims.origin(el[b].prim).shape;
}

void RadiosityIntegrator::average_corners() {
  const std::vector<RadiosityElement>& el = mesh_.elements();
  const std::vector<std::vector<uint32_t>> around = elements_around_vertices();
  corners_.assign(4 * el.size(), Rgb{});
  for (uint32_t e = 0; e < el.size(); ++e)
    for (int k = 0; k < el[e].corners; ++k) {
      // Area-weighted over the neighbours facing the same way.
      Rgb sum;
      float area = 0.0f;
      for (uint32_t o : around[el[e].v[k]])
        if (smooth_neighbours(o, e)) {
          sum += b_[o] * el[o].area;
          area += el[o].area;
        }
      corners_[4 * size_t(e) + size_t(k)] = area > 0.0f ? sum / area : b_[e];
    }
}

Rgb RadiosityIntegrator::radiosity_at(uint32_t e, Vec3 p) const {
  float w[4];
  mesh_.corner_weights(e, p, w);
  Rgb b;
  for (int k = 0; k < mesh_.elements()[e].corners; ++k)
    b += corners_[4 * size_t(e) + size_t(k)] * w[k];
  return b;
}

Rgb RadiosityIntegrator::gathered(const Ray& ray, RayCounter& counter) const {
  SurfaceInteraction y;
  if (!world_.intersect(ray, y, counter)) return {};
  const uint32_t e = mesh_.locate(y.prim, y.p, y.wo);
  if (e == UINT32_MAX) return {};
  // Reflected radiosity only: emission reached from the gather point is its direct light,
  // which the shadow ray counts.
  Rgb b = radiosity_at(e, y.p) - mesh_.elements()[e].emission;
  for (int c = 0; c < 3; ++c) b[c] = std::max(0.0f, b[c]);
  return b * std::numbers::inv_pi_v<float>;
}

Rgb RadiosityIntegrator::li(const Ray& ray, Sampler& sampler, RayCounter& counter) const {
  SurfaceInteraction si;
  if (!world_.intersect(ray, si, counter)) return world_.escaped(ray);
  const uint32_t e = mesh_.locate(si.prim, si.p, si.wo);
  if (e == UINT32_MAX) return si.emitted;
  if (show_elements_) {
    // Each element flat, in a colour of its own, scaled by its radiosity: the mesh as solved.
    const uint64_t h = mix64(e / 2 + 1);  // both sides of a piece alike
    const Rgb tint{0.4f + 0.6f * float(h & 255) / 255.0f,
                   0.4f + 0.6f * float((h >> 8) & 255) / 255.0f,
                   0.4f + 0.6f * float((h >> 16) & 255) / 255.0f};
    return tint * (b_[e].luminance() * std::numbers::inv_pi_v<float>);
  }
  if (!final_gather_) return radiosity_at(e, si.p) * std::numbers::inv_pi_v<float>;

  // Final gather: emission, direct light by a shadow ray, and one bounce into the solution,
  // all through the diffuse surface the solution assumes.
  const Rgb rho = mesh_.elements()[e].rho;
  const DiffuseMaterial diffuse(rho);
  const Vec3 wo = si.to_local(si.wo);
  Rgb l = si.emitted +
          estimate_direct(world_, light_sampler_, si, diffuse, wo, ray.time, sampler, counter);
  Rgb indirect;
  for (int g = 0; g < gather_rays_; ++g) {
    // Cosine-weighted on the side the camera sees: f cos / pdf = rho.
    Vec3 wi = sample_cosine_hemisphere(sampler.get_2d());
    if (wo.z < 0.0f) wi.z = -wi.z;
    indirect += rho * gathered(si.spawn_ray(si.to_world(wi), ray.time), counter);
  }
  return l + indirect / float(gather_rays_);
}

}  // namespace penumbra
