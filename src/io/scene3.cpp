#include "quack/io/scene3.hpp"

#include <cmath>
#include <utility>

#include <nlohmann/json.hpp>

#include "quack/collision/proxy3.hpp"
#include "quack/geometry/mass3.hpp"
#include "quack/io/shape_json.hpp"
#include "scene_fields.hpp"

namespace quack {
namespace {

using detail::atMost;
using detail::checkSceneKeys;
using detail::joinPath;
using detail::showNumber;
using nlohmann::json;

// How often a long loop reports progress (and looks whether it should stop), in bodies.
constexpr std::size_t kProgressEvery = 4096;

std::string show(Vec3 v) {
  return "[" + showNumber(static_cast<double>(v.x)) + ", " + showNumber(static_cast<double>(v.y)) +
         ", " + showNumber(static_cast<double>(v.z)) + "]";
}

double lengthD(Vec3 v) {
  const double x = static_cast<double>(v.x), y = static_cast<double>(v.y),
               z = static_cast<double>(v.z);
  return std::sqrt(x * x + y * y + z * z);
}

Result<Vec3> vec3(const json& j, const char* key, const std::string& path, Vec3 fallback) {
  if (!j.contains(key)) return fallback;
  return parseVec3(j.at(key), joinPath(path, key));
}

// A key the 2D format has and the 3D world does not (yet): said plainly rather than as an
// unknown key, so a scene converted from 2D learns what to change.
Status refuse2DKeys(const json& j, const std::string& path,
                    std::initializer_list<std::pair<const char*, const char*>> keys) {
  for (const auto& [key, why] : keys) {
    if (j.contains(key)) return fail(joinPath(path, key) + ": " + why);
  }
  return {};
}

// Material keys of a 3D shape over the defaults of ShapeDef3, with the 2D format's limits.
Result<ShapeDef3> parseMaterial3(const std::vector<std::string>& categories, const json& j,
                                 const std::string& path) {
  ShapeDef3 def;
  Result<float> density = detail::readNonNegative(j, "density", path, def.density);
  if (!density) return density.error();
  if (Status s = atMost(*density, kSceneMaxDensity, joinPath(path, "density"), " kg/m^3"); !s)
    return fail(s.message());
  Result<float> friction = detail::readNonNegative(j, "friction", path, def.friction);
  if (!friction) return friction.error();
  if (Status s = atMost(*friction, kSceneMaxFriction, joinPath(path, "friction"), ""); !s)
    return fail(s.message());
  Result<float> restitution = detail::readNonNegative(j, "restitution", path, def.restitution);
  if (!restitution) return restitution.error();
  if (Status s = atMost(*restitution, kSceneMaxRestitution, joinPath(path, "restitution"),
                        " (above 1 a bounce gains energy)");
      !s) {
    return fail(s.message());
  }
  Result<float> rolling =
      detail::readNonNegative(j, "rollingResistance", path, def.rollingResistance);
  if (!rolling) return rolling.error();
  if (Status s = atMost(*rolling, kSceneMaxFriction, joinPath(path, "rollingResistance"), ""); !s)
    return fail(s.message());
  def.density = *density;
  def.friction = *friction;
  def.restitution = *restitution;
  def.rollingResistance = *rolling;
  def.filter = {~std::uint64_t{0}, ~std::uint64_t{0}, 0};
  if (j.contains("filter")) {
    Result<Filter> f = detail::readFilter(categories, j.at("filter"), joinPath(path, "filter"));
    if (!f) return f.error();
    def.filter = *f;
  }
  return def;
}

constexpr std::initializer_list<const char*> kMaterialKeys3 = {"density", "friction", "restitution",
                                                               "rollingResistance", "filter"};

Result<SceneShape3> parseShape3At(const std::vector<std::string>& categories, const json& j,
                                  const std::string& path, BodyType bodyType) {
  if (!j.is_object() || !j.contains("type"))
    return fail(path + ": must be an object with a \"type\"");
  if (Status s = refuse2DKeys(j, path, {{"sensor", "the 3D world has no sensors yet"}}); !s)
    return fail(s.message());
  SceneShape3 shape;
  shape.path = path;
  if (isMesh3(j)) {
    if (bodyType != BodyType::staticBody) {
      return fail(path +
                  ".type: a mesh needs a static body (a triangle mesh has no volume; "
                  "World3 puts meshes on static bodies only)");
    }
    Result<Mesh3> mesh = parseMesh3(j, path, kMaterialKeys3);
    if (!mesh) return mesh.error();
    shape.geometry = std::move(*mesh);
  } else {
    if (shapeDimension(j) == 2) {
      return fail(path + ".type: a 2D shape in a 3D scene (3D shapes: sphere, capsule, box, " +
                  "hull, triangle, mesh; vectors have three components)");
    }
    Result<ShapeGeometry3> g = parseShape3(j, path, kMaterialKeys3);
    if (!g) return g.error();
    shape.geometry = std::move(*g);
  }
  Result<ShapeDef3> def = parseMaterial3(categories, j, path);
  if (!def) return def.error();
  shape.def = *def;
  return shape;
}

// The shape's box at the body's pose, world frame.
Aabb3 worldBox(const SceneGeometry3& geometry, const Transform3& xf) {
  Aabb3 box{};
  auto add = [&](int i, Vec3 p) {
    const Vec3 w = transformPoint(xf, p);
    box = i == 0 ? Aabb3{w, w} : Aabb3{minv(box.lower, w), maxv(box.upper, w)};
  };
  if (const Mesh3* mesh = std::get_if<Mesh3>(&geometry)) {
    const Aabb3 local = mesh->bounds();
    for (int i = 0; i < 8; ++i) {
      add(i, {(i & 1) ? local.upper.x : local.lower.x, (i & 2) ? local.upper.y : local.lower.y,
              (i & 4) ? local.upper.z : local.lower.z});
    }
    return box;
  }
  const ShapeProxy3 proxy = makeProxy(std::get<ShapeGeometry3>(geometry));
  for (int i = 0; i < proxy.count(); ++i)
    add(i, proxy.points()[i]);
  const Vec3 r{proxy.radius(), proxy.radius(), proxy.radius()};
  return {box.lower - r, box.upper + r};
}

bool withinLimit(Vec3 p, float limit) {
  return std::fabs(p.x) <= limit && std::fabs(p.y) <= limit && std::fabs(p.z) <= limit;
}

// What the world would refuse or overflow on, named in the scene's terms (as the 2D
// checkBodyShapes): every shape inside the coordinate limit at the body's pose, and a
// dynamic body's mass and rotational inertia (about its origin, in double) at most
// kSceneMaxMass and kSceneMaxInertia, so that they stay finite as floats.
Status checkBodyShapes3(const SceneBody3& b) {
  const Transform3 xf{b.def.position, b.def.rotation};
  const bool dynamic = b.def.type == BodyType::dynamicBody;
  double mass = 0.0, inertia = 0.0;
  for (const SceneShape3& shape : b.shapes) {
    const Aabb3 box = worldBox(shape.geometry, xf);
    if (!withinLimit(box.lower, kMaxCoordinate) || !withinLimit(box.upper, kMaxCoordinate)) {
      return fail(shape.path + ": reaches " + show(box.lower) + ".." + show(box.upper) +
                  ", beyond " + detail::coordinateLimitText());
    }
    const ShapeGeometry3* g = std::get_if<ShapeGeometry3>(&shape.geometry);
    if (g == nullptr) continue;  // a mesh: static, no mass
    const MassProperties3 m = computeMass(*g, shape.def.density);
    const double c2 = static_cast<double>(dot(m.centroid, m.centroid));
    // The largest moment about the body origin: the tensor's largest diagonal entry plus
    // the parallel-axis term's bound m |c|^2.
    const double moment =
        static_cast<double>(maxf(m.inertia.cx.x, maxf(m.inertia.cy.y, m.inertia.cz.z))) +
        static_cast<double>(m.mass) * c2;
    if (!std::isfinite(m.mass) || !std::isfinite(moment) ||
        (dynamic && (static_cast<double>(m.mass) > kSceneMaxMass || moment > kSceneMaxInertia))) {
      return fail(shape.path + ".density: the shape's mass (" +
                  showNumber(static_cast<double>(m.mass)) + " kg) or rotational inertia (" +
                  showNumber(moment) + " kg m^2) is above " + showNumber(kSceneMaxMass) + " kg (" +
                  showNumber(kSceneMaxInertia) +
                  " kg m^2); use a lower density or a smaller shape");
    }
    mass += static_cast<double>(m.mass);
    inertia += moment;
  }
  if (dynamic && (mass > kSceneMaxMass || inertia > kSceneMaxInertia)) {
    return fail(b.path + ".shapes: the body's mass (" + showNumber(mass) +
                " kg) or rotational inertia (" + showNumber(inertia) + " kg m^2) is above " +
                showNumber(kSceneMaxMass) + " kg (" + showNumber(kSceneMaxInertia) + " kg m^2)");
  }
  return {};
}

// The body's numbers and flags, over the defaults of BodyDef3.
Status parseBodyDef3(const json& j, const std::string& path, bool worldSleep, SceneBody3& body) {
  BodyDef3& def = body.def;
  Result<BodyType> type = detail::readBodyType(j, path, BodyType::dynamicBody);
  if (!type) return type.error();
  def.type = *type;
  Result<Vec3> pos = vec3(j, "pos", path, {});
  if (!pos) return pos.error();
  if (!withinLimit(*pos, kScene3MaxPosition)) {
    return fail(path + ".pos: " + show(*pos) + " is beyond +-" +
                showNumber(static_cast<double>(kScene3MaxPosition)) +
                " m (half the coordinate limit, the 3D world's limit for a body origin)");
  }
  def.position = *pos;
  if (j.contains("quat")) {
    Result<Quat> q = parseQuat(j.at("quat"), path + ".quat");
    if (!q) return q.error();
    def.rotation = *q;
  }
  Result<Vec3> vel = vec3(j, "vel", path, {});
  if (!vel) return vel.error();
  if (Status s =
          atMost(static_cast<float>(lengthD(*vel)), kSceneMaxSpeed, path + ".vel", " m/s in speed");
      !s) {
    return s;
  }
  def.linearVelocity = *vel;
  Result<Vec3> angvel = vec3(j, "angvel", path, {});
  if (!angvel) return angvel.error();
  if (Status s = atMost(static_cast<float>(lengthD(*angvel)), kSceneMaxAngularSpeed,
                        path + ".angvel", " rad/s in size");
      !s) {
    return s;
  }
  def.angularVelocity = *angvel;
  Result<float> linearDamping = detail::readNonNegative(j, "linearDamping", path, 0.0f);
  if (!linearDamping) return linearDamping.error();
  def.linearDamping = *linearDamping;
  Result<float> angularDamping = detail::readNonNegative(j, "angularDamping", path, 0.0f);
  if (!angularDamping) return angularDamping.error();
  def.angularDamping = *angularDamping;
  Result<float> gravityScale = detail::readNumber(j, "gravityScale", path, 1.0f);
  if (!gravityScale) return gravityScale.error();
  if (Status s =
          atMost(std::fabs(*gravityScale), kMaxGravityScale, path + ".gravityScale", " in size");
      !s) {
    return s;
  }
  def.gravityScale = *gravityScale;
  Result<float> threshold = detail::readNonNegative(j, "sleepThreshold", path, def.sleepThreshold);
  if (!threshold) return threshold.error();
  def.sleepThreshold = *threshold;
  Result<bool> sleep = detail::readBoolean(j, "sleep", path, true);
  if (!sleep) return sleep.error();
  def.enableSleep = *sleep;
  Result<bool> awake = detail::readBoolean(j, "awake", path, true);
  if (!awake) return awake.error();
  // As in 2D: the world would start such a body awake anyway; say so instead of silently
  // ignoring what the file asked for. A static body is never awake: "awake" is ignored there.
  if (!*awake && def.type != BodyType::staticBody && !*sleep)
    return fail(path +
                ".awake: false needs \"sleep\": true (a body that may not sleep starts awake)");
  if (!*awake && def.type != BodyType::staticBody && !worldSleep)
    return fail(path + ".awake: false needs sleeping on (world.sleep is false)");
  body.awake = *awake;
  return {};
}

Result<SceneBody3> parseBody3(const std::vector<std::string>& categories, bool worldSleep,
                              const json& j, const std::string& path, std::size_t index) {
  if (!j.is_object()) return fail(path + ": must be an object");
  if (Status s =
          refuse2DKeys(j, path,
                       {{"angle", "a 3D body turns by \"quat\": [x, y, z, w], not by an angle"},
                        {"bullet",
                         "the 3D world has no bullets: every fast body is swept against static "
                         "geometry (world.continuous)"}});
      !s) {
    return fail(s.message());
  }
  if (Status s = checkSceneKeys(
          j, path,
          {"name", "type", "pos", "quat", "vel", "angvel", "linearDamping", "angularDamping",
           "gravityScale", "sleepThreshold", "sleep", "awake", "shapes"});
      !s) {
    return fail(s.message());
  }
  SceneBody3 body;
  body.path = path;
  Result<std::string> name = detail::readBodyName(j, path, index);
  if (!name) return name.error();
  body.name = std::move(*name);
  if (Status s = parseBodyDef3(j, path, worldSleep, body); !s) return fail(s.message());
  if (j.contains("shapes")) {
    const json& shapes = j.at("shapes");
    if (!shapes.is_array()) return fail(path + ".shapes: must be an array");
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      Result<SceneShape3> s = parseShape3At(
          categories, shapes[i], path + ".shapes[" + std::to_string(i) + "]", body.def.type);
      if (!s) return s.error();
      body.shapes.push_back(std::move(*s));
    }
  }
  if (Status s = checkBodyShapes3(body); !s) return fail(s.message());
  return body;
}

Result<WorldDef3> parseWorld3(const json& j, const std::string& path) {
  WorldDef3 def;
  if (!j.is_object()) return fail(path + ": must be an object");
  if (Status s = refuse2DKeys(
          j, path,
          {{"broadphase", "the 3D world has one broad phase (a dynamic tree); leave it out"}});
      !s) {
    return fail(s.message());
  }
  if (Status s = checkSceneKeys(
          j, path,
          {"dim", "gravity", "dt", "substeps", "sleep", "contactHertz", "contactDampingRatio",
           "contactPushMaxSpeed", "restitutionThreshold", "speculativeDistance", "aabbMargin",
           "contactRecycleDistance", "continuous"});
      !s) {
    return fail(s.message());
  }
  Result<Vec3> gravity = vec3(j, "gravity", path, def.gravity);
  if (!gravity) return gravity.error();
  if (double g = lengthD(*gravity); g > static_cast<double>(kSceneMaxGravity)) {
    return fail(path + ".gravity: must be at most " +
                showNumber(static_cast<double>(kSceneMaxGravity)) + " m/s^2 in size, got " +
                showNumber(g));
  }
  Result<float> dt = detail::readNumber(j, "dt", path, def.timeStep);
  if (!dt) return dt.error();
  if (*dt <= 0.0f) return fail(path + ".dt: must be > 0");
  if (Status s = atMost(*dt, kSceneMaxTimeStep, path + ".dt", " s"); !s) return fail(s.message());
  Result<int> substeps =
      detail::readInteger(j, "substeps", path, def.substeps, 1, kSceneMaxSubsteps);
  if (!substeps) return substeps.error();
  Result<bool> sleep = detail::readBoolean(j, "sleep", path, def.enableSleep);
  if (!sleep) return sleep.error();
  Result<float> hertz = detail::readNumber(j, "contactHertz", path, def.contactHertz);
  if (!hertz) return hertz.error();
  if (*hertz <= 0.0f) return fail(path + ".contactHertz: must be > 0");
  Result<float> damping =
      detail::readNonNegative(j, "contactDampingRatio", path, def.contactDampingRatio);
  if (!damping) return damping.error();
  Result<float> push = detail::readNumber(j, "contactPushMaxSpeed", path, def.contactPushMaxSpeed);
  if (!push) return push.error();
  if (*push <= 0.0f) return fail(path + ".contactPushMaxSpeed: must be > 0");
  Result<float> threshold =
      detail::readNonNegative(j, "restitutionThreshold", path, def.restitutionThreshold);
  if (!threshold) return threshold.error();
  Result<float> speculative =
      detail::readNonNegative(j, "speculativeDistance", path, def.speculativeDistance);
  if (!speculative) return speculative.error();
  if (Status s = atMost(*speculative, 1.0f, path + ".speculativeDistance", " m"); !s)
    return fail(s.message());
  // The margin defaults to at least the speculative distance, as World3 requires.
  Result<float> margin =
      detail::readNumber(j, "aabbMargin", path, maxf(def.aabbMargin, *speculative));
  if (!margin) return margin.error();
  if (*margin < *speculative) {
    return fail(path + ".aabbMargin: must be >= speculativeDistance (" +
                showNumber(static_cast<double>(*speculative)) + " m), got " +
                showNumber(static_cast<double>(*margin)));
  }
  if (Status s = atMost(*margin, kSceneMaxGeneratedSize, path + ".aabbMargin", " m"); !s)
    return fail(s.message());
  Result<float> recycle =
      detail::readNonNegative(j, "contactRecycleDistance", path, def.contactRecycleDistance);
  if (!recycle) return recycle.error();
  if (Status s = atMost(*recycle, 1.0f, path + ".contactRecycleDistance", " m"); !s)
    return fail(s.message());
  Result<bool> continuous = detail::readBoolean(j, "continuous", path, def.enableContinuous);
  if (!continuous) return continuous.error();
  def.contactRecycleDistance = *recycle;
  def.enableContinuous = *continuous;
  def.gravity = *gravity;
  def.timeStep = *dt;
  def.substeps = *substeps;
  def.enableSleep = *sleep;
  def.contactHertz = *hertz;
  def.contactDampingRatio = *damping;
  def.contactPushMaxSpeed = *push;
  def.restitutionThreshold = *threshold;
  def.speculativeDistance = *speculative;
  def.aabbMargin = *margin;
  return def;
}

}  // namespace

namespace detail {

Result<Scene3> parseScene3Root(const json& root, const std::string& fileName,
                               const SceneProgress& progress) {
  auto relabel = [&](const Error& e) { return fail(fileName + ": " + e.message); };
  Result<int> dim = sceneDimension(root, fileName);
  if (!dim) return dim.error();
  if (*dim != 3) {
    return fail(fileName + ": world.dim: a 3D scene needs \"dim\": 3 in \"world\" (this one is " +
                "2D: parseScene reads it)");
  }
  if (Status s = refuse2DKeys(root, "",
                              {{"generate", "the 3D scene format has no generators yet"},
                               {"joints", "the 3D world has no joints yet"}});
      !s) {
    return relabel(fail(s.message()));
  }
  if (Status s = checkSceneKeys(root, "", {"world", "categories", "bodies"}); !s)
    return relabel(fail(s.message()));
  Scene3 scene;
  scene.file = fileName;
  Result<WorldDef3> w = parseWorld3(root.at("world"), "world");
  if (!w) return relabel(w.error());
  scene.world = *w;
  if (root.contains("categories")) {
    Result<std::vector<std::string>> c = readCategories(root.at("categories"), "categories");
    if (!c) return relabel(c.error());
    scene.categories = std::move(*c);
  }
  if (root.contains("bodies")) {
    const json& bodies = root.at("bodies");
    if (!bodies.is_array()) return fail(fileName + ": bodies: must be an array");
    if (bodies.size() > kSceneMaxBodies) {
      return fail(fileName + ": bodies: more than " + std::to_string(kSceneMaxBodies) +
                  " bodies in the scene");
    }
    scene.bodies.reserve(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      Result<SceneBody3> b = parseBody3(scene.categories, scene.world.enableSleep, bodies[i],
                                        "bodies[" + std::to_string(i) + "]", i);
      if (!b) return relabel(b.error());
      scene.bodies.push_back(std::move(*b));
      if ((i + 1) % kProgressEvery == 0 && progress && !progress(i + 1, 0))
        return fail(fileName + ": interrupted");
    }
  }
  return scene;
}

}  // namespace detail

Result<Scene3> parseScene3(std::string_view text, const std::string& fileName,
                           const SceneProgress& progress) {
  Result<json> root = detail::parseSceneJson(text, fileName);
  if (!root) return root.error();
  return detail::parseScene3Root(*root, fileName, progress);
}

Result<Scene3> loadScene3(const std::string& path, const SceneProgress& progress) {
  Result<std::string> text = detail::readSceneText(path);
  if (!text) return text.error();
  return parseScene3(*text, path, progress);
}

Result<AnyScene> parseAnyScene(std::string_view text, const std::string& fileName,
                               const SceneProgress& progress) {
  Result<json> root = detail::parseSceneJson(text, fileName);
  if (!root) return root.error();
  Result<int> dim = detail::sceneDimension(*root, fileName);
  if (!dim) return dim.error();
  if (*dim == 3) {
    Result<Scene3> scene = detail::parseScene3Root(*root, fileName, progress);
    if (!scene) return scene.error();
    return AnyScene{std::move(*scene)};
  }
  Result<Scene> scene = detail::parseSceneRoot(*root, fileName, progress);
  if (!scene) return scene.error();
  return AnyScene{std::move(*scene)};
}

Result<AnyScene> loadAnyScene(const std::string& path, const SceneProgress& progress) {
  Result<std::string> text = detail::readSceneText(path);
  if (!text) return text.error();
  return parseAnyScene(*text, path, progress);
}

Result<SceneWorld3> buildWorld3(const Scene3& scene, const SceneProgress& progress) {
  Result<World3> made = World3::create(scene.world);
  if (!made) return fail(scene.file + ": world: " + made.error().message);
  SceneWorld3 out{std::move(made).value(), {}, {}, {}};
  out.bodies.reserve(scene.bodies.size());
  out.names.reserve(scene.bodies.size());
  out.shapes.reserve(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const SceneBody3& b = scene.bodies[i];
    Result<BodyId3> body = out.world.createBody(b.def);
    if (!body) return fail(scene.file + ": " + b.path + ": " + body.error().message);
    std::vector<ShapeId3> shapes;
    shapes.reserve(b.shapes.size());
    for (const SceneShape3& s : b.shapes) {
      Result<ShapeId3> made3 =
          std::holds_alternative<Mesh3>(s.geometry)
              ? out.world.createShape(*body, s.def, std::get<Mesh3>(s.geometry))
              : out.world.createShape(*body, s.def, std::get<ShapeGeometry3>(s.geometry));
      if (!made3) return fail(scene.file + ": " + s.path + ": " + made3.error().message);
      shapes.push_back(*made3);
    }
    // Adding a shape wakes its body, so a body the file lists asleep is put back to sleep
    // once it has its shapes (as the 2D buildWorld does).
    if (!b.awake && b.def.type != BodyType::staticBody) {
      if (Status s = out.world.setAwake(*body, false); !s)
        return fail(scene.file + ": " + b.path + ".awake: " + s.message());
    }
    out.bodies.push_back(*body);
    out.names.push_back(b.name);
    out.shapes.push_back(std::move(shapes));
    if ((i + 1) % kProgressEvery == 0 && progress && !progress(i + 1, scene.bodies.size()))
      return fail(scene.file + ": interrupted");
  }
  return out;
}

}  // namespace quack
