// Snapshots of a 3D world (World3::snapshot, restore, fromSnapshot): every part of
// WorldState3 that decides future steps, written with the codec the 2D snapshots use
// (snapshot_codec.hpp). Layout: the magic "QUACK3SN", the format version, the payload's
// length and its FNV-1a checksum, then the payload: the settings and step count; the
// bodies' and shapes' slots (generations, free lists) and every live body and shape (the
// shapes' geometry in full: a hull's faces and edges as built, a mesh's vertices and
// triangles, rebuilt by makeMesh3); the broad phase's records; the contacts in their order
// with their manifolds, impulses and recycling caches; the last step's events and the end
// events waiting for the next. What a step computes afresh (islands, the solver's arrays,
// the continuous phase's starting poses) is not saved.
//
// Reading checks every count against the bytes left, every index against what it indexes
// and every shape by the collision layer's own validation, before the rebuilt state
// replaces anything.

#include <string>

#include "quack/geometry/hull3.hpp"
#include "quack/world/world3.hpp"
#include "snapshot_codec.hpp"
#include "world_state3.hpp"

namespace quack {

namespace detail {
namespace {

constexpr char kMagic3[8] = {'Q', 'U', 'A', 'C', 'K', '3', 'S', 'N'};
constexpr std::size_t kHeader3Size = 8 + 4 + 8 + 8;

// ---- writing ------------------------------------------------------------------------------

void vec3(Writer& w, Vec3 v) {
  w.f32(v.x);
  w.f32(v.y);
  w.f32(v.z);
}
void quat(Writer& w, Quat q) {
  w.f32(q.x);
  w.f32(q.y);
  w.f32(q.z);
  w.f32(q.w);
}
void xf3(Writer& w, Transform3 t) {
  vec3(w, t.p);
  quat(w, t.q);
}
void mat3(Writer& w, const Mat3& m) {
  vec3(w, m.cx);
  vec3(w, m.cy);
  vec3(w, m.cz);
}
void box3(Writer& w, Aabb3 b) {
  vec3(w, b.lower);
  vec3(w, b.upper);
}
void filter(Writer& w, Filter f) {
  w.u64(f.category);
  w.u64(f.mask);
  w.i32(f.group);
}
void pool(Writer& w, const IdPool& p) {
  w.size(p.capacity());
  for (std::uint32_t i = 0; i < p.capacity(); ++i)
    w.u32(p.generation(i));
  w.list(p.freeSlots());
}

void writeGeometry(Writer& w, const ShapeGeometry3& g) {
  w.u8(static_cast<std::uint8_t>(g.index()));
  if (const auto* s = std::get_if<Sphere>(&g)) {
    vec3(w, s->center);
    w.f32(s->radius);
  } else if (const auto* c = std::get_if<Capsule3>(&g)) {
    vec3(w, c->p1);
    vec3(w, c->p2);
    w.f32(c->radius);
  } else if (const auto* t = std::get_if<Triangle3>(&g)) {
    for (const Vec3& v : t->v)
      vec3(w, v);
  } else if (const auto* h = std::get_if<Hull3>(&g)) {
    w.var(static_cast<std::uint32_t>(h->vertexCount));
    w.var(static_cast<std::uint32_t>(h->faceCount));
    w.var(static_cast<std::uint32_t>(h->edgeCount));
    for (int i = 0; i < h->vertexCount; ++i)
      vec3(w, h->vertices[i]);
    for (int i = 0; i < h->faceCount; ++i) {
      vec3(w, h->faces[i].normal);
      w.f32(h->faces[i].offset);
      w.var(h->faces[i].first);
      w.u8(h->faces[i].count);
    }
    for (int i = 0; i < h->edgeCount; ++i) {
      const HullEdge3& e = h->edges[i];
      w.u8(e.v0);
      w.u8(e.v1);
      w.u8(e.faceLeft);
      w.u8(e.faceRight);
    }
    for (int i = 0; i < 2 * h->edgeCount; ++i)
      w.u8(h->faceVertices[i]);
    vec3(w, h->centroid);
    w.f32(h->radius);
  }
}

void writeEvents(Writer& w, const std::vector<ContactEvent3>& events) {
  w.size(events.size());
  for (const ContactEvent3& e : events) {
    w.var(e.shapeA.index);
    w.u32(e.shapeA.generation);
    w.var(e.shapeB.index);
    w.u32(e.shapeB.generation);
    w.u64(e.categoryA);
    w.u64(e.categoryB);
  }
}

std::vector<std::uint8_t> encode(const WorldState3& s) {
  Writer w;
  const WorldDef3& d = s.def;
  vec3(w, d.gravity);
  w.f32(d.timeStep);
  w.var(static_cast<std::uint32_t>(d.substeps));
  for (float f :
       {d.contactHertz, d.contactDampingRatio, d.contactPushMaxSpeed, d.restitutionThreshold,
        d.speculativeDistance, d.aabbMargin, d.contactRecycleDistance})
    w.f32(f);
  w.flag(d.enableContinuous);
  w.flag(d.enableSleep);
  w.u64(s.stepCount);

  const BodyStore3& store = s.store;
  pool(w, store.bodyIds);
  for (std::uint32_t i = 0; i < store.bodyIds.capacity(); ++i) {
    if (!store.bodyIds.isAlive(i)) continue;
    const Body3& b = store.bodies[i];
    w.u8(static_cast<std::uint8_t>(b.type));
    vec3(w, b.origin);
    quat(w, b.rotation);
    vec3(w, b.localCenter);
    vec3(w, b.center);
    vec3(w, b.linearVelocity);
    vec3(w, b.angularVelocity);
    w.f32(b.mass);
    w.f32(b.invMass);
    mat3(w, b.inertiaLocal);
    mat3(w, b.invInertiaLocal);
    for (float f : {b.linearDamping, b.angularDamping, b.gravityScale, b.sleepThreshold,
                    b.sleepTime, b.maxExtent, b.minExtent})
      w.f32(f);
    w.flag(b.enableSleep);
    w.flag(b.awake);
    w.u32(b.poseVersion);
    w.list(b.shapes);
    w.u64(b.userData);
  }
  pool(w, store.shapeIds);
  for (std::uint32_t i = 0; i < store.shapeIds.capacity(); ++i) {
    if (!store.shapeIds.isAlive(i)) continue;
    const Shape3& sh = store.shapes[i];
    w.var(sh.body);
    w.f32(sh.def.density);
    w.f32(sh.def.friction);
    w.f32(sh.def.restitution);
    w.f32(sh.def.rollingResistance);
    filter(w, sh.def.filter);
    w.u64(sh.def.userData);
    w.var(sh.proxy.index);
    w.u32(sh.proxy.generation);
    w.flag(sh.mesh != nullptr);
    if (sh.mesh) {
      w.size(sh.mesh->vertices().size());
      for (const Vec3& v : sh.mesh->vertices())
        vec3(w, v);
      w.size(sh.mesh->triangles().size());
      for (const MeshTriangle3& t : sh.mesh->triangles())
        for (std::int32_t v : t.v)
          w.var(static_cast<std::uint32_t>(v));
    } else {
      writeGeometry(w, *sh.geometry);
    }
  }

  const BroadPhase3Records r = store.broadPhase().records();
  w.size(r.generations.size());
  for (std::size_t p = 0; p < r.generations.size(); ++p) {
    w.u32(r.generations[p]);
    box3(w, r.tight[p]);
    box3(w, r.fat[p]);
    w.u8(static_cast<std::uint8_t>(r.kinds[p]));
    w.u8(r.buffered[p]);
    filter(w, r.filters[p]);
    w.u64(r.userData[p]);
  }
  w.list(r.freeSlots);
  w.list(r.moveBuffer);

  const std::vector<Contact3>& contacts = s.contacts.contacts();
  w.size(contacts.size());
  for (const Contact3& c : contacts) {
    w.var(c.shapeA);
    w.var(c.shapeB);
    w.f32(c.friction);
    w.f32(c.restitution);
    w.f32(c.rollingResistance);
    w.flag(c.touching);
    w.flag(c.flat);
    w.flag(c.recycleValid);
    xf3(w, c.cachedA);
    xf3(w, c.cachedB);
    w.u32(c.versionA);
    w.u32(c.versionB);
    w.flag(c.hullCache.valid);
    vec3(w, c.hullCache.axis);
    w.f32(c.hullCache.maxA);
    w.size(c.manifolds.size());
    for (const ContactManifold3& m : c.manifolds) {
      w.i32(m.triangle);
      vec3(w, m.manifold.normal);
      w.var(static_cast<std::uint32_t>(m.manifold.pointCount));
      for (int k = 0; k < m.manifold.pointCount; ++k) {
        const ManifoldPoint3& p = m.manifold.points[k];
        vec3(w, p.point);
        vec3(w, p.anchorA);
        vec3(w, p.anchorB);
        w.f32(p.separation);
        w.u32(p.id);
        w.f32(m.normalImpulse[k]);
        w.f32(m.maxNormalImpulse[k]);
        vec3(w, m.localA[k]);
        vec3(w, m.localB[k]);
        w.f32(m.computedSeparation[k]);
        vec3(w, m.armA[k]);
        vec3(w, m.armB[k]);
      }
      vec3(w, m.frictionImpulse);
      w.f32(m.twistImpulse);
      vec3(w, m.rollingImpulse);
    }
  }
  writeEvents(w, s.events.begin);
  writeEvents(w, s.events.end);
  writeEvents(w, s.pendingEnds);
  return w.bytes;
}

// ---- reading ------------------------------------------------------------------------------

Vec3 vec3(Reader& r, const char* what) {
  const float x = r.f32(what);
  const float y = r.f32(what);
  return {x, y, r.f32(what)};
}
Quat quat(Reader& r, const char* what) {
  Quat q;
  q.x = r.f32(what);
  q.y = r.f32(what);
  q.z = r.f32(what);
  q.w = r.f32(what);
  return q;
}
Transform3 xf3(Reader& r, const char* what) {
  Transform3 t;
  t.p = vec3(r, what);
  t.q = quat(r, what);
  return t;
}
Mat3 mat3(Reader& r, const char* what) {
  Mat3 m;
  m.cx = vec3(r, what);
  m.cy = vec3(r, what);
  m.cz = vec3(r, what);
  return m;
}
Aabb3 box3(Reader& r, const char* what) {
  Aabb3 b;
  b.lower = vec3(r, what);
  b.upper = vec3(r, what);
  return b;
}
Filter filter(Reader& r, const char* what) {
  Filter f;
  f.category = r.u64(what);
  f.mask = r.u64(what);
  f.group = r.i32(what);
  return f;
}
Result<IdPool> pool(Reader& r, const char* what) {
  std::vector<std::uint32_t> generations(r.count(what, 4));
  for (std::uint32_t& g : generations)
    g = r.u32(what);
  std::vector<std::uint32_t> freeSlots = r.indexList(what, generations.size());
  if (!r.ok()) return fail(r.error());
  Result<IdPool> p = IdPool::fromSlots(std::move(generations), std::move(freeSlots));
  if (!p) return fail(std::string(what) + ": " + p.error().message);
  return p;
}

ShapeGeometry3 readGeometry(Reader& r) {
  const std::uint8_t tag = r.u8("shape geometry kind");
  if (tag == 0) {
    Sphere s;
    s.center = vec3(r, "sphere centre");
    s.radius = r.f32("sphere radius");
    return s;
  }
  if (tag == 1) {
    Capsule3 c;
    c.p1 = vec3(r, "capsule p1");
    c.p2 = vec3(r, "capsule p2");
    c.radius = r.f32("capsule radius");
    return c;
  }
  if (tag == 2) {
    Hull3 h;
    const std::uint32_t vc = r.var("hull vertex count");
    const std::uint32_t fc = r.var("hull face count");
    const std::uint32_t ec = r.var("hull edge count");
    if (vc > kMaxHullVertices3 || fc > kMaxHullFaces3 || ec > kMaxHullEdges3) {
      r.fail("hull counts beyond the hull's limits");
      return h;
    }
    h.vertexCount = static_cast<int>(vc);
    h.faceCount = static_cast<int>(fc);
    h.edgeCount = static_cast<int>(ec);
    for (std::uint32_t i = 0; i < vc; ++i)
      h.vertices[i] = vec3(r, "hull vertex");
    for (std::uint32_t i = 0; i < fc; ++i) {
      h.faces[i].normal = vec3(r, "hull face normal");
      h.faces[i].offset = r.f32("hull face offset");
      h.faces[i].first = static_cast<std::uint16_t>(r.index("hull face first", 2 * ec));
      h.faces[i].count = r.u8("hull face count");
    }
    for (std::uint32_t i = 0; i < ec; ++i) {
      HullEdge3& e = h.edges[i];
      e.v0 = r.u8("hull edge");
      e.v1 = r.u8("hull edge");
      e.faceLeft = r.u8("hull edge");
      e.faceRight = r.u8("hull edge");
    }
    for (std::uint32_t i = 0; i < 2 * ec; ++i)
      h.faceVertices[i] = r.u8("hull face vertex");
    h.centroid = vec3(r, "hull centroid");
    h.radius = r.f32("hull radius");
    return h;
  }
  if (tag == 3) {
    Triangle3 t;
    for (Vec3& v : t.v)
      v = vec3(r, "triangle vertex");
    return t;
  }
  r.fail("shape geometry kind " + std::to_string(tag) + " is not a 3D shape");
  return Sphere{};
}

std::vector<ContactEvent3> readEvents(Reader& r, const char* what, std::uint32_t world,
                                      std::size_t shapes) {
  std::vector<ContactEvent3> events(r.count(what, 26));
  for (ContactEvent3& e : events) {
    e.shapeA.index = r.index(what, shapes);
    e.shapeA.generation = r.u32(what);
    e.shapeA.world = world;
    e.shapeB.index = r.index(what, shapes);
    e.shapeB.generation = r.u32(what);
    e.shapeB.world = world;
    e.categoryA = r.u64(what);
    e.categoryB = r.u64(what);
  }
  return events;
}

Result<std::unique_ptr<WorldState3>> decode(std::span<const std::uint8_t> bytes,
                                            std::uint32_t worldId) {
  const char* where = "snapshot: ";
  if (bytes.size() < kHeader3Size || std::memcmp(bytes.data(), kMagic3, 8) != 0)
    return fail(std::string(where) + "not a 3D world snapshot (no QUACK3SN header)");
  Reader header(bytes.subspan(8, kHeader3Size - 8), "header");
  const std::uint32_t version = header.u32("format version");
  const std::uint64_t length = header.u64("payload length");
  const std::uint64_t checksum = header.u64("checksum");
  if (version != kSnapshot3FormatVersion)
    return fail(std::string(where) + "format version " + std::to_string(version) +
                ", this build reads version " + std::to_string(kSnapshot3FormatVersion));
  if (length != bytes.size() - kHeader3Size)
    return fail(std::string(where) + "payload of " + std::to_string(bytes.size() - kHeader3Size) +
                " bytes, the header says " + std::to_string(length) + " (truncated?)");
  const std::span<const std::uint8_t> payload = bytes.subspan(kHeader3Size);
  if (fnv1a(payload) != checksum) return fail(std::string(where) + "checksum mismatch (corrupted)");

  Reader r(payload, "payload");
  WorldDef3 def;
  def.gravity = vec3(r, "gravity");
  def.timeStep = r.f32("timeStep");
  def.substeps = static_cast<int>(r.var("substeps"));
  def.contactHertz = r.f32("contactHertz");
  def.contactDampingRatio = r.f32("contactDampingRatio");
  def.contactPushMaxSpeed = r.f32("contactPushMaxSpeed");
  def.restitutionThreshold = r.f32("restitutionThreshold");
  def.speculativeDistance = r.f32("speculativeDistance");
  def.aabbMargin = r.f32("aabbMargin");
  def.contactRecycleDistance = r.f32("contactRecycleDistance");
  def.enableContinuous = r.flag("enableContinuous");
  def.enableSleep = r.flag("enableSleep");
  if (!r.ok()) return fail(std::string(where) + r.error());
  if (Status s = checkWorldDef3(def); !s) return fail(std::string(where) + s.message());
  const std::uint64_t stepCount = r.u64("step count");

  Result<IdPool> bodyIds = pool(r, "body slots");
  if (!bodyIds) return fail(std::string(where) + bodyIds.error().message);
  std::vector<Body3> bodies(bodyIds.value().capacity());
  for (std::uint32_t i = 0; i < bodies.size() && r.ok(); ++i) {
    if (!bodyIds.value().isAlive(i)) continue;
    Body3& b = bodies[i];
    const std::uint8_t type = r.u8("body type");
    if (type > static_cast<std::uint8_t>(BodyType::dynamicBody)) r.fail("body type");
    b.type = static_cast<BodyType>(type);
    b.origin = vec3(r, "body origin");
    b.rotation = quat(r, "body rotation");
    b.localCenter = vec3(r, "body local centre");
    b.center = vec3(r, "body centre");
    b.linearVelocity = vec3(r, "body velocity");
    b.angularVelocity = vec3(r, "body angular velocity");
    b.mass = r.f32("body mass");
    b.invMass = r.f32("body inverse mass");
    b.inertiaLocal = mat3(r, "body inertia");
    b.invInertiaLocal = mat3(r, "body inverse inertia");
    b.linearDamping = r.f32("body damping");
    b.angularDamping = r.f32("body damping");
    b.gravityScale = r.f32("body gravity scale");
    b.sleepThreshold = r.f32("body sleep threshold");
    b.sleepTime = r.f32("body sleep time");
    b.maxExtent = r.f32("body extent");
    b.minExtent = r.f32("body extent");
    b.enableSleep = r.flag("body enableSleep");
    b.awake = r.flag("body awake");
    b.poseVersion = r.u32("body pose version");
    b.shapes = r.indexList("body shapes", 0xffffffffu);
    b.userData = r.u64("body user data");
  }
  if (!r.ok()) return fail(std::string(where) + r.error());

  Result<IdPool> shapeIds = pool(r, "shape slots");
  if (!shapeIds) return fail(std::string(where) + shapeIds.error().message);
  std::vector<Shape3> shapes(shapeIds.value().capacity());
  SharedGeometries3 geometries;
  for (std::uint32_t i = 0; i < shapes.size() && r.ok(); ++i) {
    if (!shapeIds.value().isAlive(i)) continue;
    Shape3& sh = shapes[i];
    sh.body = r.index("shape body", bodies.size());
    if (r.ok() && !bodyIds.value().isAlive(sh.body))
      r.fail("shape " + std::to_string(i) + " is on a free body slot");
    sh.def.density = r.f32("shape density");
    sh.def.friction = r.f32("shape friction");
    sh.def.restitution = r.f32("shape restitution");
    sh.def.rollingResistance = r.f32("shape rolling resistance");
    sh.def.filter = filter(r, "shape filter");
    sh.def.userData = r.u64("shape user data");
    sh.proxy.index = r.var("shape proxy");
    sh.proxy.generation = r.u32("shape proxy");
    if (r.flag("shape is a mesh")) {
      std::vector<Vec3> vertices(r.count("mesh vertices", 12));
      for (Vec3& v : vertices)
        v = vec3(r, "mesh vertex");
      std::vector<std::array<std::int32_t, 3>> triangles(r.count("mesh triangles", 3));
      for (auto& t : triangles)
        for (std::int32_t& v : t)
          v = static_cast<std::int32_t>(r.index("mesh triangle vertex", vertices.size()));
      if (!r.ok()) break;
      Result<Mesh3> mesh = makeMesh3(vertices, triangles);
      if (!mesh)
        return fail(std::string(where) + "shape " + std::to_string(i) + ": " +
                    mesh.error().message);
      sh.mesh = std::make_shared<Mesh3>(std::move(mesh).value());
      sh.geometry = std::make_shared<const ShapeGeometry3>(Sphere{});  // as createMeshShape's
    } else {
      ShapeGeometry3 geometry = readGeometry(r);
      if (!r.ok()) break;
      // Validated, and shared as when the shapes were made.
      Result<StoredGeometry3> stored = geometries.intern(geometry, validateShape);
      if (!stored)
        return fail(std::string(where) + "shape " + std::to_string(i) + ": " +
                    stored.error().message);
      sh.geometry = stored.value().geometry;
      sh.hullSat = stored.value().hullSat;
    }
  }
  if (!r.ok()) return fail(std::string(where) + r.error());
  for (std::uint32_t i = 0; i < bodies.size(); ++i) {
    if (!bodyIds.value().isAlive(i)) continue;
    for (std::uint32_t s : bodies[i].shapes)
      if (s >= shapes.size() || !shapeIds.value().isAlive(s) || shapes[s].body != i)
        return fail(std::string(where) + "body " + std::to_string(i) + " lists shape " +
                    std::to_string(s) + ", not one of its own");
  }

  BroadPhase3Records records;
  const std::uint32_t proxies = r.count("proxies", 70);
  for (std::uint32_t p = 0; p < proxies && r.ok(); ++p) {
    records.generations.push_back(r.u32("proxy generation"));
    records.tight.push_back(box3(r, "proxy tight box"));
    records.fat.push_back(box3(r, "proxy fat box"));
    records.kinds.push_back(static_cast<ProxyKind>(r.u8("proxy kind")));
    records.buffered.push_back(r.u8("proxy buffered"));
    records.filters.push_back(filter(r, "proxy filter"));
    records.userData.push_back(r.u64("proxy user data"));
  }
  records.freeSlots = r.indexList("proxy free slots", proxies);
  records.moveBuffer = r.indexList("move buffer", proxies);
  if (!r.ok()) return fail(std::string(where) + r.error());
  Result<BroadPhase3> bp = BroadPhase3::fromRecords({.margin = def.aabbMargin}, std::move(records));
  if (!bp) return fail(std::string(where) + bp.error().message);
  for (std::uint32_t i = 0; i < shapes.size(); ++i) {
    if (!shapeIds.value().isAlive(i)) continue;
    const ProxyId id = shapes[i].proxy;
    if (!bp.value().isValid(id) || bp.value().userData(id) != i)
      return fail(std::string(where) + "shape " + std::to_string(i) + "'s proxy is not its own");
  }

  std::vector<Contact3> contacts(r.count("contacts", 77));
  for (Contact3& c : contacts) {
    c.shapeA = r.index("contact shape", shapes.size());
    c.shapeB = r.index("contact shape", shapes.size());
    if (r.ok() && (!shapeIds.value().isAlive(c.shapeA) || !shapeIds.value().isAlive(c.shapeB)))
      r.fail("a contact names a free shape slot");
    c.friction = r.f32("contact friction");
    c.restitution = r.f32("contact restitution");
    c.rollingResistance = r.f32("contact rolling resistance");
    c.touching = r.flag("contact touching");
    c.flat = r.flag("contact flat");
    c.recycleValid = r.flag("contact recycle");
    c.cachedA = xf3(r, "contact pose");
    c.cachedB = xf3(r, "contact pose");
    c.versionA = r.u32("contact pose version");
    c.versionB = r.u32("contact pose version");
    c.hullCache.valid = r.flag("contact hull cache");
    c.hullCache.axis = vec3(r, "contact hull cache axis");
    c.hullCache.maxA = r.f32("contact hull cache");
    c.manifolds.resize(r.count("contact manifolds", 33));
    for (ContactManifold3& m : c.manifolds) {
      m.triangle = r.i32("manifold triangle");
      m.manifold.normal = vec3(r, "manifold normal");
      m.manifold.pointCount =
          static_cast<int>(r.index("manifold point count", kMaxManifoldPoints3 + 1));
      for (int k = 0; k < m.manifold.pointCount; ++k) {
        ManifoldPoint3& p = m.manifold.points[k];
        p.point = vec3(r, "manifold point");
        p.anchorA = vec3(r, "manifold anchor");
        p.anchorB = vec3(r, "manifold anchor");
        p.separation = r.f32("manifold separation");
        p.id = r.u32("manifold id");
        m.normalImpulse[k] = r.f32("normal impulse");
        m.maxNormalImpulse[k] = r.f32("normal impulse");
        m.localA[k] = vec3(r, "recycle point");
        m.localB[k] = vec3(r, "recycle point");
        m.computedSeparation[k] = r.f32("recycle separation");
        m.armA[k] = vec3(r, "arm");
        m.armB[k] = vec3(r, "arm");
      }
      m.frictionImpulse = vec3(r, "friction impulse");
      m.twistImpulse = r.f32("twist impulse");
      m.rollingImpulse = vec3(r, "rolling impulse");
    }
    if (!r.ok()) break;
  }
  if (!r.ok()) return fail(std::string(where) + r.error());

  auto state = std::make_unique<WorldState3>(def, std::move(bp).value(), worldId);
  state->stepCount = stepCount;
  state->store.bodyIds = std::move(bodyIds).value();
  state->store.shapeIds = std::move(shapeIds).value();
  state->store.bodies = std::move(bodies);
  state->store.shapes = std::move(shapes);
  state->store.geometries = std::move(geometries);
  state->contacts.restore(std::move(contacts));
  state->events.begin = readEvents(r, "begin events", worldId, state->store.shapes.size());
  state->events.end = readEvents(r, "end events", worldId, state->store.shapes.size());
  state->pendingEnds = readEvents(r, "pending end events", worldId, state->store.shapes.size());
  if (!r.ok()) return fail(std::string(where) + r.error());
  if (!r.atEnd())
    return fail(std::string(where) + std::to_string(r.left()) + " bytes after the end");
  return state;
}

}  // namespace
}  // namespace detail

std::vector<std::uint8_t> World3::snapshot() const {
  const std::vector<std::uint8_t> payload = detail::encode(*state_);
  detail::Writer w;
  for (char c : detail::kMagic3)
    w.u8(static_cast<std::uint8_t>(c));
  w.u32(kSnapshot3FormatVersion);
  w.u64(payload.size());
  w.u64(detail::fnv1a(payload));
  w.bytes.insert(w.bytes.end(), payload.begin(), payload.end());
  return w.bytes;
}

Status World3::restore(std::span<const std::uint8_t> bytes) {
  if (state_->inCallbacks) return fail("restore: called from a contact callback");
  auto decoded = detail::decode(bytes, state_->id);
  if (!decoded) return fail("restore: " + decoded.error().message);
  // The callbacks, workers and solver path are the world's, not the snapshot's: they stay.
  detail::WorldState3& next = *decoded.value();
  next.callbacks = std::move(state_->callbacks);
  next.def.scalarSolver = state_->def.scalarSolver;
  next.def.workerCount = state_->def.workerCount;
  next.def.enqueueTask = state_->def.enqueueTask;
  next.def.finishTask = state_->def.finishTask;
  next.def.userTaskContext = state_->def.userTaskContext;
  next.tasks = std::move(state_->tasks);
  state_ = std::move(decoded).value();
  return {};
}

Result<World3> World3::fromSnapshot(std::span<const std::uint8_t> bytes) {
  auto decoded = detail::decode(bytes, detail::nextWorldId());
  if (!decoded) return Error{"fromSnapshot: " + decoded.error().message};
  return World3(std::move(decoded).value());
}

}  // namespace quack
