#include "penumbra/core/error.h"

#include <cstdint>

#include "penumbra/core/text_escape.h"

namespace penumbra {
namespace {

// "FILE:PLACE: PROBLEM" with every part escaped (built by appending: GCC 12 warns falsely,
// -Wrestrict, on "literal" + std::string).
std::string input_message(const std::string& file, const std::string& place,
                          const std::string& problem) {
  std::string message = escape_for_message(file, SIZE_MAX);
  if (!place.empty()) message.append(":").append(escape_for_message(place, SIZE_MAX));
  return message.append(": ").append(escape_for_message(problem, SIZE_MAX));
}

}  // namespace

InputError::InputError(const std::string& file, const std::string& place,
                       const std::string& problem)
    : Error(input_message(file, place, problem)) {}

}  // namespace penumbra
