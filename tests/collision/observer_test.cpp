// The GJK and EPA observers (GjkTrace, EpaTrace, gjk.hpp and epa.hpp): the records are the
// library's own run. The last record's answer is the returned answer bit for bit,
// observing changes no answer, the records account for every support point, and a buffer
// too small for the run is filled, flagged and never overrun.

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "adversarial_corpus.hpp"
#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "test_shapes.hpp"

namespace quack {
namespace {

// The same bits: NaN matches itself, -0 does not match +0.
::testing::AssertionResult sameBits(float x, float y) {
  if (std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y)) {
    return ::testing::AssertionSuccess();
  }
  char buf[96];
  std::snprintf(buf, sizeof buf, "%a != %a", static_cast<double>(x), static_cast<double>(y));
  return ::testing::AssertionFailure() << buf;
}

::testing::AssertionResult sameBits(Vec2 x, Vec2 y) {
  ::testing::AssertionResult rx = sameBits(x.x, y.x);
  if (!rx) return rx << " (x)";
  ::testing::AssertionResult ry = sameBits(x.y, y.y);
  if (!ry) return ry << " (y)";
  return ::testing::AssertionSuccess();
}

void expectSameAnswer(const DistanceOutput& x, const DistanceOutput& y) {
  EXPECT_TRUE(sameBits(x.distance, y.distance));
  EXPECT_TRUE(sameBits(x.coreDistance, y.coreDistance));
  EXPECT_TRUE(sameBits(x.pointA, y.pointA));
  EXPECT_TRUE(sameBits(x.pointB, y.pointB));
  EXPECT_TRUE(sameBits(x.normal, y.normal));
  EXPECT_EQ(x.iterations, y.iterations);
  EXPECT_EQ(x.status, y.status);
}

void expectSameAnswer(const PenetrationOutput& x, const PenetrationOutput& y) {
  EXPECT_EQ(x.overlap, y.overlap);
  EXPECT_TRUE(sameBits(x.depth, y.depth));
  EXPECT_TRUE(sameBits(x.normal, y.normal));
  EXPECT_TRUE(sameBits(x.pointA, y.pointA));
  EXPECT_TRUE(sameBits(x.pointB, y.pointB));
  EXPECT_EQ(x.iterations, y.iterations);
  EXPECT_EQ(x.status, y.status);
}

bool epaRan(EpaStatus status) {
  return status == EpaStatus::converged || status == EpaStatus::repeatedSupport ||
         status == EpaStatus::maxIterations;
}

template <class Trace>
int countSupports(const Trace& trace) {
  int n = 0;
  for (int i = 0; i < trace.count; ++i)
    n += trace.records[i].hasSupport ? 1 : 0;
  return n;
}

// Buffers big enough for any run (kGjkMaxTraceRecords, kEpaMaxTraceRecords).
struct Buffers {
  std::vector<GjkIterationRecord> gjk = std::vector<GjkIterationRecord>(kGjkMaxTraceRecords);
  std::vector<GjkIterationRecord> gjk2 = std::vector<GjkIterationRecord>(kGjkMaxTraceRecords);
  std::vector<EpaIterationRecord> epa = std::vector<EpaIterationRecord>(kEpaMaxTraceRecords);

  GjkTrace gjkTrace() { return {gjk.data(), static_cast<int>(gjk.size())}; }
  GjkTrace gjkTrace2() { return {gjk2.data(), static_cast<int>(gjk2.size())}; }
  EpaTrace epaTrace() { return {epa.data(), static_cast<int>(epa.size())}; }
};

// Everything the observers promise, on one pair. `warm` (may be null) is a cache to start
// from; each call gets its own copy so that all of them start alike.
void checkPair(const ShapeProxy& a, Transform xa, const ShapeProxy& b, Transform xb,
               const GjkCache* warm, Buffers& buffers) {
  auto cache = [&](GjkCache& c) { return warm != nullptr ? (c = *warm, &c) : nullptr; };
  GjkCache c1, c2, c3, c4;

  // Distance.
  DistanceOutput plain = computeDistance(a, xa, b, xb, cache(c1));
  GjkTrace gjk = buffers.gjkTrace();
  DistanceOutput seen = computeDistance(a, xa, b, xb, cache(c2), gjk);
  {
    SCOPED_TRACE("observing changes nothing (distance)");
    expectSameAnswer(plain, seen);
  }
  ASSERT_GE(gjk.count, 1);
  ASSERT_FALSE(gjk.truncated);
  EXPECT_EQ(gjk.count, gjk.passes);
  const GjkIterationRecord& last = gjk.records[gjk.count - 1];
  EXPECT_TRUE(sameBits(last.distance, seen.distance));
  EXPECT_TRUE(sameBits(last.coreDistance, seen.coreDistance));
  EXPECT_TRUE(sameBits(last.pointA, seen.pointA));
  EXPECT_TRUE(sameBits(last.pointB, seen.pointB));
  EXPECT_TRUE(sameBits(last.normal, seen.normal));
  // One support point per pass, except a last pass that stopped before taking one.
  const int gjkSupports = countSupports(gjk);
  EXPECT_EQ(gjkSupports, seen.iterations);
  EXPECT_EQ(gjk.count, seen.iterations + (last.hasSupport ? 0 : 1));
  for (int i = 0; i + 1 < gjk.count; ++i)
    EXPECT_TRUE(gjk.records[i].hasSupport) << "record " << i;
  for (int i = 0; i < gjk.count; ++i) {
    const GjkIterationRecord& r = gjk.records[i];
    EXPECT_GE(r.simplex.count, 1);
    EXPECT_LE(r.simplex.count, 3);
    if (r.hasSupport) {
      EXPECT_NEAR(length(r.direction), 1.0f, 1e-5f) << "record " << i;
    }
  }

  // Penetration: the same GJK run, then EPA.
  PenetrationOutput plainP = computePenetration(a, xa, b, xb, cache(c3));
  GjkTrace gjk2 = buffers.gjkTrace2();
  EpaTrace epa = buffers.epaTrace();
  PenetrationOutput seenP = computePenetration(a, xa, b, xb, cache(c4), &gjk2, &epa);
  {
    SCOPED_TRACE("observing changes nothing (penetration)");
    expectSameAnswer(plainP, seenP);
  }
  ASSERT_EQ(gjk2.count, gjk.count);
  for (int i = 0; i < gjk.count; ++i) {
    EXPECT_TRUE(sameBits(gjk2.records[i].closest, gjk.records[i].closest)) << "record " << i;
    EXPECT_TRUE(sameBits(gjk2.records[i].pointA, gjk.records[i].pointA)) << "record " << i;
  }
  if (seenP.status == EpaStatus::separated) {
    EXPECT_TRUE(sameBits(seenP.normal, last.normal));
    EXPECT_TRUE(sameBits(seenP.pointA, last.pointA));
    EXPECT_TRUE(sameBits(seenP.pointB, last.pointB));
  }
  EXPECT_FALSE(epa.truncated);
  EXPECT_EQ(epa.count, epa.passes);
  EXPECT_EQ(gjkSupports + epa.triangleSupports + countSupports(epa), seenP.iterations);
  if (!epaRan(seenP.status)) {
    EXPECT_EQ(epa.count, 0);
    return;
  }
  ASSERT_GE(epa.count, 1);
  const EpaIterationRecord& end = epa.records[epa.count - 1];
  EXPECT_TRUE(sameBits(end.depth, seenP.depth));
  EXPECT_TRUE(sameBits(end.normal, seenP.normal));
  EXPECT_TRUE(sameBits(end.pointA, seenP.pointA));
  EXPECT_TRUE(sameBits(end.pointB, seenP.pointB));
  EXPECT_EQ(end.hasSupport, seenP.status != EpaStatus::maxIterations);
  for (int i = 0; i < epa.count; ++i) {
    const EpaIterationRecord& r = epa.records[i];
    // Each pass but the last inserts its support point.
    EXPECT_EQ(r.polytopeCount, 3 + i) << "record " << i;
    EXPECT_GE(r.edge, 0);
    EXPECT_LT(r.edge, r.polytopeCount);
    if (i + 1 < epa.count) {
      EXPECT_TRUE(r.hasSupport) << "record " << i;
    }
  }
}

TEST(Observer, HandWorkedCirclesApart) {
  // Two unit circles 3 m apart: one support point (3, 0) of B - A, found again along -v.
  ShapeProxy a = makeProxy(makeCircle({}, 1.0f).value());
  ShapeProxy b = makeProxy(makeCircle({}, 1.0f).value());
  GjkIterationRecord records[4];
  GjkTrace trace{records, 4};
  DistanceOutput d = computeDistance(a, {}, b, makeTransform({3.0f, 0.0f}, 0.0f), nullptr, trace);
  EXPECT_EQ(d.status, GjkStatus::repeatedSupport);
  EXPECT_EQ(d.iterations, 1);
  ASSERT_EQ(trace.count, 1);
  const GjkIterationRecord& r = records[0];
  EXPECT_EQ(r.simplex.count, 1);
  EXPECT_EQ(r.closest, (Vec2{3.0f, 0.0f}));
  EXPECT_TRUE(r.hasSupport);
  EXPECT_EQ(r.direction, (Vec2{1.0f, 0.0f}));
  EXPECT_EQ(r.support.w, (Vec2{3.0f, 0.0f}));
  EXPECT_EQ(r.distance, 1.0f);
  EXPECT_EQ(r.pointA, (Vec2{1.0f, 0.0f}));
  EXPECT_EQ(r.pointB, (Vec2{2.0f, 0.0f}));
  EXPECT_EQ(r.normal, (Vec2{1.0f, 0.0f}));
}

TEST(Observer, HandWorkedBoxesOverlapping) {
  // Boxes of half-size 1 at x = 0 and x = 1.5: B - A spans x in [-0.5, 3.5], y in [-2, 2];
  // EPA ends on its left edge (outward normal (-1, 0), distance 0.5).
  Polygon boxA = makeBox(1.0f, 1.0f).value();
  Polygon boxB = makeBox(1.0f, 1.0f).value();
  ShapeProxy a = makeProxy(boxA);
  ShapeProxy b = makeProxy(boxB);
  std::vector<EpaIterationRecord> records(kEpaMaxTraceRecords);
  EpaTrace trace{records.data(), kEpaMaxTraceRecords};
  PenetrationOutput p =
      computePenetration(a, {}, b, makeTransform({1.5f, 0.0f}, 0.0f), nullptr, nullptr, &trace);
  ASSERT_TRUE(p.overlap);
  ASSERT_GE(trace.count, 1);
  const EpaIterationRecord& r = records[trace.count - 1];
  EXPECT_FLOAT_EQ(r.edgeDistance, 0.5f);
  EXPECT_NEAR(r.edgeNormal.x, -1.0f, 1e-6f);
  EXPECT_NEAR(r.edgeNormal.y, 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(r.depth, 0.5f);
  EXPECT_FLOAT_EQ(p.depth, 0.5f);
  Vec2 e0 = r.polytope[r.edge].w;
  Vec2 e1 = r.polytope[(r.edge + 1) % r.polytopeCount].w;
  EXPECT_FLOAT_EQ(e0.x, -0.5f);
  EXPECT_FLOAT_EQ(e1.x, -0.5f);
}

TEST(Observer, FinalRecordIsTheAnswerOnTheAdversarialCorpus) {
  Buffers buffers;
  std::vector<testing::AdversarialCase> cases = testing::adversarialCorpus();
  for (const testing::AdversarialCase& c : cases) {
    for (float turn : testing::kAdversarialTurns) {
      Transform spin = makeTransform({0.0f, 0.0f}, turn);
      for (int swap = 0; swap < 2; ++swap) {
        const ShapeGeometry& sa = swap ? c.b : c.a;
        const ShapeGeometry& sb = swap ? c.a : c.b;
        Transform xa = spin * (swap ? c.xb : c.xa);
        Transform xb = spin * (swap ? c.xa : c.xb);
        SCOPED_TRACE(std::string(c.name) + " turn " + std::to_string(turn) +
                     (swap ? " swapped" : ""));
        checkPair(makeProxy(sa), xa, makeProxy(sb), xb, nullptr, buffers);
      }
    }
  }
}

TEST(Observer, FinalRecordIsTheAnswerOnRandomPairs) {
  const unsigned seed = 777;
  std::mt19937 rng(seed);
  const ShapeType kinds[4] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                              ShapeType::polygon};
  Buffers buffers;
  for (int k = 0; k < 2000; ++k) {
    ShapeGeometry sa = testing::randomShape(rng, kinds[k % 4], 1.0f);
    ShapeGeometry sb = testing::randomShape(rng, kinds[(k / 4) % 4], 1.0f);
    Transform xa = testing::randomTransform(rng, 1.0f);
    Transform xb = testing::randomTransform(rng, 1.0f);
    ShapeProxy pa = makeProxy(sa), pb = makeProxy(sb);
    SCOPED_TRACE("seed " + std::to_string(seed) + " pair " + std::to_string(k) + ": " +
                 testing::describe(sa) + " | " + testing::describe(sb));
    checkPair(pa, xa, pb, xb, nullptr, buffers);
    // Warm-started from the simplex of a nearby pose, as the narrow phase runs it.
    GjkCache cache;
    (void)computeDistance(pa, xa, pb, xb, &cache);
    Transform nudged = makeTransform({0.05f, -0.03f}, 0.02f) * xb;
    checkPair(pa, xa, pb, nudged, &cache, buffers);
  }
}

// GJK's stall guard puts the previous simplex back; the last record is that kept simplex
// (the pass before's), and still the answer. A thin pair found by a random search (none
// of the corpus or the random pairs above stalls).
TEST(Observer, StalledRunEndsOnTheKeptSimplex) {
  const Vec2 pointsA[] = {{-0x1.b66912p-2f, 0x1.5f70acp-4f},
                          {0x1.b3796p-4f, -0x1.ad7aecp-2f},
                          {-0x1.a7e008p-2f, 0x1.7008f8p-3f}};
  const Vec2 pointsB[] = {{-0x1.331c4p-1f, -0x1.69ea76p-12f},
                          {-0x1.63b538p-2f, -0x1.97a9d8p-12f},
                          {-0x1.26e54ap-2f, -0x1.91a4acp-12f},
                          {0x1.a76cccp-2f, -0x1.982b1ep-14f},
                          {0x1.4cde12p-1f, 0x1.644d68p-13f}};
  Polygon polygonA = makePolygon(pointsA).value();
  Polygon polygonB = makePolygon(pointsB).value();
  ShapeProxy a = makeProxy(polygonA);
  ShapeProxy b = makeProxy(polygonB);
  Transform xa{{-0x1.d74bdp+1f, 0x1.8f908p-1f}, {0x1.c02436p-1f, 0x1.ef3af2p-2f}};
  Transform xb{{-0x1.42caeep+2f, 0x1.a42e3cp-2f}, {-0x1.93b816p-1f, 0x1.3ae382p-1f}};

  Buffers buffers;
  GjkTrace trace = buffers.gjkTrace();
  DistanceOutput d = computeDistance(a, xa, b, xb, nullptr, trace);
  ASSERT_EQ(d.status, GjkStatus::stalled);
  ASSERT_GE(trace.count, 2);
  const GjkIterationRecord& last = trace.records[trace.count - 1];
  const GjkIterationRecord& before = trace.records[trace.count - 2];
  EXPECT_FALSE(last.hasSupport);
  EXPECT_TRUE(sameBits(last.closest, before.closest));
  EXPECT_EQ(last.simplex.count, before.simplex.count);
  checkPair(a, xa, b, xb, nullptr, buffers);
}

// A run longer than the buffer: the first capacity - 1 passes, then the final one; the flag
// is set, the pass count is the whole run's, and nothing past capacity is touched.
TEST(Observer, TooSmallGjkBufferIsTruncatedNeverOverrun) {
  std::vector<Vec2> ring;
  for (int i = 0; i < kMaxPolygonVertices; ++i) {
    float t = 2.0f * kPi * static_cast<float>(i) / kMaxPolygonVertices;
    ring.push_back({std::cos(t), std::sin(t)});
  }
  Polygon round = makePolygon(ring).value();
  ShapeProxy a = makeProxy(round);
  ShapeProxy b = makeProxy(round);
  Transform xa = makeTransform({0.0f, 0.0f}, 0.1f);
  // Overlapping: GJK needs a point, a segment and a triangle at least.
  Transform xb = makeTransform({0.9f, 0.5f}, 0.37f);

  std::vector<GjkIterationRecord> full(kGjkMaxTraceRecords);
  GjkTrace fullTrace{full.data(), kGjkMaxTraceRecords};
  DistanceOutput answer = computeDistance(a, xa, b, xb, nullptr, fullTrace);
  ASSERT_GE(fullTrace.count, 3) << "the pair should take several passes";
  const GjkIterationRecord& fullLast = full[fullTrace.count - 1];

  for (int capacity = 0; capacity < fullTrace.count; ++capacity) {
    SCOPED_TRACE("capacity " + std::to_string(capacity));
    // One guard record past the end, marked so that any write shows.
    std::vector<GjkIterationRecord> buffer(capacity + 1);
    buffer[capacity].distance = -12345.0f;
    buffer[capacity].simplex.count = 77;
    GjkTrace trace{buffer.data(), capacity};
    DistanceOutput d = computeDistance(a, xa, b, xb, nullptr, trace);
    expectSameAnswer(d, answer);
    EXPECT_TRUE(trace.truncated);
    EXPECT_EQ(trace.passes, fullTrace.count);
    EXPECT_EQ(trace.count, capacity);
    EXPECT_EQ(buffer[capacity].distance, -12345.0f);
    EXPECT_EQ(buffer[capacity].simplex.count, 77);
    for (int i = 0; i + 1 < capacity; ++i)
      EXPECT_TRUE(sameBits(buffer[i].closest, full[i].closest)) << "record " << i;
    if (capacity > 0) {
      const GjkIterationRecord& last = buffer[capacity - 1];
      EXPECT_TRUE(sameBits(last.closest, fullLast.closest));
      EXPECT_TRUE(sameBits(last.pointA, answer.pointA));
      EXPECT_TRUE(sameBits(last.pointB, answer.pointB));
      EXPECT_TRUE(sameBits(last.distance, answer.distance));
    }
  }
  // No buffer at all: nothing written, the passes still counted.
  GjkTrace none{nullptr, 10};
  DistanceOutput d = computeDistance(a, xa, b, xb, nullptr, none);
  expectSameAnswer(d, answer);
  EXPECT_EQ(none.count, 0);
  EXPECT_EQ(none.passes, fullTrace.count);
  EXPECT_TRUE(none.truncated);
  // A buffer of exactly the run's size is not truncated; the trace resets on reuse.
  GjkTrace exact{full.data(), fullTrace.count};
  exact.truncated = true;
  exact.count = 99;
  (void)computeDistance(a, xa, b, xb, nullptr, exact);
  EXPECT_FALSE(exact.truncated);
  EXPECT_EQ(exact.count, fullTrace.count);
}

TEST(Observer, TooSmallEpaBufferIsTruncatedNeverOverrun) {
  // Two 64-gon circles nearly concentric: EPA needs many passes to find the nearest edge.
  std::vector<Vec2> ring;
  for (int i = 0; i < kMaxPolygonVertices; ++i) {
    float t = 2.0f * kPi * static_cast<float>(i) / kMaxPolygonVertices;
    ring.push_back({std::cos(t), std::sin(t)});
  }
  Polygon round = makePolygon(ring).value();
  ShapeProxy a = makeProxy(round);
  ShapeProxy b = makeProxy(round);
  Transform xa = makeTransform({0.0f, 0.0f}, 0.0f);
  Transform xb = makeTransform({0.3f, 0.2f}, 0.01f);

  std::vector<EpaIterationRecord> full(kEpaMaxTraceRecords);
  EpaTrace fullTrace{full.data(), kEpaMaxTraceRecords};
  PenetrationOutput answer = computePenetration(a, xa, b, xb, nullptr, nullptr, &fullTrace);
  ASSERT_TRUE(epaRan(answer.status));
  ASSERT_GE(fullTrace.count, 3) << "the pair should take several EPA passes";

  for (int capacity : {0, 1, 2, fullTrace.count - 1}) {
    SCOPED_TRACE("capacity " + std::to_string(capacity));
    std::vector<EpaIterationRecord> buffer(capacity + 1);
    buffer[capacity].depth = -12345.0f;
    buffer[capacity].polytopeCount = 77;
    EpaTrace trace{buffer.data(), capacity};
    PenetrationOutput p = computePenetration(a, xa, b, xb, nullptr, nullptr, &trace);
    expectSameAnswer(p, answer);
    EXPECT_TRUE(trace.truncated);
    EXPECT_EQ(trace.passes, fullTrace.count);
    EXPECT_EQ(trace.count, capacity);
    EXPECT_EQ(trace.triangleSupports, fullTrace.triangleSupports);
    EXPECT_EQ(buffer[capacity].depth, -12345.0f);
    EXPECT_EQ(buffer[capacity].polytopeCount, 77);
    for (int i = 0; i + 1 < capacity; ++i)
      EXPECT_EQ(buffer[i].polytopeCount, full[i].polytopeCount) << "record " << i;
    if (capacity > 0) {
      const EpaIterationRecord& last = buffer[capacity - 1];
      EXPECT_EQ(last.polytopeCount, full[fullTrace.count - 1].polytopeCount);
      EXPECT_TRUE(sameBits(last.depth, answer.depth));
      EXPECT_TRUE(sameBits(last.normal, answer.normal));
      EXPECT_TRUE(sameBits(last.pointA, answer.pointA));
      EXPECT_TRUE(sameBits(last.pointB, answer.pointB));
    }
  }
}

}  // namespace
}  // namespace quack
