// The world suite's scenes in Box2D v3 (compiled only when QUACK_BOX2D_V3_DIR names a v3
// tree built by hand; bench/world/CMakeLists.txt). Each scene is laid out as in v3's own
// benchmark program (read for the layout; the code is ours) and as in world_suite.cpp's
// Quack version of it.

#include <box2d/box2d.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "suite.hpp"

namespace suite::v3 {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

b2Vec2 vec(double x, double y) {
  return b2Vec2{static_cast<float>(x), static_cast<float>(y)};
}

void staticBox(b2BodyId ground, float hx, float hy, b2Vec2 at) {
  const b2Polygon box = b2MakeOffsetBox(hx, hy, at, b2Rot_identity);
  const b2ShapeDef sd = b2DefaultShapeDef();
  b2CreatePolygonShape(ground, &sd, &box);
}

void pyramid(b2WorldId world, int rows, double left, double base) {
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  const b2ShapeDef sd = b2DefaultShapeDef();
  const b2Polygon box = b2MakeSquare(0.5f);
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      bd.position = vec(left + 0.5 * row + i + 0.5, base + row + 0.5);
      b2BodyId b = b2CreateBody(world, &bd);
      b2CreatePolygonShape(b, &sd, &box);
    }
  }
}

void largePyramid(b2WorldId world) {
  b2World_EnableSleeping(world, false);
  b2BodyDef gd = b2DefaultBodyDef();
  b2BodyId ground = b2CreateBody(world, &gd);
  staticBox(ground, 100.0f, 1.0f, vec(0, -1));
  pyramid(world, 100, -50.0, 0.0);
}

void manyPyramids(b2WorldId world) {
  b2World_EnableSleeping(world, false);
  b2BodyDef gd = b2DefaultBodyDef();
  b2BodyId ground = b2CreateBody(world, &gd);
  const b2ShapeDef sd = b2DefaultShapeDef();
  for (int r = 0; r < 20; ++r) {
    const b2Segment s{vec(-110, 11.0 * r), vec(110, 11.0 * r)};
    b2CreateSegmentShape(ground, &sd, &s);
  }
  for (int r = 0; r < 20; ++r)
    for (int c = 0; c < 20; ++c)
      pyramid(world, 10, -110.0 + 11.0 * c + 0.5, 11.0 * r);
}

void smash(b2WorldId world) {
  b2World_SetGravity(world, b2Vec2{0.0f, 0.0f});
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  bd.position = vec(-20, 0);
  bd.linearVelocity = vec(40, 0);
  b2ShapeDef heavy = b2DefaultShapeDef();
  heavy.density = 8.0f;
  const b2Polygon big = b2MakeBox(4.0f, 4.0f);
  b2CreatePolygonShape(b2CreateBody(world, &bd), &heavy, &big);
  const b2Polygon small = b2MakeSquare(0.2f);
  const b2ShapeDef sd = b2DefaultShapeDef();
  bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  bd.isAwake = false;
  for (int i = 0; i < 120; ++i) {
    for (int j = 0; j < 80; ++j) {
      bd.position = vec(30.0 + 0.4 * i, 0.4 * (j - 40));
      b2CreatePolygonShape(b2CreateBody(world, &bd), &sd, &small);
    }
  }
}

// A walled pit of unit boxes: a floor of `floor` boxes centred on x = 0 and two walls of
// `wall` boxes at x = -+half.
void pit(b2BodyId ground, int floor, int wall, double half) {
  for (int i = 0; i < floor; ++i)
    staticBox(ground, 0.55f, 0.5f, vec(-half + i, 0));
  for (int i = 0; i < wall; ++i) {
    staticBox(ground, 0.5f, 0.55f, vec(-half, 1.0 + i));
    staticBox(ground, 0.5f, 0.55f, vec(half, 1.0 + i));
  }
}

b2BodyId junkyard(b2WorldId world) {
  b2BodyDef gd = b2DefaultBodyDef();
  pit(b2CreateBody(world, &gd), 161, 50, 80.0);
  b2Vec2 points[5];
  const double golden = 3.14159265358979 * (std::sqrt(5.0) - 1.0);
  for (int i = 0; i < 5; ++i)
    points[i] = vec(0.25 * std::cos(golden * i), 0.25 * std::sin(golden * i));
  const b2Hull hull = b2ComputeHull(points, 5);
  const b2Polygon pentagon = b2MakePolygon(&hull, 0.0f);
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  const b2ShapeDef sd = b2DefaultShapeDef();
  double side = -0.1;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 40; ++j) {
      bd.position = vec(0.375 * (2 * i - 200) + side, 15.0 + j);
      side = -side;
      b2CreatePolygonShape(b2CreateBody(world, &bd), &sd, &pentagon);
    }
  }
  bd = b2DefaultBodyDef();
  bd.type = b2_kinematicBody;
  b2BodyId pusher = b2CreateBody(world, &bd);
  const b2Polygon blade = b2MakeOffsetBox(2.0f, 4.0f, vec(0, 4), b2Rot_identity);
  b2CreatePolygonShape(pusher, &sd, &blade);
  return pusher;
}

void compounds(b2WorldId world) {
  b2BodyDef gd = b2DefaultBodyDef();
  b2BodyId ground = b2CreateBody(world, &gd);
  pit(ground, 81, 100, 40.0);
  const b2ShapeDef gsd = b2DefaultShapeDef();
  const b2Segment floor{vec(-800, -80), vec(800, -80)};
  b2CreateSegmentShape(ground, &gsd, &floor);
  const b2Vec2 leftPoints[3] = {vec(-1, 0), vec(0.5, 1), vec(0, 2)};
  const b2Vec2 rightPoints[3] = {vec(1, 0), vec(-0.5, 1), vec(0, 2)};
  const b2Hull leftHull = b2ComputeHull(leftPoints, 3);
  const b2Hull rightHull = b2ComputeHull(rightPoints, 3);
  const b2Polygon left = b2MakePolygon(&leftHull, 0.0f);
  const b2Polygon right = b2MakePolygon(&rightHull, 0.0f);
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.material.friction = 0.5f;
  double side = 0.25;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 150; ++j) {
      bd.position = vec(2.0 * i - 19.0 + side, 2.25 * j + 5.575);
      side = -side;
      b2BodyId b = b2CreateBody(world, &bd);
      b2CreatePolygonShape(b, &sd, &left);
      b2CreatePolygonShape(b, &sd, &right);
    }
  }
}

}  // namespace

Run run(const std::string& scene, int workers, int steps) {
  b2WorldDef def = b2DefaultWorldDef();
  def.workerCount = workers;
  b2WorldId world = b2CreateWorld(&def);
  b2BodyId pusher = b2_nullBodyId;
  Run out;
  auto t0 = Clock::now();
  if (scene == "large_pyramid") {
    largePyramid(world);
  } else if (scene == "many_pyramids") {
    manyPyramids(world);
  } else if (scene == "smash") {
    smash(world);
  } else if (scene == "junkyard") {
    pusher = junkyard(world);
  } else if (scene == "compounds") {
    compounds(world);
  } else {
    b2DestroyWorld(world);
    throw std::invalid_argument("no scene " + scene);
  }
  out.buildMs = msSince(t0);
  constexpr float dt = 1.0f / 60.0f;
  auto step = [&](int i) {
    if (B2_IS_NON_NULL(pusher)) {
      const b2WorldTransform target{vec(junkyardTargetX(i), 0), b2Rot_identity};
      b2Body_SetTargetTransform(pusher, target, dt, true);
    }
    b2World_Step(world, dt, 4);
  };
  t0 = Clock::now();
  step(0);
  out.firstStepMs = msSince(t0);
  t0 = Clock::now();
  for (int i = 1; i < steps; ++i)
    step(i);
  out.msPerStep = steps > 1 ? msSince(t0) / (steps - 1) : 0.0;
  out.contacts = b2World_GetCounters(world).contactCount;
  out.awake = b2World_GetAwakeBodyCount(world);
  b2DestroyWorld(world);
  return out;
}

}  // namespace suite::v3
