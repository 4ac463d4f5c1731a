#include "quack/core/result.hpp"

#include <gtest/gtest.h>

#include <string>

namespace quack {
namespace {

Result<int> parsePositive(int x) {
  if (x <= 0) return fail("x must be > 0, got " + std::to_string(x));
  return x;
}

TEST(Result, CarriesValue) {
  Result<int> r = parsePositive(3);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(static_cast<bool>(r));
  EXPECT_EQ(r.value(), 3);
  EXPECT_EQ(*r, 3);
  EXPECT_EQ(r.valueOr(9), 3);
}

TEST(Result, CarriesErrorMessage) {
  Result<int> r = parsePositive(-2);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "x must be > 0, got -2");
  EXPECT_EQ(r.valueOr(9), 9);
}

TEST(Result, MovesOutNonCopyableValue) {
  Result<std::string> r = std::string(100, 'q');
  std::string s = std::move(r).value();
  EXPECT_EQ(s.size(), 100u);
}

TEST(Status, DefaultIsOkAndErrorKeepsMessage) {
  Status ok;
  EXPECT_TRUE(ok.ok());
  EXPECT_TRUE(ok.message().empty());
  Status bad = fail("broken");
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.message(), "broken");
}

}  // namespace
}  // namespace quack
