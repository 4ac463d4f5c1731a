// The submodule quack.d3: 3D shapes, the pair queries of `quack query` on 3D lines and their
// batch forms over numpy arrays. Shapes go through the io layer's JSON parser and answers
// through its toJson (quack/io/shape_json.hpp, answer_json.hpp), so a 3D query in Python
// is checked and answered exactly as a `quack query` line is.

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/manifold3.hpp"
#include "quack/collision/mesh3.hpp"
#include "quack/collision/toi3.hpp"
#include "quack/geometry/mass3.hpp"
#include "quack/geometry/raycast3.hpp"
#include "quack/io/answer_json.hpp"
#include "quack/io/shape_json.hpp"

namespace quack::python {

namespace {

using nlohmann::json;

PyShape3 makeShape3(nlohmann::json j, const std::string& path) {
  PyShape3 s;
  s.geometry = valueOrRaise(parseShape3(j, path));
  s.json = std::move(j);
  return s;
}

// {"type": type} plus every keyword given (None: left out, so the format's default holds).
json shapeJson(const char* type, std::initializer_list<std::pair<const char*, py::handle>> fields) {
  json j = {{"type", type}};
  for (const auto& [key, value] : fields) {
    if (!value.is_none()) j[key] = toJson(value, std::string(type) + "." + key);
  }
  return j;
}

const PyShape3& toShape3(py::handle value, const std::string& path) {
  if (py::isinstance<PyShape>(value)) {
    raiseValue(path + ": a 2D quack.Shape in a 3D query (quack.d3 takes quack.d3.sphere, " +
               "capsule, box, hull, triangle)");
  }
  if (py::isinstance<PyMesh3>(value)) {
    raiseValue(path + ": a quack.d3.Mesh is not a convex shape (a mesh is shape a of overlap, " +
               "distance, penetration, manifold, raycast, shapecast, toi and raycast_many, " +
               "or shape b of overlap, distance, penetration and toi)");
  }
  if (!py::isinstance<PyShape3>(value)) {
    raiseValue(path +
               ": must be a quack.d3.Shape (made by quack.d3.sphere, ..., quack.d3.shape), " +
               "not " + std::string(py::str(value.get_type().attr("__name__"))));
  }
  return value.cast<const PyShape3&>();
}

// The numbers of a Python sequence (or 1-D array) as doubles; `expected` is the message for
// anything else.
std::vector<double> toNumberList(py::handle value, const std::string& path,
                                 const std::string& expected) {
  if (py::isinstance<py::str>(value) ||
      (!py::isinstance<py::sequence>(value) && !py::isinstance<py::array>(value))) {
    raiseValue(path + ": " + expected);
  }
  std::vector<double> out;
  std::size_t i = 0;
  for (py::handle item : value) {
    if (i == 8) raiseValue(path + ": " + expected);
    out.push_back(toDouble(item, path + "[" + std::to_string(i) + "]"));
    ++i;
  }
  return out;
}

// The pose numbers' first refusal, or "": the position within the coordinate limit, the
// quaternion as checkQuat.
std::string checkPose3(const double* p, const std::string& path) {
  for (int i = 0; i < 3; ++i) {
    if (std::string bad = checkCoordinate(p[i], path + "[" + std::to_string(i) + "]"); !bad.empty())
      return bad;
  }
  return checkQuat(p + 3, path, 3);
}

// Pose numbers checkPose3 accepts (the test without the message, for the batch loops).
bool pose3IsFine(const double* p) {
  for (int i = 0; i < 3; ++i)
    if (!coordinateIsFine(p[i])) return false;
  bool nonZero = false;
  for (int i = 3; i < 7; ++i) {
    const float f = static_cast<float>(p[i]);
    if (!std::isfinite(f)) return false;
    nonZero |= f != 0.0f;
  }
  return nonZero;
}

// The pose (x, y, z, qx, qy, qz, qw) of checked numbers: the quaternion read as floats and
// normalised in double, as parsePose3 does, so a Python query and a `quack query` line with
// the same numbers give the same bits.
Transform3 poseFromNumbers(const double* p) {
  double q[4];
  for (int i = 0; i < 4; ++i)
    q[i] = static_cast<double>(static_cast<float>(p[3 + i]));
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return {{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])},
          {static_cast<float>(q[0] / norm), static_cast<float>(q[1] / norm),
           static_cast<float>(q[2] / norm), static_cast<float>(q[3] / norm)}};
}

// A sweep (pose_from, pose_to) of a shape turning about its proxy's centre, as `quack query`
// op toi in 3D.
Sweep3 toSweep3(py::handle sweep, const ShapeProxy3& proxy, const std::string& path) {
  if (!py::isinstance<py::sequence>(sweep) || py::isinstance<py::str>(sweep) ||
      py::len(sweep) != 2) {
    raiseValue(path +
               ": must be (pose_from, pose_to), each pose (x, y, z) or (x, y, z, qx, qy, "
               "qz, qw)");
  }
  py::sequence s = py::reinterpret_borrow<py::sequence>(sweep);
  return makeSweep3(proxy.center(), toTransform3(s[0], path + "[0]"),
                    toTransform3(s[1], path + "[1]"));
}

// The answer object: the Python class `cls` of quack.d3 made from the JSON answer.
py::object answer(const py::module_& m, const char* cls, const json& j) {
  return m.attr(cls)(toPython(j));
}

// ---- batch ----

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// One side's shapes: one shape for every row, or a list of N shapes (kept alive by `keep`
// while the GIL is released).
struct ShapeSide3 {
  std::vector<py::object> keep;
  std::vector<const ShapeGeometry3*> shapes;
  std::vector<ShapeProxy3> proxies;
  bool single = true;
  std::size_t at(std::size_t i) const { return single ? 0 : i; }
};

ShapeSide3 toShapeSide3(py::handle value, const std::string& name) {
  ShapeSide3 side;
  auto add = [&](py::handle item, const std::string& path) {
    const PyShape3& s = toShape3(item, path);
    side.keep.push_back(py::reinterpret_borrow<py::object>(item));
    side.shapes.push_back(&s.geometry);
    side.proxies.push_back(makeProxy(s.geometry));
  };
  if (py::isinstance<PyShape3>(value)) {
    add(value, name);
    return side;
  }
  if (py::isinstance<PyMesh3>(value)) {
    raiseValue(name + ": a quack.d3.Mesh is taken by raycast_many only among the batch " +
               "queries (the pair queries take it one pair at a time)");
  }
  if (py::isinstance<py::str>(value) || !py::isinstance<py::sequence>(value)) {
    raiseValue(name + ": must be a quack.d3.Shape or a list of N quack.d3.Shape, not " +
               std::string(py::str(value.get_type().attr("__name__"))));
  }
  side.single = false;
  std::size_t i = 0;
  for (py::handle item : value) {
    add(item, name + "[" + std::to_string(i) + "]");
    ++i;
  }
  if (i == 0) raiseValue(name + ": the list of shapes is empty");
  return side;
}

// Rows of `width` numbers: an array (N, width), or one row (width,) used for every pair.
struct Rows3 {
  Doubles array;
  const double* data = nullptr;
  std::size_t count = 0;
  bool single = false;
  std::size_t width = 0;
  const double* at(std::size_t i) const { return single ? data : data + i * width; }
};

Rows3 toRows3(py::handle value, std::size_t width, const std::string& name, const char* what) {
  Rows3 r;
  r.width = width;
  const std::string expected = name + ": must be a numpy array of shape (N, " +
                               std::to_string(width) + ") or (" + std::to_string(width) + ",) (" +
                               what + " per row)";
  r.array = toDoubleArray(value, name, expected);
  if (r.array.ndim() == 2 && r.array.shape(1) == static_cast<py::ssize_t>(width)) {
    r.count = static_cast<std::size_t>(r.array.shape(0));
  } else if (r.array.ndim() == 1 && r.array.shape(0) == static_cast<py::ssize_t>(width)) {
    r.count = 1;
    r.single = true;
  } else {
    std::string got = "(";
    for (py::ssize_t i = 0; i < r.array.ndim(); ++i)
      got += (i > 0 ? ", " : "") + std::to_string(r.array.shape(i));
    raiseValue(expected + ", not " + got + (r.array.ndim() == 1 ? ",)" : ")"));
  }
  r.data = r.array.data();
  return r;
}

std::optional<std::size_t> rowsOf(const ShapeSide3& s) {
  return s.single ? std::nullopt : std::optional<std::size_t>(s.shapes.size());
}
std::optional<std::size_t> rowsOf(const Rows3& r) {
  return r.single ? std::nullopt : std::optional<std::size_t>(r.count);
}

// N: the rows every per-pair input agrees on (a single shape or row serves every pair).
std::size_t pairCount(
    std::initializer_list<std::pair<std::string, std::optional<std::size_t>>> sides) {
  std::optional<std::size_t> n;
  std::string first;
  for (const auto& [name, rows] : sides) {
    if (!rows) continue;
    if (!n) {
      n = rows;
      first = name;
    } else if (*rows != *n) {
      raiseValue(name + ": " + std::to_string(*rows) + " rows, but " + first + " has " +
                 std::to_string(*n) + " (give N of each, or one for every pair)");
    }
  }
  return n.value_or(1);
}

// Refuses the first bad pose row before any answer is computed.
void checkPoseRows(const Rows3& poses, const std::string& name, std::size_t n) {
  const std::size_t rows = poses.single ? 1 : n;
  for (std::size_t i = 0; i < rows; ++i) {
    if (pose3IsFine(poses.at(i))) continue;  // the message only for a bad row
    raiseValue(checkPose3(poses.at(i), poses.single ? name : name + "[" + std::to_string(i) + "]"));
  }
}

struct PairInputs3 {
  ShapeSide3 a, b;
  Rows3 pa, pb;
  std::size_t n = 0;
  Transform3 poseA(std::size_t i) const { return poseFromNumbers(pa.at(i)); }
  Transform3 poseB(std::size_t i) const { return poseFromNumbers(pb.at(i)); }
  const ShapeProxy3& proxyA(std::size_t i) const { return a.proxies[a.at(i)]; }
  const ShapeProxy3& proxyB(std::size_t i) const { return b.proxies[b.at(i)]; }
};

constexpr const char* kPoseColumns = "x, y, z, qx, qy, qz, qw";

PairInputs3 toPairInputs3(py::handle shapesA, py::handle posesA, py::handle shapesB,
                          py::handle posesB) {
  PairInputs3 in;
  in.a = toShapeSide3(shapesA, "shapes_a");
  in.pa = toRows3(posesA, 7, "poses_a", kPoseColumns);
  in.b = toShapeSide3(shapesB, "shapes_b");
  in.pb = toRows3(posesB, 7, "poses_b", kPoseColumns);
  in.n = pairCount({{"shapes_a", rowsOf(in.a)},
                    {"poses_a", rowsOf(in.pa)},
                    {"shapes_b", rowsOf(in.b)},
                    {"poses_b", rowsOf(in.pb)}});
  checkPoseRows(in.pa, "poses_a", in.n);
  checkPoseRows(in.pb, "poses_b", in.n);
  return in;
}

template <class T>
py::array_t<T> column(std::size_t n) {
  return py::array_t<T>(static_cast<py::ssize_t>(n));
}

py::array_t<double> triples(std::size_t n) {
  return py::array_t<double>({static_cast<py::ssize_t>(n), py::ssize_t{3}});
}

void put(double* out, std::size_t i, Vec3 v) {
  out[3 * i] = static_cast<double>(v.x);
  out[3 * i + 1] = static_cast<double>(v.y);
  out[3 * i + 2] = static_cast<double>(v.z);
}

// ---- meshes ----

// A mesh from vertices (N, 3) and triangles (M, 3) of vertex indices, counter-clockwise
// seen from the front; errors name the field as parseMesh3's do ("triangles[1][2]: ...").
PyMesh3 makePyMesh3(py::handle vertices, py::handle triangles) {
  const std::string expectedV = "vertices: must be a numpy array (N, 3) of x, y, z";
  Doubles v = toDoubleArray(vertices, "vertices", expectedV);
  if (v.ndim() != 2 || v.shape(1) != 3) raiseValue(expectedV);
  const auto n = static_cast<std::size_t>(v.shape(0));
  std::vector<Vec3> points(n);
  const double* vd = v.data();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string bad = checkCoordinate(
          vd[3 * i + k], "vertices[" + std::to_string(i) + "][" + std::to_string(k) + "]");
      if (!bad.empty()) raiseValue(bad);
    }
    points[i] = {static_cast<float>(vd[3 * i]), static_cast<float>(vd[3 * i + 1]),
                 static_cast<float>(vd[3 * i + 2])};
  }
  const std::string expectedT = "triangles: must be a numpy array (M, 3) of integer vertex indices";
  py::array t = py::module_::import("numpy").attr("asarray")(triangles);
  const char kind = t.dtype().kind();
  if (kind != 'i' && kind != 'u') {
    raiseValue(expectedT + ", not of dtype " + std::string(py::str(t.dtype())));
  }
  if (t.ndim() != 2 || t.shape(1) != 3) {
    std::string got = "(";
    for (py::ssize_t i = 0; i < t.ndim(); ++i)
      got += (i > 0 ? ", " : "") + std::to_string(t.shape(i));
    raiseValue(expectedT + ", not " + got + (t.ndim() == 1 ? ",)" : ")"));
  }
  // Unsigned indices beyond int64 stay unsigned, so they are out of range, not negative.
  using Indices = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;
  using Unsigned = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>;
  const auto m = static_cast<std::size_t>(t.shape(0));
  std::vector<std::array<std::int32_t, 3>> tris(m);
  Indices signedIndices;
  Unsigned unsignedIndices;
  if (kind == 'u') {
    unsignedIndices = Unsigned::ensure(t);
  } else {
    signedIndices = Indices::ensure(t);
  }
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t at = 3 * i + k;
      const bool negative = kind != 'u' && signedIndices.data()[at] < 0;
      const bool beyond = kind == 'u' ? unsignedIndices.data()[at] >= n
                                      : static_cast<std::uint64_t>(signedIndices.data()[at]) >= n;
      if (negative || beyond) {
        const std::string index = kind == 'u' ? std::to_string(unsignedIndices.data()[at])
                                              : std::to_string(signedIndices.data()[at]);
        raiseValue("triangles[" + std::to_string(i) + "][" + std::to_string(k) +
                   "]: vertex index " + index + " is out of range (0 to " +
                   std::to_string(static_cast<long long>(n) - 1) + ")");
      }
      tris[i][k] = static_cast<std::int32_t>(kind == 'u' ? unsignedIndices.data()[at]
                                                         : signedIndices.data()[at]);
    }
  }
  return {valueOrRaise(makeMesh3At(points, tris, ""))};
}

bool isMesh(py::handle value) {
  return py::isinstance<PyMesh3>(value);
}

// The pose of a static mesh in toi: None (the origin) or (pose, pose), the same pose twice.
Transform3 toStaticSweep3(py::handle sweep, const std::string& path) {
  if (sweep.is_none()) return Transform3{};
  if (!py::isinstance<py::sequence>(sweep) || py::isinstance<py::str>(sweep) ||
      py::len(sweep) != 2) {
    raiseValue(path +
               ": must be None (the mesh at the origin) or (pose, pose), a static mesh's "
               "pose twice");
  }
  py::sequence s = py::reinterpret_borrow<py::sequence>(sweep);
  const Transform3 from = toTransform3(s[0], path + "[0]");
  const Transform3 to = toTransform3(s[1], path + "[1]");
  if (!(from.p == to.p && from.q == to.q)) {
    raiseValue(path + "[1]: a mesh is static: its pose must be " + path +
               "[0]'s (or give None: the mesh at the origin)");
  }
  return from;
}

// A pair query with a mesh as a (any op) or as b (overlap, distance, penetration, toi), as
// `quack query` answers it: the mesh's own query (collision/mesh3.hpp), the answer with the
// triangle's index, turned round (points swapped, normal negated) when the mesh is b.
// `pa`, `pb` are the poses (the sweeps for toi); `extra` the translation (shapecast), the
// speculative distance (manifold) or the target (toi).
py::object answerMesh(const py::module_& m, const std::string& op, py::handle a, py::handle pa,
                      py::handle b, py::handle pb, py::handle extra) {
  const bool meshIsA = isMesh(a);
  if (meshIsA && isMesh(b))
    raiseValue("b: a mesh against a mesh is not supported (b must be convex)");
  if (!meshIsA && op != "overlap" && op != "distance" && op != "penetration" && op != "toi") {
    raiseValue("b: a quack.d3.Mesh must be shape a for " + op +
               " (as shape b it serves overlap, distance, penetration, toi)");
  }
  const Mesh3& mesh = (meshIsA ? a : b).cast<const PyMesh3&>().mesh;
  const char* convexKey = meshIsA ? "b" : "a";
  const PyShape3& convex = toShape3(meshIsA ? b : a, convexKey);
  const ShapeProxy3 proxy = makeProxy(convex.geometry);
  if (op == "toi") {
    const Transform3 worldFromMesh =
        toStaticSweep3(meshIsA ? pa : pb, meshIsA ? "sweepA" : "sweepB");
    const Sweep3 sweep = toSweep3(meshIsA ? pb : pa, proxy, meshIsA ? "sweepB" : "sweepA");
    const float target = extra.is_none() ? kToiTargetSeparation : toLength(extra, "target");
    return answer(m, "MeshToiResult",
                  quack::toJson(computeToiMesh(mesh, worldFromMesh, proxy, sweep, 1.0f, target)));
  }
  const Transform3 worldFromMesh = toTransform3(meshIsA ? pa : pb, meshIsA ? "pa" : "pb");
  const Transform3 worldFromConvex = toTransform3(meshIsA ? pb : pa, meshIsA ? "pb" : "pa");
  if (op == "overlap") {
    return answer(m, "OverlapResult",
                  json{{"overlap", testOverlapMesh(mesh, worldFromMesh, proxy, worldFromConvex)}});
  }
  if (op == "distance") {
    MeshDistanceOutput3 d = computeDistanceMesh(mesh, worldFromMesh, proxy, worldFromConvex);
    if (!meshIsA) {
      std::swap(d.pointA, d.pointB);
      d.normal = -d.normal;
    }
    return answer(m, "MeshDistanceResult", quack::toJson(d));
  }
  if (op == "penetration") {
    MeshPenetrationOutput3 p = computePenetrationMesh(mesh, worldFromMesh, proxy, worldFromConvex);
    if (!meshIsA) {
      std::swap(p.pointA, p.pointB);
      p.normal = -p.normal;
    }
    return answer(m, "MeshPenetrationResult", quack::toJson(p));
  }
  if (op == "shapecast") {
    const Vec3 t = toPosition3(extra, "translation");
    return answer(m, "MeshShapeCastResult",
                  quack::toJson(castShapeMesh(mesh, worldFromMesh, proxy, worldFromConvex, t)));
  }
  const float s = extra.is_none() ? kSpeculativeDistance : toLength(extra, "speculative");
  std::vector<MeshContact3> contacts;
  collideMesh(mesh, worldFromMesh, convex.geometry, worldFromConvex, contacts, s);
  return answer(m, "MeshManifoldResult", quack::toJson(contacts));
}

// Refuses the first ray row (origin, translation) with a number beyond the coordinate limit.
void checkRayRows(const Rows3& r, std::size_t n) {
  for (std::size_t i = 0; i < (r.single ? 1 : n); ++i) {
    const double* ray = r.at(i);
    bool fine = true;
    for (int k = 0; k < 6; ++k)
      fine &= coordinateIsFine(ray[k]);
    if (fine) continue;
    const std::string path = r.single ? std::string("rays") : "rays[" + std::to_string(i) + "]";
    for (int k = 0; k < 6; ++k) {
      if (std::string bad = checkCoordinate(ray[k], path + "[" + std::to_string(k) + "]");
          !bad.empty())
        raiseValue(bad);
    }
  }
}

Vec3 rayOrigin(const double* ray) {
  return {static_cast<float>(ray[0]), static_cast<float>(ray[1]), static_cast<float>(ray[2])};
}
Vec3 rayTranslation(const double* ray) {
  return {static_cast<float>(ray[3]), static_cast<float>(ray[4]), static_cast<float>(ray[5])};
}

py::object makeResult(const py::module_& root, const char* kind, py::dict fields);

// raycast_many with a mesh: rayCastMesh per row, and the triangle hit (-1 on a miss).
py::object rayCastMeshMany(const py::module_& root, py::handle meshValue, py::handle poses,
                           py::handle rays) {
  const Mesh3& mesh = meshValue.cast<const PyMesh3&>().mesh;
  Rows3 pa = toRows3(poses, 7, "poses", kPoseColumns);
  Rows3 r = toRows3(rays, 6, "rays", "origin x, y, z, translation x, y, z");
  const std::size_t n = pairCount({{"poses", rowsOf(pa)}, {"rays", rowsOf(r)}});
  checkPoseRows(pa, "poses", n);
  checkRayRows(r, n);
  auto hit = column<bool>(n);
  auto fraction = column<double>(n);
  auto point = triples(n), normal = triples(n);
  auto triangle = column<std::int32_t>(n);
  bool* h = hit.mutable_data();
  double* f = fraction.mutable_data();
  double* pt = point.mutable_data();
  double* nrm = normal.mutable_data();
  std::int32_t* tri = triangle.mutable_data();
  {
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < n; ++i) {
      const double* ray = r.at(i);
      const MeshRayHit3 rh =
          rayCastMesh(mesh, poseFromNumbers(pa.at(i)), {rayOrigin(ray), rayTranslation(ray), 1.0f});
      h[i] = rh.hit;
      f[i] = static_cast<double>(rh.fraction);
      put(pt, i, rh.point);
      put(nrm, i, rh.normal);
      tri[i] = rh.triangle;
    }
  }
  return makeResult(
      root, "raycast",
      py::dict(py::arg("hit") = hit, py::arg("fraction") = fraction, py::arg("point") = point,
               py::arg("normal") = normal, py::arg("triangle") = triangle));
}

py::object makeResult(const py::module_& root, const char* kind, py::dict fields) {
  py::object r = root.attr("BatchResult")();
  r.attr("kind") = kind;
  for (auto item : fields)
    r.attr(item.first) = item.second;
  r.attr("_fields") = py::tuple(fields.attr("keys")());
  return r;
}

// The Python answer classes: each holds the JSON answer (a dict) and shows its fields,
// vectors as tuples; to_dict gives the dict as `quack query` writes it (without "id").
constexpr const char* kAnswerClasses = R"py(
import copy as _copy

class _Answer:
    __slots__ = ("_d",)
    def __init__(self, d):
        self._d = d
    def to_dict(self):
        """The answer as `quack query` writes it for a 3D line (a dict, without "id")."""
        return _copy.deepcopy(self._d)
    def __repr__(self):
        return "%s(%s)" % (type(self).__name__, ", ".join(
            "%s=%r" % (k, v) for k, v in self._d.items() if not isinstance(v, list)))

def _field(name, doc):
    def get(self):
        v = self._d[name]
        return tuple(v) if isinstance(v, list) else v
    return property(get, doc=doc)

class OverlapResult(_Answer):
    """Answer of quack.d3.overlap."""
    __slots__ = ()
    overlap = _field("overlap", "The closed shapes share a point.")
    def __bool__(self):
        return bool(self._d["overlap"])

class DistanceResult(_Answer):
    """Answer of quack.d3.distance (world frame; normal from a to b)."""
    __slots__ = ()
    distance = _field("distance", "Distance between the shapes, metres (0 when they overlap).")
    pointA = _field("pointA", "Closest point on a (x, y, z), world frame.")
    pointB = _field("pointB", "Closest point on b (x, y, z), world frame.")
    point_a = _field("pointA", "pointA (PEP 8 name).")
    point_b = _field("pointB", "pointB (PEP 8 name).")
    normal = _field("normal", "Unit vector from a to b; zero when the cores overlap.")
    iterations = _field("iterations", "GJK support-point evaluations.")
    status = _field("status", "GJK status, one of quack.GJK_STATUSES.")

class PenetrationResult(_Answer):
    """Answer of quack.d3.penetration (world frame; normal from a to b; depth 0 apart)."""
    __slots__ = ()
    overlap = _field("overlap", "The shapes overlap.")
    depth = _field("depth", "Penetration depth, metres (0 when apart).")
    normal = _field("normal", "Unit vector from a to b along which b moves out.")
    pointA = _field("pointA", "Point of a deepest in b, world frame.")
    pointB = _field("pointB", "Point of b deepest in a, world frame.")
    point_a = _field("pointA", "pointA (PEP 8 name).")
    point_b = _field("pointB", "pointB (PEP 8 name).")
    iterations = _field("iterations", "GJK plus EPA support-point evaluations.")
    status = _field("status", "EPA status, one of quack.d3.EPA_STATUSES.")

class ManifoldPoint(_Answer):
    """One contact point of a 3D manifold (world frame)."""
    __slots__ = ()
    point = _field("point", "The contact point (x, y, z), midway between the surfaces.")
    separation = _field("separation", "Signed separation, metres (negative: overlap).")
    id = _field("id", "Feature id: the same while the same features touch.")

class ManifoldResult(_Answer):
    """Answer of quack.d3.manifold: normal from a to b ((0, 0, 0) without points) and up
    to four points."""
    __slots__ = ()
    normal = _field("normal", "Unit contact normal from a to b.")
    @property
    def points(self):
        """The contact points (0 to 4), as ManifoldPoint."""
        return [ManifoldPoint(p) for p in self._d["points"]]

class RayCastResult(_Answer):
    """Answer of quack.d3.raycast (world frame); every number 0 on a miss."""
    __slots__ = ()
    hit = _field("hit", "The ray enters the shape.")
    fraction = _field("fraction", "Fraction of the translation at the entry point.")
    point = _field("point", "Entry point (x, y, z), world frame.")
    normal = _field("normal", "Outward unit normal at the entry point.")
    def __bool__(self):
        return bool(self._d["hit"])

class ShapeCastResult(_Answer):
    """Answer of quack.d3.shapecast (world frame)."""
    __slots__ = ()
    hit = _field("hit", "b touches a within the translation (or overlaps it at the start).")
    fraction = _field("fraction", "Fraction of the translation at the first touch.")
    point = _field("point", "Point on a nearest b then, world frame.")
    normal = _field("normal", "Unit normal from a to b then.")
    depth = _field("depth", "When overlapped at the start: metres to move b out; else 0.")
    status = _field("status", "hit, missed, overlapped, max_iterations or invalid_input.")

class ToiResult(_Answer):
    """Answer of quack.d3.toi."""
    __slots__ = ()
    status = _field("status", "Time of impact status, as `quack query` answers it.")
    t = _field("t", "Fraction of the sweep in [0, 1] at the impact (1 when none).")

_TRIANGLE = "The mesh's triangle (an index into its triangles), -1 when there is none."

class MeshRayCastResult(RayCastResult):
    """Answer of quack.d3.raycast against a quack.d3.Mesh: RayCastResult and the triangle."""
    __slots__ = ()
    triangle = _field("triangle", _TRIANGLE)

class MeshShapeCastResult(ShapeCastResult):
    """Answer of quack.d3.shapecast against a quack.d3.Mesh: ShapeCastResult and the
    triangle hit."""
    __slots__ = ()
    triangle = _field("triangle", _TRIANGLE)

class MeshDistanceResult(DistanceResult):
    """Answer of quack.d3.distance with a quack.d3.Mesh: DistanceResult of the closest
    triangle, and the triangle."""
    __slots__ = ()
    triangle = _field("triangle", _TRIANGLE)

class MeshPenetrationResult(PenetrationResult):
    """Answer of quack.d3.penetration with a quack.d3.Mesh: PenetrationResult of the deepest
    triangle (the closest when none overlaps), and the triangle."""
    __slots__ = ()
    triangle = _field("triangle", _TRIANGLE)

class MeshToiResult(ToiResult):
    """Answer of quack.d3.toi with a quack.d3.Mesh: ToiResult and the triangle hit."""
    __slots__ = ()
    triangle = _field("triangle", _TRIANGLE)

class MeshContact(ManifoldResult):
    """One triangle's manifold in a MeshManifoldResult (normal from the mesh to b)."""
    __slots__ = ()
    triangle = _field("triangle", "The mesh's triangle (an index into its triangles).")

class MeshManifoldResult(_Answer):
    """Answer of quack.d3.manifold against a quack.d3.Mesh: one manifold per touching
    triangle, in triangle order."""
    __slots__ = ()
    @property
    def manifolds(self):
        """The touching triangles' manifolds, as MeshContact."""
        return [MeshContact(c) for c in self._d["manifolds"]]

for _c in (OverlapResult, DistanceResult, PenetrationResult, ManifoldPoint, ManifoldResult,
           RayCastResult, ShapeCastResult, ToiResult, MeshRayCastResult, MeshShapeCastResult,
           MeshDistanceResult, MeshPenetrationResult, MeshToiResult, MeshContact,
           MeshManifoldResult):
    _c.__module__ = "quack.d3"
del _c
)py";

}  // namespace

std::string checkQuat(const double* q, const std::string& path, int first) {
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(static_cast<float>(q[i])))
      return path + "[" + std::to_string(first + i) + "]: must be finite (as a float)";
  }
  if (static_cast<float>(q[0]) == 0.0f && static_cast<float>(q[1]) == 0.0f &&
      static_cast<float>(q[2]) == 0.0f && static_cast<float>(q[3]) == 0.0f) {
    return path + ": the quaternion (qx, qy, qz, qw) is zero, not a rotation (the identity is " +
           "(0, 0, 0, 1))";
  }
  return "";
}

Transform3 toTransform3(py::handle pose, const std::string& path) {
  if (pose.is_none()) return Transform3{};
  const std::string expected = "must be a pose (x, y, z) or (x, y, z, qx, qy, qz, qw)";
  std::vector<double> v = toNumberList(pose, path, expected);
  if (v.size() == 3) v.insert(v.end(), {0.0, 0.0, 0.0, 1.0});
  if (v.size() != 7) raiseValue(path + ": " + expected);
  if (std::string bad = checkPose3(v.data(), path); !bad.empty()) raiseValue(bad);
  return poseFromNumbers(v.data());
}

Vec3 toPosition3(py::handle value, const std::string& path) {
  std::vector<double> v = toNumberList(value, path, "must be a vector (x, y, z)");
  if (v.size() != 3) raiseValue(path + ": must be a vector (x, y, z)");
  for (int i = 0; i < 3; ++i) {
    if (std::string bad = checkCoordinate(v[i], path + "[" + std::to_string(i) + "]"); !bad.empty())
      raiseValue(bad);
  }
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

void registerD3(py::module_& root) {
  py::module_ m = root.def_submodule(
      "d3",
      "Quack in 3D: shapes (quack.d3.sphere, capsule, box, hull, triangle, shape), the pair "
      "queries of `quack query` on 3D lines (overlap, distance, penetration, manifold, "
      "raycast, shapecast, toi) and batch queries over numpy arrays (overlap_many, "
      "distance_many, penetration_many, raycast_many), static triangle meshes "
      "(quack.d3.mesh) as shape a of every pair query and raycast_many, or as shape b of "
      "overlap, distance, penetration and toi, and the 3D world (quack.d3.World: bodies and "
      "shapes that fall, collide and rest). Poses are (x, y, z) or (x, y, z, qx, "
      "qy, qz, qw), the quaternion scalar last and normalised (a zero one is refused); batch "
      "poses are arrays (N, 7). Constants: EPA_STATUSES (the status codes of "
      "penetration_many; distance_many's are quack.GJK_STATUSES), BODY_STATE_COLUMNS (the "
      "columns of World.body_state). docs/python.md, \"3D\".");
  // `import quack.d3` finds the submodule.
  py::module_::import("sys").attr("modules")["quack.d3"] = m;
  py::exec(kAnswerClasses, m.attr("__dict__"));

  py::list epa;
  for (int i = 0; i <= static_cast<int>(Epa3Status::degenerate); ++i)
    epa.append(toString(static_cast<Epa3Status>(i)));
  m.attr("EPA_STATUSES") = py::tuple(epa);

  py::class_<PyShape3>(m, "Shape",
                       "A 3D shape in its own frame (shape frame), as the JSON format has it: "
                       "made by quack.d3.sphere, capsule, box, hull, triangle or shape.")
      .def_property_readonly(
          "type", [](const PyShape3& s) { return s.json.at("type").get<std::string>(); },
          "The JSON type: sphere, capsule, box, hull or triangle.")
      .def_property_readonly(
          "vertex_count",
          [](const PyShape3& s) {
            const Hull3* h = std::get_if<Hull3>(&s.geometry);
            return h != nullptr ? h->vertexCount : makeProxy(s.geometry).count();
          },
          "Points of the shape's core: a hull's vertices after quickhull (a box 8), 3 for a "
          "triangle, 2 for a capsule, 1 for a sphere.")
      .def(
          "to_dict", [](const PyShape3& s) { return toPython(s.json); },
          "The shape as the JSON format's dict (quack.d3.shape(d) makes it again).")
      .def(
          "volume",
          [](const PyShape3& s) {
            return static_cast<double>(computeMass(s.geometry, 1.0f).volume);
          },
          "Volume in m^3 (0 for a triangle).")
      .def("__repr__", [](const PyShape3& s) {
        return "quack.d3.shape(" + s.json.dump(-1, ' ', false, json::error_handler_t::replace) +
               ")";
      });

  m.def(
      "shape", [](py::handle d) { return makeShape3(toJson(d, "shape"), "shape"); }, py::arg("d"),
      "A 3D shape from the JSON format's dict, e.g. {\"type\": \"sphere\", \"radius\": 0.5}.");
  m.def(
      "sphere",
      [](py::handle radius, py::handle center) {
        return makeShape3(shapeJson("sphere", {{"center", center}, {"radius", radius}}), "sphere");
      },
      py::arg("radius"), py::arg("center") = py::none(),
      "Solid ball: radius > 0, center (x, y, z) (default (0, 0, 0)).");
  m.def(
      "capsule",
      [](py::handle p1, py::handle p2, py::handle radius) {
        return makeShape3(shapeJson("capsule", {{"p1", p1}, {"p2", p2}, {"radius", radius}}),
                          "capsule");
      },
      py::arg("p1"), py::arg("p2"), py::arg("radius"),
      "Capsule: the points within radius > 0 of the segment p1-p2 (each (x, y, z)).");
  m.def(
      "box",
      [](py::handle half, py::handle center, py::handle quat, py::handle radius) {
        return makeShape3(
            shapeJson("box",
                      {{"half", half}, {"center", center}, {"quat", quat}, {"radius", radius}}),
            "box");
      },
      py::arg("half"), py::arg("center") = py::none(), py::arg("quat") = py::none(),
      py::arg("radius") = py::none(),
      "Box with half-extents half (hx, hy, hz) > 0, centred at center (default (0, 0, 0)), "
      "turned by quat (qx, qy, qz, qw) (default the identity), rounded by radius >= 0 "
      "(default 0: the points within it of the box); a hull of 8 vertices.");
  m.def(
      "hull",
      [](py::handle points, py::handle radius) {
        return makeShape3(shapeJson("hull", {{"points", points}, {"radius", radius}}), "hull");
      },
      py::arg("points"), py::arg("radius") = py::none(),
      "Convex hull (quickhull) of 4 to 4,096 points [(x, y, z), ...] or an array (N, 3); at "
      "most 64 vertices; rounded by radius >= 0 (default 0: the points within it of the "
      "hull).");
  m.def(
      "triangle",
      [](py::handle points) {
        return makeShape3(shapeJson("triangle", {{"points", points}}), "triangle");
      },
      py::arg("points"),
      "Triangle of three points [(x, y, z)] x 3 (no volume; its normal by the right-hand "
      "rule).");

  py::class_<PyMesh3>(m, "Mesh",
                      "A static triangle mesh in its own frame (mesh frame), one-sided (fronts "
                      "counter-clockwise), with its tree and edge adjacency: made by "
                      "quack.d3.mesh.")
      .def_property_readonly(
          "vertex_count", [](const PyMesh3& s) { return s.mesh.vertices().size(); },
          "Number of vertices.")
      .def_property_readonly(
          "triangle_count", [](const PyMesh3& s) { return s.mesh.triangleCount(); },
          "Number of triangles.")
      .def_property_readonly(
          "vertices",
          [](const PyMesh3& s) {
            const auto v = s.mesh.vertices();
            auto out = triples(v.size());
            for (std::size_t i = 0; i < v.size(); ++i)
              put(out.mutable_data(), i, v[i]);
            return out;
          },
          "The vertices, an array (N, 3) (float32 values as float64), mesh frame.")
      .def_property_readonly(
          "triangles",
          [](const PyMesh3& s) {
            const auto t = s.mesh.triangles();
            py::array_t<std::int32_t> out({static_cast<py::ssize_t>(t.size()), py::ssize_t{3}});
            for (std::size_t i = 0; i < t.size(); ++i)
              for (std::size_t k = 0; k < 3; ++k)
                out.mutable_data()[3 * i + k] = t[i].v[k];
            return out;
          },
          "The triangles, an int32 array (M, 3) of vertex indices.")
      .def_property_readonly(
          "normals",
          [](const PyMesh3& s) {
            const auto t = s.mesh.triangles();
            auto out = triples(t.size());
            for (std::size_t i = 0; i < t.size(); ++i)
              put(out.mutable_data(), i, t[i].normal);
            return out;
          },
          "Each triangle's unit front normal, an array (M, 3), mesh frame.")
      .def("__repr__", [](const PyMesh3& s) {
        return "quack.d3.Mesh(" + std::to_string(s.mesh.vertices().size()) + " vertices, " +
               std::to_string(s.mesh.triangleCount()) + " triangles)";
      });
  m.def("mesh", &makePyMesh3, py::arg("vertices"), py::arg("triangles"),
        "A static triangle mesh from vertices, an array (N, 3) of x, y, z (mesh frame), and "
        "triangles, an integer array (M, 3) of vertex indices counter-clockwise seen from the "
        "front. Refused, naming the field: a vertex not finite or beyond the coordinate "
        "limit, an index out of range, no triangles, a triangle without area or with a "
        "repeated index, an edge of three triangles, neighbours whose fronts disagree.");

  m.def(
      "overlap",
      [m](py::handle a, py::handle pa, py::handle b, py::handle pb) {
        if (isMesh(a) || isMesh(b)) return answerMesh(m, "overlap", a, pa, b, pb, py::none());
        const PyShape3& sa = toShape3(a, "a");
        const PyShape3& sb = toShape3(b, "b");
        const bool overlap = testOverlap(makeProxy(sa.geometry), toTransform3(pa, "pa"),
                                         makeProxy(sb.geometry), toTransform3(pb, "pb"));
        return answer(m, "OverlapResult", json{{"overlap", overlap}});
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"),
      "Whether 3D shape a at pose pa and b at pb share a point.");
  m.def(
      "distance",
      [m](py::handle a, py::handle pa, py::handle b, py::handle pb) {
        if (isMesh(a) || isMesh(b)) return answerMesh(m, "distance", a, pa, b, pb, py::none());
        const PyShape3& sa = toShape3(a, "a");
        const PyShape3& sb = toShape3(b, "b");
        return answer(
            m, "DistanceResult",
            quack::toJson(computeDistance(makeProxy(sa.geometry), toTransform3(pa, "pa"),
                                          makeProxy(sb.geometry), toTransform3(pb, "pb"))));
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"),
      "Distance and closest points (GJK); distance 0 when they overlap.");
  m.def(
      "penetration",
      [m](py::handle a, py::handle pa, py::handle b, py::handle pb) {
        if (isMesh(a) || isMesh(b)) return answerMesh(m, "penetration", a, pa, b, pb, py::none());
        const PyShape3& sa = toShape3(a, "a");
        const PyShape3& sb = toShape3(b, "b");
        return answer(
            m, "PenetrationResult",
            quack::toJson(computePenetration(makeProxy(sa.geometry), toTransform3(pa, "pa"),
                                             makeProxy(sb.geometry), toTransform3(pb, "pb"))));
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"),
      "Penetration depth, normal and deepest points (GJK, then EPA); depth 0 when apart.");
  m.def(
      "manifold",
      [m](py::handle a, py::handle pa, py::handle b, py::handle pb, py::handle speculative) {
        if (isMesh(a) || isMesh(b)) return answerMesh(m, "manifold", a, pa, b, pb, speculative);
        const PyShape3& sa = toShape3(a, "a");
        const PyShape3& sb = toShape3(b, "b");
        const Transform3 ta = toTransform3(pa, "pa");
        const Transform3 tb = toTransform3(pb, "pb");
        const float s =
            speculative.is_none() ? kSpeculativeDistance : toLength(speculative, "speculative");
        return answer(m, "ManifoldResult",
                      quack::toJson(collide(sa.geometry, ta, sb.geometry, tb, s)));
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"), py::arg("speculative") = py::none(),
      "Contact manifold: up to four points up to speculative metres apart (default 0.02), "
      "with feature ids.");
  m.def(
      "raycast",
      [m](py::handle a, py::handle pa, py::handle origin, py::handle translation) {
        if (isMesh(a)) {
          const Transform3 worldFromMesh = toTransform3(pa, "pa");
          const Vec3 o = toPosition3(origin, "origin");
          const Vec3 t = toPosition3(translation, "translation");
          return answer(m, "MeshRayCastResult",
                        quack::toJson(rayCastMesh(a.cast<const PyMesh3&>().mesh, worldFromMesh,
                                                  {o, t, 1.0f})));
        }
        const PyShape3& sa = toShape3(a, "a");
        const Transform3 worldFromA = toTransform3(pa, "pa");
        const Vec3 o = toPosition3(origin, "origin");
        const Vec3 t = toPosition3(translation, "translation");
        RayHit3 hit = rayCast(sa.geometry, {invTransformPoint(worldFromA, o),
                                            invTransformVector(worldFromA, t), 1.0f});
        if (hit.hit) {
          hit.point = transformPoint(worldFromA, hit.point);
          hit.normal = transformVector(worldFromA, hit.normal);
        }
        return answer(m, "RayCastResult", quack::toJson(hit));
      },
      py::arg("a"), py::arg("pa"), py::arg("origin"), py::arg("translation"),
      "The ray origin + t translation, t in [0, 1] (world frame), against shape a at pa: the "
      "first point where it enters (none from inside).");
  m.def(
      "shapecast",
      [m](py::handle a, py::handle pa, py::handle b, py::handle pb, py::handle translation) {
        if (isMesh(a) || isMesh(b)) return answerMesh(m, "shapecast", a, pa, b, pb, translation);
        const PyShape3& sa = toShape3(a, "a");
        const PyShape3& sb = toShape3(b, "b");
        const Transform3 ta = toTransform3(pa, "pa");
        const Transform3 tb = toTransform3(pb, "pb");
        const Vec3 t = toPosition3(translation, "translation");
        return answer(
            m, "ShapeCastResult",
            quack::toJson(castShape(makeProxy(sa.geometry), ta, makeProxy(sb.geometry), tb, t)));
      },
      py::arg("a"), py::arg("pa"), py::arg("b"), py::arg("pb"), py::arg("translation"),
      "Moves b by translation (x, y, z) (world frame) and reports where it first touches a.");
  m.def(
      "toi",
      [m](py::handle a, py::handle sweepA, py::handle b, py::handle sweepB, py::handle target) {
        if (isMesh(a) || isMesh(b)) return answerMesh(m, "toi", a, sweepA, b, sweepB, target);
        const PyShape3& sa = toShape3(a, "a");
        const PyShape3& sb = toShape3(b, "b");
        const ShapeProxy3 proxyA = makeProxy(sa.geometry);
        const ShapeProxy3 proxyB = makeProxy(sb.geometry);
        const Sweep3 wa = toSweep3(sweepA, proxyA, "sweepA");
        const Sweep3 wb = toSweep3(sweepB, proxyB, "sweepB");
        const float tgt = target.is_none() ? kToiTargetSeparation : toLength(target, "target");
        return answer(m, "ToiResult", quack::toJson(computeToi(proxyA, wa, proxyB, wb, 1.0f, tgt)));
      },
      py::arg("a"), py::arg("sweepA"), py::arg("b"), py::arg("sweepB"),
      py::arg("target") = py::none(),
      "Time of impact: the first fraction t in [0, 1] at which a moving by sweepA and b by "
      "sweepB (each (pose_from, pose_to), turning the short way round) come within target "
      "metres (default 0.005).");

  m.def(
      "overlap_many",
      [root](py::handle shapesA, py::handle posesA, py::handle shapesB, py::handle posesB) {
        PairInputs3 in = toPairInputs3(shapesA, posesA, shapesB, posesB);
        auto overlap = column<bool>(in.n);
        bool* o = overlap.mutable_data();
        {
          py::gil_scoped_release release;
          for (std::size_t i = 0; i < in.n; ++i)
            o[i] = testOverlap(in.proxyA(i), in.poseA(i), in.proxyB(i), in.poseB(i));
        }
        return makeResult(root, "overlap", py::dict(py::arg("overlap") = overlap));
      },
      py::arg("shapes_a"), py::arg("poses_a"), py::arg("shapes_b"), py::arg("poses_b"),
      "quack.d3.overlap over N pairs: shapes_a a quack.d3.Shape or a list of N; poses_a an "
      "array (N, 7) of x, y, z, qx, qy, qz, qw or one pose (7,); the same for b. Returns a "
      "quack.BatchResult with overlap (N,) bool.");
  m.def(
      "distance_many",
      [root](py::handle shapesA, py::handle posesA, py::handle shapesB, py::handle posesB) {
        PairInputs3 in = toPairInputs3(shapesA, posesA, shapesB, posesB);
        auto distance = column<double>(in.n);
        auto pointA = triples(in.n), pointB = triples(in.n), normal = triples(in.n);
        auto iterations = column<std::int32_t>(in.n);
        auto status = column<std::uint8_t>(in.n);
        double* dist = distance.mutable_data();
        double* pa = pointA.mutable_data();
        double* pb = pointB.mutable_data();
        double* nrm = normal.mutable_data();
        std::int32_t* it = iterations.mutable_data();
        std::uint8_t* st = status.mutable_data();
        {
          py::gil_scoped_release release;
          for (std::size_t i = 0; i < in.n; ++i) {
            const DistanceOutput3 d =
                computeDistance(in.proxyA(i), in.poseA(i), in.proxyB(i), in.poseB(i));
            dist[i] = static_cast<double>(d.distance);
            put(pa, i, d.pointA);
            put(pb, i, d.pointB);
            put(nrm, i, d.normal);
            it[i] = d.iterations;
            st[i] = static_cast<std::uint8_t>(d.status);
          }
        }
        return makeResult(root, "distance",
                          py::dict(py::arg("distance") = distance, py::arg("pointA") = pointA,
                                   py::arg("pointB") = pointB, py::arg("normal") = normal,
                                   py::arg("iterations") = iterations, py::arg("status") = status,
                                   py::arg("point_a") = pointA, py::arg("point_b") = pointB));
      },
      py::arg("shapes_a"), py::arg("poses_a"), py::arg("shapes_b"), py::arg("poses_b"),
      "quack.d3.distance over N pairs (arguments as overlap_many). Returns a "
      "quack.BatchResult with distance (N,), pointA, pointB, normal (N, 3) (aliases point_a, "
      "point_b), iterations (N,) and status (N,) codes into quack.GJK_STATUSES.");
  m.def(
      "penetration_many",
      [root](py::handle shapesA, py::handle posesA, py::handle shapesB, py::handle posesB) {
        PairInputs3 in = toPairInputs3(shapesA, posesA, shapesB, posesB);
        auto overlap = column<bool>(in.n);
        auto depth = column<double>(in.n);
        auto normal = triples(in.n), pointA = triples(in.n), pointB = triples(in.n);
        auto iterations = column<std::int32_t>(in.n);
        auto status = column<std::uint8_t>(in.n);
        bool* ov = overlap.mutable_data();
        double* dp = depth.mutable_data();
        double* nrm = normal.mutable_data();
        double* pa = pointA.mutable_data();
        double* pb = pointB.mutable_data();
        std::int32_t* it = iterations.mutable_data();
        std::uint8_t* st = status.mutable_data();
        {
          py::gil_scoped_release release;
          for (std::size_t i = 0; i < in.n; ++i) {
            const PenetrationOutput3 p =
                computePenetration(in.proxyA(i), in.poseA(i), in.proxyB(i), in.poseB(i));
            ov[i] = p.overlap;
            dp[i] = static_cast<double>(p.depth);
            put(nrm, i, p.normal);
            put(pa, i, p.pointA);
            put(pb, i, p.pointB);
            it[i] = p.iterations;
            st[i] = static_cast<std::uint8_t>(p.status);
          }
        }
        return makeResult(root, "penetration",
                          py::dict(py::arg("overlap") = overlap, py::arg("depth") = depth,
                                   py::arg("normal") = normal, py::arg("pointA") = pointA,
                                   py::arg("pointB") = pointB, py::arg("iterations") = iterations,
                                   py::arg("status") = status, py::arg("point_a") = pointA,
                                   py::arg("point_b") = pointB));
      },
      py::arg("shapes_a"), py::arg("poses_a"), py::arg("shapes_b"), py::arg("poses_b"),
      "quack.d3.penetration over N pairs (arguments as overlap_many). Returns a "
      "quack.BatchResult with overlap (N,), depth (N,), normal, pointA, pointB (N, 3), "
      "iterations (N,) and status (N,) codes into quack.d3.EPA_STATUSES.");
  m.def(
      "raycast_many",
      [root](py::handle shapes, py::handle poses, py::handle rays) {
        if (isMesh(shapes)) return rayCastMeshMany(root, shapes, poses, rays);
        ShapeSide3 a = toShapeSide3(shapes, "shapes");
        Rows3 pa = toRows3(poses, 7, "poses", kPoseColumns);
        Rows3 r = toRows3(rays, 6, "rays", "origin x, y, z, translation x, y, z");
        const std::size_t n =
            pairCount({{"shapes", rowsOf(a)}, {"poses", rowsOf(pa)}, {"rays", rowsOf(r)}});
        checkPoseRows(pa, "poses", n);
        checkRayRows(r, n);
        auto hit = column<bool>(n);
        auto fraction = column<double>(n);
        auto point = triples(n), normal = triples(n);
        bool* h = hit.mutable_data();
        double* f = fraction.mutable_data();
        double* pt = point.mutable_data();
        double* nrm = normal.mutable_data();
        {
          py::gil_scoped_release release;
          for (std::size_t i = 0; i < n; ++i) {
            const double* ray = r.at(i);
            const Transform3 worldFromA = poseFromNumbers(pa.at(i));
            const Vec3 o = rayOrigin(ray), t = rayTranslation(ray);
            RayHit3 rh = rayCast(*a.shapes[a.at(i)], {invTransformPoint(worldFromA, o),
                                                      invTransformVector(worldFromA, t), 1.0f});
            if (rh.hit) {
              rh.point = transformPoint(worldFromA, rh.point);
              rh.normal = transformVector(worldFromA, rh.normal);
            }
            h[i] = rh.hit;
            f[i] = static_cast<double>(rh.fraction);
            put(pt, i, rh.point);
            put(nrm, i, rh.normal);
          }
        }
        return makeResult(root, "raycast",
                          py::dict(py::arg("hit") = hit, py::arg("fraction") = fraction,
                                   py::arg("point") = point, py::arg("normal") = normal));
      },
      py::arg("shapes"), py::arg("poses"), py::arg("rays"),
      "quack.d3.raycast over N rays: shapes a quack.d3.Shape or a list of N; poses (N, 7) or "
      "(7,); rays (N, 6) or (6,), each row origin x, y, z and translation x, y, z (world "
      "frame). Returns a quack.BatchResult with hit (N,), fraction (N,), point and normal "
      "(N, 3). With a quack.d3.Mesh as shapes (one mesh for every ray), rayCastMesh per "
      "row and a triangle column (N,) int32 (-1 on a miss).");

  registerWorld3(m);
}

}  // namespace quack::python
