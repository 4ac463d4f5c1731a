#pragma once
/// The core layer: asserts, `Result`/`Status`, generational id pools.

#include "quack/core/assert.hpp"
#include "quack/core/id_pool.hpp"
#include "quack/core/result.hpp"
