// quack.World: bodies and shapes, stepping (GIL released), bulk state as numpy arrays,
// events, per-category callbacks, world queries, scene and state files.
//
// Callbacks: the world calls them at the end of a step, from C++ frames of the library. A
// Python exception must not unwind through those frames, so each callback catches what its
// Python callable raised, keeps the first such exception, skips the remaining callables of
// that step, and `step` raises it once the world has finished the step.

#include <pybind11/stl.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>
#include <utility>

#include "bindings.hpp"
#include "quack/io/render.hpp"
#include "quack/io/scene.hpp"
#include "quack/io/state.hpp"
#include "quack/world/world.hpp"

namespace quack::python {

namespace {

class PyWorld;

struct BodyHandle {
  py::object world;  // the PyWorld: a handle keeps its world alive
  BodyId id;
};

struct ShapeHandle {
  py::object world;
  ShapeId id;
};

struct JointHandle {
  py::object world;
  JointId id;
};

class PyWorld {
 public:
  explicit PyWorld(SceneWorld scene, std::vector<std::string> names = {})
      : sw(std::move(scene)), categories(std::move(names)) {}

  SceneWorld sw;  // the world, and its bodies in creation (scene) order with their names
  std::vector<std::string> categories;
  EventTotals totals;
  bool stepping = false;                         // a step runs (set and cleared by StepGuard)
  unsigned long stepThread = 0;                  // the Python thread that runs it
  std::optional<py::error_already_set> pending;  // the first exception a callback raised
  std::vector<py::object> callables;             // the callbacks' Python functions

  // body_state(): the array of the last fill, and the world's version it was filled at.
  // Every step and every write through the module moves `version` on.
  py::object state;
  std::uint64_t stateVersion = 0;
  std::uint64_t version = 1;
  void changed() { ++version; }

  World& world() { return sw.world; }

  // Whether a step runs in another Python thread: that thread released the GIL and the
  // world's state is changing under it (a callback of that step, on the stepping thread,
  // is not another thread: the world is consistent while its callbacks run).
  bool steppingElsewhere() const { return stepping && PyThread_get_thread_ident() != stepThread; }
  // Every entry point that reads or writes the world calls this first: calls from another
  // Python thread while this one steps are refused; calls from a callback (same thread) are
  // the world's to accept or refuse.
  void checkIdle() const {
    if (steppingElsewhere())
      throw std::runtime_error("quack.World: the world is stepping (in another thread)");
  }

  // Drops destroyed bodies from the creation-order list (not during callbacks, where
  // destruction is deferred and the list is being read).
  void compact() {
    if (stepping) return;
    std::size_t out = 0;
    for (std::size_t i = 0; i < sw.bodies.size(); ++i) {
      if (!sw.world.isValid(sw.bodies[i])) continue;
      sw.bodies[out] = sw.bodies[i];
      if (out != i) sw.names[out] = std::move(sw.names[i]);
      ++out;
    }
    sw.bodies.resize(out);
    sw.names.resize(out);
    // Joints end with their bodies and when they break: keep the live ones, in order.
    std::erase_if(sw.joints, [&](JointId j) { return !sw.world.isValid(j); });
  }
};

// Marks the world as stepping for the lifetime of one `step` call, whatever leaves it (a
// return, an exception from the world such as std::bad_alloc): the world is never left
// "stepping" by an exception.
class StepGuard {
 public:
  explicit StepGuard(PyWorld& w) : w_(w) {
    w_.stepping = true;
    w_.stepThread = PyThread_get_thread_ident();
  }
  ~StepGuard() {
    w_.stepping = false;
    w_.changed();
  }
  StepGuard(const StepGuard&) = delete;
  StepGuard& operator=(const StepGuard&) = delete;

 private:
  PyWorld& w_;
};

py::object selfObject(PyWorld& w) {
  return py::cast(&w, py::return_value_policy::reference);
}

PyWorld& worldOf(const py::object& o) {
  return o.cast<PyWorld&>();
}

BroadPhaseKind toBroadPhase(const std::string& s) {
  for (BroadPhaseKind k : kAllBroadPhaseKinds)
    if (s == toString(k)) return k;
  raiseValue("broadphase: unknown broad phase \"" + s +
             "\" (expected tree, quadtree, sap, hash, brute)");
}

void check(const Status& s) {
  if (!s) raiseValue(s.message());
}

// The id of a handle of this world that is still valid, else ValueError naming `path`.
BodyId bodyId(PyWorld& w, py::handle h, const std::string& path) {
  if (!py::isinstance<BodyHandle>(h)) raiseValue(path + ": must be a quack.BodyHandle");
  const BodyHandle& b = h.cast<const BodyHandle&>();
  if (&worldOf(b.world) != &w) raiseValue(path + ": a body of another world");
  if (!w.world().isValid(b.id)) raiseValue(path + ": stale handle (the body was destroyed)");
  return b.id;
}

// The world of a handle, once it is idle (checkIdle) and the body still exists.
const BodyHandle& validBody(const BodyHandle& b) {
  worldOf(b.world).checkIdle();
  if (!worldOf(b.world).world().isValid(b.id))
    raiseValue("stale quack.BodyHandle (the body was destroyed)");
  return b;
}

const ShapeHandle& validShape(const ShapeHandle& s) {
  worldOf(s.world).checkIdle();
  if (!worldOf(s.world).world().isValid(s.id))
    raiseValue("stale quack.ShapeHandle (the shape was destroyed)");
  return s;
}

const JointHandle& validJoint(const JointHandle& j) {
  worldOf(j.world).checkIdle();
  if (!worldOf(j.world).world().isValid(j.id))
    raiseValue(
        "stale quack.JointHandle (the joint was destroyed, broke, or went with one of its "
        "bodies)");
  return j;
}

// create_joint's keyword arguments and the scene-file keys they stand for: the arguments
// become a scene file's joint object, checked by the scene parser (parseSceneJoint), so a
// joint made here follows the same rules as one in a file (docs/scenes.md, "Joints").
struct JointArg {
  const char* name;  // Python
  const char* key;   // scene file
  bool point;        // [x, y] (or anchors' [[x, y], [x, y]]); else a number
};
constexpr JointArg kJointArgs[] = {
    {"anchor", "anchor", true},
    {"anchors", "anchors", true},
    {"axis", "axis", true},
    {"lower", "lower", false},
    {"upper", "upper", false},
    {"motor_speed", "motorSpeed", false},
    {"max_motor_torque", "maxMotorTorque", false},
    {"max_motor_force", "maxMotorForce", false},
    {"hertz", "hertz", false},
    {"damping_ratio", "dampingRatio", false},
    {"length", "length", false},
    {"min_length", "minLength", false},
    {"max_length", "maxLength", false},
    {"linear_hertz", "linearHertz", false},
    {"angular_hertz", "angularHertz", false},
    {"linear_damping_ratio", "linearDampingRatio", false},
    {"angular_damping_ratio", "angularDampingRatio", false},
    {"linear_offset", "linearOffset", true},
    {"angular_offset", "angularOffset", false},
    {"max_force", "maxForce", false},
    {"max_torque", "maxTorque", false},
    {"correction_factor", "correctionFactor", false},
    {"target", "target", true},
    {"break_force", "breakForce", false},
    {"break_torque", "breakTorque", false},
};

bool isWordChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
}

// The scene parser's message with the Python argument names in place of the file's keys
// ("maxMotorTorque: must be >= 0" -> "max_motor_torque: must be >= 0").
std::string pythonJointMessage(std::string message) {
  if (!message.empty() && message.front() == '.') message.erase(0, 1);
  auto replaceWord = [&](const std::string& from, const std::string& to) {
    std::size_t at = 0;
    while ((at = message.find(from, at)) != std::string::npos) {
      const std::size_t end = at + from.size();
      if ((at == 0 || !isWordChar(message[at - 1])) &&
          (end == message.size() || !isWordChar(message[end]))) {
        message.replace(at, from.size(), to);
        at += to.size();
      } else {
        at = end;  // inside a longer word: not the key
      }
    }
  };
  for (const JointArg& a : kJointArgs)
    if (std::string_view(a.name) != a.key) replaceWord(a.key, a.name);
  replaceWord("collideConnected", "collide_connected");
  const std::string unknown = ": unknown key for a ";
  if (std::size_t at = message.find(unknown); at != std::string::npos)
    message.replace(at, unknown.size(), ": not an argument of a ");
  return message;
}

JointType toJointType(const std::string& s) {
  for (JointType t : {JointType::revolute, JointType::prismatic, JointType::distance,
                      JointType::weld, JointType::wheel, JointType::motor, JointType::mouse})
    if (s == toString(t)) return t;
  raiseValue("type: \"" + s +
             "\" is not a joint type (revolute, prismatic, distance, weld, wheel, motor, "
             "mouse)");
}

// A body handle of an event: None for a null one (a mouse joint's body A).
py::object eventBody(py::object world, BodyId b) {
  if (b == BodyId{}) return py::none();
  return py::cast(BodyHandle{std::move(world), b});
}

// The bodies a bulk call reads or writes: the given handles (checked), or every live body
// in creation order.
std::vector<BodyId> bodyList(PyWorld& w, py::handle bodies) {
  if (bodies.is_none()) return w.sw.bodies;
  if (py::isinstance<py::str>(bodies) || !py::isinstance<py::sequence>(bodies))
    raiseValue("bodies: must be a list of quack.BodyHandle, or None for every body");
  std::vector<BodyId> out;
  out.reserve(py::len(bodies));
  std::size_t i = 0;
  for (py::handle h : bodies) {
    out.push_back(bodyId(w, h, "bodies[" + std::to_string(i) + "]"));
    ++i;
  }
  return out;
}

using Values = py::array_t<double, py::array::c_style | py::array::forcecast>;

// body_state()'s columns: x, y, angle, vx, vy, angular_velocity.
constexpr std::size_t kStateColumns = 6;

Vec2 vecAt(const double* d, std::size_t i) {
  return {static_cast<float>(d[2 * i]), static_cast<float>(d[2 * i + 1])};
}

py::array_t<double> bulkRead(PyWorld& w, py::handle bodies, std::size_t width,
                             void (*read)(const World&, BodyId, double*)) {
  w.checkIdle();
  const std::vector<BodyId> ids = bodyList(w, bodies);
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(ids.size())};
  if (width > 1) shape.push_back(static_cast<py::ssize_t>(width));
  py::array_t<double> out(shape);
  double* d = out.mutable_data();
  for (std::size_t i = 0; i < ids.size(); ++i)
    read(w.world(), ids[i], d + i * width);
  return out;
}

// Writes every body, or none: each value is checked first, and when the world still
// refuses one (a shape pushed beyond the coordinate limit), the bodies already written get
// their old values back and the world's message is raised.
template <class T, class Get, class Set>
void bulkWrite(const std::vector<BodyId>& ids, const std::vector<T>& values, Get get, Set set) {
  std::vector<T> saved;
  saved.reserve(ids.size());
  for (BodyId id : ids)
    saved.push_back(get(id));
  for (std::size_t i = 0; i < ids.size(); ++i) {
    Status s = set(ids[i], values[i]);
    if (!s) {
      for (std::size_t k = 0; k < i; ++k)
        (void)set(ids[k], saved[k]);
      raiseValue("bodies[" + std::to_string(i) + "]: " + s.message());
    }
  }
}

std::vector<Vec2> toVecs(const Values& a, std::size_t n) {
  std::vector<Vec2> out(n);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = vecAt(a.data(), i);
  return out;
}

std::vector<float> toFloats(const Values& a, std::size_t n) {
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = static_cast<float>(a.data()[i]);
  return out;
}

py::object toiTuple(py::module_& m, py::object world, const ToiEvent& e) {
  return m.attr("ToiEvent")(static_cast<double>(e.time), ShapeHandle{world, e.shapeA},
                            ShapeHandle{world, e.shapeB}, toTuple(e.point), toTuple(e.normal),
                            static_cast<double>(e.approachSpeed));
}

py::object hitTuple(py::module_& m, py::object world, const ContactHitEvent& e) {
  return m.attr("HitEvent")(ShapeHandle{world, e.shapeA}, ShapeHandle{world, e.shapeB},
                            toTuple(e.point), toTuple(e.normal),
                            static_cast<double>(e.approachSpeed));
}

py::object jointEndTuple(py::module_& m, py::object world, const JointEndEvent& e) {
  return m.attr("JointEndEvent")(JointHandle{world, e.joint}, eventBody(world, e.bodyA),
                                 eventBody(world, e.bodyB),
                                 e.reason == JointEndReason::broken ? "broken" : "body-destroyed",
                                 toTuple(e.force), static_cast<double>(e.torque));
}

// Runs a Python callback from inside the world's step: with the GIL, at most one exception
// kept (the first), none thrown into the library's frames.
template <class Call>
void runCallback(PyWorld& w, Call&& call) {
  py::gil_scoped_acquire gil;
  if (w.pending) return;
  try {
    call();
  } catch (py::error_already_set& e) {
    w.pending.emplace(std::move(e));
  } catch (const std::exception& e) {
    // A C++ exception from pybind11 (a failed cast of the callable's arguments): as Python's
    // RuntimeError, with its message.
    PyErr_SetString(PyExc_RuntimeError, e.what());
    w.pending.emplace();
  }
}

using Registrar = void (World::*)(std::uint64_t, std::uint64_t, World::ContactCallback);

void addContactCallback(PyWorld& w, Registrar reg, std::uint64_t a, std::uint64_t b,
                        py::function fn) {
  w.checkIdle();
  const std::size_t slot = w.callables.size();
  w.callables.push_back(std::move(fn));
  PyWorld* self = &w;
  (w.world().*reg)(a, b, [self, slot](World&, ShapeId x, ShapeId y) {
    runCallback(*self, [&] {
      if (self->callables[slot].is_none()) return;
      py::object world = selfObject(*self);
      self->callables[slot](ShapeHandle{world, x}, ShapeHandle{world, y});
    });
  });
}

// The same for the events that carry a record (World::onHit, World::onImpact):
// fn(toTuple(event), swapped).
template <class Event, class Callback>
void addEventCallback(PyWorld& w, py::function fn,
                      void (World::*reg)(std::uint64_t, std::uint64_t, Callback), std::uint64_t a,
                      std::uint64_t b,
                      py::object (*toTuple)(py::module_&, py::object, const Event&)) {
  w.checkIdle();
  const std::size_t slot = w.callables.size();
  w.callables.push_back(std::move(fn));
  PyWorld* self = &w;
  // No Python object in the C++ callback: the world may copy it without the GIL.
  (w.world().*reg)(a, b, [self, slot, toTuple](World&, const Event& event, bool swapped) {
    runCallback(*self, [&] {
      if (self->callables[slot].is_none()) return;
      py::module_ quackModule = py::module_::import("quack");
      py::object world = selfObject(*self);
      self->callables[slot](toTuple(quackModule, world, event), swapped);
    });
  });
}

QueryFilter toFilter(std::uint64_t category, std::uint64_t mask, bool sensors) {
  QueryFilter f;
  f.category = category;
  f.mask = mask;
  f.includeSensors = sensors;
  return f;
}

const ShapeGeometry& convexGeometry(const PyShape& s, const char* path) {
  if (s.concave)
    raiseValue(std::string(path) +
               ": a concave shape cannot be a query shape; query its "
               "convex pieces (make them with quack.polygon)");
  return s.pieces.front();
}

std::string bodyTypeName(BodyType t) {
  return toString(t);
}

// Garbage collection: a world holds its callbacks' functions and a handle holds its world,
// so a callback that refers to its world (directly or through a handle) makes a cycle.
// These let Python's collector see those references and break such cycles.
//
// The collector may run while an instance is being made (any allocation in World's
// constructor, such as numpy's first import, can start it), before its C++ value exists:
// the value is looked up in pybind11's instance record, without a cast (which would throw,
// and set Python errors, inside the collector), and a value not constructed yet is skipped.
template <class T>
T* valueOf(PyObject* self) {
  auto* inst = reinterpret_cast<py::detail::instance*>(self);
  py::detail::value_and_holder vh = inst->get_value_and_holder();
  if (!vh || !vh.holder_constructed()) return nullptr;  // not constructed yet (or no more)
  return vh.value_ptr<T>();
}

int visitType(PyObject* self, visitproc visit, void* arg) {
  return visit(reinterpret_cast<PyObject*>(Py_TYPE(self)), arg);
}

template <class Handle>
py::custom_type_setup handleGc() {
  return py::custom_type_setup([](PyHeapTypeObject* heapType) {
    PyTypeObject* type = &heapType->ht_type;
    type->tp_flags |= Py_TPFLAGS_HAVE_GC;
    type->tp_traverse = [](PyObject* self, visitproc visit, void* arg) -> int {
      if (int r = visitType(self, visit, arg)) return r;
      Handle* h = valueOf<Handle>(self);
      return h != nullptr && h->world ? visit(h->world.ptr(), arg) : 0;
    };
    type->tp_clear = [](PyObject* self) -> int {
      if (Handle* h = valueOf<Handle>(self)) h->world = py::object();
      return 0;
    };
  });
}

py::custom_type_setup worldGc() {
  return py::custom_type_setup([](PyHeapTypeObject* heapType) {
    PyTypeObject* type = &heapType->ht_type;
    type->tp_flags |= Py_TPFLAGS_HAVE_GC;
    type->tp_traverse = [](PyObject* self, visitproc visit, void* arg) -> int {
      if (int r = visitType(self, visit, arg)) return r;
      if (PyWorld* w = valueOf<PyWorld>(self)) {
        for (const py::object& f : w->callables)
          if (int r = visit(f.ptr(), arg)) return r;
      }
      return 0;
    };
    type->tp_clear = [](PyObject* self) -> int {
      // The world's C++ callbacks keep their slots; a cleared slot holds None and is skipped.
      if (PyWorld* w = valueOf<PyWorld>(self))
        for (py::object& f : w->callables)
          f = py::none();
      return 0;
    };
  });
}

}  // namespace

BodyType toBodyType(const std::string& s) {
  if (s == "static") return BodyType::staticBody;
  if (s == "kinematic") return BodyType::kinematicBody;
  if (s == "dynamic") return BodyType::dynamicBody;
  raiseValue("type: unknown body type \"" + s + "\" (expected static, kinematic, dynamic)");
}

Values toValues(py::handle v, std::size_t n, std::size_t width, const char* name) {
  const std::string expected = std::string(name) + ": must be a numpy array of shape (" +
                               std::to_string(n) +
                               (width == 1 ? ",)" : ", " + std::to_string(width) + ")") + " for " +
                               std::to_string(n) + " bodies";
  // Numbers only: a bool, complex or string array is refused, not converted.
  Values a = toDoubleArray(v, name, expected);
  const bool ok = (width == 1 ? (a.ndim() == 1 && a.shape(0) == static_cast<py::ssize_t>(n))
                              : (a.ndim() == 2 && a.shape(0) == static_cast<py::ssize_t>(n) &&
                                 a.shape(1) == static_cast<py::ssize_t>(width)));
  if (!ok) raiseValue(expected);
  const double* d = a.data();
  for (std::size_t i = 0; i < n * width; ++i) {
    if (!std::isfinite(static_cast<float>(d[i]))) {
      raiseValue(std::string(name) + "[" + std::to_string(i / width) + "]" +
                 (width == 1 ? "" : "[" + std::to_string(i % width) + "]") +
                 ": must be finite (as a float)");
    }
  }
  return a;
}

void registerWorld(py::module_& m) {
  py::exec(R"py(
import collections as _collections
Events = _collections.namedtuple(
    "Events", "begin end hit sensor_begin sensor_end toi out_of_bounds toi_capped joint_end")
Events.__doc__ = ("The events of the last step: begin, end (lists of (shape_a, shape_b)), hit "
                  "(HitEvent), sensor_begin, sensor_end ((sensor, visitor)), toi (ToiEvent, "
                  "in time order), out_of_bounds (bodies held at the edge of the world), "
                  "toi_capped (bodies that used up their impacts for the step), joint_end "
                  "(JointEndEvent: joints that broke, or went with a destroyed body).")
JointEndEvent = _collections.namedtuple(
    "JointEndEvent", "joint body_a body_b reason force torque")
JointEndEvent.__doc__ = ("A joint that ended without destroy(): joint (a stale JointHandle), "
                         "body_a (None for a mouse joint), body_b (stale when destroyed), "
                         "reason ('broken' or 'body-destroyed'), force (N, world frame, on "
                         "body_b) and torque (N m) of its last step.")
HitEvent = _collections.namedtuple("HitEvent", "shape_a shape_b point normal approach_speed")
ToiEvent = _collections.namedtuple("ToiEvent", "time shape_a shape_b point normal approach_speed")
RayHit = _collections.namedtuple("RayHit", "shape body point normal fraction")
ShapeOverlap = _collections.namedtuple("ShapeOverlap", "shape body depth depenetration")
ShapeCastHit = _collections.namedtuple("ShapeCastHit", "shape body point normal fraction")
HitEvent.__doc__ = ("A contact that began faster than the world's hit speed: shapes, point "
                    "(world frame), normal (from shape_a to shape_b), approach_speed (m/s).")
ToiEvent.__doc__ = ("An impact found by continuous collision: time (fraction of the step), "
                    "shapes, point, normal (from shape_a to shape_b), approach_speed (m/s).")
RayHit.__doc__ = ("A shape a world ray enters: shape, body, point, normal (world frame), "
                  "fraction (origin + fraction * translation).")
ShapeOverlap.__doc__ = ("A shape overlapping a query shape: shape, body, depth (metres), "
                        "depenetration (the vector that moves the query shape out).")
ShapeCastHit.__doc__ = ("The first shape a swept query shape meets: shape, body, point, normal, "
                        "fraction of the translation.")
for _t in (Events, HitEvent, ToiEvent, JointEndEvent, RayHit, ShapeOverlap, ShapeCastHit):
    _t.__module__ = "quack"
del _t, _collections
)py",
           m.attr("__dict__"));
  m.attr("ALL_CATEGORIES") = ~std::uint64_t{0};
  m.attr("BODY_STATE_COLUMNS") = py::make_tuple("x", "y", "angle", "vx", "vy", "angular_velocity");

  py::class_<BodyHandle>(m, "BodyHandle", handleGc<BodyHandle>(),
                         "A body of a World. Stays usable after the body is destroyed, but "
                         "then says so: valid is False and everything else raises ValueError.")
      .def_property_readonly(
          "valid",
          [](const BodyHandle& b) {
            worldOf(b.world).checkIdle();
            return worldOf(b.world).world().isValid(b.id);
          },
          "Whether the body still exists (False once destroyed).")
      .def_property_readonly(
          "world", [](const BodyHandle& b) { return b.world; },
          "The quack.World the body belongs to.")
      .def_property_readonly(
          "name",
          [](const BodyHandle& b) {
            PyWorld& w = worldOf(validBody(b).world);
            for (std::size_t i = 0; i < w.sw.bodies.size(); ++i)
              if (w.sw.bodies[i] == b.id) return w.sw.names[i];
            return std::string();
          },
          "The scene's (or create_body's) name.")
      .def_property_readonly(
          "type",
          [](const BodyHandle& b) {
            return bodyTypeName(worldOf(validBody(b).world).world().bodyType(b.id));
          },
          "static, kinematic or dynamic.")
      .def_property(
          "position",
          [](const BodyHandle& b) {
            return toTuple(worldOf(validBody(b).world).world().position(b.id));
          },
          [](const BodyHandle& b, py::handle p) {
            World& w = worldOf(validBody(b).world).world();
            worldOf(b.world).changed();
            check(w.setTransform(b.id, toPosition(p, "position"), w.angle(b.id)));
          },
          "Body origin, world frame, metres (setting it teleports the body).")
      .def_property(
          "angle",
          [](const BodyHandle& b) {
            return static_cast<double>(worldOf(validBody(b).world).world().angle(b.id));
          },
          [](const BodyHandle& b, py::handle a) {
            World& w = worldOf(validBody(b).world).world();
            worldOf(b.world).changed();
            check(w.setTransform(b.id, w.position(b.id), toAngle(toDouble(a, "angle"), "angle")));
          },
          "Radians; setting it turns the body (|angle| <= 1e4 rad, as in scene files).")
      .def_property(
          "velocity",
          [](const BodyHandle& b) {
            return toTuple(worldOf(validBody(b).world).world().linearVelocity(b.id));
          },
          [](const BodyHandle& b, py::handle v) {
            World& w = worldOf(validBody(b).world).world();
            worldOf(b.world).changed();
            check(w.setLinearVelocity(b.id, toVector(v, "velocity", "m/s")));
          },
          "Of the centre of mass, m/s.")
      .def_property(
          "angular_velocity",
          [](const BodyHandle& b) {
            return static_cast<double>(worldOf(validBody(b).world).world().angularVelocity(b.id));
          },
          [](const BodyHandle& b, py::handle v) {
            worldOf(validBody(b).world).changed();
            check(worldOf(b.world).world().setAngularVelocity(
                b.id, static_cast<float>(toDouble(v, "angular_velocity"))));
          },
          "rad/s.")
      .def_property_readonly(
          "mass",
          [](const BodyHandle& b) {
            return static_cast<double>(worldOf(validBody(b).world).world().mass(b.id));
          },
          "kg (0 for static and kinematic bodies).")
      .def_property_readonly(
          "shapes",
          [](const BodyHandle& b) {
            py::list out;
            for (ShapeId s : worldOf(validBody(b).world).world().shapes(b.id))
              out.append(ShapeHandle{b.world, s});
            return out;
          },
          "The body's shapes (quack.ShapeHandle), in creation order.")
      .def(
          "apply_impulse",
          [](const BodyHandle& b, py::handle impulse, py::handle point) {
            World& w = worldOf(validBody(b).world).world();
            worldOf(b.world).changed();
            const Vec2 at =
                point.is_none() ? w.worldCenterOfMass(b.id) : toPosition(point, "point");
            check(w.applyLinearImpulse(b.id, toVector(impulse, "impulse", "N s"), at));
          },
          py::arg("impulse"), py::arg("point") = py::none(),
          "Linear impulse (N s) at a world point (default: the centre of mass).")
      .def(
          "apply_force",
          [](const BodyHandle& b, py::handle force, py::handle point) {
            World& w = worldOf(validBody(b).world).world();
            const Vec2 at =
                point.is_none() ? w.worldCenterOfMass(b.id) : toPosition(point, "point");
            check(w.applyForce(b.id, toVector(force, "force", "N"), at));
          },
          py::arg("force"), py::arg("point") = py::none(),
          "Force (N) at a world point through the next step (default: the centre of mass).")
      .def("__eq__", [](const BodyHandle& a,
                        const BodyHandle& b) { return a.world.is(b.world) && a.id == b.id; })
      .def("__hash__",
           [](const BodyHandle& b) {
             return py::hash(py::make_tuple(b.id.world, b.id.index, b.id.generation));
           })
      .def("__repr__", [](const BodyHandle& b) {
        // No look at the world while another thread steps it (the repr of a handle must not
        // raise, and must not race).
        const PyWorld& w = worldOf(b.world);
        return "BodyHandle(index=" + std::to_string(b.id.index) +
               ", generation=" + std::to_string(b.id.generation) +
               (w.steppingElsewhere() || w.sw.world.isValid(b.id) ? "" : ", stale") + ")";
      });

  py::class_<ShapeHandle>(m, "ShapeHandle", handleGc<ShapeHandle>(),
                          "A shape on a body of a World; valid says whether it still exists "
                          "(everything else raises ValueError once it is destroyed).")
      .def_property_readonly(
          "valid",
          [](const ShapeHandle& s) {
            worldOf(s.world).checkIdle();
            return worldOf(s.world).world().isValid(s.id);
          },
          "Whether the shape still exists (False once destroyed).")
      .def_property_readonly(
          "body",
          [](const ShapeHandle& s) {
            return BodyHandle{s.world, worldOf(validShape(s).world).world().body(s.id)};
          },
          "The quack.BodyHandle the shape is on.")
      .def_property_readonly(
          "type",
          [](const ShapeHandle& s) {
            return std::string(
                toString(shapeType(worldOf(validShape(s).world).world().geometry(s.id))));
          },
          "circle, capsule, segment or polygon (boxes and concave pieces are polygons).")
      .def_property_readonly(
          "category",
          [](const ShapeHandle& s) {
            return worldOf(validShape(s).world).world().shapeDef(s.id).filter.category;
          },
          "Category bits (a bit set).")
      .def_property_readonly(
          "sensor",
          [](const ShapeHandle& s) {
            return worldOf(validShape(s).world).world().shapeDef(s.id).sensor;
          },
          "True for a sensor (reports overlaps, no collision response).")
      .def_property_readonly(
          "friction",
          [](const ShapeHandle& s) {
            return static_cast<double>(
                worldOf(validShape(s).world).world().shapeDef(s.id).friction);
          },
          "Friction coefficient.")
      .def("__eq__", [](const ShapeHandle& a,
                        const ShapeHandle& b) { return a.world.is(b.world) && a.id == b.id; })
      .def("__hash__",
           [](const ShapeHandle& s) {
             return py::hash(py::make_tuple(s.id.world, s.id.index, s.id.generation));
           })
      .def("__repr__", [](const ShapeHandle& s) {
        const PyWorld& w = worldOf(s.world);
        return "ShapeHandle(index=" + std::to_string(s.id.index) +
               ", generation=" + std::to_string(s.id.generation) +
               (w.steppingElsewhere() || w.sw.world.isValid(s.id) ? "" : ", stale") + ")";
      });

  py::class_<JointHandle>(m, "JointHandle", handleGc<JointHandle>(),
                          "A joint between two bodies of a World (World.create_joint). valid "
                          "says whether it still exists: a joint ends when destroyed, when it "
                          "breaks and with either body; everything else then raises ValueError.")
      .def_property_readonly(
          "valid",
          [](const JointHandle& j) {
            worldOf(j.world).checkIdle();
            return worldOf(j.world).world().isValid(j.id);
          },
          "Whether the joint still exists (False once destroyed, broken or gone with a body).")
      .def_property_readonly(
          "world", [](const JointHandle& j) { return j.world; },
          "The quack.World the joint belongs to.")
      .def_property_readonly(
          "type",
          [](const JointHandle& j) {
            return std::string(toString(worldOf(validJoint(j).world).world().jointDef(j.id).type));
          },
          "revolute, prismatic, distance, weld, wheel, motor or mouse.")
      .def_property_readonly(
          "body_a",
          [](const JointHandle& j) {
            return eventBody(j.world, worldOf(validJoint(j).world).world().jointDef(j.id).bodyA);
          },
          "The first body (quack.BodyHandle), None for a mouse joint.")
      .def_property_readonly(
          "body_b",
          [](const JointHandle& j) {
            return BodyHandle{j.world, worldOf(validJoint(j).world).world().jointDef(j.id).bodyB};
          },
          "The second body (quack.BodyHandle): the one a mouse joint pulls.")
      .def_property_readonly(
          "anchors",
          [](const JointHandle& j) {
            const auto [onA, onB] = worldOf(validJoint(j).world).world().jointAnchors(j.id);
            return py::make_tuple(toTuple(onA), toTuple(onB));
          },
          "The anchors now, world frame: (on body_a, on body_b); for a mouse joint (target, "
          "grabbed point). A point joint's two coincide while it holds.")
      .def_property_readonly(
          "force",
          [](const JointHandle& j) {
            return toTuple(worldOf(validJoint(j).world).world().jointForce(j.id));
          },
          "The force (N, world frame, on body_b) the joint applied in the last step.")
      .def_property_readonly(
          "torque",
          [](const JointHandle& j) {
            return static_cast<double>(worldOf(validJoint(j).world).world().jointTorque(j.id));
          },
          "The torque (N m) the joint applied in the last step.")
      .def_property_readonly(
          "angle",
          [](const JointHandle& j) {
            return static_cast<double>(worldOf(validJoint(j).world).world().jointAngle(j.id));
          },
          "Revolute and weld: body_b's angle relative to body_a since creation (radians, in "
          "[-pi, pi]); 0 for the other types.")
      .def_property_readonly(
          "translation",
          [](const JointHandle& j) {
            return static_cast<double>(worldOf(validJoint(j).world).world().jointTranslation(j.id));
          },
          "Prismatic and wheel: body_b's travel along the axis (m); distance: the length "
          "between the anchors; 0 for the other types.")
      .def(
          "set_motor",
          [](const JointHandle& j, py::handle speed, py::handle maxTorque, py::handle maxForce,
             bool enable) {
            PyWorld& w = worldOf(validJoint(j).world);
            const JointDef& d = w.world().jointDef(j.id);
            const bool prismatic = d.type == JointType::prismatic;
            if (d.type != JointType::revolute && d.type != JointType::wheel && !prismatic)
              raiseValue(std::string("set_motor: a ") + toString(d.type) + " joint has no motor");
            // A motor's strength is a torque, except a prismatic joint's (a force): the
            // other argument names the mistake rather than being ignored.
            if (prismatic && !maxTorque.is_none())
              raiseValue("max_torque: a prismatic joint's motor takes max_force (N)");
            if (!prismatic && !maxForce.is_none())
              raiseValue(std::string("max_force: a ") + toString(d.type) +
                         " joint's motor takes max_torque (N m)");
            const char* strengthName = prismatic ? "max_force" : "max_torque";
            py::handle strength = prismatic ? maxForce : maxTorque;
            float s = prismatic ? d.maxMotorForce : d.maxMotorTorque;
            if (!strength.is_none()) {
              s = static_cast<float>(toDouble(strength, strengthName));
              if (!(s >= 0.0f) || !std::isfinite(s))
                raiseValue(std::string(strengthName) + ": must be finite and >= 0");
            }
            float v = d.motorSpeed;
            if (!speed.is_none()) {
              v = static_cast<float>(toDouble(speed, "speed"));
              if (!std::isfinite(v)) raiseValue("speed: must be finite (as a float)");
            }
            w.changed();
            check(w.world().setJointMotor(j.id, enable, v, s));
          },
          py::arg("speed") = py::none(), py::arg("max_torque") = py::none(),
          py::arg("max_force") = py::none(), py::arg("enable") = true,
          "Turns the motor of a revolute, wheel (max_torque, N m) or prismatic (max_force, N) "
          "joint on (enable=False: off) at speed (rad/s or m/s); an argument left None keeps "
          "its value. Wakes the bodies.")
      .def(
          "set_limits",
          [](const JointHandle& j, py::handle lower, py::handle upper) {
            PyWorld& w = worldOf(validJoint(j).world);
            const JointDef& d = w.world().jointDef(j.id);
            // As in scene files: both or neither (neither turns the limit off).
            if (lower.is_none() != upper.is_none())
              raiseValue(std::string(lower.is_none() ? "lower" : "upper") +
                         ": a limit needs both lower and upper (neither: no limit)");
            const bool enable = !lower.is_none();
            float lo = d.type == JointType::distance ? d.minLength : d.lower;
            float hi = d.type == JointType::distance ? d.maxLength : d.upper;
            if (enable) {
              lo = static_cast<float>(toDouble(lower, "lower"));
              hi = static_cast<float>(toDouble(upper, "upper"));
              if (!std::isfinite(lo)) raiseValue("lower: must be finite (as a float)");
              if (!std::isfinite(hi)) raiseValue("upper: must be finite (as a float)");
              if (lo > hi) raiseValue("lower: must be at most upper");
            }
            w.changed();
            Status s = w.world().setJointLimits(j.id, enable, lo, hi);
            if (!s) raiseValue("set_limits: " + s.message().substr(s.message().find(": ") + 2));
          },
          py::arg("lower") = py::none(), py::arg("upper") = py::none(),
          "Limits of a revolute (radians within [-pi, pi]), prismatic or wheel (m of travel) "
          "or distance (m of length) joint: both given turn the limit on, neither turns it "
          "off. Wakes the bodies.")
      .def(
          "set_target",
          [](const JointHandle& j, py::handle target) {
            PyWorld& w = worldOf(validJoint(j).world);
            const JointType t = w.world().jointDef(j.id).type;
            if (t != JointType::mouse)
              raiseValue(std::string("set_target: a ") + toString(t) +
                         " joint has no target (a mouse joint has)");
            const Vec2 p = toPosition(target, "target");
            w.changed();
            check(w.world().setMouseTarget(j.id, p));
          },
          py::arg("target"),
          "Moves a mouse joint's target (world frame, m): where it pulls body_b's grabbed "
          "point. Wakes body_b.")
      .def(
          "set_offsets",
          [](const JointHandle& j, py::handle linearOffset, py::handle angularOffset) {
            PyWorld& w = worldOf(validJoint(j).world);
            const JointType t = w.world().jointDef(j.id).type;
            if (t != JointType::motor)
              raiseValue(std::string("set_offsets: a ") + toString(t) +
                         " joint has no offsets (a motor joint has)");
            const Vec2 p = toPosition(linearOffset, "linear_offset");
            const auto a = static_cast<float>(toDouble(angularOffset, "angular_offset"));
            if (!std::isfinite(a)) raiseValue("angular_offset: must be finite (as a float)");
            w.changed();
            check(w.world().setMotorTarget(j.id, p, a));
          },
          py::arg("linear_offset"), py::arg("angular_offset") = 0.0,
          "A motor joint's target pose of body_b relative to body_a: linear_offset (m, in "
          "body_a's frame) and angular_offset (radians). Wakes the bodies.")
      .def(
          "destroy",
          [](const JointHandle& j) {
            PyWorld& w = worldOf(validJoint(j).world);
            check(w.world().destroyJoint(j.id));
            w.changed();
            w.compact();
          },
          "Destroys the joint (no joint_end event: that is for joints that end by themselves) "
          "and wakes its bodies. The same as World.destroy_joint(joint).")
      .def("__eq__", [](const JointHandle& a,
                        const JointHandle& b) { return a.world.is(b.world) && a.id == b.id; })
      .def("__hash__",
           [](const JointHandle& j) {
             return py::hash(py::make_tuple(j.id.world, j.id.index, j.id.generation));
           })
      .def("__repr__", [](const JointHandle& j) {
        const PyWorld& w = worldOf(j.world);
        return "JointHandle(index=" + std::to_string(j.id.index) +
               ", generation=" + std::to_string(j.id.generation) +
               (w.steppingElsewhere() || w.sw.world.isValid(j.id) ? "" : ", stale") + ")";
      });

  py::class_<PyWorld>(m, "World", worldGc(),
                      "Rigid bodies carrying shapes, stepped by Quack's solver (docs/world.md). "
                      "World frame, SI units.")
      .def(py::init([](py::handle gravity, py::handle dt, py::handle substeps,
                       const std::string& broadphase, bool continuous, bool dynamicPairs) {
             WorldDef def;
             def.gravity = toVector(gravity, "gravity", "m/s^2");
             def.timeStep = static_cast<float>(toDouble(dt, "dt"));
             def.substeps = static_cast<int>(toInteger(substeps, "substeps", 1, 64));
             def.broadPhase = toBroadPhase(broadphase);
             def.enableContinuous = continuous;
             def.sweepDynamicPairs = dynamicPairs;
             World w = valueOrRaise(World::create(def));
             return std::make_unique<PyWorld>(SceneWorld{std::move(w), {}, {}});
           }),
           py::arg("gravity") = py::make_tuple(0.0, -10.0), py::arg("dt") = 1.0 / 60.0,
           py::arg("substeps") = 4, py::arg("broadphase") = "tree", py::arg("continuous") = true,
           py::arg("dynamic_pairs") = true,
           "A world: gravity (m/s^2), dt (seconds per step()), substeps (1..64), broadphase "
           "(tree, quadtree, sap, hash, brute), continuous collision on or off, and whether "
           "it sweeps fast dynamic bodies against each other (dynamic_pairs; off: against "
           "static and kinematic shapes only, as Box2D v3).")
      .def(
          "create_body",
          [](py::object self, const std::string& type, py::handle pos, py::handle angle,
             py::handle vel, py::handle angvel, py::handle linearDamping, py::handle angularDamping,
             py::handle gravityScale, bool bullet, const std::string& name) {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            BodyDef def;
            def.type = toBodyType(type);
            def.position = toPosition(pos, "pos");
            def.angle = toAngle(toDouble(angle, "angle"), "angle");
            def.linearVelocity = toVector(vel, "vel", "m/s");
            // Numbers through toDouble: bool and complex refused (pybind11's float
            // conversion would take a numpy complex, dropping its imaginary part).
            def.angularVelocity = static_cast<float>(toDouble(angvel, "angvel"));
            def.linearDamping = static_cast<float>(toDouble(linearDamping, "linear_damping"));
            def.angularDamping = static_cast<float>(toDouble(angularDamping, "angular_damping"));
            def.gravityScale = static_cast<float>(toDouble(gravityScale, "gravity_scale"));
            def.bullet = bullet;
            BodyId id = valueOrRaise(w.world().createBody(def));
            w.changed();
            w.sw.bodies.push_back(id);
            w.sw.names.push_back(name);
            return BodyHandle{self, id};
          },
          py::arg("type") = "dynamic", py::arg("pos") = py::make_tuple(0.0, 0.0),
          py::arg("angle") = 0.0, py::arg("vel") = py::make_tuple(0.0, 0.0),
          py::arg("angvel") = 0.0, py::arg("linear_damping") = 0.0,
          py::arg("angular_damping") = 0.0, py::arg("gravity_scale") = 1.0,
          py::arg("bullet") = false, py::arg("name") = "",
          "A new body (type static, kinematic or dynamic) at pos (world frame) and angle.")
      .def(
          "create_shape",
          [](py::object self, py::handle body, py::handle shape, py::handle density,
             py::handle friction, py::handle restitution, bool sensor, std::uint64_t category,
             std::uint64_t mask, std::int32_t group) -> py::object {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            const BodyId b = bodyId(w, body, "body");
            const PyShape& s = toShape(shape, "shape");
            ShapeDef def;
            def.density = static_cast<float>(toDouble(density, "density"));
            def.friction = static_cast<float>(toDouble(friction, "friction"));
            def.restitution = static_cast<float>(toDouble(restitution, "restitution"));
            def.sensor = sensor;
            def.filter.category = category;
            def.filter.mask = mask;
            def.filter.group = group;
            std::vector<ShapeId> made;
            for (const ShapeGeometry& piece : s.pieces) {
              Result<ShapeId> r = w.world().createShape(b, def, piece);
              if (!r) {
                // All pieces or none.
                for (ShapeId id : made)
                  (void)w.world().destroyShape(id);
                raiseValue(r.error().message);
              }
              made.push_back(*r);
            }
            if (!s.concave) return py::cast(ShapeHandle{self, made.front()});
            py::list out;
            for (ShapeId id : made)
              out.append(ShapeHandle{self, id});
            return out;
          },
          py::arg("body"), py::arg("shape"), py::arg("density") = 1.0, py::arg("friction") = 0.6,
          py::arg("restitution") = 0.0, py::arg("sensor") = false, py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0}, py::arg("group") = 0,
          "Puts a quack.Shape (body frame) on a body; returns its ShapeHandle (a concave shape: "
          "a list, one per convex piece). category and mask are bit sets.")
      .def(
          "destroy_body",
          [](PyWorld& w, py::handle body) {
            w.checkIdle();
            check(w.world().destroyBody(bodyId(w, body, "body")));
            w.changed();
            w.compact();
          },
          py::arg("body"), "Destroys a body and its shapes (deferred inside a callback).")
      .def(
          "destroy_shape",
          [](PyWorld& w, py::handle shape) {
            w.checkIdle();
            if (!py::isinstance<ShapeHandle>(shape))
              raiseValue("shape: must be a quack.ShapeHandle");
            const ShapeHandle& s = shape.cast<const ShapeHandle&>();
            if (&worldOf(s.world) != &w) raiseValue("shape: a shape of another world");
            if (!w.world().isValid(s.id))
              raiseValue("shape: stale handle (the shape was destroyed)");
            check(w.world().destroyShape(s.id));
            w.changed();
          },
          py::arg("shape"), "Destroys a shape (deferred inside a callback).")
      .def(
          "create_joint",
          [](py::object self, const std::string& type, py::handle a, py::handle b,
             py::handle anchor, py::handle anchors, py::handle axis, py::handle lower,
             py::handle upper, py::handle motorSpeed, py::handle maxMotorTorque,
             py::handle maxMotorForce, py::handle hertz, py::handle dampingRatio, py::handle length,
             py::handle minLength, py::handle maxLength, py::handle linearHertz,
             py::handle angularHertz, py::handle linearDampingRatio, py::handle angularDampingRatio,
             py::handle linearOffset, py::handle angularOffset, py::handle maxForce,
             py::handle maxTorque, py::handle correctionFactor, py::handle target,
             py::handle breakForce, py::handle breakTorque, bool collideConnected) {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            const JointType t = toJointType(type);
            // The bodies first (handles, not names), then every other argument as the scene
            // file's key, checked by the scene parser.
            BodyId bodyA;
            if (t == JointType::mouse) {
              if (!a.is_none())
                raiseValue("a: must be None for a mouse joint (it pulls body b to its target)");
            } else {
              if (a.is_none()) raiseValue(std::string("a: a ") + type + " joint needs body a");
              bodyA = bodyId(w, a, "a");
            }
            const BodyId bodyB = bodyId(w, b, "b");
            if (bodyA == bodyB) raiseValue("b: the same body as a (a joint joins two bodies)");
            const py::handle values[] = {anchor,
                                         anchors,
                                         axis,
                                         lower,
                                         upper,
                                         motorSpeed,
                                         maxMotorTorque,
                                         maxMotorForce,
                                         hertz,
                                         dampingRatio,
                                         length,
                                         minLength,
                                         maxLength,
                                         linearHertz,
                                         angularHertz,
                                         linearDampingRatio,
                                         angularDampingRatio,
                                         linearOffset,
                                         angularOffset,
                                         maxForce,
                                         maxTorque,
                                         correctionFactor,
                                         target,
                                         breakForce,
                                         breakTorque};
            static_assert(std::size(values) == std::size(kJointArgs));
            nlohmann::json j = nlohmann::json::object();
            j["type"] = type;
            if (t != JointType::mouse) j["a"] = "a";
            j["b"] = "b";
            for (std::size_t i = 0; i < std::size(values); ++i) {
              if (values[i].is_none()) continue;
              const JointArg& arg = kJointArgs[i];
              // Numbers through toDouble (bool and complex refused, naming the argument);
              // NaN and infinity pass on to the parser, which names them as in a file.
              j[arg.key] = arg.point ? toJson(values[i], arg.name)
                                     : nlohmann::json(toDouble(values[i], arg.name));
            }
            j["collideConnected"] = collideConnected;
            std::vector<SceneBody> named(2);
            named[0].name = "a";
            named[1].name = "b";
            Result<SceneJoint> parsed = parseSceneJoint(j, "", named);
            if (!parsed) raiseValue(pythonJointMessage(parsed.error().message));
            JointDef def = parsed->def;
            def.bodyA = bodyA;
            def.bodyB = bodyB;
            const JointId id = valueOrRaise(w.world().createJoint(def));
            w.changed();
            w.sw.joints.push_back(id);
            return JointHandle{self, id};
          },
          py::arg("type"), py::arg("a"), py::arg("b"), py::kw_only(),
          py::arg("anchor") = py::none(), py::arg("anchors") = py::none(),
          py::arg("axis") = py::none(), py::arg("lower") = py::none(),
          py::arg("upper") = py::none(), py::arg("motor_speed") = py::none(),
          py::arg("max_motor_torque") = py::none(), py::arg("max_motor_force") = py::none(),
          py::arg("hertz") = py::none(), py::arg("damping_ratio") = py::none(),
          py::arg("length") = py::none(), py::arg("min_length") = py::none(),
          py::arg("max_length") = py::none(), py::arg("linear_hertz") = py::none(),
          py::arg("angular_hertz") = py::none(), py::arg("linear_damping_ratio") = py::none(),
          py::arg("angular_damping_ratio") = py::none(), py::arg("linear_offset") = py::none(),
          py::arg("angular_offset") = py::none(), py::arg("max_force") = py::none(),
          py::arg("max_torque") = py::none(), py::arg("correction_factor") = py::none(),
          py::arg("target") = py::none(), py::arg("break_force") = py::none(),
          py::arg("break_torque") = py::none(), py::arg("collide_connected") = false,
          "A joint of `type` (revolute, prismatic, distance, weld, wheel, motor, mouse) between "
          "bodies a and b (quack.BodyHandle; a is None for a mouse joint), with the settings "
          "of a scene file's joint (docs/scenes.md, \"Joints\"), in the world frame at "
          "creation: a limit is on when lower and upper are given, a motor when "
          "max_motor_torque (revolute, wheel) or max_motor_force (prismatic) is, a spring "
          "when hertz is; a distance joint with min_length or max_length and no hertz is a "
          "rope. Each type takes only its own arguments; a ValueError names the argument. "
          "Returns a quack.JointHandle.")
      .def(
          "destroy_joint",
          [](PyWorld& w, py::handle joint) {
            w.checkIdle();
            if (!py::isinstance<JointHandle>(joint))
              raiseValue("joint: must be a quack.JointHandle");
            const JointHandle& j = joint.cast<const JointHandle&>();
            if (&worldOf(j.world) != &w) raiseValue("joint: a joint of another world");
            if (!w.world().isValid(j.id))
              raiseValue("joint: stale handle (the joint was destroyed)");
            check(w.world().destroyJoint(j.id));
            w.changed();
            w.compact();
          },
          py::arg("joint"),
          "Destroys a joint (no joint_end event; deferred inside a callback) and wakes its "
          "bodies.")
      .def_property_readonly(
          "joints",
          [](py::object self) {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            py::list out;
            for (JointId id : w.world().joints())
              out.append(JointHandle{self, id});
            return out;
          },
          "Every live joint (quack.JointHandle), in the world's index order.")
      .def_property_readonly(
          "joint_count",
          [](PyWorld& w) {
            w.checkIdle();
            return w.world().jointCount();
          },
          "Live joints.")
      .def_property_readonly(
          "bodies",
          [](py::object self) {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            py::list out;
            for (BodyId id : w.sw.bodies)
              out.append(BodyHandle{self, id});
            return out;
          },
          "Every live body, in creation (scene) order.")
      .def_property_readonly(
          "body_count",
          [](PyWorld& w) {
            w.checkIdle();
            return w.world().bodyCount();
          },
          "Live bodies.")
      .def_property_readonly(
          "shape_count",
          [](PyWorld& w) {
            w.checkIdle();
            return w.world().shapeCount();
          },
          "Live shapes.")
      .def_property_readonly(
          "contact_count",
          [](PyWorld& w) {
            w.checkIdle();
            return w.world().touchingContactCount();
          },
          "Touching contacts.")
      .def_property_readonly(
          "categories", [](PyWorld& w) { return w.categories; },
          "The scene's category names; category i is bit 1 << i.")
      .def(
          "body",
          [](py::object self, const std::string& name) {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            for (std::size_t i = 0; i < w.sw.bodies.size(); ++i)
              if (w.sw.names[i] == name) return BodyHandle{self, w.sw.bodies[i]};
            raiseValue("body: no body named \"" + name + "\"");
          },
          py::arg("name"), "The first body with this name.")
      .def(
          "step",
          [](PyWorld& w, py::handle dt, py::handle substeps) {
            w.checkIdle();
            if (w.stepping) raiseValue("step: called from a callback");
            std::optional<float> stepDt;
            int sub = w.world().def().substeps;
            if (!dt.is_none()) stepDt = static_cast<float>(toDouble(dt, "dt"));
            if (!substeps.is_none()) sub = static_cast<int>(toInteger(substeps, "substeps", 1, 64));
            StepStatus s;
            {
              // Cleared however the step ends; an exception (MemoryError from std::bad_alloc)
              // drops what the callbacks raised before it.
              StepGuard guard(w);
              try {
                py::gil_scoped_release release;
                s = stepDt || !substeps.is_none()
                        ? w.world().step(stepDt.value_or(w.world().def().timeStep), sub)
                        : w.world().step();
              } catch (...) {
                w.pending.reset();
                throw;
              }
            }
            if (s) {
              const StepEvents& e = w.world().events();
              w.totals.begin += e.begin.size();
              w.totals.end += e.end.size();
              w.totals.hit += e.hit.size();
              w.totals.sensor += e.sensorBegin.size();
            }
            w.compact();
            if (w.pending) {
              py::error_already_set e = std::move(*w.pending);
              w.pending.reset();
              throw e;
            }
            if (!s) raiseValue(s.message());
          },
          py::arg("dt") = py::none(), py::arg("substeps") = py::none(),
          "Advances by dt seconds (default: the world's) with substeps. The GIL is released. "
          "Callbacks run at the end; the first exception one raises is raised here, after the "
          "step is complete.")
      .def_property_readonly(
          "time",
          [](PyWorld& w) {
            w.checkIdle();
            return w.world().time();
          },
          "Simulated seconds since the world was made.")
      .def_property_readonly(
          "step_count",
          [](PyWorld& w) {
            w.checkIdle();
            return w.world().stepCount();
          },
          "Steps taken.")
      .def(
          "state_hash",
          [](PyWorld& w) {
            w.checkIdle();
            return w.world().stateHash();
          },
          "A hash of every body's position, angle and velocities (bitwise): equal in C++ "
          "(World::stateHash) for the same scene and steps.")
      .def(
          "validate",
          [](PyWorld& w) {
            w.checkIdle();
            check(w.world().validate());
          },
          "Checks every internal cross-reference; raises ValueError when one is broken.")
      .def(
          "snapshot",
          [](PyWorld& w) {
            w.checkIdle();
            Result<std::vector<std::uint8_t>> bytes = w.world().snapshot(SnapshotKind::full);
            if (!bytes) throw py::value_error(bytes.error().message);
            return py::bytes(reinterpret_cast<const char*>(bytes->data()), bytes->size());
          },
          "A full snapshot of the world (bytes): restore() brings the world back to it bit "
          "for bit (docs/determinism.md, \"Snapshots\"). Raises ValueError when the world "
          "refuses (after a step that ran out of memory).")
      .def(
          "restore",
          [](PyWorld& w, const py::bytes& data) {
            w.checkIdle();
            const std::string_view view = data;
            w.changed();  // body_state() must not hand back the array of before
            check(w.world().restore(std::span<const std::uint8_t>(
                reinterpret_cast<const std::uint8_t*>(view.data()), view.size())));
          },
          py::arg("snapshot"),
          "Puts the world back to a snapshot() of it; raises ValueError naming what is wrong "
          "with a snapshot that does not fit. The way back after a MemoryError from step(), "
          "which leaves the world refusing changes until a snapshot is restored.")
      .def(
          "events",
          [m](py::object self) mutable {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            const StepEvents& e = w.world().events();
            auto pairs = [&](const auto& list, auto first, auto second) {
              py::list out;
              for (const auto& x : list)
                out.append(
                    py::make_tuple(ShapeHandle{self, x.*first}, ShapeHandle{self, x.*second}));
              return out;
            };
            py::list hits, tois, outs, capped, jointEnds;
            for (const ContactHitEvent& h : e.hit)
              hits.append(hitTuple(m, self, h));
            for (const ToiEvent& t : e.toi)
              tois.append(toiTuple(m, self, t));
            for (BodyId b : e.outOfBounds)
              outs.append(BodyHandle{self, b});
            for (BodyId b : e.toiCapped)
              capped.append(BodyHandle{self, b});
            for (const JointEndEvent& j : e.jointEnd)
              jointEnds.append(jointEndTuple(m, self, j));
            return m.attr("Events")(
                pairs(e.begin, &ContactBeginEvent::shapeA, &ContactBeginEvent::shapeB),
                pairs(e.end, &ContactEndEvent::shapeA, &ContactEndEvent::shapeB), hits,
                pairs(e.sensorBegin, &SensorEvent::sensor, &SensorEvent::visitor),
                pairs(e.sensorEnd, &SensorEvent::sensor, &SensorEvent::visitor), tois, outs, capped,
                jointEnds);
          },
          "The events of the last step (quack.Events). Shapes destroyed since are stale handles.")
      .def(
          "on_contact_begin",
          [](PyWorld& w, py::function fn, std::uint64_t a, std::uint64_t b) {
            addContactCallback(w, &World::onContactBegin, a, b, std::move(fn));
          },
          py::arg("fn"), py::arg("categories_a") = ~std::uint64_t{0},
          py::arg("categories_b") = ~std::uint64_t{0},
          "fn(shape_a, shape_b) after each step for each contact that began between a shape of "
          "categories_a and one of categories_b (bit sets), in that order.")
      .def(
          "on_contact_end",
          [](PyWorld& w, py::function fn, std::uint64_t a, std::uint64_t b) {
            addContactCallback(w, &World::onContactEnd, a, b, std::move(fn));
          },
          py::arg("fn"), py::arg("categories_a") = ~std::uint64_t{0},
          py::arg("categories_b") = ~std::uint64_t{0}, "As on_contact_begin, for ends.")
      .def(
          "on_sensor_begin",
          [](PyWorld& w, py::function fn, std::uint64_t a, std::uint64_t b) {
            addContactCallback(w, &World::onSensorBegin, a, b, std::move(fn));
          },
          py::arg("fn"), py::arg("sensor_categories") = ~std::uint64_t{0},
          py::arg("visitor_categories") = ~std::uint64_t{0},
          "fn(sensor, visitor) for each shape that started overlapping a sensor.")
      .def(
          "on_sensor_end",
          [](PyWorld& w, py::function fn, std::uint64_t a, std::uint64_t b) {
            addContactCallback(w, &World::onSensorEnd, a, b, std::move(fn));
          },
          py::arg("fn"), py::arg("sensor_categories") = ~std::uint64_t{0},
          py::arg("visitor_categories") = ~std::uint64_t{0}, "As on_sensor_begin, for ends.")
      .def(
          "on_hit",
          [](PyWorld& w, py::function fn, std::uint64_t a, std::uint64_t b) {
            addEventCallback<ContactHitEvent>(w, std::move(fn), &World::onHit, a, b, hitTuple);
          },
          py::arg("fn"), py::arg("categories_a") = ~std::uint64_t{0},
          py::arg("categories_b") = ~std::uint64_t{0},
          "fn(hit, swapped) for each quack.HitEvent between the categories; swapped says the "
          "event's shape_a is the one in categories_b.")
      .def(
          "on_impact",
          [](PyWorld& w, py::function fn, std::uint64_t a, std::uint64_t b) {
            addEventCallback<ToiEvent>(w, std::move(fn), &World::onImpact, a, b, toiTuple);
          },
          py::arg("fn"), py::arg("categories_a") = ~std::uint64_t{0},
          py::arg("categories_b") = ~std::uint64_t{0},
          "fn(impact, swapped) for each quack.ToiEvent (continuous collision) between the "
          "categories, in time order; swapped as for on_hit.")
      .def(
          "on_joint_end",
          [](PyWorld& w, py::function fn) {
            w.checkIdle();
            const std::size_t slot = w.callables.size();
            w.callables.push_back(std::move(fn));
            PyWorld* self = &w;
            w.world().onJointEnd([self, slot](World&, const JointEndEvent& event) {
              runCallback(*self, [&] {
                if (self->callables[slot].is_none()) return;
                py::module_ quackModule = py::module_::import("quack");
                self->callables[slot](jointEndTuple(quackModule, selfObject(*self), event));
              });
            });
          },
          py::arg("fn"),
          "fn(event) after each step for each quack.JointEndEvent: a joint that broke, or "
          "went with a destroyed body (not one destroyed by destroy_joint).")
      .def(
          "get_positions",
          [](PyWorld& w, py::handle bodies) {
            return bulkRead(w, bodies, 2, [](const World& world, BodyId id, double* out) {
              const Vec2 p = world.position(id);
              out[0] = static_cast<double>(p.x);
              out[1] = static_cast<double>(p.y);
            });
          },
          py::arg("bodies") = py::none(),
          "Body origins (N, 2), world frame, of the given bodies (default: every body).")
      .def(
          "get_angles",
          [](PyWorld& w, py::handle bodies) {
            return bulkRead(w, bodies, 1, [](const World& world, BodyId id, double* out) {
              out[0] = static_cast<double>(world.angle(id));
            });
          },
          py::arg("bodies") = py::none(), "Angles (N,), radians.")
      .def(
          "get_velocities",
          [](PyWorld& w, py::handle bodies) {
            return bulkRead(w, bodies, 2, [](const World& world, BodyId id, double* out) {
              const Vec2 v = world.linearVelocity(id);
              out[0] = static_cast<double>(v.x);
              out[1] = static_cast<double>(v.y);
            });
          },
          py::arg("bodies") = py::none(), "Velocities of the centres of mass (N, 2), m/s.")
      .def(
          "get_angular_velocities",
          [](PyWorld& w, py::handle bodies) {
            return bulkRead(w, bodies, 1, [](const World& world, BodyId id, double* out) {
              out[0] = static_cast<double>(world.angularVelocity(id));
            });
          },
          py::arg("bodies") = py::none(), "Angular velocities (N,), rad/s.")
      .def(
          "set_positions",
          [](PyWorld& w, py::handle values, py::handle bodies) {
            w.checkIdle();
            const std::vector<BodyId> ids = bodyList(w, bodies);
            const Values a = toValues(values, ids.size(), 2, "positions");
            World& world = w.world();
            w.changed();
            for (std::size_t i = 0; i < ids.size(); ++i) {
              std::string bad = checkPosition(a.data()[2 * i], a.data()[2 * i + 1],
                                              "positions[" + std::to_string(i) + "]");
              if (!bad.empty()) raiseValue(bad);
            }
            bulkWrite(
                ids, toVecs(a, ids.size()), [&](BodyId id) { return world.position(id); },
                [&](BodyId id, auto v) { return world.setTransform(id, v, world.angle(id)); });
          },
          py::arg("positions"), py::arg("bodies") = py::none(),
          "Teleports bodies: positions (N, 2), world frame. All or none are moved.")
      .def(
          "set_angles",
          [](PyWorld& w, py::handle values, py::handle bodies) {
            w.checkIdle();
            const std::vector<BodyId> ids = bodyList(w, bodies);
            const Values a = toValues(values, ids.size(), 1, "angles");
            for (std::size_t i = 0; i < ids.size(); ++i)
              (void)toAngle(a.data()[i], "angles[" + std::to_string(i) + "]");
            World& world = w.world();
            w.changed();
            bulkWrite(
                ids, toFloats(a, ids.size()), [&](BodyId id) { return world.angle(id); },
                [&](BodyId id, auto v) { return world.setTransform(id, world.position(id), v); });
          },
          py::arg("angles"), py::arg("bodies") = py::none(),
          "Turns bodies: angles (N,), radians. All or none are turned.")
      .def(
          "set_velocities",
          [](PyWorld& w, py::handle values, py::handle bodies) {
            w.checkIdle();
            const std::vector<BodyId> ids = bodyList(w, bodies);
            const Values a = toValues(values, ids.size(), 2, "velocities");
            World& world = w.world();
            w.changed();
            bulkWrite(
                ids, toVecs(a, ids.size()), [&](BodyId id) { return world.linearVelocity(id); },
                [&](BodyId id, auto v) { return world.setLinearVelocity(id, v); });
          },
          py::arg("velocities"), py::arg("bodies") = py::none(),
          "Velocities (N, 2), m/s (static bodies keep theirs, zero). All or none are set.")
      .def(
          "set_angular_velocities",
          [](PyWorld& w, py::handle values, py::handle bodies) {
            w.checkIdle();
            const std::vector<BodyId> ids = bodyList(w, bodies);
            const Values a = toValues(values, ids.size(), 1, "angular_velocities");
            World& world = w.world();
            w.changed();
            bulkWrite(
                ids, toFloats(a, ids.size()), [&](BodyId id) { return world.angularVelocity(id); },
                [&](BodyId id, auto v) { return world.setAngularVelocity(id, v); });
          },
          py::arg("angular_velocities"), py::arg("bodies") = py::none(),
          "Angular velocities (N,), rad/s. All or none are set.")
      .def(
          "body_state",
          [](PyWorld& w) -> py::object {
            w.checkIdle();
            if (w.state && w.stateVersion == w.version) return w.state;
            const World& world = w.world();
            const std::size_t n = w.sw.bodies.size();
            py::array_t<double> a({static_cast<py::ssize_t>(n), py::ssize_t{kStateColumns}});
            double* d = a.mutable_data();
            for (std::size_t i = 0; i < n; ++i, d += kStateColumns) {
              const BodyId id = w.sw.bodies[i];
              const Vec2 p = world.position(id), v = world.linearVelocity(id);
              d[0] = static_cast<double>(p.x);
              d[1] = static_cast<double>(p.y);
              d[2] = static_cast<double>(world.angle(id));
              d[3] = static_cast<double>(v.x);
              d[4] = static_cast<double>(v.y);
              d[5] = static_cast<double>(world.angularVelocity(id));
            }
            // Read-only (numpy's flag, cleared without a Python attribute call).
            py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
            w.state = a;
            w.stateVersion = w.version;
            return w.state;
          },
          "Every body's state as one read-only array (N, 6), bodies in creation order, columns "
          "quack.BODY_STATE_COLUMNS: x, y, angle, vx, vy, angular_velocity (float64). Filled "
          "once after each step or write; until the next one every call returns the same "
          "array (no copy), and slices such as state[:, 0:2] are views of it. After the next "
          "step (or any write) it is stale: it keeps its values and stays valid memory, and "
          "body_state() returns a new array. See docs/python.md.")
      .def(
          "set_body_state",
          [](PyWorld& w, py::handle values) {
            w.checkIdle();
            const std::vector<BodyId>& ids = w.sw.bodies;
            const std::size_t n = ids.size();
            const Values a = toValues(values, n, kStateColumns, "state");
            const double* d = a.data();
            for (std::size_t i = 0; i < n; ++i) {
              const double* row = d + i * kStateColumns;
              const std::string path = "state[" + std::to_string(i) + "]";
              std::string bad = checkPosition(row[0], row[1], path);
              if (!bad.empty()) raiseValue(bad);
              (void)toAngle(row[2], path + "[2]");
            }
            struct Row {
              Vec2 p;
              float angle;
              Vec2 v;
              float w;
            };
            std::vector<Row> rows(n);
            for (std::size_t i = 0; i < n; ++i) {
              const double* r = d + i * kStateColumns;
              rows[i] = {{static_cast<float>(r[0]), static_cast<float>(r[1])},
                         static_cast<float>(r[2]),
                         {static_cast<float>(r[3]), static_cast<float>(r[4])},
                         static_cast<float>(r[5])};
            }
            World& world = w.world();
            w.changed();
            auto set = [&](BodyId id, const Row& r) {
              Status s = world.setTransform(id, r.p, r.angle);
              if (s) s = world.setLinearVelocity(id, r.v);
              if (s) s = world.setAngularVelocity(id, r.w);
              return s;
            };
            bulkWrite(
                ids, rows,
                [&](BodyId id) {
                  return Row{world.position(id), world.angle(id), world.linearVelocity(id),
                             world.angularVelocity(id)};
                },
                [&](BodyId id, const Row& r) {
                  const Row old{world.position(id), world.angle(id), world.linearVelocity(id),
                                world.angularVelocity(id)};
                  Status s = set(id, r);
                  if (!s) (void)set(id, old);  // this body whole too
                  return s;
                });
          },
          py::arg("state"),
          "Writes every body's state from an array (N, 6) laid out as body_state() (columns "
          "quack.BODY_STATE_COLUMNS, N = body_count, creation order). Checked first: positions "
          "within the coordinate limit, |angle| <= 1e4 rad, every number finite; then all "
          "bodies or none are written (a value the world refuses puts the others back). "
          "Static bodies keep zero velocities.")
      .def(
          "to_svg",
          [](PyWorld& w, const std::string& title) {
            w.checkIdle();
            return renderSvg(w.sw, title);
          },
          py::arg("title") = "",
          "An SVG picture of the world now (shapes filled by body type, contact points and "
          "normals in red), as `quack run --svg` draws it.")
      .def(
          "_repr_svg_",
          [](PyWorld& w) {
            w.checkIdle();
            // A notebook keeps every picture it shows: a smaller budget than to_svg's (a big
            // world is drawn as an even sample of its shapes, and the picture says so).
            SvgOptions options;
            options.maxShapes = 5000;
            options.maxContacts = 1000;
            options.maxBytes = 2u << 20;
            return renderSvg(w.sw, "", options);
          },
          "The SVG Jupyter shows for a world: to_svg()'s picture within 5,000 shapes, 1,000 "
          "contact points and 2 MB.")
      .def(
          "ray_cast_closest",
          [m](py::object self, py::handle origin, py::handle translation, std::uint64_t category,
              std::uint64_t mask, bool sensors) mutable -> py::object {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            std::optional<RayHitResult> h = w.world().rayCastClosest(
                toPosition(origin, "origin"), toPosition(translation, "translation"),
                toFilter(category, mask, sensors));
            if (!h) return py::none();
            return m.attr("RayHit")(ShapeHandle{self, h->shape}, BodyHandle{self, h->body},
                                    toTuple(h->point), toTuple(h->normal),
                                    static_cast<double>(h->fraction));
          },
          py::arg("origin"), py::arg("translation"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0}, py::arg("include_sensors") = false,
          "The first shape the ray origin + t translation (t in [0, 1]) enters: a "
          "quack.RayHit, or None.")
      .def(
          "ray_cast_all",
          [m](py::object self, py::handle origin, py::handle translation, std::uint64_t category,
              std::uint64_t mask, bool sensors) mutable {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            py::list out;
            for (const RayHitResult& h : w.world().rayCastAll(
                     toPosition(origin, "origin"), toPosition(translation, "translation"),
                     toFilter(category, mask, sensors))) {
              out.append(m.attr("RayHit")(ShapeHandle{self, h.shape}, BodyHandle{self, h.body},
                                          toTuple(h.point), toTuple(h.normal),
                                          static_cast<double>(h.fraction)));
            }
            return out;
          },
          py::arg("origin"), py::arg("translation"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0}, py::arg("include_sensors") = false,
          "Every shape the ray enters (quack.RayHit), by fraction.")
      .def(
          "overlap_aabb",
          [](py::object self, py::handle lower, py::handle upper, std::uint64_t category,
             std::uint64_t mask, bool sensors) {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            py::list out;
            for (ShapeId s :
                 w.world().overlapAabb({toPosition(lower, "lower"), toPosition(upper, "upper")},
                                       toFilter(category, mask, sensors)))
              out.append(ShapeHandle{self, s});
            return out;
          },
          py::arg("lower"), py::arg("upper"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0}, py::arg("include_sensors") = false,
          "Shapes whose bounding boxes overlap the box lower-upper (world frame).")
      .def(
          "overlap_shape",
          [m](py::object self, py::handle shape, py::handle pose, std::uint64_t category,
              std::uint64_t mask, bool sensors) mutable {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            const ShapeGeometry& g = convexGeometry(toShape(shape, "shape"), "shape");
            py::list out;
            for (const ShapeOverlap& o : valueOrRaise(w.world().overlapShape(
                     g, toTransform(pose, "pose"), toFilter(category, mask, sensors)))) {
              out.append(
                  m.attr("ShapeOverlap")(ShapeHandle{self, o.shape}, BodyHandle{self, o.body},
                                         static_cast<double>(o.depth), toTuple(o.depenetration)));
            }
            return out;
          },
          py::arg("shape"), py::arg("pose"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0}, py::arg("include_sensors") = false,
          "Shapes overlapping a convex quack.Shape at pose: quack.ShapeOverlap, each with the "
          "vector that moves the query shape out.")
      .def(
          "cast_shape",
          [m](py::object self, py::handle shape, py::handle pose, py::handle translation,
              std::uint64_t category, std::uint64_t mask, bool sensors) mutable -> py::object {
            PyWorld& w = worldOf(self);
            w.checkIdle();
            const ShapeGeometry& g = convexGeometry(toShape(shape, "shape"), "shape");
            std::optional<ShapeCastResult> r = valueOrRaise(w.world().castShape(
                g, toTransform(pose, "pose"), toPosition(translation, "translation"),
                toFilter(category, mask, sensors)));
            if (!r) return py::none();
            return m.attr("ShapeCastHit")(ShapeHandle{self, r->shape}, BodyHandle{self, r->body},
                                          toTuple(r->point), toTuple(r->normal),
                                          static_cast<double>(r->fraction));
          },
          py::arg("shape"), py::arg("pose"), py::arg("translation"), py::arg("category") = 1,
          py::arg("mask") = ~std::uint64_t{0}, py::arg("include_sensors") = false,
          "Sweeps a convex quack.Shape from pose along translation: the first shape met "
          "(quack.ShapeCastHit), or None.")
      .def(
          "write_state",
          [](PyWorld& w, const std::string& path) {
            w.checkIdle();
            const std::string text = writeState(captureState(w.sw, w.totals));
            std::ofstream out(path, std::ios::binary);
            if (!out) throw py::value_error("write_state: cannot open " + path);
            out << text;
            out.close();
            if (!out) throw py::value_error("write_state: cannot write " + path);
          },
          py::arg("path"),
          "Writes the state file `quack run --out` writes (bodies in creation order, event "
          "totals since the world was made).")
      .def("__repr__", [](PyWorld& w) {
        if (w.steppingElsewhere()) return std::string("World(stepping)");
        return "World(bodies=" + std::to_string(w.world().bodyCount()) +
               ", shapes=" + std::to_string(w.world().shapeCount()) +
               ", steps=" + std::to_string(w.world().stepCount()) + ")";
      });

  m.def(
      "load_scene",
      [](const std::string& path) {
        Scene scene = valueOrRaise(loadScene(path));
        SceneWorld sw = valueOrRaise(buildWorld(scene));
        return std::make_unique<PyWorld>(std::move(sw), scene.categories);
      },
      py::arg("path"), "A World built from a scene file (the README's format).");
}

}  // namespace quack::python
