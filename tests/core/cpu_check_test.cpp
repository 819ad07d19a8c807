#include "penumbra/core/cpu_check.h"

#include <gtest/gtest.h>

#include <string>

namespace penumbra {
namespace {

TEST(CpuCheck, ListsAreMatchedByWholeItems) {
  EXPECT_TRUE(cpu_list_names("avx2", "avx2"));
  EXPECT_TRUE(cpu_list_names("sse2,avx2,fma", "avx2"));
  EXPECT_TRUE(cpu_list_names("sse2,avx2,fma", "fma"));
  EXPECT_TRUE(cpu_list_names("sse2,avx2,fma", "sse2"));
  EXPECT_FALSE(cpu_list_names("avx2", "avx"));
  EXPECT_FALSE(cpu_list_names("avx", "avx2"));
  EXPECT_FALSE(cpu_list_names("avx512f,avx2", "avx512"));
  EXPECT_FALSE(cpu_list_names("", "avx"));
  EXPECT_FALSE(cpu_list_names(",,", "avx"));
  EXPECT_FALSE(cpu_list_names(nullptr, "avx"));
}

TEST(CpuCheck, TheBuildingMachineHasEveryExtensionItsCodeUses) {
  // The tests run on the machine that compiled them (-march=native there): nothing is missing,
  // unless an extension's name is misspelled for __builtin_cpu_supports.
  const char* missing[kMaxCpuFeatures];
  const int n = missing_cpu_features(nullptr, missing);
  std::string names;
  for (int i = 0; i < n; ++i) names += std::string(missing[i]) + " ";
  EXPECT_EQ(n, 0) << names;
}

#if defined(__x86_64__)
TEST(CpuCheck, AnExtensionNamedAsLackingIsReported) {
  // SSE2 is in every x86-64 target; AVX where the build uses it.
  const char* missing[kMaxCpuFeatures];
  ASSERT_EQ(missing_cpu_features("sse2", missing), 1);
  EXPECT_STREQ(missing[0], "sse2");
#if defined(__AVX__)
  ASSERT_EQ(missing_cpu_features("bogus,avx,sse2", missing), 2);
  EXPECT_STREQ(missing[0], "sse2");
  EXPECT_STREQ(missing[1], "avx");
#endif
  EXPECT_EQ(missing_cpu_features("bogus", missing), 0);
}
#endif

}  // namespace
}  // namespace penumbra
