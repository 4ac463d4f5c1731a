#pragma once
/// The whole collision layer.
#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/minkowski.hpp"
#include "quack/collision/pieces.hpp"
#include "quack/collision/proxy.hpp"
#include "quack/collision/sat.hpp"
#include "quack/collision/shape_cast.hpp"
#include "quack/collision/simplex2.hpp"
#include "quack/collision/toi.hpp"
