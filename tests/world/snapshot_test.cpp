// World::snapshot, restore and fromSnapshot (docs/determinism.md, "Snapshots"): stepping on
// from a restored world gives the same bits as stepping on from the original, for every
// broad phase, with sleeping on and off; bad snapshots are refused by name and change
// nothing.

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "quack/world/world.hpp"
#include "world_test_util.hpp"

namespace quack {
namespace {

using testing::addBall;
using testing::addBox;
using testing::addPyramid;
using testing::addStaticBox;
using testing::valid;
using Bytes = std::vector<std::uint8_t>;

// Everything a step reports, flattened, so that two runs can be compared event for event.
struct Trace {
  std::vector<std::uint64_t> hashes;
  std::vector<std::string> events;
};

std::string describeEvents(const StepEvents& e) {
  std::string s;
  auto id = [](ShapeId x) {
    return std::to_string(x.index) + "/" + std::to_string(x.generation) + " ";
  };
  for (const auto& b : e.begin)
    s += "b" + id(b.shapeA) + id(b.shapeB);
  for (const auto& b : e.end)
    s += "e" + id(b.shapeA) + id(b.shapeB);
  for (const auto& h : e.hit)
    s += "h" + id(h.shapeA) + id(h.shapeB) + std::to_string(h.approachSpeed) + " ";
  for (const auto& b : e.sensorBegin)
    s += "sb" + id(b.sensor) + id(b.visitor);
  for (const auto& b : e.sensorEnd)
    s += "se" + id(b.sensor) + id(b.visitor);
  for (const auto& t : e.toi)
    s += "t" + id(t.shapeA) + id(t.shapeB) + std::to_string(t.time) + " ";
  for (BodyId b : e.outOfBounds)
    s += "o" + std::to_string(b.index) + " ";
  return s;
}

Trace run(World& world, int steps) {
  Trace t;
  for (int i = 0; i < steps; ++i) {
    EXPECT_TRUE(testing::stepAndValidate(world));
    t.hashes.push_back(world.stateHash());
    t.events.push_back(describeEvents(world.events()));
  }
  return t;
}

Bytes take(const World& world, SnapshotKind kind = SnapshotKind::full) {
  Result<Bytes> s = world.snapshot(kind);
  EXPECT_TRUE(s.ok()) << (s ? "" : s.error().message);
  return s ? s.value() : Bytes{};
}

// A mixed scene that reaches every part: a pyramid that settles and sleeps, balls, a
// bullet through a thin wall, a kinematic platform, a sensor, a chain and flush tiles
// (ghost edges), a compound body, forces. Bodies are created and destroyed first so that
// slots carry generations above 1 and free lists are not empty.
World makeScene(BroadPhaseKind kind, bool sleep) {
  World world = World::create({.broadPhase = kind, .enableSleep = sleep}).value();
  // Churn: slots reused with new generations, free lists left non-empty.
  for (int i = 0; i < 4; ++i) {
    BodyId b = addBall(world, {30.0f + static_cast<float>(i), 5.0f}, 0.3f);
    if (i % 2 == 0) {
      EXPECT_TRUE(world.destroyBody(b).ok());
    }
  }
  addStaticBox(world, {0.0f, -0.5f}, {20.0f, 0.5f});
  // Flush tiles and a chain on the right.
  for (int i = 0; i < 4; ++i)
    addStaticBox(world, {22.0f + static_cast<float>(i), -0.5f}, {0.5f, 0.5f});
  BodyId chainBody = world.createBody({.type = BodyType::staticBody}).value();
  const Vec2 chain[] = {{34.0f, 0.0f}, {30.0f, 0.0f}, {27.0f, 1.0f}};
  EXPECT_TRUE(world.createChain(chainBody, {}, chain).ok());
  addPyramid(world, 6);
  for (int i = 0; i < 5; ++i)
    addBall(world, {-8.0f + static_cast<float>(i), 4.0f + static_cast<float>(i)}, 0.4f,
            {.restitution = 0.5f});
  // A thin wall and a bullet.
  addStaticBox(world, {-15.0f, 2.0f}, {0.05f, 2.0f});
  BodyId bullet =
      world
          .createBody(
              {.position = {-10.0f, 1.0f}, .linearVelocity = {-200.0f, 0.0f}, .bullet = true})
          .value();
  EXPECT_TRUE(world.createShape(bullet, {}, makeCircle({}, 0.1f).value()).ok());
  // A kinematic platform carrying a box.
  BodyId platform = world
                        .createBody({.type = BodyType::kinematicBody,
                                     .position = {10.0f, 3.0f},
                                     .linearVelocity = {0.5f, 0.0f}})
                        .value();
  EXPECT_TRUE(world.createShape(platform, {}, makeBox(1.5f, 0.2f).value()).ok());
  addBox(world, {10.0f, 3.8f}, {0.3f, 0.3f});
  // A sensor zone.
  BodyId zone = world.createBody({.type = BodyType::staticBody, .position = {-6.0f, 1.0f}}).value();
  EXPECT_TRUE(world.createShape(zone, {.sensor = true}, makeBox(2.0f, 1.0f).value()).ok());
  // A compound body (two shapes) sliding onto the tiles.
  BodyId compound =
      world.createBody({.position = {21.0f, 1.0f}, .linearVelocity = {2.0f, 0.0f}}).value();
  EXPECT_TRUE(world.createShape(compound, {}, makeBox(0.4f, 0.2f).value()).ok());
  EXPECT_TRUE(world.createShape(compound, {}, makeCircle({0.4f, 0.0f}, 0.2f).value()).ok());
  EXPECT_TRUE(world.applyForce(compound, {5.0f, 0.0f}, {21.0f, 1.0f}).ok());
  EXPECT_TRUE(valid(world));
  return world;
}

class SnapshotAllKinds : public ::testing::TestWithParam<std::tuple<BroadPhaseKind, bool>> {};

// The contract: step, snapshot, step N == restore (into a diverged world, into a fresh
// world, and a new world from the bytes), step N; event for event and hash for hash.
TEST_P(SnapshotAllKinds, StepsOnBitIdenticallyAfterRestore) {
  const auto [kind, sleep] = GetParam();
  World world = makeScene(kind, sleep);
  run(world, 100);
  if (sleep) {
    EXPECT_LT(world.awakeBodyCount(), world.bodyCount()) << "nothing sleeps: a weak test";
  }
  const Bytes full = take(world);
  const Bytes dynamic = take(world, SnapshotKind::dynamic);
  const std::uint64_t hashAtSnapshot = world.stateHash();
  const Trace reference = run(world, 100);

  // 1. The same world, diverged: stepped on, a body destroyed, two created.
  BodyId first = *world.bodies().begin();
  for (BodyId b : world.bodies()) {
    if (world.bodyType(b) == BodyType::dynamicBody) first = b;
  }
  ASSERT_TRUE(world.destroyBody(first).ok());
  addBall(world, {0.0f, 12.0f}, 0.5f);
  addBox(world, {2.0f, 12.0f}, {0.5f, 0.5f});
  run(world, 3);
  ASSERT_TRUE(world.restore(full).ok());
  EXPECT_TRUE(world.isValid(first));
  EXPECT_EQ(world.stateHash(), hashAtSnapshot);
  EXPECT_TRUE(valid(world));
  Trace again = run(world, 100);
  EXPECT_EQ(again.hashes, reference.hashes);
  EXPECT_EQ(again.events, reference.events);

  // 2. Dynamic snapshot into the same world after more steps and changes of motion.
  run(world, 37);
  for (BodyId b : world.bodies()) {
    if (world.bodyType(b) == BodyType::dynamicBody) {
      EXPECT_TRUE(world.setLinearVelocity(b, {1.0f, 2.0f}).ok());
    }
  }
  ASSERT_TRUE(world.restore(dynamic).ok()) << world.restore(dynamic).message();
  EXPECT_EQ(world.stateHash(), hashAtSnapshot);
  again = run(world, 100);
  EXPECT_EQ(again.hashes, reference.hashes);
  EXPECT_EQ(again.events, reference.events);

  // 3. A full snapshot into a freshly created world of another broad phase's settings.
  World fresh = World::create({}).value();
  ASSERT_TRUE(fresh.restore(full).ok());
  EXPECT_EQ(fresh.def().broadPhase, kind);
  again = run(fresh, 100);
  EXPECT_EQ(again.hashes, reference.hashes);
  EXPECT_EQ(again.events, reference.events);

  // 4. A new world from the bytes.
  Result<World> made = World::fromSnapshot(full);
  ASSERT_TRUE(made.ok()) << made.error().message;
  EXPECT_NE(made.value().id(), world.id());
  again = run(made.value(), 100);
  EXPECT_EQ(again.hashes, reference.hashes);
  EXPECT_EQ(again.events, reference.events);
}

INSTANTIATE_TEST_SUITE_P(Snapshot, SnapshotAllKinds,
                         ::testing::Combine(::testing::ValuesIn(kAllBroadPhaseKinds),
                                            ::testing::Bool()),
                         [](const auto& param) {
                           return std::string(toString(std::get<0>(param.param))) +
                                  (std::get<1>(param.param) ? "_sleep" : "_nosleep");
                         });

// Snapshots taken at every step of a busy stretch (bodies falling, contacts beginning,
// islands merging and splitting, bullets) all continue exactly.
TEST(Snapshot, EveryStepOfABusyStretchRestoresExactly) {
  World world = makeScene(BroadPhaseKind::tree, true);
  for (int step = 0; step < 40; ++step) {
    const Bytes bytes = take(world);
    World copy = World::fromSnapshot(bytes).value();
    const Trace a = run(world, 3);
    const Trace b = run(copy, 3);
    ASSERT_EQ(a.hashes, b.hashes) << "snapshot at step " << world.stepCount() - 3;
    ASSERT_EQ(a.events, b.events) << "snapshot at step " << world.stepCount() - 3;
  }
}

TEST(Snapshot, HandlesStayValidAcrossRestore) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {10.0f, 0.5f});
  BodyId keep = addBall(world, {0.0f, 2.0f}, 0.5f);
  const Bytes before = take(world);
  BodyId later = addBall(world, {3.0f, 2.0f}, 0.5f);
  ASSERT_TRUE(world.destroyBody(keep).ok());
  EXPECT_FALSE(world.isValid(keep));
  ASSERT_TRUE(world.restore(before).ok());
  // The destroyed body is back under its old handle; the one created after is gone, and a
  // new body does not revive its handle (the slot's generation came back too).
  EXPECT_TRUE(world.isValid(keep));
  EXPECT_FALSE(world.isValid(later));
  EXPECT_EQ(world.position(keep), (Vec2{0.0f, 2.0f}));
  EXPECT_EQ(world.shapes(keep).size(), 1u);
  BodyId next = addBall(world, {3.0f, 2.0f}, 0.5f);
  EXPECT_EQ(next.index, later.index);
  EXPECT_TRUE(valid(world));
}

TEST(Snapshot, RestoreKeepsTheCallbacks) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {10.0f, 0.5f});
  addBall(world, {0.0f, 2.0f}, 0.5f);
  const Bytes start = take(world);
  int begins = 0;
  world.onContactBegin(~0ull, ~0ull, [&](World&, ShapeId, ShapeId) { ++begins; });
  run(world, 60);
  EXPECT_EQ(begins, 1);
  ASSERT_TRUE(world.restore(start).ok());
  run(world, 60);
  EXPECT_EQ(begins, 2);
}

TEST(Snapshot, PendingEndEventsOfDestroyedShapesAreKept) {
  World world = World::create({}).value();
  BodyId ground = addStaticBox(world, {0.0f, -0.5f}, {10.0f, 0.5f});
  addBox(world, {0.0f, 0.5f}, {0.5f, 0.5f});
  run(world, 10);
  ASSERT_EQ(world.touchingContactCount(), 1u);
  ASSERT_TRUE(world.destroyBody(ground).ok());  // its end event comes with the next step
  const Bytes bytes = take(world);
  Result<World> made = World::fromSnapshot(bytes);
  ASSERT_TRUE(made.ok()) << made.error().message;
  World& copy = made.value();
  ASSERT_TRUE(copy.step().ok());
  ASSERT_EQ(copy.events().end.size(), 1u);
  EXPECT_EQ(copy.events().end[0].shapeA.world, copy.id());
}

TEST(Snapshot, DynamicIsRefusedWhenTheStructureDiffers) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {10.0f, 0.5f});
  BodyId ball = addBall(world, {0.0f, 2.0f}, 0.5f);
  run(world, 5);
  const Bytes dynamic = take(world, SnapshotKind::dynamic);
  const std::uint64_t hash = world.stateHash();

  addBall(world, {3.0f, 2.0f}, 0.5f);  // a body created since
  run(world, 5);
  const std::uint64_t diverged = world.stateHash();
  Status s = world.restore(dynamic);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("another static structure"), std::string::npos) << s.message();
  EXPECT_EQ(world.stateHash(), diverged);  // unchanged
  EXPECT_TRUE(valid(world));

  // Another world entirely.
  World other = World::create({}).value();
  EXPECT_FALSE(other.restore(dynamic).ok());
  // fromSnapshot needs a full one.
  Result<World> made = World::fromSnapshot(dynamic);
  ASSERT_FALSE(made.ok());
  EXPECT_NE(made.error().message.find("dynamic snapshot"), std::string::npos);

  // Back to the same structure: accepted.
  World same = World::create({}).value();
  addStaticBox(same, {0.0f, -0.5f}, {10.0f, 0.5f});
  BodyId sameBall = addBall(same, {0.0f, 2.0f}, 0.5f);
  EXPECT_EQ(sameBall.index, ball.index);
  ASSERT_TRUE(same.restore(dynamic).ok());
  EXPECT_EQ(same.stateHash(), hash);
}

// Every way a snapshot can be wrong: each refused with a message naming it, the world
// unchanged.
TEST(Snapshot, BadSnapshotsAreRefusedByName) {
  World source = makeScene(BroadPhaseKind::tree, true);
  run(source, 30);
  const Bytes good = take(source);
  World world = makeScene(BroadPhaseKind::sap, true);
  run(world, 7);
  const std::uint64_t hash = world.stateHash();

  auto refused = [&](const Bytes& bytes, const char* expected) {
    Status s = world.restore(bytes);
    EXPECT_FALSE(s.ok()) << "accepted; expected: " << expected;
    if (!s.ok()) {
      EXPECT_NE(s.message().find(expected), std::string::npos) << s.message();
    }
    EXPECT_EQ(world.stateHash(), hash);
  };
  // Writes a little-endian number into the header and fixes the checksum after.
  auto patch = [](Bytes b, std::size_t at, std::uint64_t value, int bytes) {
    for (int i = 0; i < bytes; ++i)
      b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(value >> (8 * i));
    return b;
  };

  refused({}, "not a Quack snapshot");
  refused(Bytes(good.begin(), good.begin() + 20), "truncated");
  refused(Bytes(good.begin(), good.end() - 1), "truncated");
  Bytes longer = good;
  longer.push_back(0);
  refused(longer, "after its payload");
  Bytes flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  refused(flipped, "checksum");
  refused(patch(good, 8, 99, 4), "format version 99");
  refused(patch(good, 12, 7, 1), "kind 7");
  refused(patch(good, 16, 12345, 8), "build fingerprint");
  Bytes magic = good;
  magic[0] = 'X';
  refused(magic, "not a Quack snapshot");
  EXPECT_TRUE(valid(world));
}

TEST(Snapshot, RefusedDuringAStep) {
  World world = World::create({}).value();
  addStaticBox(world, {0.0f, -0.5f}, {10.0f, 0.5f});
  addBall(world, {0.0f, 0.6f}, 0.5f);
  const Bytes bytes = take(world);
  int calls = 0;
  std::string snapshotError, restoreError;
  world.onContactBegin(~0ull, ~0ull, [&](World& w, ShapeId, ShapeId) {
    ++calls;
    Result<Bytes> s = w.snapshot();
    if (!s) snapshotError = s.error().message;
    Status r = w.restore(bytes);
    if (!r) restoreError = r.message();
  });
  run(world, 30);
  ASSERT_EQ(calls, 1);
  EXPECT_NE(snapshotError.find("from an event callback"), std::string::npos);
  EXPECT_NE(restoreError.find("from an event callback"), std::string::npos);
}

// Dynamic is the rollback kind: it holds what moves, so static geometry costs it almost
// nothing, and its size per body on the settled 20-row pyramid (210 boxes, 590 touching
// contacts) is recorded in docs/determinism.md: 475 bytes, of which about 370 are the
// contacts' manifolds, impulses and recycling references.
TEST(Snapshot, DynamicHoldsWhatMovesAndStaysSmall) {
  auto pyramid = [](int staticTiles) {
    World world = World::create({}).value();
    addStaticBox(world, {0.0f, -0.5f}, {40.0f, 0.5f});
    for (int i = 0; i < staticTiles; ++i)
      addStaticBox(world, {-100.0f + 0.25f * static_cast<float>(i), 50.0f}, {0.1f, 0.1f});
    addPyramid(world, 20);
    run(world, 120);
    return world;
  };
  World plain = pyramid(0);
  World tiled = pyramid(1000);
  const Bytes full = take(plain);
  const Bytes dynamic = take(plain, SnapshotKind::dynamic);
  const Bytes tiledFull = take(tiled);
  const Bytes tiledDynamic = take(tiled, SnapshotKind::dynamic);
  const double perBody = static_cast<double>(dynamic.size()) / 210.0;
  const double perTile = static_cast<double>(tiledDynamic.size() - dynamic.size()) / 1000.0;
  ::testing::Test::RecordProperty("dynamic_bytes", std::to_string(dynamic.size()));
  ::testing::Test::RecordProperty("full_bytes", std::to_string(full.size()));
  std::printf(
      "pyramid 20 rows: full %zu bytes, dynamic %zu bytes (%.1f per body), %zu touching "
      "contacts; each static tile adds %.1f bytes to full, %.1f to dynamic\n",
      full.size(), dynamic.size(), perBody, plain.touchingContactCount(),
      static_cast<double>(tiledFull.size() - full.size()) / 1000.0, perTile);
  EXPECT_LT(dynamic.size(), full.size());
  // A static shape adds its proxy's buffered flag, its ghost-edge flag and its (empty)
  // contact list's count.
  EXPECT_LE(perTile, 4.0);
  // The bar against regressions (measured 475).
  EXPECT_LT(perBody, 500.0);
}

}  // namespace
}  // namespace quack
