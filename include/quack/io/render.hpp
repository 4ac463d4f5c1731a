#pragma once
/// Pictures of a world: an SVG of one moment, and a self-contained HTML replay of a run
/// (one file, no network: play, pause, scrub, zoom, pan; shapes, contact points and
/// normals, and optionally the broad-phase boxes).

#include <cstdint>
#include <string>
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

/// SVG of the world now: shapes filled by body type, contact points and normals in red.
std::string renderSvg(const SceneWorld& scene, const std::string& title);

struct ReplayOptions {
  /// Record every proxy's fat box too (drawn when the viewer ticks "broad-phase boxes").
  bool broadPhaseBoxes = false;
  /// At most this many frames; a long run keeps every k-th step.
  int maxFrames = 1000;
  /// At most about this many numbers in the file (body poses, contacts, boxes), so a big
  /// scene gives fewer frames rather than a file too large for a browser.
  std::size_t maxNumbers = 4000000;
};

/// Records a run frame by frame and writes the replay page.
class ReplayRecorder {
 public:
  /// `totalSteps`: how many steps the run will take (to space the frames evenly).
  ReplayRecorder(const SceneWorld& scene, std::uint64_t totalSteps, ReplayOptions options = {});
  /// Call once before the first step and after every step; keeps the frames it needs.
  void record(const SceneWorld& scene);
  /// The replay page.
  std::string html(const std::string& title) const;
  int frameCount() const noexcept { return frames_; }

 private:
  ReplayOptions options_;
  std::uint64_t every_ = 1;
  std::uint64_t calls_ = 0;
  int frames_ = 0;
  std::string shapes_;                 // JSON: one entry per shape (body index, outline, style)
  std::vector<std::uint32_t> moving_;  // scene indices of non-static bodies
  std::string frameData_;              // JSON array items, comma-separated
  Aabb bounds_{{1e30f, 1e30f}, {-1e30f, -1e30f}};
};

}  // namespace quack
