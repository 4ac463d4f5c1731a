#include "quack/geometry/decompose.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "quack/geometry/bounds.hpp"
#include "quack/geometry/mass.hpp"

namespace quack {
namespace {

using Outline = std::vector<Vec2>;

double shoelace(const Outline& o) {
  double a = 0;
  for (std::size_t i = 0; i < o.size(); ++i) {
    const Vec2 p = o[i], q = o[(i + 1) % o.size()];
    a += static_cast<double>(p.x) * q.y - static_cast<double>(q.x) * p.y;
  }
  return 0.5 * a;
}

// Independent containment: crossing number in double.
bool insideOutline(const Outline& o, double x, double y) {
  bool in = false;
  for (std::size_t i = 0; i < o.size(); ++i) {
    double ax = o[i].x, ay = o[i].y;
    double bx = o[(i + 1) % o.size()].x, by = o[(i + 1) % o.size()].y;
    if ((ay > y) != (by > y)) {
      double cx = ax + (y - ay) * (bx - ax) / (by - ay);
      if (x < cx) in = !in;
    }
  }
  return in;
}

double distanceToOutline(const Outline& o, double x, double y) {
  double best = 1e300;
  for (std::size_t i = 0; i < o.size(); ++i) {
    double ax = o[i].x, ay = o[i].y;
    double bx = o[(i + 1) % o.size()].x, by = o[(i + 1) % o.size()].y;
    double dx = bx - ax, dy = by - ay;
    double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? std::clamp(((x - ax) * dx + (y - ay) * dy) / l2, 0.0, 1.0) : 0.0;
    double ex = ax + t * dx - x, ey = ay + t * dy - y;
    best = std::min(best, std::sqrt(ex * ex + ey * ey));
  }
  return best;
}

// Checks everything a decomposition promises: convex valid pieces, areas that sum to the
// polygon's, and coverage by point sampling (a point is inside the polygon iff it is
// inside some piece; points within a hair of the boundary are skipped, since there the two
// tests may round differently). Returns the decomposition for further checks.
ConvexDecomposition checkDecomposition(const Outline& outline, const std::vector<Outline>& holes,
                                       const std::string& what, int samples = 4000) {
  SCOPED_TRACE(what);
  Result<ConvexDecomposition> r = decomposePolygon(outline, holes);
  EXPECT_TRUE(r.ok()) << (r ? "" : r.error().message);
  if (!r) return {};
  const ConvexDecomposition& d = *r;
  EXPECT_EQ(d.forcedEars, 0);
  double area = std::fabs(shoelace(outline));
  for (const Outline& h : holes)
    area -= std::fabs(shoelace(h));
  double sum = 0;
  for (const Polygon& p : d.pieces) {
    Status s = validatePolygon(p);
    EXPECT_TRUE(s.ok()) << s.message();
    EXPECT_LE(p.count, kMaxPolygonVertices);
    sum += static_cast<double>(computeMass(p, 1.0f).area);
  }
  EXPECT_NEAR(sum, area, 1e-4 * area) << "pieces: " << d.pieces.size();
  // Clean-up drops vertices within the hull tolerance (1e-5 of the size) of their
  // neighbours' line, which moves the area by about that much.
  EXPECT_NEAR(d.area, area, 2e-5 * area);
  EXPECT_GE(static_cast<int>(d.pieces.size()), d.lowerBound);

  Vec2 lo = outline[0], hi = outline[0];
  for (Vec2 p : outline) {
    lo = minv(lo, p);
    hi = maxv(hi, p);
  }
  double size = static_cast<double>(length(hi - lo));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y);
  int mismatches = 0;
  for (int k = 0; k < samples; ++k) {
    double x = ux(rng), y = uy(rng);
    double near = distanceToOutline(outline, x, y);
    for (const Outline& h : holes)
      near = std::min(near, distanceToOutline(h, x, y));
    if (near < 1e-4 * size) continue;
    bool in = insideOutline(outline, x, y);
    for (const Outline& h : holes)
      in = in && !insideOutline(h, x, y);
    int covering = 0;
    Vec2 p{static_cast<float>(x), static_cast<float>(y)};
    for (const Polygon& piece : d.pieces)
      covering += containsPoint(piece, p) ? 1 : 0;
    if (in ? covering != 1 : covering != 0) {
      if (++mismatches <= 3) {
        ADD_FAILURE() << "point (" << x << ", " << y << ") inside=" << in << " covered by "
                      << covering << " pieces";
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  return d;
}

std::string errorOf(const Outline& outline, const std::vector<Outline>& holes = {}) {
  Result<ConvexDecomposition> r = decomposePolygon(outline, holes);
  return r ? std::string("(no error)") : r.error().message;
}

Outline reversed(Outline o) {
  std::reverse(o.begin(), o.end());
  return o;
}

// A star-shaped polygon with `count` vertices at random radii about the origin: reflex
// vertices wherever the radius dips.
Outline randomStar(std::mt19937& rng, int count, float size) {
  std::uniform_real_distribution<float> ur(0.3f, 1.0f);
  Outline o;
  for (int i = 0; i < count; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / static_cast<float>(count);
    float r = size * ur(rng);
    o.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return o;
}

Outline square(Vec2 c, float h) {
  return {{c.x - h, c.y - h}, {c.x + h, c.y - h}, {c.x + h, c.y + h}, {c.x - h, c.y + h}};
}

TEST(Decompose, ConvexInputIsOnePiece) {
  ConvexDecomposition d = checkDecomposition(square({}, 1.0f), {}, "square");
  EXPECT_EQ(d.pieces.size(), 1u);
  EXPECT_EQ(d.reflexCount, 0);
  EXPECT_EQ(d.lowerBound, 1);
}

TEST(Decompose, LShapeIsTwoPieces) {
  Outline l = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4}};
  ConvexDecomposition d = checkDecomposition(l, {}, "L");
  EXPECT_EQ(d.pieces.size(), 2u);
  EXPECT_EQ(d.reflexCount, 1);
  EXPECT_EQ(d.lowerBound, 2);
  ConvexDecomposition cw = checkDecomposition(reversed(l), {}, "L clockwise");
  EXPECT_EQ(cw.pieces.size(), 2u);
}

TEST(Decompose, CollinearRunsAndDuplicates) {
  // A U with many points along each straight edge, repeated points and a closing duplicate.
  Outline u;
  for (int i = 0; i <= 10; ++i)
    u.push_back({0.3f * static_cast<float>(i), 0.0f});
  u.push_back({3, 0});
  for (int i = 1; i <= 10; ++i)
    u.push_back({3.0f, 0.3f * static_cast<float>(i)});
  u.push_back({2, 3});
  u.push_back({2, 3});
  u.push_back({2, 1});
  u.push_back({1.5f, 1});
  u.push_back({1, 1});
  u.push_back({1, 3});
  u.push_back({0, 3});
  u.push_back({0, 1.5f});
  u.push_back({0, 0});
  ConvexDecomposition d = checkDecomposition(u, {}, "U with collinear runs");
  EXPECT_EQ(d.reflexCount, 2);
  EXPECT_EQ(d.pieces.size(), 3u);
}

TEST(Decompose, SpikesAreDropped) {
  // A zero-width spike out of the top edge and one folding back into the right edge.
  Outline s = {{0, 0}, {2, 0}, {2, 1}, {2, 1.5f}, {2, 1}, {2, 2}, {1, 2}, {1, 5}, {1, 2}, {0, 2}};
  ConvexDecomposition d = checkDecomposition(s, {}, "spikes");
  EXPECT_EQ(d.pieces.size(), 1u);
  EXPECT_NEAR(d.area, 4.0, 1e-9);
}

TEST(Decompose, NearTouchingEdgesAreValid) {
  // A C whose jaws come within 1e-3 of each other (100 times the tolerance).
  Outline c = {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 1.999f}, {3, 1.999f}, {3, 3}, {0, 3}};
  checkDecomposition(c, {}, "jaws 1e-3 apart");
  // A slot narrower than the 1e-5 relative tolerance is a zero-width spike: welded shut.
  Outline thin = {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1.0f, 1.00001f}, {3, 1.00001f}, {3, 3}, {0, 3}};
  Result<ConvexDecomposition> welded = decomposePolygon(thin);
  ASSERT_TRUE(welded.ok()) << welded.error().message;
  EXPECT_EQ(welded->pieces.size(), 1u);
  EXPECT_NEAR(welded->area, 9.0, 1e-4);
  // A comb of narrow teeth with gaps of 1e-3.
  Outline comb = {{0, 0}};
  for (int i = 0; i < 20; ++i) {
    float x = static_cast<float>(i);
    comb.push_back({x + 0.9995f, 0});
    comb.push_back({x + 0.9995f, -5});
    comb.push_back({x + 1.0005f, -5});
    comb.push_back({x + 1.0005f, 0});
  }
  comb.push_back({21, 0});
  comb.push_back({21, 1});
  comb.push_back({0, 1});
  std::reverse(comb.begin(), comb.end());  // make it counter-clockwise-agnostic anyway
  checkDecomposition(comb, {}, "comb with 1e-3 teeth");
}

TEST(Decompose, Holes) {
  Outline outer = square({}, 4.0f);
  std::vector<Outline> holes = {square({-2, -2}, 1.0f), reversed(square({2, 2}, 1.0f)),
                                square({2, -2}, 0.5f)};
  ConvexDecomposition d = checkDecomposition(outer, holes, "square with three holes");
  EXPECT_GE(d.pieces.size(), 4u);
  // A hole whose rightmost vertex lines up with outline vertices and another hole's.
  Outline ring = square({}, 2.0f);
  ConvexDecomposition r = checkDecomposition(ring, {square({0, 0}, 1.0f)}, "square ring");
  EXPECT_LE(r.pieces.size(), 5u);
  // A hole in a concave outline.
  Outline l = {{0, 0}, {6, 0}, {6, 2}, {2, 2}, {2, 6}, {0, 6}};
  checkDecomposition(l, {square({1, 1}, 0.5f), square({4, 1}, 0.5f), square({1, 4}, 0.5f)},
                     "L with holes");
}

TEST(Decompose, LargeOutlines) {
  // More vertices than one polygon may hold: a 200-point star and a 300-point wavy ring.
  std::mt19937 rng(42);
  Outline star = randomStar(rng, 200, 10.0f);
  ConvexDecomposition d = checkDecomposition(star, {}, "200-point star");
  EXPECT_GT(d.pieces.size(), 1u);
  Outline circle, inner;
  for (int i = 0; i < 300; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / 300.0f;
    circle.push_back({10.0f * std::cos(a), 10.0f * std::sin(a)});
  }
  for (int i = 0; i < 100; ++i) {
    float a = 2.0f * kPi * static_cast<float>(i) / 100.0f;
    inner.push_back({5.0f * std::cos(a), 5.0f * std::sin(a)});
  }
  ConvexDecomposition c = checkDecomposition(circle, {}, "300-gon");
  EXPECT_EQ(c.pieces.size(), 5u);  // 300 vertices need ceil(298 / 62) pieces at 64 each
  checkDecomposition(circle, {inner}, "annulus of 300 + 100 points");
}

TEST(Decompose, RandomStarsNearTheBound) {
  // Hertel-Mehlhorn gives at most 2r + 1 pieces, within 4x of the fewest (>= ceil(r/2)+1).
  double ratioSum = 0;
  double worst = 0;
  int cases = 0;
  for (std::uint32_t seed = 1; seed <= 60; ++seed) {
    std::mt19937 rng(seed);
    int count = 5 + static_cast<int>(rng() % 60);
    float size = std::pow(10.0f, static_cast<float>(static_cast<int>(rng() % 7)) - 3.0f);
    Outline star = randomStar(rng, count, size);
    if (seed % 2 == 0) star = reversed(star);
    ConvexDecomposition d = checkDecomposition(star, {}, "seed " + std::to_string(seed), 1500);
    if (d.pieces.empty()) continue;
    EXPECT_LE(static_cast<int>(d.pieces.size()), 2 * d.reflexCount + 1) << "seed " << seed;
    double ratio = static_cast<double>(d.pieces.size()) / d.lowerBound;
    ratioSum += ratio;
    worst = std::max(worst, ratio);
    ++cases;
  }
  std::printf("random stars: pieces / lower bound: mean %.2f, worst %.2f over %d outlines\n",
              ratioSum / cases, worst, cases);
  RecordProperty("mean_ratio_to_lower_bound", std::to_string(ratioSum / cases));
  RecordProperty("worst_ratio_to_lower_bound", std::to_string(worst));
}

TEST(Decompose, RandomHoles) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    Outline outer = randomStar(rng, 40, 20.0f);
    // Holes on a grid well inside the star's inner radius (0.3 * 20 = 6).
    std::vector<Outline> holes;
    for (int i = 0; i < 4; ++i) {
      Vec2 c{-2.5f + 5.0f * static_cast<float>(i % 2), -2.5f + 5.0f * static_cast<float>(i / 2)};
      Outline h = randomStar(rng, 8, 1.5f);
      for (Vec2& p : h)
        p += c;
      holes.push_back(i % 2 == 0 ? h : reversed(h));
    }
    checkDecomposition(outer, holes, "holes seed " + std::to_string(seed), 1500);
  }
}

TEST(Decompose, Errors) {
  EXPECT_EQ(errorOf({{0, 0}, {1, 0}}), "decomposePolygon: outline needs at least 3 points, got 2");
  EXPECT_EQ(errorOf({{0, 0}, {1, 0}, {NAN, 1}}), "decomposePolygon: outline[2] is not finite");
  EXPECT_EQ(errorOf({{0, 0}, {1, 0}, {2, 0}, {3, 0}}),
            "decomposePolygon: outline is degenerate: zero area after dropping duplicate and "
            "collinear points");
  EXPECT_EQ(errorOf({{0, 0}, {1, 1}, {1, 0}, {0, 1}}),
            "decomposePolygon: edges 0 and 2 cross (the outline must not intersect itself)");
  // A figure eight pinched at one point: edges 1 and 4 touch at (2, 1).
  Outline pinch = {{0, 0}, {2, 1}, {4, 0}, {4, 2}, {2, 1}, {0, 2}};
  EXPECT_NE(errorOf(pinch).find("touch"), std::string::npos) << errorOf(pinch);
  // Edge 2 (y = 4) and edge 5 (x = 4) of an eight-point outline cross at (4, 4).
  Outline zig = {{0, 0}, {6, 0}, {6, 4}, {2, 4}, {2, 2}, {4, 2}, {4, 6}, {0, 6}};
  EXPECT_EQ(errorOf(zig),
            "decomposePolygon: edges 2 and 5 cross (the outline must not intersect itself)");
  EXPECT_EQ(errorOf(reversed(zig)),
            "decomposePolygon: edges 1 and 4 cross (the outline must not intersect itself)");
  EXPECT_EQ(errorOf(square({}, 1), {square({5, 5}, 0.5f)}),
            "decomposePolygon: holes[0] is not inside the outline");
  EXPECT_EQ(errorOf(square({}, 4), {square({0, 0}, 2), square({0, 0}, 1)}),
            "decomposePolygon: holes[1] is inside holes[0]");
  EXPECT_NE(errorOf(square({}, 1), {square({0.5f, 0}, 1)}).find("edge"), std::string::npos);
  EXPECT_EQ(errorOf(square({}, 1), {{{0, 0}, {0.1f, 0}, {0.2f, 0}}}),
            "decomposePolygon: holes[0] is degenerate: zero area after dropping duplicate and "
            "collinear points");
  Outline many(2000, Vec2{});
  EXPECT_EQ(errorOf(many), "decomposePolygon: too many points (2000 > 1024)");
}

}  // namespace
}  // namespace quack
