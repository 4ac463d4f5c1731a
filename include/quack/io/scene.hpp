#pragma once
/// Scene files: the JSON format of the README ("Scene files"), parsed and checked in full
/// before anything is built, and the world built from them.
///
/// Every error names the file, the JSON path and what is wrong:
/// `scenes/bad.json: bodies[3].shapes[0].radius: must be > 0`. Every default is listed in
/// docs/scenes.md.

#include <string>
#include <string_view>
#include <vector>

#include "quack/core/result.hpp"
#include "quack/world/world.hpp"

namespace quack {

/// A shape of a scene body: geometry in the body frame, and its material and filter.
struct SceneShape {
  ShapeGeometry geometry;
  ShapeDef def;
};

/// A chain of one-sided segments on a static scene body (World::createChain), body frame.
struct SceneChain {
  std::vector<Vec2> points;
  bool loop = false;
  ShapeDef def;
};

/// A body of a scene, listed or generated.
struct SceneBody {
  std::string name;
  BodyDef def;
  std::vector<SceneShape> shapes;
  /// Chains, made after the shapes ({"type": "chain"} in the file; static bodies only).
  std::vector<SceneChain> chains;
};

/// A parsed scene: the world settings and every body, listed bodies first, then the
/// generators' bodies in order.
struct Scene {
  std::string file;  ///< where it came from, for messages
  WorldDef world;
  /// Category names; category i is filter bit i.
  std::vector<std::string> categories;
  std::vector<SceneBody> bodies;
};

/// Parses and checks a scene. `fileName` prefixes every error message.
Result<Scene> parseScene(std::string_view text, const std::string& fileName);
/// Reads and parses a scene file (errors: unreadable file, and those of parseScene).
Result<Scene> loadScene(const std::string& path);

/// A world built from a scene, with its bodies in scene order and their names.
struct SceneWorld {
  World world;
  std::vector<BodyId> bodies;
  std::vector<std::string> names;
};

/// Builds the world. The scene was checked when parsed, so this fails only on what the
/// world itself refuses, with the body's name and index.
Result<SceneWorld> buildWorld(const Scene& scene);

}  // namespace quack
