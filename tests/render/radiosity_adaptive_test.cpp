// Adaptive subdivision of the radiosity mesh: it refines where the solution changes, reaches the
// accuracy of a uniformly fine mesh with a fraction of its elements, keeps to its budget, leaves
// a uniform solution alone despite ray casting's noise, and its solutions can be saved and
// reused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/render/radiosity/radiosity_integrator.h"
#include "penumbra/render/radiosity/radiosity_solution.h"
#include "penumbra/render/render_job.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// A 2 x 2 floor (albedo 0.7) seen from above, lit by a 0.3 x 0.3 light at height 1.2, with a
/// black 0.4 x 0.4 occluder at height 0.6 whose shadow (with its penumbra) falls beside it.
std::string shadow_scene(const std::string& integrator) {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0],
                "vfov": 22.6}},
    "render": {{"resolution": [48, 48], "spp": 4, "seed": 1, "integrator": "{}"}},
    "materials": {{"white": {{"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
                   "black": {{"type": "diffuse", "albedo": [0, 0, 0]}}}},
    "shapes": [
      {{"type": "quad", "origin": [-1, -1, 0], "edge1": [2, 0, 0], "edge2": [0, 2, 0],
        "material": "white"}},
      {{"type": "quad", "origin": [0.1, 0.1, 0.6], "edge1": [0.4, 0, 0], "edge2": [0, 0.4, 0],
        "material": "black"}},
      {{"type": "quad", "origin": [-0.15, -0.15, 1.2], "edge1": [0, 0.3, 0],
        "edge2": [0.3, 0, 0], "material": "black", "emission": [20, 20, 20]}}
    ]
  }})",
                     integrator);
}

struct Solved {
  RgbImage image;
  RadiosityReport report;
};

Solved solve(const std::string& integrator) {
  RenderJob job(test::scene_from_text(shadow_scene(integrator)));
  job.run();
  return {job.film->resolve(), dynamic_cast<const RadiosityIntegrator&>(*job.integrator).report()};
}

double rmse(const RgbImage& a, const RgbImage& b) {
  double s = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const double d = a.at(x, y).g - b.at(x, y).g;
      s += d * d;
    }
  return std::sqrt(s / double(a.width() * a.height()));
}

// Against path (converged: only direct light and one floor reflection reach the camera), the
// Gouraud display's error comes from the mesh: patches of 0.25 blur the shadow (measured RMSE
// 0.0137), uniform patches of 0.0625 leave 0.0079 (what Gouraud shading of a penumbra can do at
// that size), and two rounds of adaptive subdivision from 0.25 (down to 0.0625 where neighbours
// differ by more than 0.3 of the mean) reach 0.0088 with 864 elements instead of 2196. The
// hemicube is deterministic; at resolution 128 its aliasing on these dyadic sizes is below
// 0.1 % of the mean.
TEST(RadiosityAdaptive, ApproachesAFineMeshWithAFractionOfItsElements) {
  const RgbImage path = test::render_desc(test::scene_from_text(shadow_scene("path")), 0);
  const std::string common = "radiosity:final_gather=false,form_factors=hemicube,resolution=128";
  const Solved coarse = solve(common + ",patch=0.25");
  const Solved fine = solve(common + ",patch=0.0625");
  const Solved adaptive = solve(common + ",patch=0.25,adapt=2");
  const double e_coarse = rmse(coarse.image, path), e_fine = rmse(fine.image, path),
               e_adaptive = rmse(adaptive.image, path);
  ASSERT_LT(e_fine, e_coarse);
  EXPECT_LT(e_adaptive - e_fine, 0.25 * (e_coarse - e_fine))
      << e_coarse << " " << e_fine << " " << e_adaptive;
  EXPECT_LT(double(adaptive.report.elements), 0.5 * double(fine.report.elements));
  ASSERT_EQ(adaptive.report.round_elements.size(), 2u);
  EXPECT_GT(adaptive.report.round_elements[0], coarse.report.elements);
  EXPECT_GT(adaptive.report.round_elements[1], adaptive.report.round_elements[0]);
}

// The budget caps the elements whatever the rounds ask for.
TEST(RadiosityAdaptive, KeepsToTheElementBudget) {
  const Solved s = solve(
      "radiosity:final_gather=false,form_factors=hemicube,patch=0.25,adapt=4,"
      "adapt_threshold=0.01,budget=400");
  EXPECT_LE(s.report.elements, 400u);
  EXPECT_GT(s.report.elements, 400u - 6u);
}

// A small emitting sphere at the centre of a large closed one lights it uniformly (by symmetry,
// and a sphere's form factor to any part of itself is the same from every point), so the true
// radiosity is the same on every element of each sphere and nothing should be split. With 256
// rays per element, about 4 of them hit the small sphere: ray casting's noise alone makes
// neighbours differ by tens of percent of the mean, which the three-sigma guard must not take for
// a gradient.
TEST(RadiosityAdaptive, NoiseIsNotAGradient) {
  const std::string json = R"({
    "camera": {"type": "pinhole", "position": [0.1, 0.2, -1.3], "look_at": [0.5, 0, 1],
               "vfov": 90},
    "render": {"resolution": [8, 8], "spp": 4, "seed": 3,
               "integrator": "radiosity:patch=0.5,rays=256,adapt=1,final_gather=false"},
    "materials": {"m": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                  "black": {"type": "diffuse", "albedo": [0, 0, 0]}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 2, "material": "m"},
               {"type": "sphere", "center": [0, 0, 0], "radius": 0.25, "material": "black",
                "emission": [50, 50, 50]}]
  })";
  RenderJob job(test::scene_from_text(json));
  job.run();
  const auto& ri = dynamic_cast<const RadiosityIntegrator&>(*job.integrator);
  EXPECT_TRUE(ri.report().round_elements.empty()) << ri.report().elements;
}

// An adaptive solution written by `penumbra radiosity` carries its subdivision, so a render of
// the same scene rebuilds the mesh and shows the same bits; a split list naming a back element
// is refused with the file and line.
TEST(RadiosityAdaptive, SavedSolutionCarriesItsSubdivision) {
  const std::string file = testing::TempDir() + "/penumbra_adaptive_solution.ply";
  RgbImage solved;
  {
    RenderJob job(test::scene_from_text(shadow_scene(
        "radiosity:final_gather=false,form_factors=hemicube,patch=0.25,adapt=2")));
    job.run();
    solved = job.film->resolve();
    const auto& ri = dynamic_cast<const RadiosityIntegrator&>(*job.integrator);
    ASSERT_EQ(ri.mesh().refinements().size(), 2u);
    write_radiosity_solution(file, ri.mesh(), ri.corner_radiosity(), "test");
  }
  EXPECT_TRUE(test::render_desc(test::scene_from_text(shadow_scene(
                  "radiosity:final_gather=false,patch=0.25,solution=" + file))) == solved);
  // Corrupt the first split: an odd (back) element.
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const size_t at = bytes.find("comment split ");
  ASSERT_NE(at, std::string::npos);
  const size_t digit = bytes.find_first_of("0123456789", at);
  const size_t end = bytes.find_first_not_of("0123456789", digit);
  const unsigned long first = std::stoul(bytes.substr(digit, end - digit));
  bytes.replace(digit, end - digit, std::to_string(first + 1));
  const std::string bad = testing::TempDir() + "/penumbra_adaptive_bad.ply";
  {
    std::ofstream out(bad, std::ios::binary);
    out << bytes;
  }
  try {
    test::render_desc(test::scene_from_text(
        shadow_scene("radiosity:final_gather=false,patch=0.25,solution=" + bad)));
    ADD_FAILURE() << "a corrupt split list was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(bad), std::string::npos) << what;
    EXPECT_NE(what.find("line 4"), std::string::npos) << what;
  }
  std::remove(file.c_str());
  std::remove(bad.c_str());
}

}  // namespace
}  // namespace penumbra
