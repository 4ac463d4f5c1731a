#pragma once
/// The broad-phase layer: the five structures behind `BroadPhase`, pairs, filters, queries.

#include "quack/broadphase/broad_phase.hpp"
#include "quack/broadphase/brute_force.hpp"
#include "quack/broadphase/dynamic_tree.hpp"
#include "quack/broadphase/proxy.hpp"
#include "quack/broadphase/quadtree.hpp"
#include "quack/broadphase/spatial_hash.hpp"
#include "quack/broadphase/sweep_and_prune.hpp"
