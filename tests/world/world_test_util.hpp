#pragma once
// Scene builders shared by the world tests.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "quack/world/world.hpp"

namespace quack::testing {

// One step, then World::validate (every cross-reference checked), as the tree tests do
// after every operation.
inline ::testing::AssertionResult stepAndValidate(World& world) {
  StepStatus s = world.step();
  if (!s) return ::testing::AssertionFailure() << "step: " << s.message();
  Status v = world.validate();
  if (!v)
    return ::testing::AssertionFailure()
           << "validate after step " << world.stepCount() << ": " << v.message();
  return ::testing::AssertionSuccess();
}

// World::validate as an assertion, for after creation and destruction.
inline ::testing::AssertionResult valid(const World& world) {
  Status v = world.validate();
  if (!v) return ::testing::AssertionFailure() << "validate: " << v.message();
  return ::testing::AssertionSuccess();
}

inline BodyId addStaticBox(World& world, Vec2 center, Vec2 half, float angle = 0.0f,
                           ShapeDef def = {}) {
  BodyId b =
      world.createBody({.type = BodyType::staticBody, .position = center, .angle = angle}).value();
  (void)world.createShape(b, def, makeBox(half.x, half.y).value()).value();
  return b;
}

inline BodyId addBox(World& world, Vec2 center, Vec2 half, float angle = 0.0f, ShapeDef def = {}) {
  BodyId b = world.createBody({.position = center, .angle = angle}).value();
  (void)world.createShape(b, def, makeBox(half.x, half.y).value()).value();
  return b;
}

inline BodyId addBall(World& world, Vec2 center, float radius, ShapeDef def = {}) {
  BodyId b = world.createBody({.position = center}).value();
  (void)world.createShape(b, def, makeCircle({}, radius).value()).value();
  return b;
}

// A pyramid of unit boxes (half-extent `half`) standing on y = 0, `rows` at the bottom.
inline std::vector<BodyId> addPyramid(World& world, int rows, float half = 0.5f,
                                      ShapeDef def = {}) {
  std::vector<BodyId> boxes;
  for (int row = 0; row < rows; ++row) {
    for (int i = 0; i < rows - row; ++i) {
      float x = (static_cast<float>(i) - 0.5f * static_cast<float>(rows - row - 1)) * 2.0f * half;
      float y = half + static_cast<float>(row) * 2.0f * half;
      boxes.push_back(addBox(world, {x, y}, {half, half}, 0.0f, def));
    }
  }
  return boxes;
}

// One of four shapes on `body`, by kind % 4: a circle of radius 0.2 - 0.5 m, a box 0.4 -
// 1.2 m wide and 0.5 m tall, a 1.6 m capsule, or `fourth`. `draw()` (a number in [0, 1))
// is called only for the circle's radius and the box's width, so a scene's random stream
// is the same whichever shapes it makes.
template <class Draw>
void addMixedShape(World& world, BodyId body, const ShapeDef& def, int kind, Draw&& draw,
                   const Polygon& fourth) {
  switch (kind % 4) {
    case 0:
      (void)world.createShape(body, def, makeCircle({}, 0.2f + 0.3f * draw()).value());
      break;
    case 1:
      (void)world.createShape(body, def, makeBox(0.2f + 0.4f * draw(), 0.25f).value());
      break;
    case 2:
      (void)world.createShape(body, def, makeCapsule({-0.4f, 0}, {0.4f, 0}, 0.2f).value());
      break;
    default:
      (void)world.createShape(body, def, fourth);
  }
}

}  // namespace quack::testing
