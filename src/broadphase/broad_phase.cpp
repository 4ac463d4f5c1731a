#include "quack/broadphase/broad_phase.hpp"

#include <algorithm>
#include <string>

namespace quack {

namespace {

std::string describe(ProxyId id) {
  return "{index " + std::to_string(id.index) + ", generation " + std::to_string(id.generation) +
         "}";
}

Status checkBox(Aabb b, const char* function, const char* argument) {
  const char* problem = nullptr;
  if (!isFinite(b.lower) || !isFinite(b.upper)) {
    problem = "has a NaN or infinite coordinate";
  } else if (b.lower.x > b.upper.x || b.lower.y > b.upper.y) {
    problem = "is inverted (lower > upper)";
  } else if (b.lower.x < -kMaxCoordinate || b.lower.y < -kMaxCoordinate ||
             b.upper.x > kMaxCoordinate || b.upper.y > kMaxCoordinate) {
    problem = "lies beyond kMaxCoordinate (1e9 m) from the origin";
  }
  if (problem == nullptr) return {};
  return fail(std::string(function) + ": " + argument + " " + problem);
}

}  // namespace

const char* toString(BroadPhaseKind kind) noexcept {
  switch (kind) {
    case BroadPhaseKind::tree:
      return "tree";
    case BroadPhaseKind::quadtree:
      return "quadtree";
    case BroadPhaseKind::sap:
      return "sap";
    case BroadPhaseKind::hash:
      return "hash";
    case BroadPhaseKind::brute:
      return "brute";
  }
  return "unknown";
}

Result<BroadPhaseKind> parseBroadPhaseKind(std::string_view name) {
  for (BroadPhaseKind k : kAllBroadPhaseKinds) {
    if (toString(k) == name) return k;
  }
  return fail("unknown broad phase '" + std::string(name) +
              "' (expected tree, quadtree, sap, hash or brute)");
}

Result<BroadPhase> BroadPhase::create(BroadPhaseConfig config) {
  if (!isFinite(config.margin) || config.margin < 0.0f) {
    return fail("BroadPhaseConfig.margin must be finite and >= 0");
  }
  if (!isFinite(config.displacementScale) || config.displacementScale < 0.0f) {
    return fail("BroadPhaseConfig.displacementScale must be finite and >= 0");
  }
  if (!isFinite(config.cellSize) || config.cellSize <= 0.0f) {
    return fail("BroadPhaseConfig.cellSize must be finite and > 0");
  }
  if (config.cellSize < kMinCellSize || config.cellSize > kMaxCoordinate) {
    return fail(
        "BroadPhaseConfig.cellSize must be in [1e-6, 1e9] m (kMinCellSize to "
        "kMaxCoordinate)");
  }
  switch (config.kind) {
    case BroadPhaseKind::tree:
    case BroadPhaseKind::quadtree:
    case BroadPhaseKind::sap:
    case BroadPhaseKind::hash:
    case BroadPhaseKind::brute:
      return BroadPhase(config);
  }
  return fail("BroadPhaseConfig.kind is not a BroadPhaseKind");
}

BroadPhase::BroadPhase(BroadPhaseConfig config) : config_(config) {
  switch (config.kind) {
    case BroadPhaseKind::tree:
      index_.emplace<DynamicTree>();
      break;
    case BroadPhaseKind::quadtree:
      index_.emplace<Quadtree>(config.cellSize);
      break;
    case BroadPhaseKind::sap:
      index_.emplace<SweepAndPrune>();
      break;
    case BroadPhaseKind::hash:
      index_.emplace<SpatialHash>(config.cellSize);
      break;
    case BroadPhaseKind::brute:
      index_.emplace<BruteForce>();
      break;
  }
}

Status BroadPhase::checkId(ProxyId id, const char* function) const {
  if (isValid(id)) return {};
  if (id.index == kNullIndex) return fail(std::string(function) + ": proxy id is null");
  if (id.index >= records_.size()) {
    return fail(std::string(function) + ": proxy id " + describe(id) + " was never created");
  }
  return fail(std::string(function) + ": proxy id " + describe(id) +
              " is stale (that proxy was destroyed)");
}

void BroadPhase::buffer(std::uint32_t proxy) {
  if ((flags_[proxy] & kBuffered) != 0) return;
  flags_[proxy] |= kBuffered;
  moveBuffer_.push_back(proxy);
}

Result<ProxyId> BroadPhase::createProxy(Aabb box, std::uint64_t userData, Filter filter,
                                        ProxyKind kind, std::optional<float> margin) {
  if (Status s = checkBox(box, "createProxy", "box"); !s) return fail(s.message());
  if (margin && (!isFinite(*margin) || *margin < 0.0f))
    return fail("createProxy: margin must be finite and >= 0, got " + std::to_string(*margin));
  if (ids_.nextIndex() >= 0x7fffffffu) return fail("createProxy: too many proxies (2^31)");
  // Slots and generations come from the IdPool (core): a fresh slot has generation 1, so
  // the default (null) id never matches a live proxy.
  const std::uint32_t p = ids_.allocate();
  if (p == records_.size()) {
    records_.push_back({});
    fat_.push_back({});
    tight_.push_back({});
    margins_.push_back(0.0f);
    flags_.push_back(0);
  }
  Record& r = records_[p];
  r.filter = filter;
  r.userData = userData;
  flags_[p] = static_cast<std::uint8_t>(kind == ProxyKind::staticProxy ? kStatic : 0);
  tight_[p] = box;
  margins_[p] = margin ? *margin : config_.margin;
  fat_[p] = inflate(box, margins_[p]);
  std::visit([&](auto& index) { index.insert(p, fat_[p]); }, index_);
  buffer(p);
  return ProxyId{p, ids_.generation(p)};
}

Status BroadPhase::destroyProxy(ProxyId id) {
  if (Status s = checkId(id, "destroyProxy"); !s) return s;
  const std::uint32_t p = id.index;
  std::visit([&](auto& index) { index.remove(p); }, index_);
  // A stale move-buffer entry is skipped by updatePairs (kBuffered is cleared here), and if
  // the slot is reused before then, the new proxy's entry is deduplicated there.
  flags_[p] = 0;
  ids_.release(p);
  return {};
}

Error BroadPhase::rejectMove(ProxyId id, Aabb box, Vec2 displacement) const {
  if (!isValid(id)) return fail(checkId(id, "moveProxy").message());
  if (Status s = checkBox(box, "moveProxy", "box"); !s) return fail(s.message());
  if (!isFinite(displacement)) return fail("moveProxy: displacement is NaN or infinite");
  return fail("moveProxy: rejected");
}

void BroadPhase::reinsert(std::uint32_t p, Aabb wanted) {
  // The stretched box may leave the coordinate range even when the tight box does not.
  const Aabb clamped{maxv(wanted.lower, Vec2{-kMaxCoordinate, -kMaxCoordinate}),
                     minv(wanted.upper, Vec2{kMaxCoordinate, kMaxCoordinate})};
  fat_[p] = clamped;
  // When many proxies move (enlargeMoves_), the tree grows the moved leaf's ancestors in
  // place and rebuilds that part once, when the pairs are next found (a walk up each and
  // one partial build); otherwise, and in the other structures, the proxy moves now.
  auto* tree = std::get_if<DynamicTree>(&index_);
  if (tree != nullptr && enlargeMoves_) {
    tree->enlarge(p, clamped);
  } else {
    std::visit([&](auto& index) { index.move(p, clamped); }, index_);
  }
  buffer(p);
}

Status BroadPhase::setFilter(ProxyId id, Filter f) {
  if (Status s = checkId(id, "setFilter"); !s) return s;
  records_[id.index].filter = f;
  buffer(id.index);
  return {};
}

Status BroadPhase::touchProxy(ProxyId id) {
  if (Status s = checkId(id, "touchProxy"); !s) return s;
  buffer(id.index);
  return {};
}

std::uint64_t BroadPhase::userData(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase::userData: invalid proxy id");
  return isValid(id) ? records_[id.index].userData : 0;
}

Filter BroadPhase::filter(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase::filter: invalid proxy id");
  return isValid(id) ? records_[id.index].filter : Filter{};
}

Aabb BroadPhase::tightBox(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase::tightBox: invalid proxy id");
  return isValid(id) ? tight_[id.index] : Aabb{};
}

Aabb BroadPhase::fatBox(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase::fatBox: invalid proxy id");
  return isValid(id) ? fat_[id.index] : Aabb{};
}

void BroadPhase::addPair(std::uint32_t a, std::uint32_t b, std::vector<ProxyPair>& pairs) const {
  if ((flags_[a] & flags_[b] & kStatic) != 0) return;
  const Record& ra = records_[a];
  const Record& rb = records_[b];
  if (!shouldCollide(ra.filter, rb.filter)) return;
  if (config_.checkTightBoxes && !overlaps(tight_[a], tight_[b])) return;
  ProxyId ia = idOf(a);
  ProxyId ib = idOf(b);
  if (a > b) std::swap(ia, ib);
  if (pairFilter_ != nullptr && !pairFilter_(pairFilterContext_, ia, records_[ia.index].userData,
                                             ib, records_[ib.index].userData)) {
    return;
  }
  pairs.push_back({ia, ib});
}

void BroadPhase::updatePairs(std::vector<ProxyPair>& pairs) {
  pairs.clear();
  beginPairPass();
  if (!sweepPairPass(pairs)) queryMoved(0, moveBuffer_.size(), pairs);
  endPairPass();
}

void BroadPhase::beginPairPass() {
  // The moved proxies' queries (possibly on several threads) read a rebuilt tree.
  if (auto* tree = std::get_if<DynamicTree>(&index_)) tree->rebuildEnlarged();
  // Keep live, buffered entries once each (a destroyed proxy lost kBuffered; a reused slot
  // may appear twice).
  std::size_t kept = 0;
  for (std::uint32_t p : moveBuffer_) {
    if ((flags_[p] & kBuffered) == 0 || (flags_[p] & kInPass) != 0) continue;
    flags_[p] |= kInPass;
    moveBuffer_[kept++] = p;
  }
  moveBuffer_.resize(kept);
  // The moves of the next pass go the way this pass's count says (a step's movers are much
  // like the last step's). From a sixteenth of the proxies up, enlarging and one partial
  // rebuild cost less than a re-insertion each (a world step: a swinging chain re-inserts
  // about half its links, a joint grid a third); below, the few moved leaves are scattered,
  // the rebuilt part is mostly untouched subtrees and the tree it leaves is worse to query
  // (bench/broadphase, 100,000 proxies moving at random, 5% and 0.25% re-inserted a frame:
  // 15% and 40% slower a frame with enlarging).
  enlargeMoves_ = std::size_t{16} * kept >= ids_.liveCount();
}

bool BroadPhase::sweepPairPass(std::vector<ProxyPair>& pairs) {
  auto* sweep = std::get_if<SweepAndPrune>(&index_);
  if (sweep == nullptr) return false;
  auto inPass = [this](std::uint32_t p) { return (flags_[p] & kInPass) != 0; };
  if (sweep->prefersSweep(moveBuffer_.size())) {
    sweep->sweepPairs(inPass, [&](std::uint32_t a, std::uint32_t b) { addPair(a, b, pairs); });
  } else {
    // Its queries sort lazily (not on several threads at once): all of them here.
    queryMoved(0, moveBuffer_.size(), pairs);
  }
  return true;
}

void BroadPhase::queryMoved(std::size_t first, std::size_t last,
                            std::vector<ProxyPair>& pairs) const {
  auto inPass = [this](std::uint32_t p) { return (flags_[p] & kInPass) != 0; };
  std::visit(
      [&](const auto& index) {
        for (std::size_t k = first; k < last; ++k) {
          const std::uint32_t m = moveBuffer_[k];
          index.query(fat_[m], [&](std::uint32_t o) {
            // When both moved, the pair is reported from the lower index only.
            if (o == m || (inPass(o) && o < m)) return true;
            addPair(m, o, pairs);
            return true;
          });
        }
      },
      index_);
}

void BroadPhase::endPairPass() {
  for (std::uint32_t p : moveBuffer_) {
    flags_[p] = static_cast<std::uint8_t>(flags_[p] & ~(kBuffered | kInPass));
  }
  moveBuffer_.clear();
}

std::optional<BroadPhaseHit> BroadPhase::rayCastClosest(Vec2 origin, Vec2 translation) const {
  std::optional<BroadPhaseHit> best;
  rayCast(origin, translation, [&](ProxyId id, std::uint64_t user, float fraction) {
    if (!best || fraction < best->fraction) best = BroadPhaseHit{id, user, fraction};
    // Clipping to the hit leaves only nearer boxes to visit; 0 (starting inside) stops.
    return fraction;
  });
  return best;
}

std::vector<BroadPhaseHit> BroadPhase::rayCastAll(Vec2 origin, Vec2 translation) const {
  std::vector<BroadPhaseHit> hits;
  rayCast(origin, translation, [&](ProxyId id, std::uint64_t user, float fraction) {
    hits.push_back({id, user, fraction});
    return 1.0f;
  });
  std::sort(hits.begin(), hits.end(), [](const BroadPhaseHit& a, const BroadPhaseHit& b) {
    return a.fraction != b.fraction ? a.fraction < b.fraction : a.proxy.index < b.proxy.index;
  });
  return hits;
}

std::optional<BroadPhaseHit> BroadPhase::boxCastClosest(Aabb box, Vec2 translation) const {
  std::optional<BroadPhaseHit> best;
  boxCast(box, translation, [&](ProxyId id, std::uint64_t user, float fraction) {
    if (!best || fraction < best->fraction) best = BroadPhaseHit{id, user, fraction};
    return fraction;
  });
  return best;
}

BroadPhaseRecords BroadPhase::records() const {
  BroadPhaseRecords r;
  const std::uint32_t slots = ids_.capacity();
  r.generations.reserve(slots);
  for (std::uint32_t p = 0; p < slots; ++p)
    r.generations.push_back(ids_.generation(p));
  r.freeSlots = ids_.freeSlots();
  r.tight = tight_;
  r.fat = fat_;
  r.margins = margins_;
  r.kinds.reserve(slots);
  r.buffered.reserve(slots);
  r.filters.reserve(slots);
  r.userData.reserve(slots);
  for (std::uint32_t p = 0; p < slots; ++p) {
    r.kinds.push_back((flags_[p] & kStatic) != 0 ? ProxyKind::staticProxy
                                                 : ProxyKind::dynamicProxy);
    r.buffered.push_back((flags_[p] & kBuffered) != 0 ? 1 : 0);
    r.filters.push_back(records_[p].filter);
    r.userData.push_back(records_[p].userData);
  }
  r.moveBuffer = moveBuffer_;
  return r;
}

Result<BroadPhase> BroadPhase::fromRecords(BroadPhaseConfig config, BroadPhaseRecords r) {
  Result<BroadPhase> made = create(config);
  if (!made) return made;
  const std::size_t slots = r.generations.size();
  if (slots >= 0x7fffffffu) return fail("BroadPhase::fromRecords: too many proxies (2^31)");
  if (r.tight.size() != slots || r.fat.size() != slots || r.kinds.size() != slots ||
      r.buffered.size() != slots || r.filters.size() != slots || r.userData.size() != slots ||
      (!r.margins.empty() && r.margins.size() != slots))
    return fail("BroadPhase::fromRecords: the per-slot arrays differ in length");
  if (r.margins.empty()) r.margins.assign(slots, config.margin);
  Result<IdPool> ids = IdPool::fromSlots(std::move(r.generations), std::move(r.freeSlots));
  if (!ids) return fail("BroadPhase::fromRecords: proxy slots: " + ids.error().message);
  BroadPhase& bp = made.value();
  bp.ids_ = std::move(ids).value();
  bp.records_.resize(slots);
  bp.flags_.assign(slots, 0);
  bp.fat_.assign(slots, Aabb{});
  bp.tight_.assign(slots, Aabb{});
  bp.margins_.assign(slots, 0.0f);
  for (std::uint32_t p = 0; p < slots; ++p) {
    if (!bp.ids_.isAlive(p)) {
      if (r.buffered[p] != 0)
        return fail("BroadPhase::fromRecords: free slot " + std::to_string(p) + " is buffered");
      continue;
    }
    const std::string name = "proxy " + std::to_string(p);
    if (Status s = checkBox(r.tight[p], "BroadPhase::fromRecords", (name + " tight box").c_str());
        !s)
      return fail(s.message());
    if (Status s = checkBox(r.fat[p], "BroadPhase::fromRecords", (name + " fat box").c_str()); !s)
      return fail(s.message());
    if (!contains(r.fat[p], r.tight[p]))
      return fail("BroadPhase::fromRecords: " + name + " tight box is outside its fat box");
    if (r.kinds[p] != ProxyKind::staticProxy && r.kinds[p] != ProxyKind::dynamicProxy)
      return fail("BroadPhase::fromRecords: " + name + " kind is not a ProxyKind");
    if (r.buffered[p] > 1)
      return fail("BroadPhase::fromRecords: " + name + " buffered flag is not 0 or 1");
    if (!isFinite(r.margins[p]) || r.margins[p] < 0.0f)
      return fail("BroadPhase::fromRecords: " + name + " margin must be finite and >= 0");
    bp.margins_[p] = r.margins[p];
    bp.records_[p] = {r.filters[p], r.userData[p]};
    bp.tight_[p] = r.tight[p];
    bp.fat_[p] = r.fat[p];
    bp.flags_[p] = static_cast<std::uint8_t>((r.kinds[p] == ProxyKind::staticProxy ? kStatic : 0) |
                                             (r.buffered[p] != 0 ? kBuffered : 0));
    std::visit([&](auto& index) { index.insert(p, bp.fat_[p]); }, bp.index_);
  }
  // Every buffered proxy is in the buffer; entries may be stale (a destroyed proxy, a slot
  // buffered twice after reuse): updatePairs skips those.
  std::vector<std::uint8_t> listed(slots, 0);
  for (std::uint32_t p : r.moveBuffer) {
    if (p >= slots)
      return fail("BroadPhase::fromRecords: move buffer entry " + std::to_string(p) +
                  " is beyond the " + std::to_string(slots) + " slots");
    listed[p] = 1;
  }
  for (std::uint32_t p = 0; p < slots; ++p) {
    if ((bp.flags_[p] & kBuffered) != 0 && listed[p] == 0)
      return fail("BroadPhase::fromRecords: proxy " + std::to_string(p) +
                  " is buffered but not in the move buffer");
  }
  bp.moveBuffer_ = std::move(r.moveBuffer);
  if (Status s = bp.validate(); !s) return fail("BroadPhase::fromRecords: " + s.message());
  return made;
}

void BroadPhase::rebuild() {
  std::visit([](auto& index) { index.rebuild(); }, index_);
}

BroadPhaseStats BroadPhase::stats() const {
  BroadPhaseStats s;
  s.proxyCount = ids_.liveCount();
  s.structureBytes = std::visit([](const auto& index) { return index.bytesUsed(); }, index_);
  s.recordBytes = (fat_.capacity() + tight_.capacity()) * sizeof(Aabb) +
                  margins_.capacity() * sizeof(float) + flags_.capacity() * sizeof(std::uint8_t) +
                  records_.capacity() * sizeof(Record) +
                  moveBuffer_.capacity() * sizeof(std::uint32_t) + ids_.memoryBytes();
  if (const auto* t = std::get_if<DynamicTree>(&index_)) {
    s.height = t->height();
    s.areaRatio = t->areaRatio();
  } else if (const auto* q = std::get_if<Quadtree>(&index_)) {
    s.height = q->depth();
  }
  return s;
}

Status BroadPhase::validate() const {
  if (Status s = std::visit([](const auto& index) { return index.validate(); }, index_); !s) {
    return fail(std::string(toString(kind())) + ": " + s.message());
  }
  std::uint32_t live = 0;
  Status result;
  std::visit(
      [&](const auto& index) {
        if (index.proxyCount() != ids_.liveCount()) {
          result = fail("structure proxy count differs from the live proxy count");
          return;
        }
        for (std::uint32_t p = 0; p < records_.size(); ++p) {
          const bool alive = ids_.isAlive(p);
          if (alive != index.contains(p)) {
            result = fail("proxy " + std::to_string(p) + " is live in one place only");
            return;
          }
          if (!alive) continue;
          ++live;
          if (!(index.box(p) == fat_[p])) {
            result = fail("structure box of proxy " + std::to_string(p) + " is not its fat box");
            return;
          }
          // The fat box may have been clamped to the coordinate range, never shrunk inside it.
          if (!contains(fat_[p], tight_[p])) {
            result = fail("fat box of proxy " + std::to_string(p) + " does not hold its tight box");
            return;
          }
        }
      },
      index_);
  if (!result) return result;
  if (live != ids_.liveCount()) return fail("live count is wrong");
  if (Status s = ids_.validate(); !s) return s;
  if (ids_.capacity() != records_.size()) return fail("id slots and records differ in number");
  std::vector<bool> inBuffer(records_.size(), false);
  for (std::uint32_t p : moveBuffer_) {
    if (p >= records_.size()) return fail("move buffer entry out of range");
    inBuffer[p] = true;
  }
  for (std::uint32_t p = 0; p < records_.size(); ++p) {
    if ((flags_[p] & kInPass) != 0) return fail("pass flag left set on a proxy");
    if ((flags_[p] & kBuffered) != 0 && !inBuffer[p]) {
      return fail("proxy " + std::to_string(p) + " flagged as buffered but not in the buffer");
    }
  }
  return {};
}

}  // namespace quack
