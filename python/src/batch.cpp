// Batch queries over numpy arrays: one C++ loop over N pairs with the GIL released, the
// same pair functions as the single queries (quack/collision/pieces.hpp), results as numpy arrays.

#include <cstring>
#include <optional>

#include "bindings.hpp"
#include "quack/collision/pieces.hpp"

namespace quack::python {

namespace {

using Poses = py::array_t<double, py::array::c_style | py::array::forcecast>;

// One side's shapes: one shape for every row, or a list of N shapes (kept alive by `keep`
// while the GIL is released).
struct ShapeSide {
  std::vector<py::object> keep;
  std::vector<Pieces> pieces;
  // Each row's proxy, formed once before the loop, when every row is one convex piece
  // (`convex`): the pair query then runs on the proxies, the work the piece functions
  // would do for a single piece but for forming the two proxies again for every pair.
  std::vector<ShapeProxy> proxies;
  bool convex = true;
  bool single = true;
  std::size_t rows() const { return pieces.size(); }
  Pieces at(std::size_t i) const { return single ? pieces[0] : pieces[i]; }
  const ShapeProxy& proxyAt(std::size_t i) const { return single ? proxies[0] : proxies[i]; }

  void add(py::handle item, Pieces p) {
    keep.push_back(py::reinterpret_borrow<py::object>(item));
    pieces.push_back(p);
    convex = convex && p.size() == 1;
    if (convex) proxies.push_back(makeProxy(p[0]));
  }
};

ShapeSide toShapeSide(py::handle value, const std::string& name) {
  ShapeSide side;
  if (py::isinstance<PyShape>(value)) {
    side.add(value, value.cast<const PyShape&>().pieces);
    return side;
  }
  if (py::isinstance<py::str>(value) || !py::isinstance<py::sequence>(value)) {
    raiseValue(name + ": must be a quack.Shape or a list of N quack.Shape, not " +
               std::string(py::str(value.get_type().attr("__name__"))));
  }
  side.single = false;
  std::size_t i = 0;
  for (py::handle item : value) {
    side.add(item, toShape(item, name + "[" + std::to_string(i) + "]").pieces);
    ++i;
  }
  if (i == 0) raiseValue(name + ": the list of shapes is empty");
  return side;
}

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    if (i > 0) s += ", ";
    s += std::to_string(a.shape(i));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// Rows of `width` numbers: an array (N, width), or one row (width,) used for every pair.
struct Rows {
  Poses array;
  const double* data = nullptr;
  std::size_t count = 0;
  bool single = false;
  const double* at(std::size_t i, std::size_t width) const {
    return single ? data : data + i * width;
  }
};

Rows toRows(py::handle value, std::size_t width, const std::string& name, const char* what) {
  Rows r;
  const std::string expected = name + ": must be a numpy array of shape (N, " +
                               std::to_string(width) + ") or (" + std::to_string(width) + ",) (" +
                               what + " per row)";
  // Numbers only: a bool, complex (its imaginary part would be dropped) or string array is
  // refused, not converted.
  r.array = toDoubleArray(value, name, expected);
  if (r.array.ndim() == 2 && r.array.shape(1) == static_cast<py::ssize_t>(width)) {
    r.count = static_cast<std::size_t>(r.array.shape(0));
  } else if (r.array.ndim() == 1 && r.array.shape(0) == static_cast<py::ssize_t>(width)) {
    r.count = 1;
    r.single = true;
  } else {
    raiseValue(expected + ", not " + shapeText(r.array));
  }
  r.data = r.array.data();
  return r;
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

std::optional<std::size_t> rowsOf(const ShapeSide& s) {
  return s.single ? std::nullopt : std::optional<std::size_t>(s.rows());
}
std::optional<std::size_t> rowsOf(const Rows& r) {
  return r.single ? std::nullopt : std::optional<std::size_t>(r.count);
}

Transform poseAt(const Rows& poses, std::size_t i) {
  const double* p = poses.at(i, 3);
  return makeTransform({static_cast<float>(p[0]), static_cast<float>(p[1])},
                       static_cast<float>(p[2]));
}

// The first bad pose of either side, as "poses_a[17][2]: must be finite (as a float)".
// Checked before the loop so that no answer is computed from a refused number.
std::string firstBadPose(const Rows& poses, const std::string& name, std::size_t n) {
  const std::size_t rows = poses.single ? 1 : n;
  for (std::size_t i = 0; i < rows; ++i) {
    const double* p = poses.at(i, 3);
    // The message (and its path string) only for a bad row: this runs for every pair.
    if (poseIsFine(p[0], p[1], p[2])) continue;
    return checkPose(p[0], p[1], p[2], poses.single ? name : name + "[" + std::to_string(i) + "]");
  }
  return "";
}

template <class T>
py::array_t<T> column(std::size_t n) {
  return py::array_t<T>(static_cast<py::ssize_t>(n));
}

py::array_t<double> pairs(std::size_t n) {
  return py::array_t<double>({static_cast<py::ssize_t>(n), py::ssize_t{2}});
}

void put(double* out, std::size_t i, Vec2 v) {
  out[2 * i] = static_cast<double>(v.x);
  out[2 * i + 1] = static_cast<double>(v.y);
}

py::object makeResult(py::module_& m, const char* kind, py::dict fields) {
  py::object r = m.attr("BatchResult")();
  r.attr("kind") = kind;
  for (auto item : fields)
    r.attr(item.first) = item.second;
  r.attr("_fields") = py::tuple(fields.attr("keys")());
  return r;
}

// The inputs of a two-shape batch query, checked.
struct PairInputs {
  ShapeSide a, b;
  Rows pa, pb;
  std::size_t n = 0;
  bool convex() const { return a.convex && b.convex; }
};

PairInputs toPairInputs(py::handle shapesA, py::handle posesA, py::handle shapesB,
                        py::handle posesB) {
  PairInputs in;
  in.a = toShapeSide(shapesA, "shapes_a");
  in.pa = toRows(posesA, 3, "poses_a", "x, y, angle");
  in.b = toShapeSide(shapesB, "shapes_b");
  in.pb = toRows(posesB, 3, "poses_b", "x, y, angle");
  in.n = pairCount({{"shapes_a", rowsOf(in.a)},
                    {"poses_a", rowsOf(in.pa)},
                    {"shapes_b", rowsOf(in.b)},
                    {"poses_b", rowsOf(in.pb)}});
  std::string bad = firstBadPose(in.pa, "poses_a", in.n);
  if (bad.empty()) bad = firstBadPose(in.pb, "poses_b", in.n);
  if (!bad.empty()) raiseValue(bad);
  return in;
}

}  // namespace

void registerBatch(py::module_& m) {
  py::exec(R"py(
class BatchResult:
    """Answers of a batch query: numpy arrays with a leading axis of N pairs, named as the
    single query's result fields (points as (N, 2); statuses as small integer codes into
    quack.GJK_STATUSES or quack.EPA_STATUSES)."""
    def to_dict(self):
        """The fields as a dict of numpy arrays."""
        return {k: getattr(self, k) for k in self._fields}
    def __repr__(self):
        n = len(getattr(self, self._fields[0]))
        return "BatchResult(%s, N=%d: %s)" % (self.kind, n, ", ".join(self._fields))
)py",
           m.attr("__dict__"));
  m.attr("BatchResult").attr("__module__") = "quack";

  py::list gjk, epa;
  for (int i = 0; i <= static_cast<int>(GjkStatus::maxIterations); ++i)
    gjk.append(toString(static_cast<GjkStatus>(i)));
  for (int i = 0; i <= static_cast<int>(EpaStatus::degenerate); ++i)
    epa.append(toString(static_cast<EpaStatus>(i)));
  m.attr("GJK_STATUSES") = py::tuple(gjk);
  m.attr("EPA_STATUSES") = py::tuple(epa);

  m.def(
      "overlap_many",
      [m](py::handle shapesA, py::handle posesA, py::handle shapesB, py::handle posesB) mutable {
        PairInputs in = toPairInputs(shapesA, posesA, shapesB, posesB);
        py::array_t<bool> overlap = column<bool>(in.n);
        bool* o = overlap.mutable_data();
        {
          py::gil_scoped_release release;
          if (in.convex()) {
            for (std::size_t i = 0; i < in.n; ++i)
              o[i] =
                  testOverlap(in.a.proxyAt(i), poseAt(in.pa, i), in.b.proxyAt(i), poseAt(in.pb, i));
          } else {
            for (std::size_t i = 0; i < in.n; ++i)
              o[i] = overlapPieces(in.a.at(i), poseAt(in.pa, i), in.b.at(i), poseAt(in.pb, i));
          }
        }
        return makeResult(m, "overlap", py::dict(py::arg("overlap") = overlap));
      },
      py::arg("shapes_a"), py::arg("poses_a"), py::arg("shapes_b"), py::arg("poses_b"),
      "quack.overlap over N pairs: shapes_a a Shape or a list of N; poses_a an array (N, 3) "
      "or one pose (3,); the same for b. Returns a BatchResult with overlap (N,) bool.");

  m.def(
      "distance_many",
      [m](py::handle shapesA, py::handle posesA, py::handle shapesB, py::handle posesB) mutable {
        PairInputs in = toPairInputs(shapesA, posesA, shapesB, posesB);
        auto distance = column<double>(in.n);
        auto pointA = pairs(in.n), pointB = pairs(in.n), normal = pairs(in.n);
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
            const DistanceOutput d =
                in.convex()
                    ? computeDistance(in.a.proxyAt(i), poseAt(in.pa, i), in.b.proxyAt(i),
                                      poseAt(in.pb, i))
                    : distancePieces(in.a.at(i), poseAt(in.pa, i), in.b.at(i), poseAt(in.pb, i));
            dist[i] = static_cast<double>(d.distance);
            put(pa, i, d.pointA);
            put(pb, i, d.pointB);
            put(nrm, i, d.normal);
            it[i] = d.iterations;
            st[i] = static_cast<std::uint8_t>(d.status);
          }
        }
        return makeResult(m, "distance",
                          py::dict(py::arg("distance") = distance, py::arg("pointA") = pointA,
                                   py::arg("pointB") = pointB, py::arg("normal") = normal,
                                   py::arg("iterations") = iterations, py::arg("status") = status,
                                   py::arg("point_a") = pointA, py::arg("point_b") = pointB));
      },
      py::arg("shapes_a"), py::arg("poses_a"), py::arg("shapes_b"), py::arg("poses_b"),
      "quack.distance over N pairs (arguments as overlap_many). Returns a BatchResult with "
      "distance (N,), pointA, pointB, normal (N, 2) (aliases point_a, point_b), iterations "
      "(N,) and status (N,) codes into quack.GJK_STATUSES.");

  m.def(
      "penetration_many",
      [m](py::handle shapesA, py::handle posesA, py::handle shapesB, py::handle posesB) mutable {
        PairInputs in = toPairInputs(shapesA, posesA, shapesB, posesB);
        auto overlap = column<bool>(in.n);
        auto depth = column<double>(in.n);
        auto normal = pairs(in.n), pointA = pairs(in.n), pointB = pairs(in.n);
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
            const PenetrationOutput p =
                in.convex()
                    ? computePenetration(in.a.proxyAt(i), poseAt(in.pa, i), in.b.proxyAt(i),
                                         poseAt(in.pb, i))
                    : penetrationPieces(in.a.at(i), poseAt(in.pa, i), in.b.at(i), poseAt(in.pb, i));
            ov[i] = p.overlap;
            dp[i] = static_cast<double>(p.depth);
            put(nrm, i, p.normal);
            put(pa, i, p.pointA);
            put(pb, i, p.pointB);
            it[i] = p.iterations;
            st[i] = static_cast<std::uint8_t>(p.status);
          }
        }
        return makeResult(m, "penetration",
                          py::dict(py::arg("overlap") = overlap, py::arg("depth") = depth,
                                   py::arg("normal") = normal, py::arg("pointA") = pointA,
                                   py::arg("pointB") = pointB, py::arg("iterations") = iterations,
                                   py::arg("status") = status, py::arg("point_a") = pointA,
                                   py::arg("point_b") = pointB));
      },
      py::arg("shapes_a"), py::arg("poses_a"), py::arg("shapes_b"), py::arg("poses_b"),
      "quack.penetration over N pairs (arguments as overlap_many). Returns a BatchResult with "
      "overlap (N,), depth (N,), normal, pointA, pointB (N, 2), iterations (N,) and status "
      "(N,) codes into quack.EPA_STATUSES.");

  m.def(
      "raycast_many",
      [m](py::handle shapes, py::handle poses, py::handle rays) mutable {
        ShapeSide a = toShapeSide(shapes, "shapes");
        Rows pa = toRows(poses, 3, "poses", "x, y, angle");
        Rows r = toRows(rays, 4, "rays", "origin x, y, translation x, y");
        const std::size_t n =
            pairCount({{"shapes", rowsOf(a)}, {"poses", rowsOf(pa)}, {"rays", rowsOf(r)}});
        if (std::string bad = firstBadPose(pa, "poses", n); !bad.empty()) raiseValue(bad);
        for (std::size_t i = 0; i < (r.single ? 1 : n); ++i) {
          const double* ray = r.at(i, 4);
          // Columns 0-1 the origin, 2-3 the translation, each within the coordinate limit;
          // the message (and its path string) only for a bad row.
          if (coordinateIsFine(ray[0]) && coordinateIsFine(ray[1]) && coordinateIsFine(ray[2]) &&
              coordinateIsFine(ray[3]))
            continue;
          const std::string path =
              r.single ? std::string("rays") : "rays[" + std::to_string(i) + "]";
          std::string bad;
          for (std::size_t k = 0; k < 4 && bad.empty(); ++k)
            bad = checkCoordinate(ray[k], path + "[" + std::to_string(k) + "]");
          if (!bad.empty()) raiseValue(bad);
        }
        auto hit = column<bool>(n);
        auto fraction = column<double>(n);
        auto point = pairs(n), normal = pairs(n);
        bool* h = hit.mutable_data();
        double* f = fraction.mutable_data();
        double* pt = point.mutable_data();
        double* nrm = normal.mutable_data();
        {
          py::gil_scoped_release release;
          for (std::size_t i = 0; i < n; ++i) {
            const double* ray = r.at(i, 4);
            const RayHit rh = rayCastPieces(
                a.at(i), poseAt(pa, i), {static_cast<float>(ray[0]), static_cast<float>(ray[1])},
                {static_cast<float>(ray[2]), static_cast<float>(ray[3])});
            h[i] = rh.hit;
            f[i] = static_cast<double>(rh.fraction);
            put(pt, i, rh.point);
            put(nrm, i, rh.normal);
          }
        }
        return makeResult(m, "raycast",
                          py::dict(py::arg("hit") = hit, py::arg("fraction") = fraction,
                                   py::arg("point") = point, py::arg("normal") = normal));
      },
      py::arg("shapes"), py::arg("poses"), py::arg("rays"),
      "quack.raycast over N rays: shapes a Shape or a list of N; poses (N, 3) or (3,); rays "
      "(N, 4) or (4,), each row origin x, y and translation x, y (world frame). Returns a "
      "BatchResult with hit (N,), fraction (N,), point and normal (N, 2).");
}

}  // namespace quack::python
