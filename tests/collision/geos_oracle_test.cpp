// GJK against an outside oracle: GEOS (the C API, reentrant functions) computes the
// distance between the cores in double precision; Quack's core distance must agree, and
// Quack's overlap answer must agree wherever the shapes are not within tolerance of
// touching. Every pair of shape kinds, sizes from 1e-3 to 1e3, apart, touching and
// overlapping.
//
// Pairs per kind combination: QUACK_ORACLE_PAIRS (environment), default 100000, or 10000
// under the sanitizers (ASan makes GEOS about 10x slower). Seeds are fixed; a failure
// prints the seed, the pair index and both shapes.
//
// Tolerance: |quack - geos| <= kOracleRelativeTolerance * S, S the largest coordinate
// magnitude of the pair (core points in the world frame, plus the sizes). Float
// coordinates carry a rounding of 6e-8 S; the transform into A's frame, the support
// differences and the projection add a few of those.

#include <geos_c.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>

#include "quack/collision/gjk.hpp"
#include "test_shapes.hpp"

namespace quack {
namespace {

constexpr double kOracleRelativeTolerance = 1e-6;

int pairsPerCombination() {
  if (const char* env = std::getenv("QUACK_ORACLE_PAIRS")) return std::atoi(env);
#if defined(__SANITIZE_ADDRESS__)
  return 10000;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return 10000;
#endif
#endif
  return 100000;
}

void geosMessage(const char*, ...) {}

class Geos {
 public:
  Geos() : ctx_(GEOS_init_r()) {
    GEOSContext_setNoticeHandler_r(ctx_, geosMessage);
    GEOSContext_setErrorHandler_r(ctx_, geosMessage);
  }
  ~Geos() { GEOS_finish_r(ctx_); }
  Geos(const Geos&) = delete;
  Geos& operator=(const Geos&) = delete;

  // The core of the proxy placed by xf: a point, a line string or a polygon. Coordinates
  // are the float transform evaluated in double.
  GEOSGeometry* core(const ShapeProxy& p, Transform xf) {
    int n = p.count();
    bool ring = n >= 3;
    GEOSCoordSequence* seq =
        GEOSCoordSeq_create_r(ctx_, static_cast<unsigned>(n + (ring ? 1 : 0)), 2);
    for (int i = 0; i <= n; ++i) {
      if (i == n && !ring) break;
      Vec2 v = p.points()[i % n];
      double x = double(xf.q.c) * v.x - double(xf.q.s) * v.y + xf.p.x;
      double y = double(xf.q.s) * v.x + double(xf.q.c) * v.y + xf.p.y;
      GEOSCoordSeq_setXY_r(ctx_, seq, static_cast<unsigned>(i), x, y);
    }
    if (n == 1) return GEOSGeom_createPoint_r(ctx_, seq);
    if (n == 2) return GEOSGeom_createLineString_r(ctx_, seq);
    return GEOSGeom_createPolygon_r(ctx_, GEOSGeom_createLinearRing_r(ctx_, seq), nullptr, 0);
  }
  double distance(const ShapeProxy& a, Transform xa, const ShapeProxy& b, Transform xb) {
    GEOSGeometry* ga = core(a, xa);
    GEOSGeometry* gb = core(b, xb);
    double d = -1.0;
    GEOSDistance_r(ctx_, ga, gb, &d);
    GEOSGeom_destroy_r(ctx_, ga);
    GEOSGeom_destroy_r(ctx_, gb);
    return d;
  }

 private:
  GEOSContextHandle_t ctx_;
};

float logUniform(std::mt19937& rng, float lo, float hi) {
  return std::exp(testing::uniform(rng, std::log(lo), std::log(hi)));
}

double coordinateScale(const ShapeProxy& p, Transform xf, float size) {
  double s = size;
  for (int i = 0; i < p.count(); ++i) {
    Vec2 w = transformPoint(xf, p.points()[i]);
    s = std::max({s, double(absf(w.x)), double(absf(w.y))});
  }
  return s;
}

struct Stats {
  double maxError = 0.0;  // largest |quack - geos| / S
  int compared = 0, overlapChecked = 0, touching = 0;
};

void runCombination(ShapeType ka, ShapeType kb, unsigned seed, Stats& stats) {
  std::mt19937 rng(seed);
  Geos geos;
  const int pairs = pairsPerCombination();
  for (int k = 0; k < pairs; ++k) {
    float scale = logUniform(rng, 1e-3f, 1e3f);
    float sizeA = scale * logUniform(rng, 0.2f, 5.0f);
    float sizeB = scale * logUniform(rng, 0.2f, 5.0f);
    ShapeGeometry sa = testing::randomShape(rng, ka, sizeA);
    ShapeGeometry sb = testing::randomShape(rng, kb, sizeB);
    ShapeProxy pa = makeProxy(sa), pb = makeProxy(sb);
    Transform xa = testing::randomTransform(rng, sizeA);
    float angle = testing::uniform(rng, -kPi, kPi);
    float reach = testing::uniform(rng, 0.0f, 2.0f) * (sizeA + sizeB);
    Transform xb = makeTransform(xa.p + reach * Vec2{std::cos(angle), std::sin(angle)},
                                 testing::uniform(rng, -kPi, kPi));
    int mode = k % 3;  // 0: as placed, 1: moved to touching cores, 2: moved to touching surfaces
    DistanceOutput d = computeDistance(pa, xa, pb, xb);
    if (mode != 0 && d.status != GjkStatus::overlap) {
      float gap = mode == 1 ? d.coreDistance : d.distance;
      xb.p = xb.p - gap * d.normal;
      d = computeDistance(pa, xa, pb, xb);
    }
    double core = geos.distance(pa, xa, pb, xb);
    double s = std::max(coordinateScale(pa, xa, sizeA), coordinateScale(pb, xb, sizeB));
    double tol = kOracleRelativeTolerance * s;
    double mine = d.status == GjkStatus::overlap ? 0.0 : double(d.coreDistance);
    double err = std::abs(mine - core);
    stats.maxError = std::max(stats.maxError, err / s);
    ++stats.compared;
    ASSERT_LE(err, tol) << "seed " << seed << " pair " << k << " (" << toString(ka) << ", "
                        << toString(kb) << "): quack " << mine << " geos " << core
                        << "\n  A: " << testing::describe(sa) << " at (" << xa.p.x << "," << xa.p.y
                        << "," << xa.q.angle() << ")\n  B: " << testing::describe(sb) << " at ("
                        << xb.p.x << "," << xb.p.y << "," << xb.q.angle() << ")";
    double radii = double(pa.radius()) + double(pb.radius());
    if (std::abs(core - radii) > tol) {
      ++stats.overlapChecked;
      bool geosOverlap = core <= radii;
      ASSERT_EQ(testOverlap(pa, xa, pb, xb), geosOverlap)
          << "seed " << seed << " pair " << k << " core " << core << " radii " << radii;
      ASSERT_EQ(d.distance == 0.0f, geosOverlap) << "seed " << seed << " pair " << k;
      if (!geosOverlap) {
        ASSERT_NEAR(d.distance, core - radii, 2 * tol) << "seed " << seed << " pair " << k;
      }
    } else {
      ++stats.touching;
    }
  }
}

class GeosOracle : public ::testing::TestWithParam<std::pair<ShapeType, ShapeType>> {};

TEST_P(GeosOracle, DistanceAndOverlapAgree) {
  auto [ka, kb] = GetParam();
  Stats stats;
  unsigned seed = 1000u + 10u * static_cast<unsigned>(ka) + static_cast<unsigned>(kb);
  runCombination(ka, kb, seed, stats);
  std::printf(
      "  %s-%s: %d pairs, max |quack - geos| / S = %.3g, overlap checked on %d, %d "
      "within tolerance of touching\n",
      toString(ka), toString(kb), stats.compared, stats.maxError, stats.overlapChecked,
      stats.touching);
}

std::vector<std::pair<ShapeType, ShapeType>> allCombinations() {
  const ShapeType kinds[4] = {ShapeType::circle, ShapeType::capsule, ShapeType::segment,
                              ShapeType::polygon};
  std::vector<std::pair<ShapeType, ShapeType>> out;
  for (int i = 0; i < 4; ++i)
    for (int j = i; j < 4; ++j)
      out.emplace_back(kinds[i], kinds[j]);
  return out;
}

INSTANTIATE_TEST_SUITE_P(AllKinds, GeosOracle, ::testing::ValuesIn(allCombinations()),
                         [](const auto& param) {
                           return std::string(toString(param.param.first)) + "_" +
                                  toString(param.param.second);
                         });

}  // namespace
}  // namespace quack
