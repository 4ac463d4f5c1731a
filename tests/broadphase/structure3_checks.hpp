#pragma once
// Checks shared by the DynamicTree3 and Octree tests: long random sequences of inserts,
// moves and removes with validate() after every operation, and box queries, ray casts, box
// casts and the set of overlapping pairs compared with brute force over the same boxes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "broadphase/oracle3.hpp"

namespace quack::test {

template <class Structure>
std::vector<std::uint32_t> queryAll3(const Structure& s, Aabb3 q) {
  std::vector<std::uint32_t> out;
  s.query(q, [&](std::uint32_t p) {
    out.push_back(p);
    return true;
  });
  std::sort(out.begin(), out.end());
  return out;
}

// Every pair of proxies whose stored boxes overlap, found by querying each proxy's own box
// (the way BroadPhase3::updatePairs finds pairs when every proxy moved), a < b.
template <class Structure>
std::vector<IndexPair> structurePairs(const Structure& s, std::uint32_t slots) {
  std::vector<IndexPair> out;
  for (std::uint32_t a = 0; a < slots; ++a) {
    if (!s.contains(a)) continue;
    s.query(s.box(a), [&](std::uint32_t b) {
      if (a < b) out.emplace_back(a, b);
      return true;
    });
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The proxies a cast reports when it never clips, against brute force over the model.
template <class Structure>
void checkCasts(const Structure& s, const std::vector<std::optional<Aabb3>>& model,
                std::mt19937& rng, float world) {
  const Vec3 origin = randomVec3(rng, -world, world);
  Vec3 translation = randomVec3(rng, -2.0f * world, 2.0f * world);
  // A quarter of the rays run along an axis (zero components take the slab test's other
  // branch), an eighth are boxes cast.
  std::uniform_int_distribution<int> kind(0, 7);
  const int k = kind(rng);
  if (k < 2) translation = {translation.x, 0.0f, 0.0f};
  if (k == 2) translation = {0.0f, 0.0f, translation.z};
  const Vec3 inflation = k == 7 ? randomVec3(rng, 0.0f, 1.0f) : Vec3{};
  const detail::Ray3 ray(origin, translation);

  std::vector<std::uint32_t> expected;
  float closest = 2.0f;
  for (std::uint32_t p = 0; p < model.size(); ++p) {
    if (!model[p]) continue;
    const AabbRayHit h = detail::rayCast3(detail::grow3(*model[p], inflation), ray, 1.0f);
    if (!h.hit) continue;
    expected.push_back(p);
    closest = std::min(closest, h.fraction);
  }

  std::vector<std::uint32_t> all;
  s.rayCast(origin, translation, 1.0f, inflation, [&](std::uint32_t p, float maxFraction) {
    EXPECT_EQ(maxFraction, 1.0f);
    all.push_back(p);
    return maxFraction;
  });
  std::sort(all.begin(), all.end());
  ASSERT_EQ(all, expected) << "all hits";

  // Clipping at every hit: the last clip is the closest hit of brute force.
  float best = 2.0f;
  s.rayCast(origin, translation, 1.0f, inflation, [&](std::uint32_t p, float maxFraction) {
    const AabbRayHit h = detail::rayCast3(detail::grow3(*model[p], inflation), ray, maxFraction);
    EXPECT_TRUE(h.hit) << "visited proxy " << p << " the clipped ray no longer reaches";
    if (!h.hit) return maxFraction;
    best = std::min(best, h.fraction);
    // A hit at 0 (the ray starts inside) stops the cast: it is the closest possible.
    return h.fraction;
  });
  ASSERT_EQ(best, closest) << "closest hit";
}

// Random inserts (70% small boxes, some large, a few far away), moves and removes, with
// validate() after each and the queries checked every few steps.
template <class Structure, class Make>
void randomSequence(Make&& make, std::uint32_t seed, int steps, std::uint32_t slots) {
  SCOPED_TRACE("seed=" + std::to_string(seed));
  std::mt19937 rng(seed);
  Structure s = make();
  std::vector<std::optional<Aabb3>> model(slots);
  std::uniform_int_distribution<std::uint32_t> pick(0, slots - 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float world = 20.0f;
  auto newBox = [&]() {
    const float r = unit(rng);
    if (r < 0.8f) return randomBox3(rng, world, 0.05f, 1.0f);
    if (r < 0.97f) return randomBox3(rng, world, 1.0f, 8.0f);
    // Far away: grows the octree's root, stretches the tree's.
    Aabb3 b = randomBox3(rng, 1.0f, 0.1f, 1.0f);
    const Vec3 far = randomVec3(rng, -5e4f, 5e4f);
    return Aabb3{b.lower + far, b.upper + far};
  };
  for (int i = 0; i < steps; ++i) {
    const std::uint32_t p = pick(rng);
    if (!model[p]) {
      const Aabb3 b = newBox();
      s.insert(p, b);
      model[p] = b;
    } else if (unit(rng) < 0.35f) {
      s.remove(p);
      model[p].reset();
    } else if (unit(rng) < 0.7f) {
      // A small step, as a body moves.
      const Vec3 d = randomVec3(rng, -0.3f, 0.3f);
      const Aabb3 b{model[p]->lower + d, model[p]->upper + d};
      s.move(p, b);
      model[p] = b;
    } else {
      const Aabb3 b = newBox();
      s.move(p, b);
      model[p] = b;
    }
    if (i % 700 == 350) s.rebuild();
    const Status v = s.validate();
    ASSERT_TRUE(v.ok()) << "step " << i << ": " << v.message();
    std::uint32_t present = 0;
    for (const auto& m : model)
      present += m ? 1u : 0u;
    ASSERT_EQ(s.proxyCount(), present);
    if (i % 10 == 0) {
      const Aabb3 q =
          unit(rng) < 0.9f ? randomBox3(rng, world, 0.5f, 6.0f) : randomBox3(rng, 1.0f, 1e4f, 6e4f);
      std::vector<std::uint32_t> expected;
      for (std::uint32_t k = 0; k < slots; ++k) {
        if (model[k] && overlaps(*model[k], q)) expected.push_back(k);
      }
      ASSERT_EQ(queryAll3(s, q), expected) << "step " << i;
      // Point queries at the corners of a stored box: touching counts, so the box must be
      // found, and those corners are where a structure's pruning is tightest (a box at the
      // edge of its loose cell, a node's box that this box bounds).
      for (int tries = 0; tries < 3; ++tries) {
        const std::uint32_t k = pick(rng);
        if (!model[k]) continue;
        for (int corner = 0; corner < 8; ++corner) {
          const Vec3 pt{(corner & 1) ? model[k]->upper.x : model[k]->lower.x,
                        (corner & 2) ? model[k]->upper.y : model[k]->lower.y,
                        (corner & 4) ? model[k]->upper.z : model[k]->lower.z};
          const std::vector<std::uint32_t> hit = queryAll3(s, Aabb3{pt, pt});
          ASSERT_TRUE(std::binary_search(hit.begin(), hit.end(), k))
              << "step " << i << ": corner " << corner << " of proxy " << k << " not found";
          std::vector<std::uint32_t> all;
          for (std::uint32_t j = 0; j < slots; ++j) {
            if (model[j] && overlaps(*model[j], Aabb3{pt, pt})) all.push_back(j);
          }
          ASSERT_EQ(hit, all) << "step " << i;
        }
      }
      for (std::uint32_t k = 0; k < slots; ++k) {
        if (model[k]) {
          ASSERT_EQ(s.box(k), *model[k]) << "step " << i << " proxy " << k;
        }
      }
    }
    if (i % 10 == 5) {
      SCOPED_TRACE("step " + std::to_string(i));
      checkCasts(s, model, rng, world);
      if (testing::Test::HasFatalFailure()) return;
    }
    if (i % 100 == 99) {
      std::vector<std::pair<bool, Aabb3>> boxes(slots, {false, Aabb3{}});
      for (std::uint32_t k = 0; k < slots; ++k) {
        if (model[k]) boxes[k] = {true, *model[k]};
      }
      ASSERT_EQ(structurePairs(s, slots), allOverlappingPairs(boxes)) << "step " << i;
    }
  }
}

}  // namespace quack::test
