#include "body_store3.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

#include "quack/collision/proxy3.hpp"
#include "quack/geometry/mass3.hpp"

namespace quack::detail {

std::uint32_t BodyStore3::addBody(const BodyDef3& def) {
  const std::uint32_t index = bodyIds.allocate();
  if (index >= bodies.size()) bodies.resize(index + 1);
  Body3& b = bodies[index];
  b = Body3{};
  b.type = def.type;
  b.origin = def.position;
  b.rotation = unitRotation(def.rotation);
  b.center = def.position;
  if (def.type != BodyType::staticBody) {
    b.linearVelocity = def.linearVelocity;
    b.angularVelocity = def.angularVelocity;
  }
  b.linearDamping = def.linearDamping;
  b.angularDamping = def.angularDamping;
  b.gravityScale = def.gravityScale;
  b.sleepThreshold = def.sleepThreshold;
  b.enableSleep = def.enableSleep;
  b.userData = def.userData;
  updateMass(index);
  return index;
}

void BodyStore3::removeBody(std::uint32_t body) {
  // Shapes leave in reverse creation order so that the freed slots are reused in order.
  while (!bodies[body].shapes.empty())
    removeShape(bodies[body].shapes.back());
  bodies[body] = Body3{};
  bodyIds.release(body);
}

Aabb3 BodyStore3::shapeBox(std::uint32_t shape) const {
  return shapeBox(shape, bodies[shapes[shape].body].transform());
}

Aabb3 BodyStore3::shapeBox(std::uint32_t shape, Transform3 xf) const {
  const Shape3& s = shapes[shape];
  if (s.mesh) {
    const Aabb3 local = s.mesh->bounds();
    Aabb3 box{};
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner{(i & 1) ? local.upper.x : local.lower.x,
                        (i & 2) ? local.upper.y : local.lower.y,
                        (i & 4) ? local.upper.z : local.lower.z};
      const Vec3 p = transformPoint(xf, corner);
      box = i == 0 ? Aabb3{p, p} : Aabb3{minv(box.lower, p), maxv(box.upper, p)};
    }
    return box;
  }
  return proxyBox(makeProxy(*s.geometry), xf);
}

Aabb3 proxyBox(const ShapeProxy3& proxy, Transform3 xf) noexcept {
  // One rotation matrix for all the points: a third of the quaternion rotations' work.
  const Mat3 rot = toMat3(xf.q);
  Aabb3 box{};
  for (int i = 0; i < proxy.count(); ++i) {
    const Vec3 p = rot * proxy.points()[i] + xf.p;
    box = i == 0 ? Aabb3{p, p} : Aabb3{minv(box.lower, p), maxv(box.upper, p)};
  }
  const Vec3 r{proxy.radius(), proxy.radius(), proxy.radius()};
  return {box.lower - r, box.upper + r};
}

Result<std::uint32_t> BodyStore3::addShape(std::uint32_t body, const ShapeDef3& def,
                                           StoredGeometry3 geometry, std::shared_ptr<Mesh3> mesh) {
  const std::uint32_t index = shapeIds.allocate();
  if (index >= shapes.size()) shapes.resize(index + 1);
  Shape3& s = shapes[index];
  s = Shape3{};
  s.body = body;
  s.def = def;
  s.geometry = std::move(geometry.geometry);
  s.hullSat = geometry.hullSat;
  s.mesh = std::move(mesh);
  const ProxyKind kind =
      bodies[body].type == BodyType::staticBody ? ProxyKind::staticProxy : ProxyKind::dynamicProxy;
  Result<ProxyId> proxy = broadPhase_.createProxy(shapeBox(index), index, def.filter, kind);
  if (!proxy) {
    shapes[index] = Shape3{};
    shapeIds.release(index);
    return fail("shape: its box is out of the world: " + proxy.error().message);
  }
  s.proxy = proxy.value();
  bodies[body].shapes.push_back(index);
  updateMass(body);
  return index;
}

namespace {

// Every field a hull's users read (its padding and the arrays' unused tails left out).
std::string hullKey(const Hull3& h) {
  const std::size_t v = std::size_t(h.vertexCount), f = std::size_t(h.faceCount),
                    e = std::size_t(h.edgeCount);
  constexpr std::size_t kFace = 4 * sizeof(float) + sizeof(std::uint16_t) + sizeof(std::uint8_t);
  static_assert(sizeof(HullEdge3) == 4 && std::has_unique_object_representations_v<HullEdge3>);
  KeyWriter w(3 * sizeof(int) + 4 * sizeof(float) + 12 * v + kFace * f + 4 * e + 2 * e);
  w.put(h.vertexCount);
  w.put(h.faceCount);
  w.put(h.edgeCount);
  w.put(h.radius);
  w.put(h.centroid);
  static_assert(sizeof(Vec3) == 3 * sizeof(float), "vertices copy as their floats");
  w.put(h.vertices, v);
  for (std::size_t i = 0; i < f; ++i) {
    w.put(h.faces[i].normal);
    w.put(h.faces[i].offset);
    w.put(h.faces[i].first);
    w.put(h.faces[i].count);
  }
  w.put(h.edges, e);
  w.put(h.faceVertices, 2 * e);
  return w.take();
}

}  // namespace

Result<StoredGeometry3> SharedGeometries3::intern(const ShapeGeometry3& geometry,
                                                  Status (*validate)(const ShapeGeometry3&)) {
  const Hull3* hull = std::get_if<Hull3>(&geometry);
  if (hull == nullptr) {
    if (Status s = validate(geometry); !s) return Error{s.message()};
    return StoredGeometry3{std::make_shared<const ShapeGeometry3>(geometry), nullptr};
  }
  // The geometry and its SAT data in one block; the shapes' pointers alias into it.
  auto share = [](const std::shared_ptr<const Hull>& h) {
    return StoredGeometry3{std::shared_ptr<const ShapeGeometry3>(h, &h->geometry), &h->sat};
  };
  std::string key = hullKey(*hull);
  if (std::shared_ptr<const Hull> held = hulls_.find(key)) return share(held);
  if (Status s = validate(geometry); !s) return Error{s.message()};
  auto made = std::make_shared<const Hull>(Hull{geometry, makeHullSatData3(*hull)});
  hulls_.insert(std::move(key), made);
  return share(made);
}

void BodyStore3::removeShape(std::uint32_t shape) {
  Shape3& s = shapes[shape];
  const std::uint32_t body = s.body;
  Status removed = broadPhase_.destroyProxy(s.proxy);
  QUACK_ASSERT(removed.ok());
  std::vector<std::uint32_t>& list = bodies[body].shapes;
  list.erase(std::find(list.begin(), list.end(), shape));
  s = Shape3{};
  shapeIds.release(shape);
  updateMass(body);
}

void BodyStore3::moveProxies(std::uint32_t body, Vec3 displacement) {
  for (std::uint32_t shape : bodies[body].shapes)
    moveProxy(shape, shapeBox(shape), displacement);
}

void BodyStore3::moveProxy(std::uint32_t shape, const Aabb3& box, Vec3 displacement) {
  Result<bool> moved = broadPhase_.moveProxy(shapes[shape].proxy, box, displacement);
  // The solver holds bodies inside kMaxCoordinate, so a refused box is a bug.
  QUACK_ASSERT(moved.ok());
}

// Mass, centre of mass and inertia from the shapes (parallel-axis theorem about the body's
// centre of mass, summed in double). A dynamic body whose shapes have no mass moves as a
// 1 kg body that does not turn, as the 2D world's does.
namespace {

// A shape's half-thickness: the radius of a ball about its centre that it holds.
float thickness(const ShapeGeometry3& g) noexcept {
  if (const Sphere* s = std::get_if<Sphere>(&g)) return s->radius;
  if (const Capsule3* c = std::get_if<Capsule3>(&g)) return c->radius;
  if (const Hull3* h = std::get_if<Hull3>(&g)) {
    float least = std::numeric_limits<float>::infinity();
    for (int f = 0; f < h->faceCount; ++f)
      least = std::min(least, h->faces[f].offset - dot(h->faces[f].normal, h->centroid));
    return std::max(least, 0.0f) + h->radius;
  }
  return 0.0f;  // a triangle has no thickness
}

}  // namespace

void BodyStore3::updateMass(std::uint32_t index) {
  Body3& b = bodies[index];
  ++b.poseVersion;  // the centre of mass may move: contacts get new manifolds
  b.mass = b.invMass = 0.0f;
  b.inertiaLocal = b.invInertiaLocal = Mat3{};
  b.localCenter = Vec3{};
  b.maxExtent = 0.0f;
  b.minExtent = 0.0f;
  if (b.type != BodyType::dynamicBody) {
    b.center = transformPoint(b.transform(), b.localCenter);
    return;
  }
  double mass = 0.0, cx = 0.0, cy = 0.0, cz = 0.0;
  std::vector<MassProperties3> parts;
  for (std::uint32_t shape : b.shapes) {
    const Shape3& s = shapes[shape];
    // The last shape's mass again when this one has the same stored geometry and density
    // (a pile of one hull): the memo holds the geometry, so its address is not reused.
    // The densities compared by their bits (std::memcmp: emscripten 3.1.6's libc++, the web
    // build's, has no std::bit_cast).
    if (s.geometry != massMemo_.geometry ||
        std::memcmp(&s.def.density, &massMemo_.density, sizeof(float)) != 0) {
      massMemo_ = {s.geometry, s.def.density, computeMass(*s.geometry, s.def.density)};
    }
    parts.push_back(massMemo_.mass);
    const MassProperties3& m = parts.back();
    mass += double(m.mass);
    cx += double(m.mass) * double(m.centroid.x);
    cy += double(m.mass) * double(m.centroid.y);
    cz += double(m.mass) * double(m.centroid.z);
  }
  if (mass > 0.0) {
    const Vec3 c{float(cx / mass), float(cy / mass), float(cz / mass)};
    double inertia[3][3] = {};
    for (const MassProperties3& m : parts) {
      const Vec3 d = m.centroid - c;
      const Vec3 cols[3] = {m.inertia.cx, m.inertia.cy, m.inertia.cz};
      const float dv[3] = {d.x, d.y, d.z};
      const double dd =
          double(d.x) * double(d.x) + double(d.y) * double(d.y) + double(d.z) * double(d.z);
      for (int col = 0; col < 3; ++col) {
        const float colv[3] = {cols[col].x, cols[col].y, cols[col].z};
        for (int row = 0; row < 3; ++row) {
          const double shift = (row == col ? dd : 0.0) - double(dv[row]) * double(dv[col]);
          inertia[col][row] += double(colv[row]) + double(m.mass) * shift;
        }
      }
    }
    b.mass = float(mass);
    b.invMass = 1.0f / b.mass;
    b.localCenter = c;
    b.inertiaLocal = {{float(inertia[0][0]), float(inertia[0][1]), float(inertia[0][2])},
                      {float(inertia[1][0]), float(inertia[1][1]), float(inertia[1][2])},
                      {float(inertia[2][0]), float(inertia[2][1]), float(inertia[2][2])}};
    // An inertia tensor is positive definite; a determinant at or below zero (a shape with
    // no volume in some direction) leaves the body unable to turn rather than spinning wild.
    if (determinant(b.inertiaLocal) > 0.0f) b.invInertiaLocal = inverse(b.inertiaLocal);
  } else {
    b.mass = 1.0f;
    b.invMass = 1.0f;
  }
  bool first = true;
  for (std::uint32_t shape : b.shapes) {
    const ShapeProxy3 proxy = makeProxy(*shapes[shape].geometry);
    for (int i = 0; i < proxy.count(); ++i) {
      b.maxExtent =
          std::max(b.maxExtent, length(proxy.points()[i] - b.localCenter) + proxy.radius());
    }
    const float thin = thickness(*shapes[shape].geometry);
    b.minExtent = first ? thin : std::min(b.minExtent, thin);
    first = false;
  }
  b.center = transformPoint(b.transform(), b.localCenter);
}

}  // namespace quack::detail
