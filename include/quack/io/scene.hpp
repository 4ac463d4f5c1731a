#pragma once
/// Scene files: the JSON format of the README ("Scene files"), parsed and checked in full
/// before anything is built, and the world built from them.
///
/// Every error names the file, the JSON path and what is wrong:
/// `scenes/bad.json: bodies[3].shapes[0].radius: must be > 0`. Every default is listed in
/// docs/scenes.md.

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "quack/core/result.hpp"
#include "quack/world/world.hpp"

namespace quack {

/// Limits of scene files (docs/scenes.md, "Limits"). A value outside them is an error that
/// names its field, so a scene never builds a world whose numbers overflow a float.
inline constexpr float kSceneMaxTimeStep = kMaxTimeStep;          ///< world.dt, seconds
inline constexpr int kSceneMaxSubsteps = 64;                      ///< world.substeps
inline constexpr float kSceneMaxGravity = kMaxGravity;            ///< |world.gravity|, m/s^2
inline constexpr float kSceneMaxSpeed = kMaxLinearSpeed;          ///< |vel|, m/s
inline constexpr float kSceneMaxAngularSpeed = kMaxAngularSpeed;  ///< |angvel|, rad/s
inline constexpr float kSceneMaxAngle = 1.0e4f;                   ///< |angle| of a body, radians
inline constexpr float kSceneMaxDensity = 1.0e9f;                 ///< kg/m^2
inline constexpr float kSceneMaxFriction = 1.0e3f;                ///< friction coefficient
inline constexpr float kSceneMaxRestitution = kMaxRestitution;    ///< above 1 adds energy
inline constexpr double kSceneMaxMass =
    static_cast<double>(kMaxBodyMass);                    ///< kg, of a dynamic body
inline constexpr double kSceneMaxInertia = 1.0e30;        ///< kg m^2, of a dynamic body
inline constexpr float kSceneMinGeneratedSize = 1.0e-6f;  ///< generator sizes, metres
inline constexpr float kSceneMaxGeneratedSize = 1.0e6f;   ///< generator sizes, metres
inline constexpr std::size_t kSceneMaxBodies = 1000000;   ///< listed and generated

/// A shape of a scene body: geometry in the body frame, and its material and filter.
struct SceneShape {
  ShapeGeometry geometry;
  ShapeDef def;
  /// Where it came from, for messages: "bodies[3].shapes[0]" or "generate[1]".
  std::string path;
};

/// A chain of one-sided segments on a static scene body (World::createChain), body frame.
struct SceneChain {
  std::vector<Vec2> points;
  bool loop = false;
  ShapeDef def;
  std::string path;  ///< "bodies[0].shapes[2]"
};

/// A body of a scene, listed or generated.
struct SceneBody {
  std::string name;
  /// Where it came from, for messages: "bodies[3]", or "generate[1]" for a generated body.
  std::string path;
  BodyDef def;
  std::vector<SceneShape> shapes;
  /// Chains, made after the shapes ({"type": "chain"} in the file; static bodies only).
  std::vector<SceneChain> chains;
};

/// A joint of a scene ({"type": "revolute", "a": NAME, "b": NAME, ...} in "joints"):
/// its settings (world-frame anchors and axis, as the file gives them) and its bodies as
/// indices into Scene::bodies (`a` is kNoSceneBody for a mouse joint).
inline constexpr std::size_t kNoSceneBody = static_cast<std::size_t>(-1);
struct SceneJoint {
  JointDef def;  ///< bodyA and bodyB are set when the world is built
  std::size_t a = kNoSceneBody, b = kNoSceneBody;
  std::string path;  ///< "joints[2]"
};

/// A parsed scene: the world settings and every body, listed bodies first, then the
/// generators' bodies in order; then the joints.
struct Scene {
  std::string file;  ///< where it came from, for messages
  WorldDef world;
  /// Category names; category i is filter bit i.
  std::vector<std::string> categories;
  std::vector<SceneBody> bodies;
  std::vector<SceneJoint> joints;
};

/// One entry of a scene's "joints" list, checked as parseScene checks it (docs/scenes.md,
/// "Joints"): its "a" and "b" name bodies of `bodies`, and each message starts with `path`
/// and the key (`joints[2].hertz: must be >= 0`). Other
/// front ends (the Python module's World.create_joint) call it so that a joint means the
/// same wherever it is made.
Result<SceneJoint> parseSceneJoint(const nlohmann::json& joint, const std::string& path,
                                   const std::vector<SceneBody>& bodies);

/// Progress of a long scene operation: `done` of `total` bodies (total 0: not known yet).
/// Return false to stop; the operation then fails with "interrupted".
using SceneProgress = std::function<bool(std::size_t done, std::size_t total)>;

/// Parses and checks a scene. `fileName` prefixes every error message. `progress`, when
/// given, is called every few thousand bodies made.
Result<Scene> parseScene(std::string_view text, const std::string& fileName,
                         const SceneProgress& progress = {});
/// Reads and parses a scene file (errors: a missing, unreadable or directory path with
/// the reason, and those of parseScene).
Result<Scene> loadScene(const std::string& path, const SceneProgress& progress = {});

/// A world built from a scene, with its bodies in scene order and their names, and its
/// joints in scene order.
struct SceneWorld {
  World world;
  std::vector<BodyId> bodies;
  std::vector<std::string> names;
  std::vector<JointId> joints;
};

/// Builds the world. The scene was checked when parsed, so this fails only on what the
/// world itself refuses; the message names the scene field (`bodies[3].shapes[0]`, or the
/// generator and the body's name). `progress` as for parseScene.
Result<SceneWorld> buildWorld(const Scene& scene, const SceneProgress& progress = {});

}  // namespace quack
