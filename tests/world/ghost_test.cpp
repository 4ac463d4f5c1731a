// Ghost collisions: a body sliding or rolling over flush static shapes (separate tiles,
// separate bodies, chains) must not catch on the seams.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

// `count` separate static bodies of half-size `half` laid flush along y < 0, starting at x0.
void addTiles(World& world, int count, Vec2 half, float x0, ShapeDef def = {}) {
  for (int i = 0; i < count; ++i) {
    float x = x0 + (2.0f * static_cast<float>(i) + 1.0f) * half.x;
    testing::addStaticBox(world, {x, -half.y}, half, 0.0f, def);
  }
}

struct SlideFigures {
  float minSpeed = 1e9f, maxSpeed = 0.0f;  // horizontal, while over the tiles
  float maxVerticalSpeed = 0.0f;           // |vy| after settling
  float maxHeight = 0.0f;                  // of the box's bottom above the floor
  float maxAngle = 0.0f;
  float endX = 0.0f;
};

// A box of half-size `boxHalf` sliding at `speed` without friction over 100 tiles.
SlideFigures slideOverTiles(Vec2 tileHalf, float boxHalf, float speed, float offset) {
  World world = World::create({}).value();
  ShapeDef slick{.friction = 0.0f};
  addTiles(world, 100, tileHalf, 0.0f, slick);
  float end = 200.0f * tileHalf.x;
  BodyId box =
      world.createBody({.position = {1.0f + offset, boxHalf}, .linearVelocity = {speed, 0}})
          .value();
  (void)world.createShape(box, slick, makeBox(boxHalf, boxHalf).value()).value();
  SlideFigures f;
  for (int step = 0; step < 100000; ++step) {
    (void)world.step();
    Vec2 v = world.linearVelocity(box);
    Vec2 p = world.position(box);
    if (p.x > end - 1.0f - boxHalf) break;
    f.minSpeed = std::min(f.minSpeed, v.x);
    f.maxSpeed = std::max(f.maxSpeed, v.x);
    if (step > 10) f.maxVerticalSpeed = std::max(f.maxVerticalSpeed, std::fabs(v.y));
    f.maxHeight = std::max(f.maxHeight, p.y - boxHalf);
    f.maxAngle = std::max(f.maxAngle, std::fabs(world.angle(box)));
    f.endX = p.x;
  }
  return f;
}

TEST(Ghost, BoxSlidesOverOneHundredFlushTiles) {
  // Unit tiles and a unit box, then sizes and speeds that put the box's corners on the
  // seams at every phase.
  struct Case {
    Vec2 tileHalf;
    float boxHalf, speed, offset;
  };
  const Case cases[] = {{{0.5f, 0.5f}, 0.5f, 4.0f, 0.0f},
                        {{0.5f, 0.5f}, 0.5f, 10.0f, 0.0f},
                        {{0.5f, 0.5f}, 0.25f, 3.0f, 0.13f},
                        {{0.25f, 0.5f}, 0.4f, 6.0f, 0.05f},
                        {{1.0f, 0.2f}, 0.1f, 2.0f, 0.0f}};
  for (const Case& c : cases) {
    SlideFigures f = slideOverTiles(c.tileHalf, c.boxHalf, c.speed, c.offset);
    std::string what = "tiles " + std::to_string(2 * c.tileHalf.x) + " m, box " +
                       std::to_string(2 * c.boxHalf) + " m at " + std::to_string(c.speed) + " m/s";
    std::printf(
        "%s: speed %.4f..%.4f, max |vy| %.4f, max lift %.4f m, max angle %.4f, end x %.1f\n",
        what.c_str(), f.minSpeed, f.maxSpeed, f.maxVerticalSpeed, f.maxHeight, f.maxAngle, f.endX);
    EXPECT_GT(f.endX, 190.0f * c.tileHalf.x) << what;
    EXPECT_GT(f.minSpeed, 0.98f * c.speed) << what;
    EXPECT_LT(f.maxSpeed, 1.02f * c.speed) << what;
    EXPECT_LT(f.maxVerticalSpeed, 0.05f) << what;
    EXPECT_LT(f.maxHeight, 0.01f) << what;
  }
}

}  // namespace
}  // namespace quack
