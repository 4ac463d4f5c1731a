#pragma once
// The 3D world's parts, held together: what World3 (world3.cpp) and its queries
// (world3_queries.cpp) reach through their one pointer. Private to the world layer.

#include <cstdint>
#include <vector>

#include "body_store3.hpp"
#include "contact_set3.hpp"
#include "continuous3.hpp"
#include "islands3.hpp"
#include "solver3.hpp"
#include "task_runner.hpp"

namespace quack::detail {

// WorldDef3's checks (world3.cpp), for snapshots.
Status checkWorldDef3(const WorldDef3& def);
std::uint32_t nextWorldId();  // world.cpp: one sequence for the 2D and 3D worlds

struct WorldState3 {
  WorldState3(const WorldDef3& d, BroadPhase3 bp, std::uint32_t worldId)
      : def(d), id(worldId), store(std::move(bp)), contacts(worldId) {
    // The workers from def (or the test suites' override, as the 2D world's).
    tasks.configure(effectiveWorkerCount(def.workerCount, def.enqueueTask != nullptr),
                    def.enqueueTask, def.finishTask, def.userTaskContext);
  }
  WorldDef3 def;
  std::uint32_t id;
  BodyStore3 store;
  ContactSet3 contacts;
  Solver3 solver;
  Continuous3 continuous;
  Islands3 islands;
  TaskRunner tasks;
  StepEvents3 events;
  std::vector<ContactEvent3> pendingEnds;  // of shapes destroyed since the last step
  std::uint64_t stepCount = 0;

  // The user's callbacks (World3::onContactBegin, onContactEnd), in registration order.
  struct Callback {
    bool begin = true;
    std::uint64_t categoriesA = 0, categoriesB = 0;
    World3::ContactCallback3 f;
  };
  std::vector<Callback> callbacks;
  bool inCallbacks = false;

  ShapeId3 shapeId(std::uint32_t shape) const noexcept {
    return {shape, store.shapeIds.generation(shape), id};
  }
  BodyId3 bodyId(std::uint32_t body) const noexcept {
    return {body, store.bodyIds.generation(body), id};
  }
};

}  // namespace quack::detail
