#pragma once
// The world suite's scenes (world_suite.cpp): the scenes of Box2D v3's own benchmark, with
// and without joints, and a long hanging chain of our own, laid out the same in both
// libraries (positions, sizes, densities, frictions, joint settings, sleeping), each written
// here for each library. Step counts are v3's (the chain's is ours). The layout data both
// backends read (the ragdoll's bones, the rain's schedule, generated outlines) is here, so
// that the two cannot drift apart.

#include <array>
#include <string>

namespace suite {

struct SceneInfo {
  const char* name;
  int steps;  // stepped in a run; the first is timed on its own
};

inline constexpr SceneInfo kScenes[] = {
    {"large_pyramid", 500},  // 100 rows of 1 m boxes (5,050), sleeping off
    {"many_pyramids", 200},  // 20 x 20 pyramids of 10 rows (22,000 boxes), sleeping off
    {"smash", 300},          // a heavy box at 40 m/s into 9,600 sleeping small boxes, no gravity
    {"junkyard", 800},       // 8,000 pentagons in a walled pit, swept by a kinematic pusher
    {"compounds", 500},      // 3,000 bodies of two triangles each, piling up in a walled pit
    // With joints:
    {"joint_grid", 500},  // 100 x 100 circles joined by revolute joints, hung by 7 of the top row
    {"rain", 1000},       // ragdolls (11 bodies, 10 joints) spawned in groups onto 5 floors
    {"spinner", 500},     // a motor-driven paddle stirring 6,076 mixed shapes in a ring
    {"tumbler", 750},     // a motor-driven box drum turning 2,025 small boxes
    {"washer", 500},      // a kinematic drum turning 8,100 small boxes (v3's washer has no joint)
    {"chain", 500},       // 1,000 capsule links, one end pinned, released horizontal (ours)
};

// What a run measured: building the scene, its first step, and the mean of the others.
struct Run {
  double buildMs = 0.0;
  double firstStepMs = 0.0;
  double msPerStep = 0.0;
  long contacts = 0;  // contacts (pairs of overlapping boxes) after the last step
  long awake = 0;     // awake bodies after the last step
  // Checks after the last step (not timed): the largest distance between a live joint's two
  // anchors (m; 0 without joints), and the bodies whose position or velocity is not finite.
  double jointGap = 0.0;
  long nonFinite = 0;
};

// The kinematic pusher of the junkyard: its target x at step `step` (60 Hz).
double junkyardTargetX(int step);

struct P2 {
  float x, y;
};

// ---- joint_grid: n x n circles of radius 0.4 one metre apart, column k at x = k, row i at
// y = -i, each joined to the one above and the one to its left at the midpoint; the top
// row's middle 7 are static. The circles' filter keeps them from colliding at all.
inline constexpr int kJointGridN = 100;
inline constexpr bool jointGridStatic(int k, int i) {
  return i == 0 && k >= kJointGridN / 2 - 3 && k <= kJointGridN / 2 + 3;
}

// ---- rain: Box2D v3's ragdoll ("human"), scale 1. Body positions, capsules and pivots are
// offsets from the figure's origin (its feet), up the y axis; the joint limits are in
// multiples of pi. Each joint has a spring towards the rest angle (5 Hz, damping 0.5) and a
// motor of speed 0 (joint friction) of at most frictionScale * 0.05 N m.
struct Bone {
  int parent;  // -1: the hip, the root
  float y;     // body origin
  float capsuleLow, capsuleHigh, radius;
  float linearDamping;
  float frictionScale;
  bool foot;     // the lower leg also carries the foot polygon
  float pivotY;  // joint point, with the parent
  float lower, upper;
  float frameTurn;  // v3's joint frame on the parent turned by this (x pi): the rest angle
};
inline constexpr std::array<Bone, 11> kBones{{
    {-1, 0.95f, -0.02f, 0.02f, 0.095f, 0.0f, 1.0f, false, 0.0f, 0.0f, 0.0f, 0.0f},      // hip
    {0, 1.2f, -0.135f, 0.135f, 0.09f, 0.0f, 0.5f, false, 1.0f, -0.25f, 0.0f, 0.0f},     // torso
    {1, 1.475f, -0.038f, 0.039f, 0.075f, 0.1f, 0.25f, false, 1.4f, -0.3f, 0.1f, 0.0f},  // head
    {0, 0.775f, -0.125f, 0.125f, 0.06f, 0.0f, 1.0f, false, 0.9f, -0.05f, 0.4f, 0.0f},   // upper leg
    {3, 0.475f, -0.155f, 0.125f, 0.045f, 0.0f, 0.5f, true, 0.625f, -0.5f, -0.02f, 0.0f},  // lower
    {0, 0.775f, -0.125f, 0.125f, 0.06f, 0.0f, 1.0f, false, 0.9f, -0.05f, 0.4f, 0.0f},  // upper leg
    {5, 0.475f, -0.155f, 0.125f, 0.045f, 0.0f, 0.5f, true, 0.625f, -0.5f, -0.02f, 0.0f},  // lower
    {1, 1.225f, -0.125f, 0.125f, 0.035f, 0.0f, 0.5f, false, 1.35f, -0.1f, 0.8f, 0.0f},  // upper arm
    {7, 0.975f, -0.125f, 0.125f, 0.03f, 0.1f, 0.1f, false, 1.1f, -0.2f, 0.3f, 0.25f},   // lower arm
    {1, 1.225f, -0.125f, 0.125f, 0.035f, 0.0f, 0.5f, false, 1.35f, -0.1f, 0.8f, 0.0f},  // upper arm
    {9, 0.975f, -0.125f, 0.125f, 0.03f, 0.1f, 0.1f, false, 1.1f, -0.2f, 0.3f, 0.25f},   // lower arm
}};
// The foot: a quadrilateral rounded by 0.015 m on the lower leg, friction 0.05, colliding
// with the ground only. Other bones: friction 0.2, colliding with the ground and other
// figures (category 2, mask 1 | 2) but not with a figure of the same group number.
inline constexpr std::array<P2, 4> kFoot{
    {{-0.03f, -0.185f}, {0.11f, -0.185f}, {0.11f, -0.16f}, {-0.03f, -0.14f}}};
inline constexpr float kFootRadius = 0.015f;
inline constexpr float kJointFriction = 0.05f, kBoneHertz = 5.0f, kBoneDamping = 0.5f;
inline constexpr float kBoneSleepThreshold = 0.1f;

// The rain's floors: kRainRows rows of 501 static boxes of 0.5 m, 45 m apart, from x =
// -125 m; groups of kRainGroupSize figures (0.5 m apart, group numbers 1..5) over each of
// kRainColumns columns of each floor, 40 m above it.
inline constexpr int kRainRows = 5, kRainColumns = 40, kRainGroupSize = 5;
inline constexpr float kRainGridSize = 0.5f;
inline constexpr int kRainGridCount = 500;
P2 rainGroupOrigin(int row, int column);
// Before step `step`: every 8th step a column of groups is spawned, one group per floor;
// the first 40 times in a new column, afterwards replacing the oldest column (its groups
// destroyed and spawned again). True when the step spawns; `column` and `replace` say how.
bool rainSpawn(int step, int& column, bool& replace);

// ---- spinner: the ring's 360 points (a loop of one-sided segments facing in; radius 40 m
// about (0, 32)), built as v3 builds them (turning a point step by step in float).
std::array<P2, 360> spinnerRing();
inline constexpr int kSpinnerBodies = 2 * 3038;

// ---- washer: the drum's 40 quadrilaterals (36 rim pieces, 4 paddles), body frame.
std::array<std::array<P2, 4>, 40> washerPieces();

// ---- chain: kChainLinks capsules of kChainLink metres (radius kChainRadius, density 1,
// friction 0.2) along +x from a static body at the origin, each joined to the next by a
// revolute joint at their shared end (the links' shapes do not collide with their neighbours'
// but do with the others'), the first pinned at the origin; released at rest, horizontal.
inline constexpr int kChainLinks = 1000;
inline constexpr float kChainLink = 0.5f, kChainRadius = 0.1f;

}  // namespace suite

// Box2D v3, compiled in its own file against its own headers (box2d_v3_world.cpp).
namespace suite::v3 {
// Runs `scene` with `workers` threads (v3's own scheduler) for `steps` steps.
Run run(const std::string& scene, int workers, int steps);
}  // namespace suite::v3
