// A tour of Quack's geometry layer: hull a messy point cloud, build shapes, and print their
// mass properties, bounding boxes and a ray cast, in numbers a person can check by hand.
#include <cstdio>
#include <vector>

#include "quack/geometry/geometry.hpp"

using namespace quack;

namespace {

void printMass(const char* name, const MassProperties& m, const char* closedForm) {
  std::printf("  %-28s area %-10.6g mass %-10.6g centroid (%.6g, %.6g)  inertia %.6g\n", name,
              static_cast<double>(m.area), static_cast<double>(m.mass),
              static_cast<double>(m.centroid.x), static_cast<double>(m.centroid.y),
              static_cast<double>(m.inertia));
  std::printf("  %-28s expected: %s\n", "", closedForm);
}

void printAabb(const char* name, Aabb b) {
  std::printf("  %-28s [%.6g, %.6g] x [%.6g, %.6g]\n", name, static_cast<double>(b.lower.x),
              static_cast<double>(b.upper.x), static_cast<double>(b.lower.y),
              static_cast<double>(b.upper.y));
}

}  // namespace

int main() {
  std::printf("Quack shapes tour\n\n");

  std::printf(
      "1. Convex hull of 9 points: a unit square's corners, a duplicate corner,\n"
      "   a point on an edge, a near-duplicate and two interior points.\n");
  const std::vector<Vec2> cloud = {{0, 0},    {1, 0},     {1, 1},       {0, 1},      {1, 1},
                                   {0.5f, 0}, {1e-7f, 0}, {0.5f, 0.5f}, {0.2f, 0.7f}};
  Result<Hull> hull = computeHull(cloud);
  if (!hull) {
    std::printf("  error: %s\n", hull.error().message.c_str());
    return 1;
  }
  std::printf("  hull (%d vertices, counter-clockwise):", hull->count);
  for (int i = 0; i < hull->count; ++i) {
    std::printf(" (%g, %g)", static_cast<double>(hull->points[i].x),
                static_cast<double>(hull->points[i].y));
  }
  std::printf("\n  expected: (0, 0) (1, 0) (1, 1) (0, 1)\n\n");

  std::printf("2. Mass properties at density 2 kg/m^2 (inertia about the centroid).\n");
  Circle circle = makeCircle({1, 2}, 0.5f).value();
  printMass("circle r=0.5 at (1,2)", computeMass(circle, 2.0f),
            "area pi/4 = 0.785398, mass 1.5708, centroid (1, 2), inertia m r^2/2 = 0.19635");
  Polygon box = makeBox(1.0f, 0.5f).value();
  printMass("box 2 x 1", computeMass(box, 2.0f),
            "area 2, mass 4, centroid (0, 0), inertia m (w^2+h^2)/12 = 1.66667");
  Capsule capsule = makeCapsule({-1, 0}, {1, 0}, 0.5f).value();
  printMass("capsule length 2, r=0.5", computeMass(capsule, 2.0f),
            "area 2 + pi/4 = 2.785398, mass 5.5708, centroid (0, 0), inertia 4.10048");
  const Vec2 tri[] = {{0, 0}, {3, 0}, {0, 3}};
  Polygon triangle = makePolygon(tri).value();
  printMass("right triangle legs 3", computeMass(triangle, 2.0f),
            "area 4.5, mass 9, centroid (1, 1), inertia m (a^2+b^2)/18 = 9");
  Polygon rounded = makeBox(1.0f, 1.0f, {}, 0.0f, 0.25f).value();
  printMass("2x2 box rounded by 0.25", computeMass(rounded, 2.0f),
            "area 4 + 8(0.25) + pi/16 = 6.19635, centroid (0, 0)");
  std::printf("\n");

  std::printf("3. Bounding boxes under a transform (moved to (10, 0), turned 90 degrees).\n");
  Transform xf = makeTransform({10, 0}, 0.5f * kPi);
  printAabb("box 2 x 1", computeAabb(box, xf));
  std::printf("  %-28s expected: [9.5, 10.5] x [-1, 1]\n", "");
  printAabb("capsule", computeAabb(capsule, xf));
  std::printf("  %-28s expected: [9.5, 10.5] x [-1.5, 1.5]\n\n", "");

  std::printf("4. A ray from (-5, 0.25) along +x, 10 m long, against the 2 x 1 box.\n");
  RayHit hit = rayCast(box, {{-5, 0.25f}, {10, 0}, 1.0f});
  std::printf("  hit %s at fraction %.6g, point (%.6g, %.6g), normal (%.6g, %.6g)\n",
              hit.hit ? "yes" : "no", static_cast<double>(hit.fraction),
              static_cast<double>(hit.point.x), static_cast<double>(hit.point.y),
              static_cast<double>(hit.normal.x), static_cast<double>(hit.normal.y));
  std::printf("  expected: hit yes at fraction 0.4, point (-1, 0.25), normal (-1, 0)\n\n");

  std::printf("5. Bad input gets a clear error:\n");
  const Vec2 concave[] = {{0, 0}, {4, 0}, {4, 4}, {2, 1}, {0, 4}};
  std::printf("  makePolygon(concave outline): %s\n", makePolygon(concave).error().message.c_str());
  std::printf("  makeCircle(r = -1):           %s\n",
              makeCircle({}, -1.0f).error().message.c_str());
  const Vec2 line[] = {{0, 0}, {1, 1}, {2, 2}};
  std::printf("  computeHull(collinear):       %s\n", computeHull(line).error().message.c_str());
  return 0;
}
