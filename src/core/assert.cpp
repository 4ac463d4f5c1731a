#include "quack/core/assert.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace quack {
namespace {

void defaultAssertHandler(const char* expression, const char* message, const char* file, int line) {
  std::fprintf(stderr, "quack: assertion failed: %s%s%s\n  at %s:%d\n", expression,
               message ? " — " : "", message ? message : "", file, line);
  std::fflush(stderr);
  std::abort();
}

std::atomic<AssertHandler> gHandler{&defaultAssertHandler};

}  // namespace

AssertHandler setAssertHandler(AssertHandler handler) noexcept {
  return gHandler.exchange(handler ? handler : &defaultAssertHandler);
}

void reportAssertFailure(const char* expression, const char* message, const char* file, int line) {
  gHandler.load()(expression, message, file, line);
}

}  // namespace quack
