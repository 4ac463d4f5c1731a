// The WebAssembly face of Quack for the pages in web/: a plain C ABI (called from
// JavaScript with cwrap) that takes shapes in the shape JSON (README, "Formats") and
// answers with JSON strings. Every number the pages show comes from the library's public API
// (computeDistance, computePenetration, collide, computeMinkowskiDifference, World), and so
// do the per-iteration pictures: the same computeDistance and computePenetration calls fill
// the library's GjkTrace and EpaTrace (gjk.hpp, epa.hpp) with every pass of GJK and EPA.
//
// Frames in the answers: shape outlines are in their shape frame (the page places them with
// the pose it passed); everything else is in the world frame, and points of B - A are in
// world axes (b - a of world points).

#include <emscripten/emscripten.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "quack/collision/epa.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/minkowski.hpp"
#include "quack/collision/pieces.hpp"
#include "quack/io/answer_json.hpp"
#include "quack/io/shape_json.hpp"
#include "quack/world/world.hpp"

namespace quack::web {
namespace {

using nlohmann::json;

// A shape in the JSON of the README's "Formats", read by the io layer's own parser (the
// same one `quack query`, scene files and Python use: unknown keys refused, fields named),
// as its convex pieces: one for a convex shape, several for a "concave" outline.
Result<std::vector<ShapeGeometry>> readShape(const char* text) {
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) return fail("shape: not valid JSON");
  return parseShapePieces(j, "shape");
}

// Outline for drawing: the core points (shape frame) and the rounding radius.
json outlineOf(const ShapeGeometry& geometry) {
  ShapeProxy proxy = makeProxy(geometry);
  json points = json::array();
  for (int i = 0; i < proxy.count(); ++i)
    points.push_back(toJson(proxy.points()[i]));
  return {{"type", toString(shapeType(geometry))}, {"points", points}, {"radius", proxy.radius()}};
}

json supportJson(const SupportPoint& s, Transform worldFromA) {
  // w = pointB - pointA in A's frame; in world axes it is the rotated vector.
  return {{"w", toJson(rotate(worldFromA.q, s.w))},
          {"a", toJson(transformPoint(worldFromA, s.pointA))},
          {"b", toJson(transformPoint(worldFromA, s.pointB))},
          {"ia", s.indexA},
          {"ib", s.indexB}};
}

// The records are in A's frame; the page draws in world axes.
json gjkJson(const GjkTrace& trace, const DistanceOutput& d, Transform worldFromA) {
  json steps = json::array();
  for (int k = 0; k < trace.count; ++k) {
    const GjkIterationRecord& step = trace.records[k];
    json simplex = json::array();
    for (int i = 0; i < step.simplex.count; ++i) {
      json v = supportJson(step.simplex.vertices[i].support, worldFromA);
      v["weight"] = step.simplex.vertices[i].weight;
      simplex.push_back(v);
    }
    json s = {{"simplex", simplex}, {"closest", toJson(rotate(worldFromA.q, step.closest))}};
    if (step.hasSupport) {
      s["direction"] = toJson(rotate(worldFromA.q, step.direction));
      s["support"] = supportJson(step.support, worldFromA);
    }
    steps.push_back(s);
  }
  return {{"steps", steps},
          {"iterations", d.iterations},
          {"status", toString(d.status)},
          {"distance", d.distance},
          {"truncated", trace.truncated}};
}

json epaJson(const EpaTrace& trace, const PenetrationOutput& p, Transform worldFromA) {
  json steps = json::array();
  for (int k = 0; k < trace.count; ++k) {
    const EpaIterationRecord& step = trace.records[k];
    json polytope = json::array();
    for (int i = 0; i < step.polytopeCount; ++i)
      polytope.push_back(supportJson(step.polytope[i], worldFromA));
    json s = {{"polytope", polytope},
              {"edge", step.edge},
              {"normal", toJson(rotate(worldFromA.q, step.edgeNormal))},
              {"distance", step.edgeDistance}};
    if (step.hasSupport) s["support"] = supportJson(step.support, worldFromA);
    steps.push_back(s);
  }
  return {{"ran", trace.count > 0},       {"steps", steps},
          {"status", toString(p.status)}, {"depth", p.depth},
          {"iterations", p.iterations},   {"truncated", trace.truncated}};
}

// memcpy, not std::bit_cast: emscripten 3.1.6's libc++ has no bit_cast.
bool sameBits(float x, float y) {
  std::uint32_t bx, by;
  std::memcpy(&bx, &x, sizeof bx);
  std::memcpy(&by, &y, sizeof by);
  return bx == by;
}
bool sameBits(Vec2 x, Vec2 y) {
  return sameBits(x.x, y.x) && sameBits(x.y, y.y);
}

// The observers' promise, checked on every call: the whole run was recorded and its last
// record is the returned answer, bit for bit (tests/collision/observer_test.cpp tests it
// too; the page shows the result).
bool traceMatches(const GjkTrace& trace, const DistanceOutput& d) {
  if (trace.truncated || trace.count < 1) return false;
  const GjkIterationRecord& last = trace.records[trace.count - 1];
  return sameBits(last.distance, d.distance) && sameBits(last.pointA, d.pointA) &&
         sameBits(last.pointB, d.pointB) && sameBits(last.normal, d.normal);
}

bool traceMatches(const EpaTrace& trace, const PenetrationOutput& p) {
  if (trace.truncated) return false;
  if (trace.count == 0) return true;  // EPA did not run: the answer is GJK's
  const EpaIterationRecord& last = trace.records[trace.count - 1];
  return sameBits(last.depth, p.depth) && sameBits(last.normal, p.normal) &&
         sameBits(last.pointA, p.pointA) && sameBits(last.pointB, p.pointB);
}

// Trace buffers big enough for any run, allocated once (an EPA record is about 4 kB).
std::vector<GjkIterationRecord> gGjkRecords(kGjkMaxTraceRecords);
std::vector<EpaIterationRecord> gEpaRecords(kEpaMaxTraceRecords);

// The GJK page's two shapes, each as its convex pieces.
std::vector<ShapeGeometry> gShapes[2] = {{Circle{{}, 0.5f}}, {Circle{{}, 0.5f}}};

json outlinesOf(const std::vector<ShapeGeometry>& pieces) {
  json out = json::array();
  for (const ShapeGeometry& g : pieces)
    out.push_back(outlineOf(g));
  return out;
}
std::string gAnswer;

const char* answer(const json& j) {
  gAnswer = j.dump();
  return gAnswer.c_str();
}

const char* errorAnswer(const std::string& message) {
  return answer({{"error", message}});
}

// ---- the 3D GJK and EPA page ----------------------------------------------------------

// The 3D page's two shapes (shape frame), set by qk3_set_shape.
ShapeGeometry3 gShapes3[2] = {Sphere{{}, 0.5f}, Sphere{{}, 0.5f}};
std::vector<Gjk3IterationRecord> gGjk3Records(kGjk3MaxTraceRecords);
std::vector<Epa3IterationRecord> gEpa3Records(kEpa3MaxTraceRecords);

// A 3D shape for drawing, shape frame: its core points and radius (sphere: the centre;
// capsule: the two ends; triangle, hull: the vertices) and, for a hull, its faces as
// vertex-index polygons.
json outline3Of(const ShapeGeometry3& geometry) {
  ShapeProxy3 proxy = makeProxy(geometry);
  json points = json::array();
  for (int i = 0; i < proxy.count(); ++i)
    points.push_back(toJson(proxy.points()[i]));
  json out = {
      {"type", toString(shapeType(geometry))}, {"points", points}, {"radius", proxy.radius()}};
  if (const Hull3* hull = std::get_if<Hull3>(&geometry)) {
    json faces = json::array();
    for (int f = 0; f < hull->faceCount; ++f) {
      json face = json::array();
      const HullFace3& hf = hull->faces[f];
      for (int k = 0; k < hf.count; ++k)
        face.push_back(hull->faceVertices[hf.first + k]);
      faces.push_back(face);
    }
    out["faces"] = faces;
  }
  return out;
}

json support3Json(const SupportPoint3& s, Transform3 worldFromA) {
  // w = pointB - pointA in A's frame; in world axes it is the rotated vector.
  return {{"w", toJson(rotate(worldFromA.q, s.w))},
          {"a", toJson(transformPoint(worldFromA, s.pointA))},
          {"b", toJson(transformPoint(worldFromA, s.pointB))},
          {"ia", s.indexA},
          {"ib", s.indexB}};
}

json gjk3Json(const Gjk3Trace& trace, const DistanceOutput3& d, Transform3 worldFromA) {
  json steps = json::array();
  for (int k = 0; k < trace.count; ++k) {
    const Gjk3IterationRecord& step = trace.records[k];
    json simplex = json::array();
    for (int i = 0; i < step.simplex.count; ++i) {
      json v = support3Json(step.simplex.v[i], worldFromA);
      v["weight"] = step.simplex.weights[i];
      simplex.push_back(v);
    }
    json s = {{"simplex", simplex}, {"closest", toJson(rotate(worldFromA.q, step.closest))}};
    if (step.hasSupport) {
      s["direction"] = toJson(rotate(worldFromA.q, step.direction));
      s["support"] = support3Json(step.support, worldFromA);
    }
    steps.push_back(s);
  }
  return {{"steps", steps},
          {"iterations", d.iterations},
          {"status", toString(d.status)},
          {"truncated", trace.truncated}};
}

json epa3Json(const Epa3Trace& trace, const PenetrationOutput3& p, Transform3 worldFromA) {
  json steps = json::array();
  for (int k = 0; k < trace.count; ++k) {
    const Epa3IterationRecord& step = trace.records[k];
    json vertices = json::array();
    for (int i = 0; i < step.vertexCount; ++i)
      vertices.push_back(toJson(rotate(worldFromA.q, step.vertices[i].w)));
    json faces = json::array();
    for (int f = 0; f < step.faceCount; ++f)
      faces.push_back({step.faces[f][0], step.faces[f][1], step.faces[f][2]});
    json s = {{"vertices", vertices},
              {"faces", faces},
              {"nearest", step.nearest},
              {"normal", toJson(rotate(worldFromA.q, step.faceNormal))},
              {"distance", step.faceDistance}};
    if (step.hasSupport) s["support"] = support3Json(step.support, worldFromA);
    steps.push_back(s);
  }
  return {{"ran", trace.count > 0},
          {"steps", steps},
          {"status", toString(p.status)},
          {"truncated", trace.truncated}};
}

bool sameBits(Vec3 x, Vec3 y) {
  return sameBits(x.x, y.x) && sameBits(x.y, y.y) && sameBits(x.z, y.z);
}

// ---- the sandbox world ----------------------------------------------------------------

struct Sandbox {
  std::optional<World> world;
  std::vector<ShapeId> shapes;  // every shape ever created, by sandbox index
};
Sandbox gSandbox;

int sandboxIndex(ShapeId id) {
  for (std::size_t i = 0; i < gSandbox.shapes.size(); ++i) {
    if (gSandbox.shapes[i] == id) return static_cast<int>(i);
  }
  return -1;
}

json aabbJson(Aabb box) {
  return json::array({box.lower.x, box.lower.y, box.upper.x, box.upper.y});
}

}  // namespace
}  // namespace quack::web

using namespace quack;
using namespace quack::web;

extern "C" {

/// Sets shape `slot` (0 = A, 1 = B) of the GJK page from the shape JSON. Returns
/// {"ok": true, "outline": ...} or {"error": "..."} (the old shape is kept on error).
EMSCRIPTEN_KEEPALIVE const char* qk_set_shape(int slot, const char* shapeJson) {
  if (slot < 0 || slot > 1) return errorAnswer("slot: must be 0 or 1");
  Result<std::vector<ShapeGeometry>> g = readShape(shapeJson);
  if (!g) return errorAnswer(g.error().message);
  gShapes[slot] = std::move(g.value());
  return answer({{"ok", true}, {"pieces", outlinesOf(gShapes[slot])}});
}

/// Everything the GJK page draws for shape A at (ax, ay, aAngle) and B at (bx, by, bAngle):
/// the library's distance, penetration and manifold answers, the core of B - A, and every
/// pass of GJK and EPA (the library's traces) with a flag saying whether each trace's last
/// record is the answer, bit for bit.
EMSCRIPTEN_KEEPALIVE const char* qk_analyze(double ax, double ay, double aAngle, double bx,
                                            double by, double bAngle) {
  Transform worldFromA =
      makeTransform({static_cast<float>(ax), static_cast<float>(ay)}, static_cast<float>(aAngle));
  Transform worldFromB =
      makeTransform({static_cast<float>(bx), static_cast<float>(by)}, static_cast<float>(bAngle));
  // A concave shape is its pieces (docs/concave.md): the answers are the library's pieces
  // answers, and the pictures are of the pairs they come from: GJK's of the closest pair,
  // EPA's, the manifold's and the Minkowski difference's of the deepest overlapping pair
  // (else the closest). For two convex shapes both pairs are the one pair.
  std::size_t closeA = 0, closeB = 0, deepA = 0, deepB = 0;
  DistanceOutput d =
      distancePieces(gShapes[0], worldFromA, gShapes[1], worldFromB, &closeA, &closeB);
  PenetrationOutput p =
      penetrationPieces(gShapes[0], worldFromA, gShapes[1], worldFromB, &deepA, &deepB);
  GjkTrace gjkTrace{gGjkRecords.data(), kGjkMaxTraceRecords};
  EpaTrace epaTrace{gEpaRecords.data(), kEpaMaxTraceRecords};
  const DistanceOutput tracedD =
      computeDistance(makeProxy(gShapes[0][closeA]), worldFromA, makeProxy(gShapes[1][closeB]),
                      worldFromB, nullptr, gjkTrace);
  const PenetrationOutput tracedP =
      computePenetration(makeProxy(gShapes[0][deepA]), worldFromA, makeProxy(gShapes[1][deepB]),
                         worldFromB, nullptr, nullptr, &epaTrace);
  const ShapeGeometry& pairA = gShapes[0][deepA];
  const ShapeGeometry& pairB = gShapes[1][deepB];
  ShapeProxy a = makeProxy(pairA);
  ShapeProxy b = makeProxy(pairB);
  Manifold m = collide(pairA, worldFromA, pairB, worldFromB);

  json out;
  out["piecesA"] = outlinesOf(gShapes[0]);
  out["piecesB"] = outlinesOf(gShapes[1]);
  out["pair"] = {{"gjk", {closeA, closeB}}, {"epa", {deepA, deepB}}};
  out["distance"] = toJson(d);
  out["distance"]["coreDistance"] = d.coreDistance;
  out["penetration"] = toJson(p);
  out["manifold"] = toJson(m);

  Result<Hull> hull = computeMinkowskiDifference(a, worldFromA, b, worldFromB);
  json minkowski = {{"radius", a.radius() + b.radius()}};
  if (hull) {
    json hp = json::array();
    for (int i = 0; i < hull->count; ++i)
      hp.push_back(toJson(hull->points[i]));
    minkowski["points"] = hp;
  } else {
    // No area (two points, parallel segments): draw the pairwise differences instead.
    json hp = json::array();
    for (int i = 0; i < a.count(); ++i) {
      for (int k = 0; k < b.count(); ++k) {
        hp.push_back(toJson(transformPoint(worldFromB, b.points()[k]) -
                            transformPoint(worldFromA, a.points()[i])));
      }
    }
    minkowski["points"] = hp;
    minkowski["flat"] = hull.error().message;
  }
  out["minkowski"] = minkowski;

  // The traced calls are the very calls the pieces answers made (same inputs, same bits);
  // traceAgrees checks the traces against the answers the page shows.
  out["gjk"] = gjkJson(gjkTrace, tracedD, worldFromA);
  out["epa"] = epaJson(epaTrace, tracedP, worldFromA);
  out["traceAgrees"] = {{"gjk", traceMatches(gjkTrace, d)}, {"epa", traceMatches(epaTrace, p)}};
  return answer(out);
}

/// Sets shape `slot` (0 = A, 1 = B) of the 3D page from the 3D shape JSON (docs/3d.md, the
/// format of `quack query`). Returns {"ok": true, "shape": outline} or {"error": "..."} (the
/// old shape is kept on error).
EMSCRIPTEN_KEEPALIVE const char* qk3_set_shape(int slot, const char* shapeJson) {
  if (slot < 0 || slot > 1) return errorAnswer("slot: must be 0 or 1");
  json j = json::parse(shapeJson, nullptr, false);
  if (j.is_discarded()) return errorAnswer("shape: not valid JSON");
  Result<ShapeGeometry3> g = parseShape3(j, "shape");
  if (!g) return errorAnswer(g.error().message);
  gShapes3[slot] = std::move(g.value());
  return answer({{"ok", true}, {"shape", outline3Of(gShapes3[slot])}});
}

/// Everything the 3D page draws for the poses {"pa": POSE, "pb": POSE} (3D poses as
/// `quack query` reads them, through the same parser): the library's distance and
/// penetration answers (the calls `quack query` makes), and every pass of GJK and EPA from
/// the traced overloads, with a flag per trace saying whether the traced call returned the
/// same answer, bit for bit.
EMSCRIPTEN_KEEPALIVE const char* qk3_analyze(const char* posesJson) {
  json j = json::parse(posesJson, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return errorAnswer("poses: not a JSON object");
  Result<Transform3> pa = parsePose3(j.value("pa", json::object()), "pa");
  if (!pa) return errorAnswer(pa.error().message);
  Result<Transform3> pb = parsePose3(j.value("pb", json::object()), "pb");
  if (!pb) return errorAnswer(pb.error().message);
  const ShapeProxy3 a = makeProxy(gShapes3[0]);
  const ShapeProxy3 b = makeProxy(gShapes3[1]);
  const DistanceOutput3 d = computeDistance(a, *pa, b, *pb);
  const PenetrationOutput3 p = computePenetration(a, *pa, b, *pb);
  Gjk3Trace gjkTrace{gGjk3Records.data(), kGjk3MaxTraceRecords};
  Epa3Trace epaTrace{gEpa3Records.data(), kEpa3MaxTraceRecords};
  const DistanceOutput3 tracedD = computeDistance(a, *pa, b, *pb, nullptr, gjkTrace);
  const PenetrationOutput3 tracedP =
      computePenetration(a, *pa, b, *pb, nullptr, nullptr, &epaTrace);
  const bool gjkAgrees = !gjkTrace.truncated && sameBits(tracedD.distance, d.distance) &&
                         sameBits(tracedD.pointA, d.pointA) && sameBits(tracedD.pointB, d.pointB) &&
                         sameBits(tracedD.normal, d.normal) && tracedD.iterations == d.iterations;
  const bool epaAgrees = !epaTrace.truncated && sameBits(tracedP.depth, p.depth) &&
                         sameBits(tracedP.normal, p.normal) && sameBits(tracedP.pointA, p.pointA) &&
                         sameBits(tracedP.pointB, p.pointB) && tracedP.iterations == p.iterations;
  json out;
  out["shapes"] = {outline3Of(gShapes3[0]), outline3Of(gShapes3[1])};
  out["distance"] = toJson(d);
  out["distance"]["coreDistance"] = d.coreDistance;
  out["penetration"] = toJson(p);
  out["gjk"] = gjk3Json(gjkTrace, tracedD, *pa);
  out["epa"] = epa3Json(epaTrace, tracedP, *pa);
  out["traceAgrees"] = {{"gjk", gjkAgrees}, {"epa", epaAgrees}};
  return answer(out);
}

/// A new sandbox world (gravity -10, the library's defaults) with broad phase `kind`
/// ("tree", "quadtree", "sap", "hash", "brute"). Returns {"ok"} or {"error"}.
EMSCRIPTEN_KEEPALIVE const char* qk_world_reset(const char* kind) {
  Result<BroadPhaseKind> k = parseBroadPhaseKind(kind);
  if (!k) return errorAnswer(k.error().message);
  Result<World> w = World::create({.broadPhase = *k});
  if (!w) return errorAnswer(w.error().message);
  gSandbox.world.emplace(std::move(w.value()));
  gSandbox.shapes.clear();
  return answer({{"ok", true}});
}

/// Adds a body of type 0 static, 1 kinematic, 2 dynamic at (x, y, angle) with one shape
/// (shape JSON) and the given restitution. Returns {"shape": index} or {"error"}.
EMSCRIPTEN_KEEPALIVE const char* qk_world_add(const char* shapeJson, int type, double x, double y,
                                              double angle, double vx, double vy,
                                              double restitution) {
  if (!gSandbox.world) return errorAnswer("no world: call qk_world_reset first");
  Result<std::vector<ShapeGeometry>> g = readShape(shapeJson);
  if (!g) return errorAnswer(g.error().message);
  static const BodyType kTypes[] = {BodyType::staticBody, BodyType::kinematicBody,
                                    BodyType::dynamicBody};
  if (type < 0 || type > 2) return errorAnswer("type: must be 0, 1 or 2");
  World& world = *gSandbox.world;
  Result<BodyId> body =
      world.createBody({.type = kTypes[type],
                        .position = {static_cast<float>(x), static_cast<float>(y)},
                        .angle = static_cast<float>(angle),
                        .linearVelocity = {static_cast<float>(vx), static_cast<float>(vy)}});
  if (!body) return errorAnswer(body.error().message);
  // A concave shape is one body with a shape per piece.
  json indices = json::array();
  const std::size_t first = gSandbox.shapes.size();
  for (const ShapeGeometry& piece : g.value()) {
    Result<ShapeId> shape =
        world.createShape(*body, {.restitution = static_cast<float>(restitution)}, piece);
    if (!shape) {
      (void)world.destroyBody(*body);
      gSandbox.shapes.resize(first);
      return errorAnswer(shape.error().message);
    }
    gSandbox.shapes.push_back(*shape);
    indices.push_back(gSandbox.shapes.size() - 1);
  }
  return answer({{"shape", first}, {"shapes", indices}});
}

/// Removes every dynamic body whose centre is below `y` (bodies that fell off the ground).
EMSCRIPTEN_KEEPALIVE int qk_world_cull(double y) {
  if (!gSandbox.world) return 0;
  World& world = *gSandbox.world;
  int removed = 0;
  for (BodyId body : world.bodies()) {
    if (world.bodyType(body) == BodyType::dynamicBody && world.position(body).y < y) {
      removed += world.destroyBody(body) ? 1 : 0;
    }
  }
  return removed;
}

/// Wakes every sleeping body with a shape within `radius` metres of the world point (x, y)
/// (the page's click, with a few pixels of slack so that a segment can be picked). Returns
/// {"woken": [shape index, ...]}: the shapes near the point whose bodies it woke (their
/// islands wake with them; empty when the point is on no sleeping body), or {"error"}.
EMSCRIPTEN_KEEPALIVE const char* qk_world_wake(double x, double y, double radius) {
  if (!gSandbox.world) return errorAnswer("no world: call qk_world_reset first");
  World& world = *gSandbox.world;
  Result<Circle> pick = makeCircle({}, static_cast<float>(radius));
  if (!pick) return errorAnswer("radius: " + pick.error().message);
  Result<std::vector<ShapeOverlap>> hits = world.overlapShape(
      pick.value(), makeTransform({static_cast<float>(x), static_cast<float>(y)}, 0.0f));
  if (!hits) return errorAnswer(hits.error().message);
  json woken = json::array();
  for (const ShapeOverlap& hit : hits.value()) {
    if (world.bodyType(hit.body) == BodyType::staticBody || world.isAwake(hit.body)) continue;
    Status s = world.setAwake(hit.body, true);
    if (!s) return errorAnswer(s.message());
    woken.push_back(sandboxIndex(hit.shape));
  }
  return answer({{"woken", woken}});
}

/// Steps the sandbox `steps` times by dt and returns the events of every step:
/// {"begin": [[a, b], ...], "end": [...], "hit": [{"a", "b", "point", "speed"}]}.
EMSCRIPTEN_KEEPALIVE const char* qk_world_step(double dt, int steps) {
  if (!gSandbox.world) return errorAnswer("no world: call qk_world_reset first");
  World& world = *gSandbox.world;
  json begin = json::array(), end = json::array(), hit = json::array();
  for (int i = 0; i < steps; ++i) {
    Status s = world.step(static_cast<float>(dt), world.def().substeps);
    if (!s) return errorAnswer(s.message());
    const StepEvents& e = world.events();
    for (const ContactBeginEvent& x : e.begin)
      begin.push_back({sandboxIndex(x.shapeA), sandboxIndex(x.shapeB)});
    for (const ContactEndEvent& x : e.end)
      end.push_back({sandboxIndex(x.shapeA), sandboxIndex(x.shapeB)});
    for (const ContactHitEvent& x : e.hit) {
      hit.push_back({{"a", sandboxIndex(x.shapeA)},
                     {"b", sandboxIndex(x.shapeB)},
                     {"point", toJson(x.point)},
                     {"speed", x.approachSpeed}});
    }
  }
  return answer({{"begin", begin}, {"end", end}, {"hit", hit}, {"time", world.time()}});
}

/// The sandbox for drawing: live shapes (outline in the shape frame plus the body pose),
/// the fat box of every broad-phase proxy, the touching contacts and the tree's figures.
EMSCRIPTEN_KEEPALIVE const char* qk_world_state() {
  if (!gSandbox.world) return errorAnswer("no world: call qk_world_reset first");
  const World& world = *gSandbox.world;
  json shapes = json::array();
  for (std::size_t i = 0; i < gSandbox.shapes.size(); ++i) {
    ShapeId id = gSandbox.shapes[i];
    if (!world.isValid(id)) continue;
    BodyId body = world.body(id);
    Transform t = world.transform(body);
    json s = outlineOf(world.geometry(id));
    s["index"] = i;
    s["pos"] = toJson(t.p);
    s["angle"] = world.angle(body);
    s["bodyType"] = static_cast<int>(world.bodyType(body));
    s["awake"] = world.isAwake(body);  // false while asleep, and always for static bodies
    shapes.push_back(s);
  }
  const BroadPhase& bp = world.broadPhase();
  json fat = json::array();
  bp.queryAabb(Aabb{{-kMaxCoordinate, -kMaxCoordinate}, {kMaxCoordinate, kMaxCoordinate}},
               [&](ProxyId id, std::uint64_t) {
                 fat.push_back(aabbJson(bp.fatBox(id)));
                 return true;
               });
  // The tree's internal nodes (x0, y0, x1, y1, depth), when the broad phase is the tree.
  json treeBoxes = json::array();
  if (const DynamicTree* tree = bp.tree()) {
    tree->visitInternalNodes([&](Aabb box, int depth) {
      json b = aabbJson(box);
      b.push_back(depth);
      treeBoxes.push_back(b);
    });
  }
  json contacts = json::array();
  for (const World::ContactView& c : world.touchingContacts()) {
    json contact = toJson(c.manifold);
    contact["a"] = sandboxIndex(c.shapeA);
    contact["b"] = sandboxIndex(c.shapeB);
    contacts.push_back(contact);
  }
  BroadPhaseStats stats = bp.stats();
  return answer({{"shapes", shapes},
                 {"fatBoxes", fat},
                 {"treeBoxes", treeBoxes},
                 {"contacts", contacts},
                 {"broadPhase",
                  {{"kind", std::string(toString(bp.kind()))},
                   {"proxies", stats.proxyCount},
                   {"height", stats.height},
                   {"areaRatio", stats.areaRatio},
                   {"hasTree", bp.tree() != nullptr}}},
                 {"bodies", world.bodyCount()},
                 {"awakeBodies", world.awakeBodyCount()},
                 {"islands", world.islandCount()},
                 {"contactCount", world.contactCount()},
                 {"time", world.time()},
                 {"steps", world.stepCount()}});
}

}  // extern "C"
