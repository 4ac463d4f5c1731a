#pragma once
/// The whole geometry layer.
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/decompose.hpp"
#include "quack/geometry/hull.hpp"
#include "quack/geometry/hull3.hpp"
#include "quack/geometry/mass.hpp"
#include "quack/geometry/mass3.hpp"
#include "quack/geometry/raycast.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/geometry/shapes.hpp"
#include "quack/geometry/shapes3.hpp"
