#include "penumbra/scene/pbrt_options.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

namespace penumbra {

namespace {

using nlohmann::json;

// pbrt-v4's defaults when a directive is absent.
constexpr int kDefaultWidth = 1280, kDefaultHeight = 720, kDefaultSpp = 16, kDefaultDepth = 5;

void map_film(const std::optional<PbrtEntity>& film, SceneDesc& scene) {
  RenderSettings& r = scene.render;
  r.width = kDefaultWidth, r.height = kDefaultHeight;
  if (!film) return;
  const PbrtEntity& f = *film;
  if (f.type != "rgb")
    pbrt_warn(scene.warnings, f.loc,
              "Film \"" + f.type + "\" read as \"rgb\" (penumbra writes one RGB image)");
  r.width = f.params.get_int("xresolution", kDefaultWidth);
  r.height = f.params.get_int("yresolution", kDefaultHeight);
  if (r.width < 1 || r.width > 65536 || r.height < 1 || r.height > 65536)
    f.loc.fail("film resolution " + std::to_string(r.width) + "x" + std::to_string(r.height) +
               " out of range [1, 65536]");
  const std::string out = f.params.get_string("filename", "");
  if (!out.empty())
    pbrt_warn(scene.warnings, f.loc,
              "Film filename \"" + out + "\" ignored: the output file is the -o option");
  f.params.report_unused(scene.warnings, f.what("Film"));
}

void map_sampler(const std::optional<PbrtEntity>& sampler, SceneDesc& scene) {
  RenderSettings& r = scene.render;
  r.spp = kDefaultSpp;
  r.sampler = "sobol";  // nearest to pbrt's default, zsobol
  if (!sampler) return;
  const PbrtEntity& s = *sampler;
  if (s.type == "stratified") {
    const int nx = s.params.get_int("xsamples", 4), ny = s.params.get_int("ysamples", 4);
    if (nx < 1 || ny < 1) s.loc.fail("xsamples and ysamples must be at least 1");
    r.spp = nx * ny;
    r.sampler = s.params.get_bool("jitter", true) ? "jittered" : "regular";
  } else {
    r.spp = s.params.get_int("pixelsamples", kDefaultSpp);
    if (r.spp < 1) s.loc.fail("pixelsamples must be at least 1");
    if (s.type == "independent") {
      r.sampler = "independent";
    } else if (s.type == "paddedsobol") {
      r.sampler = "sobol";  // both: Owen-scrambled Sobol' points per pair of dimensions
    } else if (s.type == "sobol" || s.type == "zsobol" || s.type == "halton" ||
               s.type == "pmj02bn") {
      pbrt_warn(scene.warnings, s.loc,
                "Sampler \"" + s.type +
                    "\" rendered with penumbra's \"sobol\" (Owen-scrambled Sobol' points per "
                    "pair of dimensions)");
    } else {
      s.loc.fail("unknown Sampler \"" + s.type +
                 "\" (pbrt-v4 has: halton, independent, paddedsobol, pmj02bn, sobol, "
                 "stratified, zsobol)");
    }
    s.params.get_string("randomization", "");
  }
  const int seed = s.params.get_int("seed", 0);
  r.seed = uint64_t(int64_t(seed));
  s.params.report_unused(scene.warnings, s.what("Sampler"));
}

void map_filter(const std::optional<PbrtEntity>& filter, SceneDesc& scene) {
  RenderSettings& r = scene.render;
  r.filter = "gaussian:radius=1.5,sigma=0.5";  // pbrt-v4's default filter
  if (!filter) return;
  const PbrtEntity& f = *filter;
  struct Default {
    const char* ours;
    double radius;
  };
  Default d;
  if (f.type == "box")
    d = {"box", 0.5};
  else if (f.type == "triangle")
    d = {"tent", 2.0};
  else if (f.type == "gaussian")
    d = {"gaussian", 1.5};
  else if (f.type == "mitchell")
    d = {"mitchell", 2.0};
  else if (f.type == "sinc")
    d = {"mitchell", 4.0};
  else
    f.loc.fail("unknown PixelFilter \"" + f.type +
               "\" (pbrt-v4 has: box, gaussian, mitchell, sinc, triangle)");
  const double rx = f.params.get_float("xradius", d.radius);
  const double ry = f.params.get_float("yradius", d.radius);
  double radius = rx;
  if (rx != ry) {
    radius = std::max(rx, ry);
    pbrt_warn(scene.warnings, f.loc,
              "PixelFilter radii " + pbrt_format_number(rx) + " and " + pbrt_format_number(ry) +
                  " differ; penumbra's filters have one radius, " + pbrt_format_number(radius) +
                  " is used");
  }
  if (!(radius >= 0.01 && radius <= 16)) f.loc.fail("filter radius must lie in [0.01, 16]");
  std::string s = std::string(d.ours) + ":radius=" + pbrt_format_number(radius);
  if (f.type == "gaussian") s += ",sigma=" + pbrt_format_number(f.params.get_float("sigma", 0.5));
  if (f.type == "mitchell")
    s += ",b=" + pbrt_format_number(f.params.get_float("B", 1.0 / 3.0)) +
         ",c=" + pbrt_format_number(f.params.get_float("C", 1.0 / 3.0));
  if (f.type == "sinc") {
    f.params.get_float("tau", 3.0);
    pbrt_warn(scene.warnings, f.loc,
              "PixelFilter \"sinc\" (windowed sinc) rendered with penumbra's \"mitchell\" of the "
              "same radius");
  }
  r.filter = s;
  f.params.report_unused(scene.warnings, f.what("PixelFilter"));
}

void map_integrator(const std::optional<PbrtEntity>& integrator, SceneDesc& scene) {
  RenderSettings& r = scene.render;
  r.integrator = "path";  // pbrt-v4's default is volpath, which is path without media
  r.max_depth = kDefaultDepth;
  if (!integrator) return;
  const PbrtEntity& i = *integrator;
  r.max_depth = i.params.get_int("maxdepth", kDefaultDepth);
  if (*r.max_depth < 0) i.loc.fail("maxdepth must not be negative");
  if (i.type == "sppm") {
    r.integrator = "sppm";
  } else if (i.type != "path") {
    static const char* const kPathLike[] = {
        "volpath",          "bdpt", "mlt", "lightpath", "randomwalk", "simplepath", "simplevolpath",
        "ambientocclusion", "aov"};
    if (std::find_if(std::begin(kPathLike), std::end(kPathLike),
                     [&](const char* n) { return i.type == n; }) == std::end(kPathLike))
      i.loc.fail("unknown Integrator \"" + i.type + "\"");
    pbrt_warn(scene.warnings, i.loc,
              "Integrator \"" + i.type + "\" rendered with penumbra's \"path\" (nearest)");
  }
  i.params.get_bool("regularize", false);  // no path regularisation in penumbra: same image
  i.params.get_string("lightsampler", "");
  i.params.report_unused(scene.warnings, i.what("Integrator"));
}

void map_accelerator(const std::optional<PbrtEntity>& accel, SceneDesc& scene) {
  if (!accel) return;
  if (accel->type == "bvh" || accel->type == "kdtree") {
    scene.render.accel = accel->type;
  } else {
    pbrt_warn(scene.warnings, accel->loc,
              "Accelerator \"" + accel->type + "\" unknown; penumbra's bvh is used");
  }
  accel->params.report_unused(scene.warnings, accel->what("Accelerator"));
}

void map_camera(const PbrtOptions& o, const Transform& world_from_pbrt, SceneDesc& scene) {
  double fov = 90, lens_radius = 0, focal_distance = 1e6, open = 0, close = 1;
  std::vector<double> window;  // screenwindow, when given
  if (o.camera) {
    const PbrtEntity& c = *o.camera;
    if (c.type != "perspective")
      c.loc.fail("Camera \"" + c.type +
                 "\" is not supported (penumbra has pinhole and thin-lens perspective cameras)");
    fov = c.params.get_float("fov", 90);
    lens_radius = c.params.get_float("lensradius", 0);
    focal_distance = c.params.get_float("focaldistance", 1e6);
    if (!(fov > 0 && fov < 180)) c.loc.fail("fov must lie in (0, 180) degrees");
    if (lens_radius < 0) c.loc.fail("lensradius must not be negative");
    if (!(focal_distance > 0)) c.loc.fail("focaldistance must be positive");
    if (const PbrtParam* sw = c.params.find("screenwindow", "float")) {
      if (sw->numbers.size() != 4)
        sw->loc.fail("screenwindow takes four numbers [x0 x1 y0 y1], got " +
                     std::to_string(sw->numbers.size()));
      const std::vector<double>& v = sw->numbers;
      if (!(v[0] < v[1] && v[2] < v[3]))
        sw->loc.fail("screenwindow [x0 x1 y0 y1] must have x0 < x1 and y0 < y1");
      if (!std::all_of(v.begin(), v.end(), [](double x) { return std::abs(x) <= 1e6; }))
        sw->loc.fail("screenwindow values must lie within ±1e6");
      window = v;
    }
    open = c.params.get_float("shutteropen", 0);
    close = c.params.get_float("shutterclose", 1);
    if (close < open) {  // as pbrt-v4
      pbrt_warn(scene.warnings, c.loc,
                "shutterclose " + pbrt_format_number(close) + " is before shutteropen " +
                    pbrt_format_number(open) + "; they are swapped");
      std::swap(open, close);
    }
    c.params.report_unused(scene.warnings, c.what("Camera"));
  }
  // pbrt's fov spans the shorter image axis; penumbra's vfov the vertical one. With a
  // screenwindow both use the fov's tangent as the unit of the window (pbrt's screen space).
  const int w = scene.render.width, h = scene.render.height;
  double vfov = fov;
  if (w < h && window.empty()) {
    const double t = std::tan(fov * std::numbers::pi / 360.0) * double(h) / double(w);
    vfov = std::atan(t) * 360.0 / std::numbers::pi;
  }
  // The eye, viewing direction and up vector in penumbra's world.
  const Transform c = world_from_pbrt * o.camera_to_world;
  const Vec3 eye = c.point({0, 0, 0});
  const Vec3 dir = normalize(c.vector({0, 0, 1}));
  const Vec3 up = normalize(c.vector({0, 1, 0}));
  // A look-at point as far from the eye as the eye from the origin keeps the direction's
  // precision in float.
  const float reach = std::max(1.0f, length(eye));
  const Vec3 target = eye + dir * reach;
  json cam = {{"type", lens_radius > 0 ? "thin_lens" : "pinhole"},
              {"position", {eye.x, eye.y, eye.z}},
              {"look_at", {target.x, target.y, target.z}},
              {"up", {up.x, up.y, up.z}},
              {"vfov", vfov}};
  if (lens_radius > 0) {
    cam["aperture_radius"] = lens_radius;
    cam["focus_distance"] = focal_distance;
  }
  if (!window.empty()) cam["screen_window"] = window;
  const double span = o.end_time - o.start_time;
  cam["shutter"] = {(open - o.start_time) / span, (close - o.start_time) / span};
  const PbrtLoc at = o.camera ? o.camera->loc : PbrtLoc{scene.file, 1, 1};
  scene.camera = SceneParams(std::move(cam), at.str(), "");
}

}  // namespace

bool pbrt_camera_mirrors(const Transform& camera_to_world) {
  const auto& m = camera_to_world.matrix().m;
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return det > 0;
}

void map_pbrt_options(const PbrtOptions& options, const Transform& world_from_pbrt,
                      SceneDesc& scene) {
  map_film(options.film, scene);
  map_sampler(options.sampler, scene);
  map_filter(options.filter, scene);
  map_integrator(options.integrator, scene);
  map_accelerator(options.accelerator, scene);
  map_camera(options, world_from_pbrt, scene);
}

}  // namespace penumbra
