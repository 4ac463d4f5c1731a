// The world suite's scenes in Box2D v3 (compiled only when QUACK_BOX2D_V3_DIR names a v3
// tree built by hand; bench/world/CMakeLists.txt). Each scene is laid out as in v3's own
// benchmark program (shared/benchmarks.c and shared/human.c, read for the layout; the code
// is ours) and as in world_suite.cpp's Quack version of it.

#include <box2d/box2d.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

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

b2Vec2 vec(P2 p) {
  return b2Vec2{p.x, p.y};
}

// Every joint made, so that the checks after the run can find the live ones.
std::vector<b2JointId> g_joints;

b2JointId revolute(b2WorldId world, const b2RevoluteJointDef& def) {
  const b2JointId j = b2CreateRevoluteJoint(world, &def);
  g_joints.push_back(j);
  return j;
}

// A revolute joint with v3's defaults, at a world point (bodies' frames are unturned here).
b2JointId pin(b2WorldId world, b2BodyId a, b2BodyId b, b2Vec2 at) {
  b2RevoluteJointDef jd = b2DefaultRevoluteJointDef();
  jd.base.bodyIdA = a;
  jd.base.bodyIdB = b;
  jd.base.localFrameA.p = b2Body_GetLocalPoint(a, at);
  jd.base.localFrameB.p = b2Body_GetLocalPoint(b, at);
  return revolute(world, jd);
}

void jointGrid(b2WorldId world) {
  b2World_EnableSleeping(world, false);
  constexpr int n = kJointGridN;
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.filter.categoryBits = 2;
  sd.filter.maskBits = ~std::uint64_t{2};
  const b2Circle circle{{0.0f, 0.0f}, 0.4f};
  std::vector<b2BodyId> bodies;
  bodies.reserve(static_cast<std::size_t>(n * n));
  b2BodyDef bd = b2DefaultBodyDef();
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) {
      bd.type = jointGridStatic(k, i) ? b2_staticBody : b2_dynamicBody;
      bd.position = vec(k, -i);
      const b2BodyId b = b2CreateBody(world, &bd);
      b2CreateCircleShape(b, &sd, &circle);
      const std::size_t at = bodies.size();
      // As v3: every neighbour pair joined, the static ones of the top row included.
      if (i > 0) (void)pin(world, bodies[at - 1], b, vec(k, 0.5 - i));
      if (k > 0) (void)pin(world, bodies[at - static_cast<std::size_t>(n)], b, vec(k - 0.5, -i));
      bodies.push_back(b);
    }
  }
}

struct Figure {
  std::array<b2BodyId, kBones.size()> bodies;
  std::array<b2JointId, kBones.size()> joints;
  bool live = false;
};

void spawnFigure(b2WorldId world, Figure& f, b2Vec2 origin, int group) {
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  bd.sleepThreshold = kBoneSleepThreshold;
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.material.friction = 0.2f;
  sd.filter.groupIndex = -group;
  sd.filter.categoryBits = 2;
  sd.filter.maskBits = 1 | 2;
  b2ShapeDef footDef = sd;
  footDef.material.friction = 0.05f;
  footDef.filter.maskBits = 1;
  b2Vec2 footPoints[4];
  for (std::size_t i = 0; i < 4; ++i)
    footPoints[i] = vec(kFoot[i]);
  const b2Hull footHull = b2ComputeHull(footPoints, 4);
  const b2Polygon foot = b2MakePolygon(&footHull, kFootRadius);
  for (std::size_t i = 0; i < kBones.size(); ++i) {
    const Bone& bone = kBones[i];
    bd.position = b2Vec2{origin.x, origin.y + bone.y};
    bd.linearDamping = bone.linearDamping;
    const b2BodyId b = b2CreateBody(world, &bd);
    f.bodies[i] = b;
    const b2Capsule capsule{{0.0f, bone.capsuleLow}, {0.0f, bone.capsuleHigh}, bone.radius};
    b2CreateCapsuleShape(b, &sd, &capsule);
    if (bone.foot) b2CreatePolygonShape(b, &footDef, &foot);
    f.joints[i] = b2_nullJointId;
    if (bone.parent < 0) continue;
    const b2Vec2 pivot{origin.x, origin.y + bone.pivotY};
    b2RevoluteJointDef jd = b2DefaultRevoluteJointDef();
    jd.base.bodyIdA = f.bodies[static_cast<std::size_t>(bone.parent)];
    jd.base.bodyIdB = b;
    jd.base.localFrameA.p = b2Body_GetLocalPoint(jd.base.bodyIdA, pivot);
    jd.base.localFrameA.q = b2MakeRot(bone.frameTurn * B2_PI);
    jd.base.localFrameB.p = b2Body_GetLocalPoint(b, pivot);
    jd.enableLimit = true;
    jd.lowerAngle = bone.lower * B2_PI;
    jd.upperAngle = bone.upper * B2_PI;
    jd.enableMotor = true;
    jd.maxMotorTorque = bone.frictionScale * kJointFriction;
    jd.enableSpring = true;
    jd.hertz = kBoneHertz;
    jd.dampingRatio = kBoneDamping;
    f.joints[i] = revolute(world, jd);
  }
  f.live = true;
}

void destroyFigure(Figure& f) {
  for (std::size_t i = 1; i < kBones.size(); ++i)
    b2DestroyJoint(f.joints[i]);
  for (b2BodyId b : f.bodies)
    b2DestroyBody(b);
  f.live = false;
}

struct Rain {
  std::vector<Figure> figures =
      std::vector<Figure>(static_cast<std::size_t>(kRainRows * kRainColumns * kRainGroupSize));
  void step(b2WorldId world, int step) {
    int column = 0;
    bool replace = false;
    if (!rainSpawn(step, column, replace)) return;
    for (int row = 0; row < kRainRows; ++row) {
      const P2 o = rainGroupOrigin(row, column);
      for (int i = 0; i < kRainGroupSize; ++i) {
        Figure& f =
            figures[static_cast<std::size_t>((row * kRainColumns + column) * kRainGroupSize + i)];
        if (f.live) destroyFigure(f);
        spawnFigure(world, f, b2Vec2{o.x + 0.5f * static_cast<float>(i), o.y}, i + 1);
      }
    }
  }
};

void rainFloors(b2WorldId world) {
  b2BodyDef gd = b2DefaultBodyDef();
  const b2BodyId ground = b2CreateBody(world, &gd);
  float y = 0.0f;
  for (int r = 0; r < kRainRows; ++r) {
    float x = -0.5f * static_cast<float>(kRainGridCount) * kRainGridSize;
    for (int j = 0; j <= kRainGridCount; ++j) {
      staticBox(ground, 0.5f * kRainGridSize, 0.5f * kRainGridSize, b2Vec2{x, y});
      x += kRainGridSize;
    }
    y += 45.0f;
  }
}

void spinner(b2WorldId world) {
  b2BodyDef gd = b2DefaultBodyDef();
  const b2BodyId ground = b2CreateBody(world, &gd);
  const std::array<P2, 360> ring = spinnerRing();
  std::array<b2Vec2, 360> points;
  for (std::size_t i = 0; i < ring.size(); ++i)
    points[i] = vec(ring[i]);
  b2SurfaceMaterial material{};
  material.friction = 0.1f;
  b2ChainDef cd = b2DefaultChainDef();
  cd.points = points.data();
  cd.count = static_cast<int>(points.size());
  cd.isLoop = true;
  cd.materials = &material;
  cd.materialCount = 1;
  b2CreateChain(ground, &cd);

  b2BodyDef pd = b2DefaultBodyDef();
  pd.type = b2_dynamicBody;
  pd.position = b2Vec2{0.0f, 12.0f};
  pd.enableSleep = false;
  const b2BodyId paddle = b2CreateBody(world, &pd);
  const b2Polygon blade = b2MakeRoundedBox(0.4f, 20.0f, 0.2f);
  b2ShapeDef psd = b2DefaultShapeDef();
  psd.material.friction = 0.0f;
  b2CreatePolygonShape(paddle, &psd, &blade);
  b2RevoluteJointDef jd = b2DefaultRevoluteJointDef();
  jd.base.bodyIdA = ground;
  jd.base.bodyIdB = paddle;
  jd.base.localFrameA.p = b2Body_GetLocalPoint(ground, pd.position);
  jd.enableMotor = true;
  jd.motorSpeed = 5.0f;
  jd.maxMotorTorque = FLT_MAX;
  (void)revolute(world, jd);

  const b2Capsule capsule{{-0.25f, 0.0f}, {0.25f, 0.0f}, 0.25f};
  const b2Circle circle{{0.0f, 0.0f}, 0.35f};
  const b2Polygon square = b2MakeSquare(0.35f);
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.material.friction = 0.1f;
  sd.material.restitution = 0.1f;
  sd.density = 0.25f;
  float x = -23.0f, y = 2.0f;
  for (int i = 0; i < kSpinnerBodies; ++i) {
    bd.position = b2Vec2{x, y};
    const b2BodyId b = b2CreateBody(world, &bd);
    if (i % 3 == 0) {
      b2CreateCapsuleShape(b, &sd, &capsule);
    } else if (i % 3 == 1) {
      b2CreateCircleShape(b, &sd, &circle);
    } else {
      b2CreatePolygonShape(b, &sd, &square);
    }
    x += 0.5f;
    if (x >= 23.0f) {
      x = -23.0f;
      y += 0.5f;
    }
  }
}

void tumbler(b2WorldId world) {
  b2BodyDef gd = b2DefaultBodyDef();
  const b2BodyId ground = b2CreateBody(world, &gd);
  b2BodyDef dd = b2DefaultBodyDef();
  dd.type = b2_dynamicBody;
  dd.position = b2Vec2{0.0f, 10.0f};
  const b2BodyId drum = b2CreateBody(world, &dd);
  b2ShapeDef heavy = b2DefaultShapeDef();
  heavy.density = 50.0f;
  const b2Polygon walls[4] = {b2MakeOffsetBox(0.5f, 10.0f, b2Vec2{10.0f, 0.0f}, b2Rot_identity),
                              b2MakeOffsetBox(0.5f, 10.0f, b2Vec2{-10.0f, 0.0f}, b2Rot_identity),
                              b2MakeOffsetBox(10.0f, 0.5f, b2Vec2{0.0f, 10.0f}, b2Rot_identity),
                              b2MakeOffsetBox(10.0f, 0.5f, b2Vec2{0.0f, -10.0f}, b2Rot_identity)};
  for (const b2Polygon& wall : walls)
    b2CreatePolygonShape(drum, &heavy, &wall);
  b2RevoluteJointDef jd = b2DefaultRevoluteJointDef();
  jd.base.bodyIdA = ground;
  jd.base.bodyIdB = drum;
  jd.base.localFrameA.p = b2Vec2{0.0f, 10.0f};
  jd.motorSpeed = (B2_PI / 180.0f) * 25.0f;
  jd.maxMotorTorque = 1e8f;
  jd.enableMotor = true;
  (void)revolute(world, jd);

  constexpr int n = 45;
  const b2Polygon box = b2MakeBox(0.125f, 0.125f);
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  const b2ShapeDef sd = b2DefaultShapeDef();
  float y = -0.2f * n + 10.0f;
  for (int i = 0; i < n; ++i) {
    float x = -0.2f * n;
    for (int j = 0; j < n; ++j) {
      bd.position = b2Vec2{x, y};
      b2CreatePolygonShape(b2CreateBody(world, &bd), &sd, &box);
      x += 0.4f;
    }
    y += 0.4f;
  }
}

void washer(b2WorldId world) {
  b2BodyDef dd = b2DefaultBodyDef();
  dd.type = b2_kinematicBody;
  dd.position = b2Vec2{0.0f, 10.0f};
  dd.angularVelocity = (B2_PI / 180.0f) * 25.0f;
  dd.linearVelocity = b2Vec2{0.001f, -0.002f};
  const b2BodyId drum = b2CreateBody(world, &dd);
  const b2ShapeDef dsd = b2DefaultShapeDef();
  for (const std::array<P2, 4>& piece : washerPieces()) {
    const b2Vec2 points[4] = {vec(piece[0]), vec(piece[1]), vec(piece[2]), vec(piece[3])};
    const b2Hull hull = b2ComputeHull(points, 4);
    const b2Polygon polygon = b2MakePolygon(&hull, 0.0f);
    b2CreatePolygonShape(drum, &dsd, &polygon);
  }
  constexpr int n = 90;
  const float a = 0.1f;
  const b2Polygon box = b2MakeSquare(a);
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.enableHitEvents = true;
  float y = -1.1f * a * n + 10.0f;
  for (int i = 0; i < n; ++i) {
    float x = -1.1f * a * n;
    for (int j = 0; j < n; ++j) {
      bd.position = b2Vec2{x, y};
      b2CreatePolygonShape(b2CreateBody(world, &bd), &sd, &box);
      x += 2.1f * a;
    }
    y += 2.1f * a;
  }
}

void chain(b2WorldId world) {
  b2BodyDef gd = b2DefaultBodyDef();
  b2BodyId previous = b2CreateBody(world, &gd);
  const b2Capsule link{{-0.5f * kChainLink, 0.0f}, {0.5f * kChainLink, 0.0f}, kChainRadius};
  b2BodyDef bd = b2DefaultBodyDef();
  bd.type = b2_dynamicBody;
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.material.friction = 0.2f;
  for (int i = 0; i < kChainLinks; ++i) {
    const float x = kChainLink * static_cast<float>(i);
    bd.position = b2Vec2{x + 0.5f * kChainLink, 0.0f};
    const b2BodyId b = b2CreateBody(world, &bd);
    b2CreateCapsuleShape(b, &sd, &link);
    (void)pin(world, previous, b, b2Vec2{x, 0.0f});
    previous = b;
  }
}

}  // namespace

Run run(const std::string& scene, int workers, int steps) {
  b2WorldDef def = b2DefaultWorldDef();
  def.workerCount = workers;
  b2WorldId world = b2CreateWorld(&def);
  b2BodyId pusher = b2_nullBodyId;
  std::unique_ptr<Rain> rain;
  g_joints.clear();
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
  } else if (scene == "joint_grid") {
    jointGrid(world);
  } else if (scene == "rain") {
    rainFloors(world);
    rain = std::make_unique<Rain>();
  } else if (scene == "spinner") {
    spinner(world);
  } else if (scene == "tumbler") {
    tumbler(world);
  } else if (scene == "washer") {
    washer(world);
  } else if (scene == "chain") {
    chain(world);
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
    if (rain) rain->step(world, i);
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
  // The checks (v3 has no list of bodies to read: those on live joints are checked).
  for (b2JointId j : g_joints) {
    if (!b2Joint_IsValid(j)) continue;
    out.jointGap = std::max(out.jointGap, static_cast<double>(b2Joint_GetLinearSeparation(j)));
    for (b2BodyId b : {b2Joint_GetBodyA(j), b2Joint_GetBodyB(j)}) {
      const b2Vec2 p = b2Body_GetPosition(b), v = b2Body_GetLinearVelocity(b);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(v.x) ||
          !std::isfinite(v.y) || !std::isfinite(b2Body_GetAngularVelocity(b)))
        ++out.nonFinite;
    }
  }
  b2DestroyWorld(world);
  return out;
}

}  // namespace suite::v3
