#include "quack/io/scene.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <nlohmann/json.hpp>

#include "quack/geometry/bounds.hpp"
#include "quack/geometry/mass.hpp"
#include "quack/io/shape_json.hpp"
#include "quack/math/trig.hpp"
#include "scene_fields.hpp"

namespace quack {
namespace {

using nlohmann::json;

// How often a long loop reports progress (and looks whether it should stop), in bodies.
constexpr std::size_t kProgressEvery = 4096;

// The scene being parsed: its file name and categories, for messages and filters.
struct Parser {
  std::string file;
  std::vector<std::string> categories;
  const SceneProgress* progress = nullptr;
  bool worldSleep = true;  // world.sleep, to refuse a body that asks to start asleep without it

  // False when the caller asked to stop.
  bool tick(std::size_t done) const { return !progress || !*progress || (*progress)(done, 0); }

  Error error(const std::string& path, const std::string& what) const {
    return fail(file + ": " + (path.empty() ? "" : path + ": ") + what);
  }
  Error relabel(const Error& e) const { return fail(file + ": " + e.message); }
};

// The field readers both scene parsers share (scene_fields.hpp), by their short names here.
Status checkKeys(const json& j, const std::string& path, std::initializer_list<const char*> keys) {
  return detail::checkSceneKeys(j, path, keys);
}
std::string join(const std::string& path, const char* key) {
  return detail::joinPath(path, key);
}
std::string show(double x) {
  return detail::showNumber(x);
}
std::string show(Vec2 v) {
  return "[" + show(static_cast<double>(v.x)) + ", " + show(static_cast<double>(v.y)) + "]";
}
using detail::atMost;
using detail::coordinateLimitText;
Result<float> number(const json& j, const char* key, const std::string& path, float fallback) {
  return detail::readNumber(j, key, path, fallback);
}
Result<float> nonNegative(const json& j, const char* key, const std::string& path, float fallback) {
  return detail::readNonNegative(j, key, path, fallback);
}
Result<int> integer(const json& j, const char* key, const std::string& path, int fallback, int lo,
                    int hi) {
  return detail::readInteger(j, key, path, fallback, lo, hi);
}
Result<bool> boolean(const json& j, const char* key, const std::string& path, bool fallback) {
  return detail::readBoolean(j, key, path, fallback);
}

Result<Vec2> vec(const json& j, const char* key, const std::string& path, Vec2 fallback) {
  if (!j.contains(key)) return fallback;
  return parseVec2(j.at(key), join(path, key));
}

Result<Filter> parseFilter(const Parser& p, const json& j, const std::string& path) {
  return detail::readFilter(p.categories, j, path);
}

// Material keys of a shape (or a generator), over the defaults of ShapeDef.
Result<ShapeDef> parseMaterial(const Parser& p, const json& j, const std::string& path) {
  ShapeDef def;
  Result<float> density = nonNegative(j, "density", path, def.density);
  if (!density) return density.error();
  if (Status s = atMost(*density, kSceneMaxDensity, join(path, "density"), " kg/m^2"); !s)
    return fail(s.message());
  Result<float> friction = nonNegative(j, "friction", path, def.friction);
  if (!friction) return friction.error();
  if (Status s = atMost(*friction, kSceneMaxFriction, join(path, "friction"), ""); !s)
    return fail(s.message());
  Result<float> restitution = nonNegative(j, "restitution", path, def.restitution);
  if (!restitution) return restitution.error();
  if (Status s = atMost(*restitution, kSceneMaxRestitution, join(path, "restitution"),
                        " (above 1 a bounce gains energy)");
      !s) {
    return fail(s.message());
  }
  Result<bool> sensor = boolean(j, "sensor", path, false);
  if (!sensor) return sensor.error();
  def.density = *density;
  def.friction = *friction;
  def.restitution = *restitution;
  def.sensor = *sensor;
  def.filter = {~std::uint64_t{0}, ~std::uint64_t{0}, 0};
  if (j.contains("filter")) {
    Result<Filter> f = parseFilter(p, j.at("filter"), join(path, "filter"));
    if (!f) return f.error();
    def.filter = *f;
  }
  return def;
}

// One shape of the file; a concave one becomes its convex pieces, with one material.
Result<std::vector<SceneShape>> parseSceneShape(const Parser& p, const json& j,
                                                const std::string& path) {
  Result<std::vector<ShapeGeometry>> pieces =
      parseShapePieces(j, path, {"density", "friction", "restitution", "sensor", "filter"});
  if (!pieces) return pieces.error();
  Result<ShapeDef> def = parseMaterial(p, j, path);
  if (!def) return def.error();
  std::vector<SceneShape> out;
  for (ShapeGeometry& g : *pieces)
    out.push_back({std::move(g), *def, path});
  return out;
}

// {"type": "chain", "points": [[x, y], ...], "loop": false, material...}: one-sided segments
// (World::createChain), at least 2 points (3 for a loop), consecutive points apart.
Result<SceneChain> parseChain(const Parser& p, const json& j, const std::string& path) {
  if (Status s = checkKeys(
          j, path,
          {"type", "points", "loop", "density", "friction", "restitution", "sensor", "filter"});
      !s) {
    return fail(s.message());
  }
  SceneChain chain;
  chain.path = path;
  if (!j.contains("points")) return fail(path + ".points: missing");
  const json& pts = j.at("points");
  if (!pts.is_array()) return fail(path + ".points: must be an array of [x, y]");
  if (pts.size() > 100000) return fail(path + ".points: too many points");
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Result<Vec2> v = parseVec2(pts[i], path + ".points[" + std::to_string(i) + "]");
    if (!v) return v.error();
    chain.points.push_back(*v);
  }
  Result<bool> loop = boolean(j, "loop", path, false);
  if (!loop) return loop.error();
  chain.loop = *loop;
  std::size_t least = chain.loop ? 3 : 2;
  if (chain.points.size() < least)
    return fail(path + ".points: needs at least " + std::to_string(least) + " points");
  std::size_t n = chain.points.size();
  for (std::size_t i = 0; i + (chain.loop ? 0 : 1) < n; ++i) {
    if (distanceSquared(chain.points[i], chain.points[(i + 1) % n]) <=
        kFlushEdgeTolerance * kFlushEdgeTolerance) {
      return fail(path + ".points[" + std::to_string((i + 1) % n) +
                  "]: coincides with the point before it");
    }
  }
  Result<ShapeDef> def = parseMaterial(p, j, path);
  if (!def) return def.error();
  chain.def = *def;
  return chain;
}

// Where a shape of a body is, for messages: its JSON path, and for a generated body the
// body's name too ("generate[0]: body \"rain0_7\"").
std::string shapeWhere(const SceneBody& b, const std::string& shapePath) {
  if (b.path.rfind("generate", 0) == 0) return shapePath + ": body \"" + b.name + "\"";
  return shapePath;
}

// What the world would refuse or overflow on, named in the scene's terms: every shape and
// chain point inside the coordinate limit at the body's pose, and every mass and rotational
// inertia (about the body origin, in double) at most kSceneMaxMass, so that a body's mass
// stays finite as a float whatever it is made of.
Status checkBodyShapes(const SceneBody& b) {
  const Transform xf = makeTransform(b.def.position, b.def.angle);
  double mass = 0.0, inertia = 0.0;
  for (const SceneShape& shape : b.shapes) {
    Aabb box = computeAabb(shape.geometry, xf);
    if (!withinCoordinateLimit(box.lower) || !withinCoordinateLimit(box.upper)) {
      return fail(shapeWhere(b, shape.path) + ": reaches " + show(box.lower) + ".." +
                  show(box.upper) + ", beyond " + coordinateLimitText());
    }
    MassProperties m = computeMass(shape.geometry, shape.def.density);
    double c2 = static_cast<double>(m.centroid.x) * static_cast<double>(m.centroid.x) +
                static_cast<double>(m.centroid.y) * static_cast<double>(m.centroid.y);
    double shapeInertia = static_cast<double>(m.inertia) + static_cast<double>(m.mass) * c2;
    if (!std::isfinite(m.mass) || !std::isfinite(m.inertia) ||
        (b.def.type == BodyType::dynamicBody &&
         (static_cast<double>(m.mass) > kSceneMaxMass || shapeInertia > kSceneMaxInertia))) {
      return fail(shapeWhere(b, shape.path + ".density") + ": the shape's mass (" +
                  show(static_cast<double>(m.mass)) + " kg) or rotational inertia (" +
                  show(shapeInertia) + " kg m^2) is above " + show(kSceneMaxMass) + " kg (" +
                  show(kSceneMaxInertia) + " kg m^2); use a lower density or a smaller shape");
    }
    mass += static_cast<double>(m.mass);
    inertia += shapeInertia;
  }
  if (b.def.type == BodyType::dynamicBody && (mass > kSceneMaxMass || inertia > kSceneMaxInertia)) {
    return fail(b.path + ".shapes: the body's mass (" + show(mass) +
                " kg) or rotational inertia (" + show(inertia) + " kg m^2) is above " +
                show(kSceneMaxMass) + " kg (" + show(kSceneMaxInertia) + " kg m^2)");
  }
  for (const SceneChain& chain : b.chains) {
    for (std::size_t k = 0; k < chain.points.size(); ++k) {
      Vec2 w = transformPoint(xf, chain.points[k]);
      if (!withinCoordinateLimit(w)) {
        return fail(chain.path + ".points[" + std::to_string(k) + "]: at " + show(w) +
                    " in the world, beyond " + coordinateLimitText());
      }
    }
  }
  return {};
}

Result<SceneBody> parseBody(const Parser& p, const json& j, const std::string& path,
                            std::size_t index) {
  if (!j.is_object()) return fail(path + ": must be an object");
  if (Status s = checkKeys(
          j, path,
          {"name", "type", "pos", "angle", "vel", "angvel", "bullet", "awake", "sleep", "shapes"});
      !s) {
    return fail(s.message());
  }
  SceneBody body;
  body.path = path;
  Result<std::string> name = detail::readBodyName(j, path, index);
  if (!name) return name.error();
  body.name = std::move(*name);
  Result<BodyType> type = detail::readBodyType(j, path, BodyType::dynamicBody);
  if (!type) return type.error();
  Result<Vec2> pos = vec(j, "pos", path, {});
  if (!pos) return pos.error();
  if (!withinCoordinateLimit(*pos))
    return fail(path + ".pos: " + show(*pos) + " is beyond " + coordinateLimitText());
  Result<float> angle = number(j, "angle", path, 0.0f);
  if (!angle) return angle.error();
  if (Status s = atMost(std::fabs(*angle), kSceneMaxAngle, path + ".angle", " rad in size"); !s)
    return fail(s.message());
  Result<Vec2> vel = vec(j, "vel", path, {});
  if (!vel) return vel.error();
  if (Status s = atMost(
          static_cast<float>(std::hypot(static_cast<double>(vel->x), static_cast<double>(vel->y))),
          kSceneMaxSpeed, path + ".vel", " m/s in speed");
      !s) {
    return fail(s.message());
  }
  Result<float> angvel = number(j, "angvel", path, 0.0f);
  if (!angvel) return angvel.error();
  if (Status s =
          atMost(std::fabs(*angvel), kSceneMaxAngularSpeed, path + ".angvel", " rad/s in size");
      !s) {
    return fail(s.message());
  }
  Result<bool> bullet = boolean(j, "bullet", path, false);
  if (!bullet) return bullet.error();
  Result<bool> awake = boolean(j, "awake", path, true);
  if (!awake) return awake.error();
  Result<bool> sleep = boolean(j, "sleep", path, true);
  if (!sleep) return sleep.error();
  // The world would start such a body awake anyway (World::createBody); say so instead of
  // silently ignoring what the file asked for. A static body is never awake: "awake" is
  // ignored there.
  if (!*awake && *type != BodyType::staticBody && !*sleep)
    return fail(path +
                ".awake: false needs \"sleep\": true (a body that may not sleep starts awake)");
  if (!*awake && *type != BodyType::staticBody && !p.worldSleep)
    return fail(path + ".awake: false needs sleeping on (world.sleep is false)");
  body.def.type = *type;
  body.def.position = *pos;
  body.def.angle = *angle;
  body.def.linearVelocity = *vel;
  body.def.angularVelocity = *angvel;
  body.def.bullet = *bullet;
  body.def.isAwake = *awake;
  body.def.enableSleep = *sleep;
  if (j.contains("shapes")) {
    const json& shapes = j.at("shapes");
    if (!shapes.is_array()) return fail(path + ".shapes: must be an array");
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const std::string at = path + ".shapes[" + std::to_string(i) + "]";
      if (shapes[i].is_object() && shapes[i].contains("type") && shapes[i].at("type") == "chain") {
        Result<SceneChain> c = parseChain(p, shapes[i], at);
        if (!c) return c.error();
        if (body.def.type != BodyType::staticBody)
          return fail(at + ".type: a chain needs a static body (chains are terrain)");
        body.chains.push_back(std::move(*c));
        continue;
      }
      Result<std::vector<SceneShape>> s =
          parseSceneShape(p, shapes[i], path + ".shapes[" + std::to_string(i) + "]");
      if (!s) return s.error();
      body.shapes.insert(body.shapes.end(), s->begin(), s->end());
    }
  }
  if (Status s = checkBodyShapes(body); !s) return fail(s.message());
  return body;
}

// ---- generators ------------------------------------------------------------------------

SceneBody makeBody(std::string name, const std::string& path, BodyType type, Vec2 pos, float angle,
                   ShapeGeometry g, const ShapeDef& def) {
  SceneBody b;
  b.name = std::move(name);
  b.path = path;
  b.def.type = type;
  b.def.position = pos;
  b.def.angle = angle;
  b.shapes.push_back({std::move(g), def, path});
  return b;
}

// A generator's size key: a number in kSceneMinGeneratedSize..kSceneMaxGeneratedSize
// metres, checked before anything is made so that every shape the generator makes is one
// the geometry accepts.
Result<float> generatedSize(const json& g, const char* key, const std::string& path,
                            float fallback) {
  Result<float> f = number(g, key, path, fallback);
  if (!f) return f;
  if (!(*f >= kSceneMinGeneratedSize && *f <= kSceneMaxGeneratedSize)) {
    return fail(join(path, key) + ": must be in " +
                show(static_cast<double>(kSceneMinGeneratedSize)) + ".." +
                show(static_cast<double>(kSceneMaxGeneratedSize)) + " m, got " +
                show(static_cast<double>(*f)));
  }
  return f;
}

// The farthest a generator reaches from the origin along either axis, in double, checked
// against the coordinate limit; `field` is the key to blame.
Status checkReach(double reach, const std::string& field, const std::string& what) {
  if (!(reach <= static_cast<double>(kMaxCoordinate))) {
    return fail(field + ": " + what + " reaches " + show(reach) + " m from the origin, beyond " +
                coordinateLimitText());
  }
  return {};
}

double absd(float x) {
  return std::fabs(static_cast<double>(x));
}

// One random shape of size about `s` for rain and fields. A shape the geometry refuses is
// an error (sizes are checked up front, so this is a second line of defence).
Result<ShapeGeometry> randomShape(std::mt19937& rng, const std::vector<std::string>& kinds,
                                  float lo, float hi) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const std::string& kind = kinds[static_cast<std::size_t>(rng() % kinds.size())];
  float s = lo + (hi - lo) * u(rng);
  auto wrap = [&](auto made) -> Result<ShapeGeometry> {
    if (!made)
      return fail("cannot make a " + kind + " of size " + show(static_cast<double>(s)) +
                  " m: " + made.error().message);
    return ShapeGeometry{*made};
  };
  if (kind == "circle") return wrap(makeCircle({}, s));
  if (kind == "box") return wrap(makeBox(s, s * (0.5f + 0.5f * u(rng))));
  if (kind == "capsule") return wrap(makeCapsule({-s, 0}, {s, 0}, 0.5f * s));
  // A random convex polygon: 3 to 8 points on a circle.
  int n = 3 + static_cast<int>(rng() % 6);
  std::vector<Vec2> pts;
  for (int i = 0; i < n; ++i) {
    float a = 2.0f * kPi * (static_cast<float>(i) + 0.6f * u(rng)) / static_cast<float>(n);
    pts.push_back(s * Vec2{portableCos(a), portableSin(a)});
  }
  return wrap(makePolygon(pts));
}

// Appends a generated body after checking it as a listed body is checked; reports
// progress and stops when asked.
Status addGenerated(const Parser& p, SceneBody body, std::vector<SceneBody>& out) {
  if (out.size() >= kSceneMaxBodies) {
    return fail(body.path + ": more than " + std::to_string(kSceneMaxBodies) +
                " bodies in the scene");
  }
  if (Status s = checkBodyShapes(body); !s) return s;
  out.push_back(std::move(body));
  if (out.size() % kProgressEvery == 0 && !p.tick(out.size())) return fail("interrupted");
  return {};
}

Status generate(const Parser& p, const json& g, const std::string& path, std::size_t index,
                std::vector<SceneBody>& out) {
  if (!g.is_object()) return fail(path + ": must be an object with a \"kind\"");
  if (!g.contains("kind") || !g.at("kind").is_string())
    return fail(path + ".kind: missing (pyramid, rain, field, tiles)");
  const std::string kind = g.at("kind").get<std::string>();
  const std::string prefix = kind + std::to_string(index) + "_";
  auto material = [&]() { return parseMaterial(p, g, path); };
  // Every key is checked before the first body is made.
  if (kind == "pyramid") {
    if (Status s = checkKeys(
            g, path,
            {"kind", "rows", "half", "pos", "density", "friction", "restitution", "filter"});
        !s) {
      return fail(s.message());
    }
    Result<int> rows = integer(g, "rows", path, 10, 1, 1000);
    if (!rows) return rows.error();
    Result<float> half = generatedSize(g, "half", path, 0.5f);
    if (!half) return half.error();
    Result<Vec2> pos = vec(g, "pos", path, {0.0f, *half});
    if (!pos) return pos.error();
    Result<ShapeDef> def = material();
    if (!def) return def.error();
    const double h = static_cast<double>(*half), r = static_cast<double>(*rows);
    if (Status s = checkReach(std::max(absd(pos->x) + r * h, absd(pos->y) + 2.0 * r * h),
                              path + ".pos", "the pyramid");
        !s) {
      return s;
    }
    Result<Polygon> box = makeBox(*half, *half);
    if (!box) return fail(path + ".half: " + box.error().message);
    int n = 0;
    for (int row = 0; row < *rows; ++row) {
      for (int i = 0; i < *rows - row; ++i) {
        float x = pos->x + (static_cast<float>(i) - 0.5f * static_cast<float>(*rows - row - 1)) *
                               2.0f * *half;
        float y = pos->y + static_cast<float>(row) * 2.0f * *half;
        if (Status s = addGenerated(p,
                                    makeBody(prefix + std::to_string(n++), path,
                                             BodyType::dynamicBody, {x, y}, 0.0f, *box, *def),
                                    out);
            !s) {
          return s;
        }
      }
    }
    return {};
  }
  if (kind == "rain" || kind == "field") {
    bool rain = kind == "rain";
    if (Status s = checkKeys(g, path,
                             {"kind", "count", "pos", "size", "seed", "shapes", "min", "max",
                              "type", "density", "friction", "restitution", "filter"});
        !s) {
      return fail(s.message());
    }
    Result<int> count = integer(g, "count", path, 100, 1, static_cast<int>(kSceneMaxBodies));
    if (!count) return count.error();
    Result<Vec2> pos = vec(g, "pos", path, rain ? Vec2{0, 15} : Vec2{0, 0});
    if (!pos) return pos.error();
    Result<Vec2> size = vec(g, "size", path, rain ? Vec2{10, 5} : Vec2{20, 20});
    if (!size) return size.error();
    if (size->x < 0.0f || size->y < 0.0f) return fail(path + ".size: must be >= 0");
    Result<int> seed = integer(g, "seed", path, 1, 0, 2147483647);
    if (!seed) return seed.error();
    Result<float> lo = generatedSize(g, "min", path, 0.25f);
    if (!lo) return lo.error();
    Result<float> hi = generatedSize(g, "max", path, std::max(0.5f, *lo));
    if (!hi) return hi.error();
    if (*hi < *lo) {
      return fail(path + ".max: must be >= min (" + show(static_cast<double>(*lo)) + "), got " +
                  show(static_cast<double>(*hi)));
    }
    // A shape of size s reaches at most 1.5 s from its centre (a capsule).
    const double margin = 1.5 * static_cast<double>(*hi);
    if (Status s = checkReach(
            std::max(absd(pos->x) + absd(size->x), absd(pos->y) + absd(size->y)) + margin,
            path + ".size", "the " + kind);
        !s) {
      return s;
    }
    std::vector<std::string> kinds = {"circle", "box", "capsule", "polygon"};
    if (g.contains("shapes")) {
      const json& k = g.at("shapes");
      if (!k.is_array() || k.empty())
        return fail(path + ".shapes: must be a non-empty array of shape kinds");
      kinds.clear();
      for (std::size_t i = 0; i < k.size(); ++i) {
        if (k[i] != "circle" && k[i] != "box" && k[i] != "capsule" && k[i] != "polygon") {
          return fail(path + ".shapes[" + std::to_string(i) +
                      "]: must be circle, box, capsule or polygon");
        }
        kinds.push_back(k[i].get<std::string>());
      }
    }
    Result<BodyType> type =
        detail::readBodyType(g, path, rain ? BodyType::dynamicBody : BodyType::staticBody);
    if (!type) return type.error();
    Result<ShapeDef> def = material();
    if (!def) return def.error();
    std::mt19937 rng(static_cast<std::uint32_t>(*seed));
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < *count; ++i) {
      Vec2 at{pos->x + size->x * u(rng), pos->y + size->y * u(rng)};
      float angle = kPi * u(rng);
      Result<ShapeGeometry> shape = randomShape(rng, kinds, *lo, *hi);
      if (!shape) return fail(path + ".min: " + shape.error().message);
      if (Status s = addGenerated(
              p, makeBody(prefix + std::to_string(i), path, *type, at, angle, *shape, *def), out);
          !s) {
        return s;
      }
    }
    return {};
  }
  if (kind == "tiles") {
    if (Status s = checkKeys(
            g, path,
            {"kind", "count", "half", "pos", "density", "friction", "restitution", "filter"});
        !s) {
      return fail(s.message());
    }
    Result<int> count = integer(g, "count", path, 20, 1, static_cast<int>(kSceneMaxBodies));
    if (!count) return count.error();
    Result<Vec2> half = vec(g, "half", path, {0.5f, 0.5f});
    if (!half) return half.error();
    for (float h : {half->x, half->y}) {
      if (!(h >= kSceneMinGeneratedSize && h <= kSceneMaxGeneratedSize)) {
        return fail(path + ".half: both must be in " +
                    show(static_cast<double>(kSceneMinGeneratedSize)) + ".." +
                    show(static_cast<double>(kSceneMaxGeneratedSize)) + " m, got " + show(*half));
      }
    }
    Result<Vec2> pos = vec(g, "pos", path, {0.0f, -half->y});
    if (!pos) return pos.error();
    Result<ShapeDef> def = material();
    if (!def) return def.error();
    if (Status s = checkReach(
            std::max(absd(pos->x) + static_cast<double>(*count) * static_cast<double>(half->x),
                     absd(pos->y) + static_cast<double>(half->y)),
            path + ".count", "the floor of tiles");
        !s) {
      return s;
    }
    // Separate static bodies laid flush: the floor a box slides over in the ghost-collision
    // tests.
    Result<Polygon> tile = makeBox(half->x, half->y);
    if (!tile) return fail(path + ".half: " + tile.error().message);
    for (int i = 0; i < *count; ++i) {
      Vec2 at{pos->x + (2.0f * static_cast<float>(i) - static_cast<float>(*count - 1)) * half->x,
              pos->y};
      if (Status s = addGenerated(p,
                                  makeBody(prefix + std::to_string(i), path, BodyType::staticBody,
                                           at, 0.0f, *tile, *def),
                                  out);
          !s) {
        return s;
      }
    }
    return {};
  }
  return fail(path + ".kind: unknown generator \"" + kind +
              "\" (expected pyramid, rain, field, tiles)");
}

// A joint: {"type", "a", "b", ...} with the keys its type takes (docs/scenes.md, "Joints").
// A limit is on when "lower" and "upper" are given, a motor when a most torque or force
// is, a spring when "hertz" is; a distance joint with "minLength" or "maxLength" and no
// "hertz" is a rope (free within its limits).
Result<SceneJoint> parseJoint(const json& j, const std::string& path,
                              const std::vector<SceneBody>& bodies) {
  if (!j.is_object()) return fail(path + ": must be an object");
  if (!j.contains("type") || !j.at("type").is_string())
    return fail(path +
                ".type: must be one of revolute, prismatic, distance, weld, wheel, "
                "motor, mouse");
  const std::string type = j.at("type").get<std::string>();
  SceneJoint out;
  out.path = path;
  JointDef& d = out.def;
  // Every type takes "type", "a" (not a mouse joint), "b", "collideConnected", "breakForce"
  // and "breakTorque"; then its own keys.
  std::vector<const char*> keys = {"type", "b", "collideConnected", "breakForce", "breakTorque"};
  if (type == "revolute") {
    d.type = JointType::revolute;
    keys.insert(keys.end(), {"a", "anchor", "lower", "upper", "motorSpeed", "maxMotorTorque",
                             "hertz", "dampingRatio"});
  } else if (type == "prismatic") {
    d.type = JointType::prismatic;
    keys.insert(keys.end(), {"a", "anchor", "axis", "lower", "upper", "motorSpeed", "maxMotorForce",
                             "hertz", "dampingRatio"});
  } else if (type == "wheel") {
    d.type = JointType::wheel;
    keys.insert(keys.end(), {"a", "anchor", "axis", "lower", "upper", "motorSpeed",
                             "maxMotorTorque", "hertz", "dampingRatio"});
  } else if (type == "distance") {
    d.type = JointType::distance;
    keys.insert(keys.end(),
                {"a", "anchors", "length", "minLength", "maxLength", "hertz", "dampingRatio"});
  } else if (type == "weld") {
    d.type = JointType::weld;
    keys.insert(keys.end(), {"a", "anchor", "hertz", "dampingRatio", "linearHertz", "angularHertz",
                             "linearDampingRatio", "angularDampingRatio"});
  } else if (type == "motor") {
    d.type = JointType::motor;
    keys.insert(keys.end(), {"a", "linearOffset", "angularOffset", "maxForce", "maxTorque",
                             "correctionFactor"});
  } else if (type == "mouse") {
    d.type = JointType::mouse;
    keys.insert(keys.end(), {"anchor", "target", "maxForce", "hertz", "dampingRatio"});
  } else {
    return fail(path + ".type: \"" + type +
                "\" is not a joint type (revolute, prismatic, distance, weld, wheel, motor, "
                "mouse)");
  }
  for (const auto& item : j.items()) {
    bool known = false;
    for (const char* k : keys)
      known |= item.key() == k;
    if (!known) return fail(path + "." + item.key() + ": unknown key for a " + type + " joint");
  }
  auto body = [&](const char* key) -> Result<std::size_t> {
    if (!j.contains(key) || !j.at(key).is_string())
      return fail(join(path, key) + ": must name a body (its \"name\")");
    const std::string name = j.at(key).get<std::string>();
    std::size_t found = kNoSceneBody;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (bodies[i].name != name) continue;
      if (found != kNoSceneBody)
        return fail(join(path, key) + ": \"" + name + "\" names more than one body");
      found = i;
    }
    if (found == kNoSceneBody) return fail(join(path, key) + ": no body is named \"" + name + "\"");
    return found;
  };
  if (d.type != JointType::mouse) {
    Result<std::size_t> a = body("a");
    if (!a) return fail(a.error().message);
    out.a = *a;
  }
  Result<std::size_t> b = body("b");
  if (!b) return fail(b.error().message);
  out.b = *b;
  if (out.a == out.b) return fail(path + ": \"a\" and \"b\" name the same body");
  // Numbers: each checked finite (and >= 0 where it must be), naming its key.
  auto num = [&](const char* key, float fallback, bool nonNeg) -> Result<float> {
    return nonNeg ? nonNegative(j, key, path, fallback) : number(j, key, path, fallback);
  };
  auto point = [&](const char* key, Vec2 fallback) -> Result<Vec2> {
    Result<Vec2> v = vec(j, key, path, fallback);
    if (v && !withinCoordinateLimit(*v))
      return fail(join(path, key) + ": must be within " + coordinateLimitText());
    return v;
  };
#define QUACK_READ(field, expr)               \
  do {                                        \
    auto r_ = (expr);                         \
    if (!r_) return fail(r_.error().message); \
    field = *r_;                              \
  } while (false)
  if (j.contains("anchor")) QUACK_READ(d.anchorA, point("anchor", {}));
  if (d.type == JointType::distance) {
    if (!j.contains("anchors") || !j.at("anchors").is_array() || j.at("anchors").size() != 2)
      return fail(path + ".anchors: must be two points, [[x, y], [x, y]] (on a, on b)");
    for (std::size_t k = 0; k < 2; ++k) {
      const std::string at = path + ".anchors[" + std::to_string(k) + "]";
      Result<Vec2> v = parseVec2(j.at("anchors")[k], at);
      if (!v) return fail(v.error().message);
      if (!withinCoordinateLimit(*v)) return fail(at + ": must be within " + coordinateLimitText());
      (k == 0 ? d.anchorA : d.anchorB) = *v;
    }
  } else if (d.type != JointType::motor && !j.contains("anchor")) {
    return fail(path + ".anchor: the joint's point [x, y] is required");
  }
  if (d.type == JointType::prismatic || d.type == JointType::wheel) {
    if (!j.contains("axis")) return fail(path + ".axis: the direction [x, y] is required");
    QUACK_READ(d.axis, vec(j, "axis", path, {}));
    if (length(d.axis) == 0.0f) return fail(path + ".axis: must not be zero");
  }
  const bool hasLower = j.contains("lower"), hasUpper = j.contains("upper");
  if (hasLower != hasUpper)
    return fail(join(path, hasLower ? "upper" : "lower") +
                ": a limit needs both \"lower\" and \"upper\"");
  if (hasLower) {
    d.enableLimit = true;
    QUACK_READ(d.lower, num("lower", 0.0f, false));
    QUACK_READ(d.upper, num("upper", 0.0f, false));
    if (d.lower > d.upper) return fail(path + ".lower: must be at most \"upper\"");
    if (d.type == JointType::revolute && (d.lower < -kPi || d.upper > kPi))
      return fail(path + ".lower: a revolute joint's limits must be within [-pi, pi]");
  }
  QUACK_READ(d.motorSpeed, num("motorSpeed", 0.0f, false));
  if (j.contains("maxMotorTorque")) {
    d.enableMotor = true;
    QUACK_READ(d.maxMotorTorque, num("maxMotorTorque", 0.0f, true));
  }
  if (j.contains("maxMotorForce")) {
    d.enableMotor = true;
    QUACK_READ(d.maxMotorForce, num("maxMotorForce", 0.0f, true));
  }
  if (j.contains("motorSpeed") && !d.enableMotor)
    return fail(path + ".motorSpeed: a motor needs its most torque or force (\"" +
                std::string(d.type == JointType::prismatic ? "maxMotorForce" : "maxMotorTorque") +
                "\")");
  if (d.type == JointType::mouse) {
    QUACK_READ(d.hertz, num("hertz", d.hertz, true));
    if (d.hertz == 0.0f) return fail(path + ".hertz: a mouse joint's spring must be > 0 Hz");
    QUACK_READ(d.dampingRatio, num("dampingRatio", d.dampingRatio, true));
    if (!j.contains("target"))
      return fail(path + ".target: the point [x, y] it pulls to is required");
    QUACK_READ(d.target, point("target", {}));
    QUACK_READ(d.maxForce, num("maxForce", 1000.0f, true));
  } else if (d.type == JointType::weld) {
    float hz = 0.0f, zeta = 1.0f;
    QUACK_READ(hz, num("hertz", 0.0f, true));
    QUACK_READ(zeta, num("dampingRatio", 1.0f, true));
    QUACK_READ(d.linearHertz, num("linearHertz", hz, true));
    QUACK_READ(d.angularHertz, num("angularHertz", hz, true));
    QUACK_READ(d.linearDampingRatio, num("linearDampingRatio", zeta, true));
    QUACK_READ(d.angularDampingRatio, num("angularDampingRatio", zeta, true));
  } else if (j.contains("hertz")) {
    d.enableSpring = true;
    QUACK_READ(d.hertz, num("hertz", 0.0f, true));
    QUACK_READ(d.dampingRatio, num("dampingRatio", 0.0f, true));
  } else if (j.contains("dampingRatio")) {
    return fail(path + ".dampingRatio: a spring needs its \"hertz\"");
  }
  if (d.type == JointType::distance) {
    // Without "length", the anchors' distance when the joint is made.
    d.length = -1.0f;
    if (j.contains("length")) QUACK_READ(d.length, num("length", 0.0f, true));
    const bool hasMin = j.contains("minLength"), hasMax = j.contains("maxLength");
    if (hasMin || hasMax) {
      d.enableLimit = true;
      QUACK_READ(d.minLength, num("minLength", 0.0f, true));
      QUACK_READ(d.maxLength, num("maxLength", 1.0e6f, true));
      if (d.minLength > d.maxLength)
        return fail(path + ".minLength: must be at most \"maxLength\"");
      // A rope: free within its limits unless a spring is asked for.
      if (!d.enableSpring) {
        d.enableSpring = true;
        d.hertz = 0.0f;
      }
    }
  }
  if (d.type == JointType::motor) {
    QUACK_READ(d.linearOffset, point("linearOffset", {}));
    QUACK_READ(d.angularOffset, num("angularOffset", 0.0f, false));
    QUACK_READ(d.maxForce, num("maxForce", 1000.0f, true));
    QUACK_READ(d.maxTorque, num("maxTorque", 1000.0f, true));
    QUACK_READ(d.correctionFactor, num("correctionFactor", 0.3f, true));
    if (d.correctionFactor > 1.0f) return fail(path + ".correctionFactor: must be in [0, 1]");
  }
  QUACK_READ(d.collideConnected, boolean(j, "collideConnected", path, false));
  QUACK_READ(d.breakForce, num("breakForce", 0.0f, true));
  if (!j.contains("breakForce")) d.breakForce = std::numeric_limits<float>::infinity();
  QUACK_READ(d.breakTorque, num("breakTorque", 0.0f, true));
  if (!j.contains("breakTorque")) d.breakTorque = std::numeric_limits<float>::infinity();
#undef QUACK_READ
  return out;
}

Result<WorldDef> parseWorld(const json& j, const std::string& path) {
  WorldDef def;
  if (!j.is_object()) return fail(path + ": must be an object");
  if (Status s = checkKeys(j, path, {"dim", "gravity", "dt", "substeps", "broadphase", "sleep"});
      !s)
    return fail(s.message());
  Result<Vec2> gravity = vec(j, "gravity", path, def.gravity);
  if (!gravity) return gravity.error();
  Result<float> dt = number(j, "dt", path, def.timeStep);
  if (!dt) return dt.error();
  if (*dt <= 0.0f) return fail(path + ".dt: must be > 0");
  if (Status s = atMost(*dt, kSceneMaxTimeStep, path + ".dt", " s"); !s) return fail(s.message());
  if (double g = std::hypot(static_cast<double>(gravity->x), static_cast<double>(gravity->y));
      g > static_cast<double>(kSceneMaxGravity)) {
    return fail(path + ".gravity: must be at most " + show(static_cast<double>(kSceneMaxGravity)) +
                " m/s^2 in size, got " + show(g));
  }
  Result<int> substeps = integer(j, "substeps", path, def.substeps, 1, kSceneMaxSubsteps);
  if (!substeps) return substeps.error();
  Result<bool> sleep = boolean(j, "sleep", path, def.enableSleep);
  if (!sleep) return sleep.error();
  def.enableSleep = *sleep;
  def.gravity = *gravity;
  def.timeStep = *dt;
  def.substeps = *substeps;
  if (j.contains("broadphase")) {
    if (!j.at("broadphase").is_string()) return fail(path + ".broadphase: must be a string");
    Result<BroadPhaseKind> kind = parseBroadPhaseKind(j.at("broadphase").get<std::string>());
    if (!kind) return fail(path + ".broadphase: " + kind.error().message);
    def.broadPhase = *kind;
  }
  return def;
}

}  // namespace

Result<SceneJoint> parseSceneJoint(const json& joint, const std::string& path,
                                   const std::vector<SceneBody>& bodies) {
  return parseJoint(joint, path, bodies);
}

Result<Scene> parseScene(std::string_view text, const std::string& fileName,
                         const SceneProgress& progress) {
  Result<json> root = detail::parseSceneJson(text, fileName);
  if (!root) return root.error();
  return detail::parseSceneRoot(*root, fileName, progress);
}

Result<Scene> detail::parseSceneRoot(const json& root, const std::string& fileName,
                                     const SceneProgress& progress) {
  Parser p{fileName, {}, &progress};
  Result<int> dim = sceneDimension(root, fileName);
  if (!dim) return dim.error();
  if (*dim == 3) {
    return p.error("world.dim",
                   "3 is a 3D scene (parseScene3 and parseAnyScene read it, quack run runs it)");
  }
  if (Status s = checkKeys(root, "", {"world", "categories", "bodies", "generate", "joints"}); !s) {
    return p.relabel(fail(s.message()));
  }
  Scene scene;
  scene.file = fileName;
  if (root.contains("world")) {
    Result<WorldDef> w = parseWorld(root.at("world"), "world");
    if (!w) return p.relabel(w.error());
    scene.world = *w;
    p.worldSleep = w->enableSleep;
  }
  if (root.contains("categories")) {
    Result<std::vector<std::string>> c =
        detail::readCategories(root.at("categories"), "categories");
    if (!c) return p.relabel(c.error());
    p.categories = std::move(*c);
    scene.categories = p.categories;
  }
  if (root.contains("bodies")) {
    const json& bodies = root.at("bodies");
    if (!bodies.is_array()) return p.error("bodies", "must be an array");
    if (bodies.size() > kSceneMaxBodies) {
      return p.error("bodies",
                     "more than " + std::to_string(kSceneMaxBodies) + " bodies in the scene");
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      Result<SceneBody> b = parseBody(p, bodies[i], "bodies[" + std::to_string(i) + "]", i);
      if (!b) return p.relabel(b.error());
      scene.bodies.push_back(std::move(b).value());
      if ((i + 1) % kProgressEvery == 0 && !p.tick(i + 1)) return p.error("", "interrupted");
    }
  }
  if (root.contains("generate")) {
    const json& gens = root.at("generate");
    if (!gens.is_array()) return p.error("generate", "must be an array");
    for (std::size_t i = 0; i < gens.size(); ++i) {
      if (Status s = generate(p, gens[i], "generate[" + std::to_string(i) + "]", i, scene.bodies);
          !s) {
        return p.relabel(fail(s.message()));
      }
    }
  }
  if (root.contains("joints")) {
    const json& joints = root.at("joints");
    if (!joints.is_array()) return p.error("joints", "must be an array");
    for (std::size_t i = 0; i < joints.size(); ++i) {
      Result<SceneJoint> jt =
          parseJoint(joints[i], "joints[" + std::to_string(i) + "]", scene.bodies);
      if (!jt) return p.relabel(jt.error());
      scene.joints.push_back(std::move(jt).value());
    }
  }
  return scene;
}

Result<Scene> loadScene(const std::string& path, const SceneProgress& progress) {
  Result<std::string> text = detail::readSceneText(path);
  if (!text) return text.error();
  return parseScene(*text, path, progress);
}

Result<SceneWorld> buildWorld(const Scene& scene, const SceneProgress& progress) {
  Result<World> made = World::create(scene.world);
  if (!made) return fail(scene.file + ": world: " + made.error().message);
  SceneWorld out{std::move(made).value(), {}, {}};
  out.bodies.reserve(scene.bodies.size());
  out.names.reserve(scene.bodies.size());
  // Messages name the scene field the world refused: "bodies[3].shapes[0]", or for a
  // generated body "generate[0]: body \"rain0_7\"".
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const SceneBody& b = scene.bodies[i];
    const std::string bodyPath = b.path.empty() ? "bodies[" + std::to_string(i) + "]" : b.path;
    auto where = [&](const std::string& path) {
      if (bodyPath.rfind("generate", 0) == 0) return path + ": body \"" + b.name + "\"";
      return path;
    };
    Result<BodyId> body = out.world.createBody(b.def);
    if (!body) return fail(scene.file + ": " + where(bodyPath) + ": " + body.error().message);
    for (std::size_t k = 0; k < b.shapes.size(); ++k) {
      Result<ShapeId> s = out.world.createShape(*body, b.shapes[k].def, b.shapes[k].geometry);
      if (!s) {
        const std::string shapePath = b.shapes[k].path.empty()
                                          ? bodyPath + ".shapes[" + std::to_string(k) + "]"
                                          : b.shapes[k].path;
        return fail(scene.file + ": " + where(shapePath) + ": " + s.error().message);
      }
    }
    for (std::size_t k = 0; k < b.chains.size(); ++k) {
      Result<std::vector<ShapeId>> c =
          out.world.createChain(*body, b.chains[k].def, b.chains[k].points, b.chains[k].loop);
      if (!c) {
        const std::string chainPath = b.chains[k].path.empty()
                                          ? bodyPath + ".chains[" + std::to_string(k) + "]"
                                          : b.chains[k].path;
        return fail(scene.file + ": " + where(chainPath) + ": " + c.error().message);
      }
    }
    // Adding a shape wakes its body (World::createShape), so a body the file lists asleep
    // is put back to sleep once it has its shapes: alone, as nothing touches it yet.
    if (!b.def.isAwake && b.def.type != BodyType::staticBody) {
      if (Status s = out.world.setAwake(*body, false); !s)
        return fail(scene.file + ": " + where(bodyPath) + ".awake: " + s.message());
    }
    out.bodies.push_back(*body);
    out.names.push_back(b.name);
    if ((i + 1) % kProgressEvery == 0 && progress && !progress(i + 1, scene.bodies.size()))
      return fail(scene.file + ": interrupted");
  }
  out.joints.reserve(scene.joints.size());
  for (const SceneJoint& sj : scene.joints) {
    JointDef def = sj.def;
    if (sj.a != kNoSceneBody) def.bodyA = out.bodies[sj.a];
    def.bodyB = out.bodies[sj.b];
    Result<JointId> j = out.world.createJoint(def);
    if (!j) return fail(scene.file + ": " + sj.path + ": " + j.error().message);
    out.joints.push_back(*j);
  }
  return out;
}

}  // namespace quack
