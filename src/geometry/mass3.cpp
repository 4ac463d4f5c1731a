#include "quack/geometry/mass3.hpp"

#include <cmath>

#include "quack/math/detail/vec3d.hpp"

namespace quack {
namespace {

double d(float v) {
  return static_cast<double>(v);
}

// Double-precision symmetric 3x3 accumulator.
struct Sym {
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
};

Mat3 inertiaFromCovariance(const Sym& c) {
  // I = trace(C) Id - C for the second-moment (covariance) matrix C = integral of x x^T.
  double tr = c.xx + c.yy + c.zz;
  auto f = [](double v) { return static_cast<float>(v); };
  return Mat3::fromRows({f(tr - c.xx), f(-c.xy), f(-c.xz)}, {f(-c.xy), f(tr - c.yy), f(-c.yz)},
                        {f(-c.xz), f(-c.yz), f(tr - c.zz)});
}

using detail::Vec3d;

constexpr double kPiD = 3.14159265358979323846;

// c += w a a^T.
void addOuter(Sym& c, double w, Vec3d a) {
  c.xx += w * a.x * a.x;
  c.yy += w * a.y * a.y;
  c.zz += w * a.z * a.z;
  c.xy += w * a.x * a.y;
  c.xz += w * a.x * a.z;
  c.yz += w * a.y * a.z;
}

// c += w (a b^T + b a^T).
void addSymOuter(Sym& c, double w, Vec3d a, Vec3d b) {
  c.xx += 2.0 * w * a.x * b.x;
  c.yy += 2.0 * w * a.y * b.y;
  c.zz += 2.0 * w * a.z * b.z;
  c.xy += w * (a.x * b.y + b.x * a.y);
  c.xz += w * (a.x * b.z + b.x * a.z);
  c.yz += w * (a.y * b.z + b.y * a.z);
}

// Volume, first moment and second moment (integral of x x^T) of a solid about a point.
struct Moments {
  double volume = 0;
  Vec3d first;
  Sym second;
};

// The angle between two vectors, in [0, pi], by atan2 (accurate near 0 and pi).
double angleBetween(Vec3d a, Vec3d b) {
  return std::atan2(detail::length(detail::cross(a, b)), detail::dot(a, b));
}

// What rounding by `r` adds to the core (Minkowski sum with a ball): a prism on each face, a
// cylindrical wedge on each edge and a ball sector on each vertex, which tile the rounded
// solid outside the core. Coordinates relative to `ref`. Every piece is integrated in closed
// form:
// - a face polygon P (area A, first moment m, second moment M) swept by t in [0, r] along its
//   normal n: volume r A, first moment r m + r^2/2 A n, second r M + r^2/2 (m n^T + n m^T)
//   + r^3/3 A n n^T; the triangle (a, b, c) of a fan has M = A/12 (a a^T + b b^T + c c^T +
//   s s^T), s = a + b + c;
// - an edge of length L, direction e, midpoint q, between faces of normals n1 and n2 at the
//   exterior angle theta: the circular sector of radius r from n1 towards n2 (unit b in
//   the plane across the edge) swept along the edge: sector area S = theta r^2 / 2, first
//   moment Y1 = r^3/3 (sin theta n1 + (1 - cos theta) b), second Y2 = r^4/4 ((theta/2 +
//   sin 2theta / 4) n1 n1^T + (theta/2 - sin 2theta / 4) b b^T + sin^2 theta / 2 (n1 b^T +
//   b n1^T)); the wedge has volume S L, first moment S L q + L Y1, second S L (q q^T +
//   L^2/12 e e^T) + L (q Y1^T + Y1 q^T) + L Y2;
// - a vertex v whose normal cone (the directions u with v furthest along u) covers the
//   solid angle Omega = 2 pi - (sum of its faces' angles at v) (the angle defect) holds the
//   ball sector v + rho u, rho in [0, r], u in the cone: volume Omega r^3 / 3, first moment
//   volume v + r^4/4 w, second volume v v^T + r^4/4 (v w^T + w v^T) + r^5/5 W, with w and
//   W the integrals of u and u u^T over the cone. By Stokes' theorem w = 1/2 sum over the
//   cone's arcs of (arc angle) (unit normal of the arc's great circle, towards the cone);
//   the arc of the edge from v to u spans the edge's exterior angle and its great circle's
//   normal is (v - u) / |v - u| (the cone is where dot(n, u - v) <= 0). The cones tile the
//   sphere, so the W add up to the ball's 4 pi / 3 Id, whatever each is alone.
// Their volumes add up to Steiner's formula, A r + (sum of L theta) r^2 / 2 + 4/3 pi r^3.
Moments roundingMoments(const Hull3& hull, Vec3d ref) {
  const double r = d(hull.radius);
  Moments out;
  auto at = [&](int v) { return detail::toDouble(hull.vertices[v]) - ref; };
  double faceAngles[kMaxHullVertices3] = {};
  Vec3d cone[kMaxHullVertices3];
  for (int f = 0; f < hull.faceCount; ++f) {
    const HullFace3& face = hull.faces[f];
    const Vec3d n = detail::toDouble(face.normal);
    double area = 0;
    Vec3d m;
    Sym sec;
    const Vec3d p0 = at(hull.faceVertices[face.first]);
    for (int k = 1; k + 1 < face.count; ++k) {
      const Vec3d p1 = at(hull.faceVertices[face.first + k]);
      const Vec3d p2 = at(hull.faceVertices[face.first + k + 1]);
      const double a = 0.5 * detail::dot(detail::cross(p1 - p0, p2 - p0), n);
      const Vec3d sum = p0 + p1 + p2;
      area += a;
      m = m + (a / 3.0) * sum;
      addOuter(sec, a / 12.0, p0);
      addOuter(sec, a / 12.0, p1);
      addOuter(sec, a / 12.0, p2);
      addOuter(sec, a / 12.0, sum);
    }
    out.volume += r * area;
    out.first = out.first + r * m + (0.5 * r * r * area) * n;
    out.second.xx += r * sec.xx;
    out.second.yy += r * sec.yy;
    out.second.zz += r * sec.zz;
    out.second.xy += r * sec.xy;
    out.second.xz += r * sec.xz;
    out.second.yz += r * sec.yz;
    addSymOuter(out.second, 0.5 * r * r, m, n);
    addOuter(out.second, r * r * r / 3.0 * area, n);
    for (int k = 0; k < face.count; ++k) {
      const int prev = hull.faceVertices[face.first + (k + face.count - 1) % face.count];
      const int v = hull.faceVertices[face.first + k];
      const int next = hull.faceVertices[face.first + (k + 1) % face.count];
      faceAngles[v] += angleBetween(at(prev) - at(v), at(next) - at(v));
    }
  }
  const double r2 = r * r, r3 = r2 * r, r4 = r3 * r, r5 = r4 * r;
  for (int e = 0; e < hull.edgeCount; ++e) {
    const HullEdge3& edge = hull.edges[e];
    const Vec3d p0 = at(edge.v0), p1 = at(edge.v1);
    const double len = detail::length(p1 - p0);
    const Vec3d dir = (1.0 / len) * (p1 - p0);
    const Vec3d n1 = detail::toDouble(hull.faces[edge.faceLeft].normal);
    const Vec3d n2 = detail::toDouble(hull.faces[edge.faceRight].normal);
    const double theta = angleBetween(n1, n2);
    // The unit across the edge, square to n1, on n2's side.
    Vec3d b = detail::cross(dir, n1);
    b = (1.0 / detail::length(b)) * b;
    if (detail::dot(b, n2) < 0.0) b = -1.0 * b;
    const double sn = std::sin(theta), half = std::sin(0.5 * theta);
    const double area = 0.5 * theta * r2;
    const Vec3d y1 = (r3 / 3.0) * (sn * n1 + (2.0 * half * half) * b);
    const Vec3d q = 0.5 * (p0 + p1);
    out.volume += area * len;
    out.first = out.first + (area * len) * q + len * y1;
    addOuter(out.second, area * len, q);
    addOuter(out.second, area * len * len * len / 12.0, dir);
    addSymOuter(out.second, len, q, y1);
    const double s2 = std::sin(2.0 * theta) / 4.0;
    addOuter(out.second, len * r4 / 4.0 * (0.5 * theta + s2), n1);
    addOuter(out.second, len * r4 / 4.0 * (0.5 * theta - s2), b);
    addSymOuter(out.second, len * r4 / 4.0 * 0.5 * sn * sn, n1, b);
    // Each end's cone gains half the arc's angle times the arc normal, (v - u) / |v - u|.
    cone[edge.v0] = cone[edge.v0] + (-0.5 * theta) * dir;
    cone[edge.v1] = cone[edge.v1] + (0.5 * theta) * dir;
  }
  for (int v = 0; v < hull.vertexCount; ++v) {
    const Vec3d p = at(v);
    const double volume = (2.0 * kPiD - faceAngles[v]) * r3 / 3.0;
    out.volume += volume;
    out.first = out.first + volume * p + (r4 / 4.0) * cone[v];
    addOuter(out.second, volume, p);
    addSymOuter(out.second, r4 / 4.0, p, cone[v]);
  }
  const double ball = 4.0 * kPiD / 15.0 * r5;
  out.second.xx += ball;
  out.second.yy += ball;
  out.second.zz += ball;
  return out;
}

}  // namespace

MassProperties3 computeMass(const Sphere& sphere, float density) {
  QUACK_ASSERT(std::isfinite(density) && density >= 0.0f);
  MassProperties3 m;
  float r = sphere.radius;
  m.volume = 4.0f / 3.0f * kPi * r * r * r;
  m.mass = density * m.volume;
  m.centroid = sphere.center;
  float i = 0.4f * m.mass * r * r;
  m.inertia = Mat3::diagonal({i, i, i});
  return m;
}

MassProperties3 computeMass(const Capsule3& capsule, float density) {
  QUACK_ASSERT(std::isfinite(density) && density >= 0.0f);
  double r = d(capsule.radius);
  Vec3 axis = capsule.p2 - capsule.p1;
  double h = d(length(axis));
  Vec3 u = normalize(axis);
  const double pi = 3.14159265358979323846;
  double rho = d(density);
  double mc = rho * pi * r * r * h;              // cylinder
  double ms = rho * 4.0 / 3.0 * pi * r * r * r;  // both hemispheres
  double iAxis = mc * r * r / 2.0 + ms * 0.4 * r * r;
  double iPerp =
      mc * (3.0 * r * r + h * h) / 12.0 + ms * (0.4 * r * r + h * h / 4.0 + 3.0 * h * r / 8.0);
  MassProperties3 m;
  m.volume = static_cast<float>(pi * r * r * h + 4.0 / 3.0 * pi * r * r * r);
  m.mass = static_cast<float>(mc + ms);
  m.centroid = 0.5f * (capsule.p1 + capsule.p2);
  // I = iPerp Id + (iAxis - iPerp) u u^T.
  m.inertia = Mat3::diagonal({static_cast<float>(iPerp), static_cast<float>(iPerp),
                              static_cast<float>(iPerp)}) +
              static_cast<float>(iAxis - iPerp) * outer(u, u);
  return m;
}

MassProperties3 computeMass(const Hull3& hull, float density) {
  QUACK_ASSERT(std::isfinite(density) && density >= 0.0f);
  // Tetrahedra from vertex 0 (relative coordinates keep the products small far from the
  // origin). For the tetrahedron (0, a, b, c) with D = a.(b x c), the volume is D/6, its
  // first moment D/24 (a + b + c) and its second moment D/120 (a a^T + b b^T + c c^T +
  // s s^T) with s = a + b + c.
  Vec3 ref = hull.vertices[0];
  double vol6 = 0, mx = 0, my = 0, mz = 0;
  Sym c;
  for (int f = 0; f < hull.faceCount; ++f) {
    const HullFace3& face = hull.faces[f];
    Vec3 p0 = hull.vertices[hull.faceVertices[face.first]] - ref;
    for (int k = 1; k + 1 < face.count; ++k) {
      Vec3 p1 = hull.vertices[hull.faceVertices[face.first + k]] - ref;
      Vec3 p2 = hull.vertices[hull.faceVertices[face.first + k + 1]] - ref;
      double a[3] = {d(p0.x), d(p0.y), d(p0.z)}, b[3] = {d(p1.x), d(p1.y), d(p1.z)},
             c3[3] = {d(p2.x), d(p2.y), d(p2.z)};
      double det = a[0] * (b[1] * c3[2] - b[2] * c3[1]) - a[1] * (b[0] * c3[2] - b[2] * c3[0]) +
                   a[2] * (b[0] * c3[1] - b[1] * c3[0]);
      double s[3] = {a[0] + b[0] + c3[0], a[1] + b[1] + c3[1], a[2] + b[2] + c3[2]};
      vol6 += det;
      mx += det * s[0];
      my += det * s[1];
      mz += det * s[2];
      auto term = [&](int i, int j) {
        return det / 120.0 * (a[i] * a[j] + b[i] * b[j] + c3[i] * c3[j] + s[i] * s[j]);
      };
      c.xx += term(0, 0);
      c.yy += term(1, 1);
      c.zz += term(2, 2);
      c.xy += term(0, 1);
      c.xz += term(0, 2);
      c.yz += term(1, 2);
    }
  }
  if (hull.radius > 0.0f) {
    // In the tetrahedra's relative coordinates and scale (six volumes, 24 first moments).
    const Moments round = roundingMoments(hull, detail::toDouble(ref));
    vol6 += 6.0 * round.volume;
    mx += 24.0 * round.first.x;
    my += 24.0 * round.first.y;
    mz += 24.0 * round.first.z;
    c.xx += round.second.xx;
    c.yy += round.second.yy;
    c.zz += round.second.zz;
    c.xy += round.second.xy;
    c.xz += round.second.xz;
    c.yz += round.second.yz;
  }
  double vol = vol6 / 6.0;
  double cx = mx / (4.0 * vol6), cy = my / (4.0 * vol6), cz = mz / (4.0 * vol6);
  // Second moment about the centroid (parallel axis), then times density.
  c.xx -= vol * cx * cx;
  c.yy -= vol * cy * cy;
  c.zz -= vol * cz * cz;
  c.xy -= vol * cx * cy;
  c.xz -= vol * cx * cz;
  c.yz -= vol * cy * cz;
  double rho = d(density);
  c = {rho * c.xx, rho * c.yy, rho * c.zz, rho * c.xy, rho * c.xz, rho * c.yz};
  MassProperties3 m;
  m.volume = static_cast<float>(vol);
  m.mass = static_cast<float>(rho * vol);
  m.centroid = ref + Vec3{static_cast<float>(cx), static_cast<float>(cy), static_cast<float>(cz)};
  m.inertia = inertiaFromCovariance(c);
  return m;
}

MassProperties3 computeMass(const Triangle3& triangle, [[maybe_unused]] float density) {
  QUACK_ASSERT(std::isfinite(density) && density >= 0.0f);
  MassProperties3 m;
  m.centroid = (1.0f / 3.0f) * (triangle.v[0] + triangle.v[1] + triangle.v[2]);
  return m;
}

MassProperties3 computeMass(const ShapeGeometry3& geometry, float density) {
  return std::visit([density](const auto& shape) { return computeMass(shape, density); }, geometry);
}

}  // namespace quack
