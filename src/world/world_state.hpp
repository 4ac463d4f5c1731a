#pragma once
// Everything a World holds: its parts, each with one job (docs/ARCHITECTURE.md, "The world
// inside"). Data flows one way through a step: bodies -> broad phase -> contact set ->
// solver -> continuous phase -> events. World (world.cpp) is the facade over them.

#include <cstdint>
#include <string>
#include <vector>

#include "body_store.hpp"
#include "contact_set.hpp"
#include "continuous.hpp"
#include "event_dispatcher.hpp"
#include "ghost_edges.hpp"
#include "islands.hpp"
#include "joint_set.hpp"
#include "quack/collision/proxy.hpp"
#include "quack/world/world.hpp"
#include "solver.hpp"
#include "task_runner.hpp"

namespace quack::detail {

// WorldDef::workerCount, or the test suites' override (tasks.hpp, setTestWorkerCount).
int effectiveWorkerCount(const WorldDef& def) noexcept;

struct WorldState {
  WorldState(const WorldDef& d, BroadPhase bp, std::uint32_t worldId)
      : def(d), broadPhase(std::move(bp)), store(worldId) {
    tasks.configure(effectiveWorkerCount(d), d.enqueueTask, d.finishTask, d.userTaskContext);
  }

  WorldDef def;
  BroadPhase broadPhase;
  BodyStore store;
  ContactSet contacts;
  JointSet joints;
  IslandSet islands;
  GhostEdges edges;
  Solver solver;
  ContinuousPhase continuous;
  EventDispatcher events;
  TaskRunner tasks;

  // Destruction asked for inside a callback waits until the callbacks are done.
  std::vector<std::uint32_t> pendingBodyDestroy;
  std::vector<std::uint32_t> pendingShapeDestroy;
  std::vector<std::uint32_t> pendingJointDestroy;
  std::uint64_t stepCount = 0;
  double time = 0.0;
  bool inStep = false;
  bool inCallbacks = false;
  // Set when a step's phases threw (an allocation failure): the state may be half updated,
  // so World refuses changes until a snapshot is restored. Empty when the world is sound.
  std::string failure;
};

// The handle of joint slot `joint` (world_joints.cpp).
JointId jointId(const WorldState& w, std::uint32_t joint) noexcept;
// Destroys a joint now (world_joints.cpp): its bodies wake, their island is marked for a
// split, and, unless it let them collide, their shapes look for pairs again.
void destroyJointNow(WorldState& w, std::uint32_t joint);

// A new world id: unique in the process, never 0 (world.cpp).
std::uint32_t nextWorldId();
// The checks World::create makes of a WorldDef, each failing with a message naming the field.
Status checkWorldDef(const WorldDef& def);
// The broad phase a world with `def` runs on (World::create and snapshots both build it).
BroadPhaseConfig worldBroadPhaseConfig(const WorldDef& def) noexcept;
// The fat-box margin of a shape's proxy (world.cpp, worldBroadPhaseConfig): the speculative
// distance plus an eighth of the shape's extent, at most kWorldFatMargin; twice the
// speculative distance for a static body's shape.
inline constexpr float kWorldFatMargin = 0.05f;
inline constexpr float kWorldFatMarginFraction = 0.125f;
float shapeFatMargin(const ShapeGeometry& geometry, BodyType type, const WorldDef& def) noexcept;

}  // namespace quack::detail
