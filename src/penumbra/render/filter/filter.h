#pragma once
/// Pixel reconstruction filters. Each is separable, f(x, y) = f1(x) f1(y), with a radius beyond
/// which it is zero; the renderer draws sample positions from |f| and weights them by f / pdf
/// (filter importance sampling), so a pixel's samples never touch its neighbours.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

/// A separable reconstruction filter.
class Filter {
 public:
  virtual ~Filter() = default;
  /// The registered name with parameters.
  virtual std::string name() const = 0;
  /// Support radius in pixels: f1(x) = 0 for |x| >= radius.
  virtual float radius() const = 0;
  /// The 1D profile f1(x) (may be negative, e.g. Mitchell-Netravali's lobes).
  virtual float eval(float x) const = 0;
};

/// One registered filter.
struct FilterInfo {
  std::string name;
  std::string description;
};

/// All registered filters.
const std::vector<FilterInfo>& filter_list();

/// Creates the filter named by `spec` ("gaussian:radius=1.5,sigma=0.5"); throws Error for an
/// unknown name or a bad parameter.
std::unique_ptr<Filter> make_filter(std::string_view spec);

}  // namespace penumbra
