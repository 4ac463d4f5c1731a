#pragma once
/// Shapes and poses from JSON, in the formats of the README ("Formats"), shared by scene
/// files and `quack query`.
///
/// Shape: {"type": "circle", "center": [x, y] (default [0, 0]), "radius": r > 0}
///        {"type": "capsule", "p1": [x, y], "p2": [x, y], "radius": r > 0}
///        {"type": "segment", "p1": [x, y], "p2": [x, y]}
///        {"type": "box", "half": [hx, hy], "center": [0, 0], "angle": 0, "radius": 0}
///        {"type": "polygon", "points": [[x, y], ...] (convex, 3 to 64), "radius": 0}
///        {"type": "concave", "points": [[x, y], ...] (a simple polygon, either orientation,
///         3 to 1,024 points with its holes), "holes": [[[x, y], ...], ...] (optional)}:
///         split into convex pieces by decomposePolygon (geometry/decompose.hpp); no radius
///         (rounded pieces would overlap and bulge at the seams).
/// Pose:  {"pos": [x, y] (default [0, 0]), "angle": radians (default 0)}; a missing pose
///        is the identity.
/// Unknown keys are errors; every error names the field, e.g. "a.radius: must be > 0".
/// Positions, points, half-extents and radii must lie within the coordinate limit
/// (kMaxCoordinate, 1e9 m), e.g. "a.half[0]: 1e+19 m is beyond the coordinate limit 1e9 m".

#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "quack/collision/manifold.hpp"
#include "quack/collision/proxy.hpp"
#include "quack/core/result.hpp"
#include "quack/world/types.hpp"

namespace quack {

/// One parsed shape of any kind, shape frame. A proxy made from it views its storage, so
/// keep the ParsedShape alive (and unmoved) while the proxy is in use.
struct ParsedShape {
  ShapeType type = ShapeType::circle;
  Circle circle;
  Capsule capsule;
  Segment segment;
  Polygon polygon;  ///< for a concave shape, its first piece
  /// A "concave" shape: `pieces` holds its convex pieces (type is polygon). Use
  /// geometries() or proxies() to see every piece; the single-shape accessors below give
  /// the first piece only.
  bool concave = false;
  std::vector<Polygon> pieces;

  ShapeProxy proxy() const noexcept;
  /// Every piece (one for a convex shape), viewing this object's storage.
  std::vector<ShapeProxy> proxies() const;
  /// Every piece as a world geometry (copies; one for a convex shape).
  std::vector<ShapeGeometry> geometries() const;
  /// The shape for the manifold dispatch table (refers to this object's storage).
  ShapeRef ref() const noexcept;
  /// The shape as a world geometry (a copy).
  ShapeGeometry geometry() const;
};

/// Shape from JSON; `path` prefixes error messages ("a"). Keys in `extraKeys` are allowed
/// beside the shape's own and left to the caller (scene files add material keys).
Result<ParsedShape> parseShape(const nlohmann::json& j, const std::string& path,
                               std::initializer_list<const char*> extraKeys = {});
/// Pose from JSON as worldFromShape; `path` prefixes error messages ("pa").
Result<Transform> parsePose(const nlohmann::json& j, const std::string& path);
/// [x, y] with finite numbers.
Result<Vec2> parseVec2(const nlohmann::json& j, const std::string& path);
/// [x, y] within +-kMaxCoordinate (1e9 m): a position, offset or translation. Beyond it:
/// "path[0]: 2e+19 m is beyond the coordinate limit 1e9 m".
Result<Vec2> parsePosition(const nlohmann::json& j, const std::string& path);

}  // namespace quack
