#include "quack/geometry/mass3.hpp"

#include <cmath>

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
