// quack: the command line. One program, a subcommand per task (each adds a setup function
// here and a source file): `query` and `run`.

#include <CLI/CLI.hpp>
#include <iostream>

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

void addRun(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand(
      "run", "Simulate a scene headless; write its state, an SVG and an HTML replay");
  auto options = std::make_shared<quack::app::RunOptions>();
  cmd->add_option("SCENE", options->scene, "scene file (JSON; see README, \"Scene files\")")
      ->required();
  cmd->add_option("--steps", options->steps, "steps to simulate")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000000));
  cmd->add_option("--out", options->out, "state file to write (JSON)")->required();
  cmd->add_option("--svg", options->svg, "SVG picture of the last state");
  cmd->add_option("--html", options->html, "self-contained HTML replay of the run");
  cmd->add_flag("--html-boxes", options->htmlBoxes, "record the broad-phase boxes in the replay");
  cmd->add_flag("--quiet", options->quiet, "no progress on stderr");
  cmd->callback(
      [options, &status] { status = quack::app::runScene(*options, std::cout, std::cerr); });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"quack: 2D collision detection from the command line"};
  app.require_subcommand(1);
  int status = 0;
  addQuery(app, status);
  addRun(app, status);
  CLI11_PARSE(app, argc, argv);
  return status;
}
