#pragma once
// `quack query`: JSON Lines of shape-pair queries in, one JSON answer per line out.

#include <istream>
#include <ostream>
#include <string>

namespace quack::app {

/// Answers one query line (see DESIGN.md, "quack query"); `ok` is false when the line was
/// rejected, and then `answer` is {"id", "error"}.
struct QueryAnswer {
  std::string answer;  ///< one line of JSON, no newline
  bool ok = true;
};
QueryAnswer answerQuery(const std::string& line);

/// Reads JSON Lines from `in` (blank lines are skipped) and writes one answer per line to
/// `out`, in order. Returns the number of rejected lines.
int runQueries(std::istream& in, std::ostream& out);

}  // namespace quack::app
