#pragma once
/// What the code was compiled for and what it runs on. A translation unit's SIMD code is chosen
/// when it is compiled, so compiled_vectors(), not the machine's CPU, says what it runs (a
/// portable SSE2 build on an AVX-512 machine runs SSE2 code; docs/accel.md, "2026-12-06,
/// fifteenth session"). The acceleration structures are also compiled for several levels, one
/// of which is chosen when the program runs (accel/registry.h, `isa=`): their figures were
/// measured with Accelerator::vectors(). cpu_is_intel() and cpu_has_avx512() are for the few
/// defaults that depend on the core that runs the program.
namespace penumbra {

/// "AVX-512", "AVX2", "AVX", "SSE4.2", "SSE2", "NEON" or "scalar": the widest of these the target
/// has.
constexpr const char* compiled_vectors() {
#if defined(__AVX512F__)
  return "AVX-512";
#elif defined(__AVX2__)
  return "AVX2";
#elif defined(__AVX__)
  return "AVX";
#elif defined(__SSE4_2__)
  return "SSE4.2";
#elif defined(__SSE2__)
  return "SSE2";
#elif defined(__ARM_NEON)
  return "NEON";
#else
  return "scalar";
#endif
}

/// True when the CPU running the program is Intel's (its CPUID vendor), false on other CPUs and
/// other architectures. For choices that depend on the core rather than on the instruction set
/// (`bvh:anyhit=auto`).
inline bool cpu_is_intel() {
#if defined(__x86_64__) || defined(__i386__)
  return __builtin_cpu_is("intel");
#else
  return false;
#endif
}

/// True when the CPU running the program has AVX-512 Foundation (whatever the code was compiled
/// for), false on other CPUs and other architectures. With cpu_is_intel(), for
/// `bvh:anyhit=auto`.
inline bool cpu_has_avx512() {
#if defined(__x86_64__) || defined(__i386__)
  return __builtin_cpu_supports("avx512f");
#else
  return false;
#endif
}

}  // namespace penumbra
