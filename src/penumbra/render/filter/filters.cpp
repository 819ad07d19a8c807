#include "penumbra/render/filter/filters.h"

#include <cmath>
#include <functional>

#include <fmt/format.h>

#include "penumbra/core/registry.h"

namespace penumbra {

BoxFilter::BoxFilter(const ParamList& p) : radius_(float(p.get_real("radius", 0.5, 0.01, 16))) {
  p.check_all_used();
}
std::string BoxFilter::name() const { return fmt::format("box:radius={:g}", radius_); }

TentFilter::TentFilter(const ParamList& p) : radius_(float(p.get_real("radius", 1.0, 0.01, 16))) {
  p.check_all_used();
}
std::string TentFilter::name() const { return fmt::format("tent:radius={:g}", radius_); }
float TentFilter::eval(float x) const { return std::fmax(0.0f, radius_ - std::fabs(x)); }

GaussianFilter::GaussianFilter(const ParamList& p)
    : radius_(float(p.get_real("radius", 1.5, 0.01, 16))),
      sigma_(float(p.get_real("sigma", 0.5, 0.01, 16))) {
  p.check_all_used();
  offset_ = std::exp(-radius_ * radius_ / (2 * sigma_ * sigma_));
}
std::string GaussianFilter::name() const {
  return fmt::format("gaussian:radius={:g},sigma={:g}", radius_, sigma_);
}
float GaussianFilter::eval(float x) const {
  if (std::fabs(x) >= radius_) return 0.0f;
  return std::fmax(0.0f, std::exp(-x * x / (2 * sigma_ * sigma_)) - offset_);
}

MitchellFilter::MitchellFilter(const ParamList& p)
    : radius_(float(p.get_real("radius", 2.0, 0.01, 16))),
      b_(float(p.get_real("b", 1.0 / 3.0, -10, 10))),
      c_(float(p.get_real("c", 1.0 / 3.0, -10, 10))) {
  p.check_all_used();
}
std::string MitchellFilter::name() const {
  return fmt::format("mitchell:radius={:g},b={:g},c={:g}", radius_, b_, c_);
}
float MitchellFilter::eval(float x) const {
  // The cubic is defined on [-2, 2]; map the filter's support onto it.
  x = std::fabs(2.0f * x / radius_);
  const float b = b_, c = c_;
  if (x >= 2.0f) return 0.0f;
  if (x >= 1.0f)
    return ((-b - 6 * c) * x * x * x + (6 * b + 30 * c) * x * x + (-12 * b - 48 * c) * x +
            (8 * b + 24 * c)) /
           6.0f;
  return ((12 - 9 * b - 6 * c) * x * x * x + (-18 + 12 * b + 6 * c) * x * x + (6 - 2 * b)) / 6.0f;
}

namespace {

using Factory = std::function<std::unique_ptr<Filter>(const ParamList&)>;

template <class T>
std::unique_ptr<Filter> create(const ParamList& p) {
  return std::make_unique<T>(p);
}

/// Every filter, written out explicitly: a new one is one line here.
const Registry<Factory>& registry() {
  static const Registry<Factory> all = {
      {"box", "box of half-width radius (0.5: the pixel square)", create<BoxFilter>},
      {"tent", "triangle of half-width radius (1)", create<TentFilter>},
      {"gaussian", "Gaussian of sigma (0.5) cut at radius (1.5)", create<GaussianFilter>},
      {"mitchell", "Mitchell-Netravali cubic, b = c = 1/3, radius 2", create<MitchellFilter>},
  };
  return all;
}

}  // namespace

const std::vector<FilterInfo>& filter_list() {
  static const std::vector<FilterInfo> list = [] {
    std::vector<FilterInfo> l;
    for (const auto& e : registry().entries()) l.push_back({e.name, e.description});
    return l;
  }();
  return list;
}

std::unique_ptr<Filter> make_filter(std::string_view spec) {
  const ParamList params = ParamList::parse(spec);
  return registry().get(params.name(), "filter")(params);
}

}  // namespace penumbra
