#pragma once
// `quack run`: simulate a scene headless and write its state, an SVG and an HTML replay.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>

namespace quack::app {

struct RunOptions {
  std::string scene;
  std::uint64_t steps = 600;
  std::string out;     // state JSON (required)
  std::string svg;     // optional
  std::string html;    // optional
  std::string timing;  // optional: how long each phase took (JSON)
  std::string events;  // optional: every step's events, one JSON object a line
  /// Workers the world's step is spread over (WorldDef::workerCount, 1..kMaxWorkers); 0:
  /// one per core. The state is the same to the bit for any number.
  int threads = 0;
  /// Write a run snapshot (docs/determinism.md, "Snapshots") when the world reaches step
  /// `snapshotAt` (counted from the scene's start, so a resumed run counts on) to
  /// `snapshotFile` (empty: none). The step must lie between the run's first and `steps`.
  std::uint64_t snapshotAt = 0;
  std::string snapshotFile;
  /// A run snapshot to continue from (empty: start from the scene): the world and the event
  /// totals at its step; `steps` is then the step to run up to, not a count to add.
  std::string resume;
  bool htmlBoxes = false;
  bool quiet = false;  // no progress on stderr
  /// Progress shows once the run has taken this long, and then about this often, seconds.
  double progressAfter = 1.0;
  /// For tests: called as each phase begins ("load", "build", "simulate", "render",
  /// "write", and "commit" once every temporary file is complete, before any is renamed).
  std::function<void(const std::string& phase)> onPhase;
};

/// Exit statuses of `quack run`.
inline constexpr int kRunOk = 0;
inline constexpr int kRunFailed = 2;         // bad scene, bad or unwritable output, failed step
inline constexpr int kRunInterrupted = 130;  // SIGINT (128 + 2)
inline constexpr int kRunTerminated = 143;   // SIGTERM (128 + 15)

/// Runs; returns the exit status. Every output is checked before the scene is loaded
/// (distinct files, not the scene, not a directory, in a writable folder); all are written
/// to temporary files beside their targets and renamed only once every one is complete, so
/// a failed or interrupted run changes no output and leaves no temporary behind. SIGINT
/// and SIGTERM are caught while it runs (between steps and while writing) and end it with
/// 130 or 143 after the clean-up. The summary goes to `out`, errors and progress to `err`.
int runScene(const RunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace quack::app
