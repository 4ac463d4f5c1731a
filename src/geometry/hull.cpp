#include "quack/geometry/hull.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "format.hpp"

namespace quack {
namespace {

// Distance from p to the segment a-b (to a when a and b coincide).
float distanceToSegment(Vec2 p, Vec2 a, Vec2 b) {
  Vec2 ab = b - a;
  float len2 = lengthSquared(ab);
  if (len2 == 0.0f) return distance(p, a);
  float t = clampf(dot(p - a, ab) / len2, 0.0f, 1.0f);
  return distance(p, a + t * ab);
}

bool lexLess(Vec2 a, Vec2 b) {
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

}  // namespace

float hullTolerance(Vec2 lower, Vec2 upper) noexcept {
  float size = maxf(upper.x - lower.x, upper.y - lower.y);
  float magnitude = maxf(maxf(absf(lower.x), absf(upper.x)), maxf(absf(lower.y), absf(upper.y)));
  // Below a few ulps of the coordinates themselves no geometry is meaningful.
  float resolution = 4.0f * std::numeric_limits<float>::epsilon() * magnitude;
  return maxf(kHullRelativeTolerance * size, resolution);
}

Result<Hull> computeHull(std::span<const Vec2> points) {
  if (points.size() < 3) {
    return fail("a hull needs at least three points, got " + std::to_string(points.size()));
  }
  Vec2 lower = points[0];
  Vec2 upper = points[0];
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!isFinite(points[i])) {
      return fail("points[" + std::to_string(i) + "] is not finite " +
                  detail::formatVec(points[i]));
    }
    lower = minv(lower, points[i]);
    upper = maxv(upper, points[i]);
  }
  float tol = hullTolerance(lower, upper);
  float extent = maxf(upper.x - lower.x, upper.y - lower.y);
  if (extent > 0.0f && extent < kMinShapeSize) {
    return fail("the points span " + detail::formatNumber(extent) +
                " m, less than the smallest size Quack resolves (" +
                detail::formatNumber(kMinShapeSize) + " m)");
  }

  std::vector<Vec2> sorted(points.begin(), points.end());
  std::sort(sorted.begin(), sorted.end(), lexLess);
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());

  // Monotone chain: lower hull left to right, then upper hull right to left. Popping on
  // cross <= 0 keeps only strict left turns, so exact duplicates and exact collinear runs
  // never enter the chain.
  std::vector<Vec2> chain(2 * sorted.size() + 1);
  std::size_t k = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    while (k >= 2 && cross(chain[k - 1] - chain[k - 2], sorted[i] - chain[k - 2]) <= 0.0f)
      --k;
    chain[k++] = sorted[i];
  }
  for (std::size_t i = sorted.size() - 1, lowerSize = k + 1; i-- > 0;) {
    while (k >= lowerSize && cross(chain[k - 1] - chain[k - 2], sorted[i] - chain[k - 2]) <= 0.0f) {
      --k;
    }
    chain[k++] = sorted[i];
  }
  chain.resize(k > 0 ? k - 1 : 0);  // the last point repeats the first

  // Clean-up: drop any vertex within `tol` of the segment joining its neighbours. This welds
  // near-duplicates (the segment passes through the twin) and removes near-collinear
  // vertices, whose edges would have meaningless normals. Repeat until nothing changes,
  // since one removal can expose another.
  bool removed = true;
  while (removed && chain.size() >= 3) {
    removed = false;
    for (std::size_t i = 0; i < chain.size() && chain.size() >= 3; ++i) {
      std::size_t prev = (i + chain.size() - 1) % chain.size();
      std::size_t next = (i + 1) % chain.size();
      if (distanceToSegment(chain[i], chain[prev], chain[next]) < tol) {
        chain.erase(chain.begin() + static_cast<std::ptrdiff_t>(i));
        removed = true;
        --i;
      }
    }
  }
  if (chain.size() < 3) {
    return fail(
        "the points are collinear or coincide (fewer than three distinct, "
        "non-collinear points within tolerance " +
        detail::formatNumber(tol) + ")");
  }
  if (chain.size() > static_cast<std::size_t>(kMaxPolygonVertices)) {
    return fail("the hull has " + std::to_string(chain.size()) + " vertices, more than the " +
                std::to_string(kMaxPolygonVertices) + " a polygon may have");
  }
  // Start at the lexicographically smallest vertex so that hulling a hull is the identity.
  auto first = std::min_element(chain.begin(), chain.end(), lexLess);
  std::rotate(chain.begin(), first, chain.end());

  Hull hull;
  hull.count = static_cast<int>(chain.size());
  std::copy(chain.begin(), chain.end(), hull.points);
  return hull;
}

Status validateHull(const Hull& hull) {
  if (hull.count < 3 || hull.count > kMaxPolygonVertices) {
    return fail("hull count " + std::to_string(hull.count) + " is outside [3, " +
                std::to_string(kMaxPolygonVertices) + "]");
  }
  Vec2 lower = hull.points[0];
  Vec2 upper = hull.points[0];
  for (int i = 0; i < hull.count; ++i) {
    if (!isFinite(hull.points[i])) {
      return fail("hull point " + std::to_string(i) + " is not finite");
    }
    lower = minv(lower, hull.points[i]);
    upper = maxv(upper, hull.points[i]);
  }
  // Half the construction tolerance: a valid hull keeps every vertex at least `tol` from its
  // neighbours' segment, so this leaves room for rounding when re-checking.
  float tol = 0.5f * hullTolerance(lower, upper);
  for (int i = 0; i < hull.count; ++i) {
    Vec2 a = hull.points[i];
    Vec2 b = hull.points[(i + 1) % hull.count];
    Vec2 edge = b - a;
    float len = length(edge);
    if (len < tol) return fail("hull points " + std::to_string(i) + " and the next coincide");
    Vec2 n = rightPerp(edge) * (1.0f / len);
    // Every other vertex must lie strictly on the inner side of every edge.
    for (int j = 0; j < hull.count; ++j) {
      if (j == i || j == (i + 1) % hull.count) continue;
      float s = dot(n, hull.points[j] - a);
      if (s > -tol) {
        return fail("hull is not strictly convex and counter-clockwise: point " +
                    std::to_string(j) + " is not inside edge " + std::to_string(i));
      }
    }
  }
  return {};
}

}  // namespace quack
