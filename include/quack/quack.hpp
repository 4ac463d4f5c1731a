#pragma once
/// Everything in Quack, one include: `#include "quack/quack.hpp"` with `quack::quack`.
/// Each layer also has its own header (`quack/<layer>/<layer>.hpp`, the world's is
/// `quack/world/world.hpp`) for programs that link only part of it. The io layer (scene
/// files, pictures) is here too when it was built (QUACK_BUILD_IO, the default).

#include "quack/broadphase/broadphase.hpp"
#include "quack/collision/collision.hpp"
#include "quack/core/core.hpp"
#include "quack/geometry/geometry.hpp"
#include "quack/math/math.hpp"
#include "quack/world/world.hpp"
#if __has_include("quack/io/io.hpp") && __has_include(<nlohmann/json.hpp>)
#include "quack/io/io.hpp"
#endif
