#pragma once
/// The state file `quack run` writes: where every body ended, how many events happened,
/// and how long it took. Format (keys exact):
///
/// {"time": seconds, "steps": n,
///  "bodies": [{"name", "pos": [x, y], "angle", "vel": [x, y], "angvel"}, ...],
///  "events": {"begin", "end", "hit", "sensor"},
///  "timing": {"ms_per_step", "total_ms"}}
///
/// Numbers are written so that reading them back gives the same floats (round trip).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "quack/core/result.hpp"
#include "quack/math/vec2.hpp"

namespace quack {

struct SceneWorld;

struct BodyState {
  std::string name;
  Vec2 pos;             ///< body origin, world frame
  float angle = 0.0f;   ///< radians
  Vec2 vel;             ///< centre of mass, m/s
  float angvel = 0.0f;  ///< rad/s
  friend bool operator==(const BodyState&, const BodyState&) = default;
};

/// Events counted over a whole run (sensor: sensor begin events).
struct EventTotals {
  std::uint64_t begin = 0, end = 0, hit = 0, sensor = 0;
  friend bool operator==(const EventTotals&, const EventTotals&) = default;
};

struct RunTiming {
  double msPerStep = 0.0;
  double totalMs = 0.0;
  friend bool operator==(const RunTiming&, const RunTiming&) = default;
};

struct StateFile {
  double time = 0.0;
  std::uint64_t steps = 0;
  std::vector<BodyState> bodies;
  EventTotals events;
  RunTiming timing;
  friend bool operator==(const StateFile&, const StateFile&) = default;
};

/// The state of a scene's world now, in scene order.
StateFile captureState(const SceneWorld& scene, const EventTotals& events, const RunTiming& timing);
/// JSON text of a state file.
std::string writeState(const StateFile& state);
/// Reads a state file back; errors name the file and the JSON path.
Result<StateFile> parseState(std::string_view text, const std::string& fileName);

}  // namespace quack
