#pragma once
/// The io layer: JSON shapes and scene files (2D and 3D), state files, SVG and HTML replays. Needs
/// nlohmann-json (Debian `nlohmann-json3-dev`); link `quack::io` (or `quack::quack`).

#include "quack/io/answer_json.hpp"
#include "quack/io/number_text.hpp"
#include "quack/io/render.hpp"
#include "quack/io/render3.hpp"
#include "quack/io/scene.hpp"
#include "quack/io/scene3.hpp"
#include "quack/io/shape_json.hpp"
#include "quack/io/state.hpp"
