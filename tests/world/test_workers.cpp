// QUACK_TEST_WORKERS=N runs every world this test binary creates with the default single
// worker on N workers instead (tasks.hpp, detail::setTestWorkerCount): CI runs the world
// tests so under ThreadSanitizer (docs/world.md, "Threads").

#include <cstdio>
#include <cstdlib>

#include "quack/world/tasks.hpp"

namespace {

struct TestWorkers {
  TestWorkers() {
    const char* text = std::getenv("QUACK_TEST_WORKERS");
    if (text == nullptr || *text == '\0') return;
    char* end = nullptr;
    const long n = std::strtol(text, &end, 10);
    if (*end != '\0' || n < 1 || n > quack::kMaxWorkers) {
      std::fprintf(stderr, "QUACK_TEST_WORKERS must be 1..%d, got '%s'\n", quack::kMaxWorkers,
                   text);
      std::exit(2);
    }
    quack::detail::setTestWorkerCount(static_cast<int>(n));
    std::fprintf(stderr, "world tests: worlds with one worker run on %ld\n", n);
  }
};

const TestWorkers testWorkers;

}  // namespace
