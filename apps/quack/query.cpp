#include "query.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "quack/collision/epa.hpp"
#include "quack/collision/gjk.hpp"
#include "quack/collision/manifold.hpp"
#include "shape_json.hpp"

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
        k != "speculative") {
      return rejected(id, k + ": unknown key");
    }
  }
  if (!q.contains("op")) return rejected(id, "op: missing");
  if (!q.at("op").is_string()) return rejected(id, "op: must be a string");
  const std::string op = q.at("op").get<std::string>();
  if (op != "overlap" && op != "distance" && op != "penetration" && op != "manifold") {
    return rejected(
        id, "op: unknown op \"" + op + "\" (expected overlap, distance, penetration, manifold)");
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

  ShapeProxy proxyA = a->proxy();
  ShapeProxy proxyB = b->proxy();
  json out = {{"id", id}};
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
