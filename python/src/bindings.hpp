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

#include "quack/collision/proxy.hpp"
#include "quack/core/result.hpp"
#include "quack/geometry/shapes.hpp"
#include "quack/math/aabb.hpp"
#include "quack/math/transform.hpp"

namespace quack::python {

namespace py = pybind11;

/// `quack.Shape`: a shape as the JSON format has it (kept, for `to_dict` and messages) and
/// its convex pieces (one for every type but "concave"), shape frame.
struct PyShape {
  nlohmann::json json;
  std::vector<ShapeGeometry> pieces;
  bool concave = false;
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

/// A Python value (None, bool, int, float, str, dict with str keys, list, tuple, numpy
/// array or scalar) as JSON; `path` names it in errors.
nlohmann::json toJson(py::handle value, const std::string& path);
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
/// A Vec2 as a tuple of two Python floats.
py::tuple toTuple(Vec2 v);
/// A quack.Shape argument (errors name `path`).
const PyShape& toShape(py::handle value, const std::string& path);

void registerShapes(py::module_& m);
void registerQueries(py::module_& m);
void registerBatch(py::module_& m);
void registerWorld(py::module_& m);

}  // namespace quack::python
