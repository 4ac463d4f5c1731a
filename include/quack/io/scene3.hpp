#pragma once
/// 3D scene files: the 2D format (scene.hpp, docs/scenes.md) with "dim": 3 in "world",
/// three-component vectors, a body's orientation as "quat": [x, y, z, w], and the 3D shapes
/// of `quack query` (shape_json.hpp: sphere, capsule, box, hull, triangle, and on static
/// bodies mesh). Parsed and checked in full before anything is built; every error names
/// the file, the JSON path and what is wrong (`scenes/bad-3d.json: bodies[2].quat: [0, 0, 0,
/// 0] is not a rotation ...`). Every key and default is listed in docs/scenes.md, "3D
/// scenes".
///
/// `parseAnyScene` and `loadAnyScene` read either dimension (what `quack run` calls).

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "quack/collision/mesh3.hpp"
#include "quack/core/result.hpp"
#include "quack/geometry/shapes3.hpp"
#include "quack/io/scene.hpp"
#include "quack/world/world3.hpp"

namespace quack {

/// Farthest a 3D body's origin may be from the world origin, per axis, metres: World3's
/// own limit (half the coordinate limit, so that its shapes still fit inside it).
inline constexpr float kScene3MaxPosition = 0.5f * kMaxCoordinate;

/// A shape's geometry in a 3D scene: a convex shape (or a triangle), or a triangle mesh
/// (static bodies only).
using SceneGeometry3 = std::variant<ShapeGeometry3, Mesh3>;

/// A shape of a 3D scene body: geometry in the body frame, and its material and filter.
struct SceneShape3 {
  SceneGeometry3 geometry;
  ShapeDef3 def;
  std::string path;  ///< "bodies[3].shapes[0]", for messages
};

/// A body of a 3D scene.
struct SceneBody3 {
  std::string name;
  std::string path;  ///< "bodies[3]", for messages
  BodyDef3 def;
  /// False: the body starts asleep (World3::setAwake after its shapes are made).
  bool awake = true;
  std::vector<SceneShape3> shapes;
};

/// A parsed 3D scene: the world settings and every body, in file order.
struct Scene3 {
  std::string file;  ///< where it came from, for messages
  WorldDef3 world;
  /// Category names; category i is filter bit i.
  std::vector<std::string> categories;
  std::vector<SceneBody3> bodies;
};

/// Parses and checks a 3D scene ("dim": 3 is required; a 2D scene is an error that says
/// so). `fileName` prefixes every error message; `progress` as for parseScene.
Result<Scene3> parseScene3(std::string_view text, const std::string& fileName,
                           const SceneProgress& progress = {});
/// Reads and parses a 3D scene file (errors as loadScene's and parseScene3's).
Result<Scene3> loadScene3(const std::string& path, const SceneProgress& progress = {});

/// A scene of either dimension.
using AnyScene = std::variant<Scene, Scene3>;
/// Parses a scene of either dimension, chosen by "world": {"dim"} (2 when absent; any
/// other value than 2 or 3 is an error naming world.dim). The text is parsed once.
Result<AnyScene> parseAnyScene(std::string_view text, const std::string& fileName,
                               const SceneProgress& progress = {});
/// Reads and parses a scene file of either dimension.
Result<AnyScene> loadAnyScene(const std::string& path, const SceneProgress& progress = {});

/// A 3D world built from a scene, with its bodies in scene order, their names, and each
/// body's shapes in file order.
struct SceneWorld3 {
  World3 world;
  std::vector<BodyId3> bodies;
  std::vector<std::string> names;
  std::vector<std::vector<ShapeId3>> shapes;
};

/// Builds the world. The scene was checked when parsed, so this fails only on what the
/// world itself refuses; the message names the scene field (`bodies[3].shapes[0]: ...`).
Result<SceneWorld3> buildWorld3(const Scene3& scene, const SceneProgress& progress = {});

}  // namespace quack
