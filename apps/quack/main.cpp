// quack: the command line. One program, a subcommand per task (each adds a setup function
// here and a source file): `query` and `run`.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <new>
#include <string>

#include "quack/world/tasks.hpp"
#include "query.hpp"
#include "run.hpp"

namespace {

void addQuery(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand(
      "query", "Shape-pair queries: JSON Lines in (FILE or - for stdin), JSON Lines out");
  auto file = std::make_shared<std::string>("-");
  cmd->add_option("FILE", *file, "input file of JSON Lines, or - for standard input")
      ->capture_default_str();
  cmd->callback([file, &status] {
    status = quack::app::runQueryCommand(*file, std::cin, std::cout, std::cerr);
  });
}

// --steps: a whole number of steps, 0..100,000,000, with a message that says so (CLI11's
// own range check would say "Value abc not in range 0 to 100000000").
constexpr std::uint64_t kMaxSteps = 100000000;

CLI::Validator stepsValidator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        bool digits = !text.empty() && text.size() <= 18;
        for (char c : text)
          digits = digits && c >= '0' && c <= '9';
        if (!digits) return text + " is not a whole number";
        if (std::stoull(text) > kMaxSteps)
          return text + " is more than " + std::to_string(kMaxSteps) + " steps";
        return {};
      },
      "0.." + std::to_string(kMaxSteps));
}

// --threads: 1..kMaxWorkers, said in words.
CLI::Validator threadsValidator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        bool digits = !text.empty() && text.size() <= 9;
        for (char c : text)
          digits = digits && c >= '0' && c <= '9';
        if (!digits) return text + " is not a whole number";
        const int n = std::stoi(text);
        if (n < 1 || n > quack::kMaxWorkers)
          return text + " is not in 1.." + std::to_string(quack::kMaxWorkers);
        return {};
      },
      "1.." + std::to_string(quack::kMaxWorkers));
}

void addRun(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand(
      "run", "Simulate a scene headless; write its state, an SVG and an HTML replay");
  auto options = std::make_shared<quack::app::RunOptions>();
  cmd->add_option("SCENE", options->scene, "scene file (JSON; see README, \"Scene files\")")
      ->required();
  cmd->add_option("--steps", options->steps, "steps to simulate (0..100000000)")
      ->capture_default_str()
      ->check(stepsValidator());
  cmd->add_option("--out", options->out, "state file to write (JSON)")->required();
  cmd->add_option("--events", options->events,
                  "every step's events, one JSON object a line (docs/determinism.md)");
  cmd->add_option("--svg", options->svg, "SVG picture of the last state");
  cmd->add_option("--html", options->html, "self-contained HTML replay of the run");
  cmd->add_option("--timing", options->timing,
                  "how long each phase took (JSON; the state file has no timing)");
  cmd->add_option("--threads", options->threads,
                  "workers for the step, 1.." + std::to_string(quack::kMaxWorkers) +
                      " (default: one per core); the result does not depend on it")
      ->check(threadsValidator());
  // --snapshot-at STEP FILE: two values, the step checked as --steps is.
  auto snapshotAt = std::make_shared<std::vector<std::string>>();
  cmd->add_option("--snapshot-at", *snapshotAt,
                  "write a run snapshot (for --resume) when the world reaches STEP")
      ->type_name("STEP FILE")
      ->expected(2);
  cmd->add_option("--resume", options->resume,
                  "continue from a run snapshot of this scene, up to --steps in all");
  cmd->add_flag("--html-boxes", options->htmlBoxes, "record the broad-phase boxes in the replay");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback([options, snapshotAt, &status] {
    if (!snapshotAt->empty()) {
      std::string step = (*snapshotAt)[0];
      if (std::string problem = stepsValidator()(step); !problem.empty())
        throw CLI::ValidationError("--snapshot-at", problem);
      options->snapshotAt = std::stoull(step);
      options->snapshotFile = (*snapshotAt)[1];
    }
    status = quack::app::runScene(*options, std::cout, std::cerr);
  });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"quack: 2D collision detection from the command line"};
  app.require_subcommand(1);
  int status = 0;
  addQuery(app, status);
  addRun(app, status);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Usage errors ("--steps: abc is not a whole number") exit 2, as bad input does;
    // --help and --version exit 0.
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const std::bad_alloc&) {
    // A scene too big for the memory there is (docs/world.md, "What a pile costs"): a
    // message and exit 2, as for any input the program cannot take, not an abort.
    std::cerr << "quack: out of memory (the scene needs more than this process may use)\n";
    return 2;
  }
  return status;
}
