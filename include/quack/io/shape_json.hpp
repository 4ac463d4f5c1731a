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
/// 3D (the same format with three-component vectors; `quack query` and 3D scenes):
///        {"type": "sphere", "center": [x, y, z] (default [0, 0, 0]), "radius": r > 0}
///        {"type": "capsule", "p1": [x, y, z], "p2": [x, y, z], "radius": r > 0}
///        {"type": "box", "half": [hx, hy, hz], "center": [0, 0, 0], "quat": [0, 0, 0, 1],
///         "radius": 0}
///        {"type": "hull", "points": [[x, y, z], ...] (4 to 4,096; quickhull keeps at most
///         64 vertices), "radius": 0}
///        (a box's or hull's "radius" >= 0 rounds it: the points within it of the core)
///        {"type": "triangle", "points": [[x, y, z], [x, y, z], [x, y, z]]}
///        {"type": "mesh", "vertices": [[x, y, z], ...] (3 to 1,000,000), "triangles":
///         [[i, j, k], ...] (vertex indices, counter-clockwise seen from the front)}: a
///         static one-sided triangle mesh (makeMesh3), read by parseMesh3 only.
/// 3D pose: {"pos": [x, y, z] (default [0, 0, 0]), "quat": [x, y, z, w] (scalar last,
///        default the identity; normalised here, the zero quaternion refused)}.
/// Unknown keys are errors; every error names the field, e.g. "a.radius: must be > 0".
/// Positions, points, half-extents and radii must lie within the coordinate limit
/// (kMaxCoordinate, 1e9 m), e.g. "a.half[0]: 1e+19 m is beyond the coordinate limit 1e9 m".

#include <array>
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "quack/collision/mesh3.hpp"
#include "quack/core/result.hpp"
#include "quack/geometry/shapes.hpp"
#include "quack/geometry/shapes3.hpp"
#include "quack/math/transform.hpp"
#include "quack/math/transform3.hpp"

namespace quack {

/// Convex shape from JSON (every type but "concave", which is refused with a message that
/// points to parseShapePieces), shape frame; `path` prefixes error messages ("a"). Keys in
/// `extraKeys` are allowed beside the shape's own and left to the caller (scene files add
/// material keys).
Result<ShapeGeometry> parseShape(const nlohmann::json& j, const std::string& path,
                                 std::initializer_list<const char*> extraKeys = {});
/// Shape of any type from JSON as its convex pieces, shape frame: one piece for a convex
/// type, the pieces of decomposePolygon for "concave". Errors and `extraKeys` as parseShape.
Result<std::vector<ShapeGeometry>> parseShapePieces(
    const nlohmann::json& j, const std::string& path,
    std::initializer_list<const char*> extraKeys = {});
/// Pose from JSON as worldFromShape; `path` prefixes error messages ("pa").
Result<Transform> parsePose(const nlohmann::json& j, const std::string& path);
/// [x, y] with finite numbers.
Result<Vec2> parseVec2(const nlohmann::json& j, const std::string& path);
/// [x, y] within +-kMaxCoordinate (1e9 m): a position, offset or translation. Beyond it:
/// "path[0]: 2e+19 m is beyond the coordinate limit 1e9 m".
Result<Vec2> parsePosition(const nlohmann::json& j, const std::string& path);

/// The dimension of a shape object: 3 for "sphere", "hull", "triangle" and "mesh", and for a
/// "capsule" or "box" whose first vector ("p1", "half") has three components; 2 for the 2D
/// types and for a capsule or box whose vector has any other form (parseShape then says
/// what is wrong with it); 0 when `j` is not an object with a known string "type".
int shapeDimension(const nlohmann::json& j);
/// 3D shape from JSON (the 3D formats above), shape frame; errors and `extraKeys` as
/// parseShape. A 2D type ("circle", "polygon", ...) is refused with a message saying so.
Result<ShapeGeometry3> parseShape3(const nlohmann::json& j, const std::string& path,
                                   std::initializer_list<const char*> extraKeys = {});
/// The ops `quack query` answers with a mesh as shape a.
inline constexpr const char* kMeshQueryOps =
    "overlap, distance, penetration, manifold, raycast, shapecast, toi";
/// The ops `quack query` answers with a mesh as shape b (the answer turned round).
inline constexpr const char* kMeshQueryOpsAsB = "overlap, distance, penetration, toi";
/// Most vertices of a mesh read from JSON.
inline constexpr int kMaxMeshVertices3Json = 1000000;
/// True when `j` is an object of type "mesh".
bool isMesh3(const nlohmann::json& j);
/// A static triangle mesh from JSON ({"type": "mesh", "vertices", "triangles"}), mesh
/// frame, built by makeMesh3. Every error names the field: "a.vertices[2][1]: ...",
/// "a.triangles[3][0]: vertex index 9 is out of range (0 to 7)", "a.triangles[1]: ... no
/// area" (makeMesh3's errors about one triangle), "a.triangles: edge (0, 1) is shared by 3
/// triangles ...". Keys in `extraKeys` are allowed and left to the caller, as parseShape.
Result<Mesh3> parseMesh3(const nlohmann::json& j, const std::string& path,
                         std::initializer_list<const char*> extraKeys = {});
/// makeMesh3 with its errors said as fields under `path` (parseMesh3's "a.triangles[1]: ...",
/// "a.triangles: edge (0, 1) ..."; with an empty path "triangles[1]: ..."), for callers that
/// read the vertices and triangles themselves (Python's quack.d3.mesh).
Result<Mesh3> makeMesh3At(std::span<const Vec3> vertices,
                          std::span<const std::array<std::int32_t, 3>> triangles,
                          const std::string& path);
/// 3D pose from JSON as worldFromShape; `path` prefixes error messages ("pa"). An "angle"
/// key is refused with a message that points to "quat".
Result<Transform3> parsePose3(const nlohmann::json& j, const std::string& path);
/// [x, y, z] with finite numbers.
Result<Vec3> parseVec3(const nlohmann::json& j, const std::string& path);
/// [x, y, z] within +-kMaxCoordinate (1e9 m), as parsePosition.
Result<Vec3> parsePosition3(const nlohmann::json& j, const std::string& path);
/// [x, y, z, w] (scalar last) with finite numbers, normalised (in double); the zero
/// quaternion is refused ("pa.quat: [0, 0, 0, 0] is not a rotation ...").
Result<Quat> parseQuat(const nlohmann::json& j, const std::string& path);

}  // namespace quack
