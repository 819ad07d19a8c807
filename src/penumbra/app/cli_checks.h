#pragma once
/// Checks of numeric command-line options on their text, before CLI11 converts it. CLI11 2.1
/// converts with strtoull/strtoll in base 0, so on its own it takes "-1" for an unsigned option
/// as 2^64 - 1, "010" as 8 (octal), "0x10" as 16, an out-of-range count as the largest value,
/// and "nan" as a positive number; these checks refuse all of that with the range in the message.
#include <cstdint>

#include <CLI/CLI.hpp>

namespace penumbra::app {

/// Plain decimal integers in [lo, hi] (a leading '-' only for negative values); leading zeros
/// are decimal, as a user means them.
CLI::Validator integer_in(int64_t lo, int64_t hi);
/// Plain decimal integers in [lo, hi], for unsigned options (64-bit seeds).
CLI::Validator unsigned_in(uint64_t lo, uint64_t hi);
/// Finite numbers greater than zero (seconds, error targets).
CLI::Validator positive_finite();

}  // namespace penumbra::app
