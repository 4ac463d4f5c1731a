#pragma once
/// Numbers as text that reads back bit for bit, the same on every build: what state files
/// (and event lists) print.

#include <string>

namespace quack {

/// Appends `x` as the shortest decimal text that reads back (strtod, or any correctly
/// rounded parser) as the same double, byte for byte what `std::to_chars(first, last, x)`
/// writes: fixed or scientific notation, whichever is shorter (fixed on a tie), "-0", "inf",
/// "-inf", "nan", "-nan". Uses the standard library's `std::to_chars` where it has one for
/// floating point, and `detail::appendShortestPortable` where it does not (emscripten
/// 3.1.6's libc++), so every build writes the same bytes.
void appendShortest(std::string& out, double x);

namespace detail {
/// appendShortest without `std::to_chars`: C's correctly rounded `snprintf` ("%.*e" and
/// "%.0f") and `strtod` (glibc, musl), trying 1 to 17 significant digits. Compiled in every
/// build so that tests/io/number_text_test.cpp compares it with `std::to_chars` natively.
void appendShortestPortable(std::string& out, double x);
}  // namespace detail

}  // namespace quack
