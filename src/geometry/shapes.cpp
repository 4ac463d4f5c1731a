#include "quack/geometry/shapes.hpp"

#include <string>
#include <type_traits>

#include "format.hpp"

namespace quack {
namespace {

using detail::formatNumber;
using detail::formatVec;

Status checkFinite(Vec2 v, const char* name) {
  if (!isFinite(v)) return fail(std::string(name) + " is not finite " + formatVec(v));
  return {};
}

std::string limitText() {
  static_assert(kMaxCoordinate == 1e9f, "the messages say 1e9");
  return "the coordinate limit 1e9 m";
}

// Finite and within +-kMaxCoordinate (checked before any arithmetic on the point, so that
// a huge shape is refused for its size rather than for what rounding made of it).
Status checkPoint(Vec2 v, const std::string& name) {
  if (Status s = checkFinite(v, name.c_str()); !s) return s;
  if (!withinCoordinateLimit(v))
    return fail(name + " " + formatVec(v) + " is beyond " + limitText());
  return {};
}

Status checkRadius(float radius, const char* shape, bool allowZero) {
  if (!isFinite(radius)) return fail(std::string(shape) + " radius is not finite");
  if (radius < 0.0f || (!allowZero && radius == 0.0f)) {
    return fail(std::string(shape) + " radius must be " + (allowZero ? ">= 0" : "> 0") + ", got " +
                formatNumber(radius));
  }
  if (radius > kMaxCoordinate) {
    return fail(std::string(shape) + " radius " + formatNumber(radius) + " m is beyond " +
                limitText());
  }
  return {};
}

Status checkSize(float size, const char* what) {
  if (size < kMinShapeSize) {
    return fail(std::string(what) + " " + formatNumber(size) +
                " m is below the smallest size Quack resolves (" + formatNumber(kMinShapeSize) +
                " m)");
  }
  return {};
}

// Centroid of the core polygon by a triangle fan about the first vertex (subtracting it
// keeps the products small when the polygon sits far from the origin).
Vec2 polygonCentroid(const Vec2* v, int count) {
  Vec2 origin = v[0];
  Vec2 sum;
  float area2 = 0.0f;
  for (int i = 1; i + 1 < count; ++i) {
    Vec2 e1 = v[i] - origin;
    Vec2 e2 = v[i + 1] - origin;
    float a = cross(e1, e2);
    sum += a * (e1 + e2);
    area2 += a;
  }
  return origin + (1.0f / (3.0f * area2)) * sum;
}

}  // namespace

Result<Circle> makeCircle(Vec2 center, float radius) {
  if (Status s = checkPoint(center, "circle center"); !s) return fail(s.message());
  if (Status s = checkRadius(radius, "circle", false); !s) return fail(s.message());
  if (Status s = checkSize(2.0f * radius, "circle diameter"); !s) return fail(s.message());
  return Circle{center, radius};
}

Result<Capsule> makeCapsule(Vec2 p1, Vec2 p2, float radius) {
  if (Status s = checkPoint(p1, "capsule p1"); !s) return fail(s.message());
  if (Status s = checkPoint(p2, "capsule p2"); !s) return fail(s.message());
  if (Status s = checkRadius(radius, "capsule", false); !s) {
    return fail(s.message() + (radius == 0.0f ? " (a capsule of radius 0 is a segment)" : ""));
  }
  if (distance(p1, p2) <= kHullRelativeTolerance * radius) {
    return fail("capsule p1 and p2 coincide " + formatVec(p1) + "; use a circle");
  }
  if (Status s = checkSize(maxf(distance(p1, p2), 2.0f * radius), "capsule size"); !s)
    return fail(s.message());
  return Capsule{p1, p2, radius};
}

Result<Segment> makeSegment(Vec2 p1, Vec2 p2) {
  if (Status s = checkPoint(p1, "segment p1"); !s) return fail(s.message());
  if (Status s = checkPoint(p2, "segment p2"); !s) return fail(s.message());
  if (p1 == p2) return fail("segment p1 and p2 coincide " + formatVec(p1) + " (zero length)");
  if (distance(p1, p2) < kMinShapeSize) {
    return fail("segment length " + formatNumber(distance(p1, p2)) +
                " m is below the smallest size Quack resolves (" + formatNumber(kMinShapeSize) +
                " m)");
  }
  return Segment{p1, p2};
}

Result<Polygon> makePolygon(const Hull& hull, float radius) {
  for (int i = 0; i < hull.count && i < kMaxPolygonVertices; ++i) {
    if (Status s = checkPoint(hull.points[i], "hull point " + std::to_string(i)); !s)
      return fail(s.message());
  }
  if (Status s = validateHull(hull); !s) return fail("invalid hull: " + s.message());
  if (Status s = checkRadius(radius, "polygon", true); !s) return fail(s.message());
  Polygon polygon;
  polygon.count = hull.count;
  polygon.radius = radius;
  for (int i = 0; i < hull.count; ++i) {
    polygon.vertices[i] = hull.points[i];
    Vec2 edge = hull.points[(i + 1) % hull.count] - hull.points[i];
    polygon.normals[i] = normalize(rightPerp(edge));
  }
  polygon.centroid = polygonCentroid(polygon.vertices, polygon.count);
  return polygon;
}

Result<Polygon> makePolygon(std::span<const Vec2> points, float radius) {
  for (std::size_t j = 0; j < points.size(); ++j) {
    if (Status s = checkPoint(points[j], "polygon points[" + std::to_string(j) + "]"); !s)
      return fail(s.message());
  }
  if (Status s = checkRadius(radius, "polygon", true); !s) return fail(s.message());
  Result<Hull> hull = computeHull(points);
  if (!hull) return fail("polygon points: " + hull.error().message);
  // Every given point must lie on the hull's boundary; one strictly inside means the
  // outline was concave, and silently hulling it would change the user's shape.
  Vec2 lower = points[0];
  Vec2 upper = points[0];
  for (Vec2 p : points) {
    lower = minv(lower, p);
    upper = maxv(upper, p);
  }
  float tol = hullTolerance(lower, upper);
  const Hull& h = hull.value();
  for (std::size_t j = 0; j < points.size(); ++j) {
    float depth = std::numeric_limits<float>::max();
    for (int i = 0; i < h.count; ++i) {
      Vec2 a = h.points[i];
      Vec2 n = normalize(rightPerp(h.points[(i + 1) % h.count] - a));
      depth = minf(depth, -dot(n, points[j] - a));
    }
    if (depth > tol) {
      return fail("polygon points are not convex: points[" + std::to_string(j) + "] " +
                  formatVec(points[j]) +
                  " lies inside the hull of the others (use a concave shape)");
    }
  }
  return makePolygon(h, radius);
}

Result<Polygon> makeBox(float halfWidth, float halfHeight, Vec2 center, float angle, float radius) {
  if (!isFinite(halfWidth) || !isFinite(halfHeight) || halfWidth <= 0.0f || halfHeight <= 0.0f) {
    return fail("box half-extents must be finite and > 0, got " +
                formatVec({halfWidth, halfHeight}));
  }
  if (halfWidth > kMaxCoordinate || halfHeight > kMaxCoordinate) {
    return fail("box half-extents " + formatVec({halfWidth, halfHeight}) + " m are beyond " +
                limitText());
  }
  if (Status s = checkSize(2.0f * minf(halfWidth, halfHeight), "box side"); !s)
    return fail(s.message());
  if (Status s = checkPoint(center, "box center"); !s) return fail(s.message());
  if (!isFinite(angle)) return fail("box angle is not finite");
  if (Status s = checkRadius(radius, "box", true); !s) return fail(s.message());
  Transform xf = makeTransform(center, angle);
  Polygon box;
  box.count = 4;
  box.radius = radius;
  const Vec2 corners[4] = {{-halfWidth, -halfHeight},
                           {halfWidth, -halfHeight},
                           {halfWidth, halfHeight},
                           {-halfWidth, halfHeight}};
  const Vec2 normals[4] = {{0.0f, -1.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}, {-1.0f, 0.0f}};
  for (int i = 0; i < 4; ++i) {
    box.vertices[i] = transformPoint(xf, corners[i]);
    box.normals[i] = transformVector(xf, normals[i]);
  }
  box.centroid = center;
  return box;
}

Status validatePolygon(const Polygon& polygon) {
  if (polygon.count < 3 || polygon.count > kMaxPolygonVertices) {
    return fail("polygon count " + std::to_string(polygon.count) + " is outside [3, " +
                std::to_string(kMaxPolygonVertices) + "]");
  }
  if (!isFinite(polygon.radius) || polygon.radius < 0.0f) {
    return fail("polygon radius " + formatNumber(polygon.radius) + " is not finite and >= 0");
  }
  Hull hull;
  hull.count = polygon.count;
  for (int i = 0; i < polygon.count; ++i)
    hull.points[i] = polygon.vertices[i];
  if (Status s = validateHull(hull); !s) return fail("polygon vertices: " + s.message());
  for (int i = 0; i < polygon.count; ++i) {
    Vec2 n = polygon.normals[i];
    Vec2 edge = polygon.vertices[(i + 1) % polygon.count] - polygon.vertices[i];
    // Unit length and perpendicular to the edge, to float precision of a normalisation.
    constexpr float kNormalTolerance = 1e-4f;
    if (absf(length(n) - 1.0f) > kNormalTolerance ||
        absf(dot(n, normalize(edge))) > kNormalTolerance || cross(edge, n) > 0.0f) {
      return fail("polygon normal " + std::to_string(i) +
                  " is not the outward unit normal of edge " + std::to_string(i));
    }
  }
  for (int i = 0; i < polygon.count; ++i) {
    if (dot(polygon.normals[i], polygon.centroid - polygon.vertices[i]) >= 0.0f) {
      return fail("polygon centroid " + formatVec(polygon.centroid) + " is outside edge " +
                  std::to_string(i));
    }
  }
  return {};
}

namespace {

template <ShapeType type, class Shape>
constexpr bool kHeldAt =
    std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(type), ShapeGeometry>,
                   Shape>;
static_assert(kHeldAt<ShapeType::circle, Circle> && kHeldAt<ShapeType::capsule, Capsule> &&
                  kHeldAt<ShapeType::segment, Segment> && kHeldAt<ShapeType::polygon, Polygon>,
              "ShapeGeometry's alternatives are in ShapeType order (shapeType relies on it)");

template <class T>
Status statusOf(const Result<T>& made) {
  return made ? Status{} : Status{made.error()};
}

}  // namespace

Status validateShape(const ShapeGeometry& geometry) {
  struct Visitor {
    Status operator()(const Circle& c) const { return statusOf(makeCircle(c.center, c.radius)); }
    Status operator()(const Capsule& c) const {
      return statusOf(makeCapsule(c.p1, c.p2, c.radius));
    }
    Status operator()(const Segment& s) const { return statusOf(makeSegment(s.p1, s.p2)); }
    Status operator()(const Polygon& p) const { return validatePolygon(p); }
  };
  return std::visit(Visitor{}, geometry);
}

}  // namespace quack
