#pragma once
// The world suite's scenes (world_suite.cpp): the scenes of Box2D v3's own benchmark that
// need no joints, laid out the same in both libraries (positions, sizes, densities,
// frictions, sleeping), each written here for each library. Step counts are v3's.

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
};

// What a run measured: building the scene, its first step, and the mean of the others.
struct Run {
  double buildMs = 0.0;
  double firstStepMs = 0.0;
  double msPerStep = 0.0;
  long contacts = 0;  // contacts (pairs of overlapping boxes) after the last step
  long awake = 0;     // awake bodies after the last step
};

// The kinematic pusher of the junkyard: its target x at step `step` (60 Hz).
double junkyardTargetX(int step);

}  // namespace suite

// Box2D v3, compiled in its own file against its own headers (box2d_v3_world.cpp).
namespace suite::v3 {
// Runs `scene` with `workers` threads (v3's own scheduler) for `steps` steps.
Run run(const std::string& scene, int workers, int steps);
}  // namespace suite::v3
