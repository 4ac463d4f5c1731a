#include "quack/io/shape_json.hpp"

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <span>
#include <vector>

#include "quack/geometry/decompose.hpp"

namespace quack {
namespace {

using nlohmann::json;

Status checkKeys(const json& j, const std::string& path, std::initializer_list<const char*> keys,
                 std::initializer_list<const char*> extraKeys = {}) {
  for (const auto& item : j.items()) {
    bool known = false;
    for (const char* k : keys)
      known |= item.key() == k;
    for (const char* k : extraKeys)
      known |= item.key() == k;
    if (!known) return fail(path + "." + item.key() + ": unknown key");
  }
  return {};
}

// "2e+19 m is beyond the coordinate limit 1e9 m", with the number as given in the JSON.
std::string beyondLimit(const json& j) {
  static_assert(kMaxCoordinate == 1e9f, "the messages say 1e9");
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g m is beyond the coordinate limit 1e9 m", j.get<double>());
  return buf;
}

Result<float> parseNumber(const json& j, const std::string& path) {
  if (!j.is_number()) return fail(path + ": must be a number");
  double d = j.get<double>();
  auto f = static_cast<float>(d);
  if (!std::isfinite(f)) return fail(path + ": must be finite (as a float)");
  return f;
}

// A length (radius, half-extent) within the coordinate limit.
Result<float> parseLength(const json& j, const std::string& path) {
  Result<float> f = parseNumber(j, path);
  if (!f) return f;
  if (absf(*f) > kMaxCoordinate) return fail(path + ": " + beyondLimit(j));
  return f;
}

Result<float> numberOr(const json& j, const char* key, const std::string& path, float fallback) {
  if (!j.contains(key)) return fallback;
  return parseNumber(j.at(key), path + "." + key);
}

Result<float> lengthOr(const json& j, const char* key, const std::string& path, float fallback) {
  if (!j.contains(key)) return fallback;
  return parseLength(j.at(key), path + "." + key);
}

Result<float> requiredLength(const json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) return fail(path + "." + key + ": missing");
  return parseLength(j.at(key), path + "." + key);
}

Result<Vec2> positionOr(const json& j, const char* key, const std::string& path, Vec2 fallback) {
  if (!j.contains(key)) return fallback;
  return parsePosition(j.at(key), path + "." + key);
}

Result<Vec2> requiredPosition(const json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) return fail(path + "." + key + ": missing");
  return parsePosition(j.at(key), path + "." + key);
}

// An array of at least 3 and at most 4,096 points [x, y].
Result<std::vector<Vec2>> parsePointArray(const json& pts, const std::string& path) {
  if (!pts.is_array()) return fail(path + ": must be an array of [x, y]");
  if (pts.size() < 3) return fail(path + ": needs at least 3 points");
  if (pts.size() > 4096) return fail(path + ": too many points");
  std::vector<Vec2> points;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Result<Vec2> p = parsePosition(pts[i], path + "[" + std::to_string(i) + "]");
    if (!p) return p.error();
    points.push_back(*p);
  }
  return points;
}

Result<std::vector<Vec2>> parsePoints(const json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) return fail(path + "." + key + ": missing");
  return parsePointArray(j.at(key), path + "." + key);
}

// Re-labels a geometry error with the JSON path of the shape.
Error located(const std::string& path, const Error& e) {
  return fail(path + ": " + e.message);
}

}  // namespace

Result<Vec2> parseVec2(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 2) return fail(path + ": must be [x, y]");
  Result<float> x = parseNumber(j[0], path + "[0]");
  if (!x) return x.error();
  Result<float> y = parseNumber(j[1], path + "[1]");
  if (!y) return y.error();
  return Vec2{*x, *y};
}

Result<Vec2> parsePosition(const json& j, const std::string& path) {
  Result<Vec2> v = parseVec2(j, path);
  if (!v) return v;
  if (absf(v->x) > kMaxCoordinate) return fail(path + "[0]: " + beyondLimit(j[0]));
  if (absf(v->y) > kMaxCoordinate) return fail(path + "[1]: " + beyondLimit(j[1]));
  return v;
}

Result<Transform> parsePose(const json& j, const std::string& path) {
  if (!j.is_object()) return fail(path + ": must be an object {\"pos\", \"angle\"}");
  if (j.contains("quat")) {
    return fail(path + ".quat: a 2D pose turns by \"angle\" (radians); \"quat\" is for 3D " +
                "shapes");
  }
  if (Status s = checkKeys(j, path, {"pos", "angle"}); !s) return fail(s.message());
  Result<Vec2> pos = positionOr(j, "pos", path, {});
  if (!pos) return pos.error();
  Result<float> angle = numberOr(j, "angle", path, 0.0f);
  if (!angle) return angle.error();
  return makeTransform(*pos, *angle);
}

namespace {

// The "type" of a shape object, or the error for a value that is not one.
Result<std::string> typeOf(const json& j, const std::string& path) {
  if (!j.is_object()) return fail(path + ": must be an object with a \"type\"");
  if (!j.contains("type")) return fail(path + ".type: missing");
  if (!j.at("type").is_string()) return fail(path + ".type: must be a string");
  return j.at("type").get<std::string>();
}

// A shape of a convex kind (every kind but "concave"), or the unknown-type error.
Result<ShapeGeometry> parseConvex(const json& j, const std::string& path, const std::string& type,
                                  std::initializer_list<const char*> extraKeys) {
  if (type == "circle") {
    if (Status s = checkKeys(j, path, {"type", "center", "radius"}, extraKeys); !s)
      return fail(s.message());
    Result<Vec2> c = positionOr(j, "center", path, {});
    if (!c) return c.error();
    Result<float> r = requiredLength(j, "radius", path);
    if (!r) return r.error();
    if (*r <= 0.0f) return fail(path + ".radius: must be > 0");
    Result<Circle> s = makeCircle(*c, *r);
    if (!s) return located(path, s.error());
    return ShapeGeometry{*s};
  }
  if (type == "capsule" || type == "segment") {
    bool capsule = type == "capsule";
    Status keys = capsule ? checkKeys(j, path, {"type", "p1", "p2", "radius"}, extraKeys)
                          : checkKeys(j, path, {"type", "p1", "p2"}, extraKeys);
    if (!keys) return fail(keys.message());
    Result<Vec2> p1 = requiredPosition(j, "p1", path);
    if (!p1) return p1.error();
    Result<Vec2> p2 = requiredPosition(j, "p2", path);
    if (!p2) return p2.error();
    if (!capsule) {
      Result<Segment> s = makeSegment(*p1, *p2);
      if (!s) return located(path, s.error());
      return ShapeGeometry{*s};
    }
    Result<float> r = requiredLength(j, "radius", path);
    if (!r) return r.error();
    if (*r <= 0.0f) return fail(path + ".radius: must be > 0");
    Result<Capsule> s = makeCapsule(*p1, *p2, *r);
    if (!s) return located(path, s.error());
    return ShapeGeometry{*s};
  }
  if (type == "box") {
    if (Status s = checkKeys(j, path, {"type", "half", "center", "angle", "radius"}, extraKeys);
        !s) {
      return fail(s.message());
    }
    Result<Vec2> half = requiredPosition(j, "half", path);
    if (!half) return half.error();
    if (half->x <= 0.0f || half->y <= 0.0f) return fail(path + ".half: must be > 0");
    Result<Vec2> c = positionOr(j, "center", path, {});
    if (!c) return c.error();
    Result<float> angle = numberOr(j, "angle", path, 0.0f);
    if (!angle) return angle.error();
    Result<float> r = lengthOr(j, "radius", path, 0.0f);
    if (!r) return r.error();
    if (*r < 0.0f) return fail(path + ".radius: must be >= 0");
    Result<Polygon> s = makeBox(half->x, half->y, *c, *angle, *r);
    if (!s) return located(path, s.error());
    return ShapeGeometry{*s};
  }
  if (type == "polygon") {
    if (Status s = checkKeys(j, path, {"type", "points", "radius"}, extraKeys); !s)
      return fail(s.message());
    Result<std::vector<Vec2>> points = parsePoints(j, "points", path);
    if (!points) return points.error();
    Result<float> r = lengthOr(j, "radius", path, 0.0f);
    if (!r) return r.error();
    if (*r < 0.0f) return fail(path + ".radius: must be >= 0");
    Result<Polygon> s = makePolygon(*points, *r);
    if (!s) return located(path, s.error());
    return ShapeGeometry{*s};
  }
  return fail(path + ".type: unknown shape type \"" + type +
              "\" (expected circle, capsule, segment, box, polygon, concave)");
}

// A "concave" shape: its convex pieces, from decomposePolygon.
Result<std::vector<ShapeGeometry>> parseConcave(const json& j, const std::string& path,
                                                std::initializer_list<const char*> extraKeys) {
  if (Status s = checkKeys(j, path, {"type", "points", "holes"}, extraKeys); !s)
    return fail(s.message());
  Result<std::vector<Vec2>> points = parsePoints(j, "points", path);
  if (!points) return points.error();
  std::vector<std::vector<Vec2>> holes;
  if (j.contains("holes")) {
    const json& hs = j.at("holes");
    if (!hs.is_array()) return fail(path + ".holes: must be an array of point arrays");
    for (std::size_t i = 0; i < hs.size(); ++i) {
      Result<std::vector<Vec2>> h =
          parsePointArray(hs[i], path + ".holes[" + std::to_string(i) + "]");
      if (!h) return h.error();
      holes.push_back(std::move(*h));
    }
  }
  Result<ConvexDecomposition> d = decomposePolygon(*points, holes);
  if (!d) {
    // "decomposePolygon: edges 0 and 2 cross" -> "a: edges 0 and 2 cross"
    std::string message = d.error().message;
    const std::string prefix = "decomposePolygon: ";
    if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
    return fail(path + ": " + message);
  }
  return std::vector<ShapeGeometry>(d->pieces.begin(), d->pieces.end());
}

}  // namespace

Result<ShapeGeometry> parseShape(const json& j, const std::string& path,
                                 std::initializer_list<const char*> extraKeys) {
  Result<std::string> type = typeOf(j, path);
  if (!type) return type.error();
  if (*type == "concave") {
    return fail(path +
                ".type: a concave shape is several convex pieces; read it with parseShapePieces");
  }
  return parseConvex(j, path, *type, extraKeys);
}

Result<std::vector<ShapeGeometry>> parseShapePieces(const json& j, const std::string& path,
                                                    std::initializer_list<const char*> extraKeys) {
  Result<std::string> type = typeOf(j, path);
  if (!type) return type.error();
  if (*type == "concave") return parseConcave(j, path, extraKeys);
  Result<ShapeGeometry> convex = parseConvex(j, path, *type, extraKeys);
  if (!convex) return convex.error();
  return std::vector<ShapeGeometry>{std::move(*convex)};
}

// ---------------------------------------------------------------------------------------
// 3D

Result<Vec3> parseVec3(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 3) return fail(path + ": must be [x, y, z]");
  float c[3];
  for (std::size_t i = 0; i < 3; ++i) {
    Result<float> f = parseNumber(j[i], path + "[" + std::to_string(i) + "]");
    if (!f) return f.error();
    c[i] = *f;
  }
  return Vec3{c[0], c[1], c[2]};
}

Result<Vec3> parsePosition3(const json& j, const std::string& path) {
  Result<Vec3> v = parseVec3(j, path);
  if (!v) return v;
  const float c[3] = {v->x, v->y, v->z};
  for (std::size_t i = 0; i < 3; ++i) {
    if (absf(c[i]) > kMaxCoordinate)
      return fail(path + "[" + std::to_string(i) + "]: " + beyondLimit(j[i]));
  }
  return v;
}

Result<Quat> parseQuat(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 4) return fail(path + ": must be [x, y, z, w] (scalar last)");
  double c[4];
  for (std::size_t i = 0; i < 4; ++i) {
    Result<float> f = parseNumber(j[i], path + "[" + std::to_string(i) + "]");
    if (!f) return f.error();
    c[i] = static_cast<double>(*f);
  }
  // In double, so any non-zero float quaternion (denormal components included) normalises.
  const double norm = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
  if (!(norm > 0.0)) {
    return fail(path + ": [0, 0, 0, 0] is not a rotation (the zero quaternion; the identity is " +
                "[0, 0, 0, 1])");
  }
  return Quat{static_cast<float>(c[0] / norm), static_cast<float>(c[1] / norm),
              static_cast<float>(c[2] / norm), static_cast<float>(c[3] / norm)};
}

Result<Transform3> parsePose3(const json& j, const std::string& path) {
  if (!j.is_object()) return fail(path + ": must be an object {\"pos\", \"quat\"}");
  if (j.contains("angle")) {
    return fail(path + ".angle: a 3D pose turns by \"quat\": [x, y, z, w], not by an angle");
  }
  if (Status s = checkKeys(j, path, {"pos", "quat"}); !s) return fail(s.message());
  Vec3 pos;
  if (j.contains("pos")) {
    Result<Vec3> p = parsePosition3(j.at("pos"), path + ".pos");
    if (!p) return p.error();
    pos = *p;
  }
  Quat q;
  if (j.contains("quat")) {
    Result<Quat> r = parseQuat(j.at("quat"), path + ".quat");
    if (!r) return r.error();
    q = *r;
  }
  return Transform3{pos, q};
}

namespace {

bool isTriple(const json& j) {
  return j.is_array() && j.size() == 3;
}

Result<Vec3> requiredPosition3(const json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) return fail(path + "." + key + ": missing");
  return parsePosition3(j.at(key), path + "." + key);
}

// An array of `least` to `most` points [x, y, z].
Result<std::vector<Vec3>> parsePoints3(const json& j, const char* key, const std::string& path,
                                       std::size_t least, std::size_t most) {
  const std::string at = path + "." + key;
  if (!j.contains(key)) return fail(at + ": missing");
  const json& pts = j.at(key);
  if (!pts.is_array()) return fail(at + ": must be an array of [x, y, z]");
  if (least == most && pts.size() != least)
    return fail(at + ": needs exactly " + std::to_string(least) + " points");
  if (pts.size() < least) return fail(at + ": needs at least " + std::to_string(least) + " points");
  if (pts.size() > most)
    return fail(at + ": too many points (at most " + std::to_string(most) + ")");
  std::vector<Vec3> points;
  points.reserve(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Result<Vec3> p = parsePosition3(pts[i], at + "[" + std::to_string(i) + "]");
    if (!p) return p.error();
    points.push_back(*p);
  }
  return points;
}

// A 3D box's or hull's rounding "radius": absent (0) or a length >= 0.
Result<float> roundingRadius(const json& j, const std::string& path) {
  Result<float> r = lengthOr(j, "radius", path, 0.0f);
  if (!r) return r;
  if (*r < 0.0f) return fail(path + ".radius: must be >= 0");
  return r;
}

}  // namespace

int shapeDimension(const json& j) {
  if (!j.is_object() || !j.contains("type") || !j.at("type").is_string()) return 0;
  const std::string type = j.at("type").get<std::string>();
  if (type == "sphere" || type == "hull" || type == "triangle" || type == "mesh") return 3;
  if (type == "circle" || type == "segment" || type == "polygon" || type == "concave") return 2;
  if (type == "capsule") return j.contains("p1") && isTriple(j.at("p1")) ? 3 : 2;
  if (type == "box") return j.contains("half") && isTriple(j.at("half")) ? 3 : 2;
  return 0;
}

Result<ShapeGeometry3> parseShape3(const json& j, const std::string& path,
                                   std::initializer_list<const char*> extraKeys) {
  Result<std::string> type = typeOf(j, path);
  if (!type) return type.error();
  if (*type == "sphere") {
    if (Status s = checkKeys(j, path, {"type", "center", "radius"}, extraKeys); !s)
      return fail(s.message());
    Vec3 c;
    if (j.contains("center")) {
      Result<Vec3> r = parsePosition3(j.at("center"), path + ".center");
      if (!r) return r.error();
      c = *r;
    }
    Result<float> r = requiredLength(j, "radius", path);
    if (!r) return r.error();
    if (*r <= 0.0f) return fail(path + ".radius: must be > 0");
    Result<Sphere> s = makeSphere(c, *r);
    if (!s) return located(path, s.error());
    return ShapeGeometry3{*s};
  }
  if (*type == "capsule") {
    if (Status s = checkKeys(j, path, {"type", "p1", "p2", "radius"}, extraKeys); !s)
      return fail(s.message());
    Result<Vec3> p1 = requiredPosition3(j, "p1", path);
    if (!p1) return p1.error();
    Result<Vec3> p2 = requiredPosition3(j, "p2", path);
    if (!p2) return p2.error();
    Result<float> r = requiredLength(j, "radius", path);
    if (!r) return r.error();
    if (*r <= 0.0f) return fail(path + ".radius: must be > 0");
    Result<Capsule3> s = makeCapsule3(*p1, *p2, *r);
    if (!s) return located(path, s.error());
    return ShapeGeometry3{*s};
  }
  if (*type == "box") {
    if (j.contains("angle")) {
      return fail(path + ".angle: a 3D box turns by \"quat\": [x, y, z, w], not by an angle");
    }
    if (Status s = checkKeys(j, path, {"type", "half", "center", "quat", "radius"}, extraKeys); !s)
      return fail(s.message());
    Result<float> radius = roundingRadius(j, path);
    if (!radius) return radius.error();
    Result<Vec3> half = requiredPosition3(j, "half", path);
    if (!half) return half.error();
    if (!(half->x > 0.0f && half->y > 0.0f && half->z > 0.0f))
      return fail(path + ".half: must be > 0");
    Transform3 shapeFromBox;
    if (j.contains("center")) {
      Result<Vec3> c = parsePosition3(j.at("center"), path + ".center");
      if (!c) return c.error();
      shapeFromBox.p = *c;
    }
    if (j.contains("quat")) {
      Result<Quat> q = parseQuat(j.at("quat"), path + ".quat");
      if (!q) return q.error();
      shapeFromBox.q = *q;
    }
    Result<Hull3> s = makeBox3(*half, shapeFromBox, *radius);
    if (!s) return located(path, s.error());
    return ShapeGeometry3{std::move(*s)};
  }
  if (*type == "hull") {
    if (Status s = checkKeys(j, path, {"type", "points", "radius"}, extraKeys); !s)
      return fail(s.message());
    Result<float> radius = roundingRadius(j, path);
    if (!radius) return radius.error();
    Result<std::vector<Vec3>> points = parsePoints3(j, "points", path, 4, 4096);
    if (!points) return points.error();
    Result<Hull3> s = makeHull3(std::span<const Vec3>(*points), *radius);
    if (!s) return located(path, s.error());
    return ShapeGeometry3{std::move(*s)};
  }
  if (*type == "triangle") {
    if (Status s = checkKeys(j, path, {"type", "points"}, extraKeys); !s) return fail(s.message());
    Result<std::vector<Vec3>> points = parsePoints3(j, "points", path, 3, 3);
    if (!points) return points.error();
    Result<Triangle3> s = makeTriangle3((*points)[0], (*points)[1], (*points)[2]);
    if (!s) return located(path, s.error());
    return ShapeGeometry3{*s};
  }
  if (*type == "mesh") {
    return fail(path + ".type: \"mesh\" is a static triangle mesh, not a convex shape: " +
                "a query takes it as shape a (ops " + kMeshQueryOps + ") or as shape b (ops " +
                kMeshQueryOpsAsB + ")");
  }
  if (*type == "circle" || *type == "segment" || *type == "polygon" || *type == "concave") {
    return fail(path + ".type: \"" + *type + "\" is a 2D shape (in 3D: sphere, capsule, box, " +
                "hull, triangle)");
  }
  return fail(path + ".type: unknown shape type \"" + *type +
              "\" (expected sphere, capsule, box, hull, triangle in 3D)");
}

bool isMesh3(const json& j) {
  return j.is_object() && j.contains("type") && j.at("type").is_string() &&
         j.at("type").get<std::string>() == "mesh";
}

Result<Mesh3> parseMesh3(const json& j, const std::string& path,
                         std::initializer_list<const char*> extraKeys) {
  Result<std::string> type = typeOf(j, path);
  if (!type) return type.error();
  if (*type != "mesh") return fail(path + ".type: must be \"mesh\"");
  if (Status s = checkKeys(j, path, {"type", "vertices", "triangles"}, extraKeys); !s)
    return fail(s.message());
  Result<std::vector<Vec3>> vertices =
      parsePoints3(j, "vertices", path, 3, static_cast<std::size_t>(kMaxMeshVertices3Json));
  if (!vertices) return vertices.error();
  const std::string at = path + ".triangles";
  if (!j.contains("triangles")) return fail(at + ": missing");
  const json& tris = j.at("triangles");
  if (!tris.is_array()) return fail(at + ": must be an array of [i, j, k]");
  if (tris.empty()) return fail(at + ": needs at least 1 triangle");
  if (tris.size() > static_cast<std::size_t>(kMaxMeshTriangles3)) {
    return fail(at + ": too many triangles (at most " + std::to_string(kMaxMeshTriangles3) + ")");
  }
  const auto count = static_cast<std::int64_t>(vertices->size());
  std::vector<std::array<std::int32_t, 3>> triangles(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const std::string ti = at + "[" + std::to_string(i) + "]";
    if (!tris[i].is_array() || tris[i].size() != 3)
      return fail(ti + ": must be [i, j, k] (three vertex indices)");
    for (std::size_t k = 0; k < 3; ++k) {
      const json& v = tris[i][k];
      const std::string tk = ti + "[" + std::to_string(k) + "]";
      if (!v.is_number_integer()) return fail(tk + ": must be an integer vertex index");
      // Compared as 64-bit: an unsigned 2^64 - 1 read as signed is -1, out of range too.
      const bool negative = v.is_number_unsigned() ? false : v.get<std::int64_t>() < 0;
      if (negative ||
          (v.is_number_unsigned() ? v.get<std::uint64_t>() >= static_cast<std::uint64_t>(count)
                                  : v.get<std::int64_t>() >= count)) {
        return fail(tk + ": vertex index " + v.dump() + " is out of range (0 to " +
                    std::to_string(count - 1) + ")");
      }
      triangles[i][k] = static_cast<std::int32_t>(v.get<std::int64_t>());
    }
  }
  return makeMesh3At(*vertices, triangles, path);
}

Result<Mesh3> makeMesh3At(std::span<const Vec3> vertices,
                          std::span<const std::array<std::int32_t, 3>> triangles,
                          const std::string& path) {
  Result<Mesh3> mesh = makeMesh3(vertices, triangles);
  if (mesh) return std::move(*mesh);
  const std::string at = path.empty() ? "triangles" : path + ".triangles";
  // makeMesh3 names the triangle ("makeMesh3: triangle 4: ..."); say it as its field.
  std::string message = mesh.error().message;
  const std::string prefix = "makeMesh3: triangle ";
  if (message.rfind(prefix, 0) == 0) {
    const std::size_t colon = message.find(':', prefix.size());
    if (colon != std::string::npos) {
      return fail(at + "[" + message.substr(prefix.size(), colon - prefix.size()) + "]" +
                  message.substr(colon));
    }
  }
  if (message.rfind("makeMesh3: ", 0) == 0) message = message.substr(11);
  return fail(at + ": " + message);
}

}  // namespace quack
