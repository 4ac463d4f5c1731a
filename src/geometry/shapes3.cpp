#include "quack/geometry/shapes3.hpp"

#include <string>

#include "format.hpp"
#include "quack/math/aabb.hpp"

namespace quack {
namespace {

using detail::formatNumber;

std::string formatVec3(Vec3 v) {
  return "(" + formatNumber(v.x) + ", " + formatNumber(v.y) + ", " + formatNumber(v.z) + ")";
}

// Finite and within +-kMaxCoordinate.
Status checkPoint(Vec3 v, const std::string& name) {
  if (!isFinite(v)) return fail(name + " is not finite " + formatVec3(v));
  if (!(absf(v.x) <= kMaxCoordinate && absf(v.y) <= kMaxCoordinate && absf(v.z) <= kMaxCoordinate))
    return fail(name + " " + formatVec3(v) + " is beyond the coordinate limit 1e9 m");
  return {};
}

Status checkRadius(float radius, const std::string& shape) {
  if (!std::isfinite(radius)) return fail(shape + " radius is not finite");
  if (radius <= 0.0f) return fail(shape + " radius must be > 0, got " + formatNumber(radius));
  if (radius > kMaxCoordinate)
    return fail(shape + " radius " + formatNumber(radius) +
                " m is beyond the coordinate limit 1e9 m");
  if (radius < kMinShapeSize) {
    return fail(shape + " radius " + formatNumber(radius) +
                " m is below the smallest size Quack resolves (" + formatNumber(kMinShapeSize) +
                " m)");
  }
  return {};
}

// A hull's rounding radius: finite, >= 0 (0 is the plain hull), within the coordinate limit.
Status checkRoundingRadius(float radius, const std::string& shape) {
  if (!std::isfinite(radius)) return fail(shape + " radius is not finite");
  if (radius < 0.0f) return fail(shape + " radius must be >= 0, got " + formatNumber(radius));
  if (radius > kMaxCoordinate)
    return fail(shape + " radius " + formatNumber(radius) +
                " m is beyond the coordinate limit 1e9 m");
  return {};
}

}  // namespace

Result<Sphere> makeSphere(Vec3 center, float radius) {
  if (Status s = checkPoint(center, "sphere center"); !s) return Error{s.message()};
  if (Status s = checkRadius(radius, "sphere"); !s) return Error{s.message()};
  return Sphere{center, radius};
}

Result<Capsule3> makeCapsule3(Vec3 p1, Vec3 p2, float radius) {
  if (Status s = checkPoint(p1, "capsule p1"); !s) return Error{s.message()};
  if (Status s = checkPoint(p2, "capsule p2"); !s) return Error{s.message()};
  if (Status s = checkRadius(radius, "capsule"); !s) return Error{s.message()};
  if (distance(p1, p2) <= kHull3RelativeTolerance * radius) {
    return fail("capsule p1 and p2 are " + formatNumber(distance(p1, p2)) +
                " m apart, too close for radius " + formatNumber(radius) + " (use a sphere)");
  }
  return Capsule3{p1, p2, radius};
}

Result<Triangle3> makeTriangle3(Vec3 a, Vec3 b, Vec3 c) {
  const char* names[3] = {"triangle v[0]", "triangle v[1]", "triangle v[2]"};
  Vec3 v[3] = {a, b, c};
  for (int i = 0; i < 3; ++i)
    if (Status s = checkPoint(v[i], names[i]); !s) return Error{s.message()};
  float longest = maxf(distance(a, b), maxf(distance(b, c), distance(c, a)));
  // Twice the area over the longest edge is the least height.
  float height = longest > 0.0f ? length(cross(b - a, c - a)) / longest : 0.0f;
  if (longest < kMinShapeSize || height <= kHull3RelativeTolerance * longest) {
    return fail("triangle " + formatVec3(a) + ", " + formatVec3(b) + ", " + formatVec3(c) +
                " has no area (collinear or coincident vertices)");
  }
  return Triangle3{{a, b, c}};
}

Result<Hull3> makeHull3(std::span<const Vec3> points, float radius) {
  if (Status s = checkRoundingRadius(radius, "hull"); !s) return Error{s.message()};
  Result<Hull3Build> build = computeHull3(points);
  if (!build) return build.error();
  build->hull.radius = radius;
  return build->hull;
}

Result<Hull3> makeBox3(Vec3 half, Transform3 shapeFromBox, float radius) {
  if (Status s = checkRoundingRadius(radius, "box"); !s) return Error{s.message()};
  if (!isFinite(half)) return fail("box half-extents are not finite " + formatVec3(half));
  if (!isFinite(shapeFromBox.p) || !isFinite(shapeFromBox.q))
    return fail("box transform is not finite");
  if (lengthSquared(shapeFromBox.q) == 0.0f) return fail("box rotation is the zero quaternion");
  if (half.x < kMinShapeSize || half.y < kMinShapeSize || half.z < kMinShapeSize) {
    return fail("box half-extents " + formatVec3(half) +
                " must each be at least the smallest size Quack resolves (" +
                formatNumber(kMinShapeSize) + " m)");
  }
  Transform3 t{shapeFromBox.p, normalize(shapeFromBox.q)};
  Vec3 corners[8];
  for (int i = 0; i < 8; ++i) {
    Vec3 c{(i & 1) ? half.x : -half.x, (i & 2) ? half.y : -half.y, (i & 4) ? half.z : -half.z};
    corners[i] = transformPoint(t, c);
  }
  return makeHull3(corners, radius);
}

Status validateShape(const ShapeGeometry3& geometry) {
  struct Check {
    Status operator()(const Sphere& s) const {
      Result<Sphere> r = makeSphere(s.center, s.radius);
      return r ? Status{} : Status{r.error()};
    }
    Status operator()(const Capsule3& c) const {
      Result<Capsule3> r = makeCapsule3(c.p1, c.p2, c.radius);
      return r ? Status{} : Status{r.error()};
    }
    Status operator()(const Hull3& h) const { return validateHull3(h); }
    Status operator()(const Triangle3& t) const {
      Result<Triangle3> r = makeTriangle3(t.v[0], t.v[1], t.v[2]);
      return r ? Status{} : Status{r.error()};
    }
  };
  return std::visit(Check{}, geometry);
}

}  // namespace quack
