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
#include <optional>
#include <string>
#include <utility>
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
#include "quack/io/scene3.hpp"
#include "quack/io/shape_json.hpp"
#include "quack/world/world.hpp"
#include "quack/world/world3.hpp"

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
  JointId mouse;                // the pointer's mouse joint while a body is dragged
  std::vector<JointId> drive;   // the cars' wheel joints, which qk_world_drive turns
  // The static pivot each chain hangs from, and the chain's first joint: the pivot goes
  // when that joint has (its link fell off the world, or was cleared).
  std::vector<std::pair<BodyId, JointId>> pivots;
};
Sandbox gSandbox;

int sandboxIndex(ShapeId id) {
  for (std::size_t i = 0; i < gSandbox.shapes.size(); ++i) {
    if (gSandbox.shapes[i] == id) return static_cast<int>(i);
  }
  return -1;
}

// A body with one shape, its shape recorded under the next sandbox index (so that the
// page draws it).
Result<BodyId> addBody(World& world, BodyType type, Vec2 position, float angle,
                       const ShapeGeometry& geometry, const ShapeDef& shape = {}) {
  BodyDef def;
  def.type = type;
  def.position = position;
  def.angle = angle;
  Result<BodyId> body = world.createBody(def);
  if (!body) return body;
  Result<ShapeId> s = world.createShape(*body, shape, geometry);
  if (!s) {
    (void)world.destroyBody(*body);
    return s.error();
  }
  gSandbox.shapes.push_back(*s);
  return body;
}

Result<BodyId> addBox(World& world, Vec2 position, Vec2 half, const ShapeDef& shape = {}) {
  Result<Polygon> box = makeBox(half.x, half.y);
  if (!box) return box.error();
  return addBody(world, BodyType::dynamicBody, position, 0.0f, *box, shape);
}

ShapeDef material(float density, float friction) {
  ShapeDef d;
  d.density = density;
  d.friction = friction;
  return d;
}

JointDef revoluteAt(BodyId a, BodyId b, Vec2 anchor) {
  JointDef d;
  d.type = JointType::revolute;
  d.bodyA = a;
  d.bodyB = b;
  d.anchorA = anchor;
  return d;
}

// The drop-ins (qk_world_drop). Each returns the joints it made; a failure part way leaves
// what was made (the world refuses only at its limits, which the page does not reach).

// 20 capsule links, 0.25 m each, from a static pivot at `at`, laid level towards the middle
// of the view so that the chain swings down.
Result<std::vector<JointId>> addChain(World& world, Vec2 at) {
  Result<Circle> pin = makeCircle({}, 0.08f);
  Result<Capsule> link = makeCapsule({-0.1f, 0.0f}, {0.1f, 0.0f}, 0.05f);
  if (!pin || !link) return fail("chain: bad shapes");
  Result<BodyId> pivot = addBody(world, BodyType::staticBody, at, 0.0f, *pin);
  if (!pivot) return pivot.error();
  const float dir = at.x > 0.0f ? -1.0f : 1.0f;
  std::vector<JointId> joints;
  BodyId previous = *pivot;
  for (int i = 0; i < 20; ++i) {
    const float x = at.x + dir * 0.25f * static_cast<float>(i);
    Result<BodyId> b = addBody(world, BodyType::dynamicBody, {x + dir * 0.125f, at.y}, 0.0f, *link,
                               material(1.0f, 0.4f));
    if (!b) return b.error();
    Result<JointId> j = world.createJoint(revoluteAt(previous, *b, {x, at.y}));
    if (!j) return j.error();
    joints.push_back(*j);
    previous = *b;
  }
  gSandbox.pivots.push_back({*pivot, joints.front()});
  return joints;
}

// A chassis on two wheels: wheel joints on vertical axes with 5 Hz suspension springs and
// limits, and motors held at speed 0 (brakes) until qk_world_drive turns them.
Result<std::vector<JointId>> addCar(World& world, Vec2 at) {
  Result<BodyId> chassis = addBox(world, at, {1.0f, 0.22f}, material(1.0f, 0.6f));
  if (!chassis) return chassis.error();
  Result<Circle> tyre = makeCircle({}, 0.32f);
  if (!tyre) return tyre.error();
  std::vector<JointId> joints;
  for (float dx : {-0.7f, 0.7f}) {
    const Vec2 hub = at + Vec2{dx, -0.45f};
    Result<BodyId> wheel =
        addBody(world, BodyType::dynamicBody, hub, 0.0f, *tyre, material(1.0f, 0.9f));
    if (!wheel) return wheel.error();
    JointDef d;
    d.type = JointType::wheel;
    d.bodyA = *chassis;
    d.bodyB = *wheel;
    d.anchorA = hub;
    d.axis = {0.0f, 1.0f};
    d.enableSpring = true;
    d.hertz = 5.0f;
    d.dampingRatio = 0.7f;
    d.enableLimit = true;
    d.lower = -0.2f;
    d.upper = 0.2f;
    d.enableMotor = true;
    d.motorSpeed = 0.0f;
    d.maxMotorTorque = 6.0f;
    Result<JointId> j = world.createJoint(d);
    if (!j) return j.error();
    joints.push_back(*j);
    gSandbox.drive.push_back(*j);
  }
  return joints;
}

// A ragdoll of 10 boxes about the hip at `at` (1.8 m tall), its joints revolute with limits
// and joint friction (a motor held at speed 0 with a small torque, so that limbs come to
// rest): the figure of tests/world/joint_world_test.cpp's addRagdoll.
Result<std::vector<JointId>> addRagdoll(World& world, Vec2 at) {
  struct Part {
    Vec2 center, half;
  };
  const Part parts[10] = {{{0.0f, 0.35f}, {0.12f, 0.35f}},   {{0.0f, 0.85f}, {0.1f, 0.12f}},
                          {{-0.2f, 0.45f}, {0.05f, 0.15f}},  {{0.2f, 0.45f}, {0.05f, 0.15f}},
                          {{-0.2f, 0.15f}, {0.045f, 0.15f}}, {{0.2f, 0.15f}, {0.045f, 0.15f}},
                          {{-0.08f, -0.2f}, {0.06f, 0.2f}},  {{0.08f, -0.2f}, {0.06f, 0.2f}},
                          {{-0.08f, -0.6f}, {0.05f, 0.2f}},  {{0.08f, -0.6f}, {0.05f, 0.2f}}};
  std::vector<BodyId> bodies;
  for (const Part& p : parts) {
    Result<BodyId> b = addBox(world, at + p.center, p.half);
    if (!b) return b.error();
    bodies.push_back(*b);
  }
  struct Link {
    int a, b;
    Vec2 anchor;
    float lower, upper;
  };
  const Link links[9] = {{0, 1, {0.0f, 0.72f}, -0.5f, 0.5f}, {0, 2, {-0.2f, 0.6f}, -3.0f, 1.0f},
                         {0, 3, {0.2f, 0.6f}, -1.0f, 3.0f},  {2, 4, {-0.2f, 0.3f}, -2.5f, 0.0f},
                         {3, 5, {0.2f, 0.3f}, 0.0f, 2.5f},   {0, 6, {-0.08f, 0.0f}, -1.5f, 1.0f},
                         {0, 7, {0.08f, 0.0f}, -1.0f, 1.5f}, {6, 8, {-0.08f, -0.4f}, 0.0f, 2.5f},
                         {7, 9, {0.08f, -0.4f}, -2.5f, 0.0f}};
  std::vector<JointId> joints;
  for (const Link& l : links) {
    JointDef d = revoluteAt(bodies[static_cast<std::size_t>(l.a)],
                            bodies[static_cast<std::size_t>(l.b)], at + l.anchor);
    d.enableLimit = true;
    d.lower = l.lower;
    d.upper = l.upper;
    d.enableMotor = true;
    d.motorSpeed = 0.0f;
    d.maxMotorTorque = 0.05f;
    Result<JointId> j = world.createJoint(d);
    if (!j) return j.error();
    joints.push_back(*j);
  }
  return joints;
}

json aabbJson(Aabb box) {
  return json::array({box.lower.x, box.lower.y, box.upper.x, box.upper.y});
}

// ---- the 3D sandbox world ---------------------------------------------------------------

// A World3 and what the page needs to draw it, which World3 does not give back: each
// shape's geometry (World3 has no geometry getter, so the glue keeps each shape's outline
// from when it was made) and the body it is on, by sandbox index.
struct Shape3Record {
  ShapeId3 id;
  int body = -1;  // sandbox body index
  json outline;   // outline3Of, or a mesh's vertices and triangles (body frame)
};
struct Sandbox3 {
  std::optional<World3> world;
  std::vector<BodyId3> bodies;  // every body ever made, by sandbox index
  std::vector<std::string> names;
  std::vector<Shape3Record> shapes;  // every shape ever made, by sandbox index
  double time = 0.0;                 // seconds stepped (World3 keeps the step count only)
  int shapesVersion = 0;             // bumped whenever shapes come or go: the page re-reads them
};
Sandbox3 gSandbox3;

json vec3Json(Vec3 v) {
  return json::array({v.x, v.y, v.z});
}

json meshOutline(const Mesh3& mesh) {
  json points = json::array(), faces = json::array();
  for (Vec3 v : mesh.vertices())
    points.push_back(vec3Json(v));
  for (const MeshTriangle3& t : mesh.triangles())
    faces.push_back({t.v[0], t.v[1], t.v[2]});
  return {{"type", "mesh"}, {"points", points}, {"radius", 0.0f}, {"faces", faces}};
}

// Checks that `text` is JSON, keeping nlohmann's message (the one json::parse throws)
// without throwing: this module is built without exception catching, so the try/catch in
// the io layer's scene reader could not catch a syntax error, and the whole module would
// abort. Only text that passes reaches parseScene3, which then reads it as `quack run` does;
// a syntax error is reported in the same words as `quack run` (`FILE: not valid JSON: ...`).
struct JsonSyntaxCheck {
  std::string error;
  bool null() { return true; }
  bool boolean(bool) { return true; }
  bool number_integer(json::number_integer_t) { return true; }
  bool number_unsigned(json::number_unsigned_t) { return true; }
  bool number_float(json::number_float_t, const json::string_t&) { return true; }
  bool string(json::string_t&) { return true; }
  bool binary(json::binary_t&) { return true; }
  bool start_object(std::size_t) { return true; }
  bool key(json::string_t&) { return true; }
  bool end_object() { return true; }
  bool start_array(std::size_t) { return true; }
  bool end_array() { return true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) {
    error = e.what();
    return false;
  }
};

Status checkJsonSyntax(const char* text, const std::string& what) {
  JsonSyntaxCheck check;
  if (!json::sax_parse(text, &check) || !check.error.empty()) {
    return fail(what + ": not valid JSON: " + check.error);
  }
  return {};
}

// Records a body made outside buildWorld3 (qk3_world_add) or in it, with its shapes.
int recordBody3(BodyId3 body, std::string name) {
  gSandbox3.bodies.push_back(body);
  gSandbox3.names.push_back(std::move(name));
  return static_cast<int>(gSandbox3.bodies.size()) - 1;
}

bool finite3(double x, double y, double z) {
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
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
  gSandbox.mouse = {};
  gSandbox.drive.clear();
  gSandbox.pivots.clear();
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
  // A chain's pivot goes with the chain (its first joint went with the first link).
  std::erase_if(gSandbox.pivots, [&](const std::pair<BodyId, JointId>& p) {
    if (world.isValid(p.second)) return false;
    (void)world.destroyBody(p.first);
    return true;
  });
  return removed;
}

/// Grabs the dynamic body under the world point (x, y) (within `radius` metres, the page's
/// few pixels of slack): a mouse joint on it at that point, pulling towards the pointer
/// with a 5 Hz spring damped at 0.7 and at most 1,000 times the body's weight, enough to
/// lift what hangs from it (a chain, a ragdoll) and still bounded, so that a body dragged
/// into a wall presses on it instead of being shot through (Box2D's samples bound their
/// mouse joint by the body's mass in the same way). Releases an earlier grab.
/// Returns {"grabbed": shape index} or {"grabbed": null} (nothing dynamic there), or
/// {"error"}.
EMSCRIPTEN_KEEPALIVE const char* qk_world_grab(double x, double y, double radius) {
  if (!gSandbox.world) return errorAnswer("no world: call qk_world_reset first");
  World& world = *gSandbox.world;
  if (world.isValid(gSandbox.mouse)) (void)world.destroyJoint(gSandbox.mouse);
  gSandbox.mouse = {};
  Result<Circle> pick = makeCircle({}, static_cast<float>(radius));
  if (!pick) return errorAnswer("radius: " + pick.error().message);
  const Vec2 at{static_cast<float>(x), static_cast<float>(y)};
  Result<std::vector<ShapeOverlap>> hits = world.overlapShape(*pick, makeTransform(at, 0.0f));
  if (!hits) return errorAnswer(hits.error().message);
  // The deepest hit: the shape the point is inside, rather than one just within the slack.
  const ShapeOverlap* best = nullptr;
  for (const ShapeOverlap& hit : *hits) {
    if (world.bodyType(hit.body) != BodyType::dynamicBody) continue;
    if (best == nullptr || hit.depth > best->depth) best = &hit;
  }
  if (best == nullptr) return answer({{"grabbed", nullptr}});
  JointDef d;
  d.type = JointType::mouse;
  d.bodyB = best->body;
  d.anchorA = at;
  d.target = at;
  d.hertz = 5.0f;
  d.dampingRatio = 0.7f;
  // A thousand times the body's weight (under 10 m/s^2 at least, so that a grab still pulls
  // in a world without gravity; and never 0, which createJoint refuses).
  d.maxForce =
      maxf(1000.0f * world.mass(best->body) * maxf(length(world.def().gravity), 10.0f), 1.0f);
  Result<JointId> j = world.createJoint(d);
  if (!j) return errorAnswer(j.error().message);
  gSandbox.mouse = *j;
  return answer({{"grabbed", sandboxIndex(best->shape)}});
}

/// Moves the grab's target to the world point (x, y). Returns 1, or 0 when nothing is
/// grabbed (or the grabbed body is gone).
EMSCRIPTEN_KEEPALIVE int qk_world_drag(double x, double y) {
  if (!gSandbox.world || !gSandbox.world->isValid(gSandbox.mouse)) return 0;
  return gSandbox.world->setMouseTarget(gSandbox.mouse,
                                        {static_cast<float>(x), static_cast<float>(y)})
             ? 1
             : 0;
}

/// Lets go: destroys the grab's mouse joint. Returns 1, or 0 when nothing was grabbed.
EMSCRIPTEN_KEEPALIVE int qk_world_release() {
  if (!gSandbox.world) return 0;
  const bool held = gSandbox.world->isValid(gSandbox.mouse);
  if (held) (void)gSandbox.world->destroyJoint(gSandbox.mouse);
  gSandbox.mouse = {};
  return held ? 1 : 0;
}

/// Drops in a jointed thing at the world point (x, y): "chain" (20 links from a static
/// pivot there), "car" (chassis at (x, y) on two sprung, motored wheels) or "ragdoll" (hip
/// at (x, y)). Returns {"joints": how many it made, "shapes": the sandbox indices of its
/// shapes, first the first body's, "bodies": the world's body count} or {"error"}.
EMSCRIPTEN_KEEPALIVE const char* qk_world_drop(const char* kind, double x, double y) {
  if (!gSandbox.world) return errorAnswer("no world: call qk_world_reset first");
  World& world = *gSandbox.world;
  const Vec2 at{static_cast<float>(x), static_cast<float>(y)};
  const std::string k = kind;
  const std::size_t firstShape = gSandbox.shapes.size();
  Result<std::vector<JointId>> made = fail("kind: \"" + k + "\" (expected chain, car, ragdoll)");
  if (k == "chain") made = addChain(world, at);
  if (k == "car") made = addCar(world, at);
  if (k == "ragdoll") made = addRagdoll(world, at);
  if (!made) return errorAnswer(made.error().message);
  json shapes = json::array();
  for (std::size_t i = firstShape; i < gSandbox.shapes.size(); ++i)
    shapes.push_back(i);
  return answer({{"joints", made->size()}, {"shapes", shapes}, {"bodies", world.bodyCount()}});
}

/// Turns every car's wheel motors at `speed` rad/s (negative: clockwise, so a car drives to
/// the right; 0 brakes). Returns how many wheel joints it set.
EMSCRIPTEN_KEEPALIVE int qk_world_drive(double speed) {
  if (!gSandbox.world) return 0;
  World& world = *gSandbox.world;
  std::erase_if(gSandbox.drive, [&](JointId j) { return !world.isValid(j); });
  int set = 0;
  for (JointId j : gSandbox.drive) {
    const JointDef& d = world.jointDef(j);
    set += world.setJointMotor(j, true, static_cast<float>(speed), d.maxMotorTorque) ? 1 : 0;
  }
  return set;
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
  // Every joint as the replays draw it: body A's centre, its anchor, B's anchor, B's
  // centre (a mouse joint: the target twice), and the grab's target and grabbed point.
  json joints = json::array();
  for (JointId j : world.joints()) {
    const JointDef& d = world.jointDef(j);
    const auto [onA, onB] = world.jointAnchors(j);
    const Vec2 centreA = d.type == JointType::mouse ? onA : world.worldCenterOfMass(d.bodyA);
    joints.push_back(
        {{"type", toString(d.type)},
         {"line",
          {toJson(centreA), toJson(onA), toJson(onB), toJson(world.worldCenterOfMass(d.bodyB))}}});
  }
  json mouse = nullptr;
  if (world.isValid(gSandbox.mouse)) {
    const auto [target, grabbed] = world.jointAnchors(gSandbox.mouse);
    mouse = {{"target", toJson(target)}, {"point", toJson(grabbed)}};
  }
  BroadPhaseStats stats = bp.stats();
  return answer({{"shapes", shapes},
                 {"joints", joints},
                 {"jointCount", world.jointCount()},
                 {"mouse", mouse},
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

// ---- the 3D sandbox (sandbox3d.html) ---------------------------------------------------

/// Replaces the 3D sandbox's world with the 3D scene `text` (docs/scenes.md, "3D scenes"),
/// read by the parser `quack run` uses (parseScene3, then buildWorld3): every error is
/// `quack run`'s message, `fileName` first (`fileName: bodies[2].quat: ...`). On an error the
/// old world stays. Returns {"ok", "bodies", "shapes", "substeps", "timeStep"} or {"error"}.
EMSCRIPTEN_KEEPALIVE const char* qk3_world_load(const char* text, const char* fileName) {
  const std::string file = fileName != nullptr ? fileName : "scene";
  if (text == nullptr) return errorAnswer(file + ": no text");
  if (Status s = checkJsonSyntax(text, file); !s) return errorAnswer(s.message());
  Result<Scene3> scene = parseScene3(text, file);
  if (!scene) return errorAnswer(scene.error().message);
  Result<SceneWorld3> built = buildWorld3(*scene);
  if (!built) return errorAnswer(built.error().message);
  Sandbox3 next;
  next.world.emplace(std::move(built->world));
  const int version = gSandbox3.shapesVersion;
  gSandbox3 = std::move(next);
  for (std::size_t b = 0; b < built->bodies.size(); ++b) {
    const int index = recordBody3(built->bodies[b], built->names[b]);
    const SceneBody3& sb = scene->bodies[b];
    for (std::size_t k = 0; k < built->shapes[b].size(); ++k) {
      const SceneGeometry3& g = sb.shapes[k].geometry;
      json outline = std::holds_alternative<Mesh3>(g) ? meshOutline(std::get<Mesh3>(g))
                                                      : outline3Of(std::get<ShapeGeometry3>(g));
      gSandbox3.shapes.push_back({built->shapes[b][k], index, std::move(outline)});
    }
  }
  gSandbox3.shapesVersion = version + 1;
  const WorldDef3& def = gSandbox3.world->def();
  return answer({{"ok", true},
                 {"bodies", gSandbox3.world->bodyCount()},
                 {"shapes", gSandbox3.world->shapeCount()},
                 {"substeps", def.substeps},
                 {"timeStep", def.timeStep},
                 {"gravity", vec3Json(def.gravity)}});
}

/// Adds a dynamic body with one shape: {"shape": 3D shape JSON (as `quack query`), "pos":
/// [x, y, z], "quat": [x, y, z, w] (optional), "vel": [x, y, z] (optional), "density",
/// "restitution" (optional numbers)}. Every field is checked, by the io layer's parsers
/// where there is one, and an error names it. Returns {"body", "shape"} (sandbox indices)
/// or {"error"}.
EMSCRIPTEN_KEEPALIVE const char* qk3_world_add(const char* bodyJson) {
  if (!gSandbox3.world) return errorAnswer("no 3D world: call qk3_world_load first");
  if (bodyJson == nullptr) return errorAnswer("body: no text");
  if (Status s = checkJsonSyntax(bodyJson, "body"); !s) return errorAnswer(s.message());
  const json j = json::parse(bodyJson, nullptr, false);
  if (!j.is_object()) return errorAnswer("body: must be a JSON object");
  for (const auto& [key, value] : j.items()) {
    (void)value;
    if (key != "shape" && key != "pos" && key != "quat" && key != "vel" && key != "density" &&
        key != "restitution") {
      return errorAnswer("body." + key +
                         ": unknown key (expected shape, pos, quat, vel, density, restitution)");
    }
  }
  if (!j.contains("shape")) return errorAnswer("body.shape: missing");
  Result<ShapeGeometry3> g = parseShape3(j.at("shape"), "body.shape");
  if (!g) return errorAnswer(g.error().message);
  json pose = {{"pos", j.value("pos", json::array({0, 0, 0}))}};
  if (j.contains("quat")) pose["quat"] = j.at("quat");
  Result<Transform3> t = parsePose3(pose, "body");
  if (!t) return errorAnswer(t.error().message);
  Vec3 vel;
  if (j.contains("vel")) {
    Result<Vec3> v = parseVec3(j.at("vel"), "body.vel");
    if (!v) return errorAnswer(v.error().message);
    vel = *v;
  }
  ShapeDef3 shape;
  for (const char* key : {"density", "restitution"}) {
    if (!j.contains(key)) continue;
    const json& x = j.at(key);
    if (!x.is_number() || !std::isfinite(x.get<double>())) {
      return errorAnswer(std::string("body.") + key + ": must be a finite number");
    }
    (std::string(key) == "density" ? shape.density : shape.restitution) = x.get<float>();
  }
  World3& world = *gSandbox3.world;
  Result<BodyId3> body = world.createBody(
      {.type = BodyType::dynamicBody, .position = t->p, .rotation = t->q, .linearVelocity = vel});
  if (!body) return errorAnswer(body.error().message);
  Result<ShapeId3> s = world.createShape(*body, shape, *g);
  if (!s) {
    (void)world.destroyBody(*body);
    return errorAnswer(s.error().message);
  }
  const int index = recordBody3(*body, "");
  gSandbox3.shapes.push_back({*s, index, outline3Of(*g)});
  ++gSandbox3.shapesVersion;
  return answer({{"body", index}, {"shape", gSandbox3.shapes.size() - 1}});
}

/// Steps the 3D sandbox `steps` times (1 to 1000) by `dt` seconds in the world's own
/// sub-steps (the scene's world.substeps). Returns {"time", "steps", "begin", "end"} (the
/// begin and end events of the last step) or {"error"}; a step the world refuses stops there.
EMSCRIPTEN_KEEPALIVE const char* qk3_world_step(double dt, int steps) {
  if (!gSandbox3.world) return errorAnswer("no 3D world: call qk3_world_load first");
  if (steps < 1 || steps > 1000) return errorAnswer("steps: must be 1 to 1000");
  World3& world = *gSandbox3.world;
  for (int i = 0; i < steps; ++i) {
    Status s = world.step(static_cast<float>(dt), world.def().substeps);
    if (!s) return errorAnswer(s.message());
    gSandbox3.time += static_cast<double>(static_cast<float>(dt));
  }
  return answer({{"time", gSandbox3.time},
                 {"steps", world.stepCount()},
                 {"begin", world.events().begin.size()},
                 {"end", world.events().end.size()}});
}

/// The 3D sandbox for drawing: every live body's pose (position of its origin, rotation
/// [x, y, z, w]), velocity, type and awake flag, the world's counts, and, when
/// `withContacts` is not 0, the touching contacts' points and normals.
EMSCRIPTEN_KEEPALIVE const char* qk3_world_state(int withContacts) {
  if (!gSandbox3.world) return errorAnswer("no 3D world: call qk3_world_load first");
  const World3& world = *gSandbox3.world;
  json bodies = json::array();
  for (std::size_t i = 0; i < gSandbox3.bodies.size(); ++i) {
    const BodyId3 b = gSandbox3.bodies[i];
    if (!world.isValid(b)) continue;
    const Quat q = world.rotation(b);
    bodies.push_back({{"index", i},
                      {"name", gSandbox3.names[i]},
                      {"type", toString(world.bodyType(b))},
                      {"pos", vec3Json(world.position(b))},
                      {"quat", {q.x, q.y, q.z, q.w}},
                      {"vel", vec3Json(world.linearVelocity(b))},
                      {"awake", world.isAwake(b)}});
  }
  json contacts = json::array();
  if (withContacts != 0) {
    for (const ContactView3& c : world.touchingContacts()) {
      for (const Manifold3& m : c.manifolds)
        contacts.push_back(toJson(m));
    }
  }
  return answer({{"bodies", bodies},
                 {"bodyCount", world.bodyCount()},
                 {"shapeCount", world.shapeCount()},
                 {"awakeBodies", world.awakeBodyCount()},
                 {"contactCount", world.contactCount()},
                 {"touching", world.touchingContactCount()},
                 {"contacts", contacts},
                 {"steps", world.stepCount()},
                 {"time", gSandbox3.time},
                 {"substeps", world.def().substeps},
                 {"shapesVersion", gSandbox3.shapesVersion}});
}

/// Every live shape of the 3D sandbox, for building the page's meshes: {"version", "shapes":
/// [{"index", "body", outline (body frame: outline3Of's, or a mesh's "points" and
/// triangle "faces")}]}.
EMSCRIPTEN_KEEPALIVE const char* qk3_world_shapes() {
  if (!gSandbox3.world) return errorAnswer("no 3D world: call qk3_world_load first");
  const World3& world = *gSandbox3.world;
  json shapes = json::array();
  for (std::size_t i = 0; i < gSandbox3.shapes.size(); ++i) {
    const Shape3Record& r = gSandbox3.shapes[i];
    if (!world.isValid(r.id)) continue;
    json s = r.outline;
    s["index"] = i;
    s["body"] = r.body;
    shapes.push_back(std::move(s));
  }
  return answer({{"version", gSandbox3.shapesVersion}, {"shapes", shapes}});
}

/// The first shape the ray from (ox, oy, oz) along (tx, ty, tz) enters (World3's
/// rayCastClosest; the page casts through the pointer to drop a body there): {"hit": null}
/// or {"hit": {"point", "normal", "fraction", "body"}}, or {"error"} for non-finite input.
EMSCRIPTEN_KEEPALIVE const char* qk3_world_raycast(double ox, double oy, double oz, double tx,
                                                   double ty, double tz) {
  if (!gSandbox3.world) return errorAnswer("no 3D world: call qk3_world_load first");
  if (!finite3(ox, oy, oz)) return errorAnswer("ray origin: must be finite");
  if (!finite3(tx, ty, tz)) return errorAnswer("ray translation: must be finite");
  const World3& world = *gSandbox3.world;
  const Vec3 origin{static_cast<float>(ox), static_cast<float>(oy), static_cast<float>(oz)};
  const Vec3 translation{static_cast<float>(tx), static_cast<float>(ty), static_cast<float>(tz)};
  std::optional<RayHitResult3> hit = world.rayCastClosest(origin, translation);
  if (!hit) return answer({{"hit", nullptr}});
  int body = -1;
  for (std::size_t i = 0; i < gSandbox3.bodies.size(); ++i) {
    if (gSandbox3.bodies[i] == hit->body) body = static_cast<int>(i);
  }
  return answer({{"hit",
                  {{"point", vec3Json(hit->point)},
                   {"normal", vec3Json(hit->normal)},
                   {"fraction", hit->fraction},
                   {"body", body}}}});
}

/// Removes every dynamic body whose origin is below `y` (bodies that fell off the ground).
/// Returns how many it removed.
EMSCRIPTEN_KEEPALIVE int qk3_world_cull(double y) {
  if (!gSandbox3.world || !std::isfinite(y)) return 0;
  World3& world = *gSandbox3.world;
  int removed = 0;
  for (BodyId3 b : gSandbox3.bodies) {
    if (world.isValid(b) && world.bodyType(b) == BodyType::dynamicBody && world.position(b).y < y) {
      removed += world.destroyBody(b) ? 1 : 0;
    }
  }
  if (removed > 0) ++gSandbox3.shapesVersion;
  return removed;
}

}  // extern "C"
