// 3D narrow phase against the peers, in the same run: GJK distance (Quack, Bullet's
// btGjkEpaSolver2::Distance), overlap (Quack's testOverlap, libccd's ccdGJKIntersect) and
// penetration (Quack's computePenetration, Bullet's btGjkEpaSolver2::Penetration, libccd's
// ccdGJKPenetration) on random hulls of 8, 16 and 32 vertices (points on ellipsoids), 256
// pairs per size at random poses, each library given the same shapes and poses. Bullet's
// hulls have their margin set to 0 so all three see the same polytopes. Cold queries (no
// warm start), as a broad phase's new pairs are.
//
// Hull-hull contact manifolds: Quack's collideHulls (SAT, then the incident face clipped and
// reduced to four points) against Bullet's btConvexConvexAlgorithm through its collision
// dispatcher, on btConvexHullShapes with their polyhedral features (btConvexPolyhedron),
// margin 0: with m_enableSatConvex (btPolyhedralContactClipping's SAT, then its clipping)
// and with Bullet's default (GJK/EPA for the normal, then the same clipping). The pairs are
// the half-overlapping random hulls above and boxes resting on boxes (a unit cube 0 to 0.01
// m deep on a slab, tilted up to 0.02 rad, turned about the slab's normal). Bullet's
// algorithm is made once per pair (not timed) and its persistent manifold cleared after
// every query, so each query is cold; the speculative distance is 0.02 m for both
// (Quack's kSpeculativeDistance, Bullet's contact breaking threshold).
//
// `narrowphase3d_bench --count KERNEL SET ROUNDS` runs one kernel over the 256 pairs of SET
// (random8, random16, random32, resting) ROUNDS times and nothing else, for instruction
// counts under callgrind (docs/3d.md). Manifolds: quack, bullet-sat, bullet-gjk; GJK and EPA
// (random sets only): quack-distance, bullet-distance (apart pairs), quack-overlap,
// ccd-overlap, quack-penetration, bullet-penetration, ccd-penetration (half-overlapping
// pairs). A Quack kernel with -hash appended (quack-hash, quack-distance-hash, ...) also
// prints a hash of its answers, to show that a change left them alone.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "quack/collision/epa3.hpp"
#include "quack/collision/gjk3.hpp"
#include "quack/collision/manifold3.hpp"

#if QUACK_HAVE_BULLET
#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
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

// FNV-1a over the answers of a --count run: the same number before and after a change
// that must not change any answer.
std::uint64_t g_quackHash = 1469598103934665603ull;

void hashBytes(const void* data, std::size_t n) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i)
    g_quackHash = (g_quackHash ^ p[i]) * 1099511628211ull;
}

// One query of each kind, shared by the timed loops and --count.
void quackDistance(const Case& c, bool hash = false) {
  DistanceOutput3 d = computeDistance(makeProxy(c.a), c.ta, makeProxy(c.b), c.tb);
  if (hash) {
    hashBytes(&d.distance, sizeof d.distance);
    hashBytes(&d.normal, sizeof d.normal);
    hashBytes(&d.pointA, sizeof d.pointA);
    hashBytes(&d.pointB, sizeof d.pointB);
  }
  benchmark::DoNotOptimize(d.distance);
}

void quackOverlap(const Case& c, bool hash = false) {
  bool hit = testOverlap(makeProxy(c.a), c.ta, makeProxy(c.b), c.tb);
  if (hash) hashBytes(&hit, sizeof hit);
  benchmark::DoNotOptimize(hit);
}

void quackPenetration(const Case& c, bool hash = false) {
  PenetrationOutput3 p = computePenetration(makeProxy(c.a), c.ta, makeProxy(c.b), c.tb);
  if (hash) {
    hashBytes(&p.overlap, sizeof p.overlap);
    hashBytes(&p.depth, sizeof p.depth);
    hashBytes(&p.normal, sizeof p.normal);
    hashBytes(&p.pointA, sizeof p.pointA);
    hashBytes(&p.pointB, sizeof p.pointB);
  }
  benchmark::DoNotOptimize(p.depth);
}

void BM_QuackDistance(benchmark::State& state) {
  const std::vector<Case>& cs = cases(static_cast<int>(state.range(0)), true);
  std::size_t i = 0;
  for (auto _ : state)
    quackDistance(cs[i++ & 255]);
}
BENCHMARK(BM_QuackDistance)->Arg(8)->Arg(16)->Arg(32);

void BM_QuackOverlap(benchmark::State& state) {
  const std::vector<Case>& cs = cases(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state)
    quackOverlap(cs[i++ & 255]);
}
BENCHMARK(BM_QuackOverlap)->Arg(8)->Arg(16)->Arg(32);

void BM_QuackPenetration(benchmark::State& state) {
  const std::vector<Case>& cs = cases(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state)
    quackPenetration(cs[i++ & 255]);
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

void bulletDistance(BulletCase& c) {
  btGjkEpaSolver2::sResults r;
  btGjkEpaSolver2::Distance(&c.a, c.ta, &c.b, c.tb, c.tb.getOrigin() - c.ta.getOrigin(), r);
  benchmark::DoNotOptimize(r.distance);
}

void bulletPenetration(BulletCase& c) {
  btGjkEpaSolver2::sResults r;
  bool hit =
      btGjkEpaSolver2::Penetration(&c.a, c.ta, &c.b, c.tb, c.tb.getOrigin() - c.ta.getOrigin(), r);
  benchmark::DoNotOptimize(hit);
  benchmark::DoNotOptimize(r.distance);
}

void BM_BulletDistance(benchmark::State& state) {
  std::vector<BulletCase>& cs = bulletCases(static_cast<int>(state.range(0)), true);
  std::size_t i = 0;
  for (auto _ : state)
    bulletDistance(cs[i++ & 255]);
}
BENCHMARK(BM_BulletDistance)->Arg(8)->Arg(16)->Arg(32);

void BM_BulletPenetration(benchmark::State& state) {
  std::vector<BulletCase>& cs = bulletCases(static_cast<int>(state.range(0)), false);
  std::size_t i = 0;
  for (auto _ : state)
    bulletPenetration(cs[i++ & 255]);
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

void ccdOverlap(CcdCase& c, const ccd_t& ccd) {
  benchmark::DoNotOptimize(ccdGJKIntersect(&c.a, &c.b, &ccd));
}

void ccdPenetration(CcdCase& c, const ccd_t& ccd) {
  ccd_real_t depth;
  ccd_vec3_t dir, pos;
  benchmark::DoNotOptimize(ccdGJKPenetration(&c.a, &c.b, &ccd, &depth, &dir, &pos));
  benchmark::DoNotOptimize(depth);
}

void BM_CcdIntersect(benchmark::State& state) {
  std::vector<CcdCase>& cs = ccdCases(static_cast<int>(state.range(0)));
  ccd_t ccd = makeCcd();
  std::size_t i = 0;
  for (auto _ : state)
    ccdOverlap(cs[i++ & 255], ccd);
}
BENCHMARK(BM_CcdIntersect)->Arg(8)->Arg(16)->Arg(32);

void BM_CcdPenetration(benchmark::State& state) {
  std::vector<CcdCase>& cs = ccdCases(static_cast<int>(state.range(0)));
  ccd_t ccd = makeCcd();
  std::size_t i = 0;
  for (auto _ : state)
    ccdPenetration(cs[i++ & 255], ccd);
}
BENCHMARK(BM_CcdPenetration)->Arg(8)->Arg(16)->Arg(32);
#endif

// ---- hull-hull manifolds ----

// A unit cube resting on a 4 x 1 x 4 slab: 256 pairs, the slab anywhere and turned, the cube
// 0 to 0.01 m deep, tilted by up to 0.02 rad about a random horizontal axis, turned about
// the slab's normal, anywhere on the slab's top.
std::vector<Case> makeRestingCases() {
  std::mt19937 rng(4242);
  std::normal_distribution<float> g(0, 1);
  std::uniform_real_distribution<float> u(-1, 1);
  const Hull3 slab = makeBox3({2, 0.5f, 2}).value();
  const Hull3 cube = makeBox3({0.5f, 0.5f, 0.5f}).value();
  std::vector<Case> cases(256);
  for (Case& c : cases) {
    c.a = slab;
    c.b = cube;
    c.ta = {{10 * g(rng), 10 * g(rng), 10 * g(rng)},
            normalize(Quat{g(rng), g(rng), g(rng), g(rng)})};
    const float tilt = 0.02f * 0.5f * (u(rng) + 1);
    const float heading = 3.14159265f * u(rng);
    const Quat yaw = Quat::fromAxisAngle({0, 1, 0}, heading);
    const Quat lean = Quat::fromAxisAngle(normalize(Vec3{u(rng), 0, u(rng) + 2.0f}), tilt);
    const float depth = 0.005f * (u(rng) + 1);
    const Transform3 slabFromCube{{1.2f * u(rng), 1.0f - depth, 1.2f * u(rng)}, lean * yaw};
    c.tb = c.ta * slabFromCube;
  }
  return cases;
}

// The pairs of a manifold set: 8, 16 or 32 (random hulls, half overlapping) or 0 (resting).
const std::vector<Case>& manifoldCases(int n) {
  static std::vector<Case> resting;
  if (n != 0) return cases(n, false);
  if (resting.empty()) resting = makeRestingCases();
  return resting;
}

int g_quackPoints = 0;

void quackManifold(const Case& c, bool hash = false) {
  Manifold3 m = collideHulls(c.a, c.ta, c.b, c.tb, kSpeculativeDistance);
  g_quackPoints += m.pointCount;
  if (hash) {
    hashBytes(&m.pointCount, sizeof m.pointCount);
    if (m.pointCount > 0) hashBytes(&m.normal, sizeof m.normal);
    for (int k = 0; k < m.pointCount; ++k) {
      hashBytes(&m.points[k].point, sizeof m.points[k].point);
      hashBytes(&m.points[k].separation, sizeof m.points[k].separation);
      hashBytes(&m.points[k].id, sizeof m.points[k].id);
    }
  }
  benchmark::DoNotOptimize(m);
}

void BM_QuackManifold(benchmark::State& state) {
  const std::vector<Case>& cs = manifoldCases(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  g_quackPoints = 0;
  for (auto _ : state)
    quackManifold(cs[i++ & 255]);
  state.counters["points"] = static_cast<double>(g_quackPoints) / static_cast<double>(i);
}
BENCHMARK(BM_QuackManifold)->ArgName("verts")->Arg(8)->Arg(16)->Arg(32)->Arg(0);

#if QUACK_HAVE_BULLET
// Bullet's dispatcher set up once; one algorithm per pair, found by the dispatcher.
struct BulletWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDispatcherInfo info;
};

struct BulletPair {
  std::unique_ptr<btConvexHullShape> shapeA, shapeB;
  btCollisionObject objectA, objectB;
  btCollisionAlgorithm* algorithm = nullptr;
};

std::unique_ptr<btConvexHullShape> toBulletHull(const Hull3& h) {
  auto shape = std::make_unique<btConvexHullShape>();
  for (int i = 0; i < h.vertexCount; ++i)
    shape->addPoint(btVector3(h.vertices[i].x, h.vertices[i].y, h.vertices[i].z), false);
  shape->recalcLocalAabb();
  shape->setMargin(0);
  shape->initializePolyhedralFeatures();  // btConvexPolyhedron: Bullet's clipping needs it
  return shape;
}

BulletWorld& bulletWorld() {
  static BulletWorld w;
  return w;
}

std::vector<BulletPair>& bulletPairs(int n) {
  static std::vector<BulletPair> store[33];
  std::vector<BulletPair>& out = store[n];
  if (out.empty()) {
    const std::vector<Case>& cs = manifoldCases(n);
    out = std::vector<BulletPair>(cs.size());
    for (std::size_t k = 0; k < cs.size(); ++k) {
      BulletPair& p = out[k];
      p.shapeA = toBulletHull(cs[k].a);
      p.shapeB = toBulletHull(cs[k].b);
      p.objectA.setCollisionShape(p.shapeA.get());
      p.objectB.setCollisionShape(p.shapeB.get());
      p.objectA.setWorldTransform(toBullet(cs[k].ta));
      p.objectB.setWorldTransform(toBullet(cs[k].tb));
      btCollisionObjectWrapper wa(nullptr, p.shapeA.get(), &p.objectA,
                                  p.objectA.getWorldTransform(), -1, -1);
      btCollisionObjectWrapper wb(nullptr, p.shapeB.get(), &p.objectB,
                                  p.objectB.getWorldTransform(), -1, -1);
      p.algorithm =
          bulletWorld().dispatcher.findAlgorithm(&wa, &wb, nullptr, BT_CONTACT_POINT_ALGORITHMS);
    }
  }
  return out;
}

int g_bulletPoints = 0;

void bulletManifold(BulletPair& p, bool sat) {
  BulletWorld& w = bulletWorld();
  w.info.m_enableSatConvex = sat;
  btCollisionObjectWrapper wa(nullptr, p.shapeA.get(), &p.objectA, p.objectA.getWorldTransform(),
                              -1, -1);
  btCollisionObjectWrapper wb(nullptr, p.shapeB.get(), &p.objectB, p.objectB.getWorldTransform(),
                              -1, -1);
  btManifoldResult result(&wa, &wb);
  p.algorithm->processCollision(&wa, &wb, w.info, &result);
  btPersistentManifold* m = result.getPersistentManifold();
  if (m != nullptr) {
    g_bulletPoints += m->getNumContacts();
    benchmark::DoNotOptimize(m->getNumContacts());
    m->clearManifold();  // cold: the next query of this pair starts from nothing
  }
}

void bulletManifoldBenchmark(benchmark::State& state, bool sat) {
  std::vector<BulletPair>& ps = bulletPairs(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  g_bulletPoints = 0;
  for (auto _ : state)
    bulletManifold(ps[i++ & 255], sat);
  state.counters["points"] = static_cast<double>(g_bulletPoints) / static_cast<double>(i);
}

void BM_BulletManifoldSat(benchmark::State& state) {
  bulletManifoldBenchmark(state, true);
}
BENCHMARK(BM_BulletManifoldSat)->ArgName("verts")->Arg(8)->Arg(16)->Arg(32)->Arg(0);

void BM_BulletManifoldGjk(benchmark::State& state) {
  bulletManifoldBenchmark(state, false);
}
BENCHMARK(BM_BulletManifoldGjk)->ArgName("verts")->Arg(8)->Arg(16)->Arg(32)->Arg(0);
#endif

// --count KERNEL SET ROUNDS: the kernel over SET's 256 pairs, ROUNDS times; the setup is
// the same for every ROUNDS, so the instruction counts of two runs differ by the queries.
// The GJK and EPA kernels of --count (random sets only): distance on the apart pairs,
// overlap and penetration on the half-overlapping ones; true when `kernel` is one of them.
bool countQuery(const std::string& kernel, int n, int rounds, int& status) {
  status = 0;
  const bool hash = kernel.size() > 5 && kernel.compare(kernel.size() - 5, 5, "-hash") == 0;
  const std::string name = hash ? kernel.substr(0, kernel.size() - 5) : kernel;
  auto run = [&](auto&& cases, auto&& query) {
    if (n == 0) {
      std::fprintf(stderr, "%s runs on the random sets only\n", kernel.c_str());
      status = 2;
      return true;
    }
    auto& set = cases();  // built even for 0 rounds, so that the setup is the same
    for (int r = 0; r < rounds; ++r)
      for (auto& c : set)
        query(c);
    std::printf("%s random%d: %d rounds", kernel.c_str(), n, rounds);
    if (hash) std::printf(", answers' hash %016llx", static_cast<unsigned long long>(g_quackHash));
    std::printf("\n");
    return true;
  };
  if (name == "quack-distance")
    return run([&]() -> const std::vector<Case>& { return cases(n, true); },
               [&](const Case& c) { quackDistance(c, hash); });
  if (name == "quack-overlap")
    return run([&]() -> const std::vector<Case>& { return cases(n, false); },
               [&](const Case& c) { quackOverlap(c, hash); });
  if (name == "quack-penetration")
    return run([&]() -> const std::vector<Case>& { return cases(n, false); },
               [&](const Case& c) { quackPenetration(c, hash); });
  if (hash) return false;
#if QUACK_HAVE_BULLET
  if (name == "bullet-distance")
    return run([&]() -> std::vector<BulletCase>& { return bulletCases(n, true); },
               [](BulletCase& c) { bulletDistance(c); });
  if (name == "bullet-penetration")
    return run([&]() -> std::vector<BulletCase>& { return bulletCases(n, false); },
               [](BulletCase& c) { bulletPenetration(c); });
#endif
#if QUACK_HAVE_CCD
  const ccd_t ccd = makeCcd();
  if (name == "ccd-overlap")
    return run([&]() -> std::vector<CcdCase>& { return ccdCases(n); },
               [&](CcdCase& c) { ccdOverlap(c, ccd); });
  if (name == "ccd-penetration")
    return run([&]() -> std::vector<CcdCase>& { return ccdCases(n); },
               [&](CcdCase& c) { ccdPenetration(c, ccd); });
#endif
  return false;
}

int countMode(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr,
                 "usage: %s --count KERNEL SET ROUNDS\n"
                 "  manifolds: quack|quack-hash|bullet-sat|bullet-gjk, "
                 "SET random8|random16|random32|resting\n"
                 "  GJK/EPA: quack-distance|quack-overlap|quack-penetration (each also "
                 "-hash)|bullet-distance|bullet-penetration|ccd-overlap|ccd-penetration, "
                 "SET random8|random16|random32\n",
                 argv[0]);
    return 2;
  }
  const std::string kernel = argv[2], set = argv[3];
  const int rounds = std::atoi(argv[4]);
  int n = -1;
  if (set == "random8") n = 8;
  if (set == "random16") n = 16;
  if (set == "random32") n = 32;
  if (set == "resting") n = 0;
  if (n < 0 || rounds < 0) {
    std::fprintf(stderr, "unknown set %s or negative rounds\n", set.c_str());
    return 2;
  }
  int status = 0;
  if (countQuery(kernel, n, rounds, status)) return status;
  if (kernel == "quack" || kernel == "quack-hash") {
    // quack-hash also hashes every answer (not for instruction counts).
    const bool hash = kernel == "quack-hash";
    const std::vector<Case>& cs = manifoldCases(n);
    for (int r = 0; r < rounds; ++r)
      for (const Case& c : cs)
        quackManifold(c, hash);
    std::printf("%s %s: %d rounds, %.3f points per query", kernel.c_str(), set.c_str(), rounds,
                rounds > 0 ? g_quackPoints / (256.0 * rounds) : 0.0);
    if (hash) std::printf(", answers' hash %016llx", static_cast<unsigned long long>(g_quackHash));
    std::printf("\n");
    return 0;
  }
#if QUACK_HAVE_BULLET
  if (kernel == "bullet-sat" || kernel == "bullet-gjk") {
    std::vector<BulletPair>& ps = bulletPairs(n);
    for (int r = 0; r < rounds; ++r)
      for (BulletPair& p : ps)
        bulletManifold(p, kernel == "bullet-sat");
    std::printf("%s %s: %d rounds, %.3f points per query\n", kernel.c_str(), set.c_str(), rounds,
                rounds > 0 ? g_bulletPoints / (256.0 * rounds) : 0.0);
    return 0;
  }
#endif
  std::fprintf(stderr, "unknown or unavailable kernel %s\n", kernel.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "--count") == 0) return countMode(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
