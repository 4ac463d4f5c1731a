// Ghost-collision removal on static geometry, and chains.
//
// A body sliding over a floor of separate tiles meets, at every seam, the side face and the
// corner of the next tile: its manifold with that tile may take the side face (or the
// corner's diagonal) as the normal, and the body catches or hops. The union of the tiles
// has no such face. So, when static geometry changes, we find the edges of static polygons
// that lie flush against an opposite edge of another static polygon (internal edges), and
// at each vertex touching an internal edge the faces of the union that really meet there;
// in the narrow phase, a contact point on an internal edge is dropped and a normal at such
// a vertex is turned into the cone of those faces, its separation measured again along
// the new normal. Chains use their neighbouring points (ghost vertices) the same way, and
// are one-sided. The idea is that of Bullet's btAdjustInternalEdgeContacts and Jolt's
// InternalEdgeRemovingCollector (read for understanding; this is our own formulation).
// docs/concave.md has the method, its limits and the measured figures.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "ghost_edges.hpp"

#include "body_store.hpp"
#include "contact_set.hpp"
#include "quack/world/world.hpp"
#include "radix_sort.hpp"
#include "world_state.hpp"

namespace quack::detail {
namespace {

// Normals closer than this (sine of the angle between them) count as parallel: a flat
// joint between two flush faces. About 0.006 degrees: float noise of a normalised edge,
// far below a slope a body should feel.
constexpr float kFlatJointSine = 1e-4f;

Vec2 clampToCone(Vec2 n, Vec2 lo, Vec2 hi) {
  if (absf(cross(lo, hi)) <= kFlatJointSine && dot(lo, hi) > 0.0f) return lo;
  // The cones are convex corners of polygons or chains: narrower than a half turn.
  if (cross(lo, n) >= 0.0f && cross(n, hi) >= 0.0f) return n;
  return dot(n, lo) >= dot(n, hi) ? lo : hi;
}

// The cone of normals at a vertex where the union's boundary arrives along the edge with
// normal nIn (direction dIn) and leaves along nOut (dOut); world frame.
EdgeCone coneBetween(Vec2 dIn, Vec2 nIn, Vec2 dOut, Vec2 nOut) {
  EdgeCone c;
  float turn = cross(dIn, dOut);
  if (absf(turn) <= kFlatJointSine && dot(dIn, dOut) > 0.0f) {
    c.kind = EdgeCone::Kind::range;
    c.lo = c.hi = normalize(nIn + nOut);
  } else if (turn > 0.0f) {
    c.kind = EdgeCone::Kind::range;
    c.lo = nIn;
    c.hi = nOut;
  } else {
    c.kind = EdgeCone::Kind::snap;
    c.lo = nIn;
    c.hi = nOut;
  }
  return c;
}

// Cells of side 4 tolerances: two points within the tolerance are in the same or
// neighbouring cells.
using Cell = std::pair<long long, long long>;
// A cell index along one axis, clamped so that a body parked at 1e30 m cannot overflow the
// integer (the world keeps shapes within kMaxCoordinate, so this is belt and braces).
long long cellIndexOf(float x, float size) {
  // floor(x / size) clamped to +-1e15: clamped first (the bounds are integers and floor is
  // monotonic, so the same integer), then floored by truncation and one correction, which is
  // exact below 2^53 and a fraction of std::floor's instructions without SSE4.1.
  const double c = std::clamp(static_cast<double>(x) / static_cast<double>(size), -1e15, 1e15);
  const auto t = static_cast<long long>(c);
  return t - static_cast<long long>(c < static_cast<double>(t));
}

Cell cellOf(Vec2 p) {
  const float size = 4.0f * kFlushEdgeTolerance;
  return {cellIndexOf(p.x, size), cellIndexOf(p.y, size)};
}

// An edge entered in a cell. Sorted by cell, then edge, a list of these is the grid: a
// cell's edges are a run, in the order a std::map of vectors filled edge by edge iterates
// them, so the covered intervals and the stored spans are the same bits as with the map it
// replaced (a node and a vector per cell: 56 M instructions for 2,505 floor tiles, now 26 M).
struct CellOrder {
  bool operator()(const CellEntry& a, const CellEntry& b) const noexcept {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.edge < b.edge;
  }
};

// Edges grouped by cell, each cell's edges in the order they were added, found through an
// open-addressing hash (a binary search per lookup was most of the update's time; filled by
// counting, so nothing is sorted).
class CellRuns {
 public:
  explicit CellRuns(const std::vector<CellEntry>& entries) {
    std::size_t size = 16;
    while (size < 2 * entries.size())
      size *= 2;
    slots_.assign(size, Slot{});
    std::vector<std::uint32_t> slotOfEntry(entries.size());
    for (std::size_t k = 0; k < entries.size(); ++k) {
      std::size_t i = find(entries[k].x, entries[k].y);
      Slot& slot = slots_[i];
      if (slot.count == 0) {
        slot.x = entries[k].x;
        slot.y = entries[k].y;
      }
      ++slot.count;
      slotOfEntry[k] = static_cast<std::uint32_t>(i);
    }
    std::uint32_t at = 0;
    for (Slot& slot : slots_) {
      slot.begin = at;
      at += slot.count;
    }
    // Each slot's begin serves as its filling cursor, and is moved back after.
    edges_.resize(entries.size());
    for (std::size_t k = 0; k < entries.size(); ++k)
      edges_[slots_[slotOfEntry[k]].begin++] = static_cast<std::uint32_t>(entries[k].edge);
    for (Slot& slot : slots_)
      slot.begin -= slot.count;
  }
  // f(edge) for the edges entered in cell (x, y), in the order they were added.
  template <class F>
  void forEach(long long x, long long y, F&& f) const {
    const Slot& slot = slots_[find(x, y)];
    for (std::size_t k = slot.begin; k < slot.begin + slot.count; ++k)
      f(edges_[k]);
  }

 private:
  struct Slot {
    long long x = 0, y = 0;
    std::uint32_t begin = 0, count = 0;  // count 0: an empty slot
  };
  // The slot of cell (x, y), or the empty slot where it would go.
  std::size_t find(long long x, long long y) const noexcept {
    const auto h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^
                   static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full;
    const std::size_t mask = slots_.size() - 1;
    std::size_t i = static_cast<std::size_t>(h >> 20) & mask;
    while (slots_[i].count != 0 && (slots_[i].x != x || slots_[i].y != y))
      i = (i + 1) & mask;
    return i;
  }
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> edges_;
};

bool near(Vec2 a, Vec2 b) {
  return distanceSquared(a, b) <= kFlushEdgeTolerance * kFlushEdgeTolerance;
}

}  // namespace

void GhostEdges::update(BodyStore& store, bool removeGhostCollisions) {
  dirty_ = false;
  activeShapes_ = 0;
  struct WorldEdge {
    std::uint32_t shape;
    int edge;
    Vec2 a, b, n;
    Vec2 d;     // normalize(b - a), computed once: the pair tests below use it many times
    float len;  // length(b - a)
  };
  std::vector<WorldEdge> edges;
  for (std::uint32_t s = 0; s < store.shapes.size(); ++s) {
    Shape& shape = store.shapes[s];
    if (!store.shapeAlive(s) || store.bodies[shape.body].type != BodyType::staticBody) continue;
    // A sensor blocks nothing, so its edges make no other edge internal: a sensor zone
    // standing on the ground must not open a hole in the ground.
    if (shape.def.sensor) continue;
    StaticEdges& e = shape.edges;
    if (e.chain) {
      // Ghost vertices: the cone at each joint is that of the two segments meeting there.
      const Segment& seg = std::get<Segment>(*shape.geometry);
      Vec2 d = normalize(seg.p2 - seg.p1);
      Vec2 n = rightPerp(d);
      e.cones.assign(2, EdgeCone{});
      if (e.hasPrev) {
        Vec2 dp = normalize(seg.p1 - e.prev);
        e.cones[0] = coneBetween(dp, rightPerp(dp), d, n);
        // At a valley the other segment answers for its own face: keep this one's.
        if (e.cones[0].kind == EdgeCone::Kind::snap) e.cones[0].lo = e.cones[0].hi = n;
      }
      if (e.hasNext) {
        Vec2 dn = normalize(e.next - seg.p2);
        e.cones[1] = coneBetween(d, n, dn, rightPerp(dn));
        if (e.cones[1].kind == EdgeCone::Kind::snap) e.cones[1].lo = e.cones[1].hi = n;
      }
      e.active = true;
      ++activeShapes_;
      continue;
    }
    e = StaticEdges{};
    if (!removeGhostCollisions) continue;
    const Polygon* p = std::get_if<Polygon>(shape.geometry.get());
    if (p == nullptr) continue;
    const Transform xf = store.bodies[shape.body].xf;
    for (int i = 0; i < p->count; ++i) {
      const Vec2 a = transformPoint(xf, p->vertices[i]);
      const Vec2 b = transformPoint(xf, p->vertices[(i + 1) % p->count]);
      edges.push_back({s, i, a, b, rotate(xf.q, p->normals[i]), normalize(b - a), length(b - a)});
    }
  }
  if (edges.empty()) return;

  // Coverage: the parts of each edge that lie against an opposite, collinear edge of another
  // static shape, as intervals of the edge's length. Candidate pairs come from a grid of
  // cells about one mean edge long, each edge entered in the cells its box touches.
  float meanLength = 0.0f;
  for (const WorldEdge& w : edges)
    meanLength += w.len;
  meanLength /= static_cast<float>(edges.size());
  const float cellSize = maxf(meanLength, 16.0f * kFlushEdgeTolerance);
  auto cellIndex = [&](float x) { return cellIndexOf(x, cellSize); };
  std::vector<CellEntry> grid;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    Vec2 lo = minv(edges[k].a, edges[k].b), hi = maxv(edges[k].a, edges[k].b);
    long long x0 = cellIndex(lo.x - kFlushEdgeTolerance),
              x1 = cellIndex(hi.x + kFlushEdgeTolerance);
    long long y0 = cellIndex(lo.y - kFlushEdgeTolerance),
              y1 = cellIndex(hi.y + kFlushEdgeTolerance);
    // An edge spanning more cells than this (a long ground under many small tiles) is
    // entered once per cell anyway, but never more than kMaxEdgeCells: beyond that it is
    // left out of the search (its seams keep their ghosts; documented in docs/concave.md).
    constexpr long long kMaxEdgeCells = 4096;
    if (x1 - x0 >= kMaxEdgeCells || y1 - y0 >= kMaxEdgeCells ||
        (x1 - x0 + 1) * (y1 - y0 + 1) > kMaxEdgeCells) {
      continue;
    }
    for (long long x = x0; x <= x1; ++x)
      for (long long y = y0; y <= y1; ++y)
        grid.push_back({x, y, k});
  }
  std::vector<CellEntry> gridScratch;
  sortCellEntries(grid, gridScratch);
  // Each edge's covered intervals as a list in one pool (first added first), not a vector
  // per edge: most edges have none or one, and ten thousand small vectors were a third of
  // the update's instructions in allocation.
  struct Interval {
    float t0, t1;        // metres along the edge from its start
    std::uint32_t next;  // the edge's next interval in `pool`, or kNone
  };
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<Interval> pool;
  std::vector<std::uint32_t> firstCover(edges.size(), kNone), lastCover(edges.size(), kNone);
  auto forCovers = [&](std::size_t k, auto&& f) {
    for (std::uint32_t i = firstCover[k]; i != kNone; i = pool[i].next)
      if (f(pool[i])) return true;
    return false;
  };
  auto addCover = [&](std::size_t k, float t0, float t1) {
    const float len = edges[k].len;
    t0 = maxf(t0, 0.0f);
    t1 = minf(t1, len);
    if (t1 - t0 <= kFlushEdgeTolerance) return;
    const bool merged = forCovers(k, [&](Interval& i) {
      if (t0 <= i.t1 + kFlushEdgeTolerance && i.t0 <= t1 + kFlushEdgeTolerance) {
        i.t0 = minf(i.t0, t0);
        i.t1 = maxf(i.t1, t1);
        return true;
      }
      return false;
    });
    if (merged) return;
    const auto at = static_cast<std::uint32_t>(pool.size());
    pool.push_back({t0, t1, kNone});
    if (firstCover[k] == kNone) {
      firstCover[k] = at;
    } else {
      pool[lastCover[k]].next = at;
    }
    lastCover[k] = at;
  };
  auto lineDistance = [&](std::size_t k, Vec2 p) {
    return absf(cross(edges[k].d, p - edges[k].a));
  };
  // A pair that shares several cells is covered once per cell; the intervals merge.
  for (std::size_t first = 0, last = 0; first < grid.size(); first = last) {
    last = first + 1;
    while (last < grid.size() && grid[last].x == grid[first].x && grid[last].y == grid[first].y)
      ++last;
    for (std::size_t x = first; x < last; ++x) {
      for (std::size_t y = x + 1; y < last; ++y) {
        std::size_t k = grid[x].edge, j = grid[y].edge;
        if (edges[k].shape == edges[j].shape) continue;
        const Vec2 dk = edges[k].d, dj = edges[j].d;
        if (dot(dk, dj) >= 0.0f || absf(cross(dk, dj)) > kFlatJointSine) continue;
        if (lineDistance(k, edges[j].a) > kFlushEdgeTolerance ||
            lineDistance(k, edges[j].b) > kFlushEdgeTolerance) {
          continue;
        }
        float ja = dot(edges[j].a - edges[k].a, dk), jb = dot(edges[j].b - edges[k].a, dk);
        addCover(k, minf(ja, jb), maxf(ja, jb));
        float ka = dot(edges[k].a - edges[j].a, dj), kb = dot(edges[k].b - edges[j].a, dj);
        addCover(j, minf(ka, kb), maxf(ka, kb));
      }
    }
  }
  auto coveredAt = [&](std::size_t k, float t) {
    return forCovers(k, [&](const Interval& i) {
      return t >= i.t0 - kFlushEdgeTolerance && t <= i.t1 + kFlushEdgeTolerance;
    });
  };

  std::vector<CellEntry> startList, endList;
  startList.reserve(edges.size());
  endList.reserve(edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const Cell a = cellOf(edges[k].a), b = cellOf(edges[k].b);
    startList.push_back({a.first, a.second, k});
    endList.push_back({b.first, b.second, k});
  }
  const CellRuns starts(startList), ends(endList);
  auto around = [](const CellRuns& cells, Vec2 p, auto&& f) {
    // The cells a point near p (within the tolerance, with room for the rounding of
    // near()'s squared distance) can be in: one or two along each axis, as the cells are
    // four tolerances wide. Those points are all a caller keeps; its counts and its last
    // match do not depend on which other edges it is shown.
    const float reach = 1.01f * kFlushEdgeTolerance;
    const Cell lo = cellOf(p - Vec2{reach, reach}), hi = cellOf(p + Vec2{reach, reach});
    for (long long cx = lo.first; cx <= hi.first; ++cx) {
      for (long long cy = lo.second; cy <= hi.second; ++cy) {
        cells.forEach(cx, cy, f);
      }
    }
  };
  // Shapes with covered edges get the covered intervals (shape frame: the same lengths) and,
  // at each vertex an edge is covered up to, the faces of the union that meet there.
  for (std::size_t k = 0; k < edges.size(); ++k) {
    if (firstCover[k] == kNone) continue;
    Shape& shape = store.shapes[edges[k].shape];
    StaticEdges& e = shape.edges;
    const Polygon& p = std::get<Polygon>(*shape.geometry);
    if (!e.active) {
      e.active = true;
      e.cones.assign(static_cast<std::size_t>(p.count), EdgeCone{});
      ++activeShapes_;
    }
    forCovers(k, [&](const Interval& i) {
      e.covered.push_back({edges[k].edge, i.t0, i.t1});
      return false;
    });
    const Rot q = store.bodies[shape.body].xf.q;
    const float len = edges[k].len;
    // Edge i joins vertices i and i + 1.
    for (int end = 0; end < 2; ++end) {
      if (!coveredAt(k, end == 0 ? 0.0f : len)) continue;
      int v = (edges[k].edge + end) % p.count;
      Vec2 at = end == 0 ? edges[k].a : edges[k].b;
      int inCount = 0, outCount = 0;
      std::size_t in = 0, out = 0;
      around(ends, at, [&](std::size_t j) {
        if (near(edges[j].b, at) && !coveredAt(j, edges[j].len)) {
          ++inCount;
          in = j;
        }
      });
      around(starts, at, [&](std::size_t j) {
        if (near(edges[j].a, at) && !coveredAt(j, 0.0f)) {
          ++outCount;
          out = j;
        }
      });
      EdgeCone cone;
      if (inCount == 1 && outCount == 1) {
        const Vec2 dIn = edges[in].d;
        const Vec2 dOut = edges[out].d;
        cone = coneBetween(dIn, edges[in].n, dOut, edges[out].n);
        cone.lo = invRotate(q, cone.lo);
        cone.hi = invRotate(q, cone.hi);
      } else if (inCount == 0 && outCount == 0) {
        cone.kind = EdgeCone::Kind::inside;
      }
      // Otherwise several faces meet here (a chequerboard corner), or the union's boundary
      // passes through the middle of another shape's edge: leave the vertex alone.
      e.cones[static_cast<std::size_t>(v)] = cone;
    }
  }
}

namespace {

enum class Verdict { keep, drop, correct };

// What a contact on static shape `S` at `local` (on its surface, shape frame) with the
// normal `localN` (out of S, shape frame) is: genuine (keep), on a covered part of an edge
// or at a vertex inside the union (drop), or at a flush vertex or chain joint whose cone
// does not hold the normal (correct: `target` is the nearest normal in the cone).
Verdict classify(const StaticEdges& edges, const ShapeGeometry& geometry, Vec2 local, Vec2 localN,
                 Vec2& target) {
  Vec2 segmentPoints[2];
  const Vec2* vertices = nullptr;
  int count = 0;
  if (const Polygon* p = std::get_if<Polygon>(&geometry)) {
    vertices = p->vertices;
    count = p->count;
  } else if (const Segment* seg = std::get_if<Segment>(&geometry)) {
    segmentPoints[0] = seg->p1;
    segmentPoints[1] = seg->p2;
    vertices = segmentPoints;
    count = 2;
  } else {
    return Verdict::keep;
  }
  int vertex = -1;
  float best = kGhostVertexRadius * kGhostVertexRadius;
  for (int i = 0; i < count; ++i) {
    float d2 = distanceSquared(local, vertices[i]);
    if (d2 <= best) {
      best = d2;
      vertex = i;
    }
  }
  if (vertex >= 0) {
    const EdgeCone& cone = edges.cones[static_cast<std::size_t>(vertex)];
    switch (cone.kind) {
      case EdgeCone::Kind::natural:
        return Verdict::keep;
      case EdgeCone::Kind::range:
        target = clampToCone(localN, cone.lo, cone.hi);
        return Verdict::correct;
      case EdgeCone::Kind::snap:
        target = dot(localN, cone.lo) >= dot(localN, cone.hi) ? cone.lo : cone.hi;
        return Verdict::correct;
      case EdgeCone::Kind::inside:
        return Verdict::drop;
    }
  }
  const int edgeCount = edges.chain ? 1 : count;
  int edge = 0;
  float bestEdge = std::numeric_limits<float>::max();
  for (int i = 0; i < edgeCount; ++i) {
    Vec2 a = vertices[i], ab = vertices[(i + 1) % count] - a;
    float u = clampf(dot(local - a, ab) / lengthSquared(ab), 0.0f, 1.0f);
    float d2 = distanceSquared(local, a + u * ab);
    if (d2 < bestEdge) {
      bestEdge = d2;
      edge = i;
    }
  }
  Vec2 a = vertices[edge], d = normalize(vertices[(edge + 1) % count] - a);
  float along = dot(local - a, d);
  for (const CoveredSpan& span : edges.covered) {
    if (span.edge == edge && along >= span.t0 - kFlushEdgeTolerance &&
        along <= span.t1 + kFlushEdgeTolerance) {
      return Verdict::drop;
    }
  }
  if (edges.chain && dot(localN, rightPerp(d)) <= 0.0f) {
    target = rightPerp(d);
    return Verdict::correct;
  }
  return Verdict::keep;
}

}  // namespace

bool GhostEdges::isGhostImpact(const BodyStore& store, std::uint32_t staticShape, Vec2 point,
                               Vec2 normal) const {
  const Shape& S = store.shapes[staticShape];
  if (!S.edges.active || store.bodies[S.body].type != BodyType::staticBody) return false;
  const Transform xs = store.bodies[S.body].xf;
  Vec2 target;
  Vec2 localN = invRotate(xs.q, normal);
  Verdict v = classify(S.edges, *S.geometry, invTransformPoint(xs, point), localN, target);
  if (v == Verdict::drop) return true;
  // A turned normal is a ghost when it leaves the cone by more than float noise.
  return v == Verdict::correct && dot(target, localN) < 1.0f - 1e-6f;
}

void GhostEdges::removeGhostContacts(const BodyStore& store, Contact& c) const {
  Manifold& m = c.manifold;
  if (m.pointCount == 0) return;
  const bool staticIsA = store.shapes[c.shapeA].edges.active &&
                         store.bodies[store.shapes[c.shapeA].body].type == BodyType::staticBody;
  const Shape& S = store.shapes[staticIsA ? c.shapeA : c.shapeB];
  const Shape& D = store.shapes[staticIsA ? c.shapeB : c.shapeA];
  if (!S.edges.active || store.bodies[S.body].type != BodyType::staticBody) return;
  const Transform xs = store.bodies[S.body].xf;
  const Transform xd = store.bodies[D.body].xf;
  const Vec2 nOut = staticIsA ? m.normal : -m.normal;  // out of the static shape

  if (S.edges.chain) {
    // One-sided: a body whose centre is behind the segment passes through it.
    const Segment& seg = std::get<Segment>(*S.geometry);
    Vec2 center = invTransformPoint(xs, transformPoint(xd, makeProxy(*D.geometry).center()));
    if (dot(center - seg.p1, rightPerp(seg.p2 - seg.p1)) < 0.0f) {
      m.pointCount = 0;
      return;
    }
  }

  const Vec2 localN = invRotate(xs.q, nOut);
  bool haveTarget = false;
  Vec2 target;
  float targetSeparation = 0.0f;
  int kept = 0;
  for (int k = 0; k < m.pointCount; ++k) {
    const ManifoldPoint mp = m.points[k];
    Vec2 local = invTransformPoint(xs, mp.point - 0.5f * mp.separation * nOut);
    Vec2 t;
    Verdict v = classify(S.edges, *S.geometry, local, localN, t);
    if (v == Verdict::drop) continue;
    if (v == Verdict::correct && (!haveTarget || mp.separation < targetSeparation)) {
      haveTarget = true;
      target = t;
      targetSeparation = mp.separation;
    }
    m.points[kept++] = mp;
  }
  m.pointCount = kept;
  if (!haveTarget || kept == 0) return;
  const Vec2 nNew = rotate(xs.q, target);
  // Already inside the cone (to float noise): leave the routine's answer untouched.
  if (dot(nNew, nOut) >= 1.0f - 1e-6f) return;

  // Measure again along the new normal: the separation of the dynamic shape from the face
  // through the static point, using its deepest point along the normal where that is deeper
  // than the point the routine found (a circle's lowest point, not its diagonal one).
  const ShapeProxy proxy = makeProxy(*D.geometry);
  const Vec2 dir = invRotate(xd.q, -nNew);
  int deepest = 0;
  for (int i = 1; i < proxy.count(); ++i) {
    if (dot(proxy.points()[i], dir) > dot(proxy.points()[deepest], dir)) deepest = i;
  }
  const Vec2 support = transformPoint(xd, proxy.points()[deepest]) - proxy.radius() * nNew;
  const Transform xa = store.bodies[store.shapes[c.shapeA].body].xf;
  const Transform xb = store.bodies[store.shapes[c.shapeB].body].xf;
  for (int k = 0; k < m.pointCount; ++k) {
    ManifoldPoint& mp = m.points[k];
    Vec2 onStatic = mp.point - 0.5f * mp.separation * nOut;
    Vec2 onDynamic = mp.point + 0.5f * mp.separation * nOut;
    float gap = dot(onDynamic - onStatic, nNew);
    float supportGap = dot(support - onStatic, nNew);
    if (supportGap < gap) {
      onDynamic = support;
      gap = supportGap;
    }
    mp.separation = gap;
    mp.point = onDynamic - 0.5f * gap * nNew;
    mp.anchorA = mp.point - xa.p;
    mp.anchorB = mp.point - xb.p;
  }
  m.normal = staticIsA ? nNew : -nNew;
}

void sortCellEntries(std::vector<CellEntry>& entries, std::vector<CellEntry>& scratch) {
  // std::sort's comparisons were most of the search's time (rain's 10,020 floor edges).
  constexpr std::size_t kRadixFrom = 256;
  if (entries.size() < kRadixFrom) {
    std::sort(entries.begin(), entries.end(), CellOrder{});
    return;
  }
  long long minX = entries[0].x, maxX = minX, minY = entries[0].y, maxY = minY;
  for (const CellEntry& e : entries) {
    minX = std::min(minX, e.x);
    maxX = std::max(maxX, e.x);
    minY = std::min(minY, e.y);
    maxY = std::max(maxY, e.y);
  }
  // Offsets from the least cell, as unsigned (two's complement wraps them right).
  const auto spanX = static_cast<std::uint64_t>(maxX) - static_cast<std::uint64_t>(minX);
  const auto spanY = static_cast<std::uint64_t>(maxY) - static_cast<std::uint64_t>(minY);
  const int bitsX = 64 - std::countl_zero(spanX), bitsY = 64 - std::countl_zero(spanY);
  if (bitsX + bitsY > 64) {
    std::sort(entries.begin(), entries.end(), CellOrder{});
    return;
  }
  auto key = [&](const CellEntry& e) {
    const std::uint64_t x = static_cast<std::uint64_t>(e.x) - static_cast<std::uint64_t>(minX);
    const std::uint64_t y = static_cast<std::uint64_t>(e.y) - static_cast<std::uint64_t>(minY);
    return bitsY == 64 ? y : (x << bitsY) | y;
  };
  // Stable: equal cells keep the order they were added in, which is the edges'.
  radixSortByKey(entries, scratch, bitsX + bitsY, key);
}

}  // namespace quack::detail

namespace quack {

Result<std::vector<ShapeId>> World::createChain(BodyId bodyId, const ShapeDef& def,
                                                std::span<const Vec2> points, bool loop) {
  if (Status u = checkUsable("createChain"); !u) return fail(u.message());
  if (Status s = checkBody(bodyId, "createChain"); !s) return fail(s.message());
  if (state().store.bodies[bodyId.index].type != BodyType::staticBody)
    return fail("createChain: body must be static (chains are terrain)");
  const std::size_t n = points.size();
  if (n < (loop ? 3u : 2u)) {
    return fail("createChain: points: needs at least " + std::string(loop ? "3" : "2") +
                " points, got " + std::to_string(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!isFinite(points[i]))
      return fail("createChain: points[" + std::to_string(i) + "] is not finite");
  }
  if (loop) {
    // A loop must enclose area: points all on one line would make a closed chain of
    // segments folded back on themselves, whose sides face each other.
    std::size_t far = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (distanceSquared(points[0], points[i]) > distanceSquared(points[0], points[far])) far = i;
    const Vec2 axis = normalize(points[far] - points[0]);
    float offLine = 0.0f;
    for (std::size_t i = 0; i < n; ++i)
      offLine = maxf(offLine, absf(cross(axis, points[i] - points[0])));
    if (offLine <= kLinearSlop)
      return fail(
          "createChain: points: a loop's points lie on one line (within kLinearSlop, "
          "5 mm), so it encloses no area; give loop = false for an open chain");
  }
  const std::size_t segments = loop ? n : n - 1;
  for (std::size_t i = 0; i < segments; ++i) {
    if (detail::near(points[i], points[(i + 1) % n])) {
      return fail("createChain: points[" + std::to_string(i) + "] and points[" +
                  std::to_string((i + 1) % n) + "] coincide");
    }
  }
  std::vector<ShapeId> out;
  for (std::size_t i = 0; i < segments; ++i) {
    Result<Segment> seg = makeSegment(points[i], points[(i + 1) % n]);
    Result<ShapeId> id =
        seg ? createShape(bodyId, def, *seg) : Result<ShapeId>(fail(seg.error().message));
    if (!id) {
      for (ShapeId s : out)
        destroyShapeNow(*s_, s.index);
      return fail("createChain: segment " + std::to_string(i) + ": " + id.error().message);
    }
    detail::StaticEdges& e = state().store.shapes[id->index].edges;
    e.chain = true;
    e.hasPrev = loop || i > 0;
    e.hasNext = loop || i + 1 < segments;
    e.prev = points[(i + n - 1) % n];
    e.next = points[(i + 2) % n];
    out.push_back(*id);
  }
  state().edges.markDirty();
  return out;
}

}  // namespace quack
