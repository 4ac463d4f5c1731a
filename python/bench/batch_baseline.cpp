// The C++ side of python/bench/bench_batch.py: the per-query cost of a plain C++ loop over
// the same pairs the Python batch functions get, so that the two can be compared.
//   quack_python_baseline OP SHAPE_A SHAPE_B FILE REPEATS [inloop]
// OP: distance, overlap, penetration or raycast; SHAPE_A, SHAPE_B: JSON shapes (convex);
// FILE: float64 rows, (xa, ya, angle_a, xb, yb, angle_b) per pair, or for raycast (x, y,
// angle, origin x, origin y, translation x, translation y). Prints the best of REPEATS runs
// in ns per query, twice: building each Transform from (x, y, angle) inside the loop (the
// work the batch functions do) and with the Transforms built beforehand.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/geometry/raycast.hpp"
#include "quack/io/shape_json.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace quack;

Transform transformAt(const double* p) {
  return makeTransform({static_cast<float>(p[0]), static_cast<float>(p[1])},
                       static_cast<float>(p[2]));
}

enum class Op { distance, overlap, penetration, raycast };

// One query; its answer folded into a checksum so the loop cannot be optimised away. The op
// is a template argument, chosen once outside the timed loops.
template <Op op>
double query(const ShapeGeometry& a, Transform ta, const ShapeGeometry& b, Transform tb,
             const double* ray) {
  if constexpr (op == Op::distance) {
    return static_cast<double>(computeDistance(a, ta, b, tb).distance);
  } else if constexpr (op == Op::overlap) {
    return testOverlap(a, ta, b, tb) ? 1.0 : 0.0;
  } else if constexpr (op == Op::penetration) {
    return static_cast<double>(computePenetration(a, ta, b, tb).depth);
  } else {
    const RayCastInput in{
        invTransformPoint(ta, {static_cast<float>(ray[0]), static_cast<float>(ray[1])}),
        invRotate(ta.q, {static_cast<float>(ray[2]), static_cast<float>(ray[3])}), 1.0f};
    const RayHit h = rayCast(a, in);
    return h.hit ? static_cast<double>(transformPoint(ta, h.point).x) : 0.0;
  }
}

struct Timing {
  double inLoop = 1e300, prebuilt = 1e300, checksum = 0.0;
};

// The best of `repeats` runs of both loops over the rows (`width` numbers each).
template <Op op>
Timing timeLoops(const ShapeGeometry& a, const ShapeGeometry& b, const std::vector<double>& rows,
                 std::size_t width, int repeats, bool inLoopOnly) {
  const std::size_t n = rows.size() / width;
  std::vector<Transform> ta(n), tb(n);
  for (std::size_t i = 0; i < n; ++i) {
    ta[i] = transformAt(&rows[i * width]);
    if constexpr (op != Op::raycast) tb[i] = transformAt(&rows[i * width + 3]);
  }
  Timing t;
  for (int r = 0; r < repeats; ++r) {
    auto t0 = Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      const double* row = &rows[i * width];
      Transform tb1;
      if constexpr (op != Op::raycast) tb1 = transformAt(row + 3);
      t.checksum += query<op>(a, transformAt(row), b, tb1, row + 3);
    }
    auto t1 = Clock::now();
    for (std::size_t i = 0; i < (inLoopOnly ? 0 : n); ++i)
      t.checksum += query<op>(a, ta[i], b, tb[i], &rows[i * width + 3]);
    auto t2 = Clock::now();
    t.inLoop = std::min(t.inLoop, std::chrono::duration<double, std::nano>(t1 - t0).count());
    t.prebuilt = std::min(t.prebuilt, std::chrono::duration<double, std::nano>(t2 - t1).count());
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  // A seventh argument "inloop" runs only the first loop (for instruction counts).
  if (argc != 6 && !(argc == 7 && std::string(argv[6]) == "inloop")) {
    std::fprintf(stderr, "usage: quack_python_baseline OP SHAPE_A SHAPE_B FILE REPEATS [inloop]\n");
    return 2;
  }
  const std::string op = argv[1];
  if (op != "distance" && op != "overlap" && op != "penetration" && op != "raycast") {
    std::fprintf(stderr, "unknown op %s\n", op.c_str());
    return 2;
  }
  Result<ShapeGeometry> a = parseShape(nlohmann::json::parse(argv[2]), "a");
  Result<ShapeGeometry> b = parseShape(nlohmann::json::parse(argv[3]), "b");
  if (!a || !b) {
    std::fprintf(stderr, "%s\n", (!a ? a.error() : b.error()).message.c_str());
    return 2;
  }
  std::ifstream in(argv[4], std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t width = op == "raycast" ? 7 : 6;
  const std::size_t n = bytes.size() / (width * sizeof(double));
  std::vector<double> rows(n * width);
  std::copy(bytes.begin(),
            bytes.begin() + static_cast<std::ptrdiff_t>(rows.size() * sizeof(double)),
            reinterpret_cast<char*>(rows.data()));
  const int repeats = std::max(1, std::atoi(argv[5]));
  const bool inLoopOnly = argc == 7;

  Timing t;
  if (op == "distance") t = timeLoops<Op::distance>(*a, *b, rows, width, repeats, inLoopOnly);
  if (op == "overlap") t = timeLoops<Op::overlap>(*a, *b, rows, width, repeats, inLoopOnly);
  if (op == "penetration") t = timeLoops<Op::penetration>(*a, *b, rows, width, repeats, inLoopOnly);
  if (op == "raycast") t = timeLoops<Op::raycast>(*a, *b, rows, width, repeats, inLoopOnly);
  std::printf(
      "{\"op\": \"%s\", \"n\": %zu, \"ns_per_query\": %.2f, \"ns_per_query_prebuilt\": %.2f, "
      "\"checksum\": %.6g}\n",
      op.c_str(), n, t.inLoop / static_cast<double>(n), t.prebuilt / static_cast<double>(n),
      t.checksum);
  return 0;
}
