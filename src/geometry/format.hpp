#pragma once
// Number formatting for error messages (internal to the geometry layer).

#include <cstdio>
#include <cstdlib>
#include <string>

#include "quack/math/vec2.hpp"

namespace quack::detail {

// The shortest of %.6g .. %.9g that reads back as the same float ("1e-09", not
// "9.99999972e-10").
inline std::string formatNumber(float x) {
  char buf[32];
  for (int digits = 6; digits <= 9; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, static_cast<double>(x));
    if (std::strtof(buf, nullptr) == x) break;
  }
  return buf;
}

inline std::string formatVec(Vec2 v) {
  return "(" + formatNumber(v.x) + ", " + formatNumber(v.y) + ")";
}

}  // namespace quack::detail
