#pragma once
/// The registry of the 2D structures: names, descriptions and factories, with parameters after a
/// colon as for the 3D ones ("bsp:order=first", "quadtree:leaf=4,depth=8").
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/accel2d/accel2d.h"

namespace penumbra::lab2d {

/// One registered structure.
struct Accel2DInfo {
  std::string name;         ///< what `--structure` takes before the colon
  std::string description;  ///< one line for --help and docs
  bool segments_only;       ///< true when it takes segments only
  bool disjoint;            ///< true when its theory needs disjoint input (checked by the CLI)
};

/// All registered structures, in registration order.
const std::vector<Accel2DInfo>& accel2d_list();

/// Creates the structure named by `spec`, unbuilt. Throws Error for an unknown name (listing the
/// valid ones) or a bad parameter.
std::unique_ptr<Accel2D> make_accel2d(std::string_view spec);

/// The brute-force reference: every shape for every ray.
class Brute2D final : public Accel2D {
 public:
  std::string name() const override { return "brute"; }
  void build(const Scene2D& scene) override { scene_ = scene; }
  Hit2 shoot(const Ray2& ray, TraceLog* trace = nullptr) const override;
  Stats2D stats() const override;
  Drawing2D draw(const Box2d& frame) const override;

 private:
  Scene2D scene_;
};

}  // namespace penumbra::lab2d
