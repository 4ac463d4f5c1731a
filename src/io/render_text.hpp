#pragma once
// Text for pictures and replays (internal to the io layer), shared by the 2D (render.cpp)
// and 3D (render3.cpp) replays.

#include <string>

namespace quack::detail {

/// Numbers for pictures: 4 decimals (0.1 mm, 0.1 mrad) is below what a screen shows, and
/// keeps big replays small. Trailing zeros are trimmed; a non-finite number is written 0.
void appendPictureNumber(std::string& out, double x);
/// A string as JSON inside an HTML <script> (no "</" may appear).
std::string scriptJsonString(const std::string& s);
/// A string for XML and HTML text.
std::string xmlEscape(const std::string& s);

}  // namespace quack::detail
