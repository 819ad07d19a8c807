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
///
/// Every structure takes `isa=auto|native|sse2|avx2|avx512`: which compiled copy of the
/// structures' code builds and traverses it. `native` is the build's own target (-march=native
/// by default); the others are copies compiled for the x86-64 levels x86-64 (SSE2), x86-64-v3
/// (AVX2) and x86-64-v4 (AVX-512) where the build holds them (isa_levels()). `auto`, the default,
/// takes the widest level this CPU has when it is wider than the build's target, else `native`:
/// a portable build (-DPENUMBRA_NATIVE=OFF) runs the AVX2 or AVX-512 code on a CPU that has it.
/// A level the CPU lacks is an Error naming the missing extensions. The environment variable
/// PENUMBRA_CPU_LACKS (a comma-separated list, as core/cpu_check.h spells them) makes the CPU
/// appear to lack those extensions.
std::unique_ptr<Accelerator> make_accelerator(std::string_view spec);

/// The levels `isa=` can name besides `auto` and `native`, in increasing width: sse2, avx2 and
/// avx512 in builds for x86-64 (PENUMBRA_ISA_DISPATCH, CMakeLists.txt), none elsewhere.
std::vector<std::string> isa_levels();

/// What `isa=auto` picks on this CPU: "native" or one of isa_levels(). `lacks`: extensions to
/// take as missing (PENUMBRA_CPU_LACKS's form; may be null).
std::string isa_auto(const char* lacks);

}  // namespace penumbra
