#pragma once
// The 3D world's continuous collision: after the solver, a body that moved more than half
// its thinnest shape in the step is swept from where the step began to where it ended
// against the static shapes and meshes in the way, the bodies that did not move fast (at
// their end poses) and the other fast bodies (sweep against sweep). The meetings are taken
// in time order; each puts its bodies back to that time (velocities kept, so the next step's
// contacts meet the surface), and a body put back stays there for the rest of the step, met
// there by the fast bodies still moving. Private to the world layer.

#include <cstdint>
#include <utility>
#include <vector>

#include "body_store3.hpp"
#include "quack/math/sweep3.hpp"
#include "task_runner.hpp"

namespace quack::detail {

// Most pairs of fast bodies whose swept boxes overlap that one step checks; the pairs past
// it are left to the speculative contacts (each pair costs a time of impact, and again when
// one of the two is put back).
inline constexpr int kMaxFastPairs3 = 1 << 16;

enum class Continuous3Status : std::uint8_t {
  complete,     // every pair of fast bodies with overlapping swept boxes was checked
  pairsCapped,  // more than the cap of pairs: the rest were not checked
};

struct Continuous3Result {
  int fastBodies = 0;  // bodies swept
  int fastPairs = 0;   // pairs of fast bodies checked against each other
  int putBack = 0;     // bodies put back to a time of impact
  Continuous3Status status = Continuous3Status::complete;
};

class Continuous3 {
 public:
  // Before the solver: remembers where every awake dynamic body starts the step.
  void recordStarts(const BodyStore3& store);
  // After the solver: sweeps the fast bodies and puts them back, meetings in time order
  // (ties to the lower body index), so the result does not depend on the order of the bodies.
  // The searches run on `tasks`' workers; the result is the same for any number.
  Continuous3Result solve(BodyStore3& store, TaskRunner& tasks, int maxPairs = kMaxFastPairs3);

 private:
  struct Start {
    std::uint32_t body;
    Transform3 pose;
  };
  struct Fast {
    std::uint32_t body;
    Transform3 start;
    Sweep3 sweep;
    Aabb3 startBox;          // its shapes' boxes at the start, together
    Aabb3 box;               // its shapes' swept boxes together
    float stillTime = 1.0f;  // first impact with static or slow shapes (1: none)
    float stopTime = 1.0f;   // when it was put back (1: not put back)
    bool stopped = false;
  };
  enum class Kind : std::uint8_t {
    still,    // a meets static geometry or a body that is not fast
    moving,   // a and b (a < b) meet, both on their sweeps
    stopped,  // a, on its sweep, meets b where b was put back
  };
  struct Event {
    float t;      // step fraction
    float local;  // kind stopped: the fraction of a's sweep left after b stopped; else t
    std::uint32_t a, b;
    Kind kind;
  };

  void findFast(const BodyStore3& store);
  float meetStill(const BodyStore3& store, const Fast& f,
                  std::vector<std::uint32_t>& candidates) const;
  float meetMoving(const BodyStore3& store, const Fast& a, const Fast& b, float tMax) const;
  float meetStopped(const BodyStore3& store, const Fast& moving, const Sweep3& rest,
                    const Fast& stopped) const;
  void findPairs(int maxPairs, Continuous3Result& result);
  void stop(BodyStore3& store, std::uint32_t f, float t, const Transform3& at);
  void pushEvent(const Event& e);

  std::vector<Start> starts_;
  std::vector<std::vector<std::uint32_t>> candidateParts_;  // per worker: meetStill's
  std::vector<float> pairTimes_;                            // per pair: meetMoving's
  std::vector<Fast> fast_;            // the bodies that moved fast, in body order
  std::vector<std::uint8_t> isFast_;  // per body index
  std::vector<std::uint32_t> order_;  // fast_ by the sweep axis
  // Pairs of fast bodies (indices into fast_) whose swept boxes overlap, and each body's
  // neighbours among them (neighbourStart_[i] .. neighbourStart_[i + 1] in neighbours_).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs_;
  std::vector<std::uint32_t> neighbourStart_, neighbours_;
  std::vector<Event> events_;  // a binary heap, earliest on top
  std::vector<std::uint32_t> justStopped_;
};

}  // namespace quack::detail
