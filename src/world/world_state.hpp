#pragma once
// Everything a World holds: its parts, each with one job (docs/ARCHITECTURE.md, "The world
// inside"). Data flows one way through a step: bodies -> broad phase -> contact set ->
// solver -> continuous phase -> events. World (world.cpp) is the facade over them.

#include <cstdint>
#include <vector>

#include "body_store.hpp"
#include "contact_set.hpp"
#include "continuous.hpp"
#include "event_dispatcher.hpp"
#include "ghost_edges.hpp"
#include "islands.hpp"
#include "quack/collision/proxy.hpp"
#include "quack/world/world.hpp"
#include "solver.hpp"

namespace quack::detail {

struct WorldState {
  WorldState(const WorldDef& d, BroadPhase bp, std::uint32_t worldId)
      : def(d), broadPhase(std::move(bp)), store(worldId) {}

  WorldDef def;
  BroadPhase broadPhase;
  BodyStore store;
  ContactSet contacts;
  IslandSet islands;
  GhostEdges edges;
  Solver solver;
  ContinuousPhase continuous;
  EventDispatcher events;

  // Destruction asked for inside a callback waits until the callbacks are done.
  std::vector<std::uint32_t> pendingBodyDestroy;
  std::vector<std::uint32_t> pendingShapeDestroy;
  std::uint64_t stepCount = 0;
  double time = 0.0;
  bool inStep = false;
  bool inCallbacks = false;
};

}  // namespace quack::detail
