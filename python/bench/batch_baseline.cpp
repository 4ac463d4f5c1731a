// The C++ side of python/bench/bench_batch.py: the per-query cost of a plain C++ loop over
// the same pairs the Python batch functions get, so that the two can be compared.
//   quack_python_baseline OP SHAPE_A SHAPE_B FILE REPEATS
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

// One query; its answer folded into a checksum so the loop cannot be optimised away.
double query(const std::string& op, const ShapeGeometry& a, Transform ta, const ShapeGeometry& b,
             Transform tb, const double* ray) {
  if (op == "distance") return static_cast<double>(computeDistance(a, ta, b, tb).distance);
  if (op == "overlap") return testOverlap(a, ta, b, tb) ? 1.0 : 0.0;
  if (op == "penetration") return static_cast<double>(computePenetration(a, ta, b, tb).depth);
  const RayCastInput in{
      invTransformPoint(ta, {static_cast<float>(ray[0]), static_cast<float>(ray[1])}),
      invRotate(ta.q, {static_cast<float>(ray[2]), static_cast<float>(ray[3])}), 1.0f};
  const RayHit h = rayCast(a, in);
  return h.hit ? static_cast<double>(transformPoint(ta, h.point).x) : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: quack_python_baseline OP SHAPE_A SHAPE_B FILE REPEATS\n");
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

  std::vector<Transform> ta(n), tb(n);
  for (std::size_t i = 0; i < n; ++i) {
    ta[i] = transformAt(&rows[i * width]);
    tb[i] = op == "raycast" ? Transform{} : transformAt(&rows[i * width + 3]);
  }
  double bestInLoop = 1e300, bestPrebuilt = 1e300, sum = 0.0;
  for (int r = 0; r < repeats; ++r) {
    auto t0 = Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      const double* row = &rows[i * width];
      const Transform tb1 = op == "raycast" ? Transform{} : transformAt(row + 3);
      sum += query(op, *a, transformAt(row), *b, tb1, row + 3);
    }
    auto t1 = Clock::now();
    for (std::size_t i = 0; i < n; ++i)
      sum += query(op, *a, ta[i], *b, tb[i], &rows[i * width + 3]);
    auto t2 = Clock::now();
    bestInLoop = std::min(bestInLoop, std::chrono::duration<double, std::nano>(t1 - t0).count());
    bestPrebuilt =
        std::min(bestPrebuilt, std::chrono::duration<double, std::nano>(t2 - t1).count());
  }
  std::printf(
      "{\"op\": \"%s\", \"n\": %zu, \"ns_per_query\": %.2f, \"ns_per_query_prebuilt\": %.2f, "
      "\"checksum\": %.6g}\n",
      op.c_str(), n, bestInLoop / static_cast<double>(n), bestPrebuilt / static_cast<double>(n),
      sum);
  return 0;
}
