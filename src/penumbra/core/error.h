#pragma once
/// Errors raised by penumbra: one exception type whose message names the file, the place and the
/// problem.
#include <stdexcept>
#include <string>

namespace penumbra {

/// An error caused by bad input or a failed operation; caught once by the CLI, printed, exit
/// non-zero.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Error in an input file: message is "FILE:PLACE: PROBLEM" (PLACE is a line, JSON path or byte
/// offset). Control bytes and bytes that are not UTF-8 in any part (a JSON key in the path, a token
/// quoted in the problem) are escaped as \xNN, so the message never carries the file's raw bytes.
class InputError : public Error {
 public:
  InputError(const std::string& file, const std::string& place, const std::string& problem);
};

}  // namespace penumbra
