#pragma once
/// Pictures of a world: an SVG of one moment, and a self-contained HTML replay of a run
/// (one file, no network: play, pause, scrub, zoom, pan; shapes, contact points and
/// normals, and optionally the broad-phase boxes).

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "quack/io/scene.hpp"

namespace quack {

/// The outline of a shape as a polyline in its own frame: circles and rounded corners cut
/// into arcs of at most `maxArcStep` radians; a segment is its two ends (open).
struct Outline {
  std::vector<Vec2> points;
  bool closed = true;
};
Outline outlineOf(const ShapeGeometry& geometry, float maxArcStep = 0.2f);

/// The SVG's size budget: a big scene draws an even sample of its shapes and says so in
/// the picture (docs/scenes.md, "Size budgets").
struct SvgOptions {
  /// At most this many shapes (every k-th in scene order), and at most `maxBytes` of text.
  std::size_t maxShapes = 20000;
  /// At most this many contact points.
  std::size_t maxContacts = 5000;
  /// The file stays below this size, bytes.
  std::size_t maxBytes = 16u << 20;
};

/// SVG of the world now: shapes filled by body type, contact points and normals in red.
std::string renderSvg(const SceneWorld& scene, const std::string& title,
                      const SvgOptions& options = {});

/// The replay's budgets (docs/scenes.md, "Size budgets"): a big scene draws an even sample
/// of its shapes, a long or large run keeps fewer frames, and the page says what it left
/// out, so the file stays small enough for a browser.
struct ReplayOptions {
  /// Record every proxy's fat box too (drawn when the viewer ticks "broad-phase boxes").
  bool broadPhaseBoxes = false;
  /// At most this many frames; a long run keeps every k-th step (and always the last).
  int maxFrames = 1000;
  /// The page stays below this size, bytes: a quarter for the shapes, the rest for frames
  /// (thinned, evenly, until they fit).
  std::size_t maxBytes = 32u << 20;
  /// At most this many shapes drawn (every k-th in scene order).
  std::size_t maxShapes = 20000;
  /// At most this many contact points and broad-phase boxes in one frame.
  std::size_t maxContactsPerFrame = 2000;
  std::size_t maxBoxesPerFrame = 5000;
};

namespace detail {
/// The frames of a replay, 2D or 3D (render.cpp, render3.cpp): which record() calls are
/// kept (every k-th, and always the last), and the thinning that keeps their text within
/// a budget (every other frame dropped, evenly, the last kept).
class ReplayFrames {
 public:
  /// `totalCalls`: how many record() calls the run will make; at most `maxFrames` kept.
  void start(std::uint64_t totalCalls, int maxFrames);
  /// Counts a record() call; true when its frame is to be kept (then call add()).
  bool due();
  /// Keeps the frame of the call due() just counted, then thins the frames until their
  /// text fits in `budget` bytes (always keeping at least two).
  void add(std::string frame, std::size_t budget);
  std::size_t count() const noexcept { return frames_.size(); }
  std::size_t bytes() const noexcept { return bytes_; }
  /// The frames as the elements of a JSON array, one a line.
  void appendJoined(std::string& out) const;

 private:
  void thin();

  std::uint64_t totalCalls_ = 0, every_ = 1, calls_ = 0, call_ = 0;
  std::vector<std::pair<std::uint64_t, std::string>> frames_;  // (call, JSON object)
  std::size_t bytes_ = 0;
};
}  // namespace detail

/// Records a run frame by frame and writes the replay page.
class ReplayRecorder {
 public:
  /// `totalSteps`: how many steps the run will take (to space the frames evenly).
  ReplayRecorder(const SceneWorld& scene, std::uint64_t totalSteps, ReplayOptions options = {});
  /// Call once before the first step and after every step; keeps the frames it needs.
  void record(const SceneWorld& scene);
  /// The replay page.
  std::string html(const std::string& title) const;
  int frameCount() const noexcept { return static_cast<int>(frames_.count()); }
  /// Shapes drawn, and shapes in the world when recording began.
  std::size_t shapesDrawn() const noexcept { return shapesDrawn_; }
  std::size_t shapesTotal() const noexcept { return shapesTotal_; }

 private:
  ReplayOptions options_;
  detail::ReplayFrames frames_;
  std::size_t shapesDrawn_ = 0, shapesTotal_ = 0;
  bool contactsCapped_ = false;
  std::string shapes_;                 // JSON: one entry per shape (body index, outline, style)
  std::vector<std::uint32_t> moving_;  // scene indices of drawn non-static bodies
  std::vector<float> reach_;           // per moving_ entry: farthest outline point from origin
  Aabb bounds_{{1e30f, 1e30f}, {-1e30f, -1e30f}};
};

}  // namespace quack
