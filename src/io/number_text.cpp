#include "quack/io/number_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <system_error>

namespace quack {
namespace detail {
namespace {

// Significant digits (no leading or trailing zeros) and the decimal exponent of the first:
// the value is 0.d1d2d3... * 10^(exponent + 1), that is d1.d2d3... * 10^exponent.
struct Decimal {
  std::string digits;
  int exponent = 0;
};

// "d.ddde+XX" (from %.*e) as a Decimal.
Decimal parseScientific(const char* text) {
  Decimal d;
  const char* p = text;
  for (; *p != 'e'; ++p) {
    if (*p != '.') d.digits += *p;
  }
  d.exponent = std::atoi(p + 1);
  return d;
}

// d plus `step` (+1 or -1) in its last digit, keeping the digit count: 9.99e0 + 1 is
// 1.00e1, 1.00e0 - 1 is 9.99e-1.
Decimal stepLastDigit(Decimal d, int step) {
  std::string& s = d.digits;
  int i = static_cast<int>(s.size()) - 1;
  if (step > 0) {
    while (i >= 0 && s[static_cast<std::size_t>(i)] == '9')
      s[static_cast<std::size_t>(i--)] = '0';
    if (i < 0) {
      s.insert(s.begin(), '1');
      s.pop_back();
      ++d.exponent;
    } else {
      ++s[static_cast<std::size_t>(i)];
    }
  } else {
    while (i >= 0 && s[static_cast<std::size_t>(i)] == '0')
      s[static_cast<std::size_t>(i--)] = '9';
    --s[static_cast<std::size_t>(i)];  // i >= 0: the first digit is not 0
    if (s[0] == '0') {                 // 1.00 -> 0.99: one more 9 at the end
      s.erase(s.begin());
      s += '9';
      --d.exponent;
    }
  }
  return d;
}

bool readsBackAs(const Decimal& d, double x) {
  std::string text =
      d.digits.substr(0, 1) + "." + d.digits.substr(1) + "e" + std::to_string(d.exponent);
  return std::strtod(text.c_str(), nullptr) == x;
}

// The shortest decimal that reads back as x (> 0, finite), the nearest of that length.
Decimal shortest(double x) {
  char buf[64];
  for (int precision = 1;; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*e", precision - 1, x);
    const Decimal nearest = parseScientific(buf);
    if (precision >= 17 || readsBackAs(nearest, x)) return nearest;
    // The nearest decimal of this length can miss x's rounding interval where a neighbour
    // on the other side hits it: at a power of two the interval below x is half as wide as
    // the one above.
    for (int step : {1, -1}) {
      const Decimal other = stepLastDigit(nearest, step);
      if (readsBackAs(other, x)) return other;
    }
  }
}

}  // namespace

void appendShortestPortable(std::string& out, double x) {
  if (std::signbit(x)) out += '-';
  if (std::isnan(x)) {
    out += "nan";
    return;
  }
  if (std::isinf(x)) {
    out += "inf";
    return;
  }
  x = std::fabs(x);
  if (x == 0.0) {
    out += '0';
    return;
  }
  Decimal d = shortest(x);
  while (d.digits.size() > 1 && d.digits.back() == '0')
    d.digits.pop_back();
  const int n = static_cast<int>(d.digits.size());
  const int e = d.exponent;

  std::string scientific = d.digits.substr(0, 1);
  if (n > 1) scientific += "." + d.digits.substr(1);
  const int ae = e < 0 ? -e : e;
  scientific += e < 0 ? "e-" : "e+";
  if (ae < 10) scientific += '0';
  scientific += std::to_string(ae);

  std::string fixed;
  if (e < 0) {
    fixed = "0." + std::string(static_cast<std::size_t>(-e - 1), '0') + d.digits;
  } else if (n <= e + 1) {
    fixed = d.digits + std::string(static_cast<std::size_t>(e + 1 - n), '0');
  } else {
    fixed = d.digits.substr(0, static_cast<std::size_t>(e + 1)) + "." +
            d.digits.substr(static_cast<std::size_t>(e + 1));
  }
  if (fixed.size() > scientific.size()) {
    out += scientific;
  } else if (n < e + 1) {
    // A whole number with fewer significant digits than places: std::to_chars prints it
    // "as if by printf", the exact integer (the same length), not the digits and zeros.
    char buf[320];
    std::snprintf(buf, sizeof buf, "%.0f", x);
    out += buf;
  } else {
    out += fixed;
  }
}

}  // namespace detail

void appendShortest(std::string& out, double x) {
#if defined(__cpp_lib_to_chars)
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  if (ec == std::errc{}) {
    out += std::string_view(buf, static_cast<std::size_t>(end - buf));
    return;
  }
#endif
  detail::appendShortestPortable(out, x);
}

}  // namespace quack
