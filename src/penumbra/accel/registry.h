#pragma once
/// The registry of acceleration structures: names, descriptions and factories.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/accel/accelerator.h"

namespace penumbra {

/// One registered structure.
struct AccelInfo {
  std::string name;         ///< what `--accel` takes before the colon (or a NAME:variant)
  std::string description;  ///< one line for --help and docs
};

/// All registered structures, in registration order.
const std::vector<AccelInfo>& accelerator_list();

/// Creates the structure named by `spec` ("name" or "name:k=v,..."), unbuilt. Throws Error for an
/// unknown name (listing the valid ones) or a bad parameter.
std::unique_ptr<Accelerator> make_accelerator(std::string_view spec);

}  // namespace penumbra
