#pragma once
// Number formatting for error messages (internal to the geometry layer).

#include <cstdio>
#include <string>

#include "quack/math/vec2.hpp"

namespace quack::detail {

inline std::string formatNumber(float x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(x));
  return buf;
}

inline std::string formatVec(Vec2 v) {
  return "(" + formatNumber(v.x) + ", " + formatNumber(v.y) + ")";
}

}  // namespace quack::detail
