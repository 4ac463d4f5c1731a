// Box2D v3's side of the query benchmark (box2d_v3_peer.hpp). The only translation unit
// that includes Box2D v3's headers.

#include "box2d_v3_peer.hpp"

#include <box2d/box2d.h>
#include <box2d/collision.h>
#include <box2d/math_functions.h>

#include <limits>
#include <vector>

namespace quack_bench::v3 {
namespace {

struct Shape {
  b2Polygon polygon;
};

// The proxy is made for every query, from the polygon, as v3's world does
// (b2MakeShapeDistanceProxy) and as Quack's makeProxy is in the same benchmark.
b2ShapeProxy proxyOf(const Shape& shape) {
  return b2MakeProxy(shape.polygon.vertices, shape.polygon.count, shape.polygon.radius);
}

std::vector<Shape>& pool() {
  static std::vector<Shape> shapes;
  return shapes;
}

b2Transform transformOf(const Pose& pose) {
  return {{pose.x, pose.y}, b2MakeRot(pose.angle)};
}

b2DistanceOutput runDistance(const QueryPair& pair) {
  const std::vector<Shape>& shapes = pool();
  b2DistanceInput input;
  input.proxyA = proxyOf(shapes[pair.a]);
  input.proxyB = proxyOf(shapes[pair.b]);
  input.transform = b2InvMulTransforms(transformOf(pair.pa), transformOf(pair.pb));
  input.useRadii = true;
  b2SimplexCache cache = {};
  return b2ShapeDistance(&input, &cache, nullptr, 0);
}

b2LocalManifold runManifold(const QueryPair& pair) {
  const std::vector<Shape>& shapes = pool();
  return b2CollidePolygons(&shapes[pair.a].polygon, &shapes[pair.b].polygon,
                           b2InvMulTransforms(transformOf(pair.pa), transformOf(pair.pb)));
}

b2Sweep sweepOf(const Pose& p1, const Pose& p2) {
  return {{0.0f, 0.0f}, {p1.x, p1.y}, {p2.x, p2.y}, b2MakeRot(p1.angle), b2MakeRot(p2.angle)};
}

b2TOIOutput runToi(const QuerySweep& sweep) {
  const std::vector<Shape>& shapes = pool();
  b2TOIInput input;
  input.proxyA = proxyOf(shapes[sweep.a]);
  input.proxyB = proxyOf(shapes[sweep.b]);
  input.sweepA = sweepOf(sweep.a1, sweep.a2);
  input.sweepB = sweepOf(sweep.b1, sweep.b2);
  input.maxFraction = 1.0f;
  return b2TimeOfImpact(&input);
}

}  // namespace

bool setPool(const PoolPolygon* polygons, std::size_t count) {
  std::vector<Shape> shapes(count);
  for (std::size_t i = 0; i < count; ++i) {
    b2Vec2 points[B2_MAX_POLYGON_VERTICES];
    const int n = polygons[i].count;
    if (n > B2_MAX_POLYGON_VERTICES) return false;
    for (int k = 0; k < n; ++k)
      points[k] = {polygons[i].x[k], polygons[i].y[k]};
    const b2Hull hull = b2ComputeHull(points, n);
    if (hull.count != n) return false;
    shapes[i].polygon = b2MakePolygon(&hull, 0.0f);
  }
  pool() = std::move(shapes);
  return true;
}

void rotation(float radians, float* cosine, float* sine) {
  const b2Rot q = b2MakeRot(radians);
  *cosine = q.c;
  *sine = q.s;
}

float distance(const QueryPair& pair) {
  return runDistance(pair).distance;
}

float manifoldSeparation(const QueryPair& pair, int* pointCount) {
  const b2LocalManifold m = runManifold(pair);
  *pointCount = m.pointCount;
  float deepest = std::numeric_limits<float>::infinity();
  for (int i = 0; i < m.pointCount; ++i)
    deepest = deepest < m.points[i].separation ? deepest : m.points[i].separation;
  return deepest;
}

float timeOfImpact(const QuerySweep& sweep, bool* hit) {
  const b2TOIOutput out = runToi(sweep);
  *hit = out.state == b2_toiStateHit;
  return out.fraction;
}

[[gnu::noinline]] float distanceBatch(const QueryPair* pairs, std::size_t count) {
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i)
    sum += runDistance(pairs[i]).distance;
  return sum;
}

[[gnu::noinline]] float manifoldBatch(const QueryPair* pairs, std::size_t count) {
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i) {
    const b2LocalManifold m = runManifold(pairs[i]);
    sum += m.normal.x + static_cast<float>(m.pointCount);
  }
  return sum;
}

[[gnu::noinline]] float toiBatch(const QuerySweep* sweeps, std::size_t count) {
  float sum = 0.0f;
  for (std::size_t i = 0; i < count; ++i)
    sum += runToi(sweeps[i]).fraction;
  return sum;
}

}  // namespace quack_bench::v3
