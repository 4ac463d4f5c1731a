#include "quack/broadphase/broad_phase3.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace quack {

namespace {

std::string describe(ProxyId id) {
  return "{index " + std::to_string(id.index) + ", generation " + std::to_string(id.generation) +
         "}";
}

Status checkBox(Aabb3 b, const char* function, const char* argument) {
  const char* problem = nullptr;
  if (!isFinite(b.lower) || !isFinite(b.upper)) {
    problem = "has a NaN or infinite coordinate";
  } else if (b.lower.x > b.upper.x || b.lower.y > b.upper.y || b.lower.z > b.upper.z) {
    problem = "is inverted (lower > upper)";
  } else if (b.lower.x < -kMaxCoordinate || b.lower.y < -kMaxCoordinate ||
             b.lower.z < -kMaxCoordinate || b.upper.x > kMaxCoordinate ||
             b.upper.y > kMaxCoordinate || b.upper.z > kMaxCoordinate) {
    problem = "lies beyond kMaxCoordinate (1e9 m) from the origin";
  }
  if (problem == nullptr) return {};
  return fail(std::string(function) + ": " + argument + " " + problem);
}

}  // namespace

const char* toString(BroadPhase3Kind kind) noexcept {
  switch (kind) {
    case BroadPhase3Kind::tree:
      return "tree";
    case BroadPhase3Kind::octree:
      return "octree";
  }
  return "unknown";
}

Result<BroadPhase3Kind> parseBroadPhase3Kind(std::string_view name) {
  for (BroadPhase3Kind k : kAllBroadPhase3Kinds) {
    if (toString(k) == name) return k;
  }
  return fail("unknown 3D broad phase '" + std::string(name) + "' (expected tree or octree)");
}

Result<BroadPhase3> BroadPhase3::create(BroadPhase3Config config) {
  if (!isFinite(config.margin) || config.margin < 0.0f) {
    return fail("BroadPhase3Config.margin must be finite and >= 0");
  }
  if (!isFinite(config.displacementScale) || config.displacementScale < 0.0f) {
    return fail("BroadPhase3Config.displacementScale must be finite and >= 0");
  }
  if (!isFinite(config.cellSize) || config.cellSize < kMinCellSize ||
      config.cellSize > kMaxCoordinate) {
    return fail(
        "BroadPhase3Config.cellSize must be in [1e-6, 1e9] m (kMinCellSize to kMaxCoordinate)");
  }
  switch (config.kind) {
    case BroadPhase3Kind::tree:
    case BroadPhase3Kind::octree:
      return BroadPhase3(config);
  }
  return fail("BroadPhase3Config.kind is not a BroadPhase3Kind");
}

BroadPhase3::BroadPhase3(BroadPhase3Config config) : config_(config) {
  if (config.kind == BroadPhase3Kind::octree) index_.emplace<Octree>(config.cellSize);
}

Status BroadPhase3::checkId(ProxyId id, const char* function) const {
  if (isValid(id)) return {};
  if (id.index == kNullIndex) return fail(std::string(function) + ": proxy id is null");
  if (id.index >= records_.size()) {
    return fail(std::string(function) + ": proxy id " + describe(id) + " was never created");
  }
  return fail(std::string(function) + ": proxy id " + describe(id) +
              " is stale (that proxy was destroyed)");
}

void BroadPhase3::buffer(std::uint32_t proxy) {
  if ((flags_[proxy] & kBuffered) != 0) return;
  flags_[proxy] |= kBuffered;
  moveBuffer_.push_back(proxy);
}

Result<ProxyId> BroadPhase3::createProxy(Aabb3 box, std::uint64_t userData, Filter filter,
                                         ProxyKind kind) {
  if (Status s = checkBox(box, "createProxy", "box"); !s) return fail(s.message());
  if (ids_.nextIndex() >= 0x7fffffffu) return fail("createProxy: too many proxies (2^31)");
  // A fresh slot has generation 1, so the default (null) id never matches a live proxy.
  const std::uint32_t p = ids_.allocate();
  if (p == records_.size()) {
    records_.push_back({});
    fat_.push_back({});
    tight_.push_back({});
    flags_.push_back(0);
  }
  records_[p] = {filter, userData};
  flags_[p] = static_cast<std::uint8_t>(kind == ProxyKind::staticProxy ? kStatic : 0);
  tight_[p] = box;
  // The margin may carry a box near kMaxCoordinate past it; clamp as reinsert() does.
  const Vec3 limit{kMaxCoordinate, kMaxCoordinate, kMaxCoordinate};
  const Aabb3 grown = detail::inflate3(box, config_.margin);
  fat_[p] = {maxv(grown.lower, -limit), minv(grown.upper, limit)};
  std::visit([&](auto& index) { index.insert(p, fat_[p]); }, index_);
  buffer(p);
  return ProxyId{p, ids_.generation(p)};
}

Status BroadPhase3::destroyProxy(ProxyId id) {
  if (Status s = checkId(id, "destroyProxy"); !s) return s;
  const std::uint32_t p = id.index;
  std::visit([&](auto& index) { index.remove(p); }, index_);
  // A stale move-buffer entry is skipped by updatePairs (kBuffered is cleared here), and if
  // the slot is reused before then, the new proxy's entry is deduplicated there.
  flags_[p] = 0;
  ids_.release(p);
  return {};
}

Error BroadPhase3::rejectMove(ProxyId id, Aabb3 box, Vec3 displacement) const {
  if (!isValid(id)) return fail(checkId(id, "moveProxy").message());
  if (Status s = checkBox(box, "moveProxy", "box"); !s) return fail(s.message());
  if (!isFinite(displacement)) return fail("moveProxy: displacement is NaN or infinite");
  return fail("moveProxy: rejected");
}

void BroadPhase3::reinsert(std::uint32_t p, Aabb3 wanted) {
  // The stretched box may leave the coordinate range even when the tight box does not.
  const Vec3 limit{kMaxCoordinate, kMaxCoordinate, kMaxCoordinate};
  const Aabb3 clamped{maxv(wanted.lower, -limit), minv(wanted.upper, limit)};
  fat_[p] = clamped;
  std::visit([&](auto& index) { index.move(p, clamped); }, index_);
  buffer(p);
}

Status BroadPhase3::setFilter(ProxyId id, Filter f) {
  if (Status s = checkId(id, "setFilter"); !s) return s;
  records_[id.index].filter = f;
  buffer(id.index);
  return {};
}

Status BroadPhase3::touchProxy(ProxyId id) {
  if (Status s = checkId(id, "touchProxy"); !s) return s;
  buffer(id.index);
  return {};
}

std::uint64_t BroadPhase3::userData(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase3::userData: invalid proxy id");
  return isValid(id) ? records_[id.index].userData : 0;
}

Filter BroadPhase3::filter(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase3::filter: invalid proxy id");
  return isValid(id) ? records_[id.index].filter : Filter{};
}

Aabb3 BroadPhase3::tightBox(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase3::tightBox: invalid proxy id");
  return isValid(id) ? tight_[id.index] : Aabb3{};
}

Aabb3 BroadPhase3::fatBox(ProxyId id) const {
  QUACK_ASSERT_MSG(isValid(id), "BroadPhase3::fatBox: invalid proxy id");
  return isValid(id) ? fat_[id.index] : Aabb3{};
}

void BroadPhase3::addPair(std::uint32_t a, std::uint32_t b, std::vector<ProxyPair>& pairs) const {
  if ((flags_[a] & flags_[b] & kStatic) != 0) return;
  if (!shouldCollide(records_[a].filter, records_[b].filter)) return;
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

void BroadPhase3::beginPass() {
  // Keep live, buffered entries once each (a destroyed proxy lost kBuffered; a reused slot
  // may appear twice).
  std::size_t kept = 0;
  for (std::uint32_t p : moveBuffer_) {
    if ((flags_[p] & kBuffered) == 0 || (flags_[p] & kInPass) != 0) continue;
    flags_[p] |= kInPass;
    moveBuffer_[kept++] = p;
  }
  moveBuffer_.resize(kept);
}

void BroadPhase3::endPass() {
  for (std::uint32_t p : moveBuffer_) {
    flags_[p] = static_cast<std::uint8_t>(flags_[p] & ~(kBuffered | kInPass));
  }
  moveBuffer_.clear();
}

void BroadPhase3::updatePairs(std::vector<ProxyPair>& pairs) {
  pairs.clear();
  beginPass();
  std::visit([&](const auto& index) { queryMoved(index, 0, moveBuffer_.size(), pairs); }, index_);
  endPass();
}

std::optional<BroadPhaseHit> BroadPhase3::rayCastClosest(Vec3 origin, Vec3 translation) const {
  std::optional<BroadPhaseHit> best;
  rayCast(origin, translation, [&](ProxyId id, std::uint64_t user, float fraction) {
    if (!best || fraction < best->fraction) best = BroadPhaseHit{id, user, fraction};
    // Clipping to the hit leaves only nearer boxes to visit; 0 (starting inside) stops.
    return fraction;
  });
  return best;
}

std::vector<BroadPhaseHit> BroadPhase3::rayCastAll(Vec3 origin, Vec3 translation) const {
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

void BroadPhase3::rebuild() {
  std::visit([](auto& index) { index.rebuild(); }, index_);
}

BroadPhase3Stats BroadPhase3::stats() const {
  BroadPhase3Stats s;
  s.proxyCount = ids_.liveCount();
  s.structureBytes = std::visit([](const auto& index) { return index.bytesUsed(); }, index_);
  s.recordBytes = (fat_.capacity() + tight_.capacity()) * sizeof(Aabb3) +
                  flags_.capacity() * sizeof(std::uint8_t) + records_.capacity() * sizeof(Record) +
                  moveBuffer_.capacity() * sizeof(std::uint32_t) + ids_.memoryBytes();
  if (const auto* t = std::get_if<DynamicTree3>(&index_)) {
    s.height = t->height();
    s.areaRatio = t->areaRatio();
  } else if (const auto* o = std::get_if<Octree>(&index_)) {
    s.height = o->depth();
  }
  return s;
}

BroadPhase3Records BroadPhase3::records() const {
  BroadPhase3Records r;
  const std::uint32_t slots = ids_.capacity();
  for (std::uint32_t p = 0; p < slots; ++p) {
    r.generations.push_back(ids_.generation(p));
    r.kinds.push_back((flags_[p] & kStatic) != 0 ? ProxyKind::staticProxy
                                                 : ProxyKind::dynamicProxy);
    r.buffered.push_back((flags_[p] & kBuffered) != 0 ? 1 : 0);
    r.filters.push_back(records_[p].filter);
    r.userData.push_back(records_[p].userData);
  }
  r.freeSlots = ids_.freeSlots();
  r.tight = tight_;
  r.fat = fat_;
  r.moveBuffer = moveBuffer_;
  return r;
}

Result<BroadPhase3> BroadPhase3::fromRecords(BroadPhase3Config config, BroadPhase3Records r) {
  Result<BroadPhase3> made = create(config);
  if (!made) return made;
  const std::size_t slots = r.generations.size();
  const char* where = "BroadPhase3::fromRecords: ";
  if (slots >= 0x7fffffffu) return fail(std::string(where) + "too many proxies (2^31)");
  if (r.tight.size() != slots || r.fat.size() != slots || r.kinds.size() != slots ||
      r.buffered.size() != slots || r.filters.size() != slots || r.userData.size() != slots)
    return fail(std::string(where) + "the per-slot arrays differ in length");
  Result<IdPool> ids = IdPool::fromSlots(std::move(r.generations), std::move(r.freeSlots));
  if (!ids) return fail(std::string(where) + "proxy slots: " + ids.error().message);
  BroadPhase3& bp = made.value();
  bp.ids_ = std::move(ids).value();
  bp.records_.resize(slots);
  bp.flags_.assign(slots, 0);
  bp.fat_.assign(slots, Aabb3{});
  bp.tight_.assign(slots, Aabb3{});
  for (std::uint32_t p = 0; p < slots; ++p) {
    const std::string name = std::string(where) + "proxy " + std::to_string(p);
    if (!bp.ids_.isAlive(p)) {
      if (r.buffered[p] != 0) return fail(name + " is free and buffered");
      continue;
    }
    if (!isAcceptableBox(r.tight[p])) return fail(name + " tight box is invalid");
    if (!isAcceptableBox(r.fat[p])) return fail(name + " fat box is invalid");
    if (!contains(r.fat[p], r.tight[p])) return fail(name + " tight box is outside its fat box");
    if (r.kinds[p] != ProxyKind::staticProxy && r.kinds[p] != ProxyKind::dynamicProxy)
      return fail(name + " kind is not a ProxyKind");
    if (r.buffered[p] > 1) return fail(name + " buffered flag is not 0 or 1");
    bp.records_[p] = {r.filters[p], r.userData[p]};
    bp.tight_[p] = r.tight[p];
    bp.fat_[p] = r.fat[p];
    bp.flags_[p] = static_cast<std::uint8_t>((r.kinds[p] == ProxyKind::staticProxy ? kStatic : 0) |
                                             (r.buffered[p] != 0 ? kBuffered : 0));
    std::visit([&](auto& index) { index.insert(p, bp.fat_[p]); }, bp.index_);
  }
  std::vector<std::uint8_t> listed(slots, 0);
  for (std::uint32_t p : r.moveBuffer) {
    if (p >= slots)
      return fail(std::string(where) + "move buffer entry " + std::to_string(p) +
                  " is beyond the " + std::to_string(slots) + " slots");
    listed[p] = 1;
  }
  for (std::uint32_t p = 0; p < slots; ++p) {
    if ((bp.flags_[p] & kBuffered) != 0 && listed[p] == 0)
      return fail(std::string(where) + "proxy " + std::to_string(p) +
                  " is buffered but not in the move buffer");
  }
  bp.moveBuffer_ = std::move(r.moveBuffer);
  if (Status s = bp.validate(); !s) return fail(std::string(where) + s.message());
  return made;
}

Status BroadPhase3::validate() const {
  if (Status s = std::visit([](const auto& index) { return index.validate(); }, index_); !s) {
    return fail(std::string(toString(kind())) + ": " + s.message());
  }
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
