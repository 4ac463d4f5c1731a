// The world suite: Box2D v3's benchmark scenes (those without joints, those with them) and a
// long hanging chain, in Quack and (when built with QUACK_BOX2D_V3_DIR) Box2D v3, side by
// side in one run. The joint scenes are laid out as Box2D v3's shared/benchmarks.c and
// shared/human.c (commit 617d32a), read for understanding; the code is ours.
//
//   world_suite [--scene NAME[,NAME...]] [--workers 1,2] [--runs 3] [--steps N]
//               [--only quack|v3] [--dynamic-pairs on|off]
//
// Each run builds the scene, times that, times the first step on its own and then the mean
// of the remaining steps (v3's step counts, suite.hpp). Runs alternate between the
// libraries; the table gives each figure's median over the runs, and the speed ratio
// v3 time / Quack time (above 1: Quack is faster). Both step at 60 Hz with 4 sub-steps, each
// with its own thread pool of `workers` threads. After the last step (untimed) each run
// checks its world: the last column gives the largest distance between a joint's two anchors
// (mm), and the table warns of any body whose position or velocity is not finite. For
// instruction counts run one library
// alone under callgrind: `valgrind --tool=callgrind world_suite --scene large_pyramid
// --only quack --runs 1 --steps 20`.
//
// `--dynamic-pairs off` runs Quack with WorldDef::sweepDynamicPairs off: fast bodies swept
// against static and kinematic shapes only, v3's rule, to measure what sweeping moving
// against moving costs. The default (on) is Quack's default and the suite's headline.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "quack/world/world.hpp"
#include "suite.hpp"

namespace suite {

double junkyardTargetX(int step) {
  return 60.0 * std::sin(0.2 * (static_cast<double>(step) / 60.0));
}

P2 rainGroupOrigin(int row, int column) {
  const float span = static_cast<float>(kRainGridCount) * kRainGridSize;
  const float spacing = span / static_cast<float>(kRainColumns);
  return {-0.5f * span + spacing * (static_cast<float>(column) + 0.5f),
          40.0f + 45.0f * static_cast<float>(row)};
}

bool rainSpawn(int step, int& column, bool& replace) {
  if ((step & 7) != 0) return false;
  const int event = step >> 3;
  replace = event >= kRainColumns;
  column = replace ? (event - kRainColumns) % kRainColumns : event;
  return true;
}

namespace {
P2 turn(float c, float s, P2 v) {
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}
P2 scaled(float k, P2 v) {
  return {k * v.x, k * v.y};
}
}  // namespace

std::array<P2, 360> spinnerRing() {
  // Clockwise, so that each one-sided segment faces the inside of the ring.
  const float angle = -2.0f * 3.14159265f / 360.0f;
  const float c = std::cos(angle), s = std::sin(angle);
  std::array<P2, 360> points;
  P2 p{40.0f, 0.0f};
  for (P2& q : points) {
    q = {p.x, p.y + 32.0f};
    p = turn(c, s, p);
  }
  return points;
}

std::array<std::array<P2, 4>, 40> washerPieces() {
  // 36 rim pieces between radii 16 and 18 m, each 10 degrees less a small gap, and every
  // 90 degrees a paddle between 14 and 16 m; in the order v3 adds them.
  const float r0 = 14.0f, r1 = 16.0f, r2 = 18.0f;
  const float angle = 3.14159265f / 18.0f;
  const float c = std::cos(angle), s = std::sin(angle);
  const float co = std::cos(0.1f * angle), so = std::sin(0.1f * angle);
  std::array<std::array<P2, 4>, 40> pieces;
  int n = 0;
  P2 u1{1.0f, 0.0f};
  for (int i = 0; i < 36; ++i) {
    const P2 u2 = i == 35 ? P2{1.0f, 0.0f} : turn(c, s, u1);
    const P2 a1 = turn(co, -so, u1), a2 = turn(co, so, u2);
    pieces[static_cast<std::size_t>(n++)] = {scaled(r1, a1), scaled(r2, a1), scaled(r1, a2),
                                             scaled(r2, a2)};
    if (i % 9 == 0)
      pieces[static_cast<std::size_t>(n++)] = {scaled(r0, u1), scaled(r1, u1), scaled(r0, u2),
                                               scaled(r1, u2)};
    u1 = u2;
  }
  return pieces;
}

namespace quackside {

using namespace quack;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Vec2 vec(double x, double y) {
  return {static_cast<float>(x), static_cast<float>(y)};
}

void pyramid(World& world, int rows, double left, double base) {
  const Polygon box = makeBox(0.5f, 0.5f).value();
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      BodyId b =
          world.createBody({.position = vec(left + 0.5 * row + i + 0.5, base + row + 0.5)}).value();
      (void)world.createShape(b, {}, box);
    }
  }
}

void largePyramid(World& world) {
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  (void)world.createShape(ground, {}, makeBox(100.0f, 1.0f, {0, -1}).value());
  pyramid(world, 100, -50.0, 0.0);
}

void manyPyramids(World& world) {
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  for (int r = 0; r < 20; ++r)
    (void)world.createShape(ground, {},
                            makeSegment(vec(-110, 11.0 * r), vec(110, 11.0 * r)).value());
  for (int r = 0; r < 20; ++r)
    for (int c = 0; c < 20; ++c)
      pyramid(world, 10, -110.0 + 11.0 * c + 0.5, 11.0 * r);
}

void smash(World& world) {
  BodyId heavy = world.createBody({.position = {-20, 0}, .linearVelocity = {40, 0}}).value();
  (void)world.createShape(heavy, {.density = 8.0f}, makeBox(4.0f, 4.0f).value());
  const Polygon small = makeBox(0.2f, 0.2f).value();
  for (int i = 0; i < 120; ++i) {
    for (int j = 0; j < 80; ++j) {
      BodyId b =
          world.createBody({.position = vec(30.0 + 0.4 * i, 0.4 * (j - 40)), .isAwake = false})
              .value();
      (void)world.createShape(b, {}, small);
      (void)world.setAwake(b, false);
    }
  }
}

void pit(World& world, BodyId ground, int floor, int wall, double half) {
  for (int i = 0; i < floor; ++i)
    (void)world.createShape(ground, {}, makeBox(0.55f, 0.5f, vec(-half + i, 0)).value());
  for (int i = 0; i < wall; ++i) {
    (void)world.createShape(ground, {}, makeBox(0.5f, 0.55f, vec(-half, 1.0 + i)).value());
    (void)world.createShape(ground, {}, makeBox(0.5f, 0.55f, vec(half, 1.0 + i)).value());
  }
}

BodyId junkyard(World& world) {
  pit(world, world.createBody({.type = BodyType::staticBody}).value(), 161, 50, 80.0);
  Vec2 points[5];
  const double golden = 3.14159265358979 * (std::sqrt(5.0) - 1.0);
  for (int i = 0; i < 5; ++i)
    points[i] = vec(0.25 * std::cos(golden * i), 0.25 * std::sin(golden * i));
  const Polygon pentagon = makePolygon(points).value();
  double side = -0.1;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 40; ++j) {
      BodyId b =
          world.createBody({.position = vec(0.375 * (2 * i - 200) + side, 15.0 + j)}).value();
      side = -side;
      (void)world.createShape(b, {}, pentagon);
    }
  }
  BodyId pusher = world.createBody({.type = BodyType::kinematicBody}).value();
  (void)world.createShape(pusher, {}, makeBox(2.0f, 4.0f, {0, 4}).value());
  return pusher;
}

void compounds(World& world) {
  BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  pit(world, ground, 81, 100, 40.0);
  (void)world.createShape(ground, {}, makeSegment({-800, -80}, {800, -80}).value());
  const Vec2 leftPoints[3] = {{-1, 0}, {0.5f, 1}, {0, 2}};
  const Vec2 rightPoints[3] = {{1, 0}, {-0.5f, 1}, {0, 2}};
  const Polygon left = makePolygon(leftPoints).value();
  const Polygon right = makePolygon(rightPoints).value();
  const ShapeDef def{.friction = 0.5f};
  double side = 0.25;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 150; ++j) {
      BodyId b =
          world.createBody({.position = vec(2.0 * i - 19.0 + side, 2.25 * j + 5.575)}).value();
      side = -side;
      (void)world.createShape(b, def, left);
      (void)world.createShape(b, def, right);
    }
  }
}

Vec2 vec(P2 p) {
  return {p.x, p.y};
}

JointId revolute(World& world, BodyId a, BodyId b, Vec2 anchor) {
  return world.createJoint({.type = JointType::revolute, .bodyA = a, .bodyB = b, .anchorA = anchor})
      .value();
}

void jointGrid(World& world) {
  constexpr int n = kJointGridN;
  // v3's filter: category 2, colliding with every category but 2, so no circle meets another.
  const ShapeDef sd{.filter = {.category = 2, .mask = ~std::uint64_t{2}}};
  const Circle circle = makeCircle({}, 0.4f).value();
  std::vector<BodyId> bodies;
  bodies.reserve(static_cast<std::size_t>(n * n));
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) {
      const bool fixed = jointGridStatic(k, i);
      const BodyId b =
          world
              .createBody({.type = fixed ? BodyType::staticBody : BodyType::dynamicBody,
                           .position = vec(k, -i)})
              .value();
      (void)world.createShape(b, sd, circle);
      const std::size_t at = bodies.size();
      if (i > 0) (void)revolute(world, bodies[at - 1], b, vec(k, 0.5 - i));
      // v3 also joins the static neighbours of the top row to each other (6 joints that do
      // nothing); Quack refuses a joint with no dynamic body, so those are left out.
      if (k > 0 && !(fixed && jointGridStatic(k - 1, i)))
        (void)revolute(world, bodies[at - static_cast<std::size_t>(n)], b, vec(k - 0.5, -i));
      bodies.push_back(b);
    }
  }
}

// One ragdoll of the rain, and what destroying it needs.
struct Figure {
  std::array<BodyId, kBones.size()> bodies;
  std::array<JointId, kBones.size()> joints;  // joints[0], the hip's, is unused
  bool live = false;
};

void spawnFigure(World& world, Figure& f, Vec2 origin, int group) {
  const Filter body{.category = 2, .mask = 1 | 2, .group = -group};
  const Filter foot{.category = 2, .mask = 1, .group = -group};
  const std::array<Vec2, 4> footPoints{vec(kFoot[0]), vec(kFoot[1]), vec(kFoot[2]), vec(kFoot[3])};
  const Polygon footShape = makePolygon(footPoints, kFootRadius).value();
  for (std::size_t i = 0; i < kBones.size(); ++i) {
    const Bone& bone = kBones[i];
    const Vec2 at = origin + Vec2{0.0f, bone.y};
    const Vec2 pivot = origin + Vec2{0.0f, bone.pivotY};
    // v3 measures a joint's angle between frames on the bodies, and turns the lower arm's
    // frame on the upper arm by frameTurn: its rest angle (limits and spring) is then
    // -frameTurn from the layout. Quack measures from the angle at creation, so the lower
    // arm is created turned by frameTurn about its pivot, jointed, and set back.
    const float turnBy = bone.frameTurn * kPi;
    const Transform turned = makeTransform(pivot, turnBy);
    const BodyDef def{.position = turnBy != 0.0f ? transformPoint(turned, at - pivot) : at,
                      .angle = turnBy,
                      .linearDamping = bone.linearDamping,
                      .sleepThreshold = kBoneSleepThreshold};
    const BodyId b = world.createBody(def).value();
    f.bodies[i] = b;
    (void)world.createShape(
        b, {.friction = 0.2f, .filter = body},
        makeCapsule({0.0f, bone.capsuleLow}, {0.0f, bone.capsuleHigh}, bone.radius).value());
    if (bone.foot) (void)world.createShape(b, {.friction = 0.05f, .filter = foot}, footShape);
    if (bone.parent < 0) continue;
    f.joints[i] = world
                      .createJoint({.type = JointType::revolute,
                                    .bodyA = f.bodies[static_cast<std::size_t>(bone.parent)],
                                    .bodyB = b,
                                    .anchorA = pivot,
                                    .enableLimit = true,
                                    .lower = bone.lower * kPi,
                                    .upper = bone.upper * kPi,
                                    .enableMotor = true,
                                    .motorSpeed = 0.0f,
                                    .maxMotorTorque = bone.frictionScale * kJointFriction,
                                    .enableSpring = true,
                                    .hertz = kBoneHertz,
                                    .dampingRatio = kBoneDamping})
                      .value();
    if (turnBy != 0.0f) (void)world.setTransform(b, at, 0.0f);
  }
  f.live = true;
}

void destroyFigure(World& world, Figure& f) {
  for (std::size_t i = 1; i < kBones.size(); ++i)
    (void)world.destroyJoint(f.joints[i]);
  for (BodyId b : f.bodies)
    (void)world.destroyBody(b);
  f.live = false;
}

struct Rain {
  std::vector<Figure> figures =
      std::vector<Figure>(static_cast<std::size_t>(kRainRows * kRainColumns * kRainGroupSize));
  void spawn(World& world, int row, int column) {
    const P2 o = rainGroupOrigin(row, column);
    for (int i = 0; i < kRainGroupSize; ++i) {
      Figure& f =
          figures[static_cast<std::size_t>((row * kRainColumns + column) * kRainGroupSize + i)];
      if (f.live) destroyFigure(world, f);
      spawnFigure(world, f, {o.x + 0.5f * static_cast<float>(i), o.y}, i + 1);
    }
  }
  void step(World& world, int step) {
    int column = 0;
    bool replace = false;
    if (!rainSpawn(step, column, replace)) return;
    for (int row = 0; row < kRainRows; ++row)
      spawn(world, row, column);
  }
};

void rainFloors(World& world) {
  const BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  float y = 0.0f;
  for (int r = 0; r < kRainRows; ++r) {
    float x = -0.5f * static_cast<float>(kRainGridCount) * kRainGridSize;
    for (int j = 0; j <= kRainGridCount; ++j) {
      (void)world.createShape(ground, {},
                              makeBox(0.5f * kRainGridSize, 0.5f * kRainGridSize, {x, y}).value());
      x += kRainGridSize;
    }
    y += 45.0f;
  }
}

void spinner(World& world) {
  const BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  const std::array<P2, 360> ring = spinnerRing();
  std::array<Vec2, 360> points;
  for (std::size_t i = 0; i < ring.size(); ++i)
    points[i] = vec(ring[i]);
  (void)world.createChain(ground, {.friction = 0.1f}, points, true).value();
  const BodyId paddle = world.createBody({.position = {0.0f, 12.0f}, .enableSleep = false}).value();
  (void)world.createShape(paddle, {.friction = 0.0f}, makeBox(0.4f, 20.0f, {}, 0.0f, 0.2f).value());
  // v3's motor has no torque bound (FLT_MAX): the paddle turns at 5 rad/s whatever it meets.
  (void)world
      .createJoint({.type = JointType::revolute,
                    .bodyA = ground,
                    .bodyB = paddle,
                    .anchorA = {0.0f, 12.0f},
                    .enableMotor = true,
                    .motorSpeed = 5.0f,
                    .maxMotorTorque = std::numeric_limits<float>::max()})
      .value();
  const Capsule capsule = makeCapsule({-0.25f, 0.0f}, {0.25f, 0.0f}, 0.25f).value();
  const Circle circle = makeCircle({}, 0.35f).value();
  const Polygon square = makeBox(0.35f, 0.35f).value();
  const ShapeDef sd{.density = 0.25f, .friction = 0.1f, .restitution = 0.1f};
  float x = -23.0f, y = 2.0f;
  for (int i = 0; i < kSpinnerBodies; ++i) {
    const BodyId b = world.createBody({.position = {x, y}}).value();
    if (i % 3 == 0) {
      (void)world.createShape(b, sd, capsule);
    } else if (i % 3 == 1) {
      (void)world.createShape(b, sd, circle);
    } else {
      (void)world.createShape(b, sd, square);
    }
    x += 0.5f;
    if (x >= 23.0f) {
      x = -23.0f;
      y += 0.5f;
    }
  }
}

void tumbler(World& world) {
  const BodyId ground = world.createBody({.type = BodyType::staticBody}).value();
  const BodyId drum = world.createBody({.position = {0.0f, 10.0f}}).value();
  const ShapeDef heavy{.density = 50.0f};
  (void)world.createShape(drum, heavy, makeBox(0.5f, 10.0f, {10.0f, 0.0f}).value());
  (void)world.createShape(drum, heavy, makeBox(0.5f, 10.0f, {-10.0f, 0.0f}).value());
  (void)world.createShape(drum, heavy, makeBox(10.0f, 0.5f, {0.0f, 10.0f}).value());
  (void)world.createShape(drum, heavy, makeBox(10.0f, 0.5f, {0.0f, -10.0f}).value());
  (void)world
      .createJoint({.type = JointType::revolute,
                    .bodyA = ground,
                    .bodyB = drum,
                    .anchorA = {0.0f, 10.0f},
                    .enableMotor = true,
                    .motorSpeed = (kPi / 180.0f) * 25.0f,
                    .maxMotorTorque = 1.0e8f})
      .value();
  constexpr int n = 45;
  const Polygon box = makeBox(0.125f, 0.125f).value();
  float y = -0.2f * n + 10.0f;
  for (int i = 0; i < n; ++i) {
    float x = -0.2f * n;
    for (int j = 0; j < n; ++j) {
      (void)world.createShape(world.createBody({.position = {x, y}}).value(), {}, box);
      x += 0.4f;
    }
    y += 0.4f;
  }
}

void washer(World& world) {
  // v3's washer turns its drum as a kinematic body (its motor-joint variant is switched off
  // in v3's code), drifting slowly as v3 sets it.
  const BodyId drum = world
                          .createBody({.type = BodyType::kinematicBody,
                                       .position = {0.0f, 10.0f},
                                       .linearVelocity = {0.001f, -0.002f},
                                       .angularVelocity = (kPi / 180.0f) * 25.0f})
                          .value();
  for (const std::array<P2, 4>& piece : washerPieces()) {
    const std::array<Vec2, 4> points{vec(piece[0]), vec(piece[1]), vec(piece[2]), vec(piece[3])};
    (void)world.createShape(drum, {}, makePolygon(points).value());
  }
  constexpr int n = 90;
  const float a = 0.1f;
  const Polygon box = makeBox(a, a).value();
  float y = -1.1f * a * n + 10.0f;
  for (int i = 0; i < n; ++i) {
    float x = -1.1f * a * n;
    for (int j = 0; j < n; ++j) {
      (void)world.createShape(world.createBody({.position = {x, y}}).value(), {}, box);
      x += 2.1f * a;
    }
    y += 2.1f * a;
  }
}

void chain(World& world) {
  BodyId previous = world.createBody({.type = BodyType::staticBody}).value();
  const Capsule link =
      makeCapsule({-0.5f * kChainLink, 0.0f}, {0.5f * kChainLink, 0.0f}, kChainRadius).value();
  for (int i = 0; i < kChainLinks; ++i) {
    const float x = kChainLink * static_cast<float>(i);
    const BodyId b = world.createBody({.position = {x + 0.5f * kChainLink, 0.0f}}).value();
    (void)world.createShape(b, {.friction = 0.2f}, link);
    (void)revolute(world, previous, b, {x, 0.0f});
    previous = b;
  }
}

// The checks after a run: the largest anchor separation of a live joint, and the bodies
// whose state is not finite.
void check(const World& world, Run& out) {
  for (JointId j : world.joints()) {
    const auto [a, b] = world.jointAnchors(j);
    out.jointGap = std::max(out.jointGap, static_cast<double>(length(b - a)));
  }
  for (BodyId b : world.bodies()) {
    const Transform xf = world.transform(b);
    if (!isFinite(xf.p) || !std::isfinite(world.angle(b)) || !isFinite(world.linearVelocity(b)) ||
        !std::isfinite(world.angularVelocity(b)))
      ++out.nonFinite;
  }
}

bool gSweepDynamicPairs = true;  // --dynamic-pairs

Run run(const std::string& scene, int workers, int steps) {
  const bool noSleep =
      scene == "large_pyramid" || scene == "many_pyramids" || scene == "joint_grid";
  WorldDef def{.enableSleep = !noSleep, .workerCount = workers};
  def.sweepDynamicPairs = gSweepDynamicPairs;
  if (scene == "smash") def.gravity = {0, 0};
  Run out;
  auto t0 = Clock::now();
  World world = World::create(def).value();
  BodyId pusher;
  bool hasPusher = false;
  std::unique_ptr<Rain> rain;
  if (scene == "large_pyramid") {
    largePyramid(world);
  } else if (scene == "many_pyramids") {
    manyPyramids(world);
  } else if (scene == "smash") {
    smash(world);
  } else if (scene == "junkyard") {
    pusher = junkyard(world);
    hasPusher = true;
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
    throw std::invalid_argument("no scene " + scene);
  }
  out.buildMs = msSince(t0);
  constexpr float dt = 1.0f / 60.0f;
  // What the scene does before step i (timed with the step, as in v3's benchmark program).
  auto step = [&](int i) {
    if (hasPusher) {
      // What v3's b2Body_SetTargetTransform does: the velocity that reaches the target in dt.
      const float x = world.position(pusher).x;
      (void)world.setLinearVelocity(
          pusher, {static_cast<float>((junkyardTargetX(i) - static_cast<double>(x)) /
                                      static_cast<double>(dt)),
                   0.0f});
    }
    if (rain) rain->step(world, i);
    world.step(dt, 4);
  };
  t0 = Clock::now();
  step(0);
  out.firstStepMs = msSince(t0);
  t0 = Clock::now();
  for (int i = 1; i < steps; ++i)
    step(i);
  out.msPerStep = steps > 1 ? msSince(t0) / (steps - 1) : 0.0;
  out.contacts = static_cast<long>(world.contactCount());
  out.awake = static_cast<long>(world.awakeBodyCount());
  check(world, out);
  return out;
}

}  // namespace quackside
}  // namespace suite

#if !QUACK_HAVE_BOX2D_V3
namespace suite::v3 {
Run run(const std::string&, int, int) {
  throw std::runtime_error("built without Box2D v3 (configure with -DQUACK_BOX2D_V3_DIR=...)");
}
}  // namespace suite::v3
#endif

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= s.size()) {
    const std::size_t comma = s.find(',', at);
    const std::size_t end = comma == std::string::npos ? s.size() : comma;
    if (end > at) out.push_back(s.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

std::string fixed(double x, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, x);
  return text;
}

int usage(const char* why) {
  std::fprintf(stderr,
               "world_suite: %s\nusage: world_suite [--scene NAME[,NAME...]] [--workers 1,2] "
               "[--runs 3] [--steps N] [--only quack|v3] [--dynamic-pairs on|off]\n",
               why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes;
  std::vector<int> workers{1, 2};
  int runs = 3, steps = 0;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) return usage(("missing value after " + arg).c_str());
    const std::string value = argv[++i];
    if (arg == "--scene") {
      scenes = split(value);
    } else if (arg == "--workers") {
      workers.clear();
      for (const std::string& w : split(value))
        workers.push_back(std::atoi(w.c_str()));
    } else if (arg == "--runs") {
      runs = std::atoi(value.c_str());
    } else if (arg == "--steps") {
      steps = std::atoi(value.c_str());
    } else if (arg == "--only") {
      only = value;
    } else if (arg == "--dynamic-pairs") {
      if (value != "on" && value != "off") return usage("--dynamic-pairs takes on or off");
      suite::quackside::gSweepDynamicPairs = value == "on";
    } else {
      return usage(("unknown option " + arg).c_str());
    }
  }
  if (runs < 1) return usage("--runs must be >= 1");
  for (int w : workers)
    if (w < 1 || w > 64) return usage("--workers must be in 1..64");
  if (only != "" && only != "quack" && only != "v3") return usage("--only takes quack or v3");
  const bool withV3 = QUACK_HAVE_BOX2D_V3 && only != "quack";
  const bool withQuack = only != "v3";
  if (only == "v3" && !QUACK_HAVE_BOX2D_V3) return usage("built without Box2D v3");
  if (scenes.empty())
    for (const suite::SceneInfo& s : suite::kScenes)
      scenes.push_back(s.name);
  std::printf("%-14s %3s | %9s %9s %6s | %9s %9s %6s | %8s %8s | %8s %8s | %-13s | %s\n", "scene",
              "thr", "Quack ms", "v3 ms", "speed", "Q first", "v3 first", "speed", "Q build",
              "v3 build", "Q cont", "v3 cont", "awake Q/v3", "joint gap mm Q/v3");
  for (const std::string& name : scenes) {
    int sceneSteps = 0;
    for (const suite::SceneInfo& s : suite::kScenes)
      if (name == s.name) sceneSteps = s.steps;
    if (sceneSteps == 0) return usage(("no scene " + name).c_str());
    if (steps > 0) sceneSteps = steps;
    for (int w : workers) {
      std::vector<double> q[3], v[3];
      suite::Run lastQ, lastV;
      for (int r = 0; r < runs; ++r) {
        if (withQuack) {
          lastQ = suite::quackside::run(name, w, sceneSteps);
          q[0].push_back(lastQ.msPerStep);
          q[1].push_back(lastQ.firstStepMs);
          q[2].push_back(lastQ.buildMs);
        }
        if (withV3) {
          lastV = suite::v3::run(name, w, sceneSteps);
          v[0].push_back(lastV.msPerStep);
          v[1].push_back(lastV.firstStepMs);
          v[2].push_back(lastV.buildMs);
        }
      }
      const double qs = median(q[0]), vs = median(v[0]), qf = median(q[1]), vf = median(v[1]);
      if (withQuack && withV3) {
        const std::string awake = std::to_string(lastQ.awake) + "/" + std::to_string(lastV.awake);
        std::printf(
            "%-14s %3d | %9.3f %9.3f %5.2fx | %9.2f %9.2f %5.2fx | %8.1f %8.1f | %8ld %8ld | "
            "%-13s | %.3f/%.3f\n",
            name.c_str(), w, qs, vs, vs / qs, qf, vf, vf / qf, median(q[2]), median(v[2]),
            lastQ.contacts, lastV.contacts, awake.c_str(), 1e3 * lastQ.jointGap,
            1e3 * lastV.jointGap);
      } else {
        // One library: its figures in its columns, the other's and the ratios left blank.
        const bool q1 = withQuack;
        const suite::Run& last = q1 ? lastQ : lastV;
        const double ms = q1 ? qs : vs, first = q1 ? qf : vf, build = median(q1 ? q[2] : v[2]);
        const std::string gap =
            q1 ? fixed(1e3 * last.jointGap, 3) + "/-" : "-/" + fixed(1e3 * last.jointGap, 3);
        std::printf("%-14s %3d | %9s %9s %6s | %9s %9s %6s | %8s %8s | %8s %8s | %-13s | %s\n",
                    name.c_str(), w, q1 ? fixed(ms, 3).c_str() : "-",
                    q1 ? "-" : fixed(ms, 3).c_str(), "-", q1 ? fixed(first, 2).c_str() : "-",
                    q1 ? "-" : fixed(first, 2).c_str(), "-", q1 ? fixed(build, 1).c_str() : "-",
                    q1 ? "-" : fixed(build, 1).c_str(),
                    q1 ? std::to_string(last.contacts).c_str() : "-",
                    q1 ? "-" : std::to_string(last.contacts).c_str(),
                    std::to_string(last.awake).c_str(), gap.c_str());
      }
      for (const suite::Run* last : {withQuack ? &lastQ : nullptr, withV3 ? &lastV : nullptr})
        if (last != nullptr && last->nonFinite > 0)
          std::printf("  warning: %s: %ld bodies with a position or velocity not finite\n",
                      last == &lastQ ? "Quack" : "v3", last->nonFinite);
      std::fflush(stdout);
    }
  }
  return 0;
}
