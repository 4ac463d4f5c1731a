#include "quack/geometry/decompose.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "quack/core/assert.hpp"
#include "quack/geometry/hull.hpp"

namespace quack {
namespace {

struct DVec {
  double x = 0.0, y = 0.0;
};
DVec operator-(DVec a, DVec b) {
  return {a.x - b.x, a.y - b.y};
}
double crossD(DVec a, DVec b) {
  return a.x * b.y - a.y * b.x;
}
double dotD(DVec a, DVec b) {
  return a.x * b.x + a.y * b.y;
}
double lengthD(DVec a) {
  return std::sqrt(dotD(a, a));
}
bool sameD(DVec a, DVec b) {
  return a.x == b.x && a.y == b.y;
}
// Twice the signed area of triangle abc; > 0 counter-clockwise.
double orient(DVec a, DVec b, DVec c) {
  return crossD(b - a, c - a);
}

// A ring of the input: points and, for each, its index in the input (for messages).
struct Ring {
  std::vector<DVec> p;
  std::vector<int> source;
};

double signedArea(const Ring& r) {
  double a = 0.0;
  for (std::size_t i = 0, n = r.p.size(); i < n; ++i)
    a += crossD(r.p[i], r.p[(i + 1) % n]);
  return 0.5 * a;
}

void reverseRing(Ring& r) {
  std::reverse(r.p.begin(), r.p.end());
  std::reverse(r.source.begin(), r.source.end());
}

// Drops duplicates, collinear vertices and zero-width spikes until nothing changes. A vertex
// b between a and c goes when it is within `tol` of a, or when the triangle abc is lower
// than `tol` over its longest side (b on the line ac: a collinear run; c on the line ab:
// a spike folding back). Each pass removes a vertex or ends the loop, so at most n passes.
void cleanRing(Ring& r, double tol) {
  bool changed = true;
  while (changed && r.p.size() >= 3) {
    changed = false;
    for (std::size_t i = 0; i < r.p.size() && r.p.size() >= 3;) {
      std::size_t n = r.p.size();
      DVec a = r.p[(i + n - 1) % n], b = r.p[i], c = r.p[(i + 1) % n];
      double longest = std::max({lengthD(b - a), lengthD(c - b), lengthD(c - a)});
      bool drop = lengthD(b - a) <= tol || std::fabs(orient(a, b, c)) <= tol * longest;
      if (drop) {
        r.p.erase(r.p.begin() + static_cast<std::ptrdiff_t>(i));
        r.source.erase(r.source.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
      } else {
        ++i;
      }
    }
  }
}

double pointSegmentDistance(DVec p, DVec a, DVec b) {
  DVec ab = b - a;
  double l2 = dotD(ab, ab);
  double t = l2 > 0.0 ? std::clamp(dotD(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  DVec q{a.x + t * ab.x, a.y + t * ab.y};
  return lengthD(p - q);
}

bool properCross(DVec a, DVec b, DVec c, DVec d) {
  double o1 = orient(a, b, c), o2 = orient(a, b, d);
  double o3 = orient(c, d, a), o4 = orient(c, d, b);
  return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

// Closed segments ab and cd share a point (exact predicates on doubles).
bool segmentsMeet(DVec a, DVec b, DVec c, DVec d) {
  double o1 = orient(a, b, c), o2 = orient(a, b, d);
  double o3 = orient(c, d, a), o4 = orient(c, d, b);
  auto onSegment = [](DVec p, DVec q, DVec r) {  // r on pq, given collinear
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  if (o1 == 0 && onSegment(a, b, c)) return true;
  if (o2 == 0 && onSegment(a, b, d)) return true;
  if (o3 == 0 && onSegment(c, d, a)) return true;
  if (o4 == 0 && onSegment(c, d, b)) return true;
  return false;
}

// Crossing-number test; the point is known not to be on the boundary.
bool insideRing(DVec p, const Ring& r) {
  bool in = false;
  for (std::size_t i = 0, n = r.p.size(); i < n; ++i) {
    DVec a = r.p[i], b = r.p[(i + 1) % n];
    if ((a.y > p.y) != (b.y > p.y)) {
      double x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
      if (p.x < x) in = !in;
    }
  }
  return in;
}

std::string edgeName(int ring, int source) {
  if (ring == 0) return "edge " + std::to_string(source);
  return "holes[" + std::to_string(ring - 1) + "] edge " + std::to_string(source);
}

std::string ringName(int ring) {
  return ring == 0 ? std::string("outline") : "holes[" + std::to_string(ring - 1) + "]";
}

// The direction d leaves vertex p into the solid, whose boundary arrives from a and
// leaves to c with the solid on the left (strictly inside the interior angle).
bool inCone(DVec a, DVec p, DVec c, DVec d) {
  DVec in = a - p, out = c - p;
  if (orient(a, p, c) >= 0.0) return crossD(out, d) > 0.0 && crossD(d, in) > 0.0;
  return !(crossD(in, d) >= 0.0 && crossD(d, out) >= 0.0);
}

struct Node {
  DVec p;
  int id = 0;  // the same for a point and its copies made by bridging
};

}  // namespace

Result<ConvexDecomposition> decomposePolygon(std::span<const Vec2> outline,
                                             std::span<const std::vector<Vec2>> holes) {
  // ---- input checks ------------------------------------------------------------------------
  std::size_t total = outline.size();
  for (const auto& h : holes)
    total += h.size();
  if (total > static_cast<std::size_t>(kMaxConcaveVertices)) {
    return fail("decomposePolygon: too many points (" + std::to_string(total) + " > " +
                std::to_string(kMaxConcaveVertices) + ")");
  }
  std::vector<Ring> rings(1 + holes.size());
  Vec2 lower{outline.empty() ? 0.0f : outline[0].x, outline.empty() ? 0.0f : outline[0].y};
  Vec2 upper = lower;
  for (std::size_t r = 0; r < rings.size(); ++r) {
    std::span<const Vec2> pts = r == 0 ? outline : std::span<const Vec2>(holes[r - 1]);
    if (pts.size() < 3) {
      return fail("decomposePolygon: " + ringName(static_cast<int>(r)) +
                  " needs at least 3 points, got " + std::to_string(pts.size()));
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (!isFinite(pts[i])) {
        return fail("decomposePolygon: " + ringName(static_cast<int>(r)) + "[" + std::to_string(i) +
                    "] is not finite");
      }
      if (!withinCoordinateLimit(pts[i])) {
        return fail("decomposePolygon: " + ringName(static_cast<int>(r)) + "[" + std::to_string(i) +
                    "] is beyond the coordinate limit 1e9 m");
      }
      lower = minv(lower, pts[i]);
      upper = maxv(upper, pts[i]);
      rings[r].p.push_back({static_cast<double>(pts[i].x), static_cast<double>(pts[i].y)});
      rings[r].source.push_back(static_cast<int>(i));
    }
  }
  // The hull tolerance of the whole point set: what counts as a duplicate, a collinear
  // vertex or two edges touching (docs/geometry.md explains the value).
  const double tol = static_cast<double>(hullTolerance(lower, upper));

  // ---- clean-up ----------------------------------------------------------------------------
  const double size = static_cast<double>(length(upper - lower));
  for (std::size_t r = 0; r < rings.size(); ++r) {
    cleanRing(rings[r], tol);
    if (rings[r].p.size() < 3) {
      return fail("decomposePolygon: " + ringName(static_cast<int>(r)) +
                  " is degenerate: zero area after dropping duplicate and collinear points");
    }
  }
  std::vector<bool> reversed(rings.size(), false);

  // ---- simplicity: no two edges may cross or touch -----------------------------------------
  // Edge k of a cleaned ring joins its points k and k + 1; it is named by the input index of
  // the point it starts from in the input's order (the first input edge of the run it
  // stands for, when collinear points were dropped).
  auto edgeSource = [&](int r, std::size_t k) {
    const Ring& ring = rings[static_cast<std::size_t>(r)];
    std::size_t next = (k + 1) % ring.p.size();
    return reversed[static_cast<std::size_t>(r)] ? ring.source[next] : ring.source[k];
  };
  for (std::size_t r1 = 0; r1 < rings.size(); ++r1) {
    for (std::size_t r2 = r1; r2 < rings.size(); ++r2) {
      const Ring& A = rings[r1];
      const Ring& B = rings[r2];
      for (std::size_t i = 0; i < A.p.size(); ++i) {
        for (std::size_t j = r1 == r2 ? i + 1 : 0; j < B.p.size(); ++j) {
          std::size_t n = A.p.size();
          if (r1 == r2 && (j == i + 1 || (i == 0 && j == n - 1))) continue;  // adjacent
          DVec a = A.p[i], b = A.p[(i + 1) % n];
          DVec c = B.p[j], d = B.p[(j + 1) % B.p.size()];
          bool cross = properCross(a, b, c, d);
          bool touch =
              cross ||
              std::min({pointSegmentDistance(a, c, d), pointSegmentDistance(b, c, d),
                        pointSegmentDistance(c, a, b), pointSegmentDistance(d, a, b)}) <= tol;
          if (!touch) continue;
          int ea = edgeSource(static_cast<int>(r1), i);
          int eb = edgeSource(static_cast<int>(r2), j);
          std::string what = cross ? " cross" : " touch";
          if (r1 == 0 && r2 == 0) {
            return fail("decomposePolygon: edges " + std::to_string(std::min(ea, eb)) + " and " +
                        std::to_string(std::max(ea, eb)) + what +
                        " (the outline must not intersect itself)");
          }
          if (r1 == r2) {
            return fail("decomposePolygon: " + ringName(static_cast<int>(r1)) + " edges " +
                        std::to_string(std::min(ea, eb)) + " and " +
                        std::to_string(std::max(ea, eb)) + what);
          }
          return fail("decomposePolygon: " + edgeName(static_cast<int>(r1), ea) + " and " +
                      edgeName(static_cast<int>(r2), eb) + what);
        }
      }
    }
  }
  // ---- orientation: outline counter-clockwise, holes clockwise (solid on the left) ---------
  for (std::size_t r = 0; r < rings.size(); ++r) {
    double area = signedArea(rings[r]);
    if (std::fabs(area) <= tol * size) {
      return fail("decomposePolygon: " + ringName(static_cast<int>(r)) +
                  " is degenerate: zero area after dropping duplicate and collinear points");
    }
    if ((r == 0) != (area > 0.0)) {
      reverseRing(rings[r]);
      reversed[r] = true;
    }
  }
  for (std::size_t r = 1; r < rings.size(); ++r) {
    if (!insideRing(rings[r].p[0], rings[0])) {
      return fail("decomposePolygon: " + ringName(static_cast<int>(r)) +
                  " is not inside the outline");
    }
    for (std::size_t s = 1; s < rings.size(); ++s) {
      if (s != r && insideRing(rings[r].p[0], rings[s])) {
        return fail("decomposePolygon: " + ringName(static_cast<int>(r)) + " is inside " +
                    ringName(static_cast<int>(s)));
      }
    }
  }

  ConvexDecomposition out;
  std::vector<DVec> position;  // by node id
  std::vector<std::vector<Node>> nodeRings(rings.size());
  for (std::size_t r = 0; r < rings.size(); ++r) {
    double a = signedArea(rings[r]);
    out.area += a;  // holes are clockwise: negative
    std::size_t n = rings[r].p.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (orient(rings[r].p[(i + n - 1) % n], rings[r].p[i], rings[r].p[(i + 1) % n]) < 0.0)
        ++out.reflexCount;
      nodeRings[r].push_back({rings[r].p[i], static_cast<int>(position.size())});
      position.push_back(rings[r].p[i]);
    }
  }
  out.lowerBound = std::max(1, (out.reflexCount + 1) / 2 + 1 - static_cast<int>(holes.size()));

  // ---- bridge holes into the outline (rightmost hole first) ------------------------------------
  std::vector<Node> ring = nodeRings[0];
  std::vector<std::size_t> order;
  for (std::size_t r = 1; r < rings.size(); ++r)
    order.push_back(r);
  auto rightmost = [&](std::size_t r) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < nodeRings[r].size(); ++i) {
      DVec p = nodeRings[r][i].p, q = nodeRings[r][best].p;
      if (p.x > q.x || (p.x == q.x && p.y > q.y)) best = i;
    }
    return best;
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return nodeRings[x][rightmost(x)].p.x > nodeRings[y][rightmost(y)].p.x;
  });
  std::vector<bool> merged(rings.size(), false);
  for (std::size_t h : order) {
    const std::vector<Node>& hole = nodeRings[h];
    std::size_t m = rightmost(h);
    std::size_t hn = hole.size();
    DVec M = hole[m].p;
    DVec mPrev = hole[(m + hn - 1) % hn].p, mNext = hole[(m + 1) % hn].p;
    std::vector<std::size_t> candidates(ring.size());
    for (std::size_t i = 0; i < ring.size(); ++i)
      candidates[i] = i;
    std::stable_sort(candidates.begin(), candidates.end(), [&](std::size_t x, std::size_t y) {
      return dotD(ring[x].p - M, ring[x].p - M) < dotD(ring[y].p - M, ring[y].p - M);
    });
    // A bridge must leave both ends into the solid and meet no edge except at its ends.
    auto clear = [&](DVec a, DVec b, const std::vector<Node>& edges) {
      for (std::size_t i = 0, n = edges.size(); i < n; ++i) {
        DVec c = edges[i].p, d = edges[(i + 1) % n].p;
        if (sameD(c, a) || sameD(d, a) || sameD(c, b) || sameD(d, b)) continue;
        if (segmentsMeet(a, b, c, d)) return false;
      }
      return true;
    };
    std::size_t chosen = ring.size();
    for (std::size_t k : candidates) {
      std::size_t n = ring.size();
      DVec P = ring[k].p;
      if (sameD(P, M)) continue;
      if (!inCone(ring[(k + n - 1) % n].p, P, ring[(k + 1) % n].p, M - P)) continue;
      if (!inCone(mPrev, M, mNext, P - M)) continue;
      bool ok = clear(P, M, ring);
      for (std::size_t r = 1; ok && r < rings.size(); ++r) {
        if (!merged[r]) ok = clear(P, M, nodeRings[r]);
      }
      if (ok) {
        chosen = k;
        break;
      }
    }
    if (chosen == ring.size()) {
      // Cannot happen for a valid polygon (the nearest visible vertex always exists); the
      // checks above make it a float accident.
      return fail("decomposePolygon: " + ringName(static_cast<int>(h)) +
                  ": no bridge to the outline found (nearly degenerate input)");
    }
    std::vector<Node> splice;
    for (std::size_t i = 0; i <= hn; ++i)
      splice.push_back(hole[(m + i) % hn]);
    splice.push_back(ring[chosen]);
    ring.insert(ring.begin() + static_cast<std::ptrdiff_t>(chosen + 1), splice.begin(),
                splice.end());
    merged[h] = true;
  }

  // ---- ear clipping ------------------------------------------------------------------------
  struct Tri {
    int a, b, c;
  };
  std::vector<Tri> triangles;
  {
    std::size_t n = ring.size();
    std::vector<std::size_t> prev(n), next(n);
    for (std::size_t i = 0; i < n; ++i) {
      prev[i] = (i + n - 1) % n;
      next[i] = (i + 1) % n;
    }
    auto corner = [&](std::size_t i) {
      return orient(ring[prev[i]].p, ring[i].p, ring[next[i]].p);
    };
    auto isEar = [&](std::size_t i) {
      DVec a = ring[prev[i]].p, b = ring[i].p, c = ring[next[i]].p;
      if (orient(a, b, c) <= 0.0) return false;
      for (std::size_t j = next[next[i]]; j != prev[i]; j = next[j]) {
        DVec p = ring[j].p;
        if (sameD(p, a) || sameD(p, b) || sameD(p, c)) continue;
        if (corner(j) > 0.0) continue;  // only reflex (or flat) points can block an ear
        if (orient(a, b, p) >= 0.0 && orient(b, c, p) >= 0.0 && orient(c, a, p) >= 0.0)
          return false;
      }
      return true;
    };
    std::size_t remaining = n;
    std::size_t i = 0;
    std::size_t stalled = 0;
    // Each pass round the ring clips an ear or forces one, so this ends after at most
    // n * (n + 1) visits.
    while (remaining > 3) {
      double o = corner(i);
      bool clip = false;
      if (o == 0.0) {
        clip = true;  // a flat vertex or a zero-width fold left by bridging: no area to lose
      } else if (isEar(i)) {
        clip = true;
      } else if (++stalled > remaining) {
        // No ear passed the test: float trouble on nearly degenerate input. Cut the most
        // convex corner and say so.
        std::size_t best = i;
        double bestO = -1.0;
        std::size_t j = i;
        for (std::size_t k = 0; k < remaining; ++k, j = next[j]) {
          if (corner(j) > bestO) {
            bestO = corner(j);
            best = j;
          }
        }
        i = best;
        o = corner(i);
        clip = true;
        ++out.forcedEars;
      }
      if (clip) {
        if (o > 0.0) triangles.push_back({ring[prev[i]].id, ring[i].id, ring[next[i]].id});
        next[prev[i]] = next[i];
        prev[next[i]] = prev[i];
        std::size_t p = prev[i];
        --remaining;
        stalled = 0;
        i = p;  // the neighbours' corners changed: look there first
      } else {
        i = next[i];
      }
    }
    if (orient(ring[prev[i]].p, ring[i].p, ring[next[i]].p) > 0.0)
      triangles.push_back({ring[prev[i]].id, ring[i].id, ring[next[i]].id});
  }
  out.triangleCount = static_cast<int>(triangles.size());

  // ---- Hertel-Mehlhorn merging ---------------------------------------------------------------
  std::vector<std::vector<int>> pieces;
  std::map<std::pair<int, int>, int> owner;  // directed edge -> piece
  for (const Tri& t : triangles) {
    int idx = static_cast<int>(pieces.size());
    pieces.push_back({t.a, t.b, t.c});
    owner[{t.a, t.b}] = idx;
    owner[{t.b, t.c}] = idx;
    owner[{t.c, t.a}] = idx;
  }
  std::vector<std::pair<int, int>> diagonals;
  for (const auto& [edge, piece] : owner) {
    if (edge.first < edge.second && owner.count({edge.second, edge.first}) != 0)
      diagonals.push_back(edge);
  }
  // Longest first: long diagonals cross the middle of the polygon, and removing them first
  // tends to leave the short ones near reflex vertices, which must stay anyway.
  auto len2 = [&](std::pair<int, int> e) {
    DVec d =
        position[static_cast<std::size_t>(e.first)] - position[static_cast<std::size_t>(e.second)];
    return dotD(d, d);
  };
  std::stable_sort(diagonals.begin(), diagonals.end(),
                   [&](auto x, auto y) { return len2(x) > len2(y); });
  std::vector<bool> alive(pieces.size(), true);
  auto at = [&](int id) { return position[static_cast<std::size_t>(id)]; };
  for (auto [u, v] : diagonals) {
    auto pu = owner.find({u, v});
    auto qv = owner.find({v, u});
    if (pu == owner.end() || qv == owner.end()) continue;
    int pi = pu->second, qi = qv->second;
    if (pi == qi || !alive[static_cast<std::size_t>(pi)] || !alive[static_cast<std::size_t>(qi)])
      continue;
    std::vector<int>& P = pieces[static_cast<std::size_t>(pi)];
    std::vector<int>& Q = pieces[static_cast<std::size_t>(qi)];
    std::size_t pn = P.size(), qn = Q.size();
    if (pn + qn - 2 > static_cast<std::size_t>(kMaxPolygonVertices)) continue;
    std::size_t iu = pn, jv = qn;
    for (std::size_t k = 0; k < pn; ++k)
      if (P[k] == u && P[(k + 1) % pn] == v) iu = k;
    for (std::size_t k = 0; k < qn; ++k)
      if (Q[k] == v && Q[(k + 1) % qn] == u) jv = k;
    if (iu == pn || jv == qn) continue;
    // Convex at both ends of the diagonal once it is gone (collinear is fine: the polygon
    // builder drops the vertex).
    if (orient(at(P[(iu + pn - 1) % pn]), at(u), at(Q[(jv + 2) % qn])) < 0.0) continue;
    if (orient(at(Q[(jv + qn - 1) % qn]), at(v), at(P[(iu + 2) % pn])) < 0.0) continue;
    std::vector<int> joined;
    for (std::size_t k = 0; k < pn; ++k)
      joined.push_back(P[(iu + 1 + k) % pn]);  // v ... u
    for (std::size_t k = 2; k < qn; ++k)
      joined.push_back(Q[(jv + k) % qn]);  // after u, up to before v
    owner.erase({u, v});
    owner.erase({v, u});
    for (std::size_t k = 0; k < qn; ++k) {
      auto it = owner.find({Q[k], Q[(k + 1) % qn]});
      if (it != owner.end() && it->second == qi) it->second = pi;
    }
    P = std::move(joined);
    alive[static_cast<std::size_t>(qi)] = false;
  }

  // ---- pieces as polygons ------------------------------------------------------------------
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (!alive[k]) continue;
    std::vector<Vec2> pts;
    double area2 = 0.0;
    for (std::size_t i = 0; i < pieces[k].size(); ++i) {
      DVec p = at(pieces[k][i]);
      DVec q = at(pieces[k][(i + 1) % pieces[k].size()]);
      area2 += crossD(p, q);
      pts.push_back({static_cast<float>(p.x), static_cast<float>(p.y)});
    }
    Result<Polygon> poly = makePolygon(pts);
    if (!poly) {
      // A sliver below the tolerance (thinner than the hull tolerance everywhere) has no
      // area worth a shape; anything else would be a bug.
      if (0.5 * std::fabs(area2) <= tol * size) continue;
      return fail("decomposePolygon: internal error: piece " + std::to_string(k) +
                  " is not a valid polygon: " + poly.error().message);
    }
    out.pieces.push_back(*poly);
  }
  return out;
}

}  // namespace quack
