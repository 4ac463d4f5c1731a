#pragma once
// `quack query`: JSON Lines of shape-pair queries in, one JSON answer per line out.

#include <istream>
#include <nlohmann/json_fwd.hpp>
#include <ostream>
#include <string>

namespace quack::app {

/// Deepest nesting of [ and { a query line may have. The deepest real query (a concave
/// shape's holes) nests 5 levels; the limit is checked by a linear scan before the JSON
/// parser runs, so a line like an id nested 70,000 deep is refused instead of overflowing
/// the stack when the id is echoed.
inline constexpr int kMaxQueryNesting = 64;

/// Answers one query line (see README, "Formats", Queries); `ok` is false when the line was
/// rejected, and then `answer` is {"id", "error"} (id null when the line could not be
/// parsed). A successful answer never holds a non-finite number: such an answer is
/// refused with an error naming the field instead.
struct QueryAnswer {
  std::string answer;  ///< one line of JSON, no newline
  bool ok = true;
};
QueryAnswer answerQuery(const std::string& line);

/// The first number in `answer` that is not finite (nlohmann would print it as null), as a
/// path such as "normal[0]"; empty when every number is finite. answerQuery refuses an
/// answer for which this is not empty.
std::string firstNonFiniteField(const nlohmann::json& answer);

/// Reads JSON Lines from `in` and writes one answer per line to `out`, in order: answer N
/// is for input line N (a blank line gets {"id": null, "error": "line N is blank"}). Stops
/// early when `out` fails. Returns the number of rejected lines.
int runQueries(std::istream& in, std::ostream& out);

/// `quack query FILE`: FILE ("-" for `standardInput`) through runQueries to `out`, with
/// messages on `err`. Returns the exit status: 0, 1 when any line was rejected, 2 when
/// FILE cannot be opened or read (a directory, say) or the answers cannot all be written
/// (a full disk); the message names the path and the reason.
int runQueryCommand(const std::string& file, std::istream& standardInput, std::ostream& out,
                    std::ostream& err);

}  // namespace quack::app
