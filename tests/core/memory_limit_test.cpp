/// Tests of the memory limit that allocations sized by the input are checked against.
#include "penumbra/core/memory_limit.h"

#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"

namespace penumbra {
namespace {

TEST(MemoryLimit, SizesParseInBinaryUnits) {
  EXPECT_EQ(parse_memory_size("1073741824"), uint64_t(1) << 30);
  EXPECT_EQ(parse_memory_size("16G"), uint64_t(16) << 30);
  EXPECT_EQ(parse_memory_size("16GiB"), uint64_t(16) << 30);
  EXPECT_EQ(parse_memory_size("16gb"), uint64_t(16) << 30);
  EXPECT_EQ(parse_memory_size("800M"), uint64_t(800) << 20);
  EXPECT_EQ(parse_memory_size("1.5G"), uint64_t(3) << 29);
  EXPECT_EQ(parse_memory_size("2k"), 2048u);
  EXPECT_EQ(parse_memory_size("1T"), uint64_t(1) << 40);
  EXPECT_EQ(parse_memory_size("512B"), 512u);
  for (const char* bad : {"", "G", "0", "-1G", "12Q", "1.5 G", "nan", "inf", "1e30G", "0.1"}) {
    SCOPED_TRACE(bad);
    EXPECT_THROW(parse_memory_size(bad), Error);
  }
}

TEST(MemoryLimit, BytesAreFormattedInBinaryUnits) {
  EXPECT_EQ(format_bytes(512), "512 B");
  EXPECT_EQ(format_bytes(3 * 1024), "3.0 KiB");
  EXPECT_EQ(format_bytes(1.5 * (1 << 30)), "1.5 GiB");
}

TEST(MemoryLimit, DefaultIsThreeQuartersOfTheMachine) {
  const ScopedMemoryLimit none(0);  // whatever a test before set, this reads the default
  set_memory_limit(0);
  EXPECT_GT(machine_memory(), uint64_t(64) << 20);
  EXPECT_EQ(memory_limit(), machine_memory() / 4 * 3);
}

TEST(MemoryLimit, CheckRefusesAboveTheLimitNamingWhatAndHint) {
  const ScopedMemoryLimit limit(uint64_t(1) << 20);
  EXPECT_NO_THROW(check_memory(double(1 << 20), "exactly the limit"));
  try {
    check_memory(3.0 * (1 << 20), "the thing of 3 MiB", "make it smaller");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "the thing of 3 MiB needs 3.0 MiB, more than the memory limit of 1.0 MiB (set by "
              "--max-memory); make it smaller");
  }
  // NaN and infinite estimates (an overflowed product) are refused too.
  EXPECT_THROW(check_memory(1.0 / 0.0, "infinite"), Error);
  EXPECT_THROW(check_memory(0.0 / 0.0, "NaN"), Error);
}

TEST(MemoryLimit, ScopedLimitRestoresThePreviousOne) {
  const ScopedMemoryLimit outer(uint64_t(5) << 20);
  {
    const ScopedMemoryLimit inner(uint64_t(7) << 20);
    EXPECT_EQ(memory_limit(), uint64_t(7) << 20);
    const ScopedMemoryLimit keep(0);
    EXPECT_EQ(memory_limit(), uint64_t(7) << 20);
  }
  EXPECT_EQ(memory_limit(), uint64_t(5) << 20);
}

}  // namespace
}  // namespace penumbra
