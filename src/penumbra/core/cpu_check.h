#pragma once
/// Whether this CPU has the instruction-set extensions the program was compiled to use. The
/// default build compiles for the building machine's CPU (-march=native), so a binary copied to
/// an older machine (another node of a cluster, a colleague's laptop) would die of an illegal
/// instruction somewhere in its first vector loop. The program checks before any of its code
/// runs (src/main.cpp, a constructor of the highest priority) and stops with a message naming
/// the missing extensions instead.
///
/// Everything here is compiled for the x86-64 baseline (`target("arch=x86-64")`), whatever the
/// -march of the translation unit, so that the check itself runs on any x86-64 CPU; it calls
/// nothing but builtins, same-target functions and the C library. What it checks is read from
/// the compiler's macros (`__AVX2__` ...) of the translation unit that includes it, compiled
/// with the project's flags.
#include <cstddef>

namespace penumbra {

/// The most extensions missing_cpu_features() can report.
inline constexpr int kMaxCpuFeatures = 40;

#if defined(__x86_64__) || defined(__i386__)
#define PENUMBRA_BASELINE_X86 [[gnu::target("arch=x86-64")]]
#else
#define PENUMBRA_BASELINE_X86
#endif

/// True where the comma-separated `list` (may be null) holds `name` as one of its items.
PENUMBRA_BASELINE_X86 inline bool cpu_list_names(const char* list, const char* name) {
  if (!list) return false;
  for (const char* item = list; *item;) {
    const char* end = item;
    while (*end && *end != ',') ++end;
    std::size_t i = 0;
    while (item + i < end && name[i] && item[i] == name[i]) ++i;
    if (item + i == end && !name[i]) return true;
    item = *end ? end + 1 : end;
  }
  return false;
}

/// Writes to `out` (room for kMaxCpuFeatures) the names, as GCC's __builtin_cpu_supports spells
/// them ("avx2", "avx512f", ...), of the extensions the including translation unit is compiled
/// to use that this CPU lacks or that `lacks` names (a comma-separated list: the test hook
/// PENUMBRA_CPU_LACKS; may be null); returns how many. Zero on other architectures.
PENUMBRA_BASELINE_X86 inline int missing_cpu_features(const char* lacks, const char** out) {
  int n = 0;
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();  // required before __builtin_cpu_supports in a constructor
#define PENUMBRA_CPU_NEEDS(name)                                                             \
  if (n < kMaxCpuFeatures && (!__builtin_cpu_supports(name) || cpu_list_names(lacks, name))) \
    out[n++] = name;
#if defined(__SSE2__)
  PENUMBRA_CPU_NEEDS("sse2")
#endif
#if defined(__SSE3__)
  PENUMBRA_CPU_NEEDS("sse3")
#endif
#if defined(__SSSE3__)
  PENUMBRA_CPU_NEEDS("ssse3")
#endif
#if defined(__SSE4_1__)
  PENUMBRA_CPU_NEEDS("sse4.1")
#endif
#if defined(__SSE4_2__)
  PENUMBRA_CPU_NEEDS("sse4.2")
#endif
#if defined(__POPCNT__)
  PENUMBRA_CPU_NEEDS("popcnt")
#endif
#if defined(__AES__)
  PENUMBRA_CPU_NEEDS("aes")
#endif
#if defined(__PCLMUL__)
  PENUMBRA_CPU_NEEDS("pclmul")
#endif
#if defined(__AVX__)
  PENUMBRA_CPU_NEEDS("avx")
#endif
#if defined(__AVX2__)
  PENUMBRA_CPU_NEEDS("avx2")
#endif
#if defined(__FMA__)
  PENUMBRA_CPU_NEEDS("fma")
#endif
#if defined(__BMI__)
  PENUMBRA_CPU_NEEDS("bmi")
#endif
#if defined(__BMI2__)
  PENUMBRA_CPU_NEEDS("bmi2")
#endif
#if defined(__AVX512F__)
  PENUMBRA_CPU_NEEDS("avx512f")
#endif
#if defined(__AVX512VL__)
  PENUMBRA_CPU_NEEDS("avx512vl")
#endif
#if defined(__AVX512BW__)
  PENUMBRA_CPU_NEEDS("avx512bw")
#endif
#if defined(__AVX512DQ__)
  PENUMBRA_CPU_NEEDS("avx512dq")
#endif
#if defined(__AVX512CD__)
  PENUMBRA_CPU_NEEDS("avx512cd")
#endif
#if defined(__AVX512VBMI__)
  PENUMBRA_CPU_NEEDS("avx512vbmi")
#endif
#if defined(__AVX512VBMI2__)
  PENUMBRA_CPU_NEEDS("avx512vbmi2")
#endif
#if defined(__AVX512IFMA__)
  PENUMBRA_CPU_NEEDS("avx512ifma")
#endif
#if defined(__AVX512VNNI__)
  PENUMBRA_CPU_NEEDS("avx512vnni")
#endif
#if defined(__AVX512BITALG__)
  PENUMBRA_CPU_NEEDS("avx512bitalg")
#endif
#if defined(__AVX512VPOPCNTDQ__)
  PENUMBRA_CPU_NEEDS("avx512vpopcntdq")
#endif
#if defined(__AVX512BF16__)
  PENUMBRA_CPU_NEEDS("avx512bf16")
#endif
#if defined(__GFNI__)
  PENUMBRA_CPU_NEEDS("gfni")
#endif
#if defined(__VPCLMULQDQ__)
  PENUMBRA_CPU_NEEDS("vpclmulqdq")
#endif
// Names clang 14's __builtin_cpu_supports does not know.
#if !defined(__clang__)
#if defined(__F16C__)
  PENUMBRA_CPU_NEEDS("f16c")
#endif
#if defined(__LZCNT__)
  PENUMBRA_CPU_NEEDS("lzcnt")
#endif
#if defined(__MOVBE__)
  PENUMBRA_CPU_NEEDS("movbe")
#endif
#if defined(__ADX__)
  PENUMBRA_CPU_NEEDS("adx")
#endif
#if defined(__SHA__)
  PENUMBRA_CPU_NEEDS("sha")
#endif
#if defined(__AVXVNNI__)
  PENUMBRA_CPU_NEEDS("avxvnni")
#endif
#if defined(__AVX512FP16__)
  PENUMBRA_CPU_NEEDS("avx512fp16")
#endif
#endif
#undef PENUMBRA_CPU_NEEDS
#else
  (void)lacks, (void)out;
#endif
  return n;
}

}  // namespace penumbra
