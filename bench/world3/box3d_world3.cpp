// The Box3D backend of world3_bench (scenes3.hpp): the scenes built through Box3D's C API,
// as its benchmark program builds and steps them (benchmark/main.c: a fresh world per run,
// b3DefaultWorldDef with `workerCount` workers and Box3D's own scheduler, 60 Hz, 4 sub-steps).
// Compiled only when QUACK_BOX3D_DIR names a Box3D source tree built by hand
// (bench/world3/CMakeLists.txt).

#include <box3d/box3d.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenes3.hpp"

namespace bench3::box3d {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

b3Pos pos(P3 p) {
  b3Pos out{};
  out.x = p.x;
  out.y = p.y;
  out.z = p.z;
  return out;
}

void ground(b3WorldId world, float half) {
  b3BodyDef bd = b3DefaultBodyDef();  // static
  bd.position = pos({0.0f, -1.0f, 0.0f});
  const b3BodyId body = b3CreateBody(world, &bd);
  const b3BoxHull box = b3MakeBoxHull(half, 1.0f, half);
  b3ShapeDef sd = b3DefaultShapeDef();
  sd.baseMaterial.friction = kFriction;
  (void)b3CreateHullShape(body, &sd, &box.base);
}

std::vector<b3BodyId> largePyramid(b3WorldId world) {
  b3World_EnableSleeping(world, false);
  ground(world, kPyramidGroundHalf);
  const b3BoxHull box = b3MakeBoxHull(kPyramidHalf, kPyramidHalf, kPyramidHalf);
  b3ShapeDef sd = b3DefaultShapeDef();
  sd.density = kPyramidDensity;
  sd.baseMaterial.friction = kFriction;
  b3BodyDef bd = b3DefaultBodyDef();
  bd.type = b3_dynamicBody;
  std::vector<b3BodyId> bodies;
  for (const P3& p : pyramidPositions()) {
    bd.position = pos(p);
    const b3BodyId b = b3CreateBody(world, &bd);
    (void)b3CreateHullShape(b, &sd, &box.base);
    bodies.push_back(b);
  }
  return bodies;
}

std::vector<b3BodyId> convexPile(b3WorldId world) {
  ground(world, kPileGroundHalf);
  std::vector<b3Vec3> points;
  for (const P3& p : pilePoints())
    points.push_back({p.x, p.y, p.z});
  b3HullData* hull = b3CreateHull(points.data(), kPilePoints, kPilePoints);
  if (hull == nullptr) throw std::runtime_error("Box3D: b3CreateHull failed on the pile's points");
  b3ShapeDef sd = b3DefaultShapeDef();
  sd.density = kPileDensity;
  sd.baseMaterial.friction = kFriction;
  b3BodyDef bd = b3DefaultBodyDef();
  bd.type = b3_dynamicBody;
  std::vector<b3BodyId> bodies;
  for (const P3& p : pilePositions()) {
    bd.position = pos(p);
    const b3BodyId b = b3CreateBody(world, &bd);
    (void)b3CreateHullShape(b, &sd, hull);
    bodies.push_back(b);
  }
  b3DestroyHull(hull);
  return bodies;
}

bool finite(b3Vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

bool available() {
  return true;
}

Run run(const Plan& plan) {
  Run out;
  auto t0 = Clock::now();
  b3WorldDef wd = b3DefaultWorldDef();
  wd.workerCount = static_cast<std::uint32_t>(plan.workers);
  wd.enableContinuous = plan.continuous;
  if (plan.scene == "convex_pile") {
    // The capacities Box3D's benchmark gives this scene (preallocation only).
    wd.capacity.dynamicShapeCount = kPileCountX * kPileCountZ * kPileLayers;
    wd.capacity.dynamicBodyCount = kPileCountX * kPileCountZ * kPileLayers;
    wd.capacity.contactCount = 50 * 1024;
  }
  const b3WorldId world = b3CreateWorld(&wd);
  std::vector<b3BodyId> bodies;
  if (plan.scene == "large_pyramid") {
    bodies = largePyramid(world);
  } else if (plan.scene == "convex_pile") {
    bodies = convexPile(world);
  } else {
    b3DestroyWorld(world);
    throw std::invalid_argument("no scene " + plan.scene);
  }
  out.buildMs = msSince(t0);
  auto positions = [&] {
    std::vector<P3> at;
    for (b3BodyId b : bodies) {
      const b3Pos p = b3Body_GetPosition(b);
      at.push_back({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
    }
    return at;
  };
  auto step = [&](int i) {
    b3World_Step(world, kTimeStep, kSubsteps);
    if (plan.traceEvery > 0 && (i + 1) % plan.traceEvery == 0) out.trace.push_back(positions());
  };
  t0 = Clock::now();
  step(0);
  out.firstStepMs = msSince(t0);
  t0 = Clock::now();
  for (int i = 1; i < plan.steps; ++i)
    step(i);
  out.msPerStep = plan.steps > 1 ? msSince(t0) / (plan.steps - 1) : 0.0;
  out.contacts = b3World_GetCounters(world).contactCount;
  out.awake = b3World_GetAwakeBodyCount(world);
  out.positions = positions();
  for (b3BodyId b : bodies) {
    const b3Pos p = b3Body_GetPosition(b);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
        !finite(b3Body_GetLinearVelocity(b)) || !finite(b3Body_GetAngularVelocity(b)))
      ++out.nonFinite;
  }
  b3DestroyWorld(world);
  return out;
}

}  // namespace bench3::box3d
