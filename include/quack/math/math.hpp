#pragma once
/// The whole math layer.
#include "quack/math/aabb.hpp"
#include "quack/math/mat3.hpp"
#include "quack/math/quat.hpp"
#include "quack/math/rot.hpp"
#include "quack/math/sweep.hpp"
#include "quack/math/sweep3.hpp"
#include "quack/math/transform.hpp"
#include "quack/math/transform3.hpp"
#include "quack/math/vec2.hpp"
#include "quack/math/vec3.hpp"
