// Form factors against closed forms (Howell's catalogue), reciprocity, closed enclosures, thread
// independence and the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/core/parallel.h"
#include "penumbra/render/radiosity/form_factors.h"
#include "penumbra/render/radiosity/radiosity_mesh.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// Two directly opposed parallel a x b rectangles at distance c (Howell, "A Catalog of Radiation
/// Heat Transfer Configuration Factors", factor C-11; Siegel, Howell, "Thermal Radiation Heat
/// Transfer", appendix C).
double parallel_rectangles(double a, double b, double c) {
  const double x = a / c, y = b / c, x1 = 1 + x * x, y1 = 1 + y * y;
  return 2 / (kPi * x * y) *
         (std::log(std::sqrt(x1 * y1 / (x1 + y * y))) +
          x * std::sqrt(y1) * std::atan(x / std::sqrt(y1)) +
          y * std::sqrt(x1) * std::atan(y / std::sqrt(x1)) - x * std::atan(x) - y * std::atan(y));
}

/// From a w x l rectangle to a perpendicular h x l rectangle sharing the edge of length l
/// (Howell, factor C-14).
double perpendicular_rectangles(double w, double h, double l) {
  const double W = w / l, H = h / l, s = W * W + H * H;
  const double log_term = std::log((1 + W * W) * (1 + H * H) / (1 + s)) +
                          W * W * std::log(W * W * (1 + s) / ((1 + W * W) * s)) +
                          H * H * std::log(H * H * (1 + s) / ((1 + H * H) * s));
  return (W * std::atan(1 / W) + H * std::atan(1 / H) - std::sqrt(s) * std::atan(1 / std::sqrt(s)) +
          0.25 * log_term) /
         (kPi * W);
}

TEST(FormFactorClosedForms, ReproduceTheCatalogueValues) {
  EXPECT_NEAR(parallel_rectangles(1, 1, 1), 0.19982, 1e-5);
  EXPECT_NEAR(perpendicular_rectangles(1, 1, 1), 0.20004, 1e-5);
}

/// Two quads A (shape 0) and B (shape 1), each facing the other; json fragments for their origin
/// and edges.
std::string pair_scene(const std::string& a, const std::string& b) {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0], "vfov": 40}},
    "render": {{"resolution": [8, 8], "spp": 1}},
    "materials": {{"m": {{"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}}}},
    "shapes": [{{"type": "quad", {}, "material": "m"}}, {{"type": "quad", {}, "material": "m"}}]
  }})",
                     a, b);
}

/// a x b rectangles at z = 0 (front +z) and z = c (front -z).
std::string parallel_scene(double a, double b, double c) {
  return pair_scene(
      fmt::format(R"("origin": [0, 0, 0], "edge1": [{}, 0, 0], "edge2": [0, {}, 0])", a, b),
      fmt::format(R"("origin": [0, 0, {}], "edge1": [0, {}, 0], "edge2": [{}, 0, 0])", c, b, a));
}

/// A: w x l in the plane y = 0 (front +y); B: h x l in the plane x = 0 (front +x); common edge
/// along z.
std::string perpendicular_scene(double w, double h, double l) {
  return pair_scene(
      fmt::format(R"("origin": [0, 0, 0], "edge1": [0, 0, {}], "edge2": [{}, 0, 0])", l, w),
      fmt::format(R"("origin": [0, 0, 0], "edge1": [0, {}, 0], "edge2": [0, 0, {}])", h, l));
}

/// The area-weighted form factor between the front sides of shapes a and b:
/// F_ab = sum_{i in a} A_i sum_{j in b} F_ij / A_a.
double shape_factor(const World& world, const RadiosityMesh& mesh, const FormFactors& ff,
                    uint32_t a, uint32_t b) {
  auto front_of = [&](const RadiosityElement& e, uint32_t shape) {
    return world.primitives().origin(e.prim).shape == shape &&
           dot(e.normal, world.area_normal(e.prim)) > 0;
  };
  double sum = 0, area = 0;
  for (size_t i = 0; i < mesh.size(); ++i) {
    if (!front_of(mesh.elements()[i], a)) continue;
    area += mesh.elements()[i].area;
    for (size_t j = 0; j < mesh.size(); ++j)
      if (front_of(mesh.elements()[j], b)) sum += mesh.elements()[i].area * double(ff.at(i, j));
  }
  return sum / area;
}

struct Case {
  const char* name;
  std::string scene;
  double exact;
  double area_a, area_b;
};

std::vector<Case> cases() {
  return {
      {"parallel unit squares", parallel_scene(1, 1, 1), 0.19982, 1, 1},
      {"perpendicular unit squares", perpendicular_scene(1, 1, 1), 0.20004, 1, 1},
      {"parallel 2 x 1 at 0.5", parallel_scene(2, 1, 0.5), parallel_rectangles(2, 1, 0.5), 2, 2},
      {"perpendicular 0.5 to 2, edge 1", perpendicular_scene(0.5, 2, 1),
       perpendicular_rectangles(0.5, 2, 1), 0.5, 2}};
}

// Ray casting from single elements is unbiased: with N = 2^19 rays the estimate's standard
// deviation is sqrt(F (1 - F) / N), under 0.3% of F for these factors, so 1% is beyond 3.4
// sigma (checked). Reciprocity A_a F_ab = A_b F_ba holds within 4 sigma of the two estimates.
TEST(FormFactors, RaycastMatchesClosedForms) {
  const int rays = 1 << 19;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const World world(test::scene_from_text(c.scene), "bvh");
    const RadiosityMesh mesh = RadiosityMesh::build(world, 100.0f, 100);
    ASSERT_EQ(mesh.size(), 4u);
    const FormFactors ff = compute_form_factors(world, mesh, {"raycast", 64, rays, 1});
    const double f_ab = shape_factor(world, mesh, ff, 0, 1),
                 f_ba = shape_factor(world, mesh, ff, 1, 0);
    const double sigma = std::sqrt(c.exact * (1 - c.exact) / rays);
    ASSERT_LT(3.4 * sigma, 0.01 * c.exact);
    EXPECT_NEAR(f_ab, c.exact, 0.01 * c.exact);
    const double exact_ba = c.exact * c.area_a / c.area_b;
    EXPECT_NEAR(f_ba, exact_ba,
                std::max(0.01 * exact_ba, 4 * std::sqrt(exact_ba * (1 - exact_ba) / rays)));
    const double sigma_ba = std::sqrt(exact_ba * (1 - exact_ba) / rays);
    EXPECT_NEAR(c.area_a * f_ab, c.area_b * f_ba,
                4 * std::hypot(c.area_a * sigma, c.area_b * sigma_ba));
    EXPECT_LE(ff.max_row_sum, 1.0);
  }
}

// The hemicube gives point-to-area factors at element centroids, on a grid of cells: subdivided
// into patches of 1/8 (1/16 for the close 0.5 pair and its smaller sides), at resolution 128,
// the area-weighted sums lie within 1% of the closed forms, and so does reciprocity.
TEST(FormFactors, HemicubeMatchesClosedForms) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const World world(test::scene_from_text(c.scene), "bvh");
    const RadiosityMesh mesh = RadiosityMesh::build(world, 0.125f, 100000);
    const FormFactors ff = compute_form_factors(world, mesh, {"hemicube", 128, 1, 0});
    const double f_ab = shape_factor(world, mesh, ff, 0, 1),
                 f_ba = shape_factor(world, mesh, ff, 1, 0);
    EXPECT_NEAR(f_ab, c.exact, 0.01 * c.exact);
    EXPECT_NEAR(c.area_a * f_ab, c.area_b * f_ba, 0.01 * c.area_a * f_ab);
    EXPECT_LT(ff.reciprocity_error, 0.05);
    EXPECT_LE(ff.max_row_sum, 1.0 + 1e-5);
  }
}

/// A unit cube of six quads facing inwards (each face subdivided by the patch size).
std::string closed_box() {
  return R"({
    "camera": {"type": "pinhole", "position": [0.5, 0.5, 0.5], "look_at": [0.5, 0.5, 1],
               "vfov": 40},
    "render": {"resolution": [8, 8], "spp": 1},
    "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [
    {"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "m"},
    {"type": "quad", "origin": [0, 0, 1], "edge1": [0, 1, 0], "edge2": [1, 0, 0], "material": "m"},
    {"type": "quad", "origin": [0, 0, 0], "edge1": [0, 0, 1], "edge2": [1, 0, 0], "material": "m"},
    {"type": "quad", "origin": [0, 1, 0], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "material": "m"},
    {"type": "quad", "origin": [0, 0, 0], "edge1": [0, 1, 0], "edge2": [0, 0, 1], "material": "m"},
    {"type": "quad", "origin": [1, 0, 0], "edge1": [0, 0, 1], "edge2": [0, 1, 0], "material": "m"}
    ]
  })";
}

// Inside a closed box every ray from an inner side hits an inner side: those rows sum to 1 (the
// counts are exact; a ray slipping between two walls would lower it by 1/rays), the outer sides'
// rows to 0 (their rays escape). The hemicube's cells all see a wall and its delta form factors
// sum to 1, so its inner rows sum to 1 up to float rounding.
TEST(FormFactors, ClosedBoxRowsSumToOne) {
  const World world(test::scene_from_text(closed_box()), "bvh");
  const RadiosityMesh mesh = RadiosityMesh::build(world, 0.25f, 10000);
  ASSERT_EQ(mesh.size(), 6u * 16 * 2);
  for (const char* method : {"raycast", "hemicube"}) {
    SCOPED_TRACE(method);
    const FormFactors ff = compute_form_factors(world, mesh, {method, 32, 256, 3});
    for (size_t i = 0; i < mesh.size(); ++i) {
      const RadiosityElement& e = mesh.elements()[i];
      const bool inner = dot(e.normal, Vec3(0.5f) - e.centroid) > 0;
      double sum = 0;
      for (size_t j = 0; j < mesh.size(); ++j) {
        sum += ff.at(i, j);
        if (ff.at(i, j) > 0) {
          const RadiosityElement& o = mesh.elements()[j];
          ASSERT_GT(dot(o.normal, Vec3(0.5f) - o.centroid), 0.0f) << "only inner sides are seen";
        }
      }
      if (inner)
        EXPECT_NEAR(sum, 1.0, 1e-5) << "element " << i;
      else
        EXPECT_EQ(sum, 0.0) << "element " << i;
    }
    EXPECT_NEAR(ff.max_row_sum, 1.0, 1e-5);
    EXPECT_EQ(ff.min_row_sum, 0.0);
  }
}

// Inside a sphere of radius r every point sees every other with the same kernel: both cosines
// are d / (2 r) at distance d, so cos cos / (pi d^2) = 1 / (4 pi r^2) and F_ij = A_j / (4 pi r^2)
// for the true sphere. Ray casting traces the true sphere: inner rows sum to exactly 1 (outer
// ones to 0: their rays escape), an element even sees itself (it is concave from inside), and
// the hits split evenly between the hemispheres z > 0 and z < 0 (with n_lat = 4 the equator is a
// ring of the grid): 48 x 4096 rays give a standard deviation of 0.5 / sqrt(196608) = 0.0011 for
// the share, bounded at 4 sigma.
TEST(FormFactors, RaycastInsideASphereSeesTheTrueSphere) {
  const World world(test::scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [0, 0, 0], "look_at": [0, 0, 1], "vfov": 40},
    "render": {"resolution": [8, 8], "spp": 1},
    "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]
  })"),
                    "bvh");
  const RadiosityMesh mesh = RadiosityMesh::build(world, 0.8f, 1000);
  ASSERT_EQ(mesh.size(), 2u * 48);
  const int rays = 4096;
  const FormFactors ff = compute_form_factors(world, mesh, {"raycast", 64, rays, 5});
  double north = 0, area = 0;
  for (size_t i = 0; i < mesh.size(); ++i) {
    const RadiosityElement& e = mesh.elements()[i];
    const bool inner = dot(e.normal, e.centroid) < 0;
    double sum = 0;
    for (size_t j = 0; j < mesh.size(); ++j) {
      sum += ff.at(i, j);
      if (inner && mesh.elements()[j].centroid.z > 0) north += e.area * double(ff.at(i, j));
    }
    EXPECT_NEAR(sum, inner ? 1.0 : 0.0, 1e-6) << "element " << i;
    if (inner) {
      area += e.area;
      EXPECT_GT(ff.at(i, i), 0.0f) << "element " << i;
    }
  }
  EXPECT_NEAR(north / area, 0.5, 4 * 0.5 / std::sqrt(48.0 * rays));
}

// Rows are computed independently from per-element random numbers: the same bits on 1 and 2
// threads; a different seed changes them.
TEST(FormFactors, RaycastIsIndependentOfThreadCount) {
  const World world(test::scene_from_text(closed_box()), "bvh");
  const RadiosityMesh mesh = RadiosityMesh::build(world, 0.25f, 10000);
  FormFactors one, two, other;
  {
    const ThreadLimit limit(1);
    one = compute_form_factors(world, mesh, {"raycast", 64, 64, 9});
  }
  {
    const ThreadLimit limit(2);
    two = compute_form_factors(world, mesh, {"raycast", 64, 64, 9});
    other = compute_form_factors(world, mesh, {"raycast", 64, 64, 10});
  }
  EXPECT_EQ(one.f, two.f);
  EXPECT_NE(one.f, other.f);
}

TEST(FormFactors, RefusesBadOptionsAndOversizedMatrices) {
  const World world(test::scene_from_text(closed_box()), "bvh");
  const RadiosityMesh mesh = RadiosityMesh::build(world, 0.5f, 10000);
  EXPECT_THROW(compute_form_factors(world, mesh, {"radiant", 64, 64, 0}), Error);
  EXPECT_THROW(compute_form_factors(world, mesh, {"hemicube", 63, 64, 0}), Error);
  EXPECT_THROW(compute_form_factors(world, mesh, {"raycast", 64, 0, 0}), Error);
  // 6 x 64^2 pieces: 49152 elements, a 9 GiB matrix, beyond a limit of 2 GiB (set here: the
  // default limit depends on the machine).
  const ScopedMemoryLimit limit(uint64_t(2) << 30);
  const RadiosityMesh big = RadiosityMesh::build(world, 1.0f / 64, 100000);
  ASSERT_EQ(big.size(), 49152u);
  try {
    compute_form_factors(world, big, {"raycast", 64, 1, 0});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("49152 elements needs 9.0 GiB"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace penumbra
