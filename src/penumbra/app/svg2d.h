#pragma once
/// SVG pictures of the 2D laboratory: the input, the partition (splitting lines clipped to their
/// cells and labelled, leaves), a ray and its hit; and the line plots of the fragment experiment.
/// Files are written through write_atomically (a temporary file, then a rename).
#include <optional>
#include <string>
#include <vector>

#include "penumbra/accel2d/accel2d.h"

namespace penumbra::app {

/// What one picture of a structure shows.
struct Svg2DContent {
  const lab2d::Scene2D* scene = nullptr;      ///< the shapes (required)
  const lab2d::Drawing2D* drawing = nullptr;  ///< the partition (optional)
  std::optional<Ray2> ray;                    ///< the ray, drawn to its hit or out of the frame
  lab2d::Hit2 hit;                            ///< the ray's hit
  std::string title;                          ///< a caption line
};

/// The SVG document of a structure over its scene; labels are drawn when there are few enough
/// to read (at most 400 shapes, 400 lines, 400 cells).
std::string svg_of_structure(const Svg2DContent& content);

/// One curve of a plot: (x, y) points and a name for the legend.
struct PlotSeries {
  std::string name;
  std::vector<std::pair<double, double>> points;
};

/// A panel of a plot: a logarithmic x axis, a linear y axis from 0.
struct PlotPanel {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
};

/// The SVG document of panels stacked vertically.
std::string svg_of_plot(const std::vector<PlotPanel>& panels);

/// Writes text to path through a temporary file and a rename; throws Error naming path on failure.
void write_text_atomically(const std::string& path, const std::string& text);

}  // namespace penumbra::app
