#pragma once
/// The registry of integrators, chosen with --integrator NAME[:params].
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/render/integrator/integrator.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// One registered integrator.
struct IntegratorInfo {
  std::string name;
  std::string description;
};

/// All registered integrators, in registration order.
const std::vector<IntegratorInfo>& integrator_list();

/// Creates the integrator named by `spec` over `world`; throws Error for an unknown name (listing
/// the valid ones) or a bad parameter.
std::unique_ptr<Integrator> make_integrator(std::string_view spec, const World& world,
                                            const RenderSettings& settings);

}  // namespace penumbra
