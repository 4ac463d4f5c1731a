// World3 snapshots: a world restored from one steps on to the same bits as the world it was
// taken from (against that world itself, step by step), handles stay valid, and bad bytes
// are refused by name with the world left as it was.

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <vector>

#include "quack/world/world3.hpp"

namespace quack {
namespace {

// A mixed pile (boxes, spheres, capsules, hulls) on a mesh floor with a box pedestal.
struct Pile {
  World3 world = World3::create().value();
  std::vector<BodyId3> bodies;
  Pile() {
    const std::array<Vec3, 4> v = {Vec3{-20, 0, -20}, Vec3{-20, 0, 20}, Vec3{20, 0, 20},
                                   Vec3{20, 0, -20}};
    const std::array<std::array<std::int32_t, 3>, 2> t = {{{0, 1, 2}, {0, 2, 3}}};
    const BodyId3 floor = world.createBody({.type = BodyType::staticBody}).value();
    EXPECT_TRUE(world.createShape(floor, {}, makeMesh3(v, t).value()).ok());
    EXPECT_TRUE(
        world.createShape(floor, {}, makeBox3({0.5f, 0.5f, 0.5f}, {{2, 0.5f, 0}, {}}).value())
            .ok());
    const std::array<Vec3, 6> points = {Vec3{0.4f, 0, 0},  Vec3{-0.4f, 0, 0},
                                        Vec3{0, 0.3f, 0},  Vec3{0, -0.3f, 0},
                                        Vec3{0, 0, 0.35f}, Vec3{0.1f, 0.1f, -0.3f}};
    const Hull3 hull = makeHull3(points).value();
    for (int i = 0; i < 20; ++i) {
      const float fi = float(i);
      const BodyId3 b =
          world
              .createBody({.position = {0.9f * float(i % 4) - 1.0f, 0.8f + 0.7f * float(i / 4),
                                        0.5f * float((i / 2) % 2) + 0.05f * fi},
                           .rotation = Quat::fromAxisAngle({0, 1, 0}, 0.3f * fi)})
              .value();
      if (i % 4 == 0) (void)world.createShape(b, {}, makeBox3({0.3f, 0.25f, 0.3f}).value());
      if (i % 4 == 1) (void)world.createShape(b, {.rollingResistance = 0.1f}, Sphere{{}, 0.3f});
      if (i % 4 == 2) (void)world.createShape(b, {}, Capsule3{{-0.25f, 0, 0}, {0.25f, 0, 0}, 0.2f});
      if (i % 4 == 3) (void)world.createShape(b, {}, hull);
      bodies.push_back(b);
    }
  }
};

// Every body's pose and velocities, bitwise.
std::vector<float> state(const World3& world, const std::vector<BodyId3>& bodies) {
  std::vector<float> out;
  for (BodyId3 b : bodies) {
    const Transform3 xf = world.transform(b);
    const Vec3 v = world.linearVelocity(b), w = world.angularVelocity(b);
    out.insert(out.end(), {xf.p.x, xf.p.y, xf.p.z, xf.q.x, xf.q.y, xf.q.z, xf.q.w, v.x, v.y, v.z,
                           w.x, w.y, w.z, world.isAwake(b) ? 1.0f : 0.0f});
  }
  return out;
}

bool same(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(World3Snapshot, ARestoredWorldStepsOnToTheSameBits) {
  Pile pile;
  for (int s = 0; s < 50; ++s)
    ASSERT_TRUE(pile.world.step().ok());
  ASSERT_GT(pile.world.touchingContactCount(), 10u);
  const std::vector<std::uint8_t> bytes = pile.world.snapshot();
  // Taking a snapshot changes nothing, and two are the same bytes.
  EXPECT_EQ(bytes, pile.world.snapshot());

  World3 copy = World3::fromSnapshot(bytes).value();
  EXPECT_NE(copy.id(), pile.world.id());
  // The same handles (re-stamped with the copy's world id) name the same bodies.
  std::vector<BodyId3> copyBodies;
  for (BodyId3 b : pile.bodies)
    copyBodies.push_back({b.index, b.generation, copy.id()});
  for (BodyId3 b : copyBodies)
    ASSERT_TRUE(copy.isValid(b));
  // Restored into another world as well (its own id kept).
  Pile other;
  ASSERT_TRUE(other.world.restore(bytes).ok());
  std::vector<BodyId3> otherBodies;
  for (BodyId3 b : pile.bodies)
    otherBodies.push_back({b.index, b.generation, other.world.id()});

  EXPECT_TRUE(same(state(copy, copyBodies), state(pile.world, pile.bodies)));
  int asleep = 0;
  for (int s = 0; s < 150; ++s) {
    ASSERT_TRUE(pile.world.step().ok());
    ASSERT_TRUE(copy.step().ok());
    ASSERT_TRUE(other.world.step().ok());
    const std::vector<float> want = state(pile.world, pile.bodies);
    ASSERT_TRUE(same(state(copy, copyBodies), want)) << "step " << s;
    ASSERT_TRUE(same(state(other.world, otherBodies), want)) << "step " << s;
    ASSERT_EQ(copy.events().begin.size(), pile.world.events().begin.size()) << "step " << s;
    ASSERT_EQ(copy.events().end.size(), pile.world.events().end.size()) << "step " << s;
  }
  for (BodyId3 b : pile.bodies)
    asleep += pile.world.isAwake(b) ? 0 : 1;
  EXPECT_GT(asleep, 0);  // the run reached sleeping islands too
}

TEST(World3Snapshot, BadBytesAreRefusedByNameAndChangeNothing) {
  Pile pile;
  for (int s = 0; s < 20; ++s)
    ASSERT_TRUE(pile.world.step().ok());
  const std::vector<std::uint8_t> good = pile.world.snapshot();
  const std::vector<float> before = state(pile.world, pile.bodies);
  auto refused = [&](std::vector<std::uint8_t> bytes, const char* words) {
    const Status s = pile.world.restore(bytes);
    EXPECT_FALSE(s.ok()) << words;
    if (!s.ok()) {
      EXPECT_NE(s.message().find(words), std::string::npos) << s.message();
    }
    EXPECT_TRUE(same(state(pile.world, pile.bodies), before));
    EXPECT_FALSE(World3::fromSnapshot(bytes).ok());
  };
  refused({}, "not a 3D world snapshot");
  std::vector<std::uint8_t> b = good;
  b[0] = 'X';
  refused(b, "not a 3D world snapshot");
  b = good;
  b[8] = static_cast<std::uint8_t>(kSnapshot3FormatVersion + 1);
  refused(b, "format version");
  b = good;
  b.resize(b.size() - 5);
  refused(b, "truncated");
  b = good;
  b[b.size() / 2] ^= 0x10;
  refused(b, "checksum");
  // The good bytes still restore, and the world steps on.
  ASSERT_TRUE(pile.world.restore(good).ok());
  EXPECT_TRUE(same(state(pile.world, pile.bodies), before));
  EXPECT_TRUE(pile.world.step().ok());
}

}  // namespace
}  // namespace quack
