#pragma once
/// The state file `quack run` writes: where every body ended and how many events happened.
/// Format (keys exact):
///
/// {"time": seconds, "steps": n,
///  "bodies": [{"name", "pos": [x, y], "angle", "vel": [x, y], "angvel", "awake"}, ...],
///  "events": {"begin", "end", "hit", "sensor"}}
///
/// plus, when the scene has joints, "joints": [{"type", "a", "b", "force": [x, y],
/// "torque"}, ...]: each joint still alive at the end, in scene order, with the bodies'
/// names and the force (N, on b, world frame) and torque (N m) it applied in the last step.
///
/// A state file is a pure function of the scene and the step count: two runs write the
/// same bytes. How long a run took is not in it (`quack run` prints it, and writes it with
/// `--timing FILE`); a "timing" object in a file from an older Quack is accepted and
/// ignored. Numbers are written so that reading them back gives the same floats.
/// "awake" is World::isAwake at the end (false for a sleeping body, and always for a
/// static one); a file from a Quack without sleeping has none, and reads as awake.
///
/// The 3D state file (a World3 run, `StateFile3`) says its dimension first and has 3- and
/// 4-component vectors, and only the events the 3D world has:
///
/// {"dim": 3, "time": seconds, "steps": n,
///  "bodies": [{"name", "pos": [x, y, z], "quat": [x, y, z, w], "vel": [x, y, z],
///              "angvel": [x, y, z], "awake"}, ...],
///  "events": {"begin", "end"}}
///
/// with the same promises: a pure function of the scene and the step count, numbers that
/// read back as the same floats. Each reader refuses the other dimension's file, saying so.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "quack/core/result.hpp"
#include "quack/math/quat.hpp"
#include "quack/math/vec2.hpp"
#include "quack/math/vec3.hpp"
#include "quack/world/types.hpp"

namespace quack {

struct SceneWorld;
struct SceneWorld3;
struct StepEvents3;

struct BodyState {
  std::string name;
  Vec2 pos;             ///< body origin, world frame
  float angle = 0.0f;   ///< radians
  Vec2 vel;             ///< centre of mass, m/s
  float angvel = 0.0f;  ///< rad/s
  bool awake = true;    ///< World::isAwake: false while asleep, and for static bodies
  friend bool operator==(const BodyState&, const BodyState&) = default;
};

/// Events counted over a whole run (sensor: sensor begin events).
struct EventTotals {
  std::uint64_t begin = 0, end = 0, hit = 0, sensor = 0;
  friend bool operator==(const EventTotals&, const EventTotals&) = default;
};

/// A joint of a state file.
struct JointState {
  std::string type;  ///< "revolute", ...
  std::string a, b;  ///< the bodies' names ("" for a mouse joint's missing body a)
  Vec2 force;        ///< N, on b, world frame, in the last step
  float torque = 0.0f;
  friend bool operator==(const JointState&, const JointState&) = default;
};

struct StateFile {
  double time = 0.0;
  std::uint64_t steps = 0;
  std::vector<BodyState> bodies;
  std::vector<JointState> joints;  ///< written only when the scene has joints
  bool hasJoints = false;
  EventTotals events;
  friend bool operator==(const StateFile&, const StateFile&) = default;
};

/// The state of a scene's world now, in scene order.
StateFile captureState(const SceneWorld& scene, const EventTotals& events);
/// JSON text of a state file.
std::string writeState(const StateFile& state);
/// Reads a state file back; errors name the file and the JSON path.
Result<StateFile> parseState(std::string_view text, const std::string& fileName);

/// Appends one step's events as event-list lines (`quack run --events`), one JSON object a
/// line, in the world's order: contact begin, end, hit, sensor begin, sensor end,
/// time of impact, out of bounds. Shapes and bodies are named by their id's index (the same
/// on every build: ids are handed out in creation order); numbers print exactly as in state
/// files, so two builds that agree on the events write the same bytes. `step` counts from 1.
///
///   {"step": 3, "event": "begin", "a": 4, "b": 9}
///   {"step": 3, "event": "end", "a": 4, "b": 9}
///   {"step": 3, "event": "hit", "a": 4, "b": 9, "point": [x, y], "normal": [x, y], "speed": v}
///   {"step": 3, "event": "sensor-begin", "sensor": 2, "visitor": 7}   (and "sensor-end")
///   {"step": 3, "event": "toi", "time": t, "a": 4, "b": 9, "point": [x, y], "normal": [x, y]}
///   {"step": 3, "event": "out-of-bounds", "body": 5}
///   {"step": 3, "event": "joint-end", "joint": 2, "reason": "broken", "force": [x, y],
///    "torque": t}   (reason "broken" or "body-destroyed"; the joint's id index)
void appendEventLines(std::string& out, std::uint64_t step, const StepEvents& events);

/// A body of a 3D state file.
struct BodyState3 {
  std::string name;
  Vec3 pos;           ///< body origin, world frame
  Quat quat;          ///< worldFromBody's rotation, [x, y, z, w]
  Vec3 vel;           ///< centre of mass, m/s
  Vec3 angvel;        ///< rad/s, world axes
  bool awake = true;  ///< World3::isAwake, and false for a static body (as in 2D)
  friend bool operator==(const BodyState3&, const BodyState3&) = default;
};

/// A 3D state file. `events` counts begin and end only (the 3D world has no hit or
/// sensor events; those stay 0 and are not written).
struct StateFile3 {
  double time = 0.0;  ///< steps times the world's dt, in double
  std::uint64_t steps = 0;
  std::vector<BodyState3> bodies;
  EventTotals events;
  friend bool operator==(const StateFile3&, const StateFile3&) = default;
};

/// The state of a 3D scene's world now, in scene order.
StateFile3 captureState3(const SceneWorld3& scene, const EventTotals& events);
/// JSON text of a 3D state file (one body per line).
std::string writeState3(const StateFile3& state);
/// Reads a 3D state file back; errors name the file and the JSON path. A 2D state file is
/// refused with a message saying so.
Result<StateFile3> parseState3(std::string_view text, const std::string& fileName);

/// Appends one step's 3D events as event-list lines, as appendEventLines: begin, then end,
/// shapes named by their id's index. `step` counts from 1.
///
///   {"step": 3, "event": "begin", "a": 4, "b": 9}
///   {"step": 3, "event": "end", "a": 4, "b": 9}
void appendEventLines3(std::string& out, std::uint64_t step, const StepEvents3& events);

}  // namespace quack
