// The adversarial corpus (adversarial_corpus.hpp): every query must return a finite answer and a
// status, within its iteration cap: no NaN, no hang. Each case runs at several rotations, and with
// A and B swapped.

#include <gtest/gtest.h>

#include "adversarial_corpus.hpp"
#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/sat.hpp"

namespace quack {
namespace {

using testing::AdversarialCase;

void expectFinite(Vec2 v, const std::string& what) {
  EXPECT_TRUE(isFinite(v)) << what;
}

TEST(Adversarial, EveryQueryIsFiniteAndEnds) {
  std::vector<AdversarialCase> cases = testing::adversarialCorpus();
  for (const AdversarialCase& c : cases) {
    for (float turn : testing::kAdversarialTurns) {
      Transform spin = makeTransform({0.0f, 0.0f}, turn);
      for (int swap = 0; swap < 2; ++swap) {
        const ShapeGeometry& sa = swap ? c.b : c.a;
        const ShapeGeometry& sb = swap ? c.a : c.b;
        Transform xa = spin * (swap ? c.xb : c.xa);
        Transform xb = spin * (swap ? c.xa : c.xb);
        ShapeProxy pa = makeProxy(sa), pb = makeProxy(sb);
        std::string what =
            std::string(c.name) + " turn " + std::to_string(turn) + (swap ? " swapped" : "");
        DistanceOutput d = computeDistance(pa, xa, pb, xb);
        EXPECT_TRUE(std::isfinite(d.distance)) << what;
        EXPECT_GE(d.distance, 0.0f) << what;
        expectFinite(d.pointA, what);
        expectFinite(d.pointB, what);
        expectFinite(d.normal, what);
        EXPECT_NE(d.status, GjkStatus::maxIterations) << what;
        PenetrationOutput p = computePenetration(pa, xa, pb, xb);
        EXPECT_TRUE(std::isfinite(p.depth)) << what;
        EXPECT_GE(p.depth, 0.0f) << what;
        expectFinite(p.pointA, what);
        expectFinite(p.pointB, what);
        expectFinite(p.normal, what);
        EXPECT_NEAR(length(p.normal), 1.0f, 1e-3f) << what;
        EXPECT_NE(p.status, EpaStatus::maxIterations) << what;
        (void)testOverlap(pa, xa, pb, xb);
        // Every manifold routine, through the table and through the general path.
        for (const Manifold& m : {collide(sa, xa, sb, xb), collideGeneral(pa, xa, pb, xb)}) {
          ASSERT_GE(m.pointCount, 0) << what;
          ASSERT_LE(m.pointCount, kMaxManifoldPoints) << what;
          if (m.pointCount > 0) {
            EXPECT_NEAR(length(m.normal), 1.0f, 1e-3f) << what;
          }
          for (int k = 0; k < m.pointCount; ++k) {
            expectFinite(m.points[k].point, what);
            expectFinite(m.points[k].anchorA, what);
            EXPECT_TRUE(std::isfinite(m.points[k].separation)) << what;
            EXPECT_LE(m.points[k].separation, kSpeculativeDistance + 1e-3f) << what;
          }
          // Overlapping shapes always get a manifold.
          if (p.overlap) {
            EXPECT_GE(m.pointCount, 1) << what;
          }
        }
        if (shapeType(sa) == ShapeType::polygon && shapeType(sb) == ShapeType::polygon) {
          SatOutput s = computeSat(std::get<Polygon>(sa), xa, std::get<Polygon>(sb), xb);
          EXPECT_TRUE(std::isfinite(s.separation)) << what;
          if (p.status == EpaStatus::converged || p.status == EpaStatus::repeatedSupport) {
            float scale = 1e-5f * (1.0f + length(xa.p) + length(xb.p) + 2e3f);
            EXPECT_NEAR(p.depth, -s.separation, scale) << what;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace quack
