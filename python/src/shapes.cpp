// Shapes (quack.circle, ..., quack.shape) and the conversions the whole module uses. Every
// shape goes through the io layer's JSON parser (quack/io/shape_json.hpp), so a shape made
// in Python is checked exactly as a scene file or a `quack query` line is, with the same
// messages.

#include <cmath>
#include <cstdio>
#include <utility>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/geometry/mass.hpp"
#include "quack/io/scene.hpp"
#include "quack/io/shape_json.hpp"

namespace quack::python {

using nlohmann::json;

void raiseValue(const std::string& message) {
  throw py::value_error(message);
}

PyShape makeShape(json j, const std::string& path) {
  PyShape s;
  s.pieces = valueOrRaise(parseShapePieces(j, path));
  s.concave = j.at("type") == "concave";
  s.json = std::move(j);
  return s;
}

namespace {

std::string typeName(py::handle value) {
  return std::string(py::str(value.get_type().attr("__name__")));
}

// numpy's kind letter of a numpy scalar or array ('b' bool, 'i' 'u' integers, 'f' float,
// 'c' complex, 'U' 'S' strings, 'O' objects...), or 0 for anything else.
char numpyKind(py::handle value) {
  if (py::isinstance<py::array>(value))
    return py::reinterpret_borrow<py::array>(value).dtype().kind();
  if (!PyObject_HasAttrString(value.ptr(), "dtype") || py::isinstance<py::str>(value)) return 0;
  py::object dtype = value.attr("dtype");
  if (!py::isinstance<py::dtype>(dtype)) return 0;
  return py::reinterpret_borrow<py::dtype>(dtype).kind();
}

// The message of the Python exception being raised (cleared).
std::string takeError() {
  py::error_already_set e;
  return e.what();
}

// A Python int as JSON: 64-bit when it fits, else a float as a JSON reader would read it;
// beyond a double, ValueError naming `path`.
json intJson(py::handle value, const std::string& path) {
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow == 0) {
    if (v == -1 && PyErr_Occurred()) raiseValue(path + ": " + takeError());
    return v;
  }
  const double d = PyLong_AsDouble(value.ptr());
  if (d == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    raiseValue(path + ": the integer is too large for a number (beyond 1.8e308)");
  }
  return d;
}

// obj.__index__() as a Python int, or ValueError naming `path` with what it raised.
py::object indexOf(py::handle value, const std::string& path) {
  PyObject* i = PyNumber_Index(value.ptr());
  if (i == nullptr) raiseValue(path + ": " + takeError());
  return py::reinterpret_steal<py::object>(i);
}

bool isComplex(py::handle value) {
  return PyComplex_Check(value.ptr()) || numpyKind(value) == 'c';
}

json toJsonAt(py::handle value, const std::string& path, const std::string& root, int depth) {
  if (depth > kMaxJsonDepth) {
    raiseValue(root + ": nested more than " + std::to_string(kMaxJsonDepth) +
               " levels deep (or a list or dict that contains itself)");
  }
  if (value.is_none()) return nullptr;
  // bool before int: Python's bool is an int.
  if (py::isinstance<py::bool_>(value)) return PyObject_IsTrue(value.ptr()) == 1;
  // Integers beyond 64 bits become floats, as a JSON reader would read them.
  if (py::isinstance<py::int_>(value)) return intJson(value, path);
  if (py::isinstance<py::float_>(value)) return PyFloat_AsDouble(value.ptr());
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::dict>(value)) {
    json out = json::object();
    for (auto item : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(item.first))
        raiseValue(path + ": dict keys must be strings, not " + typeName(item.first));
      std::string key = item.first.cast<std::string>();
      out[key] = toJsonAt(item.second, path.empty() ? key : path + "." + key, root, depth + 1);
    }
    return out;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value) ||
      py::isinstance<py::array>(value)) {
    if (py::isinstance<py::array>(value) && py::reinterpret_borrow<py::array>(value).ndim() == 0)
      return toJsonAt(value.attr("item")(), path, root, depth + 1);
    json out = json::array();
    std::size_t i = 0;
    for (py::handle item : value) {
      out.push_back(toJsonAt(item, path + "[" + std::to_string(i) + "]", root, depth + 1));
      ++i;
    }
    return out;
  }
  // numpy scalars (looked at last: numpyKind costs an attribute lookup) and anything else that
  // is a number.
  if (numpyKind(value) == 'b') return PyObject_IsTrue(value.ptr()) == 1;
  if (isComplex(value)) raiseValue(path + ": a complex number is not a JSON value");
  if (py::hasattr(value, "__index__")) return intJson(indexOf(value, path), path);
  if (py::hasattr(value, "__float__")) return toDouble(value, path);
  raiseValue(path + ": a " + typeName(value) +
             " is not a JSON value (expected a number, string, list, tuple, dict or None)");
}

}  // namespace

json toJson(py::handle value, const std::string& path) {
  return toJsonAt(value, path, path, 0);
}

double toDouble(py::handle value, const std::string& path) {
  // Python floats (numpy float64 among them) and ints first, without numpyKind's lookup.
  if (PyFloat_Check(value.ptr())) return PyFloat_AS_DOUBLE(value.ptr());
  if (PyBool_Check(value.ptr()) || (!PyLong_Check(value.ptr()) && numpyKind(value) == 'b'))
    raiseValue(path + ": must be a number, not a bool");
  if (PyLong_Check(value.ptr())) return intJson(value, path).get<double>();
  if (isComplex(value)) raiseValue(path + ": must be a real number, not a complex one");
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
      py::isinstance<py::array>(value) ||
      (!py::hasattr(value, "__float__") && !py::hasattr(value, "__index__")))
    raiseValue(path + ": must be a number, not a " + typeName(value));
  if (!py::hasattr(value, "__float__")) return intJson(indexOf(value, path), path).get<double>();
  const double d = PyFloat_AsDouble(value.ptr());
  if (d == -1.0 && PyErr_Occurred()) raiseValue(path + ": " + takeError());
  return d;
}

long long toInteger(py::handle value, const std::string& path, long long lo, long long hi) {
  const std::string expected =
      path + ": must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi);
  if (py::isinstance<py::bool_>(value) || numpyKind(value) == 'b' ||
      (!py::isinstance<py::int_>(value) && !py::hasattr(value, "__index__")) ||
      py::isinstance<py::array>(value))
    raiseValue(expected + ", not a " + typeName(value));
  py::object i = indexOf(value, path);
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (v == -1 && PyErr_Occurred()) raiseValue(path + ": " + takeError());
  if (overflow != 0 || v < lo || v > hi) raiseValue(expected + ", got " + std::string(py::str(i)));
  return v;
}

py::array_t<double, py::array::c_style | py::array::forcecast> toDoubleArray(
    py::handle value, const std::string& path, const std::string& expected) {
  using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
  py::array a = py::array::ensure(value);
  if (!a) {
    PyErr_Clear();
    raiseValue(expected);
  }
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u' && kind != 'f') {
    raiseValue(path + ": must hold integers or floats, not " + std::string(py::str(a.dtype())) +
               " (" + expected + ")");
  }
  Doubles d = Doubles::ensure(a);
  if (!d) {
    PyErr_Clear();
    raiseValue(expected);
  }
  return d;
}

py::object toPython(const json& j) {
  switch (j.type()) {
    case json::value_t::null:
      return py::none();
    case json::value_t::boolean:
      return py::bool_(j.get<bool>());
    case json::value_t::number_integer:
      return py::int_(j.get<long long>());
    case json::value_t::number_unsigned:
      return py::int_(j.get<unsigned long long>());
    case json::value_t::number_float:
      return py::float_(j.get<double>());
    case json::value_t::string:
      return py::str(j.get<std::string>());
    case json::value_t::array: {
      py::list out;
      for (const json& item : j)
        out.append(toPython(item));
      return out;
    }
    case json::value_t::object: {
      py::dict out;
      for (const auto& item : j.items())
        out[py::str(item.key())] = toPython(item.value());
      return out;
    }
    default:
      return py::none();
  }
}

std::string formatNumber(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

namespace {

// The io layer's rules for one number of a pose or position: finite as a float, and for
// coordinates within kMaxCoordinate.
std::string checkNumber(double v, const std::string& path, bool coordinate) {
  const float f = static_cast<float>(v);
  if (!std::isfinite(f)) return path + ": must be finite (as a float)";
  if (coordinate && std::fabs(f) > kMaxCoordinate)
    return path + ": " + formatNumber(v) + " m is beyond the coordinate limit 1e9 m";
  return "";
}

}  // namespace

std::vector<double> toNumbers(py::handle value, std::size_t n, const std::string& path,
                              const char* what) {
  const std::string expected = path + ": must be " + what;
  if (py::isinstance<py::str>(value) || !py::isinstance<py::sequence>(value)) {
    if (!py::isinstance<py::array>(value)) raiseValue(expected);
  }
  std::vector<double> out;
  std::size_t i = 0;
  for (py::handle item : value) {
    if (i == n) raiseValue(expected);
    out.push_back(toDouble(item, path + "[" + std::to_string(i) + "]"));
    ++i;
  }
  if (i != n) raiseValue(expected);
  return out;
}

std::string checkCoordinate(double v, const std::string& path) {
  return checkNumber(v, path, true);
}

std::string checkPose(double x, double y, double angle, const std::string& path) {
  std::string bad = checkNumber(x, path + "[0]", true);
  if (bad.empty()) bad = checkNumber(y, path + "[1]", true);
  if (bad.empty()) bad = checkNumber(angle, path + "[2]", false);
  return bad;
}

std::string checkPosition(double x, double y, const std::string& path) {
  std::string bad = checkNumber(x, path + "[0]", true);
  if (bad.empty()) bad = checkNumber(y, path + "[1]", true);
  return bad;
}

Transform toTransform(py::handle pose, const std::string& path) {
  if (pose.is_none()) return Transform{};
  std::vector<double> v = toNumbers(pose, 3, path, "a pose (x, y, angle)");
  if (std::string bad = checkPose(v[0], v[1], v[2], path); !bad.empty()) raiseValue(bad);
  return makeTransform({static_cast<float>(v[0]), static_cast<float>(v[1])},
                       static_cast<float>(v[2]));
}

Vec2 toPosition(py::handle value, const std::string& path) {
  std::vector<double> v = toNumbers(value, 2, path, "a vector (x, y)");
  if (std::string bad = checkPosition(v[0], v[1], path); !bad.empty()) raiseValue(bad);
  return {static_cast<float>(v[0]), static_cast<float>(v[1])};
}

float toLength(py::handle value, const std::string& path) {
  const double v = toDouble(value, path);
  if (!(v >= 0.0) || v > static_cast<double>(kMaxCoordinate))
    raiseValue(path + ": must be a number >= 0 within the coordinate limit 1e9 m");
  return static_cast<float>(v);
}

Vec2 toVector(py::handle value, const std::string& path, const char* unit) {
  std::vector<double> v = toNumbers(value, 2, path, "a vector (x, y)");
  for (int i = 0; i < 2; ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    const float f = static_cast<float>(v[i]);
    if (!std::isfinite(f)) raiseValue(at + ": must be finite (as a float)");
    if (std::fabs(f) > kMaxCoordinate)
      raiseValue(at + ": " + formatNumber(v[i]) + " " + unit + " is beyond the limit 1e9 " + unit);
  }
  return {static_cast<float>(v[0]), static_cast<float>(v[1])};
}

float toAngle(double angle, const std::string& path) {
  const float f = static_cast<float>(angle);
  if (!std::isfinite(f)) raiseValue(path + ": must be finite (as a float)");
  if (std::fabs(f) > kSceneMaxAngle)
    raiseValue(path + ": " + formatNumber(angle) +
               " rad is beyond the limit 1e4 rad (as in scene files)");
  return f;
}

py::tuple toTuple(Vec2 v) {
  return py::make_tuple(static_cast<double>(v.x), static_cast<double>(v.y));
}

const PyShape& toShape(py::handle value, const std::string& path) {
  if (!py::isinstance<PyShape>(value)) {
    if (std::string(py::str(value.get_type().attr("__module__"))) == "quack.d3") {
      raiseValue(path + ": a 3D quack.d3.Shape in a 2D query (3D shapes go to quack.d3.distance, " +
                 "...)");
    }
    raiseValue(path + ": must be a quack.Shape (made by quack.circle, ..., quack.shape), not " +
               std::string(py::str(value.get_type().attr("__name__"))));
  }
  return value.cast<const PyShape&>();
}

namespace {

// {"type": type} plus every keyword given (None: left out, so the format's default holds).
json shapeJson(const char* type, std::initializer_list<std::pair<const char*, py::handle>> fields) {
  json j = {{"type", type}};
  for (const auto& [key, value] : fields) {
    if (!value.is_none()) j[key] = toJson(value, std::string(type) + "." + key);
  }
  return j;
}

}  // namespace

void registerShapes(py::module_& m) {
  py::class_<PyShape>(m, "Shape",
                      "A shape in its own frame (shape frame), as the JSON format has it: "
                      "made by quack.circle, capsule, segment, box, polygon, concave or shape. "
                      "A concave shape holds its convex pieces.")
      .def_property_readonly(
          "type", [](const PyShape& s) { return s.json.at("type").get<std::string>(); },
          "The JSON type: circle, capsule, segment, box, polygon or concave.")
      .def_property_readonly(
          "concave", [](const PyShape& s) { return s.concave; },
          "True for a concave outline (split into convex pieces).")
      .def_property_readonly(
          "piece_count", [](const PyShape& s) { return s.pieces.size(); },
          "Convex pieces: 1, or the pieces of a concave outline.")
      .def(
          "to_dict", [](const PyShape& s) { return toPython(s.json); },
          "The shape as the JSON format's dict (quack.shape(d) makes it again).")
      .def(
          "area",
          [](const PyShape& s) {
            double area = 0.0;
            for (const ShapeGeometry& piece : s.pieces)
              area += static_cast<double>(computeMass(piece, 1.0f).mass);
            return area;
          },
          "Area in m^2 (the mass at density 1); 0 for a segment.")
      .def(
          "contains",
          [](const PyShape& s, py::handle point, py::handle pose) {
            const Vec2 p = invTransformPoint(toTransform(pose, "pose"), toPosition(point, "point"));
            for (const ShapeGeometry& piece : s.pieces)
              if (containsPoint(piece, p)) return true;
            return false;
          },
          py::arg("point"), py::arg("pose") = py::none(),
          "True when the world point lies in the shape placed by pose (x, y, angle).")
      .def("__repr__", [](const PyShape& s) {
        return "quack.shape(" + s.json.dump(-1, ' ', false, json::error_handler_t::replace) + ")";
      });

  m.def(
      "shape", [](py::handle d) { return makeShape(toJson(d, "shape"), "shape"); }, py::arg("d"),
      "A shape from the JSON format's dict, e.g. {\"type\": \"circle\", \"radius\": 0.5}.");
  m.def(
      "circle",
      [](py::handle radius, py::handle center) {
        return makeShape(shapeJson("circle", {{"center", center}, {"radius", radius}}), "circle");
      },
      py::arg("radius"), py::arg("center") = py::none(),
      "Solid disk: radius > 0, center (x, y) (default (0, 0)).");
  m.def(
      "capsule",
      [](py::handle p1, py::handle p2, py::handle radius) {
        return makeShape(shapeJson("capsule", {{"p1", p1}, {"p2", p2}, {"radius", radius}}),
                         "capsule");
      },
      py::arg("p1"), py::arg("p2"), py::arg("radius"),
      "Stadium: the points within radius > 0 of the segment p1-p2.");
  m.def(
      "segment",
      [](py::handle p1, py::handle p2) {
        return makeShape(shapeJson("segment", {{"p1", p1}, {"p2", p2}}), "segment");
      },
      py::arg("p1"), py::arg("p2"), "Line segment p1-p2 (no area).");
  m.def(
      "box",
      [](py::handle half, py::handle center, py::handle angle, py::handle radius) {
        return makeShape(
            shapeJson("box",
                      {{"half", half}, {"center", center}, {"angle", angle}, {"radius", radius}}),
            "box");
      },
      py::arg("half"), py::arg("center") = py::none(), py::arg("angle") = py::none(),
      py::arg("radius") = py::none(),
      "Rectangle with half-extents half (hx, hy) > 0, centred at center (default (0, 0)), "
      "turned by angle radians (default 0), rounded by radius (default 0).");
  m.def(
      "polygon",
      [](py::handle points, py::handle radius) {
        return makeShape(shapeJson("polygon", {{"points", points}, {"radius", radius}}), "polygon");
      },
      py::arg("points"), py::arg("radius") = py::none(),
      "Convex polygon from 3 to 64 points [(x, y), ...] in any order, rounded by radius "
      "(default 0). A concave point set is an error: use quack.concave.");
  m.def(
      "concave",
      [](py::handle points, py::handle holes) {
        return makeShape(shapeJson("concave", {{"points", points}, {"holes", holes}}), "concave");
      },
      py::arg("points"), py::arg("holes") = py::none(),
      "Simple polygon outline [(x, y), ...] (either orientation, with optional holes), split "
      "into convex pieces.");
}

}  // namespace quack::python
