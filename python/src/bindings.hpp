#pragma once
/// Shared pieces of the Python module `quack` (docs/python.md): the shape object, the
/// conversions between Python values and Quack's, and the registration functions of each
/// part of the module.

#include <pybind11/eval.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "quack/collision/mesh3.hpp"
#include "quack/collision/proxy.hpp"
#include "quack/core/result.hpp"
#include "quack/geometry/shapes.hpp"
#include "quack/geometry/shapes3.hpp"
#include "quack/math/aabb.hpp"
#include "quack/math/transform.hpp"
#include "quack/world/types.hpp"

namespace quack::python {

namespace py = pybind11;

/// `quack.Shape`: a shape as the JSON format has it (kept, for `to_dict` and messages) and
/// its convex pieces (one for every type but "concave"), shape frame.
struct PyShape {
  nlohmann::json json;
  std::vector<ShapeGeometry> pieces;
  bool concave = false;
};

/// `quack.d3.Shape`: a 3D shape as the JSON format has it, and its geometry (shape frame).
struct PyShape3 {
  nlohmann::json json;
  ShapeGeometry3 geometry;
};

/// `quack.d3.Mesh`: a static triangle mesh (mesh frame), made by quack.d3.mesh.
struct PyMesh3 {
  Mesh3 mesh;
};

/// Parses a shape in the JSON format (errors raise ValueError with the io layer's message,
/// whose fields start with `path`).
PyShape makeShape(nlohmann::json json, const std::string& path);

/// Raises ValueError with `message`.
[[noreturn]] void raiseValue(const std::string& message);
/// The value of a Result, or ValueError with its message.
template <class T>
T valueOrRaise(Result<T> r) {
  if (!r) raiseValue(r.error().message);
  return std::move(r).value();
}

/// How deep toJson follows lists, tuples, dicts and arrays (a shape needs 3 levels); deeper,
/// or a container that contains itself, is a ValueError naming the argument.
inline constexpr int kMaxJsonDepth = 64;
/// A Python value (None, bool, int, float, str, dict with str keys, list, tuple, numpy
/// array or scalar) as JSON; `path` names it in errors.
nlohmann::json toJson(py::handle value, const std::string& path);

/// A Python number (int, float, numpy integer or float, anything with __index__ or
/// __float__) as a double; bool, complex, str and anything else raise ValueError naming
/// `path`, as does a conversion that fails (an int beyond a double, a raising __float__).
double toDouble(py::handle value, const std::string& path);
/// A Python integer (int, numpy integer, anything with __index__; not bool) in lo..hi, or
/// ValueError naming `path`.
long long toInteger(py::handle value, const std::string& path, long long lo, long long hi);
/// `value` as a C-contiguous array of doubles, converted from an array (or nested list) of
/// integers or floats; bool, complex, string and object arrays raise ValueError naming `path`
/// with `expected`. A value that is no array at all raises the same.
py::array_t<double, py::array::c_style | py::array::forcecast> toDoubleArray(
    py::handle value, const std::string& path, const std::string& expected);
/// A Python sequence (or 1-D array) of exactly `n` numbers as doubles (each through
/// toDouble, naming `path[i]`), or ValueError "`path`: must be `what`".
std::vector<double> toNumbers(py::handle value, std::size_t n, const std::string& path,
                              const char* what);
/// `v` as printf's %g writes it, for messages.
std::string formatNumber(double v);
/// An array (N, width) (or (N,) for width 1) of numbers, each finite as a float, for N
/// bodies; errors name `name` and the row and column.
py::array_t<double, py::array::c_style | py::array::forcecast> toValues(py::handle v, std::size_t n,
                                                                        std::size_t width,
                                                                        const char* name);
/// A body type by its scene-file name (static, kinematic, dynamic), or ValueError naming
/// `type`.
BodyType toBodyType(const std::string& s);
/// JSON as Python values (objects as dicts, arrays as lists).
py::object toPython(const nlohmann::json& json);

/// Why the pose numbers (x, y, angle) are refused, or "" when they are fine: x and y finite
/// as floats and within the coordinate limit, the angle finite. `path` names the pose.
std::string checkPose(double x, double y, double angle, const std::string& path);
/// A coordinate finite as a float and within the coordinate limit (checkCoordinate's test,
/// without the message).
inline bool coordinateIsFine(double v) {
  const float f = static_cast<float>(v);
  return f >= -kMaxCoordinate && f <= kMaxCoordinate;  // false for NaN
}
/// Pose numbers checkPose accepts.
inline bool poseIsFine(double x, double y, double angle) {
  const float a = static_cast<float>(angle);
  return coordinateIsFine(x) && coordinateIsFine(y) && a - a == 0.0f;  // false for NaN, inf
}
/// Why the number is refused as a coordinate (finite as a float, within the coordinate
/// limit), or "".
std::string checkCoordinate(double v, const std::string& path);
/// Why the vector (x, y) is refused as a position or translation, or "".
std::string checkPosition(double x, double y, const std::string& path);
/// A pose `(x, y, angle)` as worldFromShape; None is the identity.
Transform toTransform(py::handle pose, const std::string& path);
/// A vector `(x, y)` (position or translation, metres, world frame).
Vec2 toPosition(py::handle value, const std::string& path);
/// A float >= 0 within the coordinate limit (a distance option).
float toLength(py::handle value, const std::string& path);
/// A vector (x, y) of another quantity (velocity, impulse, force, gravity): finite as
/// floats and at most 1e9 in size, in `unit` (said in the message).
Vec2 toVector(py::handle value, const std::string& path, const char* unit);
/// An angle of a body, radians: finite, |angle| <= 1e4 (kSceneMaxAngle, as in scene files).
float toAngle(double angle, const std::string& path);
/// A Vec2 as a tuple of two Python floats.
py::tuple toTuple(Vec2 v);
/// A quack.Shape argument (errors name `path`).
const PyShape& toShape(py::handle value, const std::string& path);
/// A vector (x, y, z) within the coordinate limit: a position or translation, metres.
Vec3 toPosition3(py::handle value, const std::string& path);
/// A pose: None (the identity), (x, y, z) (no rotation) or (x, y, z, qx, qy, qz, qw), the
/// quaternion read as floats and normalised in double (as `quack query` reads one).
Transform3 toTransform3(py::handle pose, const std::string& path);
/// Why the quaternion q[0..3] (qx, qy, qz, qw) is refused, or "": each component finite as a
/// float (errors name `path`[first + i]), not all zero.
std::string checkQuat(const double* q, const std::string& path, int first);

void registerShapes(py::module_& m);
void registerQueries(py::module_& m);
void registerBatch(py::module_& m);
void registerWorld(py::module_& m);
/// The submodule quack.d3 (3D shapes and queries), with its own answer classes; it calls
/// registerWorld3.
void registerD3(py::module_& m);
/// quack.d3.World and its handles, in the submodule `d3`.
void registerWorld3(py::module_& d3);

}  // namespace quack::python
