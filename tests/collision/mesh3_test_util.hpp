#pragma once
// Meshes shared by the mesh tests.

#include <array>
#include <cstdint>
#include <vector>

#include <cmath>

#include "quack/collision/mesh3.hpp"
#include "quack/collision/proxy3.hpp"

namespace quack::testing {

// An n x n grid of quads over [-s, s]^2 at heights height(x, z), two triangles each, with
// the diagonals alternating.
template <class Height>
Mesh3 grid(int n, float s, Height height) {
  std::vector<Vec3> v;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const float x = -s + 2 * s * static_cast<float>(i) / static_cast<float>(n);
      const float z = -s + 2 * s * static_cast<float>(j) / static_cast<float>(n);
      v.push_back({x, height(x, z), z});
    }
  }
  std::vector<std::array<std::int32_t, 3>> t;
  auto at = [n](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if ((i + j) % 2 == 0) {
        t.push_back({a, d, c});
        t.push_back({a, c, b});
      } else {
        t.push_back({a, d, b});
        t.push_back({d, c, b});
      }
    }
  }
  return makeMesh3(v, t).value();
}

// The closed box [-h, h]^3 as twelve triangles, fronts out.
inline Mesh3 closedBox(Vec3 h) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) {
    v.push_back({(i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z});
  }
  // Each face's corners counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  std::vector<std::array<std::int32_t, 3>> t;
  for (const auto& f : faces) {
    t.push_back({f[0], f[1], f[2]});
    t.push_back({f[0], f[2], f[3]});
  }
  return makeMesh3(v, t).value();
}

// The rolling field the random mesh tests use: a 6 x 6 grid over [-3, 3]^2.
inline Mesh3 rollingField() {
  return grid(6, 3, [](float x, float z) { return 0.4f * std::sin(1.3f * x + z); });
}

// One shape of each convex kind the random mesh tests move about, and their proxies. The
// proxies point into the shapes, so the set is neither copied nor moved.
struct ConvexKinds {
  explicit ConvexKinds(Vec3 sphereCenter = {})
      : sphere(makeSphere(sphereCenter, 0.3f).value()),
        capsule(makeCapsule3({-0.4f, 0, 0}, {0.4f, 0, 0}, 0.15f).value()),
        hull(makeBox3({0.3f, 0.2f, 0.25f}).value()),
        triangle(makeTriangle3({-0.4f, 0, -0.4f}, {0.4f, 0, -0.4f}, {0, 0, 0.5f}).value()),
        proxies{makeProxy(sphere), makeProxy(capsule), makeProxy(hull), makeProxy(triangle)} {}
  ConvexKinds(const ConvexKinds&) = delete;
  ConvexKinds& operator=(const ConvexKinds&) = delete;

  Sphere sphere;
  Capsule3 capsule;
  Hull3 hull;
  Triangle3 triangle;
  std::vector<ShapeProxy3> proxies;
};

}  // namespace quack::testing
