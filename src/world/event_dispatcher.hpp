#pragma once
// The event dispatcher: one part of the world. It owns the step's event lists, the user's
// callbacks and the end events of shapes destroyed between steps, and calls the callbacks
// at the end of a step so that callbacks and event lists always agree.

#include <array>
#include <cstdint>
#include <vector>

#include "quack/world/world.hpp"

namespace quack::detail {

class BodyStore;
struct Contact;

class EventDispatcher {
 public:
  enum class Kind { begin, end, hit, sensorBegin, sensorEnd, impact, jointEnd };
  struct Callback {
    Kind kind;
    std::uint64_t categoriesA, categoriesB;
    World::ContactCallback contact;
    World::HitCallback hit;
    World::ImpactCallback impact;
    World::JointEndCallback jointEnd;
  };

  StepEvents events;

  /// Clears the lists for a new step and moves in the ends of shapes destroyed since.
  void beginStep();
  /// A contact (or sensor overlap) ended: in this step's lists, or, between steps, kept for
  /// the next step's. The shapes' categories are kept for selecting callbacks.
  void contactEnded(const BodyStore& store, const Contact& c, bool inStep);
  void add(Kind kind, std::uint64_t a, std::uint64_t b, World::ContactCallback contact,
           World::HitCallback hit, bool fromCallback, World::ImpactCallback impact = {});
  void addJointEnd(World::JointEndCallback f, bool fromCallback);
  /// Calls the callbacks, in event order, kind by kind (begin, end, sensor begin, sensor
  /// end, hit, impact, joint end); then takes in callbacks registered meanwhile.
  void dispatch(World& world, const BodyStore& store);

 private:
  friend class SnapshotCodec;  // snapshot.cpp reads and rebuilds every field
  struct PendingEnd {
    ShapeId shapeA, shapeB;
    std::uint64_t categoryA = 0, categoryB = 0;
    bool sensor = false;
  };
  std::vector<Callback> callbacks_;
  std::vector<Callback> pending_;  // registered from inside a callback
  std::vector<PendingEnd> endsSinceStep_;
  // The categories of the shapes of events.end and events.sensorEnd, index for index:
  // their shapes may be destroyed before the callbacks run.
  std::vector<std::array<std::uint64_t, 2>> endCategories_;
  std::vector<std::array<std::uint64_t, 2>> sensorEndCategories_;
};

}  // namespace quack::detail
