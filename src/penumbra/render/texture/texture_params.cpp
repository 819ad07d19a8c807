#include "penumbra/render/texture/texture_params.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>

#include <fmt/format.h>

#include "penumbra/image/image_io.h"
#include "penumbra/scene/json_value.h"

namespace penumbra {

namespace {

/// Checks that every channel of `c` lies in [lo, hi], failing at `place`.
Rgb checked(Rgb c, const JsonPlace& place, float lo, float hi) {
  for (int i = 0; i < 3; ++i)
    if (!(c[i] >= lo && c[i] <= hi)) place.fail(fmt::format("must lie in [{}, {}]", lo, hi));
  return c;
}

/// A positive finite number.
float positive(const SceneParams& p, const std::string& key, float value) {
  if (!(value > 0.0f) || !std::isfinite(value)) p.fail(key, "must be a positive number");
  return value;
}

/// The pair "colors": [C0, C1] of a texture, default (black, white).
void read_colors(const SceneParams& tex, float lo, float hi, Rgb& c0, Rgb& c1) {
  c0 = Rgb(0.0f);
  c1 = Rgb(std::min(1.0f, hi));
  const nlohmann::json* v = tex.get_json("colors");
  if (!v) return;
  const JsonPlace place = JsonPlace{tex.file(), tex.path()}.key("colors");
  const nlohmann::json& a = json_array(*v, place);
  if (a.size() != 2) place.fail(fmt::format("expected an array of 2 colours, got {}", a.size()));
  c0 = checked(json_rgb(a[0], place.index(0)), place.index(0), lo, hi);
  c1 = checked(json_rgb(a[1], place.index(1)), place.index(1), lo, hi);
}

/// The embedded image named `path`, or nullptr.
const EmbeddedImage* find_embedded(const std::vector<EmbeddedImage>* embedded,
                                   const std::string& path) {
  if (!embedded) return nullptr;
  for (const EmbeddedImage& e : *embedded)
    if (e.name == path && e.bytes) return &e;
  return nullptr;
}

/// The image at `path` (a file, or one of `embedded`), decoded once per process while any texture
/// holds it (materials sharing a file share its pixels), every pixel times `factor` checked to lie
/// in [lo, hi].
std::shared_ptr<const RgbImage> texture_image(const SceneParams& tex, const std::string& path,
                                              const std::vector<EmbeddedImage>* embedded,
                                              Rgb factor, float lo, float hi) {
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<const RgbImage>> cache;
  // Embedded images are keyed by their bytes too: two scenes may reuse a name ("a.glb#/images/0").
  const EmbeddedImage* e = find_embedded(embedded, path);
  const std::string key = e ? fmt::format("embedded:{}:{}:{:x}", path, e->bytes->size(),
                                          std::hash<std::string_view>{}(*e->bytes))
                            : path;
  std::shared_ptr<const RgbImage> image;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    image = cache[key].lock();
  }
  if (!image) {
    std::error_code ec;
    if (!e && !std::filesystem::is_regular_file(path, ec))
      tex.fail("file", "image not found: " + path);
    try {
      image =
          std::make_shared<const RgbImage>(e ? decode_image(*e->bytes, path) : read_image(path));
    } catch (const Error& err) {
      tex.fail("file", std::string("cannot read the texture: ") + err.what());
    }
    if (image->empty()) tex.fail("file", "the image has no pixels: " + path);
    const std::lock_guard<std::mutex> lock(mutex);
    cache[key] = image;
  }
  for (int y = 0; y < image->height(); ++y)
    for (int x = 0; x < image->width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = image->at(x, y)[c] * factor[c];
        if (!(v >= lo && v <= hi))
          tex.fail("file", fmt::format("{}: pixel ({}, {}) is {}; a texture here must lie in "
                                       "[{}, {}]",
                                       path, x, y, v, lo, hi));
      }
  return image;
}

/// One wrap mode by name.
Texture::Wrap parse_wrap(const nlohmann::json& v, const JsonPlace& place) {
  const std::string name = json_string(v, place);
  if (name == "repeat") return Texture::Wrap::kRepeat;
  if (name == "clamp") return Texture::Wrap::kClamp;
  if (name == "black") return Texture::Wrap::kBlack;
  if (name == "mirror") return Texture::Wrap::kMirror;
  place.fail("unknown wrap '" + name + "' (valid: repeat, clamp, black, mirror)");
}

/// "wrap": one mode for both axes, or [s, t]; default repeat.
void read_wrap(const SceneParams& tex, Texture::Wrap& s, Texture::Wrap& t) {
  s = t = Texture::Wrap::kRepeat;
  const nlohmann::json* v = tex.get_json("wrap");
  if (!v) return;
  const JsonPlace place = JsonPlace{tex.file(), tex.path()}.key("wrap");
  if (!v->is_array()) {
    s = t = parse_wrap(*v, place);
    return;
  }
  if (v->size() != 2) place.fail(fmt::format("expected 2 wrap modes [s, t], got {}", v->size()));
  s = parse_wrap((*v)[0], place.index(0));
  t = parse_wrap((*v)[1], place.index(1));
}

/// The texture described by the object `tex`.
Texture parse_texture(const SceneParams& tex, float lo, float hi,
                      const std::vector<EmbeddedImage>* embedded) {
  const JsonPlace here{tex.file(), tex.path()};
  Texture t;
  Rgb c0, c1;
  if (tex.type() == "constant") {
    const nlohmann::json* v = tex.get_json("color");
    if (!v) here.fail("missing required key \"color\"");
    t = Texture::constant(checked(json_rgb(*v, here.key("color")), here.key("color"), lo, hi));
  } else if (tex.type() == "checkerboard") {
    const nlohmann::json* s = tex.get_json("scale");
    if (!s) here.fail("missing required key \"scale\"");
    const std::string space = tex.get_string("space", "uv");
    read_colors(tex, lo, hi, c0, c1);
    if (space == "uv") {
      const Vec2 scale = s->is_array() ? json_vec2(*s, here.key("scale"))
                                       : Vec2(json_float(*s, here.key("scale")),
                                              json_float(*s, here.key("scale")));
      positive(tex, "scale", scale.x);
      positive(tex, "scale", scale.y);
      t = Texture::checkerboard(scale, c0, c1);
    } else if (space == "world") {
      t = Texture::checkerboard_3d(positive(tex, "scale", json_float(*s, here.key("scale"))), c0,
                                   c1);
    } else {
      tex.fail("space", "unknown space '" + space + "' (valid: uv, world)");
    }
  } else if (tex.type() == "zone_plate") {
    const float k = positive(tex, "k", tex.require_float("k"));
    const nlohmann::json* c = tex.get_json("center");
    const Vec2 center = c ? json_vec2(*c, here.key("center")) : Vec2(0.5f, 0.5f);
    read_colors(tex, lo, hi, c0, c1);
    t = Texture::zone_plate(k, center, c0, c1);
  } else if (tex.type() == "image") {
    const std::string path = tex.get_string("file", "");
    if (path.empty()) here.fail("missing required key \"file\"");
    Vec2 scale(1.0f, 1.0f), offset(0.0f, 0.0f);
    if (const nlohmann::json* v = tex.get_json("scale"))
      scale = v->is_array()
                  ? json_vec2(*v, here.key("scale"))
                  : Vec2(json_float(*v, here.key("scale")), json_float(*v, here.key("scale")));
    if (!std::isfinite(scale.x) || !std::isfinite(scale.y) || scale.x == 0 || scale.y == 0)
      tex.fail("scale", "must be finite and non-zero");
    if (const nlohmann::json* v = tex.get_json("offset"))
      offset = json_vec2(*v, here.key("offset"));
    if (!std::isfinite(offset.x) || !std::isfinite(offset.y)) tex.fail("offset", "must be finite");
    Texture::Wrap wrap_s, wrap_t;
    read_wrap(tex, wrap_s, wrap_t);
    Rgb factor(1.0f);
    if (const nlohmann::json* v = tex.get_json("factor"))
      factor = checked(json_rgb(*v, here.key("factor")), here.key("factor"), 0.0f, 1.0f);
    t = Texture::image(texture_image(tex, path, embedded, factor, lo, hi), scale, offset, wrap_s,
                       wrap_t, factor);
  } else {
    tex.fail("type", "unknown texture type '" + tex.type() + "' (valid: " + kTextureTypes + ")");
  }
  tex.check_all_used();
  return t;
}

}  // namespace

Texture read_texture(const SceneParams& params, const std::string& key, Rgb fallback, float lo,
                     float hi, const std::vector<EmbeddedImage>* embedded) {
  const nlohmann::json* v = params.get_json(key);
  if (!v) return Texture::constant(fallback);
  const JsonPlace place = JsonPlace{params.file(), params.path()}.key(key);
  if (v->is_object())
    return parse_texture(SceneParams(*v, place.file, place.path), lo, hi, embedded);
  // A plain colour: the message of the untextured materials.
  const Rgb c = json_rgb(*v, place);
  for (int i = 0; i < 3; ++i)
    if (!(c[i] >= lo && c[i] <= hi)) params.fail(key, fmt::format("must lie in [{}, {}]", lo, hi));
  return Texture::constant(c);
}

}  // namespace penumbra
