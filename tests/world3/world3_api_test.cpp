// World3's public boundary: every bad input refused with a message naming the field, handles
// with generations, mass properties against closed forms, events.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "quack/world/world3.hpp"

namespace quack {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

bool mentions(const std::string& message, const char* field) {
  return message.find(field) != std::string::npos;
}

TEST(World3Api, BadWorldDefsAreRefusedNamingTheField) {
  struct Case {
    WorldDef3 def;
    const char* field;
  };
  const Case cases[] = {
      {{.gravity = {0, kNaN, 0}}, "gravity"},
      {{.timeStep = 0.0f}, "timeStep"},
      {{.timeStep = 2.0f}, "timeStep"},
      {{.substeps = 0}, "substeps"},
      {{.substeps = 65}, "substeps"},
      {{.contactHertz = -1.0f}, "contactHertz"},
      {{.contactDampingRatio = kNaN}, "contactDampingRatio"},
      {{.contactPushMaxSpeed = 0.0f}, "contactPushMaxSpeed"},
      {{.restitutionThreshold = -1.0f}, "restitutionThreshold"},
      {{.speculativeDistance = 2.0f}, "speculativeDistance"},
      {{.aabbMargin = 0.001f}, "aabbMargin"},
      {{.contactRecycleDistance = kNaN}, "contactRecycleDistance"},
      {{.contactRecycleDistance = -0.1f}, "contactRecycleDistance"},
  };
  for (const Case& c : cases) {
    Result<World3> made = World3::create(c.def);
    ASSERT_FALSE(made.ok()) << c.field;
    EXPECT_TRUE(mentions(made.error().message, c.field)) << made.error().message;
  }
  EXPECT_TRUE(World3::create().ok());
}

TEST(World3Api, BadBodyAndShapeInputIsRefusedAndChangesNothing) {
  World3 world = World3::create().value();
  struct BodyCase {
    BodyDef3 def;
    const char* field;
  };
  const BodyCase bodies[] = {
      {{.position = {kNaN, 0, 0}}, "position"},
      {{.position = {0, 1e9f, 0}}, "position"},
      {{.rotation = {0, 0, 0, 0}}, "rotation"},
      {{.linearVelocity = {0, 0, kNaN}}, "linearVelocity"},
      {{.angularVelocity = {1e6f, 0, 0}}, "angularVelocity"},
      {{.linearDamping = -1.0f}, "linearDamping"},
      {{.angularDamping = kNaN}, "angularDamping"},
      {{.gravityScale = kNaN}, "gravityScale"},
      {{.sleepThreshold = -1.0f}, "sleepThreshold"},
  };
  for (const BodyCase& c : bodies) {
    Result<BodyId3> made = world.createBody(c.def);
    ASSERT_FALSE(made.ok()) << c.field;
    EXPECT_TRUE(mentions(made.error().message, c.field)) << made.error().message;
  }
  EXPECT_EQ(world.bodyCount(), 0u);

  const BodyId3 body = world.createBody({}).value();
  struct ShapeCase {
    ShapeDef3 def;
    const char* field;
  };
  const ShapeCase shapes[] = {
      {{.density = -1.0f}, "density"},
      {{.friction = kNaN}, "friction"},
      {{.restitution = 11.0f}, "restitution"},
      {{.rollingResistance = -0.1f}, "rollingResistance"},
  };
  for (const ShapeCase& c : shapes) {
    Result<ShapeId3> made = world.createShape(body, c.def, Sphere{{}, 0.5f});
    ASSERT_FALSE(made.ok()) << c.field;
    EXPECT_TRUE(mentions(made.error().message, c.field)) << made.error().message;
  }
  Result<ShapeId3> bad = world.createShape(body, {}, Sphere{{}, 0.0f});
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(mentions(bad.error().message, "geometry")) << bad.error().message;
  EXPECT_EQ(world.shapeCount(), 0u);

  const std::array<Vec3, 3> vertices = {Vec3{0, 0, 0}, Vec3{0, 0, 1}, Vec3{1, 0, 0}};
  const std::array<std::array<std::int32_t, 3>, 1> triangles = {{{0, 1, 2}}};
  Mesh3 mesh = makeMesh3(vertices, triangles).value();
  Result<ShapeId3> onDynamic = world.createShape(body, {}, mesh);
  ASSERT_FALSE(onDynamic.ok());
  EXPECT_TRUE(mentions(onDynamic.error().message, "static")) << onDynamic.error().message;

  EXPECT_FALSE(world.step(0.0f, 4).ok());
  EXPECT_FALSE(world.step(1.0f / 60.0f, 0).ok());
  EXPECT_FALSE(world.setLinearVelocity(body, {kNaN, 0, 0}).ok());
  EXPECT_FALSE(world.applyLinearImpulse(body, {0, 0, 0}, {kNaN, 0, 0}).ok());
  EXPECT_FALSE(world.setTransform(body, {0, 0, 0}, {0, 0, 0, 0}).ok());
  EXPECT_EQ(world.stepCount(), 0u);
}

// Shapes of one hull share a stored copy, validated once (docs/world3.md): a copy that
// differs in one bit is still validated and refused, one body's density is not another's,
// and a destroyed shape's hull can come back.
TEST(World3Api, SharedHullsAreStillValidatedAndWeighedPerShape) {
  World3 world = World3::create().value();
  const Hull3 box = makeBox3({0.5f, 0.5f, 0.5f}).value();
  const BodyId3 a = world.createBody({}).value();
  const ShapeId3 first = world.createShape(a, {.density = 1.0f}, box).value();
  Hull3 bent = box;
  bent.faces[0].normal.x = -bent.faces[0].normal.x + 0.5f;  // no longer a unit normal
  const BodyId3 b = world.createBody({.position = {3, 0, 0}}).value();
  Result<ShapeId3> refused = world.createShape(b, {}, bent);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(mentions(refused.error().message, "geometry")) << refused.error().message;
  EXPECT_EQ(world.shapeCount(), 1u);
  // The same hull at density 3 weighs 3 kg; the 1 kg body keeps its mass.
  ASSERT_TRUE(world.createShape(b, {.density = 3.0f}, box).ok());
  EXPECT_NEAR(world.mass(a), 1.0f, 1e-5f);
  EXPECT_NEAR(world.mass(b), 3.0f, 1e-5f);
  const BodyId3 c = world.createBody({.position = {6, 0, 0}}).value();
  ASSERT_TRUE(world.createShape(c, {.density = 1.0f}, box).ok());
  EXPECT_NEAR(world.mass(c), 1.0f, 1e-5f);
  // Every shape of that hull gone, then the hull again: made, and the world still steps.
  ASSERT_TRUE(world.destroyShape(first).ok());
  ASSERT_TRUE(world.destroyBody(b).ok());
  ASSERT_TRUE(world.destroyBody(c).ok());
  ASSERT_TRUE(world.createShape(a, {.density = 2.0f}, box).ok());
  EXPECT_NEAR(world.mass(a), 2.0f, 1e-5f);
  ASSERT_TRUE(world.step(1.0f / 60.0f, 4).ok());
}

TEST(World3Api, StaleAndForeignHandlesAreCaught) {
  World3 world = World3::create().value();
  World3 other = World3::create().value();
  EXPECT_NE(world.id(), other.id());
  const BodyId3 body = world.createBody({.position = {1, 2, 3}}).value();
  const ShapeId3 shape = world.createShape(body, {}, Sphere{{}, 0.5f}).value();
  EXPECT_TRUE(world.isValid(body));
  EXPECT_FALSE(other.isValid(body));
  EXPECT_FALSE(other.setLinearVelocity(body, {1, 0, 0}).ok());
  EXPECT_EQ(world.body(shape), body);
  ASSERT_TRUE(world.destroyBody(body).ok());
  EXPECT_FALSE(world.isValid(body));
  EXPECT_FALSE(world.isValid(shape));
  EXPECT_FALSE(world.destroyBody(body).ok());
  EXPECT_EQ(world.position(body), (Vec3{}));  // neutral value
  // The slot is reused with a new generation: the old handle stays stale.
  const BodyId3 again = world.createBody({}).value();
  EXPECT_EQ(again.index, body.index);
  EXPECT_NE(again.generation, body.generation);
  EXPECT_FALSE(world.isValid(body));
  EXPECT_FALSE(world.isValid(BodyId3{}));
}

TEST(World3Api, MassPropertiesMatchClosedForms) {
  World3 world = World3::create().value();
  // A 1 x 2 x 3 m box of density 2: m = 12, I = m/12 (b^2 + c^2) about each axis.
  const BodyId3 box = world.createBody({}).value();
  ASSERT_TRUE(world.createShape(box, {.density = 2.0f}, makeBox3({0.5f, 1.0f, 1.5f}).value()).ok());
  EXPECT_NEAR(world.mass(box), 12.0f, 1e-4f);
  const Mat3 i = world.inertia(box);
  EXPECT_NEAR(i.cx.x, 12.0f / 12.0f * (4.0f + 9.0f), 1e-3f);
  EXPECT_NEAR(i.cy.y, 12.0f / 12.0f * (1.0f + 9.0f), 1e-3f);
  EXPECT_NEAR(i.cz.z, 12.0f / 12.0f * (1.0f + 4.0f), 1e-3f);
  EXPECT_NEAR(i.cx.y, 0.0f, 1e-4f);

  // Two unit-density spheres of radius 0.5 at x = -1 and x = 2: the centre of mass halfway,
  // inertia about y = 2 (2/5 m r^2 + m d^2) with d = 1.5, about x = 2 (2/5 m r^2).
  const BodyId3 pair = world.createBody({.position = {10, 0, 0}}).value();
  ASSERT_TRUE(world.createShape(pair, {}, Sphere{{-1, 0, 0}, 0.5f}).ok());
  ASSERT_TRUE(world.createShape(pair, {}, Sphere{{2, 0, 0}, 0.5f}).ok());
  const float m = 4.0f / 3.0f * kPi * 0.125f;
  EXPECT_NEAR(world.mass(pair), 2.0f * m, 1e-5f);
  EXPECT_NEAR(world.worldCenterOfMass(pair).x, 10.5f, 1e-5f);
  const Mat3 ip = world.inertia(pair);
  EXPECT_NEAR(ip.cx.x, 2.0f * 0.4f * m * 0.25f, 1e-5f);
  EXPECT_NEAR(ip.cy.y, 2.0f * (0.4f * m * 0.25f + m * 2.25f), 1e-4f);

  // Turned a quarter about z, the box's world inertia swaps its x and y entries.
  ASSERT_TRUE(world.setTransform(box, {0, 0, 0}, Quat::fromAxisAngle({0, 0, 1}, 0.5f * kPi)).ok());
  const Mat3 turned = world.inertia(box);
  EXPECT_NEAR(turned.cx.x, i.cy.y, 1e-3f);
  EXPECT_NEAR(turned.cy.y, i.cx.x, 1e-3f);
}

TEST(World3Api, BeginAndEndEvents) {
  World3 world = World3::create().value();
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  const ShapeId3 floor = world.createShape(ground, {}, makeBox3({5, 0.5f, 5}).value()).value();
  const BodyId3 ball = world.createBody({.position = {0, 1.0f, 0}}).value();
  const ShapeId3 shape = world.createShape(ball, {}, Sphere{{}, 0.25f}).value();
  int begins = 0;
  for (int i = 0; i < 60; ++i) {
    ASSERT_TRUE(world.step().ok());
    for (const ContactEvent3& e : world.events().begin) {
      EXPECT_EQ(e.shapeA, floor);
      EXPECT_EQ(e.shapeB, shape);
      ++begins;
    }
    EXPECT_TRUE(world.events().end.empty());
  }
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(world.touchingContactCount(), 1u);
  ASSERT_TRUE(world.destroyBody(ball).ok());
  EXPECT_EQ(world.contactCount(), 0u);
  ASSERT_TRUE(world.step().ok());
  ASSERT_EQ(world.events().end.size(), 1u);
  EXPECT_EQ(world.events().end[0].shapeB, shape);
}

// Rotations: a huge quaternion (its squared length overflows float) becomes the unit one
// it points along, not zero; a rotation read back from a body writes back to the bit.
TEST(World3Api, RotationsAreMadeUnitWithoutOverflowAndWriteBackExactly) {
  World3 world = World3::create().value();
  const BodyId3 b = world.createBody({.rotation = {0, 1e30f, 0, 1e30f}}).value();
  const Quat expected = Quat::fromAxisAngle({0, 1, 0}, 0.5f * kPi);
  EXPECT_GT(std::fabs(dot(world.rotation(b), expected)), 1.0f - 1e-6f);
  ASSERT_TRUE(world.setTransform(b, {}, {3e38f, 0, 0, 3e38f}).ok());
  EXPECT_GT(std::fabs(dot(world.rotation(b), Quat::fromAxisAngle({1, 0, 0}, 0.5f * kPi))),
            1.0f - 1e-6f);
  // Turned by a spin over some steps: a unit-to-rounding quaternion, written back as read.
  ASSERT_TRUE(world.setAngularVelocity(b, {0.3f, 1.1f, -0.7f}).ok());
  for (int i = 0; i < 7; ++i)
    ASSERT_TRUE(world.step().ok());
  const Quat read = world.rotation(b);
  const Vec3 p = world.position(b);
  ASSERT_TRUE(world.setTransform(b, p, read).ok());
  const Quat again = world.rotation(b);
  EXPECT_EQ(std::memcmp(&read, &again, sizeof(Quat)), 0);
}

// Callbacks: matched by category both ways round, shapes passed in the matching order,
// once per event; a shape destroyed in a begin callback gets its end callback next step
// (matched by the categories it had); step() from a callback is refused; a callback
// registered inside one runs from the next step.
TEST(World3Api, ContactCallbacksMatchByCategoryAndMayChangeTheWorld) {
  World3 world = World3::create().value();
  const BodyId3 ground = world.createBody({.type = BodyType::staticBody}).value();
  const ShapeId3 floor = world
                             .createShape(ground, {.filter = {.category = 1}},
                                          makeBox3({5, 0.5f, 5}, {{0, -0.5f, 0}, {}}).value())
                             .value();
  const BodyId3 ball = world.createBody({.position = {0, 0.6f, 0}}).value();
  const ShapeId3 ballShape =
      world.createShape(ball, {.filter = {.category = 2}}, Sphere{{}, 0.5f}).value();
  int groundFirst = 0, ballFirst = 0, ends = 0, late = 0;
  bool stepRefused = false;
  world.onContactBegin(1, 2, [&](World3& w, ShapeId3 a, ShapeId3 b) {
    ++groundFirst;
    EXPECT_EQ(a, floor);
    EXPECT_EQ(b, ballShape);
    stepRefused = !w.step().ok();
    w.onContactBegin(~std::uint64_t{0}, ~std::uint64_t{0},
                     [&](World3&, ShapeId3, ShapeId3) { ++late; });
    EXPECT_TRUE(w.destroyBody(w.body(b)).ok());
  });
  world.onContactBegin(2, 1, [&](World3&, ShapeId3 a, ShapeId3 b) {
    ++ballFirst;
    EXPECT_EQ(a, ballShape);
    EXPECT_EQ(b, floor);
  });
  world.onContactBegin(4, 4, [&](World3&, ShapeId3, ShapeId3) { ADD_FAILURE() << "category 4"; });
  world.onContactEnd(2, 1, [&](World3& w, ShapeId3 a, ShapeId3 b) {
    ++ends;
    EXPECT_FALSE(w.isValid(a));  // destroyed: its categories matched it
    EXPECT_EQ(b, floor);
  });
  // The ball falls 0.1 m before it touches: step until the begin event.
  for (int i = 0; i < 60 && groundFirst == 0; ++i)
    ASSERT_TRUE(world.step().ok());
  EXPECT_EQ(groundFirst, 1);
  EXPECT_EQ(ballFirst, 1);
  EXPECT_TRUE(stepRefused);
  EXPECT_FALSE(world.isValid(ball));
  EXPECT_EQ(late, 0);
  ASSERT_TRUE(world.step().ok());
  EXPECT_EQ(ends, 1);
  EXPECT_EQ(late, 0);  // the next step had no begin event
}

}  // namespace
}  // namespace quack
