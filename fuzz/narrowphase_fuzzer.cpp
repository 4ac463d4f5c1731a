// libFuzzer target over the narrow-phase queries, in two modes chosen by the first byte:
// - '{': the input is one `quack query` line (JSON), answered by answerQuery. The answer
//   must be one line of JSON, an object with an "id"; a refused line carries a string
//   "error", an accepted one no non-finite number. The seed corpus (fuzz/narrowphase_seeds)
//   holds the lines of tests/query/cases.jsonl and the hardening regressions.
// - anything else: the bytes become two shapes (any kind, through the checked make*
//   functions, so only valid shapes reach the queries) and two poses; every query must
//   return finite numbers and a status.
// A failure aborts.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/sat.hpp"
#include "query.hpp"

namespace {

using namespace quack;

struct Reader {
  const std::uint8_t* data;
  std::size_t size;
  float next() {
    float f = 0.0f;
    if (size >= 4) {
      std::memcpy(&f, data, 4);
      data += 4;
      size -= 4;
    }
    // Keep numbers in the range the library promises to handle (|x| <= 1e6).
    if (!std::isfinite(f)) f = 0.0f;
    return std::fmod(f, 1e6f);
  }
  std::uint8_t byte() {
    if (size == 0) return 0;
    --size;
    return *data++;
  }
};

bool readShape(Reader& r, ShapeGeometry& s) {
  switch (r.byte() % 4) {
    case 0: {
      auto c = makeCircle({r.next(), r.next()}, std::fabs(r.next()));
      if (!c) return false;
      s = *c;
      return true;
    }
    case 1: {
      auto c = makeCapsule({r.next(), r.next()}, {r.next(), r.next()}, std::fabs(r.next()));
      if (!c) return false;
      s = *c;
      return true;
    }
    case 2: {
      auto c = makeSegment({r.next(), r.next()}, {r.next(), r.next()});
      if (!c) return false;
      s = *c;
      return true;
    }
    default: {
      int n = 3 + r.byte() % 30;
      Vec2 pts[32];
      for (int i = 0; i < n; ++i)
        pts[i] = {r.next(), r.next()};
      auto p =
          makePolygon(std::span<const Vec2>(pts, static_cast<std::size_t>(n)), std::fabs(r.next()));
      if (!p) return false;
      s = *p;
      return true;
    }
  }
}

void check(bool ok) {
  if (!ok) std::abort();
}

void checkQueryLine(const std::uint8_t* data, std::size_t size) {
  const std::string line(reinterpret_cast<const char*>(data), size);
  const quack::app::QueryAnswer a = quack::app::answerQuery(line);
  check(a.answer.find('\n') == std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(a.answer, nullptr, false);
  check(j.is_object() && j.contains("id"));
  if (a.ok) {
    check(!j.contains("error") && quack::app::firstNonFiniteField(j).empty());
  } else {
    check(j.contains("error") && j.at("error").is_string());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] == '{') {
    checkQueryLine(data, size);
    return 0;
  }
  Reader r{data, size};
  ShapeGeometry a, b;
  if (!readShape(r, a) || !readShape(r, b)) return 0;
  Transform xa = makeTransform({r.next(), r.next()}, r.next());
  Transform xb = makeTransform({r.next(), r.next()}, r.next());
  GjkCache cache;
  DistanceOutput d = computeDistance(a, xa, b, xb, &cache);
  check(std::isfinite(d.distance) && isFinite(d.pointA) && isFinite(d.pointB) &&
        isFinite(d.normal) && d.iterations <= kGjkMaxIterations);
  DistanceOutput warm = computeDistance(a, xa, b, xb, &cache);
  check(std::isfinite(warm.distance));
  (void)testOverlap(a, xa, b, xb);
  PenetrationOutput p = computePenetration(a, xa, b, xb);
  check(std::isfinite(p.depth) && isFinite(p.pointA) && isFinite(p.pointB) && isFinite(p.normal));
  const Polygon* polygonA = std::get_if<Polygon>(&a);
  const Polygon* polygonB = std::get_if<Polygon>(&b);
  if (polygonA != nullptr && polygonB != nullptr) {
    SatOutput s = computeSat(*polygonA, xa, *polygonB, xb);
    check(std::isfinite(s.separation) && isFinite(s.normal));
  }
  return 0;
}
