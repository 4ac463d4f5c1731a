#pragma once
// The 3D world benchmark's scenes (world3_bench.cpp): Box3D's benchmark scenes
// `large_pyramid` and `convex_pile`, laid out as Box3D's shared/benchmarks.c (commit
// 30c67b5, read for understanding; the code here is ours), the same in every backend:
// positions, sizes, densities, frictions, sleeping, step settings and step counts. The layout
// data every backend reads is here, so that the backends cannot drift apart; each backend
// (Quack here, Box3D and Bullet in their own files, built only when found) builds the scene
// in its own world and steps it.

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace bench3 {

struct P3 {
  float x, y, z;
};

struct SceneInfo {
  const char* name;
  int steps;  // Box3D's step count for the scene; the first step is timed on its own
};

inline constexpr SceneInfo kScenes[] = {
    {"large_pyramid", 200},  // 100 rows of 1 m cubes (5,050) in one wall, sleeping off
    {"convex_pile", 500},    // 8 x 8 x 80 hulls of 32 points (5,120) dropped on a floor
};

// Both scenes: 60 Hz, 4 sub-steps, gravity -10 m/s^2 in y, friction 0.6 (Box3D's defaults:
// contact hertz 30, damping ratio 10, push-out speed 3 m/s, as Quack's World3 defaults).
inline constexpr float kTimeStep = 1.0f / 60.0f;
inline constexpr int kSubsteps = 4;
inline constexpr float kFriction = 0.6f;

// The ground of both scenes: a static box whose top face is y = 0 (half height 1, centre at
// y = -1), kGroundHalf[scene] metres each way in x and z.
inline constexpr float kPyramidGroundHalf = 400.0f;
inline constexpr float kPileGroundHalf = 250.0f;

// ---- large_pyramid: a pyramid of kPyramidRows rows of cubes (half-extent 0.5 m, density
// 100 kg/m^3) standing in the x-y plane (z = 0), each row on the row below, the bottom row
// on the ground, touching side by side. Sleeping is off. The last box is the apex.
inline constexpr int kPyramidRows = 100;
inline constexpr float kPyramidHalf = 0.5f;
inline constexpr float kPyramidDensity = 100.0f;

inline std::vector<P3> pyramidPositions() {
  std::vector<P3> out;
  const float h = kPyramidHalf;
  const int n = kPyramidRows;
  for (int row = 0; row < n; ++row) {
    const float y = (2.0f * static_cast<float>(row) + 1.0f) * h;
    for (int i = row; i < n; ++i) {
      const float x = (static_cast<float>(row) + 1.0f) * h +
                      2.0f * static_cast<float>(i - row) * h - h * static_cast<float>(n);
      out.push_back({x, y, 0.0f});
    }
  }
  return out;
}

// ---- convex_pile (PEEL's convex pile, as Box3D ports it): one convex hull of 32 random
// points on a sphere of radius 2 m, density 1000 kg/m^3, copied to a grid of 8 x 8 bodies
// 4 m apart in x and z, 80 layers 4 m apart in y (the lowest centred at y = 2, touching the
// ground's plane), that falls into a pile. Sleeping is on.
inline constexpr int kPileCountX = 8;
inline constexpr int kPileCountZ = 8;
inline constexpr int kPileLayers = 80;
inline constexpr float kPileRadius = 2.0f;
inline constexpr int kPilePoints = 32;
inline constexpr float kPileDensity = 1000.0f;

// The hull's points: directions drawn by rejection from the cube [-0.5, 0.5]^3 (kept inside
// the ball of radius 0.5), normalised, times kPileRadius; the random numbers from PEEL's
// linear congruential generator (multiplier 2147001325, increment 715136305, seed 42; each
// float from the low 16 bits), so that the hull is the one Box3D's benchmark uses.
inline std::array<P3, kPilePoints> pilePoints() {
  std::uint32_t state = 42u;
  auto uniform = [&state]() {
    state = state * 2147001325u + 715136305u;
    return static_cast<float>(state & 0xffffu) / 65535.0f - 0.5f;
  };
  std::array<P3, kPilePoints> out{};
  for (P3& p : out) {
    float x = 0, y = 0, z = 0, lengthSq = 0;
    do {
      x = uniform();
      y = uniform();
      z = uniform();
      lengthSq = x * x + y * y + z * z;
    } while (lengthSq > 0.25f);
    // lengthSq > 0: a coordinate is 0 only for the 16-bit value 32767.5, which is none.
    const float inverse = 1.0f / std::sqrt(lengthSq);
    p = {kPileRadius * (inverse * x), kPileRadius * (inverse * y), kPileRadius * (inverse * z)};
  }
  return out;
}

inline std::vector<P3> pilePositions() {
  std::vector<P3> out;
  const float scatter = 2.0f * kPileRadius;
  for (int layer = 0; layer < kPileLayers; ++layer)
    for (int z = 0; z < kPileCountZ; ++z)
      for (int x = 0; x < kPileCountX; ++x)
        out.push_back({(static_cast<float>(x) - 0.5f * kPileCountX) * scatter,
                       kPileRadius + scatter * static_cast<float>(layer),
                       (static_cast<float>(z) - 0.5f * kPileCountZ) * scatter});
  return out;
}

// What one run measured, and the state it ended in (not timed).
struct Run {
  double buildMs = 0.0;
  double firstStepMs = 0.0;
  double msPerStep = 0.0;  // mean of steps 1..N-1
  long contacts = 0;       // the library's contact count (pairs whose boxes overlap)
  long awake = 0;          // awake dynamic bodies
  // The dynamic bodies' origins after the last step, in creation order.
  std::vector<P3> positions;
  long nonFinite = 0;  // bodies whose position or velocity is not finite
  // With Plan::traceEvery > 0: the origins after every traceEvery-th step (the timings then
  // include taking them).
  std::vector<std::vector<P3>> trace;
};

// What a backend is asked to do: build `scene` in a fresh world with `workers` worker
// threads (Box3D only; Quack's World3 and Bullet are single-threaded), step it `steps` times
// at kTimeStep with kSubsteps sub-steps (Bullet: one step of kTimeStep, its solver's 10
// iterations), Box3D's continuous collision on or off.
struct Plan {
  std::string scene;
  int workers = 1;
  int steps = 2;
  bool continuous = true;
  int traceEvery = 0;
};

}  // namespace bench3

// The backends; each throws std::invalid_argument for an unknown scene.
namespace bench3::quack3 {
Run run(const Plan& plan);
}
namespace bench3::box3d {
bool available();
Run run(const Plan& plan);
}  // namespace bench3::box3d
namespace bench3::bullet {
bool available();
Run run(const Plan& plan);
}  // namespace bench3::bullet
