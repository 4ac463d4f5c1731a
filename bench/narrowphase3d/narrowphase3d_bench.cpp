// 3D narrow phase against the peers, in the same run: GJK distance (Quack, Bullet's
// btGjkEpaSolver2::Distance), overlap (Quack's testOverlap, libccd's ccdGJKIntersect) and
// penetration (Quack's computePenetration, Bullet's btGjkEpaSolver2::Penetration, libccd's
// ccdGJKPenetration) on random hulls of 8, 16 and 32 vertices (points on ellipsoids), 256
// pairs per size at random poses, each library given the same shapes and poses. Bullet's
// hulls have their margin set to 0 so all three see the same polytopes. Cold queries (no
// warm start), as a broad phase's new pairs are.

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"

#if QUACK_HAVE_BULLET
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>
#endif
#if QUACK_HAVE_CCD
#include <ccd/ccd.h>
#include <ccd/quat.h>
#endif

namespace {

using namespace quack;

struct Case {
  Hull3 a, b;
  Transform3 ta, tb;
};

// 256 pairs of hulls with `n` vertices; `reach` scales B's offset from A (3: apart, 1: about
// half overlapping).
std::vector<Case> makeCases(int n, float reach) {
  std::mt19937 rng(static_cast<unsigned>(1000 * n + static_cast<int>(10 * reach)));
  std::normal_distribution<float> g(0, 1);
  std::uniform_real_distribution<float> u(0.5f, 1.0f);
  auto hull = [&] {
    while (true) {
      Vec3 axes{u(rng), u(rng), u(rng)};
      std::vector<Vec3> pts;
      for (int i = 0; i < n; ++i) {
        Vec3 p = normalize(Vec3{g(rng), g(rng), g(rng)});
        pts.push_back({p.x * axes.x, p.y * axes.y, p.z * axes.z});
      }
      Result<Hull3Build> h = computeHull3(pts);
      if (h.ok() && h->hull.vertexCount == n) return h->hull;
    }
  };
  auto quat = [&] { return normalize(Quat{g(rng), g(rng), g(rng), g(rng)}); };
  std::vector<Case> cases(256);
  for (Case& c : cases) {
    c.a = hull();
    c.b = hull();
    c.ta = {{g(rng), g(rng), g(rng)}, quat()};
    c.tb = {c.ta.p + reach * normalize(Vec3{g(rng), g(rng), g(rng)}), quat()};
  }
  return cases;
}

const std::vector<Case>& cases(int n, bool apart) {
  static std::vector<Case> store[2][33];
  std::vector<Case>& c = store[apart ? 1 : 0][n];
  if (c.empty()) c = makeCases(n, apart ? 3.0f : 1.0f);
  return c;
}

void BM_QuackDistance(benchmark::State& state) {
  const std::vector<Case>& cs = cases(static_cast<int>(state.range(0)), true);
  std::size_t i = 0;
  for (auto _ : state) {
    const Case& c = cs[i++ & 255];
    DistanceOutput3 d = computeDistance(makeProxy(c.a), c.ta, makeProxy(c.b), c.tb);
    benchmark::DoNotOptimize(d.distance);
  }
}
BENCHMARK(BM_QuackDistance)->Arg(8)->Arg(16)->Arg(32);

void BM_QuackOverlap(benchmark::State& state) {
  const std::vector<Case>& cs = cases(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state) {
    const Case& c = cs[i++ & 255];
    benchmark::DoNotOptimize(testOverlap(makeProxy(c.a), c.ta, makeProxy(c.b), c.tb));
  }
}
BENCHMARK(BM_QuackOverlap)->Arg(8)->Arg(16)->Arg(32);

void BM_QuackPenetration(benchmark::State& state) {
  const std::vector<Case>& cs = cases(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state) {
    const Case& c = cs[i++ & 255];
    PenetrationOutput3 p = computePenetration(makeProxy(c.a), c.ta, makeProxy(c.b), c.tb);
    benchmark::DoNotOptimize(p.depth);
  }
}
BENCHMARK(BM_QuackPenetration)->Arg(8)->Arg(16)->Arg(32);

#if QUACK_HAVE_BULLET
struct BulletCase {
  btConvexHullShape a, b;
  btTransform ta, tb;
};

btTransform toBullet(Transform3 t) {
  return btTransform(btQuaternion(t.q.x, t.q.y, t.q.z, t.q.w), btVector3(t.p.x, t.p.y, t.p.z));
}

std::vector<BulletCase>& bulletCases(int n, bool apart) {
  static std::vector<BulletCase> store[2][33];
  std::vector<BulletCase>& out = store[apart ? 1 : 0][n];
  if (out.empty()) {
    const std::vector<Case>& cs = cases(n, apart);
    out.resize(cs.size());
    for (std::size_t k = 0; k < cs.size(); ++k) {
      for (int i = 0; i < cs[k].a.vertexCount; ++i) {
        Vec3 v = cs[k].a.vertices[i];
        out[k].a.addPoint(btVector3(v.x, v.y, v.z), false);
      }
      for (int i = 0; i < cs[k].b.vertexCount; ++i) {
        Vec3 v = cs[k].b.vertices[i];
        out[k].b.addPoint(btVector3(v.x, v.y, v.z), false);
      }
      out[k].a.recalcLocalAabb();
      out[k].b.recalcLocalAabb();
      out[k].a.setMargin(0);
      out[k].b.setMargin(0);
      out[k].ta = toBullet(cs[k].ta);
      out[k].tb = toBullet(cs[k].tb);
    }
  }
  return out;
}

void BM_BulletDistance(benchmark::State& state) {
  std::vector<BulletCase>& cs = bulletCases(static_cast<int>(state.range(0)), true);
  std::size_t i = 0;
  for (auto _ : state) {
    BulletCase& c = cs[i++ & 255];
    btGjkEpaSolver2::sResults r;
    btGjkEpaSolver2::Distance(&c.a, c.ta, &c.b, c.tb, c.tb.getOrigin() - c.ta.getOrigin(), r);
    benchmark::DoNotOptimize(r.distance);
  }
}
BENCHMARK(BM_BulletDistance)->Arg(8)->Arg(16)->Arg(32);

void BM_BulletPenetration(benchmark::State& state) {
  std::vector<BulletCase>& cs = bulletCases(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state) {
    BulletCase& c = cs[i++ & 255];
    btGjkEpaSolver2::sResults r;
    bool hit = btGjkEpaSolver2::Penetration(&c.a, c.ta, &c.b, c.tb,
                                            c.tb.getOrigin() - c.ta.getOrigin(), r);
    benchmark::DoNotOptimize(hit);
    benchmark::DoNotOptimize(r.distance);
  }
}
BENCHMARK(BM_BulletPenetration)->Arg(8)->Arg(16)->Arg(32);
#endif

#if QUACK_HAVE_CCD
// A hull for libccd: local vertices in double and the pose; the support rotates the
// direction into the hull frame, scans, and rotates the vertex back (as Quack and Bullet do).
struct CcdHull {
  std::vector<ccd_vec3_t> v;
  ccd_quat_t q, qInv;
  ccd_vec3_t p;
};

void ccdSupport(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const CcdHull* h = static_cast<const CcdHull*>(obj);
  ccd_vec3_t d;
  ccdVec3Copy(&d, dir);
  ccdQuatRotVec(&d, &h->qInv);
  std::size_t best = 0;
  ccd_real_t bestDot = ccdVec3Dot(&h->v[0], &d);
  for (std::size_t i = 1; i < h->v.size(); ++i) {
    ccd_real_t dd = ccdVec3Dot(&h->v[i], &d);
    if (dd > bestDot) {
      bestDot = dd;
      best = i;
    }
  }
  ccdVec3Copy(out, &h->v[best]);
  ccdQuatRotVec(out, &h->q);
  ccdVec3Add(out, &h->p);
}

void ccdCenter(const void* obj, ccd_vec3_t* out) {
  ccdVec3Copy(out, &static_cast<const CcdHull*>(obj)->p);
}

struct CcdCase {
  CcdHull a, b;
};

CcdHull toCcd(const Hull3& h, Transform3 t) {
  CcdHull c;
  for (int i = 0; i < h.vertexCount; ++i) {
    ccd_vec3_t v;
    ccdVec3Set(&v, h.vertices[i].x, h.vertices[i].y, h.vertices[i].z);
    c.v.push_back(v);
  }
  ccdQuatSet(&c.q, t.q.x, t.q.y, t.q.z, t.q.w);
  ccdQuatInvert2(&c.qInv, &c.q);
  ccdVec3Set(&c.p, t.p.x, t.p.y, t.p.z);
  return c;
}

std::vector<CcdCase>& ccdCases(int n) {
  static std::vector<CcdCase> store[33];
  std::vector<CcdCase>& out = store[n];
  if (out.empty()) {
    for (const Case& c : cases(n, false))
      out.push_back({toCcd(c.a, c.ta), toCcd(c.b, c.tb)});
  }
  return out;
}

ccd_t makeCcd() {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = ccdSupport;
  ccd.support2 = ccdSupport;
  ccd.center1 = ccdCenter;
  ccd.center2 = ccdCenter;
  ccd.max_iterations = 100;
  ccd.epa_tolerance = 1e-6;
  return ccd;
}

void BM_CcdIntersect(benchmark::State& state) {
  std::vector<CcdCase>& cs = ccdCases(static_cast<int>(state.range(0)));
  ccd_t ccd = makeCcd();
  std::size_t i = 0;
  for (auto _ : state) {
    CcdCase& c = cs[i++ & 255];
    benchmark::DoNotOptimize(ccdGJKIntersect(&c.a, &c.b, &ccd));
  }
}
BENCHMARK(BM_CcdIntersect)->Arg(8)->Arg(16)->Arg(32);

void BM_CcdPenetration(benchmark::State& state) {
  std::vector<CcdCase>& cs = ccdCases(static_cast<int>(state.range(0)));
  ccd_t ccd = makeCcd();
  std::size_t i = 0;
  for (auto _ : state) {
    CcdCase& c = cs[i++ & 255];
    ccd_real_t depth;
    ccd_vec3_t dir, pos;
    benchmark::DoNotOptimize(ccdGJKPenetration(&c.a, &c.b, &ccd, &depth, &dir, &pos));
    benchmark::DoNotOptimize(depth);
  }
}
BENCHMARK(BM_CcdPenetration)->Arg(8)->Arg(16)->Arg(32);
#endif

}  // namespace

BENCHMARK_MAIN();
