#include "penumbra/app/svg2d.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/image/image_io.h"

namespace penumbra::app {

namespace {

/// Labels are drawn only when there are at most this many of a kind (else they are unreadable).
constexpr size_t kMaxLabels = 400;

/// Text with the XML special characters escaped.
std::string xml(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else
      out += c;
  }
  return out;
}

/// Maps plane coordinates to SVG pixels (y up becomes y down).
struct View {
  Box2d frame;
  double k = 1, margin = 24, top = 40;
  double x(double v) const { return margin + (v - frame.lo.x) * k; }
  double y(double v) const { return top + (frame.hi.y - v) * k; }
};

/// The points of a polygon as an SVG points attribute.
std::string points(const View& v, const std::vector<Vec2d>& poly) {
  std::string s;
  for (Vec2d p : poly) fmt::format_to(std::back_inserter(s), "{:.2f},{:.2f} ", v.x(p.x), v.y(p.y));
  return s;
}

Vec2d centroid(const std::vector<Vec2d>& poly) {
  Vec2d c;
  for (Vec2d p : poly) c = c + p;
  return c * (1.0 / double(poly.size()));
}

}  // namespace

std::string svg_of_structure(const Svg2DContent& c) {
  const lab2d::Scene2D& scene = *c.scene;
  // The frame: the drawing's, or the scene's box with a margin of a tenth.
  Box2d frame = c.drawing ? c.drawing->frame : Box2d{};
  if (frame.empty()) {
    frame = scene.bounds();
    if (c.ray) frame.extend(c.ray->o);
    const Vec2d ext = frame.extent();
    const double m = 0.1 * std::max({ext.x, ext.y, 1e-9});
    frame.lo = frame.lo - Vec2d{m, m};
    frame.hi = frame.hi + Vec2d{m, m};
  }
  View v;
  v.frame = frame;
  const Vec2d ext = frame.extent();
  v.k = std::min(800.0 / ext.x, 800.0 / ext.y);
  const double width = 2 * v.margin + ext.x * v.k, height = v.top + v.margin + ext.y * v.k;
  std::string s = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" "
      "viewBox=\"0 0 {:.0f} {:.0f}\" font-family=\"sans-serif\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      "<text x=\"{}\" y=\"24\" font-size=\"14\">{}</text>\n",
      width, height, width, height, v.margin, xml(c.title));
  auto out = std::back_inserter(s);
  if (c.drawing) {
    // Leaves' cells, then the splitting lines clipped to their cells.
    const bool cell_labels = c.drawing->cells.size() <= kMaxLabels;
    s += "<g id=\"cells\" fill=\"#eef3fa\" stroke=\"#c9d6e8\" stroke-width=\"0.5\">\n";
    for (const auto& cell : c.drawing->cells)
      fmt::format_to(out, "<polygon points=\"{}\"/>\n", points(v, cell.poly));
    s += "</g>\n<g id=\"cell-labels\" fill=\"#7a8799\" font-size=\"9\" text-anchor=\"middle\">\n";
    if (cell_labels)
      for (const auto& cell : c.drawing->cells) {
        const Vec2d m = centroid(cell.poly);
        fmt::format_to(out, "<text x=\"{:.2f}\" y=\"{:.2f}\">{}</text>\n", v.x(m.x), v.y(m.y) + 12,
                       xml(cell.label));
      }
    s += "</g>\n<g id=\"lines\" stroke=\"#2f6fd0\" stroke-width=\"1\" stroke-dasharray=\"5,3\">\n";
    for (const auto& line : c.drawing->lines)
      fmt::format_to(out, "<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\"/>\n",
                     v.x(line.s.a.x), v.y(line.s.a.y), v.x(line.s.b.x), v.y(line.s.b.y));
    s += "</g>\n<g id=\"line-labels\" fill=\"#2f6fd0\" font-size=\"11\">\n";
    if (c.drawing->lines.size() <= kMaxLabels)
      for (const auto& line : c.drawing->lines) {
        if (line.label.empty()) continue;
        const Vec2d m = line.s.at(0.25);
        fmt::format_to(out, "<text x=\"{:.2f}\" y=\"{:.2f}\">{}</text>\n", v.x(m.x) + 3,
                       v.y(m.y) - 3, xml(line.label));
      }
    s += "</g>\n";
  }
  // The shapes: segments s1.., polygons O1.. (labels by their input number).
  const bool shape_labels = scene.shapes.size() <= kMaxLabels;
  const double stroke = scene.shapes.size() > 2000 ? 0.8 : 2.2;
  fmt::format_to(out, "<g id=\"shapes\" stroke=\"black\" stroke-width=\"{}\" fill=\"#bbbbbb\">\n",
                 stroke);
  for (const auto& shape : scene.shapes) {
    if (shape.is_segment())
      fmt::format_to(out, "<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\"/>\n",
                     v.x(shape.v[0].x), v.y(shape.v[0].y), v.x(shape.v[1].x), v.y(shape.v[1].y));
    else
      fmt::format_to(out, "<polygon points=\"{}\"/>\n", points(v, shape.v));
  }
  s += "</g>\n<g id=\"shape-labels\" font-size=\"12\" font-weight=\"bold\">\n";
  if (shape_labels)
    for (size_t k = 0; k < scene.shapes.size(); ++k) {
      const auto& shape = scene.shapes[k];
      const Vec2d m = shape.is_segment() ? shape.segment().at(0.5) : centroid(shape.v);
      fmt::format_to(out, "<text x=\"{:.2f}\" y=\"{:.2f}\">{}{}</text>\n", v.x(m.x) + 4,
                     v.y(m.y) - 4, shape.is_segment() ? 's' : 'O', k + 1);
    }
  s += "</g>\n";
  // The ray: to its hit, or to where it leaves the frame.
  if (c.ray) {
    const Ray2& r = *c.ray;
    double t0 = r.tmin, t1 = r.tmax;
    if (c.hit.hit()) {
      t1 = c.hit.t;
    } else if (!ray_box_interval(r, frame, t0, t1)) {
      t1 = r.tmin;
    }
    const Vec2d a = r.o + r.d * r.tmin, b = r.o + r.d * t1;
    fmt::format_to(out,
                   "<g id=\"ray\" stroke=\"#d62728\" fill=\"#d62728\">\n"
                   "<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3\"/>\n"
                   "<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" "
                   "stroke-width=\"1.8\"/>\n",
                   v.x(a.x), v.y(a.y), v.x(a.x), v.y(a.y), v.x(b.x), v.y(b.y));
    if (c.hit.hit())
      fmt::format_to(out, "<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"5\" fill=\"none\"/>\n", v.x(b.x),
                     v.y(b.y));
    s += "</g>\n";
  }
  s += "</svg>\n";
  return s;
}

std::string svg_of_plot(const std::vector<PlotPanel>& panels) {
  const double w = 720, h = 300, left = 80, right = 180, top = 40, bottom = 50;
  const double total_h = panels.size() * (h + top + bottom);
  std::string s = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0f}\" height=\"{1:.0f}\" "
      "viewBox=\"0 0 {0:.0f} {1:.0f}\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      left + w + right, total_h);
  auto out = std::back_inserter(s);
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  for (size_t p = 0; p < panels.size(); ++p) {
    const PlotPanel& panel = panels[p];
    const double y0 = p * (h + top + bottom) + top;
    // Axis ranges: x logarithmic over whole decades, y linear from 0.
    double xmin = INFINITY, xmax = -INFINITY, ymax = 0;
    for (const auto& series : panel.series)
      for (auto [x, y] : series.points)
        xmin = std::min(xmin, x), xmax = std::max(xmax, x), ymax = std::max(ymax, y);
    if (!(xmin < xmax)) xmin = 1, xmax = 10;
    if (!(ymax > 0)) ymax = 1;
    const double lx0 = std::floor(std::log10(xmin)), lx1 = std::ceil(std::log10(xmax));
    // A round y step: 1, 2 or 5 times a power of ten, about five ticks.
    const double raw = ymax * 1.1 / 5, mag = std::pow(10, std::floor(std::log10(raw)));
    const double step = raw / mag <= 1   ? mag
                        : raw / mag <= 2 ? 2 * mag
                        : raw / mag <= 5 ? 5 * mag
                                         : 10 * mag;
    const double ytop = step * std::ceil(ymax * 1.1 / step);
    auto px = [&](double x) { return left + (std::log10(x) - lx0) / (lx1 - lx0) * w; };
    auto py = [&](double y) { return y0 + h - y / ytop * h; };
    fmt::format_to(out,
                   "<text x=\"{}\" y=\"{}\" font-size=\"14\">{}</text>\n"
                   "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" "
                   "stroke=\"black\"/>\n",
                   left, y0 - 12, xml(panel.title), left, y0, w, h);
    for (double e = lx0; e <= lx1; ++e)
      fmt::format_to(out,
                     "<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#ddd\"/>\n"
                     "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4:g}</text>\n",
                     px(std::pow(10, e)), y0, y0 + h, y0 + h + 16, std::pow(10, e));
    for (double y = 0; y <= ytop * (1 + 1e-9); y += step)
      fmt::format_to(out,
                     "<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#ddd\"/>\n"
                     "<text x=\"{3}\" y=\"{4:.1f}\" text-anchor=\"end\">{5:g}</text>\n",
                     left, py(y), left + w, left - 6, py(y) + 4, y);
    fmt::format_to(out,
                   "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n"
                   "<text x=\"16\" y=\"{}\" transform=\"rotate(-90 16 {})\" "
                   "text-anchor=\"middle\">{}</text>\n",
                   left + w / 2, y0 + h + 36, xml(panel.x_label), y0 + h / 2, y0 + h / 2,
                   xml(panel.y_label));
    for (size_t k = 0; k < panel.series.size(); ++k) {
      const PlotSeries& series = panel.series[k];
      const char* colour = colours[k % std::size(colours)];
      std::string pts;
      for (auto [x, y] : series.points)
        fmt::format_to(std::back_inserter(pts), "{:.1f},{:.1f} ", px(x), py(y));
      fmt::format_to(out,
                     "<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>\n",
                     pts, colour);
      for (auto [x, y] : series.points)
        fmt::format_to(out, "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3\" fill=\"{}\"/>\n", px(x),
                       py(y), colour);
      fmt::format_to(out,
                     "<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"{3}\" "
                     "stroke-width=\"2\"/>\n<text x=\"{4}\" y=\"{5}\">{6}</text>\n",
                     left + w + 10, y0 + 14 + 18 * k, left + w + 30, colour, left + w + 36,
                     y0 + 18 + 18 * k, xml(series.name));
    }
  }
  s += "</svg>\n";
  return s;
}

void write_text_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, text);
}

}  // namespace penumbra::app
