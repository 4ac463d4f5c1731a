#include "query.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "quack/collision/shape_cast.hpp"
#include "quack/collision/toi.hpp"
#include "quack/io/shape_json.hpp"

namespace quack::app {
namespace {

using nlohmann::json;

json toJson(Vec2 v) {
  return json::array({v.x, v.y});
}

QueryAnswer rejected(const json& id, const std::string& message) {
  json out = {{"id", id}, {"error", message}};
  return {out.dump(), false};
}

}  // namespace

QueryAnswer answerQuery(const std::string& line) {
  json q = json::parse(line, nullptr, false);
  if (q.is_discarded()) return rejected(nullptr, "line is not valid JSON");
  if (!q.is_object()) return rejected(nullptr, "line must be a JSON object");
  json id = q.contains("id") ? q.at("id") : json(nullptr);
  for (const auto& item : q.items()) {
    const std::string& k = item.key();
    if (k != "id" && k != "op" && k != "a" && k != "pa" && k != "b" && k != "pb" &&
        k != "speculative" && k != "translation" && k != "sweepA" && k != "sweepB" &&
        k != "target") {
      return rejected(id, k + ": unknown key");
    }
  }
  if (!q.contains("op")) return rejected(id, "op: missing");
  if (!q.at("op").is_string()) return rejected(id, "op: must be a string");
  const std::string op = q.at("op").get<std::string>();
  if (op != "overlap" && op != "distance" && op != "penetration" && op != "manifold" &&
      op != "shapecast" && op != "toi") {
    return rejected(id,
                    "op: unknown op \"" + op +
                        "\" (expected overlap, distance, penetration, manifold, shapecast, toi)");
  }
  // Keys that belong to one op only.
  if (q.contains("translation") && op != "shapecast")
    return rejected(id, "translation: only for op shapecast");
  for (const char* key : {"sweepA", "sweepB", "target"}) {
    if (q.contains(key) && op != "toi") return rejected(id, std::string(key) + ": only for op toi");
  }
  if (op == "toi") {
    for (const char* key : {"pa", "pb"}) {
      if (q.contains(key))
        return rejected(id, std::string(key) + ": not used by op toi (give sweepA and sweepB)");
    }
  }
  // manifold only: the speculative distance in metres (default kSpeculativeDistance).
  float speculative = kSpeculativeDistance;
  if (q.contains("speculative")) {
    if (op != "manifold") return rejected(id, "speculative: only for op manifold");
    const json& v = q.at("speculative");
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0 ||
        v.get<double>() > 1e30) {
      return rejected(id, "speculative: must be a finite number >= 0");
    }
    speculative = v.get<float>();
  }
  if (!q.contains("a")) return rejected(id, "a: missing");
  if (!q.contains("b")) return rejected(id, "b: missing");
  Result<ParsedShape> a = parseShape(q.at("a"), "a");
  if (!a) return rejected(id, a.error().message);
  Result<ParsedShape> b = parseShape(q.at("b"), "b");
  if (!b) return rejected(id, b.error().message);
  Result<Transform> pa =
      q.contains("pa") ? parsePose(q.at("pa"), "pa") : Result<Transform>(Transform{});
  if (!pa) return rejected(id, pa.error().message);
  Result<Transform> pb =
      q.contains("pb") ? parsePose(q.at("pb"), "pb") : Result<Transform>(Transform{});
  if (!pb) return rejected(id, pb.error().message);

  json out = {{"id", id}};
  if (a->concave || b->concave) {
    // A concave shape is its convex pieces: overlap, distance and penetration are answered
    // over every pair of pieces (docs/concave.md); the other ops want one convex shape.
    const char* which = a->concave ? "a" : "b";
    if (op != "overlap" && op != "distance" && op != "penetration") {
      return rejected(id, std::string(which) + ": a concave shape supports ops overlap, " +
                              "distance and penetration only, not " + op);
    }
    const std::vector<ShapeProxy> piecesA = a->proxies();
    const std::vector<ShapeProxy> piecesB = b->proxies();
    if (op == "overlap") {
      bool any = false;
      for (const ShapeProxy& x : piecesA)
        for (const ShapeProxy& y : piecesB)
          any = any || testOverlap(x, *pa, y, *pb);
      out["overlap"] = any;
      return {out.dump(), true};
    }
    // The closest pair of pieces (first in order on ties); for penetration, the deepest
    // overlapping pair, else the closest.
    std::size_t bestA = 0, bestB = 0;
    DistanceOutput closest;
    bool first = true;
    for (std::size_t i = 0; i < piecesA.size(); ++i) {
      for (std::size_t k = 0; k < piecesB.size(); ++k) {
        DistanceOutput d = computeDistance(piecesA[i], *pa, piecesB[k], *pb);
        if (first || d.distance < closest.distance) {
          closest = d;
          bestA = i;
          bestB = k;
          first = false;
        }
      }
    }
    if (op == "distance") {
      out["distance"] = closest.distance;
      out["pointA"] = toJson(closest.pointA);
      out["pointB"] = toJson(closest.pointB);
      out["normal"] = toJson(closest.normal);
      out["iterations"] = closest.iterations;
      out["status"] = toString(closest.status);
      return {out.dump(), true};
    }
    PenetrationOutput best = computePenetration(piecesA[bestA], *pa, piecesB[bestB], *pb);
    for (const ShapeProxy& x : piecesA) {
      for (const ShapeProxy& y : piecesB) {
        PenetrationOutput p = computePenetration(x, *pa, y, *pb);
        if (p.overlap && (!best.overlap || p.depth > best.depth)) best = p;
      }
    }
    out["overlap"] = best.overlap;
    out["depth"] = best.depth;
    out["normal"] = toJson(best.normal);
    out["pointA"] = toJson(best.pointA);
    out["pointB"] = toJson(best.pointB);
    out["iterations"] = best.iterations;
    out["status"] = toString(best.status);
    return {out.dump(), true};
  }
  ShapeProxy proxyA = a->proxy();
  ShapeProxy proxyB = b->proxy();
  if (op == "shapecast") {
    if (!q.contains("translation")) return rejected(id, "translation: missing");
    Result<Vec2> translation = parseVec2(q.at("translation"), "translation");
    if (!translation) return rejected(id, translation.error().message);
    ShapeCastOutput c = castShape(proxyA, *pa, proxyB, *pb, *translation);
    out["hit"] = c.hit;
    out["fraction"] = c.fraction;
    out["point"] = toJson(c.point);
    out["normal"] = toJson(c.normal);
    out["depth"] = c.depth;
    out["status"] = toString(c.status);
    return {out.dump(), true};
  }
  if (op == "toi") {
    // A sweep is {"from": POSE, "to": POSE}; the shape turns about its centre (the centre
    // of mass of a one-shape body), the short way round.
    auto parseSweep = [&](const char* key, const ShapeProxy& proxy) -> Result<Sweep> {
      if (!q.contains(key)) return fail(std::string(key) + ": missing");
      const json& j = q.at(key);
      if (!j.is_object()) return fail(std::string(key) + ": must be an object {\"from\", \"to\"}");
      for (const auto& item : j.items()) {
        if (item.key() != "from" && item.key() != "to")
          return fail(std::string(key) + "." + item.key() + ": unknown key");
      }
      if (!j.contains("from")) return fail(std::string(key) + ".from: missing");
      if (!j.contains("to")) return fail(std::string(key) + ".to: missing");
      Result<Transform> from = parsePose(j.at("from"), std::string(key) + ".from");
      if (!from) return fail(from.error().message);
      Result<Transform> to = parsePose(j.at("to"), std::string(key) + ".to");
      if (!to) return fail(to.error().message);
      return makeSweep(proxy.center(), *from, *to);
    };
    Result<Sweep> sweepA = parseSweep("sweepA", proxyA);
    if (!sweepA) return rejected(id, sweepA.error().message);
    Result<Sweep> sweepB = parseSweep("sweepB", proxyB);
    if (!sweepB) return rejected(id, sweepB.error().message);
    float target = kToiTargetSeparation;
    if (q.contains("target")) {
      const json& v = q.at("target");
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0 ||
          v.get<double>() > 1e30) {
        return rejected(id, "target: must be a finite number >= 0");
      }
      target = v.get<float>();
    }
    ToiOutput t = computeToi(proxyA, *sweepA, proxyB, *sweepB, 1.0f, target);
    out["status"] = toString(t.status);
    out["t"] = t.t;
    return {out.dump(), true};
  }
  if (op == "overlap") {
    out["overlap"] = testOverlap(proxyA, *pa, proxyB, *pb);
  } else if (op == "distance") {
    DistanceOutput d = computeDistance(proxyA, *pa, proxyB, *pb);
    out["distance"] = d.distance;
    out["pointA"] = toJson(d.pointA);
    out["pointB"] = toJson(d.pointB);
    out["normal"] = toJson(d.normal);
    out["iterations"] = d.iterations;
    out["status"] = toString(d.status);
  } else if (op == "manifold") {
    Manifold m = collide(a->ref(), *pa, b->ref(), *pb, speculative);
    out["normal"] = toJson(m.pointCount > 0 ? m.normal : Vec2{});
    json points = json::array();
    for (int i = 0; i < m.pointCount; ++i) {
      points.push_back({{"point", toJson(m.points[i].point)},
                        {"separation", m.points[i].separation},
                        {"id", m.points[i].id}});
    }
    out["points"] = points;
  } else {
    PenetrationOutput p = computePenetration(proxyA, *pa, proxyB, *pb);
    out["overlap"] = p.overlap;
    out["depth"] = p.depth;
    out["normal"] = toJson(p.normal);
    out["pointA"] = toJson(p.pointA);
    out["pointB"] = toJson(p.pointB);
    out["iterations"] = p.iterations;
    out["status"] = toString(p.status);
  }
  return {out.dump(), true};
}

int runQueries(std::istream& in, std::ostream& out) {
  int failures = 0;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    QueryAnswer a = answerQuery(line);
    if (!a.ok) ++failures;
    out << a.answer << '\n';
  }
  return failures;
}

}  // namespace quack::app
