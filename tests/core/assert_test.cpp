#include "quack/core/assert.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace quack {
namespace {

struct AssertFired : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void throwingHandler(const char* expression, const char* message, const char*, int) {
  throw AssertFired(std::string(expression) + "|" + (message ? message : ""));
}

TEST(Assert, ReplaceableHandlerReceivesExpressionAndMessage) {
#if defined(QUACK_ENABLE_ASSERTS)
  AssertHandler previous = setAssertHandler(&throwingHandler);
  try {
    QUACK_ASSERT_MSG(1 + 1 == 3, "arithmetic");
    ADD_FAILURE() << "assert did not fire";
  } catch (const AssertFired& e) {
    EXPECT_EQ(std::string(e.what()), "1 + 1 == 3|arithmetic");
  }
  EXPECT_NO_THROW(QUACK_ASSERT(2 + 2 == 4));
  EXPECT_EQ(setAssertHandler(previous), &throwingHandler);
#else
  // Asserts compiled out: the condition is not even evaluated.
  int evaluated = 0;
  QUACK_ASSERT(++evaluated == 100);
  EXPECT_EQ(evaluated, 0);
#endif
}

TEST(Assert, ReportCallsInstalledHandlerAndNullRestoresDefault) {
  AssertHandler previous = setAssertHandler(&throwingHandler);
  EXPECT_THROW(reportAssertFailure("x", nullptr, __FILE__, __LINE__), AssertFired);
  // Installing null puts the default back; the default is not our handler.
  setAssertHandler(nullptr);
  AssertHandler current = setAssertHandler(previous);
  EXPECT_NE(current, &throwingHandler);
  EXPECT_NE(current, nullptr);
}

TEST(AssertDeathTest, DefaultHandlerAborts) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(reportAssertFailure("false", "boom", "file.cpp", 7), "assertion failed: false");
}

}  // namespace
}  // namespace quack
