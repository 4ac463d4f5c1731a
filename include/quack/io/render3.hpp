#pragma once
/// The replay of a 3D run: one self-contained HTML file (no network; raw WebGL, nothing
/// fetched when it is viewed) that a person can orbit (drag), pan (shift-drag or right
/// drag), zoom (wheel), play, pause and scrub (a slider). Boxes and hulls are drawn by their
/// faces, spheres and capsules tessellated, triangles and meshes as they are, with two
/// lights and the hulls' edges outlined so that depth reads; contact points and normals on
/// top; sleeping bodies faded.
///
/// The page's data: every shape once, in its body's frame (a static body's pose with it),
/// and per frame every moving body's pose, which bodies sleep, and the contact points.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "quack/io/render.hpp"
#include "quack/io/scene3.hpp"

namespace quack {

/// The 3D replay's budgets (docs/scenes.md, "Size budgets"), as the 2D replay's.
struct ReplayOptions3 {
  /// At most this many frames; a long run keeps every k-th step (and always the last).
  int maxFrames = 1000;
  /// The page stays below this size, bytes: a quarter for the shapes, the rest for frames
  /// (thinned, evenly, until they fit).
  std::size_t maxBytes = 32u << 20;
  /// At most this many shapes drawn (every k-th in scene order); a shape whose text would
  /// pass the shapes' quarter (a huge mesh) is left out.
  std::size_t maxShapes = 20000;
  /// At most this many contact points in one frame.
  std::size_t maxContactsPerFrame = 2000;
};

/// Records a 3D run frame by frame and writes the replay page.
class ReplayRecorder3 {
 public:
  /// The shapes come from the scene (World3 keeps them, but does not hand them out);
  /// `world` is the world built from it. `totalSteps`: how many steps the run will take.
  ReplayRecorder3(const Scene3& scene, const SceneWorld3& world, std::uint64_t totalSteps,
                  ReplayOptions3 options = {});
  /// Call once before the first step and after every step; keeps the frames it needs.
  void record(const SceneWorld3& world);
  /// The replay page.
  std::string html(const std::string& title) const;
  int frameCount() const noexcept { return static_cast<int>(frames_.count()); }
  /// Shapes drawn, and shapes in the scene.
  std::size_t shapesDrawn() const noexcept { return shapesDrawn_; }
  std::size_t shapesTotal() const noexcept { return shapesTotal_; }

 private:
  ReplayOptions3 options_;
  detail::ReplayFrames frames_;
  std::size_t shapesDrawn_ = 0, shapesTotal_ = 0;
  bool contactsCapped_ = false;
  std::string shapes_;                 // JSON: one entry per drawn shape
  std::vector<std::uint32_t> moving_;  // scene indices of drawn non-static bodies
  std::vector<float> reach_;           // per moving_ entry: farthest shape point from origin
  // Everything drawn, and the moving bodies alone (where the camera looks first).
  Aabb3 bounds_{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
  Aabb3 movingBounds_{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
};

}  // namespace quack
