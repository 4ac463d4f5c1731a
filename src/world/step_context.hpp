#pragma once
// What every phase of a step works with (World::step builds one per step): the world's
// settings, the bodies, the broad phase, the event lists, the workers, and the step's
// length. The phases take it, and what else each needs, instead of long argument lists;
// each returns what it produced (docs/ARCHITECTURE.md, "One step through the code").

namespace quack {
struct WorldDef;
class BroadPhase;
}  // namespace quack

namespace quack::detail {

class BodyStore;
class EventDispatcher;
class JointSet;
class TaskRunner;

struct StepContext {
  const WorldDef& def;
  BodyStore& store;
  BroadPhase& broadPhase;
  const JointSet& joints;  // which pairs of bodies must not collide
  EventDispatcher& events;
  TaskRunner& tasks;
  float dt = 0.0f;   // seconds
  int substeps = 1;  // the solver's
};

}  // namespace quack::detail
