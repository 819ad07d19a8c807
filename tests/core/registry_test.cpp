/// Tests of the named-factory registry: lookup, registration order and the unknown-name error.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/registry.h"

namespace penumbra {
namespace {

using Factory = std::function<int(int)>;

const Registry<Factory>& numbers() {
  static const Registry<Factory> all = {
      {"double", "twice the argument", [](int x) { return 2 * x; }},
      {"square", "the argument squared", [](int x) { return x * x; }},
      {"negate", "", [](int x) { return -x; }},
  };
  return all;
}

TEST(Registry, FindReturnsTheRegisteredFactory) {
  const Factory* square = numbers().find("square");
  ASSERT_NE(square, nullptr);
  EXPECT_EQ((*square)(7), 49);
  ASSERT_NE(numbers().find("double"), nullptr);
  EXPECT_EQ((*numbers().find("double"))(7), 14);
}

TEST(Registry, FindUnknownNameIsNull) {
  EXPECT_EQ(numbers().find("cube"), nullptr);
  EXPECT_EQ(numbers().find(""), nullptr);
  EXPECT_EQ(numbers().find("Square"), nullptr);  // names are case-sensitive
}

TEST(Registry, NamesAndEntriesKeepRegistrationOrder) {
  EXPECT_EQ(numbers().names(), (std::vector<std::string>{"double", "square", "negate"}));
  ASSERT_EQ(numbers().entries().size(), 3u);
  EXPECT_EQ(numbers().entries()[0].description, "twice the argument");
  EXPECT_EQ(numbers().entries()[2].description, "");
}

TEST(Registry, ValidNamesJoinedInOrder) {
  EXPECT_EQ(numbers().valid_names(), "double, square, negate");
  EXPECT_EQ(numbers().valid_names([](const std::string& n) { return n != "square"; }),
            "double, negate");
}

TEST(Registry, UnknownNameMessageListsValidNames) {
  EXPECT_EQ(numbers().unknown_name_message("operation", "cube"),
            "unknown operation 'cube' (valid: double, square, negate)");
}

TEST(Registry, GetThrowsErrorListingValidNames) {
  EXPECT_EQ(numbers().get("negate", "operation")(3), -3);
  try {
    numbers().get("cube", "operation");
    FAIL() << "no error for an unknown name";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "unknown operation 'cube' (valid: double, square, negate)");
  }
}

TEST(Registry, EmptyRegistry) {
  const Registry<Factory> none = {};
  EXPECT_TRUE(none.names().empty());
  EXPECT_EQ(none.find("x"), nullptr);
  EXPECT_EQ(none.unknown_name_message("thing", "x"), "unknown thing 'x' (valid: )");
}

}  // namespace
}  // namespace penumbra
