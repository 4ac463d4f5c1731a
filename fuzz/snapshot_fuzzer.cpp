// libFuzzer target over World::restore and World::fromSnapshot (docs/determinism.md,
// "Snapshots"): any bytes must be refused with a message or give a world that validates and
// steps, never a crash, a hang, a huge allocation or a sanitizer report; a refused restore
// leaves the world exactly as it was.
//
// The seeds are real snapshots, made at start-up from small worlds that reach every part
// (stacks asleep and awake, a bullet, a sensor, a kinematic body, flush tiles and a chain,
// churned handles), with each broad phase, full and dynamic. The first input byte picks
// what the rest is:
//   0: raw bytes, restored as they are (reach the header checks);
//   1: edits (offset, xor) to a seed snapshot, with its length and checksum made right
//      again, so that the contents reach the parser and the validation behind the header;
//   2: a seed's header followed by the input as its payload, length and checksum made right.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "quack/world/world.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;
using namespace quack;

constexpr std::size_t kHeader = 48;
constexpr std::size_t kChecksumAt = 40;
constexpr std::size_t kLengthAt = 32;
constexpr std::size_t kFingerprintAt = 24;

std::uint64_t fnv1a(const std::uint8_t* p, std::size_t n, std::uint64_t h) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ull;
  }
  return h;
}

// Makes the header agree with the bytes, by the format's own rules: the payload length; for
// a full snapshot, the structure fingerprint (FNV-1a 64 of the structure section, whose
// length leads the payload); the checksum (FNV-1a 64 over the first 40 header bytes, then
// the payload).
void seal(Bytes& b) {
  if (b.size() < kHeader) return;
  const std::uint64_t length = b.size() - kHeader;
  for (int i = 0; i < 8; ++i)
    b[kLengthAt + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(length >> (8 * i));
  if (b[12] == 0 && length >= 8) {
    std::uint64_t structure = 0;
    for (int i = 0; i < 8; ++i)
      structure |= static_cast<std::uint64_t>(b[kHeader + static_cast<std::size_t>(i)]) << (8 * i);
    if (structure <= length - 8) {
      const std::uint64_t f =
          fnv1a(b.data() + kHeader + 8, static_cast<std::size_t>(structure), 0xcbf29ce484222325ull);
      for (int i = 0; i < 8; ++i)
        b[kFingerprintAt + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(f >> (8 * i));
    }
  }
  std::uint64_t h = fnv1a(b.data(), kChecksumAt, 0xcbf29ce484222325ull);
  h = fnv1a(b.data() + kHeader, b.size() - kHeader, h);
  for (int i = 0; i < 8; ++i)
    b[kChecksumAt + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(h >> (8 * i));
}

World makeWorld(BroadPhaseKind kind) {
  World w = World::create({.broadPhase = kind}).value();
  for (int i = 0; i < 3; ++i) {
    BodyId b = w.createBody({.position = {20.0f + static_cast<float>(i), 3.0f}}).value();
    (void)w.createShape(b, {}, makeCircle({}, 0.3f).value());
    if (i != 1) (void)w.destroyBody(b);
  }
  BodyId ground = w.createBody({.type = BodyType::staticBody, .position = {0.0f, -0.5f}}).value();
  (void)w.createShape(ground, {}, makeBox(10.0f, 0.5f).value());
  for (int i = 0; i < 3; ++i) {
    BodyId tile = w.createBody({.type = BodyType::staticBody,
                                .position = {10.5f + static_cast<float>(i), -0.5f}})
                      .value();
    (void)w.createShape(tile, {}, makeBox(0.5f, 0.5f).value());
  }
  BodyId chainBody = w.createBody({.type = BodyType::staticBody}).value();
  const Vec2 chain[] = {{-10.0f, 0.0f}, {-14.0f, 0.0f}, {-16.0f, 2.0f}};
  (void)w.createChain(chainBody, {}, chain);
  for (int row = 0; row < 4; ++row) {
    for (int i = 0; i < 4 - row; ++i) {
      BodyId b =
          w.createBody({.position = {static_cast<float>(i) - 0.5f * static_cast<float>(3 - row),
                                     0.5f + static_cast<float>(row)}})
              .value();
      (void)w.createShape(b, {}, makeBox(0.5f, 0.5f).value());
    }
  }
  BodyId ball = w.createBody({.position = {5.0f, 3.0f}}).value();
  (void)w.createShape(ball, {.restitution = 0.5f},
                      makeCapsule({-0.2f, 0.0f}, {0.2f, 0.0f}, 0.2f).value());
  BodyId bullet =
      w.createBody({.position = {-5.0f, 1.0f}, .linearVelocity = {-150.0f, 0.0f}, .bullet = true})
          .value();
  (void)w.createShape(bullet, {}, makeCircle({}, 0.1f).value());
  BodyId lift = w.createBody({.type = BodyType::kinematicBody,
                              .position = {7.0f, 2.0f},
                              .linearVelocity = {0.0f, 0.3f}})
                    .value();
  (void)w.createShape(lift, {}, makeBox(1.0f, 0.1f).value());
  BodyId zone = w.createBody({.type = BodyType::staticBody, .position = {3.0f, 1.0f}}).value();
  (void)w.createShape(zone, {.sensor = true}, makeBox(1.0f, 1.0f).value());
  return w;
}

struct Seeds {
  std::vector<Bytes> snapshots;  // full and dynamic, of worlds at several steps
  std::vector<Bytes> fullOf;     // per snapshot: a full snapshot of the world it came from
};

const Seeds& seeds() {
  static const Seeds s = [] {
    Seeds out;
    for (BroadPhaseKind kind : kAllBroadPhaseKinds) {
      World w = makeWorld(kind);
      for (int steps : {0, 20, 60}) {
        while (w.stepCount() < static_cast<std::uint64_t>(steps))
          (void)w.step();
        const Bytes full = w.snapshot(SnapshotKind::full).value();
        out.snapshots.push_back(full);
        out.fullOf.push_back(full);
        out.snapshots.push_back(w.snapshot(SnapshotKind::dynamic).value());
        out.fullOf.push_back(full);
      }
    }
    return out;
  }();
  return s;
}

void check(const Bytes& bytes, const Bytes& home) {
  // A new world: either a message or a world that validates and steps.
  Result<World> made = World::fromSnapshot(bytes);
  if (!made) {
    if (made.error().message.empty()) __builtin_trap();
  } else {
    if (!made.value().validate().ok()) __builtin_trap();
    for (int i = 0; i < 2; ++i)
      (void)made.value().step();
  }
  // Into a world: a refusal changes nothing.
  World target = World::fromSnapshot(home).value();
  const std::uint64_t before = target.stateHash();
  const std::size_t bodies = target.bodyCount(), contacts = target.contactCount();
  Status s = target.restore(bytes);
  if (!s) {
    if (s.message().empty() || target.stateHash() != before || target.bodyCount() != bodies ||
        target.contactCount() != contacts || !target.validate().ok())
      __builtin_trap();
  } else {
    if (!target.validate().ok()) __builtin_trap();
    (void)target.step();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2 || size > 1 << 16) return 0;
  const Seeds& s = seeds();
  const std::size_t pick = data[1] % s.snapshots.size();
  const Bytes& seed = s.snapshots[pick];
  Bytes bytes;
  switch (data[0] % 3) {
    case 0:
      bytes.assign(data + 2, data + size);
      break;
    case 1: {
      bytes = seed;
      // Edits of 5 bytes each: a 4-byte offset into the payload and a byte to xor there.
      for (std::size_t i = 2; i + 5 <= size; i += 5) {
        std::uint32_t at;
        std::memcpy(&at, data + i, 4);
        const std::size_t payload = bytes.size() - kHeader;
        bytes[kHeader + at % payload] ^= data[i + 4];
      }
      seal(bytes);
      break;
    }
    default:
      bytes.assign(seed.begin(), seed.begin() + kHeader);
      bytes.insert(bytes.end(), data + 2, data + size);
      seal(bytes);
      break;
  }
  check(bytes, s.fullOf[pick]);
  return 0;
}
