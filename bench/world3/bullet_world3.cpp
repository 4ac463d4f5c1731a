// The Bullet backend of world3_bench (scenes3.hpp): the scenes in Bullet's
// btDiscreteDynamicsWorld (Debian libbullet-dev; dynamic AABB tree broad phase, sequential
// impulse solver with its default 10 iterations), one step of 1/60 s per step, no sub-steps.
// Bullet multiplies the two frictions of a pair, so each shape gets sqrt(0.6) for a pair's
// 0.6. Its shapes keep Bullet's default collision margin (0.04 m): inside the box's
// half-extents for btBoxShape, around the points for btConvexHullShape (the pile's hulls are
// then 0.04 m larger than in Quack and Box3D). Compiled only when Bullet is found
// (bench/world3/CMakeLists.txt).

#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenes3.hpp"

namespace bench3::bullet {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// A Bullet world and everything it points at, freed in the right order.
struct BulletWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions;
  std::vector<std::unique_ptr<btRigidBody>> bodies;

  BulletWorld() { world.setGravity({0, -10, 0}); }
  ~BulletWorld() {
    for (auto& b : bodies)
      world.removeRigidBody(b.get());
  }
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  btRigidBody* add(btCollisionShape* shape, float mass, P3 at) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0.0f) shape->calculateLocalInertia(mass, inertia);
    btTransform t;
    t.setIdentity();
    t.setOrigin({at.x, at.y, at.z});
    motions.push_back(std::make_unique<btDefaultMotionState>(t));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motions.back().get(), shape, inertia);
    info.m_friction = std::sqrt(kFriction);
    bodies.push_back(std::make_unique<btRigidBody>(info));
    world.addRigidBody(bodies.back().get());
    return bodies.back().get();
  }

  void ground(float half) {
    shapes.push_back(std::make_unique<btBoxShape>(btVector3(half, 1.0f, half)));
    (void)add(shapes.back().get(), 0.0f, {0.0f, -1.0f, 0.0f});
  }
};

std::vector<btRigidBody*> largePyramid(BulletWorld& w) {
  w.ground(kPyramidGroundHalf);
  w.shapes.push_back(
      std::make_unique<btBoxShape>(btVector3(kPyramidHalf, kPyramidHalf, kPyramidHalf)));
  btCollisionShape* box = w.shapes.back().get();
  const float side = 2.0f * kPyramidHalf;
  const float mass = kPyramidDensity * side * side * side;
  std::vector<btRigidBody*> bodies;
  for (const P3& p : pyramidPositions()) {
    btRigidBody* b = w.add(box, mass, p);
    b->setActivationState(DISABLE_DEACTIVATION);  // sleeping off, as in Box3D's scene
    bodies.push_back(b);
  }
  return bodies;
}

std::vector<btRigidBody*> convexPile(BulletWorld& w) {
  w.ground(kPileGroundHalf);
  auto hull = std::make_unique<btConvexHullShape>();
  for (const P3& p : pilePoints())
    hull->addPoint({p.x, p.y, p.z}, false);
  hull->recalcLocalAabb();
  hull->optimizeConvexHull();
  // Bullet takes a mass, not a density: the ball's (the hull nearly fills it). The pile's
  // bodies are all alike and the ground is static, so the scale changes no motion. Bullet's
  // inertia for a hull is its bounding box's.
  const float mass =
      kPileDensity * 4.0f / 3.0f * 3.14159265f * kPileRadius * kPileRadius * kPileRadius;
  btCollisionShape* shape = hull.get();
  w.shapes.push_back(std::move(hull));
  std::vector<btRigidBody*> bodies;
  for (const P3& p : pilePositions())
    bodies.push_back(w.add(shape, mass, p));
  return bodies;
}

bool finite(const btVector3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

}  // namespace

bool available() {
  return true;
}

Run run(const Plan& plan) {
  Run out;
  auto t0 = Clock::now();
  auto w = std::make_unique<BulletWorld>();
  std::vector<btRigidBody*> bodies;
  if (plan.scene == "large_pyramid") {
    bodies = largePyramid(*w);
  } else if (plan.scene == "convex_pile") {
    bodies = convexPile(*w);
  } else {
    throw std::invalid_argument("no scene " + plan.scene);
  }
  out.buildMs = msSince(t0);
  auto positions = [&] {
    std::vector<P3> at;
    for (btRigidBody* b : bodies) {
      const btVector3& p = b->getWorldTransform().getOrigin();
      at.push_back({p.x(), p.y(), p.z()});
    }
    return at;
  };
  auto step = [&](int i) {
    (void)w->world.stepSimulation(kTimeStep, 1, kTimeStep);
    if (plan.traceEvery > 0 && (i + 1) % plan.traceEvery == 0) out.trace.push_back(positions());
  };
  t0 = Clock::now();
  step(0);
  out.firstStepMs = msSince(t0);
  t0 = Clock::now();
  for (int i = 1; i < plan.steps; ++i)
    step(i);
  out.msPerStep = plan.steps > 1 ? msSince(t0) / (plan.steps - 1) : 0.0;
  out.contacts = w->dispatcher.getNumManifolds();
  out.positions = positions();
  for (btRigidBody* b : bodies) {
    if (b->isActive()) ++out.awake;
    if (!finite(b->getWorldTransform().getOrigin()) || !finite(b->getLinearVelocity()) ||
        !finite(b->getAngularVelocity()))
      ++out.nonFinite;
  }
  return out;
}

}  // namespace bench3::bullet
