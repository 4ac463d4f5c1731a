#pragma once
// `quack run`: simulate a scene headless and write its state, an SVG and an HTML replay.

#include <cstdint>
#include <iosfwd>
#include <string>

namespace quack::app {

struct RunOptions {
  std::string scene;
  std::uint64_t steps = 600;
  std::string out;   // state JSON (required)
  std::string svg;   // optional
  std::string html;  // optional
  bool htmlBoxes = false;
  bool quiet = false;  // no progress on stderr
};

/// Runs; returns the exit status (0 ok, 2 bad scene or unwritable output). The summary
/// goes to `out`, errors and progress to `err`.
int runScene(const RunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace quack::app
