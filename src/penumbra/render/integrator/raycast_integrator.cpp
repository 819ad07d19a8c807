#include "penumbra/render/integrator/raycast_integrator.h"

#include <cmath>

#include "penumbra/core/error.h"
#include "penumbra/render/material/material.h"

namespace penumbra {

RaycastIntegrator::RaycastIntegrator(const World& world, const ParamList& params) : world_(world) {
  const std::string mode = params.get_string("mode", "eyelight");
  if (mode == "normal") mode_ = Mode::kNormal;
  else if (mode == "albedo") mode_ = Mode::kAlbedo;
  else if (mode == "eyelight") mode_ = Mode::kEyelight;
  else throw Error("raycast: unknown mode '" + mode + "' (valid: normal, albedo, eyelight)");
  params.check_all_used();
}

std::string RaycastIntegrator::name() const {
  return mode_ == Mode::kNormal ? "raycast:mode=normal"
                                : (mode_ == Mode::kAlbedo ? "raycast:mode=albedo" : "raycast");
}

Rgb RaycastIntegrator::li(const Ray& ray, Sampler&, RayCounter& counter) const {
  SurfaceInteraction si;
  if (!world_.intersect(ray, si, counter)) return world_.escaped(ray);
  MaterialScratch scratch;
  si.material = &si.material->at(si, scratch);  // textures evaluated at the hit
  switch (mode_) {
    case Mode::kNormal:
      return {0.5f * (si.ns.x + 1.0f), 0.5f * (si.ns.y + 1.0f), 0.5f * (si.ns.z + 1.0f)};
    case Mode::kAlbedo:
      return si.emitted.is_black() ? si.material->albedo() : si.emitted;
    case Mode::kEyelight:
    default:
      if (!si.emitted.is_black()) return si.emitted;
      return si.material->albedo() * std::fabs(dot(si.ns, si.wo));
  }
}

}  // namespace penumbra
