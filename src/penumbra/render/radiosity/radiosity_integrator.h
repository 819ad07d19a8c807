#pragma once
/// `radiosity`: diffuse global illumination as a linear system over a patch mesh, solved before
/// the first pass and displayed per camera sample (Goral, Torrance, Greenberg, Battaile 1984,
/// "Modeling the Interaction of Light Between Diffuse Surfaces"; Cohen, Wallace 1993,
/// "Radiosity and Realistic Image Synthesis").
#include <memory>
#include <string>
#include <vector>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/light/light_sampler.h"
#include "penumbra/render/radiosity/form_factors.h"
#include "penumbra/render/radiosity/radiosity_mesh.h"
#include "penumbra/render/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

class HierarchicalRadiosity;

/// What the last solve did, for the CLI's report and the benchmarks.
struct RadiosityReport {
  size_t elements = 0;
  double mesh_seconds = 0, form_factor_seconds = 0, solve_seconds = 0;
  size_t matrix_bytes = 0;  ///< the dense form factors (0 with the hierarchy)
  double reciprocity_error = 0, min_row_sum = 0, max_row_sum = 0;
  int iterations = 0;
  std::vector<double> residuals;  ///< per iteration (the hierarchy: per gather the change)
  size_t links = 0, nodes = 0, hierarchy_bytes = 0;  ///< with the hierarchy
  size_t top_patches = 0, clusters = 0, leaves = 0;  ///< with the hierarchy
  double refine_seconds = 0, gather_seconds = 0;     ///< with the hierarchy: parts of solve
  bool loaded = false;                               ///< the solution came from a file
  std::vector<size_t> round_elements;  ///< elements after each adaptive subdivision
};

/// The preprocess meshes every surface into patches of about `patch` world units, computes the
/// form factors (ray casting through the world's accelerator, or the hemicube) and solves the
/// radiosity system (Gauss-Seidel, Jacobi or progressive refinement), or, with `hierarchy`,
/// solves by hierarchical radiosity with links instead of a matrix (Hanrahan, Salzman,
/// Aupperle 1991): the top level is then one patch per primitive, which the hierarchy subdivides
/// where the light changes down to leaves of a quarter patch, and the display mesh's elements
/// take the mean of the leaves over them (so display and saved solutions work alike). Each
/// element's radiosity is averaged to its corners over the neighbouring elements that face the same
/// way, so a camera sample sees the Gouraud-interpolated radiosity B(x) / pi of the element it
/// hits; with `final_gather` (the default) it sees instead the emission, direct light by a shadow
/// ray and one bounce of gather rays into the solution, which sharpens shadows and hides the mesh.
/// Only emissive shapes are the solution's light sources; point, directional and environment lights
/// reach the image only through the final gather's direct term (a warning says so). Non-diffuse
/// materials are treated as diffuse with their albedo (a warning names them).
///
/// Parameters (defaults): patch [diagonal / 25], max_elements [200000], form_factors [raycast;
/// hemicube], rays [1024], resolution [64], solver [gauss-seidel; jacobi, progressive],
/// tolerance [1e-4], max_iterations [1000], adapt [0] rounds of adaptive subdivision (split
/// each piece whose radiosity differs from a neighbour's by more than adapt_threshold [0.3]
/// times the mean, then form factors and solve again) within budget [12000] elements,
/// hierarchy [false], epsilon [the hierarchy's link
/// threshold], final_gather [true], gather [1] rays per sample, solution [a .ply written by
/// `penumbra radiosity` to reuse instead of solving], show [none; elements: each element flat in
/// a colour of its own, to see the mesh].
class RadiosityIntegrator final : public SamplingIntegrator {
 public:
  RadiosityIntegrator(const World& world, const ParamList& params, const RenderSettings& settings);
  ~RadiosityIntegrator() override;
  std::string name() const override;
  void preprocess(RenderJob& job) override;
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;

  /// Builds the mesh and solves (or loads the solution); the preprocess step, callable alone.
  void solve(RenderJob& job);
  const RadiosityMesh& mesh() const { return mesh_; }
  /// Per element, its radiosity (W/m^2).
  const std::vector<Rgb>& radiosity() const { return b_; }
  /// Per element and corner (4 per element), the radiosity interpolated for display.
  const std::vector<Rgb>& corner_radiosity() const { return corners_; }
  /// The hierarchical solution (null unless `hierarchy`): its leaves are the display's patches.
  const HierarchicalRadiosity* hierarchy() const { return hr_.get(); }
  const RadiosityReport& report() const { return report_; }

 private:
  /// The Gouraud-interpolated radiosity of element e at p.
  Rgb radiosity_at(uint32_t e, Vec3 p) const;
  /// Averages element radiosity to the element corners (over neighbours facing the same way).
  void solve_matrix(RenderJob& job);
  std::vector<uint32_t> adaptive_split() const;
  void resample_hierarchy(const RadiosityMesh& top);
  /// Per vertex of the mesh, the elements that have it as a corner.
  std::vector<std::vector<uint32_t>> elements_around_vertices() const;
  /// Whether elements a and b are smoothed across at a shared corner.
  bool smooth_neighbours(uint32_t a, uint32_t b) const;
  void average_corners();
  /// Radiance reflected (not emitted) by the surface a gather ray reached.
  Rgb gathered(const Ray& ray, RayCounter& counter) const;

  const World& world_;
  float patch_;
  size_t max_elements_;
  FormFactorOptions ff_options_;
  SolveOptions solve_options_;
  bool hierarchy_;
  int adapt_rounds_ = 0;
  double adapt_threshold_ = 0.3;
  size_t budget_ = 12000;
  std::vector<float> noise_;  ///< per element: ray casting's standard deviation of B
  double epsilon_;
  int link_grid_;
  std::string clusters_;  ///< "auto", "true" or "false"
  bool final_gather_;
  bool show_elements_ = false;
  int gather_rays_;
  std::string solution_file_;
  LightSampler light_sampler_;
  RadiosityMesh mesh_;
  std::vector<Rgb> b_, corners_;
  std::unique_ptr<HierarchicalRadiosity> hr_;  ///< the hierarchical solution, when used
  RadiosityReport report_;
};

}  // namespace penumbra
