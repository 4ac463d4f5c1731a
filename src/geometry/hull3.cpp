// Quickhull in 3D (Barber, Dobkin and Huhdanpaa 1996) with thick planes, then the merge of
// coplanar triangles into polygonal faces. See hull3.hpp for the contract.
//
// Everything runs in double on the float inputs (exact), so the only tolerance that matters
// is the thick-plane one, kHull3RelativeTolerance of the point set's size: the rounding of
// the double plane tests is ~1e-16 of the size, nine orders below it. The conflict lists
// are per face, as in the paper; the visible region is grown from the face the eye point
// was taken from, across neighbours that see it by more than the tolerance, so it is
// connected and the horizon is the boundary of one region. Visibility itself is exact
// (above the plane at all), so the hull stays convex to double rounding; only the choice of
// which points to add uses the thick planes.

#include "quack/geometry/hull3.hpp"
#include "quack/math/detail/vec3d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>
#include <vector>

#include "format.hpp"
#include "quack/math/aabb.hpp"

namespace quack {
namespace {

using detail::formatNumber;

using D3 = detail::Vec3d;
using detail::toDouble;

struct Face {
  int v[3];
  D3 n;      // outward unit normal
  double d;  // plane offset: dot(n, x) = d
  bool alive = true;
  std::vector<int> outside;  // conflict list: input points above this face by > tol
};

// Quickhull stops once the hull it is building has this many vertices: the answer is then
// "more than kMaxHullVertices3" however the remaining points fall. It adds the furthest
// points first, so a hull that large almost never shrinks back under the limit, and without
// the stop a large round cloud (1e5 points on a sphere) takes minutes to be refused.
constexpr int kHull3BuildVertexLimit = 4 * kMaxHullVertices3;

enum class RunResult { done, cap, tooManyVertices };

std::uint64_t edgeKey(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

std::string formatVec3(Vec3 v) {
  return "(" + formatNumber(v.x) + ", " + formatNumber(v.y) + ", " + formatNumber(v.z) + ")";
}

class QuickHull {
 public:
  QuickHull(const std::vector<D3>& p, double tol) : p_(p), tol_(tol) {}

  // Plane through a, b, c (counter-clockwise seen from outside).
  Face makeFace(int a, int b, int c) const {
    Face f;
    f.v[0] = a;
    f.v[1] = b;
    f.v[2] = c;
    D3 n = detail::cross(p_[b] - p_[a], p_[c] - p_[a]);
    double len = detail::length(n);
    f.n = len > 0 ? (1.0 / len) * n : D3{};
    f.d = detail::dot(f.n, p_[a]);
    return f;
  }
  double height(const Face& f, int i) const { return detail::dot(f.n, p_[i]) - f.d; }

  int addFace(Face f) {
    int id = static_cast<int>(faces_.size());
    for (int k = 0; k < 3; ++k)
      owner_[edgeKey(f.v[k], f.v[(k + 1) % 3])] = id;
    faces_.push_back(std::move(f));
    ++live_;
    return id;
  }
  void removeFace(int id) {
    Face& f = faces_[static_cast<std::size_t>(id)];
    f.alive = false;
    --live_;
    for (int k = 0; k < 3; ++k)
      owner_.erase(edgeKey(f.v[k], f.v[(k + 1) % 3]));
  }
  int neighbour(int a, int b) const {  // the face owning the directed edge b -> a
    auto it = owner_.find(edgeKey(b, a));
    return it == owner_.end() ? -1 : it->second;
  }

  // Assigns point i to the first of `candidates` it is above by more than tol; failing
  // that, to any live face it is above by more than tol. A point within tol of every face
  // plane may still be further than tol from the hull, beyond a sharp edge (the rim of a
  // sliver: within tol of both planes, yet well outside both faces), so such a point is
  // dropped only when its true distance to the hull is at most tol; otherwise it goes to
  // the face it is most above.
  void assign(int i, const std::vector<int>& candidates) {
    for (int id : candidates) {
      Face& f = faces_[static_cast<std::size_t>(id)];
      if (height(f, i) > tol_) {
        f.outside.push_back(i);
        return;
      }
    }
    int best = -1;
    double bestHeight = 0.0;
    for (std::size_t id = 0; id < faces_.size(); ++id) {
      Face& f = faces_[id];
      if (!f.alive) continue;
      double h = height(f, i);
      if (h > tol_) {
        f.outside.push_back(i);
        return;
      }
      if (h > bestHeight) {
        bestHeight = h;
        best = static_cast<int>(id);
      }
    }
    if (best < 0) return;  // inside every plane: inside the hull
    double d2 = std::numeric_limits<double>::infinity();
    for (const Face& f : faces_) {
      if (f.alive) d2 = std::min(d2, distanceSquaredToTriangle(i, f));
    }
    if (d2 > tol_ * tol_) faces_[static_cast<std::size_t>(best)].outside.push_back(i);
  }

  // Squared distance from point i to the triangle of face f (Ericson, "Real-Time Collision
  // Detection", 5.1.5, by Voronoi regions).
  double distanceSquaredToTriangle(int i, const Face& f) const {
    D3 pt = p_[static_cast<std::size_t>(i)];
    D3 a = p_[static_cast<std::size_t>(f.v[0])], b = p_[static_cast<std::size_t>(f.v[1])],
       c = p_[static_cast<std::size_t>(f.v[2])];
    D3 ab = b - a, ac = c - a, ap = pt - a;
    auto sq = [&](D3 q) { return detail::dot(pt - q, pt - q); };
    double d1 = detail::dot(ab, ap), d2 = detail::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return sq(a);
    D3 bp = pt - b;
    double d3 = detail::dot(ab, bp), d4 = detail::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return sq(b);
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return sq(a + (d1 / (d1 - d3)) * ab);
    D3 cp = pt - c;
    double d5 = detail::dot(ab, cp), d6 = detail::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return sq(c);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return sq(a + (d2 / (d2 - d6)) * ac);
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
      return sq(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
    double denom = 1.0 / (va + vb + vc);
    return sq(a + (vb * denom) * ab + (vc * denom) * ac);
  }

  // Runs the quickhull loop from the tetrahedron i0..i3 over `candidates`: done, or the
  // iteration cap (cannot happen: each step adds one point for good), or the vertex limit.
  RunResult run(int i0, int i1, int i2, int i3, const std::vector<int>& candidates) {
    int tet[4] = {i0, i1, i2, i3};
    static constexpr int kTetFaces[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
    std::vector<int> ids;
    for (int k = 0; k < 4; ++k) {
      int a = tet[kTetFaces[k][0]], b = tet[kTetFaces[k][1]], c = tet[kTetFaces[k][2]];
      Face f = makeFace(a, b, c);
      int opposite = tet[6 - kTetFaces[k][0] - kTetFaces[k][1] - kTetFaces[k][2]];
      if (height(f, opposite) > 0) f = makeFace(a, c, b);
      ids.push_back(k);
      faces_.push_back(f);
    }
    // Orientation may have swapped edges: register ownership now.
    for (int id = 0; id < 4; ++id) {
      const Face& f = faces_[static_cast<std::size_t>(id)];
      for (int k = 0; k < 3; ++k)
        owner_[edgeKey(f.v[k], f.v[(k + 1) % 3])] = id;
    }
    live_ = 4;
    for (int i : candidates)
      assign(i, ids);

    // Cap: each pass makes one input point a vertex for good or drops it, so there are at
    // most as many passes as points.
    const std::size_t cap = candidates.size() + 1;
    for (std::size_t pass = 0; pass <= cap; ++pass) {
      int start = -1;
      for (std::size_t id = 0; id < faces_.size(); ++id) {
        if (faces_[id].alive && !faces_[id].outside.empty()) {
          start = static_cast<int>(id);
          break;
        }
      }
      if (start < 0) return RunResult::done;
      Face& sf = faces_[static_cast<std::size_t>(start)];
      int eye = sf.outside[0];
      double best = height(sf, eye);
      for (int i : sf.outside) {
        double h = height(sf, i);
        if (h > best) {
          best = h;
          eye = i;
        }
      }
      addPoint(eye, start);
      // A closed triangulated hull has F = 2V - 4.
      if ((live_ + 4) / 2 > kHull3BuildVertexLimit) return RunResult::tooManyVertices;
    }
    return RunResult::cap;
  }

  void addPoint(int eye, int start) {
    std::vector<int> visible{start};
    std::vector<char> seen(faces_.size(), 0), isVisible(faces_.size(), 0);
    seen[static_cast<std::size_t>(start)] = 1;
    isVisible[static_cast<std::size_t>(start)] = 1;
    for (std::size_t k = 0; k < visible.size(); ++k) {
      const Face& f = faces_[static_cast<std::size_t>(visible[k])];
      for (int e = 0; e < 3; ++e) {
        int g = neighbour(f.v[e], f.v[(e + 1) % 3]);
        if (g < 0 || seen[static_cast<std::size_t>(g)]) continue;
        seen[static_cast<std::size_t>(g)] = 1;
        // Visible when the eye is above the plane at all (double rounding aside): only the
        // choice of eye points uses the thick planes. A thick visibility test would keep
        // faces the eye is barely above, leave an edge concave by up to tol, and such
        // concavities add up over the passes.
        if (height(faces_[static_cast<std::size_t>(g)], eye) > 0.0) {
          isVisible[static_cast<std::size_t>(g)] = 1;
          visible.push_back(g);
        }
      }
    }
    // Horizon: directed edges of visible faces whose neighbour is not visible.
    std::vector<std::pair<int, int>> horizon;
    for (int id : visible) {
      const Face& f = faces_[static_cast<std::size_t>(id)];
      for (int e = 0; e < 3; ++e) {
        int a = f.v[e], b = f.v[(e + 1) % 3];
        int g = neighbour(a, b);
        if (g >= 0 && !isVisible[static_cast<std::size_t>(g)]) horizon.emplace_back(a, b);
      }
    }
    std::vector<int> orphans;
    for (int id : visible) {
      Face& f = faces_[static_cast<std::size_t>(id)];
      for (int i : f.outside)
        if (i != eye) orphans.push_back(i);
      f.outside.clear();
      f.outside.shrink_to_fit();
      removeFace(id);
    }
    std::vector<int> created;
    for (auto [a, b] : horizon)
      created.push_back(addFace(makeFace(a, b, eye)));
    for (int i : orphans)
      assign(i, created);
  }

  const std::vector<Face>& faces() const { return faces_; }
  int neighbourOf(int a, int b) const { return neighbour(a, b); }

 private:
  const std::vector<D3>& p_;
  double tol_;
  std::vector<Face> faces_;
  std::unordered_map<std::uint64_t, int> owner_;
  int live_ = 0;
};

}  // namespace

float hull3Tolerance(Vec3 lower, Vec3 upper) noexcept {
  Vec3 size = upper - lower;
  float extent = maxf(size.x, maxf(size.y, size.z));
  Vec3 m = maxv(absv(lower), absv(upper));
  float magnitude = maxf(m.x, maxf(m.y, m.z));
  // Below a few ulps of the coordinates themselves no geometry is meaningful.
  float resolution = 4.0f * std::numeric_limits<float>::epsilon() * magnitude;
  return maxf(kHull3RelativeTolerance * extent, resolution);
}

Result<Hull3Build> computeHull3(std::span<const Vec3> points) {
  const int n = static_cast<int>(points.size());
  if (n == 0) return fail("a hull needs at least four points, got none");
  for (int i = 0; i < n; ++i) {
    Vec3 v = points[static_cast<std::size_t>(i)];
    if (!isFinite(v))
      return fail("points[" + std::to_string(i) + "] is not finite " + formatVec3(v));
    if (!(absf(v.x) <= kMaxCoordinate && absf(v.y) <= kMaxCoordinate &&
          absf(v.z) <= kMaxCoordinate)) {
      return fail("points[" + std::to_string(i) + "] " + formatVec3(v) +
                  " is beyond the coordinate limit 1e9 m");
    }
  }
  Vec3 lower = points[0], upper = points[0];
  for (Vec3 v : points) {
    lower = minv(lower, v);
    upper = maxv(upper, v);
  }
  const float tolF = hull3Tolerance(lower, upper);
  const double tol = static_cast<double>(tolF);
  std::vector<D3> p(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    p[i] = toDouble(points[i]);

  auto build = std::make_unique<Hull3Build>();
  Hull3Report& report = build->report;
  report.inputCount = n;
  report.tolerance = tolF;

  // Duplicates: sweep in x order; a point within tol of a kept point seen before it is one.
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const D3 &pa = p[static_cast<std::size_t>(a)], &pb = p[static_cast<std::size_t>(b)];
    return pa.x != pb.x ? pa.x < pb.x : a < b;
  });
  std::vector<char> duplicate(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const D3& pk = p[static_cast<std::size_t>(order[k])];
    for (std::size_t j = k; j-- > 0;) {
      const D3& pj = p[static_cast<std::size_t>(order[j])];
      if (pk.x - pj.x > tol) break;
      if (!duplicate[static_cast<std::size_t>(order[j])] && detail::length(pk - pj) <= tol) {
        duplicate[static_cast<std::size_t>(order[k])] = 1;
        ++report.duplicates;
        break;
      }
    }
  }
  std::vector<int> kept;
  for (int i = 0; i < n; ++i)
    if (!duplicate[static_cast<std::size_t>(i)]) kept.push_back(i);
  auto P = [&](int i) { return p[static_cast<std::size_t>(i)]; };

  // Initial tetrahedron: extremes along the widest axis, then the furthest from their line,
  // then the furthest from their plane.
  Vec3 ext = upper - lower;
  int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  auto coord = [&](int i) { return axis == 0 ? P(i).x : (axis == 1 ? P(i).y : P(i).z); };
  int i0 = kept[0], i1 = kept[0];
  for (int i : kept) {
    if (coord(i) < coord(i0)) i0 = i;
    if (coord(i) > coord(i1)) i1 = i;
  }
  if (detail::length(P(i1) - P(i0)) <= tol) {
    return fail("the " + std::to_string(n) + " points are all within " + formatNumber(tolF) +
                " m of one point: a hull needs volume (use a sphere)");
  }
  D3 u = (1.0 / detail::length(P(i1) - P(i0))) * (P(i1) - P(i0));
  int i2 = -1;
  double bestLine = 0;
  for (int i : kept) {
    double dl = detail::length(detail::cross(P(i) - P(i0), u));
    if (dl > bestLine) {
      bestLine = dl;
      i2 = i;
    }
  }
  if (i2 < 0 || bestLine <= tol) {
    return fail("the points are collinear (within " + formatNumber(tolF) +
                " m of a line): a hull needs volume (use a capsule)");
  }
  D3 pn = detail::cross(P(i1) - P(i0), P(i2) - P(i0));
  pn = (1.0 / detail::length(pn)) * pn;
  int i3 = -1;
  double bestPlane = 0;
  for (int i : kept) {
    double dp = std::fabs(detail::dot(pn, P(i) - P(i0)));
    if (dp > bestPlane) {
      bestPlane = dp;
      i3 = i;
    }
  }
  if (i3 < 0 || bestPlane <= tol) {
    return fail("the points are coplanar (within " + formatNumber(tolF) +
                " m of a plane): a hull needs volume (use a triangle or a thin box)");
  }

  std::vector<int> rest;
  for (int i : kept)
    if (i != i0 && i != i1 && i != i2 && i != i3) rest.push_back(i);
  QuickHull qh(p, tol);
  RunResult run = qh.run(i0, i1, i2, i3, rest);
  if (run == RunResult::cap) return fail("quickhull: iteration cap reached (internal)");
  if (run == RunResult::tooManyVertices) {
    return fail("the hull has more than " + std::to_string(kMaxHullVertices3) +
                " vertices (quickhull stopped at " + std::to_string(kHull3BuildVertexLimit) + ")");
  }

  // Merge adjacent triangles within mergeTol of one plane into polygonal faces. Points
  // within tol of the hull were never added, so what is left to merge are faces that are
  // coplanar up to the rounding of their float corners (a rotated box's faces: ~1e-7 of
  // the size). A merge tolerance as large as tol would also merge nearly parallel faces
  // that meet at a bent seam (the seam of two planes that close is ill-conditioned), and
  // dropping the seam's two-face vertices would then cut off more than tol.
  const double mergeTol = static_cast<double>(kHull3MergeFraction) * tol;
  const std::vector<Face>& tri = qh.faces();
  std::vector<int> group(tri.size(), -1);
  struct Poly {
    std::vector<int> loop;
  };
  std::vector<Poly> polys;
  // Seeds in order of decreasing area: a large triangle's plane is well defined, while a
  // sliver's (three nearly collinear points) can tilt by anything within the tolerance, so
  // slivers join the plane of a large neighbour rather than seed a face of their own.
  std::vector<std::size_t> seeds;
  std::vector<double> area(tri.size(), 0.0);
  for (std::size_t t = 0; t < tri.size(); ++t) {
    if (!tri[t].alive) continue;
    seeds.push_back(t);
    const Face& f = tri[t];
    area[t] = detail::length(detail::cross(P(f.v[1]) - P(f.v[0]), P(f.v[2]) - P(f.v[0])));
  }
  std::stable_sort(seeds.begin(), seeds.end(),
                   [&](std::size_t a, std::size_t b) { return area[a] > area[b]; });
  for (std::size_t t : seeds) {
    if (group[t] >= 0) continue;
    int g = static_cast<int>(polys.size());
    const Face& seed = tri[t];
    std::vector<int> members{static_cast<int>(t)};
    group[t] = g;
    for (std::size_t k = 0; k < members.size(); ++k) {
      const Face& f = tri[static_cast<std::size_t>(members[k])];
      for (int e = 0; e < 3; ++e) {
        int h = qh.neighbourOf(f.v[e], f.v[(e + 1) % 3]);
        if (h < 0 || group[static_cast<std::size_t>(h)] >= 0) continue;
        const Face& fh = tri[static_cast<std::size_t>(h)];
        // A triangle facing the other way joins only if it is a sliver (height within the
        // tolerance, so its normal means nothing): thick planes can leave such a fold.
        D3 e0 = P(fh.v[1]) - P(fh.v[0]), e1 = P(fh.v[2]) - P(fh.v[1]), e2 = P(fh.v[0]) - P(fh.v[2]);
        double longest =
            std::max(detail::length(e0), std::max(detail::length(e1), detail::length(e2)));
        bool sliver = detail::length(detail::cross(e0, e1)) <= tol * longest;
        bool coplanar = sliver || detail::dot(fh.n, seed.n) > 0;
        for (int q = 0; q < 3 && coplanar; ++q)
          coplanar = std::fabs(detail::dot(seed.n, P(fh.v[q])) - seed.d) <= mergeTol;
        if (!coplanar) continue;
        group[static_cast<std::size_t>(h)] = g;
        members.push_back(h);
      }
    }
    // Boundary loop: directed edges whose reverse belongs to another group.
    std::unordered_map<int, int> next;
    for (int m : members) {
      const Face& f = tri[static_cast<std::size_t>(m)];
      for (int e = 0; e < 3; ++e) {
        int a = f.v[e], b = f.v[(e + 1) % 3];
        int h = qh.neighbourOf(a, b);
        if (h >= 0 && group[static_cast<std::size_t>(h)] == g) continue;
        if (next.count(a)) return fail("quickhull: a face boundary touches itself (internal)");
        next[a] = b;
      }
    }
    // The loop starts at its lowest vertex index: the map's own order is the standard
    // library's (libstdc++ and libc++ differ), and a start taken from it gave the WebAssembly
    // build other face loops, clip orders and manifolds than x86 and aarch64.
    Poly poly;
    int startV = next.begin()->first;
    for (const auto& [from, to] : next)
      startV = std::min(startV, from);
    int v = startV;
    do {
      poly.loop.push_back(v);
      v = next[v];
    } while (v != startV && poly.loop.size() <= next.size());
    if (poly.loop.size() != next.size())
      return fail("quickhull: a face boundary has more than one loop (internal)");
    polys.push_back(std::move(poly));
  }

  // Vertices on fewer than three faces lie on an edge (collinear points): drop them.
  std::unordered_map<int, int> degree;
  for (const Poly& f : polys)
    for (int v : f.loop)
      ++degree[v];
  for (Poly& f : polys) {
    std::erase_if(f.loop, [&](int v) { return degree[v] < 3; });
    if (f.loop.size() < 3) return fail("quickhull: a face lost its area (internal)");
  }
  std::vector<int> used;
  for (auto [v, d] : degree)
    if (d >= 3) used.push_back(v);
  std::sort(used.begin(), used.end());
  if (used.size() > static_cast<std::size_t>(kMaxHullVertices3)) {
    return fail("the hull has " + std::to_string(used.size()) + " vertices, more than " +
                std::to_string(kMaxHullVertices3));
  }
  std::unordered_map<int, int> index;
  Hull3& hull = build->hull;
  for (std::size_t k = 0; k < used.size(); ++k) {
    index[used[k]] = static_cast<int>(k);
    hull.vertices[k] = points[static_cast<std::size_t>(used[k])];
  }
  hull.vertexCount = static_cast<int>(used.size());
  if (polys.size() > static_cast<std::size_t>(kMaxHullFaces3))
    return fail("quickhull: too many faces (internal)");

  // Faces: Newell's normal of the loop (robust for polygons), offset through the furthest
  // vertex so every vertex is on or inside the plane.
  std::unordered_map<std::uint64_t, int> edgeOf;
  int fv = 0;
  for (std::size_t fi = 0; fi < polys.size(); ++fi) {
    const std::vector<int>& loop = polys[fi].loop;
    D3 nn{};
    for (std::size_t k = 0; k < loop.size(); ++k) {
      D3 a = P(loop[k]), b = P(loop[(k + 1) % loop.size()]);
      nn = nn + D3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    }
    nn = (1.0 / detail::length(nn)) * nn;
    double off = -std::numeric_limits<double>::infinity();
    for (int v : loop)
      off = std::max(off, detail::dot(nn, P(v)));
    HullFace3& face = hull.faces[fi];
    face.normal = {static_cast<float>(nn.x), static_cast<float>(nn.y), static_cast<float>(nn.z)};
    face.offset = static_cast<float>(off);
    face.first = static_cast<std::uint16_t>(fv);
    face.count = static_cast<std::uint8_t>(loop.size());
    for (std::size_t k = 0; k < loop.size(); ++k) {
      int a = index[loop[k]], b = index[loop[(k + 1) % loop.size()]];
      hull.faceVertices[fv++] = static_cast<std::uint8_t>(a);
      if (a < b) {
        int e = hull.edgeCount++;
        if (e >= kMaxHullEdges3) return fail("quickhull: too many edges (internal)");
        hull.edges[e] = {static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b),
                         static_cast<std::uint8_t>(fi), 0};
        edgeOf[edgeKey(a, b)] = e;
      }
    }
  }
  hull.faceCount = static_cast<int>(polys.size());
  for (int fi = 0; fi < hull.faceCount; ++fi) {
    const HullFace3& face = hull.faces[fi];
    for (int k = 0; k < face.count; ++k) {
      int a = hull.faceVertices[face.first + k];
      int b = hull.faceVertices[face.first + (k + 1) % face.count];
      if (a > b) {
        auto it = edgeOf.find(edgeKey(b, a));
        if (it == edgeOf.end()) return fail("quickhull: an edge has one face (internal)");
        hull.edges[it->second].faceRight = static_cast<std::uint8_t>(fi);
      }
    }
  }

  // Centroid: tetrahedra from a vertex to each face's fan, in double.
  D3 ref = P(used[0]);
  double vol6 = 0;
  D3 c{};
  for (const Poly& f : polys) {
    for (std::size_t k = 1; k + 1 < f.loop.size(); ++k) {
      D3 a = P(f.loop[0]) - ref, b = P(f.loop[k]) - ref, d = P(f.loop[k + 1]) - ref;
      double v6 = detail::dot(a, detail::cross(b, d));
      vol6 += v6;
      c = c + v6 * (a + b + d);
    }
  }
  c = ref + (1.0 / (4.0 * vol6)) * c;
  hull.centroid = {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};

  // The report: every kept input point that is not a vertex is inside or on the boundary.
  report.vertices = hull.vertexCount;
  for (int i : kept) {
    if (index.count(i)) continue;
    double h = -std::numeric_limits<double>::infinity();
    for (int fi = 0; fi < hull.faceCount; ++fi) {
      const HullFace3& face = hull.faces[fi];
      h = std::max(h, detail::dot(toDouble(face.normal), P(i)) - static_cast<double>(face.offset));
    }
    if (h > 2.0 * tol) {
      return fail("quickhull: points[" + std::to_string(i) + "] is outside the hull (internal)");
    }
    if (h < -tol)
      ++report.inside;
    else
      ++report.onBoundary;
  }
  if (Status s = validateHull3(hull); !s) return fail("quickhull: " + s.message() + " (internal)");
  return std::move(*build);
}

namespace {
// Signed distance of v from the face's plane, in double: far from the origin the float
// dot product alone rounds by more than the tolerances checked here.
double planeDistance(const HullFace3& face, Vec3 v) {
  return detail::dot(toDouble(face.normal), toDouble(v)) - static_cast<double>(face.offset);
}
}  // namespace

Status validateHull3(const Hull3& hull) {
  const int nv = hull.vertexCount, nf = hull.faceCount, ne = hull.edgeCount;
  if (nv < 4 || nv > kMaxHullVertices3)
    return fail("hull vertexCount " + std::to_string(nv) + " is outside [4, 64]");
  if (nf < 4 || nf > kMaxHullFaces3 || ne < 6 || ne > kMaxHullEdges3)
    return fail("hull face or edge count out of range");
  if (nv - ne + nf != 2) {
    return fail("hull V - E + F = " + std::to_string(nv - ne + nf) + ", not 2 (V " +
                std::to_string(nv) + ", E " + std::to_string(ne) + ", F " + std::to_string(nf) +
                ")");
  }
  if (!std::isfinite(hull.radius) || !(hull.radius >= 0.0f) || hull.radius > kMaxCoordinate) {
    return fail("hull.radius " + formatNumber(hull.radius) +
                " must be finite, >= 0 and at most the coordinate limit 1e9 m");
  }
  Vec3 lower = hull.vertices[0], upper = hull.vertices[0];
  for (int i = 0; i < nv; ++i) {
    if (!isFinite(hull.vertices[i]))
      return fail("hull.vertices[" + std::to_string(i) + "] is not finite");
    lower = minv(lower, hull.vertices[i]);
    upper = maxv(upper, hull.vertices[i]);
  }
  // Stored normals and offsets are rounded to float: allow a few times the tolerance.
  const float tol = 4.0f * hull3Tolerance(lower, upper);
  int loopTotal = 0;
  for (int f = 0; f < nf; ++f) {
    const HullFace3& face = hull.faces[f];
    std::string name = "hull.faces[" + std::to_string(f) + "]";
    if (face.count < 3) return fail(name + " has fewer than 3 vertices");
    if (face.first != loopTotal) return fail(name + " loop is not contiguous");
    loopTotal += face.count;
    if (loopTotal > 2 * kMaxHullEdges3) return fail(name + " loop overflows");
    if (!isFinite(face.normal) || absf(length(face.normal) - 1.0f) > 1e-5f)
      return fail(name + " normal is not unit");
    for (int k = 0; k < face.count; ++k) {
      int ia = hull.faceVertices[face.first + k];
      if (ia >= nv) return fail(name + " has a vertex index out of range");
      Vec3 a = hull.vertices[ia];
      if (std::fabs(planeDistance(face, a)) > static_cast<double>(tol))
        return fail(name + " is not planar: vertex " + std::to_string(ia) + " is off its plane");
      Vec3 b = hull.vertices[hull.faceVertices[face.first + (k + 1) % face.count]];
      Vec3 c = hull.vertices[hull.faceVertices[face.first + (k + 2) % face.count]];
      if (detail::dot(detail::cross(toDouble(b) - toDouble(a), toDouble(c) - toDouble(b)),
                      toDouble(face.normal)) <
          -static_cast<double>(tol) * detail::length(toDouble(c) - toDouble(b)))
        return fail(name + " is not convex (counter-clockwise seen from outside)");
    }
    for (int i = 0; i < nv; ++i) {
      if (planeDistance(face, hull.vertices[i]) > static_cast<double>(tol))
        return fail("hull vertex " + std::to_string(i) + " is outside " + name);
    }
  }
  if (loopTotal != 2 * ne) return fail("hull face loops do not use every edge twice");
  for (int e = 0; e < ne; ++e) {
    const HullEdge3& edge = hull.edges[e];
    std::string name = "hull.edges[" + std::to_string(e) + "]";
    if (edge.v0 >= nv || edge.v1 >= nv || edge.faceLeft >= nf || edge.faceRight >= nf)
      return fail(name + " has an index out of range");
    auto hasDirected = [&](int f, int a, int b) {
      const HullFace3& face = hull.faces[f];
      for (int k = 0; k < face.count; ++k) {
        if (hull.faceVertices[face.first + k] == a &&
            hull.faceVertices[face.first + (k + 1) % face.count] == b)
          return true;
      }
      return false;
    };
    if (!hasDirected(edge.faceLeft, edge.v0, edge.v1) ||
        !hasDirected(edge.faceRight, edge.v1, edge.v0))
      return fail(name + " does not match its faces' loops");
    // Two faces much closer to one plane than the merge tolerance would have been merged.
    const HullFace3& left = hull.faces[edge.faceLeft];
    const HullFace3& right = hull.faces[edge.faceRight];
    bool onePlane = dot(left.normal, right.normal) > 0.0f;
    for (int k = 0; k < right.count && onePlane; ++k) {
      Vec3 v = hull.vertices[hull.faceVertices[right.first + k]];
      onePlane = std::fabs(planeDistance(left, v)) <=
                 0.125 * static_cast<double>(kHull3MergeFraction * tol);
    }
    if (onePlane) return fail(name + " joins two faces of one plane");
  }
  return {};
}

}  // namespace quack
