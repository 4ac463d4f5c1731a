// quack.d3.World: the 3D world (World3, docs/world3.md) from Python, bound as quack.World is
// (world.cpp): bodies and shapes made by the world and reached through handles that know
// when they are stale; stepping with the GIL released; every body's state as one numpy
// array; touching contacts and begin/end events. World3 checks every input; the module
// checks what Python adds (types, array shapes) and puts the Python argument names in
// World3's messages.

#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <span>
#include <string_view>
#include <utility>

#include "bindings.hpp"
#include "quack/io/answer_json.hpp"
#include "quack/world/world.hpp"
#include "quack/world/world3.hpp"

namespace quack::python {

namespace {

class PyWorld3 {
 public:
  explicit PyWorld3(World3 w) : world(std::move(w)) {}

  World3 world;
  std::vector<BodyId3> bodies;  // the live bodies, in creation order
  // Every body this world made, in creation order, destroyed ones too: after restore() the
  // live bodies are the valid ones among them (World3 lists no bodies of its own).
  std::vector<BodyId3> created;
  bool stepping = false;  // a step runs (set and cleared by StepGuard3)
  unsigned long stepThread = 0;

  // body_state(): the array of the last fill and the `version` it was filled at; every step
  // and every write through the module moves `version` on.
  py::object state;
  std::uint64_t stateVersion = 0;
  std::uint64_t version = 1;
  void changed() { ++version; }

  // As quack.World: while one thread steps with the GIL released, every other thread's call
  // is refused (World3 has no callbacks, so the stepping thread makes none).
  bool steppingElsewhere() const { return stepping && PyThread_get_thread_ident() != stepThread; }
  void checkIdle() const {
    if (steppingElsewhere())
      throw std::runtime_error("quack.d3.World: the world is stepping (in another thread)");
  }

  void compact() {
    std::erase_if(bodies, [&](BodyId3 b) { return !world.isValid(b); });
  }

  // The live bodies after a restore: the valid ones of `created`, in creation order; false
  // when the world has bodies `created` does not hold (a snapshot of another world).
  bool relist() {
    std::vector<BodyId3> live;
    for (BodyId3 b : created)
      if (world.isValid(b)) live.push_back(b);
    if (live.size() != world.bodyCount()) return false;
    bodies = std::move(live);
    return true;
  }
};

// Marks the world as stepping for one `step` call, however it ends.
class StepGuard3 {
 public:
  explicit StepGuard3(PyWorld3& w) : w_(w) {
    w_.stepping = true;
    w_.stepThread = PyThread_get_thread_ident();
  }
  ~StepGuard3() {
    w_.stepping = false;
    w_.changed();
  }
  StepGuard3(const StepGuard3&) = delete;
  StepGuard3& operator=(const StepGuard3&) = delete;

 private:
  PyWorld3& w_;
};

struct BodyHandle3 {
  py::object world;  // the PyWorld3: a handle keeps its world alive
  BodyId3 id;
};

struct ShapeHandle3 {
  py::object world;
  ShapeId3 id;
};

PyWorld3& worldOf(const py::object& o) {
  return o.cast<PyWorld3&>();
}

std::string snakeCase(std::string_view camel) {
  std::string out;
  for (char c : camel) {
    if (std::isupper(static_cast<unsigned char>(c)) != 0) {
      out += '_';
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out;
}

// World3's message with the Python argument names in place of its definitions' fields
// ("BodyDef3::linearVelocity: must be ..." -> "linear_velocity: must be ...";
// WorldDef3::timeStep is the argument dt).
std::string pythonMessage(std::string message) {
  for (std::string_view prefix : {"WorldDef3::", "BodyDef3::", "ShapeDef3::"}) {
    std::size_t at = 0;
    while ((at = message.find(prefix, at)) != std::string::npos) {
      const std::size_t start = at + prefix.size();
      std::size_t end = start;
      while (end < message.size() && std::isalnum(static_cast<unsigned char>(message[end])) != 0)
        ++end;
      const std::string_view field = std::string_view(message).substr(start, end - start);
      const std::string name = field == "timeStep" ? "dt" : snakeCase(field);
      message.replace(at, end - at, name);
      at += name.size();
    }
  }
  return message;
}

void check(const Status& s) {
  if (!s) raiseValue(pythonMessage(s.message()));
}

template <class T>
T valueOrRaise3(Result<T> r) {
  if (!r) raiseValue(pythonMessage(r.error().message));
  return std::move(r).value();
}

float toFloat(py::handle value, const char* path) {
  return static_cast<float>(toDouble(value, path));
}

// True or False (Python's or numpy's bool); anything else raises naming `path`, where
// pybind11's bool would take None as False and 1 as True.
bool toBool(py::handle value, const char* path) {
  if (PyBool_Check(value.ptr())) return value.ptr() == Py_True;
  if (py::isinstance(value, py::module_::import("numpy").attr("bool_")))
    return PyObject_IsTrue(value.ptr()) == 1;
  raiseValue(std::string(path) + ": must be True or False, not a " +
             std::string(py::str(value.get_type().attr("__name__"))));
}

// A vector (x, y, z) of another quantity than a position (velocity, impulse, gravity):
// finite as floats, each component at most 1e9, in `unit` (said in the message), as the 2D
// module's toVector.
Vec3 toVector3(py::handle value, const std::string& path, const char* unit) {
  const std::vector<double> v = toNumbers(value, 3, path, "a vector (x, y, z)");
  for (int i = 0; i < 3; ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    const float f = static_cast<float>(v[i]);
    if (!std::isfinite(f)) raiseValue(at + ": must be finite (as a float)");
    if (std::fabs(f) > kMaxCoordinate)
      raiseValue(at + ": " + formatNumber(v[i]) + " " + unit + " is beyond the limit 1e9 " + unit);
  }
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// A rotation for World3, which normalises it (in float): the quaternion q[0..3] (qx, qy, qz,
// qw) checked by checkQuat, then scaled by a power of two (exact) so that its largest
// component lies in [0.5, 1). The scaling keeps a float's square of a huge or tiny component
// from overflowing or vanishing in that normalisation and adds no rounding of its own:
// World3's normalisation is the only one (a body's rotation written back changes only where
// World3's float length of it is not exactly 1, by an ulp).
Quat rotationFromNumbers(const double* q, const std::string& path, int first) {
  if (std::string bad = checkQuat(q, path, first); !bad.empty()) raiseValue(bad);
  float f[4];
  float largest = 0.0f;
  for (int i = 0; i < 4; ++i) {
    f[i] = static_cast<float>(q[i]);
    largest = std::max(largest, std::fabs(f[i]));
  }
  int exponent = 0;
  (void)std::frexp(largest, &exponent);
  for (float& c : f)
    c = std::ldexp(c, -exponent);
  return {f[0], f[1], f[2], f[3]};
}

// A rotation argument (qx, qy, qz, qw), scalar last: any non-zero quaternion.
Quat toRotation3(py::handle value, const std::string& path) {
  const std::vector<double> v = toNumbers(value, 4, path, "a quaternion (qx, qy, qz, qw)");
  return rotationFromNumbers(v.data(), path, 0);
}

py::tuple toTuple3(Vec3 v) {
  return py::make_tuple(static_cast<double>(v.x), static_cast<double>(v.y),
                        static_cast<double>(v.z));
}

py::tuple toTuple3(Quat q) {
  return py::make_tuple(static_cast<double>(q.x), static_cast<double>(q.y),
                        static_cast<double>(q.z), static_cast<double>(q.w));
}

// The id of a body handle of this world that is still valid, else ValueError naming `path`.
BodyId3 bodyId(PyWorld3& w, py::handle h, const std::string& path) {
  if (!py::isinstance<BodyHandle3>(h)) raiseValue(path + ": must be a quack.d3.BodyHandle");
  const BodyHandle3& b = h.cast<const BodyHandle3&>();
  if (&worldOf(b.world) != &w) raiseValue(path + ": a body of another world");
  if (!w.world.isValid(b.id)) raiseValue(path + ": stale handle (the body was destroyed)");
  return b.id;
}

ShapeId3 shapeId(PyWorld3& w, py::handle h, const std::string& path) {
  if (!py::isinstance<ShapeHandle3>(h)) raiseValue(path + ": must be a quack.d3.ShapeHandle");
  const ShapeHandle3& s = h.cast<const ShapeHandle3&>();
  if (&worldOf(s.world) != &w) raiseValue(path + ": a shape of another world");
  if (!w.world.isValid(s.id)) raiseValue(path + ": stale handle (the shape was destroyed)");
  return s.id;
}

// The world of a handle, once it is idle and the body still exists.
PyWorld3& liveWorld(const BodyHandle3& b) {
  PyWorld3& w = worldOf(b.world);
  w.checkIdle();
  if (!w.world.isValid(b.id)) raiseValue("stale quack.d3.BodyHandle (the body was destroyed)");
  return w;
}

PyWorld3& liveWorld(const ShapeHandle3& s) {
  PyWorld3& w = worldOf(s.world);
  w.checkIdle();
  if (!w.world.isValid(s.id)) raiseValue("stale quack.d3.ShapeHandle (the shape was destroyed)");
  return w;
}

// body_state()'s columns.
constexpr std::size_t kStateColumns3 = 13;

// One body's row of body_state: position, rotation, linear and angular velocity.
struct BodyRow3 {
  Vec3 position;
  Quat rotation;
  Vec3 linearVelocity;
  Vec3 angularVelocity;
};

BodyRow3 readRow(const World3& world, BodyId3 id) {
  return {world.position(id), world.rotation(id), world.linearVelocity(id),
          world.angularVelocity(id)};
}

// Writes a row; a static body keeps its zero velocities (World3 refuses to give it any).
Status writeRow(World3& world, BodyId3 id, const BodyRow3& r) {
  Status s = world.setTransform(id, r.position, r.rotation);
  if (!s || world.bodyType(id) == BodyType::staticBody) return s;
  s = world.setLinearVelocity(id, r.linearVelocity);
  if (s) s = world.setAngularVelocity(id, r.angularVelocity);
  return s;
}

QueryFilter toFilter3(std::uint64_t category, std::uint64_t mask) {
  QueryFilter f;
  f.category = category;
  f.mask = mask;
  return f;
}

// The query shape of overlap_shape and cast_shape: a convex quack.d3.Shape.
const ShapeGeometry3& queryGeometry(py::handle shape) {
  if (py::isinstance<PyShape3>(shape)) return shape.cast<const PyShape3&>().geometry;
  if (py::isinstance<PyMesh3>(shape))
    raiseValue(
        "shape: a quack.d3.Mesh cannot be a query shape (overlap_shape and cast_shape take a "
        "convex quack.d3.Shape; a mesh's triangle is one: quack.d3.triangle)");
  if (py::isinstance<PyShape>(shape))
    raiseValue(
        "shape: a 2D quack.Shape in a 3D query (quack.d3.World takes quack.d3.sphere, "
        "capsule, box, hull, triangle, shape)");
  raiseValue("shape: must be a quack.d3.Shape, not a " +
             std::string(py::str(shape.get_type().attr("__name__"))));
}

// The bytes of a snapshot argument: bytes or bytearray.
std::span<const std::uint8_t> snapshotBytes(py::handle data) {
  char* at = nullptr;
  Py_ssize_t size = 0;
  if (PyBytes_Check(data.ptr())) {
    at = PyBytes_AS_STRING(data.ptr());
    size = PyBytes_GET_SIZE(data.ptr());
  } else if (PyByteArray_Check(data.ptr())) {
    at = PyByteArray_AS_STRING(data.ptr());
    size = PyByteArray_GET_SIZE(data.ptr());
  } else {
    raiseValue("snapshot: must be bytes (from quack.d3.World.snapshot()), not a " +
               std::string(py::str(data.get_type().attr("__name__"))));
  }
  return {reinterpret_cast<const std::uint8_t*>(at), static_cast<std::size_t>(size)};
}

py::object rayHit(const py::module_& m, const py::object& self, const RayHitResult3& h) {
  return m.attr("RayHit")(ShapeHandle3{self, h.shape}, BodyHandle3{self, h.body}, toTuple3(h.point),
                          toTuple3(h.normal), static_cast<double>(h.fraction), h.triangle);
}

}  // namespace

void registerWorld3(py::module_& m) {
  py::exec(R"py(
import collections as _collections
Events = _collections.namedtuple("Events", "begin end")
Events.__doc__ = ("The events of the last step of a quack.d3.World: begin and end, lists of "
                  "(shape_a, shape_b) (quack.d3.ShapeHandle) of contacts that started or "
                  "stopped touching (end also for shapes destroyed since the step before).")
Contact = _collections.namedtuple("Contact", "shape_a shape_b manifolds")
Contact.__doc__ = ("A touching contact of a quack.d3.World: shape_a, shape_b "
                   "(quack.d3.ShapeHandle; shape_a is the mesh when there is one) and "
                   "manifolds (quack.d3.ManifoldResult, world frame, normals from a to b: one "
                   "for two convex shapes, one per touching triangle of a mesh).")
RayHit = _collections.namedtuple("RayHit", "shape body point normal fraction triangle")
RayHit.__doc__ = ("A shape a ray of a quack.d3.World enters: shape, body (handles), point "
                  "and normal (world frame; unit, outward; a mesh's: its triangle's face "
                  "normal), fraction (origin + fraction * translation) and triangle (the mesh "
                  "triangle entered, else -1).")
ShapeOverlap = _collections.namedtuple("ShapeOverlap", "shape body depth depenetration")
ShapeOverlap.__doc__ = ("A shape of a quack.d3.World overlapping a query shape: shape, body, "
                        "depth (metres, >= 0; a mesh: its deepest triangle's) and "
                        "depenetration (x, y, z), the move (world frame, metres) that takes "
                        "the query shape out of it.")
ShapeCastHit = _collections.namedtuple("ShapeCastHit", "shape body point normal fraction")
ShapeCastHit.__doc__ = ("The first shape of a quack.d3.World a swept query shape meets: shape, "
                        "body, point (on the shape met), normal (unit, from the shape met "
                        "towards the query shape), fraction of the translation (0 when it "
                        "starts overlapping).")
for _t in (Events, Contact, RayHit, ShapeOverlap, ShapeCastHit):
    _t.__module__ = "quack.d3"
del _t, _collections
)py",
           m.attr("__dict__"));
  m.attr("BODY_STATE_COLUMNS") =
      py::make_tuple("x", "y", "z", "qx", "qy", "qz", "qw", "vx", "vy", "vz", "wx", "wy", "wz");

  py::class_<BodyHandle3>(m, "BodyHandle",
                          "A body of a quack.d3.World. Stays usable after the body is "
                          "destroyed, but then says so: valid is False and everything else "
                          "raises ValueError.")
      .def_property_readonly(
          "valid",
          [](const BodyHandle3& b) {
            worldOf(b.world).checkIdle();
            return worldOf(b.world).world.isValid(b.id);
          },
          "Whether the body still exists (False once destroyed).")
      .def_property_readonly(
          "world", [](const BodyHandle3& b) { return b.world; },
          "The quack.d3.World the body belongs to.")
      .def_property_readonly(
          "type",
          [](const BodyHandle3& b) {
            return std::string(toString(liveWorld(b).world.bodyType(b.id)));
          },
          "static, kinematic or dynamic.")
      .def_property(
          "position",
          [](const BodyHandle3& b) { return toTuple3(liveWorld(b).world.position(b.id)); },
          [](const BodyHandle3& b, py::handle p) {
            PyWorld3& w = liveWorld(b);
            const Vec3 to = toPosition3(p, "position");
            w.changed();
            check(w.world.setTransform(b.id, to, w.world.rotation(b.id)));
          },
          "Body origin (x, y, z), world frame, metres; setting it teleports the body (and "
          "wakes it).")
      .def_property(
          "rotation",
          [](const BodyHandle3& b) { return toTuple3(liveWorld(b).world.rotation(b.id)); },
          [](const BodyHandle3& b, py::handle q) {
            PyWorld3& w = liveWorld(b);
            const Quat to = toRotation3(q, "rotation");
            w.changed();
            check(w.world.setTransform(b.id, w.world.position(b.id), to));
          },
          "worldFromBody's rotation as a unit quaternion (qx, qy, qz, qw), scalar last; set "
          "it with any non-zero one (normalised), which turns the body about its origin (and "
          "wakes it).")
      .def(
          "set_transform",
          [](const BodyHandle3& b, py::handle position, py::handle rotation) {
            PyWorld3& w = liveWorld(b);
            const Vec3 p = toPosition3(position, "position");
            const Quat q = toRotation3(rotation, "rotation");
            w.changed();
            check(w.world.setTransform(b.id, p, q));
          },
          py::arg("position"), py::arg("rotation"),
          "Teleports and turns the body at once: position (x, y, z) and rotation (qx, qy, "
          "qz, qw). Wakes it.")
      .def_property(
          "linear_velocity",
          [](const BodyHandle3& b) { return toTuple3(liveWorld(b).world.linearVelocity(b.id)); },
          [](const BodyHandle3& b, py::handle v) {
            PyWorld3& w = liveWorld(b);
            const Vec3 to = toVector3(v, "linear_velocity", "m/s");
            w.changed();
            check(w.world.setLinearVelocity(b.id, to));
          },
          "Of the centre of mass, m/s (a static body has none to set). Setting it wakes the "
          "body.")
      .def_property(
          "angular_velocity",
          [](const BodyHandle3& b) { return toTuple3(liveWorld(b).world.angularVelocity(b.id)); },
          [](const BodyHandle3& b, py::handle v) {
            PyWorld3& w = liveWorld(b);
            const Vec3 to = toVector3(v, "angular_velocity", "rad/s");
            w.changed();
            check(w.world.setAngularVelocity(b.id, to));
          },
          "rad/s about world axes (a static body has none to set). Setting it wakes the body.")
      .def_property(
          "awake", [](const BodyHandle3& b) { return liveWorld(b).world.isAwake(b.id); },
          [](const BodyHandle3& b, py::handle awake) {
            PyWorld3& w = liveWorld(b);
            const bool to = toBool(awake, "awake");
            w.changed();
            check(w.world.setAwake(b.id, to));
          },
          "Whether the body is simulated (not asleep). Setting False puts it to sleep and "
          "zeroes its velocities; a static body stays as it is.")
      .def_property_readonly(
          "mass",
          [](const BodyHandle3& b) { return static_cast<double>(liveWorld(b).world.mass(b.id)); },
          "kg (0 for static and kinematic bodies).")
      .def_property_readonly(
          "inertia",
          [](const BodyHandle3& b) {
            const Mat3 i = liveWorld(b).world.inertia(b.id);
            // Mat3 keeps columns; the tuple is rows (the tensor is symmetric, but rows read
            // as the written matrix).
            return py::make_tuple(toTuple3(Vec3{i.cx.x, i.cy.x, i.cz.x}),
                                  toTuple3(Vec3{i.cx.y, i.cy.y, i.cz.y}),
                                  toTuple3(Vec3{i.cx.z, i.cy.z, i.cz.z}));
          },
          "Inertia tensor about the centre of mass, world axes, kg m^2: three rows.")
      .def_property_readonly(
          "center_of_mass",
          [](const BodyHandle3& b) { return toTuple3(liveWorld(b).world.worldCenterOfMass(b.id)); },
          "Centre of mass (x, y, z), world frame.")
      .def(
          "apply_impulse",
          [](const BodyHandle3& b, py::handle impulse, py::handle point) {
            PyWorld3& w = liveWorld(b);
            const Vec3 j = toVector3(impulse, "impulse", "N s");
            const Vec3 at =
                point.is_none() ? w.world.worldCenterOfMass(b.id) : toPosition3(point, "point");
            w.changed();
            check(w.world.applyLinearImpulse(b.id, j, at));
          },
          py::arg("impulse"), py::arg("point") = py::none(),
          "Linear impulse (N s) at a world point (default: the centre of mass): changes both "
          "velocities of a dynamic body, and wakes it.")
      .def("__eq__", [](const BodyHandle3& a,
                        const BodyHandle3& b) { return a.world.is(b.world) && a.id == b.id; })
      .def("__hash__",
           [](const BodyHandle3& b) {
             return py::hash(py::make_tuple(b.id.world, b.id.index, b.id.generation));
           })
      .def("__repr__", [](const BodyHandle3& b) {
        const PyWorld3& w = worldOf(b.world);
        return "quack.d3.BodyHandle(index=" + std::to_string(b.id.index) +
               ", generation=" + std::to_string(b.id.generation) +
               (w.steppingElsewhere() || w.world.isValid(b.id) ? "" : ", stale") + ")";
      });

  py::class_<ShapeHandle3>(m, "ShapeHandle",
                           "A shape on a body of a quack.d3.World; valid says whether it "
                           "still exists (body raises ValueError once it is destroyed).")
      .def_property_readonly(
          "valid",
          [](const ShapeHandle3& s) {
            worldOf(s.world).checkIdle();
            return worldOf(s.world).world.isValid(s.id);
          },
          "Whether the shape still exists (False once destroyed).")
      .def_property_readonly(
          "body",
          [](const ShapeHandle3& s) {
            return BodyHandle3{s.world, liveWorld(s).world.body(s.id)};
          },
          "The quack.d3.BodyHandle the shape is on.")
      .def("__eq__", [](const ShapeHandle3& a,
                        const ShapeHandle3& b) { return a.world.is(b.world) && a.id == b.id; })
      .def("__hash__",
           [](const ShapeHandle3& s) {
             return py::hash(py::make_tuple(s.id.world, s.id.index, s.id.generation));
           })
      .def("__repr__", [](const ShapeHandle3& s) {
        const PyWorld3& w = worldOf(s.world);
        return "quack.d3.ShapeHandle(index=" + std::to_string(s.id.index) +
               ", generation=" + std::to_string(s.id.generation) +
               (w.steppingElsewhere() || w.world.isValid(s.id) ? "" : ", stale") + ")";
      });

  const WorldDef3 worldDefaults;
  const BodyDef3 bodyDefaults;
  const ShapeDef3 shapeDefaults;
  auto number = [](float v) { return static_cast<double>(v); };
  auto vector = [](Vec3 v) { return toTuple3(v); };

  py::class_<PyWorld3>(m, "World",
                       "The 3D rigid-body world (World3, docs/world3.md): bodies carrying "
                       "convex shapes (or triangle meshes on static bodies) that fall, "
                       "collide, stack, slide, roll and fall asleep. World frame, y up, SI "
                       "units.")
      .def(py::init([](py::handle gravity, py::handle dt, py::handle substeps,
                       py::handle contactHertz, py::handle contactDampingRatio,
                       py::handle contactPushMaxSpeed, py::handle restitutionThreshold,
                       py::handle speculativeDistance, py::handle aabbMargin,
                       py::handle contactRecycleDistance, py::handle enableContinuous,
                       py::handle enableSleep) {
             WorldDef3 def;
             def.gravity = toVector3(gravity, "gravity", "m/s^2");
             def.timeStep = toFloat(dt, "dt");
             def.substeps = static_cast<int>(toInteger(substeps, "substeps", 1, 64));
             def.contactHertz = toFloat(contactHertz, "contact_hertz");
             def.contactDampingRatio = toFloat(contactDampingRatio, "contact_damping_ratio");
             def.contactPushMaxSpeed = toFloat(contactPushMaxSpeed, "contact_push_max_speed");
             def.restitutionThreshold = toFloat(restitutionThreshold, "restitution_threshold");
             def.speculativeDistance = toFloat(speculativeDistance, "speculative_distance");
             def.aabbMargin = toFloat(aabbMargin, "aabb_margin");
             def.contactRecycleDistance =
                 toFloat(contactRecycleDistance, "contact_recycle_distance");
             def.enableContinuous = toBool(enableContinuous, "enable_continuous");
             def.enableSleep = toBool(enableSleep, "enable_sleep");
             return std::make_unique<PyWorld3>(valueOrRaise3(World3::create(def)));
           }),
           py::arg("gravity") = vector(worldDefaults.gravity),
           py::arg("dt") = number(worldDefaults.timeStep),
           py::arg("substeps") = worldDefaults.substeps,
           py::arg("contact_hertz") = number(worldDefaults.contactHertz),
           py::arg("contact_damping_ratio") = number(worldDefaults.contactDampingRatio),
           py::arg("contact_push_max_speed") = number(worldDefaults.contactPushMaxSpeed),
           py::arg("restitution_threshold") = number(worldDefaults.restitutionThreshold),
           py::arg("speculative_distance") = number(worldDefaults.speculativeDistance),
           py::arg("aabb_margin") = number(worldDefaults.aabbMargin),
           py::arg("contact_recycle_distance") = number(worldDefaults.contactRecycleDistance),
           py::arg("enable_continuous") = worldDefaults.enableContinuous,
           py::arg("enable_sleep") = worldDefaults.enableSleep,
           "A 3D world (WorldDef3's fields): gravity (m/s^2), dt (seconds per step(), in (0, "
           "1]), substeps (1..64), contact_hertz (> 0) and contact_damping_ratio (>= 0) of the "
           "soft contacts, contact_push_max_speed (m/s, > 0), restitution_threshold (m/s, >= "
           "0), speculative_distance (m, in [0, 1]), aabb_margin (m, >= "
           "speculative_distance), contact_recycle_distance (m, in [0, 1]: a resting pair of "
           "flat shapes keeps its manifold while their relative pose moves less; 0: a new "
           "manifold every step), enable_continuous (fast bodies stopped at static geometry), "
           "enable_sleep.")
      .def(
          "create_body",
          [](py::object self, const std::string& type, py::handle position, py::handle rotation,
             py::handle linearVelocity, py::handle angularVelocity, py::handle linearDamping,
             py::handle angularDamping, py::handle gravityScale, py::handle enableSleep,
             py::handle sleepThreshold) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            BodyDef3 def;
            def.type = toBodyType(type);
            def.position = toPosition3(position, "position");
            def.rotation = toRotation3(rotation, "rotation");
            def.linearVelocity = toVector3(linearVelocity, "linear_velocity", "m/s");
            def.angularVelocity = toVector3(angularVelocity, "angular_velocity", "rad/s");
            def.linearDamping = toFloat(linearDamping, "linear_damping");
            def.angularDamping = toFloat(angularDamping, "angular_damping");
            def.gravityScale = toFloat(gravityScale, "gravity_scale");
            def.enableSleep = toBool(enableSleep, "enable_sleep");
            def.sleepThreshold = toFloat(sleepThreshold, "sleep_threshold");
            const BodyId3 id = valueOrRaise3(w.world.createBody(def));
            w.changed();
            w.bodies.push_back(id);
            w.created.push_back(id);
            return BodyHandle3{self, id};
          },
          py::arg("type") = "dynamic", py::arg("position") = vector(bodyDefaults.position),
          py::arg("rotation") = toTuple3(bodyDefaults.rotation),
          py::arg("linear_velocity") = vector(bodyDefaults.linearVelocity),
          py::arg("angular_velocity") = vector(bodyDefaults.angularVelocity),
          py::arg("linear_damping") = number(bodyDefaults.linearDamping),
          py::arg("angular_damping") = number(bodyDefaults.angularDamping),
          py::arg("gravity_scale") = number(bodyDefaults.gravityScale),
          py::arg("enable_sleep") = bodyDefaults.enableSleep,
          py::arg("sleep_threshold") = number(bodyDefaults.sleepThreshold),
          "A new body (BodyDef3's fields): type static, kinematic or dynamic; position (x, y, "
          "z) and rotation (qx, qy, qz, qw; any non-zero quaternion, normalised) of its "
          "origin, world frame; linear_velocity (m/s) and angular_velocity (rad/s, world "
          "axes); linear_damping and angular_damping (1/s, >= 0); gravity_scale; "
          "enable_sleep; sleep_threshold (m/s, >= 0). Returns a quack.d3.BodyHandle.")
      .def(
          "create_shape",
          [](py::object self, py::handle body, py::handle shape, py::handle density,
             py::handle friction, py::handle restitution, py::handle rollingResistance,
             std::uint64_t category, std::uint64_t mask, std::int32_t group) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            const BodyId3 b = bodyId(w, body, "body");
            ShapeDef3 def;
            def.density = toFloat(density, "density");
            def.friction = toFloat(friction, "friction");
            def.restitution = toFloat(restitution, "restitution");
            def.rollingResistance = toFloat(rollingResistance, "rolling_resistance");
            def.filter.category = category;
            def.filter.mask = mask;
            def.filter.group = group;
            ShapeId3 id;
            if (py::isinstance<PyMesh3>(shape)) {
              id = valueOrRaise3(w.world.createShape(b, def, shape.cast<const PyMesh3&>().mesh));
            } else if (py::isinstance<PyShape3>(shape)) {
              id = valueOrRaise3(
                  w.world.createShape(b, def, shape.cast<const PyShape3&>().geometry));
            } else if (py::isinstance<PyShape>(shape)) {
              raiseValue(
                  "shape: a 2D quack.Shape in a 3D world (quack.d3.World takes quack.d3.sphere, "
                  "capsule, box, hull, triangle, shape, or a quack.d3.mesh on a static body)");
            } else {
              raiseValue("shape: must be a quack.d3.Shape or a quack.d3.Mesh, not " +
                         std::string(py::str(shape.get_type().attr("__name__"))));
            }
            w.changed();
            return ShapeHandle3{self, id};
          },
          py::arg("body"), py::arg("shape"), py::arg("density") = number(shapeDefaults.density),
          py::arg("friction") = number(shapeDefaults.friction),
          py::arg("restitution") = number(shapeDefaults.restitution),
          py::arg("rolling_resistance") = number(shapeDefaults.rollingResistance),
          py::arg("category") = shapeDefaults.filter.category,
          py::arg("mask") = shapeDefaults.filter.mask,
          py::arg("group") = shapeDefaults.filter.group,
          "Puts a quack.d3.Shape (body frame) on a body, or a quack.d3.Mesh on a static body "
          "(ShapeDef3's fields): density (kg/m^3, >= 0), friction (>= 0; a pair uses "
          "sqrt(fa fb)), restitution (0..10; a pair uses the larger), rolling_resistance (>= "
          "0; a pair uses the larger), category and mask (bit sets), group. The body's mass "
          "and inertia are recomputed. Returns a quack.d3.ShapeHandle.")
      .def(
          "destroy_body",
          [](PyWorld3& w, py::handle body) {
            w.checkIdle();
            check(w.world.destroyBody(bodyId(w, body, "body")));
            w.changed();
            w.compact();
          },
          py::arg("body"),
          "Destroys a body, its shapes and their contacts (touching ones end in the next "
          "step's events).")
      .def(
          "destroy_shape",
          [](PyWorld3& w, py::handle shape) {
            w.checkIdle();
            check(w.world.destroyShape(shapeId(w, shape, "shape")));
            w.changed();
          },
          py::arg("shape"),
          "Destroys a shape (a touching contact ends in the next step's events); the body's "
          "mass is recomputed.")
      .def(
          "step",
          [](PyWorld3& w, py::handle dt, py::handle substeps) {
            w.checkIdle();
            const bool own = !dt.is_none() || !substeps.is_none();
            const float stepDt = dt.is_none() ? w.world.def().timeStep : toFloat(dt, "dt");
            const int sub = substeps.is_none()
                                ? w.world.def().substeps
                                : static_cast<int>(toInteger(substeps, "substeps", 1, 64));
            Status s;
            {
              StepGuard3 guard(w);
              py::gil_scoped_release release;
              s = own ? w.world.step(stepDt, sub) : w.world.step();
            }
            check(s);
          },
          py::arg("dt") = py::none(), py::arg("substeps") = py::none(),
          "Advances by dt seconds (default: the world's dt; in (0, 1]) in substeps (default: "
          "the world's; 1..64). The GIL is released meanwhile; other threads' calls on this "
          "world raise RuntimeError until it returns.")
      .def(
          "events",
          [m](py::object self) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            const StepEvents3& e = w.world.events();
            auto pairs = [&](const std::vector<ContactEvent3>& list) {
              py::list out;
              for (const ContactEvent3& x : list)
                out.append(
                    py::make_tuple(ShapeHandle3{self, x.shapeA}, ShapeHandle3{self, x.shapeB}));
              return out;
            };
            return m.attr("Events")(pairs(e.begin), pairs(e.end));
          },
          "The events of the last step (quack.d3.Events: begin, end). Shapes destroyed since "
          "are stale handles.")
      .def(
          "touching_contacts",
          [m](py::object self) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            py::list out;
            for (const ContactView3& c : w.world.touchingContacts()) {
              py::list manifolds;
              for (const Manifold3& manifold : c.manifolds)
                manifolds.append(m.attr("ManifoldResult")(toPython(quack::toJson(manifold))));
              out.append(m.attr("Contact")(ShapeHandle3{self, c.shapeA},
                                           ShapeHandle3{self, c.shapeB}, manifolds));
            }
            return out;
          },
          "Every touching contact (quack.d3.Contact: shape_a, shape_b, manifolds), in the "
          "world's contact order.")
      .def_property_readonly(
          "bodies",
          [](py::object self) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            py::list out;
            for (BodyId3 id : w.bodies)
              out.append(BodyHandle3{self, id});
            return out;
          },
          "Every live body (quack.d3.BodyHandle), in creation order (body_state's rows).")
      .def_property_readonly(
          "body_count",
          [](PyWorld3& w) {
            w.checkIdle();
            return w.world.bodyCount();
          },
          "Live bodies.")
      .def_property_readonly(
          "shape_count",
          [](PyWorld3& w) {
            w.checkIdle();
            return w.world.shapeCount();
          },
          "Live shapes.")
      .def_property_readonly(
          "contact_count",
          [](PyWorld3& w) {
            w.checkIdle();
            return w.world.touchingContactCount();
          },
          "Touching contacts.")
      .def_property_readonly(
          "awake_body_count",
          [](PyWorld3& w) {
            w.checkIdle();
            return w.world.awakeBodyCount();
          },
          "Bodies that are awake (static bodies are never awake).")
      .def_property_readonly(
          "step_count",
          [](PyWorld3& w) {
            w.checkIdle();
            return w.world.stepCount();
          },
          "Steps taken.")
      .def(
          "body_state",
          [](PyWorld3& w) -> py::object {
            w.checkIdle();
            if (w.state && w.stateVersion == w.version) return w.state;
            const std::size_t n = w.bodies.size();
            py::array_t<double> a({static_cast<py::ssize_t>(n), py::ssize_t{kStateColumns3}});
            double* d = a.mutable_data();
            for (std::size_t i = 0; i < n; ++i, d += kStateColumns3) {
              const BodyRow3 r = readRow(w.world, w.bodies[i]);
              const float row[kStateColumns3] = {
                  r.position.x,       r.position.y,       r.position.z,        r.rotation.x,
                  r.rotation.y,       r.rotation.z,       r.rotation.w,        r.linearVelocity.x,
                  r.linearVelocity.y, r.linearVelocity.z, r.angularVelocity.x, r.angularVelocity.y,
                  r.angularVelocity.z};
              for (std::size_t k = 0; k < kStateColumns3; ++k)
                d[k] = static_cast<double>(row[k]);
            }
            // Read-only, as quack.World.body_state's.
            py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
            w.state = a;
            w.stateVersion = w.version;
            return w.state;
          },
          "Every body's state as one read-only array (N, 13), bodies in creation order, "
          "columns quack.d3.BODY_STATE_COLUMNS: x, y, z, qx, qy, qz, qw, vx, vy, vz, wx, wy, "
          "wz (float64). Filled once after each step or write; until the next one every call "
          "returns the same array (no copy). After the next step (or any write) it is stale: "
          "it keeps its values, and body_state() returns a new array.")
      .def(
          "set_body_state",
          [](PyWorld3& w, py::handle values) {
            w.checkIdle();
            const std::size_t n = w.bodies.size();
            const auto a = toValues(values, n, kStateColumns3, "state");
            std::vector<BodyRow3> rows(n);
            for (std::size_t i = 0; i < n; ++i) {
              const double* r = a.data() + i * kStateColumns3;
              const std::string path = "state[" + std::to_string(i) + "]";
              for (int k = 0; k < 3; ++k) {
                const std::string at = path + "[" + std::to_string(k) + "]";
                if (std::string bad = checkCoordinate(r[k], at); !bad.empty()) raiseValue(bad);
              }
              auto f = [&](int k) { return static_cast<float>(r[k]); };
              rows[i] = {{f(0), f(1), f(2)},
                         rotationFromNumbers(r + 3, path, 3),
                         {f(7), f(8), f(9)},
                         {f(10), f(11), f(12)}};
            }
            std::vector<BodyRow3> saved(n);
            for (std::size_t i = 0; i < n; ++i)
              saved[i] = readRow(w.world, w.bodies[i]);
            w.changed();
            for (std::size_t i = 0; i < n; ++i) {
              Status s = writeRow(w.world, w.bodies[i], rows[i]);
              if (s) continue;
              // All or none: the bodies written so far, this one included, get their rows
              // back (rows World3 accepted before).
              for (std::size_t k = 0; k <= i; ++k)
                (void)writeRow(w.world, w.bodies[k], saved[k]);
              raiseValue("state[" + std::to_string(i) + "]: " + pythonMessage(s.message()));
            }
          },
          py::arg("state"),
          "Writes every body's state from an array (N, 13) laid out as body_state() (N = "
          "body_count, creation order). Checked first (positions within the coordinate limit, "
          "every number finite, quaternions not zero); then all bodies or none are written (a "
          "row World3 refuses puts the others back). Static bodies keep zero velocities. "
          "Every body is woken.")
      .def(
          "ray_cast_closest",
          [m](py::object self, py::handle origin, py::handle translation, std::uint64_t category,
              std::uint64_t mask) -> py::object {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            const Vec3 o = toPosition3(origin, "origin");
            const Vec3 t = toPosition3(translation, "translation");
            const std::optional<RayHitResult3> h =
                w.world.rayCastClosest(o, t, toFilter3(category, mask));
            if (!h) return py::none();
            return rayHit(m, self, *h);
          },
          py::arg("origin"), py::arg("translation"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0},
          "The first shape the ray origin + t translation (t in [0, 1], world frame) enters: a "
          "quack.d3.RayHit, or None (also for a zero translation). A mesh is entered from its "
          "triangles' fronts only; a ray that starts inside a convex shape does not enter it. "
          "Ties go to the lower shape index. category and mask filter the shapes as a shape's "
          "own do (each side's category in the other's mask).")
      .def(
          "ray_cast_all",
          [m](py::object self, py::handle origin, py::handle translation, std::uint64_t category,
              std::uint64_t mask) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            const Vec3 o = toPosition3(origin, "origin");
            const Vec3 t = toPosition3(translation, "translation");
            py::list out;
            for (const RayHitResult3& h : w.world.rayCastAll(o, t, toFilter3(category, mask)))
              out.append(rayHit(m, self, h));
            return out;
          },
          py::arg("origin"), py::arg("translation"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0},
          "Every shape the ray enters (quack.d3.RayHit, one per shape), by fraction (ties: "
          "lower shape index).")
      .def(
          "overlap_aabb",
          [](py::object self, py::handle lower, py::handle upper, std::uint64_t category,
             std::uint64_t mask) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            const Aabb3 box{toPosition3(lower, "lower"), toPosition3(upper, "upper")};
            const float lo[3] = {box.lower.x, box.lower.y, box.lower.z};
            const float hi[3] = {box.upper.x, box.upper.y, box.upper.z};
            for (int i = 0; i < 3; ++i) {
              if (hi[i] < lo[i])
                raiseValue("upper[" + std::to_string(i) +
                           "]: " + formatNumber(static_cast<double>(hi[i])) + " is below lower[" +
                           std::to_string(i) + "] " + formatNumber(static_cast<double>(lo[i])));
            }
            py::list out;
            for (ShapeId3 s : w.world.overlapAabb(box, toFilter3(category, mask)))
              out.append(ShapeHandle3{self, s});
            return out;
          },
          py::arg("lower"), py::arg("upper"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0},
          "Shapes (quack.d3.ShapeHandle) whose bounding boxes overlap the box lower-upper "
          "(world frame; upper >= lower in each axis), by shape index. The boxes are the "
          "broad phase's, which moving bodies' grow by the world's aabb_margin.")
      .def(
          "overlap_shape",
          [m](py::object self, py::handle shape, py::handle pose, std::uint64_t category,
              std::uint64_t mask) {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            const ShapeGeometry3& g = queryGeometry(shape);
            const Transform3 xf = toTransform3(pose, "pose");
            py::list out;
            for (const ShapeOverlap3& o :
                 valueOrRaise3(w.world.overlapShape(g, xf, toFilter3(category, mask)))) {
              out.append(
                  m.attr("ShapeOverlap")(ShapeHandle3{self, o.shape}, BodyHandle3{self, o.body},
                                         static_cast<double>(o.depth), toTuple3(o.depenetration)));
            }
            return out;
          },
          py::arg("shape"), py::arg("pose"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0},
          "Shapes overlapping a convex quack.d3.Shape placed at pose (None, (x, y, z) or (x, "
          "y, z, qx, qy, qz, qw)): quack.d3.ShapeOverlap, by shape index, each with its depth "
          "and the depenetration that moves the query shape out (EPA; a mesh: its deepest "
          "triangle).")
      .def(
          "cast_shape",
          [m](py::object self, py::handle shape, py::handle pose, py::handle translation,
              std::uint64_t category, std::uint64_t mask) -> py::object {
            PyWorld3& w = worldOf(self);
            w.checkIdle();
            const ShapeGeometry3& g = queryGeometry(shape);
            const Transform3 xf = toTransform3(pose, "pose");
            const Vec3 t = toPosition3(translation, "translation");
            const std::optional<ShapeCastResult3> r =
                valueOrRaise3(w.world.castShape(g, xf, t, toFilter3(category, mask)));
            if (!r) return py::none();
            return m.attr("ShapeCastHit")(ShapeHandle3{self, r->shape}, BodyHandle3{self, r->body},
                                          toTuple3(r->point), toTuple3(r->normal),
                                          static_cast<double>(r->fraction));
          },
          py::arg("shape"), py::arg("pose"), py::arg("translation"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0},
          "Sweeps a convex quack.d3.Shape from pose along translation (x, y, z): the first "
          "shape it meets (quack.d3.ShapeCastHit; lowest fraction, ties to the lower shape "
          "index; fraction 0 for one it starts in), or None.")
      .def(
          "snapshot",
          [](PyWorld3& w) {
            w.checkIdle();
            const std::vector<std::uint8_t> bytes = w.world.snapshot();
            return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
          },
          "The world's whole state as bytes (docs/world3.md, \"Snapshots\"): restore() brings "
          "it back, and the world then steps on to the same bits as it did from here.")
      .def(
          "restore",
          [](PyWorld3& w, py::handle snapshot) {
            w.checkIdle();
            const std::span<const std::uint8_t> bytes = snapshotBytes(snapshot);
            // The way back if the restored world has bodies this one cannot list.
            const std::vector<std::uint8_t> before = w.world.snapshot();
            w.changed();
            check(w.world.restore(bytes));
            if (w.relist()) return;
            // A snapshot of this world, just taken: its restore cannot be refused.
            check(w.world.restore(before));
            raiseValue(
                "snapshot: holds bodies this quack.d3.World did not make (a snapshot of "
                "another world, which it cannot list in bodies and body_state's rows); the "
                "world is unchanged");
          },
          py::arg("snapshot"),
          "Puts the world back to a snapshot() of it: bodies and shapes, their handles (valid "
          "again if destroyed since), contacts and the last step's events. Raises ValueError "
          "with World3's message, leaving the world unchanged, for bytes that are not a 3D "
          "snapshot, of another format version, truncated or corrupted; and for a snapshot "
          "of another world with bodies this one did not make.")
      .def("__repr__", [](PyWorld3& w) {
        if (w.steppingElsewhere()) return std::string("quack.d3.World(stepping)");
        return "quack.d3.World(bodies=" + std::to_string(w.world.bodyCount()) +
               ", shapes=" + std::to_string(w.world.shapeCount()) +
               ", steps=" + std::to_string(w.world.stepCount()) + ")";
      });
}

}  // namespace quack::python
