#pragma once
// Ghost-collision removal on static geometry, and chains (ghost_edges.cpp): one part of the
// world. It owns what static shapes know about their neighbours and rewrites the manifolds
// of contacts with flagged static shapes. docs/concave.md explains the method.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "quack/collision/manifold.hpp"
#include "quack/math/vec2.hpp"

namespace quack::detail {

/// An edge entered in a cell of the static-edge search's grid (ghost_edges.cpp).
struct CellEntry {
  long long x, y;
  std::size_t edge;
};
/// Sorts `entries` by cell (x, then y), then edge: the order of std::sort by (x, y, edge).
/// Precondition: entries of one cell were added in increasing edge order (the grid adds
/// them edge by edge). By radix on the cell packed into one key when there are many and
/// the cells' ranges fit in 64 bits; `scratch` is its second buffer.
void sortCellEntries(std::vector<CellEntry>& entries, std::vector<CellEntry>& scratch);

class BodyStore;
struct Contact;

// What a static shape knows about its neighbours, for ghost-collision removal. Shape frame.
// Vertex i of a polygon joins edge i - 1 and edge i; a chain segment has vertices 0 (p1) and
// 1 (p2) and one edge.
struct EdgeCone {
  enum class Kind : std::uint8_t {
    natural,  // no correction at this vertex
    range,    // normals from `lo` counter-clockwise to `hi` (lo == hi: one normal)
    snap,     // a reflex corner of the union: the nearer of `lo` and `hi`
    inside,   // the vertex is inside the union of flush shapes: contacts here are ghosts
  };
  Kind kind = Kind::natural;
  Vec2 lo, hi;
};

// The part of edge `edge` from t0 to t1 metres along it that lies flush against an
// opposite edge of another static shape: inside the union, so no contact belongs there.
struct CoveredSpan {
  int edge = 0;
  float t0 = 0.0f, t1 = 0.0f;
};

struct StaticEdges {
  bool active = false;               // contacts with this shape go through removeGhostContacts
  std::vector<CoveredSpan> covered;  // internal (parts of) edges
  std::vector<EdgeCone> cones;       // per vertex
  // Chains: the segment pushes only along `normal` (right of p1 -> p2); ghost vertices.
  bool chain = false;
  bool hasPrev = false, hasNext = false;
  Vec2 prev, next;  // the neighbouring chain points before p1 and after p2
};

class GhostEdges {
 public:
  /// Static geometry changed: find flush edges again before the next narrow phase.
  void markDirty() noexcept { dirty_ = true; }
  bool dirty() const noexcept { return dirty_; }
  /// Static shapes with ghost-collision data; 0 makes every check a single branch.
  std::size_t activeShapes() const noexcept { return activeShapes_; }

  /// Re-finds internal edges and vertex cones of every static shape (writes Shape::edges);
  /// with `removeGhostCollisions` off only chains are flagged.
  void update(BodyStore& store, bool removeGhostCollisions);
  /// Drops contact points on internal edges and turns normals at flush vertices into the
  /// faces' cone; one shape of `c` is a flagged static shape.
  void removeGhostContacts(const BodyStore& store, Contact& c) const;
  /// True when an impact at `point` (world frame) with `normal` (pointing into the static
  /// shape) lands on a flush seam or the back of a chain: not a real surface.
  bool isGhostImpact(const BodyStore& store, std::uint32_t staticShape, Vec2 point,
                     Vec2 normal) const;

 private:
  friend class SnapshotCodec;  // snapshot.cpp reads and rebuilds every field
  bool dirty_ = false;
  std::size_t activeShapes_ = 0;
};

}  // namespace quack::detail
