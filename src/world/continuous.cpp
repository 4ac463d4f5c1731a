// The continuous phase of a step: swept boxes for fast bodies, time of impact between
// sweeps, and the time-ordered handling of the impacts (the execution phase of
// docs/background.md).
// docs/continuous.md, "In the world", explains the choices.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "continuous.hpp"
#include "quack/collision/toi.hpp"
#include "quack/geometry/bounds.hpp"

#include "body_store.hpp"
#include "contact_set.hpp"
#include "event_dispatcher.hpp"
#include "ghost_edges.hpp"
#include "joint_set.hpp"
#include "quack/world/world.hpp"
#include "radix_sort.hpp"
#include "step_context.hpp"
#include "task_runner.hpp"

namespace quack::detail {
namespace {

// Fast bodies per task block of the first searches (each a broad-phase query and a few
// time-of-impact searches: a few microseconds).
constexpr int kMinSearchesPerTask = 32;

// Earliest first; ties by the shapes' indices, so the order never depends on the broad
// phase (determinism across structures).
template <class Candidate>
bool earlier(const Candidate& x, const Candidate& y) {
  if (x.time != y.time) return x.time < y.time;
  if (x.shapeA != y.shapeA) return x.shapeA < y.shapeA;
  return x.shapeB < y.shapeB;
}

// merge(computeAabb(g, {p1, q}), computeAabb(g, {p2, q})) with the shape's points rotated
// once: computeAabb takes the least and most of rotate(q, v) + p, and as rounding is
// monotonic that is the least and most of rotate(q, v), plus p (the same numbers; a zero
// bound may differ in sign, which no comparison sees). Then the radius, as computeAabb.
Aabb boxAtBothEnds(const ShapeGeometry& geometry, Rot q, Vec2 p1, Vec2 p2) {
  Vec2 lo, hi;
  float radius = 0.0f;
  auto extents = [&](const Vec2* points, int count) {
    lo = hi = rotate(q, points[0]);
    for (int i = 1; i < count; ++i) {
      const Vec2 v = rotate(q, points[i]);
      lo = minv(lo, v);
      hi = maxv(hi, v);
    }
  };
  if (const Polygon* polygon = std::get_if<Polygon>(&geometry)) {
    extents(polygon->vertices, polygon->count);
    radius = polygon->radius;
  } else if (const Circle* circle = std::get_if<Circle>(&geometry)) {
    extents(&circle->center, 1);
    radius = circle->radius;
  } else if (const Capsule* capsule = std::get_if<Capsule>(&geometry)) {
    const Vec2 points[2] = {capsule->p1, capsule->p2};
    extents(points, 2);
    radius = capsule->radius;
  } else {
    const Segment& segment = std::get<Segment>(geometry);
    const Vec2 points[2] = {segment.p1, segment.p2};
    extents(points, 2);
    // A segment's box has no radius term: (x + p) - 0 is x + p, so the same code serves.
  }
  const Vec2 r{radius, radius};
  return merge(Aabb{(lo + p1) - r, (hi + p1) + r}, Aabb{(lo + p2) - r, (hi + p2) + r});
}

}  // namespace

Aabb ContinuousPhase::sweptBox(const BodyStore& store, const FastBody& f) const {
  const Body& b = store.bodies[f.body];
  Aabb box;
  if (f.sweep.a1 != f.sweep.a2) {
    // Any point of the body stays within maxExtent of the centre, whatever the rotation.
    box = inflate(Aabb{minv(f.sweep.c1, f.sweep.c2), maxv(f.sweep.c1, f.sweep.c2)}, b.maxExtent);
  } else {
    // Not turning: one rotation for both ends (transformAt's at t = 0 and t = 1, computed once).
    const Rot q = Rot::fromAngle(f.sweep.a1);
    const Transform start{f.sweep.c1 - rotate(q, f.sweep.localCenter), q};
    const Transform end{f.sweep.c2 - rotate(q, f.sweep.localCenter), q};
    bool first = true;
    for (std::uint32_t s : b.shapes) {
      const Aabb u = boxAtBothEnds(*store.shapes[s].geometry, q, start.p, end.p);
      box = first ? u : merge(box, u);
      first = false;
    }
  }
  // Shapes within the target separation count too.
  return inflate(box, kToiTargetSeparation + kToiTolerance);
}

std::uint32_t ContinuousPhase::addParticipant(BodyStore& store, std::uint32_t body,
                                              bool searching) {
  const Body& b = store.bodies[body];
  FastBody f;
  f.body = body;
  f.searching = searching;
  if (b.fast) {
    f.sweep = {b.localCenter, b.startCenter, b.center, b.startAngle, b.endAngle};
  } else {
    // A body that is not fast stands at its end-of-step pose (it moved less than half its
    // thickness: the contact solver has its own motion) until an impact sets it moving.
    const float angle = b.xf.q.angle();
    f.sweep = {b.localCenter, b.center, b.center, angle, angle};
    f.baseV = b.v;
    f.baseW = b.w;
  }
  f.box = sweptBox(store, f);
  f.anchored = anchoredByJoint(store, body);
  const auto index = static_cast<std::uint32_t>(fast_.size());
  fast_.push_back(f);
  participantOf_[body] = index;
  movedSlot_.push_back(0);
  if (indexBuilt_) markMoved(index);  // joined after the index was built
  return index;
}

void ContinuousPhase::markMoved(std::uint32_t index) {
  // The box is copied beside the id, so that queries scan a compact array rather than the
  // participants' records; a second change updates the copy in place.
  if (movedSlot_[index] != 0) {
    moved_[movedSlot_[index] - 1].box = fast_[index].box;
    return;
  }
  moved_.push_back({fast_[index].box, index});
  movedSlot_[index] = static_cast<std::uint32_t>(moved_.size());
}

void BoxGrid::build(std::span<const Item> items) {
  count_ = items.size();
  all_.assign(items.begin(), items.end());
  float sum = 0.0f;
  for (const Item& item : items)
    sum += maxf(item.box.upper.x - item.box.lower.x, item.box.upper.y - item.box.lower.y);
  const float mean = items.empty() ? 1.0f : sum / static_cast<float>(items.size());
  inverseCell_ = 1.0f / maxf(1.5f * mean, 1.0e-3f);
  large_.clear();
  // Each item's cells, found once for the counting and filling passes below.
  ranges_.resize(items.size());
  std::size_t count = 0;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Aabb& b = items[i].box;
    CellRange& r = ranges_[i];
    r = {cellOf(b.lower.x), cellOf(b.upper.x), cellOf(b.lower.y), cellOf(b.upper.y)};
    const std::int64_t cells = (std::int64_t{r.x1} - r.x0 + 1) * (std::int64_t{r.y1} - r.y0 + 1);
    if (cells > kMaxCells) {
      large_.push_back(items[i]);
      r.x1 = r.x0 - 1;
    } else {
      count += static_cast<std::size_t>(cells);
    }
  }
  std::uint32_t buckets = 16;
  while (buckets < 2 * count)
    buckets *= 2;
  bucketMask_ = buckets - 1;
  bucketStart_.assign(buckets + 1, 0);
  for (const CellRange& r : ranges_)
    for (std::int32_t y = r.y0; r.x0 <= r.x1 && y <= r.y1; ++y)
      for (std::int32_t x = r.x0; x <= r.x1; ++x)
        ++bucketStart_[bucketOf(x, y) + 1];
  // Each bucket padded to a multiple of four entries, so that a query tests whole groups
  // of four: the padding's cell matches no cell (cells are clamped to +-1e9).
  for (std::uint32_t b = 0; b < buckets; ++b)
    bucketStart_[b + 1] = bucketStart_[b] + ((bucketStart_[b + 1] + 3u) & ~3u);
  const std::uint32_t slots = bucketStart_[buckets];
  entryCount_ = count;
  for (auto* column : {&lowerX_, &lowerY_, &upperX_, &upperY_})
    column->resize(slots);
  ids_.resize(slots);
  cellX_.assign(slots, std::numeric_limits<std::int32_t>::min());
  cellY_.resize(slots);
  first_.resize(slots);
  cursor_.assign(bucketStart_.begin(), bucketStart_.end() - 1);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const CellRange& r = ranges_[i];
    const Aabb box = items[i].box;
    for (std::int32_t y = r.y0; r.x0 <= r.x1 && y <= r.y1; ++y) {
      for (std::int32_t x = r.x0; x <= r.x1; ++x) {
        const std::uint32_t k = cursor_[bucketOf(x, y)]++;
        lowerX_[k] = box.lower.x;
        lowerY_[k] = box.lower.y;
        upperX_[k] = box.upper.x;
        upperY_[k] = box.upper.y;
        ids_[k] = items[i].id;
        cellX_[k] = x;
        cellY_[k] = y;
        first_[k] = (x == r.x0 ? 1u : 0u) | (y == r.y0 ? 2u : 0u);
      }
    }
  }
}

void ContinuousPhase::sortByLowerX() {
  // A stable radix sort of the participants (taken in index order) by their boxes' lower x:
  // ties stay in index order, so the order is the same whatever the broad phase. The key
  // is the float's bits made to compare as unsigned integers (negative numbers reversed,
  // -0 taken as +0, as the comparison of floats takes it), above the participant's index.
  // A tenth of the instructions of std::sort's comparisons of keys read through the indices.
  const auto n = static_cast<std::uint32_t>(fast_.size());
  sortKeys_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const float x = fast_[i].box.lower.x + 0.0f;  // -0 + 0 is +0
    std::uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    bits = (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
    sortKeys_[i] = (std::uint64_t{bits} << 32) | i;
  }
  // Bytes: a few thousand participants at most, for which 2,048 counts a pass cost more.
  radixSortByKey<8>(sortKeys_, sortScratch_, 32, [](std::uint64_t k) { return k >> 32; });
  sorted_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i)
    sorted_[i] = static_cast<std::uint32_t>(sortKeys_[i]);
}

void ContinuousPhase::buildIndex() {
  // Which participant is found from which cell never changes an answer (a search keeps the
  // earliest impact by a total order, and re-checks are sorted).
  gridItems_.clear();
  for (std::uint32_t p = 0; p < fast_.size(); ++p)
    gridItems_.push_back({fast_[p].box, p});
  grid_.build(gridItems_);
  for (const BoxGrid::Item& m : moved_)
    movedSlot_[m.id] = 0;
  moved_.clear();
  indexed_ = static_cast<std::uint32_t>(fast_.size());
  indexBuilt_ = true;
}

template <class Visit>
void ContinuousPhase::queryParticipants(Aabb box, Visit&& visit) const {
  // A participant not in moved_ still has the box it was indexed with.
  grid_.query(box, [&](std::uint32_t p) {
    if (movedSlot_[p] == 0) visit(p);
  });
  for (const BoxGrid::Item& m : moved_)
    if (overlaps(m.box, box)) visit(m.id);
}

bool ContinuousPhase::anchoredByJoint(const BodyStore& store, std::uint32_t body) const {
  if (joints_->jointCountOf(body) == 0) return false;
  bool anchored = false;
  joints_->forEachOf(body, [&](std::uint32_t j) {
    const std::uint32_t other = joints_->other(j, body);
    anchored = anchored || other == kNoBody || store.bodies[other].type != BodyType::dynamicBody;
  });
  return anchored;
}

bool ContinuousPhase::heldBySolver(const BodyStore& store, std::uint32_t shapeA,
                                   std::uint32_t shapeB, std::uint32_t fastA,
                                   std::uint32_t fastB) const {
  const Body& a = store.bodies[store.shapes[shapeA].body];
  const Body& b = store.bodies[store.shapes[shapeB].body];
  if (a.bullet || b.bullet || a.type != BodyType::dynamicBody || b.type != BodyType::dynamicBody)
    return false;
  // An impact's response moves and turns the two bodies as if they were free. A body held
  // by a joint to static or kinematic geometry (a paddle on a motor, a pendulum, a door, a
  // body on a mouse joint) cannot be moved so without opening that joint: a motor-driven
  // paddle hit by a box was knocked 7 cm off its pivot. Its encounters with other dynamic
  // bodies are the solver's, with its joints, as Box2D v3 leaves every non-bullet pair of
  // dynamic bodies (read for understanding); against static geometry it is still swept.
  // Bodies jointed only to dynamic bodies (a ragdoll's limbs, a car's wheels) keep their
  // sweeps: their partners move too, and the solver closes the joints in the next step,
  // while without sweeps a falling ragdoll's limbs sank into what they hit and stayed
  // wedged there with their joints 11 cm open.
  if (fast_[fastA].anchored ||
      (fastB != kNoParticipant ? fast_[fastB].anchored
                               : anchoredByJoint(store, store.shapes[shapeB].body)))
    return true;
  const std::uint32_t* c = contacts_->find(shapeA, shapeB);
  return c != nullptr && contacts_->contacts[*c].touching && !contacts_->contacts[*c].sensor;
}

bool ContinuousPhase::findImpactWith(SearchScratch& scratch, const BodyStore& store,
                                     const BroadPhase& broadPhase, const GhostEdges& edges,
                                     std::uint32_t fast, bool continuation, ToiCandidate& best,
                                     std::uint32_t onlyBody) const {
  const FastBody& f = fast_[fast];
  const Body& body = store.bodies[f.body];
  std::vector<std::uint32_t>& candidates_ = scratch.candidates;
  std::vector<std::uint32_t>& near_ = scratch.near;
  candidates_.clear();
  near_.clear();
  // Static and kinematic shapes, and dynamic bodies that stand still (not followed yet),
  // come from the broad phase; followed bodies from their swept boxes (a fast body's
  // broad-phase box is at its end pose, which may be far from where two paths cross).
  // A body anchored by a joint meets only static and kinematic shapes and bullets (see
  // heldBySolver): the rest are skipped here, before any search (a 40 m paddle's sweep
  // covers thousands of bodies).
  const bool anchored = !body.bullet && f.anchored;
  // Without WorldDef::sweepDynamicPairs a body that is not a bullet meets static and
  // kinematic shapes only (a bullet's own search finds it).
  const bool staticOnly = !sweepDynamicPairs_ && !body.bullet;
  auto consider = [&](std::uint32_t s) {
    const Shape& other = store.shapes[s];
    if (other.body == f.body || other.def.sensor) return;
    if (participantOf_[other.body] != kNoParticipant) return;
    // Jointed bodies do not collide unless the joint says so (JointDef::collideConnected):
    // a pendulum is not stopped at its pivot's post. Between dynamic bodies jointed pairs
    // are still swept: a falling ragdoll's limbs hold each other so, and without it its
    // joints came to rest up to 17 cm open
    // (JointScenes.RagdollDroppedOnAPyramidNeverGainsEnergyAndRests).
    if (store.bodies[other.body].type != BodyType::dynamicBody &&
        joints_->blocksCollision(f.body, other.body))
      return;
    if (anchored || staticOnly) {
      const Body& ob = store.bodies[other.body];
      if (ob.type == BodyType::dynamicBody && (staticOnly || !ob.bullet)) return;
    }
    candidates_.push_back(s);
  };
  if (onlyBody != 0xffffffffu) {
    const std::uint32_t p = participantOf_[onlyBody];
    if (p != kNoParticipant) {
      if (p != fast) near_.push_back(p);
    } else {
      for (std::uint32_t s : store.bodies[onlyBody].shapes)
        consider(s);
    }
  } else {
    if (listed_) {
      for (const ListedShape& l : listedShapes_)
        if (overlaps(l.box, f.box)) consider(l.shape);
    } else if (stillGridded_) {
      stillGrid_.query(f.box, consider);
    } else {
      broadPhase.queryAabb(f.box, [&](ProxyId, std::uint64_t user) {
        consider(static_cast<std::uint32_t>(user));
        return true;
      });
    }
    if (!staticOnly) {
      queryParticipants(f.box, [&](std::uint32_t p) {
        if (p != fast) near_.push_back(p);
      });
    }
  }
  // Not sorted: `best` is the earliest by (time, shapeA, shapeB), a total order over the
  // pairs tested (each at most once), so the order they are tested in cannot change it.
  bool found = false;
  // The time of impact of one of this body's shapes (moving with `sweep`, which covers
  // [from, 1]) with shape s moving with `otherSweep`.
  auto test = [&](std::uint32_t own, const ShapeProxy& proxy, const Sweep& sweep, float from,
                  std::uint32_t s, const Sweep& otherSweep, std::uint32_t other,
                  std::uint32_t otherStamp) {
    const Shape& shape = store.shapes[own];
    const Shape& otherShape = store.shapes[s];
    if (otherShape.def.sensor || !shouldCollide(shape.def.filter, otherShape.def.filter)) return;
    // Two dynamic bodies that touch at the start of the step (a manifold with points) are
    // the contact solver's, as two slow bodies are: its speculative contact already stops
    // them closing further than their gap, so neither can pass through the other. Sweeping
    // them too made the phase a second solver inside piles (world_suite's compounds, 3,000
    // bodies raining into a pit: thousands of queued impacts a step). Bullets are always
    // swept.
    if (heldBySolver(store, own, s, fast, other)) return;
    const ShapeProxy otherProxy = makeProxy(*otherShape.geometry);
    ++scratch.toiSearches;
    ToiOutput toi = computeToi(proxy, sweep, otherProxy, otherSweep);
    bool stop = false;
    if ((toi.status == ToiStatus::hit || toi.status == ToiStatus::failed) && toi.t == 0.0f) {
      // Already within the target at the start: usually the shape the body hit last
      // (this step or the step before). Aim at half the present gap, so that the body may
      // slide along it but not into it. With no gap left to halve the pair is touching:
      // at the start of the step the contact solver has it; in a continued sweep, stop.
      if (toi.distance > 4.0f * kToiMinTolerance) {
        toi = computeToi(proxy, sweep, otherProxy, otherSweep, 1.0f, 0.5f * toi.distance);
        if (toi.status != ToiStatus::hit && toi.status != ToiStatus::failed) return;
        stop = toi.t == 0.0f;
      } else {
        if (!continuation && from == 0.0f) return;
        stop = true;
      }
    } else if (toi.status == ToiStatus::overlapped && (continuation || from > 0.0f)) {
      // Overlapping (within the contact solver's slop) at the start of a continued sweep: a
      // body resting against a wall that an impact now pushes into it. Stop it here, with
      // an impact, when its sweep moves it deeper; otherwise it is the contact solver's.
      stop = true;
    } else if (toi.status != ToiStatus::hit && toi.status != ToiStatus::failed) {
      return;  // separated, or overlapping at the start of the step (the contact solver's)
    }
    if (stop) {
      // Touching or overlapping at the start: an impact only when the sweeps move the
      // shapes together there (two bodies resting on each other are the contact solver's).
      const float t0 = toi.t;
      auto velocityAt = [&](const Sweep& w) {
        const Vec2 center = (1.0f - t0) * w.c1 + t0 * w.c2;
        return (w.c2 - w.c1) + cross(w.a2 - w.a1, toi.point - center);
      };
      if (dot(velocityAt(otherSweep) - velocityAt(sweep), toi.normal) >= 0.0f) return;
    }
    // A failed search returns the last time proven free: stopping there never tunnels.
    ToiCandidate c;
    c.time = from + toi.t * (1.0f - from);
    c.fast = fast;
    c.stamp = f.stamp;
    c.other = other;
    c.otherStamp = otherStamp;
    c.shapeA = own;
    c.shapeB = s;
    // Ghost collisions: an impact on a flush seam of static geometry, or from behind a
    // chain, is not a surface (edges.cpp); the discrete contacts handle the real ones.
    if (edges.activeShapes() != 0 && otherShape.edges.active &&
        edges.isGhostImpact(store, s, toi.point, -toi.normal))
      return;
    c.point = toi.point;
    c.normal = toi.normal;
    c.stop = stop || toi.status == ToiStatus::failed;
    if (!found || earlier(c, best)) best = c;
    found = true;
  };
  // The participants near the sweep that pass the pair rules below, with both sweeps over
  // the part of the step they share: found once, for every shape of this body.
  std::vector<NearSweep>& passing = scratch.passing;
  passing.clear();
  for (std::uint32_t p : near_) {
    const FastBody& g = fast_[p];
    // In the first searches every participant searches, and the tests of a pair are the
    // same from either side: the participant with the lower index tests it. An impact
    // it does not queue (it has an earlier one) is found again when that earlier one is
    // handled, since its body then searches again and every sweep it meets is re-checked.
    if (!continuation && p < fast) continue;
    if ((anchored && !store.bodies[g.body].bullet) || staticOnly) continue;
    if (!overlaps(g.box, f.box)) continue;
    // Both sweeps over the same part of the step: from the later of their starts.
    const float from = maxf(f.t0, g.t0);
    auto over = [from](const FastBody& x) {
      return x.t0 < from ? advance(x.sweep, clampf((from - x.t0) / (1.0f - x.t0), 0.0f, 1.0f))
                         : x.sweep;
    };
    const Sweep mine = over(f), theirs = over(g);
    const Body& otherBody = store.bodies[g.body];
    // Moving together: when one body moves relative to the other by less than the
    // fraction of the thinner one's thickness that makes a body fast (kCcdFastFraction),
    // neither can pass through the other in this step, for the reason a slow body cannot
    // pass through a wall: the discrete contacts hold them. Neighbours in a falling pile
    // or a scattered crowd move much alike and end here, without a search.
    const float relativeMotion = length((theirs.c2 - theirs.c1) - (mine.c2 - mine.c1)) +
                                 absf(theirs.a2 - theirs.a1) * otherBody.maxExtent +
                                 absf(mine.a2 - mine.a1) * body.maxExtent;
    if (relativeMotion < kCcdFastFraction * minf(body.minExtent, otherBody.minExtent)) continue;
    // Bounding circles (each body within its maxExtent of its centre of mass): when the
    // centres, moving linearly, never come within the sum (plus the target and band), no
    // shape pair can meet. Most neighbours of a crowd end here without a search.
    const Vec2 offset = theirs.c1 - mine.c1;
    const Vec2 rate = (theirs.c2 - theirs.c1) - (mine.c2 - mine.c1);
    const float rr = lengthSquared(rate);
    const float u = rr > 0.0f ? clampf(-dot(offset, rate) / rr, 0.0f, 1.0f) : 0.0f;
    const float reach = body.maxExtent + otherBody.maxExtent + kToiTargetSeparation + kToiTolerance;
    if (lengthSquared(offset + u * rate) > reach * reach) continue;
    passing.push_back({p, from, mine, theirs});
  }
  // Most sweeps in a crowd end here, before any shape's proxy is formed.
  if (candidates_.empty() && passing.empty()) return false;
  for (std::uint32_t own : body.shapes) {
    const Shape& shape = store.shapes[own];
    if (shape.def.sensor) continue;
    const ShapeProxy proxy = makeProxy(*shape.geometry);
    for (std::uint32_t s : candidates_) {
      const Body& ob = store.bodies[store.shapes[s].body];
      const float angle = ob.xf.q.angle();
      test(own, proxy, f.sweep, f.t0, s, {ob.localCenter, ob.center, ob.center, angle, angle},
           kNoParticipant, 0);
    }
    for (const NearSweep& n : passing) {
      const FastBody& g = fast_[n.participant];
      for (std::uint32_t s : store.bodies[g.body].shapes)
        test(own, proxy, n.mine, n.from, s, n.theirs, n.participant, g.stamp);
    }
  }
  return found;
}

std::span<const std::uint32_t> ContinuousPhase::run(StepContext& step,
                                                    const std::vector<std::uint64_t>& awake,
                                                    const GhostEdges& edges,
                                                    const ContactSet& contacts) {
  const WorldDef& def = step.def;
  BodyStore& store = step.store;
  BroadPhase& broadPhase = step.broadPhase;
  EventDispatcher& events = step.events;
  TaskRunner& tasks = step.tasks;
  const float dt = step.dt;
  contacts_ = &contacts;
  joints_ = &step.joints;
  sweepDynamicPairs_ = def.sweepDynamicPairs;
  pushed_.clear();
  stats_ = {};
  for (SearchScratch& scratch : scratch_)
    scratch.toiSearches = 0;
  if (!def.enableContinuous) return pushed_;
  fast_.clear();
  sorted_.clear();
  indexBuilt_ = false;
  indexed_ = 0;
  waitNodes_.clear();
  moved_.clear();
  movedSlot_.clear();
  // Entries are reset after each run (only the participants'), so that a step with a few
  // fast bodies among many asleep costs nothing per body.
  if (participantOf_.size() < store.bodies.size()) {
    participantOf_.resize(store.bodies.size(), kNoParticipant);
    waitHead_.resize(store.bodies.size(), kNoParticipant);
  }
  // Only bodies that moved can be fast (sleeping ones are not).
  for (std::size_t word = 0; word < awake.size(); ++word) {
    for (std::uint64_t bits = awake[word]; bits != 0; bits &= bits - 1) {
      const auto i = static_cast<std::uint32_t>(word * 64 + __builtin_ctzll(bits));
      // The flag stays set until the solver's next step: the contact set does not recycle
      // the manifolds of a body that moved fast (contact_set.cpp).
      if (store.bodies[i].fast) addParticipant(store, i, true);
    }
  }
  stats_.fastBodies = fast_.size();
  if (fast_.empty()) return pushed_;
  // Few shapes outside the participants: list them (see listedShapes_). Every shape has a
  // broad-phase proxy; the list holds everything a query would find (its boxes are the fat
  // ones, which hold the tight ones some broad phases test; an extra candidate is only an
  // extra search, and the earliest impact does not depend on the candidates' order).
  // Bodies that join later are skipped in the search as in a query (participantOf_).
  std::uint32_t participantShapes = 0;
  for (const FastBody& f : fast_)
    participantShapes += static_cast<std::uint32_t>(store.bodies[f.body].shapes.size());
  listedShapes_.clear();
  listed_ = broadPhase.proxyCount() <= participantShapes + kMaxListedShapes;
  if (listed_) {
    for (std::uint32_t s = 0; s < store.shapes.size(); ++s) {
      if (!store.shapeAlive(s)) continue;
      const Shape& shape = store.shapes[s];
      if (shape.def.sensor || participantOf_[shape.body] != kNoParticipant) continue;
      listedShapes_.push_back({s, broadPhase.fatBox(shape.proxy)});
    }
  }
  const std::uint32_t stillShapes = broadPhase.proxyCount() - participantShapes;
  stillGridded_ = !listed_ && 2 * stillShapes <= broadPhase.proxyCount();
  if (stillGridded_) {
    gridItems_.clear();
    for (std::uint32_t s = 0; s < store.shapes.size(); ++s) {
      if (!store.shapeAlive(s)) continue;
      const Shape& shape = store.shapes[s];
      if (shape.def.sensor || participantOf_[shape.body] != kNoParticipant) continue;
      gridItems_.push_back({broadPhase.tightBox(shape.proxy), s});
    }
    stillGrid_.build(gridItems_);
  }
  sortByLowerX();
  buildIndex();

  // A min-heap by time (std's heap functions keep the largest on top: invert the order).
  auto later = [](const ToiCandidate& x, const ToiCandidate& y) { return earlier(y, x); };
  queue_.clear();
  auto push = [&](const ToiCandidate& c) {
    const std::uint32_t with = store.shapes[c.shapeB].body;
    fast_[c.fast].bestTime = c.time;
    fast_[c.fast].bestBody = with;
    // Only a dynamic body can change during the phase (become or be a participant).
    if (store.bodies[with].type == BodyType::dynamicBody) {
      waitNodes_.push_back({c.fast, with, waitHead_[with]});
      waitHead_[with] = static_cast<std::uint32_t>(waitNodes_.size() - 1);
    }
    queue_.push_back(c);
    std::push_heap(queue_.begin(), queue_.end(), later);
  };
  // The first searches, on the workers (each reads the step's state, and writes its own
  // result and its worker's scratch), then queued in participant order.
  if (scratch_.size() < static_cast<std::size_t>(tasks.workers()))
    scratch_.resize(static_cast<std::size_t>(tasks.workers()));
  first_.resize(fast_.size());
  firstFound_.resize(fast_.size());
  const BodyStore& readStore = store;
  const BroadPhase& readBroadPhase = broadPhase;
  // Sweep-and-prune restores its order lazily, in its first query after changes (the
  // solver has just moved proxies): one query here, so that those on the workers only read.
  // (Any valid box flushes it; an empty one at the origin always is valid.)
  if (tasks.workers() > 1 && !listed_ && !stillGridded_)
    broadPhase.queryAabb(Aabb{}, [](ProxyId, std::uint64_t) { return false; });
  tasks.parallelFor(static_cast<int>(fast_.size()), kMinSearchesPerTask,
                    [&](int begin, int end, int participant) {
                      SearchScratch& scratch = scratch_[static_cast<std::size_t>(participant)];
                      for (int k = begin; k < end; ++k) {
                        // In the order of the swept boxes along x, not of the bodies:
                        // neighbouring searches then walk the same tree nodes, warm in the
                        // cache (the order they run in changes no result).
                        const std::uint32_t i = sorted_[static_cast<std::size_t>(k)];
                        const auto at = static_cast<std::size_t>(i);
                        firstFound_[at] = findImpactWith(scratch, readStore, readBroadPhase, edges,
                                                         i, false, first_[at], 0xffffffffu)
                                              ? 1
                                              : 0;
                      }
                    });
  for (std::size_t i = 0; i < fast_.size(); ++i)
    if (firstFound_[i] != 0) push(first_[i]);

  // Moves participant p to step fraction `time` (the start of what remains of its sweep).
  auto moveTo = [&](FastBody& p, float time) {
    if (p.t0 < time && p.t0 < 1.0f)
      p.sweep = advance(p.sweep, clampf((time - p.t0) / (1.0f - p.t0), 0.0f, 1.0f));
    p.t0 = maxf(p.t0, time);
  };
  // Sets what remains of p's motion from its present start (c, angle at p.t0): on with the
  // body's velocity, or held there. Then the body's pose, broad-phase and swept boxes follow.
  auto resweep = [&](std::uint32_t index, bool hold) {
    FastBody& p = fast_[index];
    Body& b = store.bodies[p.body];
    const Vec2 c = p.sweep.c1;
    const float angle = p.sweep.a1;
    const float remaining = (1.0f - p.t0) * dt;
    if (!hold && remaining > 0.0f) {
      p.sweep = {b.localCenter, c, c + remaining * (b.v - p.baseV), angle,
                 angle + remaining * (b.w - p.baseW)};
    } else {
      p.sweep = {b.localCenter, c, c, angle, angle};
    }
    auto within = [&](Vec2 center, float at) {
      return store.shapesWithinWorld(
          p.body, makeTransform(center - rotate(Rot::fromAngle(at), b.localCenter), at));
    };
    // Where the body ends the step; false: where the step's solver left it (see below).
    bool place = true;
    if (!within(p.sweep.c2, p.sweep.a2)) {
      // The rest of the sweep would leave the world (kMaxCoordinate): stop here, as the
      // solver does with a body at the edge (StepEvents::outOfBounds).
      p.sweep = {b.localCenter, c, c, angle, angle};
      b.v = {};
      b.w = 0.0f;
      events.events.outOfBounds.push_back(store.bodyId(p.body));
      // A long shape at the edge of the world may reach past it at the impact's angle and
      // not at the step's two ends (found by the snapshot fuzzer): then it stays where the
      // solver left it, a pose the world has accepted.
      if (!within(c, angle)) {
        const float end = b.xf.q.angle();
        p.sweep = {b.localCenter, b.center, b.center, end, end};
        place = false;
      }
    }
    p.box = sweptBox(store, p);
    markMoved(index);
    ++p.stamp;
    p.bestTime = 2.0f;
    p.bestBody = 0xffffffffu;
    if (!place) return;
    // The body ends the step where its new sweep ends; the broad phase follows at once so
    // that later searches see it there.
    const Vec2 oldCenter = b.center;
    b.center = p.sweep.c2;
    b.xf.q = Rot::fromAngle(p.sweep.a2);
    b.xf.p = b.center - rotate(b.xf.q, b.localCenter);
    store.updateShapeBoxes(broadPhase, p.body, b.center - oldCenter);
  };

  std::vector<std::uint32_t> changed;
  while (!queue_.empty()) {
    // Many boxes changed since the index was built: index them again, so that queries do
    // not scan them one by one.
    if (moved_.size() > 32 + indexed_ / 32) buildIndex();
    std::pop_heap(queue_.begin(), queue_.end(), later);
    const ToiCandidate e = queue_.back();
    queue_.pop_back();
    if (e.stamp != fast_[e.fast].stamp) continue;  // the sweep changed since this was found
    const std::uint32_t otherBody = store.shapes[e.shapeB].body;
    std::uint32_t o = participantOf_[otherBody];
    if (e.other != o || (o != kNoParticipant && e.otherStamp != fast_[o].stamp)) continue;
    Body& b = store.bodies[fast_[e.fast].body];
    Body& ob = store.bodies[otherBody];
    const bool otherMoves = ob.type == BodyType::dynamicBody &&
                            (o == kNoParticipant || fast_[o].events < kMaxToiEventsPerBody);
    // What a still dynamic body's pose already holds of its motion (see FastBody::baseV).
    const Vec2 otherV = ob.v;
    const float otherW = ob.w;
    FastBody& f = fast_[e.fast];
    f.bestTime = 2.0f;
    f.bestBody = 0xffffffffu;

    // Both bodies to the time of impact.
    moveTo(f, e.time);
    const Vec2 c = f.sweep.c1;
    const float angle = f.sweep.a1;
    Transform otherXf = ob.xf;
    Vec2 otherCenter = ob.center;
    if (o != kNoParticipant) {
      moveTo(fast_[o], e.time);
      otherCenter = fast_[o].sweep.c1;
      const Rot q = Rot::fromAngle(fast_[o].sweep.a1);
      otherXf = {otherCenter - rotate(q, ob.localCenter), q};
    }

    // Immediate velocity response at the impact, with both bodies' masses: restitution as
    // the solver's (the larger of the pair, above the threshold), then Coulomb friction (the
    // solver's mix) capped by the normal impulse. The impulse acts at the middle of the
    // contact manifold at the impact poses, so that a face meeting a face is pushed square
    // (TOI's single witness point is a corner, and an impulse there would start a spurious
    // spin).
    //
    // The two impulses are applied one after the other, friction from the velocity the
    // normal impulse left: each is then a one-dimensional impulse that cannot add kinetic
    // energy (restitution e <= 1 loses (1 - e^2) of the normal part; friction, clamped, only
    // slows the sliding). Computed together from the velocity before the impact, a turning
    // body's friction and normal impulses act on each other through its inertia and can add
    // energy at every impact (four bars with friction in a closed box gained 9,000x their
    // energy in 25 steps). Both bodies are then held to the speed limits at once, so that a
    // restitution above 1 cannot drive them past the limits inside a step.
    Vec2 n = e.normal;
    Vec2 hitPoint = e.point;
    const Transform xfAt = {c - rotate(Rot::fromAngle(angle), b.localCenter),
                            Rot::fromAngle(angle)};
    const Shape& shapeA = store.shapes[e.shapeA];
    const Shape& shapeB = store.shapes[e.shapeB];
    const Manifold m = quack::collide(*shapeA.geometry, xfAt, *shapeB.geometry, otherXf,
                                      kToiTargetSeparation + 2.0f * kToiTolerance);
    if (m.pointCount > 0) {
      n = m.normal;
      hitPoint = m.points[0].point;
      if (m.pointCount == 2) hitPoint = 0.5f * (m.points[0].point + m.points[1].point);
    }
    const Vec2 rA = hitPoint - c;
    const Vec2 rB = hitPoint - otherCenter;
    // Velocity of B's point relative to A's at the hit point (B's is zero when static).
    auto relativeVelocity = [&] { return ob.v + cross(ob.w, rB) - (b.v + cross(b.w, rA)); };
    auto applyImpulse = [&](Vec2 impulse) {  // on B; A gets its opposite
      b.v -= b.invMass * impulse;
      b.w -= b.invInertia * cross(rA, impulse);
      if (otherMoves) {
        ob.v += ob.invMass * impulse;
        ob.w += ob.invInertia * cross(rB, impulse);
      }
    };
    const float vn = dot(relativeVelocity(), n);
    bool impulseApplied = false;
    if (vn < 0.0f) {
      float e0 = maxf(shapeA.def.restitution, shapeB.def.restitution);
      if (-vn < def.restitutionThreshold) e0 = 0.0f;
      const float rnA = cross(rA, n), rnB = cross(rB, n);
      float k = b.invMass + b.invInertia * rnA * rnA;
      if (otherMoves) k += ob.invMass + ob.invInertia * rnB * rnB;
      if (k > 0.0f) {
        const float jn = -(1.0f + e0) * vn / k;
        applyImpulse(jn * n);
        const Vec2 tangent = rightPerp(n);
        const float rtA = cross(rA, tangent), rtB = cross(rB, tangent);
        float kt = b.invMass + b.invInertia * rtA * rtA;
        if (otherMoves) kt += ob.invMass + ob.invInertia * rtB * rtB;
        const float mu = std::sqrt(shapeA.def.friction * shapeB.def.friction);
        const float jt =
            kt > 0.0f ? clampf(-dot(relativeVelocity(), tangent) / kt, -mu * jn, mu * jn) : 0.0f;
        applyImpulse(jt * tangent);
        b.v = clampSpeed(b.v);
        b.w = clampf(b.w, -kMaxAngularSpeed, kMaxAngularSpeed);
        if (otherMoves) {
          ob.v = clampSpeed(ob.v);
          ob.w = clampf(ob.w, -kMaxAngularSpeed, kMaxAngularSpeed);
          pushed_.push_back(otherBody);
        }
        impulseApplied = true;
      }
    }
    events.events.toi.push_back({e.time, store.shapeId(e.shapeA), store.shapeId(e.shapeB), e.point,
                                 e.normal, maxf(0.0f, -vn)});

    // The rest of the step for both: on with the new velocities, or, past the bound, held.
    changed.clear();
    auto finishBody = [&](std::uint32_t index, bool stopped) {
      FastBody& p = fast_[index];
      ++p.events;
      const bool capped = p.events >= kMaxToiEventsPerBody;
      if (capped) events.events.toiCapped.push_back(store.bodyId(p.body));
      if (capped || stopped) p.searching = false;
      resweep(index, capped || stopped);
      changed.push_back(index);
    };
    finishBody(e.fast, e.stop);
    if (otherMoves && impulseApplied) {
      // A dynamic body an impact sets moving is followed from now on (only then: entries of
      // others that met it standing still stay valid until it moves, and the re-check below
      // renews them when it does).
      if (o == kNoParticipant) {
        o = addParticipant(store, otherBody, false);
        fast_[o].baseV = otherV;
        fast_[o].baseW = otherW;
        moveTo(fast_[o], e.time);  // it stood still until now: its sweep starts here
      }
      fast_[o].searching = true;  // it looks along its new sweep
      finishBody(o, false);
    }

    // Re-check what the changed sweeps touch: their own new sweeps, then every followed
    // body whose queued impact was with one of them (search again from scratch) or whose
    // swept box meets a new one (checked against that body alone; an earlier impact goes
    // into the queue beside its old one, which is then stale). None is earlier than this.
    // Those waiting on a changed body are taken from its list first, and the list emptied
    // (each is re-checked below and queues afresh), so that what the changed bodies' own
    // searches queue next (one may wait on the other) stays listed.
    recheck_.clear();
    for (std::uint32_t index : changed) {
      const std::uint32_t body = fast_[index].body;
      for (std::uint32_t node = waitHead_[body]; node != kNoParticipant;
           node = waitNodes_[node].next) {
        const std::uint32_t g = waitNodes_[node].participant;
        if (fast_[g].bestBody == body) recheck_.push_back(g);
      }
      waitHead_[body] = kNoParticipant;
    }
    for (std::uint32_t index : changed) {
      ToiCandidate next;
      if (fast_[index].searching && findImpact(store, broadPhase, edges, index, true, next))
        push(next);
    }
    for (std::uint32_t index : changed) {
      queryParticipants(fast_[index].box, [&](std::uint32_t g) { recheck_.push_back(g); });
    }
    std::sort(recheck_.begin(), recheck_.end());
    recheck_.erase(std::unique(recheck_.begin(), recheck_.end()), recheck_.end());
    for (std::uint32_t g : recheck_) {
      FastBody& p = fast_[g];
      if (!p.searching || g == changed[0] || (changed.size() > 1 && g == changed[1])) continue;
      // Only re-parameterised (same path, and its swept box still holds it): its queued
      // impact stays valid.
      moveTo(p, e.time);
      for (std::uint32_t index : changed) {
        const std::uint32_t moved = fast_[index].body;
        ToiCandidate next;
        if (p.bestBody == moved) {
          ++p.stamp;
          p.bestTime = 2.0f;
          p.bestBody = 0xffffffffu;
          if (findImpact(store, broadPhase, edges, g, true, next)) push(next);
        } else if (overlaps(p.box, fast_[index].box) &&
                   findImpact(store, broadPhase, edges, g, true, next, moved) &&
                   next.time < p.bestTime) {
          push(next);
        }
      }
    }
  }
  for (const SearchScratch& scratch : scratch_)
    stats_.toiSearches += scratch.toiSearches;
  for (const FastBody& f : fast_)
    participantOf_[f.body] = kNoParticipant;
  for (const WaitNode& node : waitNodes_)
    waitHead_[node.body] = kNoParticipant;
  return pushed_;
}

}  // namespace quack::detail
