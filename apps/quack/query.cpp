#include "query.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "quack/collision/epa.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/collision/pieces.hpp"
#include "quack/collision/shape_cast.hpp"
#include "quack/collision/toi.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/raycast.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/io/answer_json.hpp"
#include "quack/io/shape_json.hpp"

namespace quack::app {
namespace {

using nlohmann::json;

// One line of JSON. Strings the program echoes (ids, keys, the parser's "last read" bytes)
// may hold invalid UTF-8; it is replaced by U+FFFD rather than thrown about.
std::string dumpLine(const json& j) {
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

QueryAnswer rejected(const json& id, const std::string& message) {
  json out = {{"id", id}, {"error", message}};
  return {dumpLine(out), false};
}

// True when the line nests [ and { (outside strings) deeper than `limit`. A linear scan
// with no recursion, run before the parser sees the line.
bool nestsDeeperThan(const std::string& line, int limit) {
  int depth = 0;
  bool inString = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (inString) {
      if (c == '\\') {
        ++i;  // the escaped character cannot end the string
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

// Re-reads a line the parser refused, to say where and why: the byte, the field being read
// ("pb.pos[0]") and the parser's reason. Iterative (nlohmann's SAX parser keeps its own
// stack) and run only on lines within the nesting limit.
class ParseDiagnosis {
 public:
  using number_integer_t = json::number_integer_t;
  using number_unsigned_t = json::number_unsigned_t;
  using number_float_t = json::number_float_t;
  using string_t = json::string_t;
  using binary_t = json::binary_t;

  bool null() { return value(); }
  bool boolean(bool) { return value(); }
  bool number_integer(number_integer_t) { return value(); }
  bool number_unsigned(number_unsigned_t) { return value(); }
  bool number_float(number_float_t, const string_t&) { return value(); }
  bool string(string_t&) { return value(); }
  bool binary(binary_t&) { return value(); }
  bool start_object(std::size_t) {
    frames_.push_back({false, {}, 0});
    return true;
  }
  bool key(string_t& k) {
    frames_.back().key = k;
    return true;
  }
  bool end_object() { return close(); }
  bool start_array(std::size_t) {
    frames_.push_back({true, {}, 0});
    return true;
  }
  bool end_array() { return close(); }
  bool parse_error(std::size_t position, const std::string& lastToken,
                   const nlohmann::detail::exception& ex) {
    position_ = position;
    lastToken_ = lastToken;
    outOfRange_ = ex.id == 406;
    reason_ = ex.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 9: syntax error ..."
    // keeps the part after the column; the byte is given separately.
    const std::size_t column = reason_.find("column ");
    const std::size_t colon = column == std::string::npos ? column : reason_.find(": ", column);
    if (colon != std::string::npos) {
      reason_ = reason_.substr(colon + 2);
    } else if (const std::size_t bracket = reason_.find("] "); bracket != std::string::npos) {
      reason_ = reason_.substr(bracket + 2);
    }
    return false;
  }

  /// The message for a refused line.
  std::string message() const {
    std::string path;
    for (const Frame& f : frames_) {
      if (f.array) {
        path += "[" + std::to_string(f.index) + "]";
      } else if (!f.key.empty()) {
        path += (path.empty() ? "" : ".") + f.key;
      }
    }
    // nlohmann gives the count of bytes read, up to the end of the offending token; report
    // where that token starts, counting bytes from 1.
    const std::size_t byte =
        position_ >= lastToken_.size() ? position_ - lastToken_.size() + 1 : position_;
    const std::string at = "byte " + std::to_string(byte);
    if (outOfRange_) {
      return (path.empty() ? std::string("number") : path + ": number") + " " + lastToken_ +
             " is out of range (beyond a double) at " + at;
    }
    return "line is not valid JSON at " + at + (path.empty() ? "" : " (near " + path + ")") + ": " +
           reason_;
  }

 private:
  struct Frame {
    bool array;
    std::string key;
    std::size_t index;
  };
  bool value() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return true;
  }
  bool close() {
    frames_.pop_back();
    return value();
  }

  std::vector<Frame> frames_;
  std::size_t position_ = 0;
  std::string lastToken_;
  std::string reason_ = "not valid JSON";
  bool outOfRange_ = false;
};

// A distance or length option: finite, >= 0 and within the coordinate limit.
bool isLengthOption(const json& v) {
  return v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() >= 0.0 &&
         v.get<double>() <= static_cast<double>(kMaxCoordinate);
}

QueryAnswer answerParsed(const json& q);

// True for a shape of type "concave" (a parsed shape: an object with a string "type").
bool isConcave(const json& shape) {
  return shape.is_object() && shape.contains("type") && shape.at("type") == "concave";
}

std::string firstNonFinitePath(const json& j, const std::string& path) {
  if (j.is_number_float()) return std::isfinite(j.get<double>()) ? "" : path;
  if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      std::string bad = firstNonFinitePath(j[i], path + "[" + std::to_string(i) + "]");
      if (!bad.empty()) return bad;
    }
  } else if (j.is_object()) {
    for (const auto& item : j.items()) {
      std::string bad =
          firstNonFinitePath(item.value(), path.empty() ? item.key() : path + "." + item.key());
      if (!bad.empty()) return bad;
    }
  }
  return "";
}

}  // namespace

std::string firstNonFiniteField(const nlohmann::json& answer) {
  return firstNonFinitePath(answer, "");
}

QueryAnswer answerQuery(const std::string& line) {
  if (nestsDeeperThan(line, kMaxQueryNesting)) {
    return rejected(nullptr, "line nests [ and { deeper than the limit of " +
                                 std::to_string(kMaxQueryNesting) + " levels");
  }
  json q = json::parse(line, nullptr, false);
  if (q.is_discarded()) {
    ParseDiagnosis diagnosis;
    json::sax_parse(line, &diagnosis);
    return rejected(nullptr, diagnosis.message());
  }
  return answerParsed(q);
}

namespace {

// The answer line, or an error when some number in it is not finite: never a null (or a
// NaN) where the user expects a number.
QueryAnswer finished(const json& id, const json& out) {
  const std::string bad = firstNonFiniteField(out);
  if (!bad.empty()) {
    return rejected(id, bad +
                            ": the answer is not finite (the inputs are beyond what float "
                            "arithmetic resolves); refused rather than printed as null");
  }
  return {dumpLine(out), true};
}

// The ray {"origin", "translation"} of op raycast, checked for unknown and missing keys;
// its vectors are left to the caller (2D or 3D).
// A sweep, 2D or 3D, is {"from": POSE, "to": POSE} under `key`: the object and its keys.
Status checkSweep(const json& q, const char* key) {
  if (!q.contains(key)) return fail(std::string(key) + ": missing");
  const json& j = q.at(key);
  if (!j.is_object()) return fail(std::string(key) + ": must be an object {\"from\", \"to\"}");
  for (const auto& item : j.items()) {
    if (item.key() != "from" && item.key() != "to")
      return fail(std::string(key) + "." + item.key() + ": unknown key");
  }
  if (!j.contains("from")) return fail(std::string(key) + ".from: missing");
  if (!j.contains("to")) return fail(std::string(key) + ".to: missing");
  return {};
}

Status checkRay(const json& q) {
  if (!q.contains("ray")) return fail("ray: missing");
  const json& ray = q.at("ray");
  if (!ray.is_object()) return fail("ray: must be an object {\"origin\", \"translation\"}");
  for (const auto& item : ray.items()) {
    if (item.key() != "origin" && item.key() != "translation")
      return fail("ray." + item.key() + ": unknown key");
  }
  if (!ray.contains("origin")) return fail("ray.origin: missing");
  if (!ray.contains("translation")) return fail("ray.translation: missing");
  return {};
}

// op raycast: the ray {"origin", "translation"} (world frame) against shape `pieces` placed
// by worldFromA. The answer is the geometry layer's rayCast in A's frame, carried to the
// world frame; a concave shape gives its nearest piece's hit, and none when the ray starts
// inside a piece (as a ray starting inside a convex shape is not entering it).
QueryAnswer answerRayCast(const json& id, const std::vector<ShapeGeometry>& pieces,
                          Transform worldFromA, const json& q) {
  if (Status s = checkRay(q); !s) return rejected(id, s.message());
  const json& ray = q.at("ray");
  Result<Vec2> origin = parsePosition(ray.at("origin"), "ray.origin");
  if (!origin) return rejected(id, origin.error().message);
  Result<Vec2> translation = parsePosition(ray.at("translation"), "ray.translation");
  if (!translation) return rejected(id, translation.error().message);
  json out = toJson(rayCastPieces(pieces, worldFromA, *origin, *translation));
  out["id"] = id;
  return finished(id, out);
}

// op raycast in 3D: the ray (world frame) is carried into A's frame, cast against the
// shape, and the hit carried back; a miss keeps every number 0, as in 2D.
QueryAnswer answerRayCast3(const json& id, const ShapeGeometry3& shape, Transform3 worldFromA,
                           const json& q) {
  if (Status s = checkRay(q); !s) return rejected(id, s.message());
  const json& ray = q.at("ray");
  Result<Vec3> origin = parsePosition3(ray.at("origin"), "ray.origin");
  if (!origin) return rejected(id, origin.error().message);
  Result<Vec3> translation = parsePosition3(ray.at("translation"), "ray.translation");
  if (!translation) return rejected(id, translation.error().message);
  RayHit3 hit = rayCast(shape, {invTransformPoint(worldFromA, *origin),
                                invTransformVector(worldFromA, *translation), 1.0f});
  if (hit.hit) {
    hit.point = transformPoint(worldFromA, hit.point);
    hit.normal = transformVector(worldFromA, hit.normal);
  }
  json out = toJson(hit);
  out["id"] = id;
  return finished(id, out);
}

// The sweep {"from": POSE, "to": POSE} under `key` of op toi: the shape turns about
// `localCenter` (its proxy's centre), the short way round, at a constant rate.
Result<Sweep3> parseSweep3(const json& q, const char* key, Vec3 localCenter) {
  if (Status s = checkSweep(q, key); !s) return fail(s.message());
  const json& j = q.at(key);
  Result<Transform3> from = parsePose3(j.at("from"), std::string(key) + ".from");
  if (!from) return from.error();
  Result<Transform3> to = parsePose3(j.at("to"), std::string(key) + ".to");
  if (!to) return to.error();
  return makeSweep3(localCenter, *from, *to);
}

// Op toi's `target`: metres, kToiTargetSeparation when absent.
Result<float> parseToiTarget(const json& q) {
  if (!q.contains("target")) return kToiTargetSeparation;
  const json& v = q.at("target");
  if (!isLengthOption(v))
    return fail("target: must be a number >= 0 within the coordinate limit 1e9 m");
  return v.get<float>();
}

// The pose of a static mesh in op toi: its sweep's `from` when `key` is given (its `to` must
// be the same pose), else the origin.
Result<Transform3> parseStaticSweep3(const json& q, const char* key) {
  if (!q.contains(key)) return Transform3{};
  if (Status s = checkSweep(q, key); !s) return fail(s.message());
  const json& j = q.at(key);
  Result<Transform3> from = parsePose3(j.at("from"), std::string(key) + ".from");
  if (!from) return from.error();
  Result<Transform3> to = parsePose3(j.at("to"), std::string(key) + ".to");
  if (!to) return to.error();
  if (!(to->p == from->p && to->q == from->q)) {
    return fail(std::string(key) + ".to: a mesh is static: its pose must be " + key +
                ".from's (or leave " + key + " out: the mesh at the origin)");
  }
  return *from;
}

// A query with a static triangle mesh as shape a, or as shape b of ops overlap, distance,
// penetration and toi (the other shape convex): the mesh's own queries
// (collision/mesh3.hpp), each answer the convex one with the triangle's index; manifold
// gives one manifold per touching triangle. With the mesh as b the answer is turned round
// to say A to B: points swapped, normal negated.
QueryAnswer answerMesh3(const json& id, const std::string& op, const json& q, float speculative) {
  const bool meshIsA = isMesh3(q.at("a"));
  if (meshIsA && op != "raycast" && isMesh3(q.at("b")))
    return rejected(id, "b: a mesh against a mesh is not supported (shape b must be convex)");
  if (!meshIsA && op != "overlap" && op != "distance" && op != "penetration" && op != "toi") {
    return rejected(id, "b: a mesh must be shape a for op " + op + " (as shape b it supports ops " +
                            kMeshQueryOpsAsB + ")");
  }
  const char* meshKey = meshIsA ? "a" : "b";
  const char* convexKey = meshIsA ? "b" : "a";
  Result<Mesh3> mesh = parseMesh3(q.at(meshKey), meshKey);
  if (!mesh) return rejected(id, mesh.error().message);
  json out = {{"id", id}};
  if (op == "toi") {
    Result<ShapeGeometry3> convex = parseShape3(q.at(convexKey), convexKey);
    if (!convex) return rejected(id, convex.error().message);
    const ShapeProxy3 proxy = makeProxy(*convex);
    Result<Transform3> worldFromMesh = parseStaticSweep3(q, meshIsA ? "sweepA" : "sweepB");
    if (!worldFromMesh) return rejected(id, worldFromMesh.error().message);
    Result<Sweep3> sweep = parseSweep3(q, meshIsA ? "sweepB" : "sweepA", proxy.center());
    if (!sweep) return rejected(id, sweep.error().message);
    Result<float> target = parseToiTarget(q);
    if (!target) return rejected(id, target.error().message);
    // The answer (status, t, triangle) reads the same either way round.
    out.update(toJson(computeToiMesh(*mesh, *worldFromMesh, proxy, *sweep, 1.0f, *target)));
    return finished(id, out);
  }
  const char* meshPoseKey = meshIsA ? "pa" : "pb";
  Result<Transform3> pm = q.contains(meshPoseKey) ? parsePose3(q.at(meshPoseKey), meshPoseKey)
                                                  : Result<Transform3>(Transform3{});
  if (!pm) return rejected(id, pm.error().message);
  if (op == "raycast") {
    if (Status s = checkRay(q); !s) return rejected(id, s.message());
    const json& ray = q.at("ray");
    Result<Vec3> origin = parsePosition3(ray.at("origin"), "ray.origin");
    if (!origin) return rejected(id, origin.error().message);
    Result<Vec3> translation = parsePosition3(ray.at("translation"), "ray.translation");
    if (!translation) return rejected(id, translation.error().message);
    out.update(toJson(rayCastMesh(*mesh, *pm, {*origin, *translation, 1.0f})));
    return finished(id, out);
  }
  Result<ShapeGeometry3> convex = parseShape3(q.at(convexKey), convexKey);
  if (!convex) return rejected(id, convex.error().message);
  const char* convexPoseKey = meshIsA ? "pb" : "pa";
  Result<Transform3> pc = q.contains(convexPoseKey) ? parsePose3(q.at(convexPoseKey), convexPoseKey)
                                                    : Result<Transform3>(Transform3{});
  if (!pc) return rejected(id, pc.error().message);
  const ShapeProxy3 proxy = makeProxy(*convex);
  if (op == "shapecast") {
    if (!q.contains("translation")) return rejected(id, "translation: missing");
    Result<Vec3> translation = parsePosition3(q.at("translation"), "translation");
    if (!translation) return rejected(id, translation.error().message);
    out.update(toJson(castShapeMesh(*mesh, *pm, proxy, *pc, *translation)));
  } else if (op == "overlap") {
    out["overlap"] = testOverlapMesh(*mesh, *pm, proxy, *pc);
  } else if (op == "distance") {
    MeshDistanceOutput3 d = computeDistanceMesh(*mesh, *pm, proxy, *pc);
    if (!meshIsA) {
      std::swap(d.pointA, d.pointB);
      d.normal = -d.normal;
    }
    out.update(toJson(d));
  } else if (op == "penetration") {
    MeshPenetrationOutput3 p = computePenetrationMesh(*mesh, *pm, proxy, *pc);
    if (!meshIsA) {
      std::swap(p.pointA, p.pointB);
      p.normal = -p.normal;
    }
    out.update(toJson(p));
  } else {
    std::vector<MeshContact3> contacts;
    collideMesh(*mesh, *pm, *convex, *pc, contacts, speculative);
    out.update(toJson(contacts));
  }
  return finished(id, out);
}

// A query whose shapes are 3D (answerParsed has checked the keys, the op and the
// speculative distance, and that no shape is 2D): the same ops, fields and errors as in
// 2D, with [x, y, z] vectors and {"pos", "quat"} poses.
QueryAnswer answerParsed3(const json& id, const std::string& op, const json& q, float speculative) {
  auto parsePoseOrIdentity = [&](const char* key) -> Result<Transform3> {
    if (!q.contains(key)) return Transform3{};
    return parsePose3(q.at(key), key);
  };
  if (isMesh3(q.at("a")) || (op != "raycast" && isMesh3(q.at("b"))))
    return answerMesh3(id, op, q, speculative);
  Result<ShapeGeometry3> a = parseShape3(q.at("a"), "a");
  if (!a) return rejected(id, a.error().message);
  if (op == "raycast") {
    Result<Transform3> pa = parsePoseOrIdentity("pa");
    if (!pa) return rejected(id, pa.error().message);
    return answerRayCast3(id, *a, *pa, q);
  }
  Result<ShapeGeometry3> b = parseShape3(q.at("b"), "b");
  if (!b) return rejected(id, b.error().message);
  Result<Transform3> pa = parsePoseOrIdentity("pa");
  if (!pa) return rejected(id, pa.error().message);
  Result<Transform3> pb = parsePoseOrIdentity("pb");
  if (!pb) return rejected(id, pb.error().message);
  // The proxies view the hulls held by *a and *b, which outlive them.
  const ShapeProxy3 proxyA = makeProxy(*a);
  const ShapeProxy3 proxyB = makeProxy(*b);
  json out = {{"id", id}};
  if (op == "shapecast") {
    if (!q.contains("translation")) return rejected(id, "translation: missing");
    Result<Vec3> translation = parsePosition3(q.at("translation"), "translation");
    if (!translation) return rejected(id, translation.error().message);
    out.update(toJson(castShape(proxyA, *pa, proxyB, *pb, *translation)));
    return finished(id, out);
  }
  if (op == "toi") {
    // The shapes turn about their proxies' centres (the centres of their cores).
    Result<Sweep3> sweepA = parseSweep3(q, "sweepA", proxyA.center());
    if (!sweepA) return rejected(id, sweepA.error().message);
    Result<Sweep3> sweepB = parseSweep3(q, "sweepB", proxyB.center());
    if (!sweepB) return rejected(id, sweepB.error().message);
    Result<float> target = parseToiTarget(q);
    if (!target) return rejected(id, target.error().message);
    out.update(toJson(computeToi(proxyA, *sweepA, proxyB, *sweepB, 1.0f, *target)));
    return finished(id, out);
  }
  if (op == "overlap") {
    out["overlap"] = testOverlap(proxyA, *pa, proxyB, *pb);
  } else if (op == "distance") {
    out.update(toJson(computeDistance(proxyA, *pa, proxyB, *pb)));
  } else if (op == "manifold") {
    out.update(toJson(collide(*a, *pa, *b, *pb, speculative)));
  } else {
    out.update(toJson(computePenetration(proxyA, *pa, proxyB, *pb)));
  }
  return finished(id, out);
}

QueryAnswer answerParsed(const json& q) {
  if (!q.is_object()) return rejected(nullptr, "line must be a JSON object");
  json id = q.contains("id") ? q.at("id") : json(nullptr);
  for (const auto& item : q.items()) {
    const std::string& k = item.key();
    if (k != "id" && k != "op" && k != "a" && k != "pa" && k != "b" && k != "pb" &&
        k != "speculative" && k != "translation" && k != "sweepA" && k != "sweepB" &&
        k != "target" && k != "ray") {
      return rejected(id, k + ": unknown key");
    }
  }
  if (!q.contains("op")) return rejected(id, "op: missing");
  if (!q.at("op").is_string()) return rejected(id, "op: must be a string");
  const std::string op = q.at("op").get<std::string>();
  if (op != "overlap" && op != "distance" && op != "penetration" && op != "manifold" &&
      op != "raycast" && op != "shapecast" && op != "toi") {
    return rejected(id, "op: unknown op \"" + op +
                            "\" (expected overlap, distance, penetration, manifold, raycast, "
                            "shapecast, toi)");
  }
  // Keys that belong to one op only.
  if (q.contains("translation") && op != "shapecast")
    return rejected(id, "translation: only for op shapecast");
  if (q.contains("ray") && op != "raycast") return rejected(id, "ray: only for op raycast");
  if (op == "raycast") {
    for (const char* key : {"b", "pb"}) {
      if (q.contains(key))
        return rejected(id, std::string(key) + ": not used by op raycast (the ray meets a only)");
    }
  }
  for (const char* key : {"sweepA", "sweepB", "target"}) {
    if (q.contains(key) && op != "toi") return rejected(id, std::string(key) + ": only for op toi");
  }
  if (op == "toi") {
    for (const char* key : {"pa", "pb"}) {
      if (q.contains(key))
        return rejected(id, std::string(key) + ": not used by op toi (give sweepA and sweepB)");
    }
  }
  // manifold only: the speculative distance in metres (default kSpeculativeDistance).
  float speculative = kSpeculativeDistance;
  if (q.contains("speculative")) {
    if (op != "manifold") return rejected(id, "speculative: only for op manifold");
    const json& v = q.at("speculative");
    if (!isLengthOption(v)) {
      return rejected(id, "speculative: must be a number >= 0 within the coordinate limit 1e9 m");
    }
    speculative = v.get<float>();
  }
  if (!q.contains("a")) return rejected(id, "a: missing");
  // A shape whose vectors have three components (or a 3D-only type) is 3D; both shapes of
  // a line are in one dimension.
  const int dimensionA = shapeDimension(q.at("a"));
  const int dimensionB = op != "raycast" && q.contains("b") ? shapeDimension(q.at("b")) : 0;
  if (dimensionA == 3 || dimensionB == 3) {
    if (op != "raycast" && !q.contains("b")) return rejected(id, "b: missing");
    if (dimensionA == 2 || dimensionB == 2) {
      const char* flat = dimensionA == 2 ? "a" : "b";
      const char* solid = dimensionA == 2 ? "b" : "a";
      return rejected(id, std::string(flat) + ": a 2D shape in one query with the 3D shape " +
                              solid + " (both shapes must be 2D, or both 3D)");
    }
    return answerParsed3(id, op, q, speculative);
  }
  if (op == "raycast") {
    Result<std::vector<ShapeGeometry>> a = parseShapePieces(q.at("a"), "a");
    if (!a) return rejected(id, a.error().message);
    Result<Transform> pa =
        q.contains("pa") ? parsePose(q.at("pa"), "pa") : Result<Transform>(Transform{});
    if (!pa) return rejected(id, pa.error().message);
    return answerRayCast(id, *a, *pa, q);
  }
  if (!q.contains("b")) return rejected(id, "b: missing");
  Result<std::vector<ShapeGeometry>> a = parseShapePieces(q.at("a"), "a");
  if (!a) return rejected(id, a.error().message);
  Result<std::vector<ShapeGeometry>> b = parseShapePieces(q.at("b"), "b");
  if (!b) return rejected(id, b.error().message);
  Result<Transform> pa =
      q.contains("pa") ? parsePose(q.at("pa"), "pa") : Result<Transform>(Transform{});
  if (!pa) return rejected(id, pa.error().message);
  Result<Transform> pb =
      q.contains("pb") ? parsePose(q.at("pb"), "pb") : Result<Transform>(Transform{});
  if (!pb) return rejected(id, pb.error().message);

  json out = {{"id", id}};
  const bool concaveA = isConcave(q.at("a"));
  const bool concaveB = isConcave(q.at("b"));
  if (concaveA || concaveB) {
    // A concave shape is its convex pieces: overlap, distance and penetration are answered
    // over every pair of pieces (docs/concave.md); the other ops want one convex shape.
    const char* which = concaveA ? "a" : "b";
    if (op != "overlap" && op != "distance" && op != "penetration") {
      return rejected(id, std::string(which) + ": a concave shape supports ops overlap, " +
                              "distance and penetration only, not " + op);
    }
    const std::vector<ShapeGeometry>& piecesA = *a;
    const std::vector<ShapeGeometry>& piecesB = *b;
    if (op == "overlap") {
      out["overlap"] = overlapPieces(piecesA, *pa, piecesB, *pb);
      return finished(id, out);
    }
    if (op == "distance") {
      out.update(toJson(distancePieces(piecesA, *pa, piecesB, *pb)));
      return finished(id, out);
    }
    out.update(toJson(penetrationPieces(piecesA, *pa, piecesB, *pb)));
    return finished(id, out);
  }
  const ShapeGeometry& shapeA = a->front();
  const ShapeGeometry& shapeB = b->front();
  if (op == "shapecast") {
    if (!q.contains("translation")) return rejected(id, "translation: missing");
    Result<Vec2> translation = parsePosition(q.at("translation"), "translation");
    if (!translation) return rejected(id, translation.error().message);
    out.update(toJson(castShape(shapeA, *pa, shapeB, *pb, *translation)));
    return finished(id, out);
  }
  if (op == "toi") {
    // A sweep is {"from": POSE, "to": POSE}; the shape turns about its centre (the centre
    // of mass of a one-shape body), the short way round.
    auto parseSweep = [&](const char* key, const ShapeGeometry& shape) -> Result<Sweep> {
      if (Status s = checkSweep(q, key); !s) return fail(s.message());
      const json& j = q.at(key);
      Result<Transform> from = parsePose(j.at("from"), std::string(key) + ".from");
      if (!from) return fail(from.error().message);
      Result<Transform> to = parsePose(j.at("to"), std::string(key) + ".to");
      if (!to) return fail(to.error().message);
      return makeSweep(makeProxy(shape).center(), *from, *to);
    };
    Result<Sweep> sweepA = parseSweep("sweepA", shapeA);
    if (!sweepA) return rejected(id, sweepA.error().message);
    Result<Sweep> sweepB = parseSweep("sweepB", shapeB);
    if (!sweepB) return rejected(id, sweepB.error().message);
    Result<float> target = parseToiTarget(q);
    if (!target) return rejected(id, target.error().message);
    out.update(toJson(computeToi(shapeA, *sweepA, shapeB, *sweepB, 1.0f, *target)));
    return finished(id, out);
  }
  if (op == "overlap") {
    out["overlap"] = testOverlap(shapeA, *pa, shapeB, *pb);
  } else if (op == "distance") {
    out.update(toJson(computeDistance(shapeA, *pa, shapeB, *pb)));
  } else if (op == "manifold") {
    out.update(toJson(collide(shapeA, *pa, shapeB, *pb, speculative)));
  } else {
    out.update(toJson(computePenetration(shapeA, *pa, shapeB, *pb)));
  }
  return finished(id, out);
}

}  // namespace

int runQueries(std::istream& in, std::ostream& out) {
  int failures = 0;
  std::string line;
  long long number = 0;
  while (out && std::getline(in, line)) {
    ++number;
    QueryAnswer a = line.find_first_not_of(" \t\r") == std::string::npos
                        ? rejected(nullptr, "line " + std::to_string(number) + " is blank")
                        : answerQuery(line);
    if (!a.ok) ++failures;
    out << a.answer << '\n';
  }
  return failures;
}

int runQueryCommand(const std::string& file, std::istream& standardInput, std::ostream& out,
                    std::ostream& err) {
  const bool fromStdin = file == "-";
  const std::string inName = fromStdin ? "standard input" : file;
  std::ifstream opened;
  if (!fromStdin) {
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) {
      err << "quack query: cannot read " << file << ": " << std::strerror(EISDIR) << '\n';
      return 2;
    }
    errno = 0;
    opened.open(file);
    if (!opened) {
      err << "quack query: cannot open " << file << ": "
          << (errno != 0 ? std::strerror(errno) : "open failed") << '\n';
      return 2;
    }
  }
  std::istream& in = fromStdin ? standardInput : opened;
  errno = 0;
  const int failures = runQueries(in, out);
  const int readErrno = errno;
  out.flush();
  if (!out) {
    const int writeErrno = errno;
    err << "quack query: cannot write the answers to standard output: "
        << (writeErrno != 0 ? std::strerror(writeErrno) : "write failed") << '\n';
    return 2;
  }
  if (in.bad()) {
    err << "quack query: cannot read " << inName << ": "
        << (readErrno != 0 ? std::strerror(readErrno) : "read failed") << '\n';
    return 2;
  }
  if (failures > 0) {
    err << "quack query: " << failures << " line(s) failed\n";
    return 1;
  }
  return 0;
}

}  // namespace quack::app
