#include "quack/geometry/mass.hpp"

#include <cmath>

#include "quack/math/trig.hpp"

namespace quack {
namespace {

// Accumulates pieces (mass, centroid, inertia about the piece's own centroid) and combines
// them with the parallel-axis theorem. Positions are taken relative to `origin`, a point
// near the shape, to keep float cancellation small for shapes far from the frame origin.
struct MassSum {
  Vec2 origin;
  float mass = 0.0f;
  Vec2 moment;           // sum of m * c (relative to origin)
  float inertia = 0.0f;  // sum of I_c + m |c|^2 (about origin)

  void add(float m, Vec2 c, float inertiaAtCentroid) {
    Vec2 r = c - origin;
    mass += m;
    moment += m * r;
    inertia += inertiaAtCentroid + m * lengthSquared(r);
  }

  MassProperties finish(float density) const {
    MassProperties out;
    out.mass = density * mass;
    out.area = mass;
    if (mass <= 0.0f) {
      out.centroid = origin;
      return out;
    }
    Vec2 c = (1.0f / mass) * moment;
    out.centroid = origin + c;
    out.inertia = density * (inertia - mass * lengthSquared(c));
    return out;
  }
};

}  // namespace

MassProperties computeMass(const Circle& circle, float density) {
  QUACK_ASSERT(isFinite(density) && density >= 0.0f);
  float r2 = circle.radius * circle.radius;
  float a = kPi * r2;
  return {density * a, a, circle.center, density * a * 0.5f * r2};
}

MassProperties computeMass(const Capsule& capsule, float density) {
  QUACK_ASSERT(isFinite(density) && density >= 0.0f);
  float r = capsule.radius;
  Vec2 axis = capsule.p2 - capsule.p1;
  float len = length(axis);
  Vec2 u = (1.0f / len) * axis;
  MassSum sum;
  sum.origin = 0.5f * (capsule.p1 + capsule.p2);
  // Rectangle len x 2r: I = m (len^2 + (2r)^2) / 12.
  float rectArea = 2.0f * r * len;
  sum.add(rectArea, sum.origin, rectArea * (len * len + 4.0f * r * r) / 12.0f);
  // Half-disks: centroid 4r/(3 pi) beyond each end; polar moment about the flat side's
  // midpoint is m r^2 / 2, moved to the centroid by the parallel-axis theorem.
  float halfArea = 0.5f * kPi * r * r;
  float offset = 4.0f * r / (3.0f * kPi);
  float halfInertia = halfArea * (0.5f * r * r - offset * offset);
  sum.add(halfArea, capsule.p2 + offset * u, halfInertia);
  sum.add(halfArea, capsule.p1 - offset * u, halfInertia);
  return sum.finish(density);
}

MassProperties computeMass(const Segment& segment, float density) {
  QUACK_ASSERT(isFinite(density) && density >= 0.0f);
  (void)density;
  MassProperties out;
  out.centroid = 0.5f * (segment.p1 + segment.p2);
  return out;
}

MassProperties computeMass(const Polygon& polygon, float density) {
  QUACK_ASSERT(isFinite(density) && density >= 0.0f);
  const int n = polygon.count;
  const float r = polygon.radius;
  MassSum sum;
  sum.origin = polygon.centroid;
  // Core polygon as a fan of triangles (origin, v_i, v_{i+1}) about the reference point.
  // Triangle with a vertex at the reference point: centroid (e1 + e2) / 3 and polar
  // moment about that vertex (area / 6) (|e1|^2 + e1.e2 + |e2|^2).
  float coreArea = 0.0f;
  Vec2 coreMoment;
  float coreInertia = 0.0f;
  for (int i = 0; i < n; ++i) {
    Vec2 e1 = polygon.vertices[i] - sum.origin;
    Vec2 e2 = polygon.vertices[(i + 1) % n] - sum.origin;
    float a = 0.5f * cross(e1, e2);
    coreArea += a;
    coreMoment += (a / 3.0f) * (e1 + e2);
    coreInertia += (a / 6.0f) * (dot(e1, e1) + dot(e1, e2) + dot(e2, e2));
  }
  sum.mass += coreArea;
  sum.moment += coreMoment;
  sum.inertia += coreInertia;

  if (r > 0.0f) {
    for (int i = 0; i < n; ++i) {
      Vec2 v1 = polygon.vertices[i];
      Vec2 v2 = polygon.vertices[(i + 1) % n];
      Vec2 normal = polygon.normals[i];
      // Rectangle of length L and width r along the edge.
      float len = distance(v1, v2);
      float rectArea = len * r;
      sum.add(rectArea, 0.5f * (v1 + v2) + (0.5f * r) * normal,
              rectArea * (len * len + r * r) / 12.0f);
      // Sector at v2 between this edge's normal and the next one's (the exterior angle).
      Vec2 next = polygon.normals[(i + 1) % n];
      float theta = portableAtan2(cross(normal, next), dot(normal, next));
      if (theta <= 0.0f) continue;
      float sectorArea = 0.5f * theta * r * r;
      // Centroid of a sector of angle theta: 4 r sin(theta/2) / (3 theta) along the bisector.
      float d = 4.0f * r * portableSin(0.5f * theta) / (3.0f * theta);
      Vec2 bisector = normalize(normal + next);
      float inertiaAtApex = sectorArea * 0.5f * r * r;
      sum.add(sectorArea, v2 + d * bisector, inertiaAtApex - sectorArea * d * d);
    }
  }
  return sum.finish(density);
}

MassProperties computeMass(const ShapeGeometry& geometry, float density) {
  return std::visit([&](const auto& shape) { return computeMass(shape, density); }, geometry);
}

}  // namespace quack
