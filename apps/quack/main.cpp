// quack: the command line. One program, a subcommand per task; `query` now, `run` and
// `bench` with their issues (each adds a setup function here and a source file).

#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>

#include "query.hpp"

namespace {

void addQuery(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand(
      "query", "Shape-pair queries: JSON Lines in (FILE or - for stdin), JSON Lines out");
  auto file = std::make_shared<std::string>("-");
  cmd->add_option("FILE", *file, "input file of JSON Lines, or - for standard input")
      ->capture_default_str();
  cmd->callback([file, &status] {
    int failures = 0;
    if (*file == "-") {
      failures = quack::app::runQueries(std::cin, std::cout);
    } else {
      std::ifstream in(*file);
      if (!in) {
        std::cerr << "quack query: cannot open " << *file << '\n';
        status = 2;
        return;
      }
      failures = quack::app::runQueries(in, std::cout);
    }
    if (failures > 0) {
      std::cerr << "quack query: " << failures << " line(s) failed\n";
      status = 1;
    }
  });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"quack: 2D collision detection from the command line"};
  app.require_subcommand(1);
  int status = 0;
  addQuery(app, status);
  CLI11_PARSE(app, argc, argv);
  return status;
}
