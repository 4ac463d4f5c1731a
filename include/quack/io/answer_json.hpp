#pragma once
/// The collision answers as JSON, in the field names of `quack query` (README, "Formats"):
/// the one place an answer becomes JSON, shared by `quack query`, the web demo's glue and
/// the Python module's JSON form. Points and normals are written as they are given (the
/// callers pass world-frame answers); vectors are [x, y] arrays.
///
///   toJson(DistanceOutput)    {"distance", "pointA", "pointB", "normal", "iterations",
///                              "status"}
///   toJson(PenetrationOutput) {"overlap", "depth", "normal", "pointA", "pointB",
///                              "iterations", "status"}
///   toJson(Manifold)          {"normal", "points": [{"point", "separation", "id"}]}
///                              (the normal is [0, 0] when there is no point)
///   toJson(ShapeCastOutput)   {"hit", "fraction", "point", "normal", "depth", "status"}
///   toJson(RayHit)            {"hit", "fraction", "point", "normal"}
///   toJson(ToiOutput)         {"status", "t"}
///
/// The 3D answers have the same field names, with [x, y, z] vectors (`"status"` of a 3D
/// penetration is an Epa3Status name, e.g. "converged", "cores_separated").

#include <nlohmann/json.hpp>

#include "quack/collision/epa.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/collision/shape_cast.hpp"
#include "quack/collision/toi.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/geometry/raycast.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/math/vec2.hpp"

namespace quack {

nlohmann::json toJson(Vec2 v);
nlohmann::json toJson(const DistanceOutput& d);
nlohmann::json toJson(const PenetrationOutput& p);
nlohmann::json toJson(const Manifold& m);
nlohmann::json toJson(const ShapeCastOutput& c);
nlohmann::json toJson(const RayHit& r);
nlohmann::json toJson(const ToiOutput& t);

nlohmann::json toJson(Vec3 v);
nlohmann::json toJson(const DistanceOutput3& d);
nlohmann::json toJson(const PenetrationOutput3& p);
nlohmann::json toJson(const Manifold3& m);
nlohmann::json toJson(const ShapeCastOutput3& c);
nlohmann::json toJson(const RayHit3& r);
nlohmann::json toJson(const ToiOutput3& t);
/// A mesh's answers: the convex answer with the triangle's index added ("triangle", -1
/// when there is none), and its contacts as {"manifolds": [{"triangle", "normal",
/// "points"}, ...]}, one per touching triangle in triangle order.
nlohmann::json toJson(const MeshRayHit3& r);
nlohmann::json toJson(const MeshDistanceOutput3& d);
nlohmann::json toJson(const MeshShapeCastOutput3& c);
nlohmann::json toJson(const MeshToiOutput3& t);
nlohmann::json toJson(const MeshPenetrationOutput3& p);
nlohmann::json toJson(const std::vector<MeshContact3>& contacts);

}  // namespace quack
