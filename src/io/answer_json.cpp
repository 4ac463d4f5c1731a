// The collision answers as JSON (answer_json.hpp): one spelling of every field for every
// edge of the library.

#include "quack/io/answer_json.hpp"

namespace quack {

using nlohmann::json;

json toJson(Vec2 v) {
  return json::array({v.x, v.y});
}

json toJson(const DistanceOutput& d) {
  return {{"distance", d.distance},     {"pointA", toJson(d.pointA)},
          {"pointB", toJson(d.pointB)}, {"normal", toJson(d.normal)},
          {"iterations", d.iterations}, {"status", toString(d.status)}};
}

json toJson(const PenetrationOutput& p) {
  return {{"overlap", p.overlap},        {"depth", p.depth},           {"normal", toJson(p.normal)},
          {"pointA", toJson(p.pointA)},  {"pointB", toJson(p.pointB)}, {"iterations", p.iterations},
          {"status", toString(p.status)}};
}

json toJson(const Manifold& m) {
  json points = json::array();
  for (int i = 0; i < m.pointCount; ++i) {
    points.push_back({{"point", toJson(m.points[i].point)},
                      {"separation", m.points[i].separation},
                      {"id", m.points[i].id}});
  }
  return {{"normal", toJson(m.pointCount > 0 ? m.normal : Vec2{})}, {"points", points}};
}

json toJson(const ShapeCastOutput& c) {
  return {{"hit", c.hit},
          {"fraction", c.fraction},
          {"point", toJson(c.point)},
          {"normal", toJson(c.normal)},
          {"depth", c.depth},
          {"status", toString(c.status)}};
}

json toJson(const RayHit& r) {
  return {{"hit", r.hit},
          {"fraction", r.fraction},
          {"point", toJson(r.point)},
          {"normal", toJson(r.normal)}};
}

json toJson(const ToiOutput& t) {
  return {{"status", toString(t.status)}, {"t", t.t}};
}

// 3D: the same fields, three components.

json toJson(Vec3 v) {
  return json::array({v.x, v.y, v.z});
}

json toJson(const DistanceOutput3& d) {
  return {{"distance", d.distance},     {"pointA", toJson(d.pointA)},
          {"pointB", toJson(d.pointB)}, {"normal", toJson(d.normal)},
          {"iterations", d.iterations}, {"status", toString(d.status)}};
}

json toJson(const PenetrationOutput3& p) {
  return {{"overlap", p.overlap},        {"depth", p.depth},           {"normal", toJson(p.normal)},
          {"pointA", toJson(p.pointA)},  {"pointB", toJson(p.pointB)}, {"iterations", p.iterations},
          {"status", toString(p.status)}};
}

json toJson(const Manifold3& m) {
  json points = json::array();
  for (int i = 0; i < m.pointCount; ++i) {
    points.push_back({{"point", toJson(m.points[i].point)},
                      {"separation", m.points[i].separation},
                      {"id", m.points[i].id}});
  }
  return {{"normal", toJson(m.pointCount > 0 ? m.normal : Vec3{})}, {"points", points}};
}

json toJson(const ShapeCastOutput3& c) {
  return {{"hit", c.hit},
          {"fraction", c.fraction},
          {"point", toJson(c.point)},
          {"normal", toJson(c.normal)},
          {"depth", c.depth},
          {"status", toString(c.status)}};
}

json toJson(const RayHit3& r) {
  return {{"hit", r.hit},
          {"fraction", r.fraction},
          {"point", toJson(r.point)},
          {"normal", toJson(r.normal)}};
}

json toJson(const ToiOutput3& t) {
  return {{"status", toString(t.status)}, {"t", t.t}};
}

// A mesh answer: the convex answer it extends, and the triangle it names.
namespace {

template <class Convex, class MeshAnswer>
json withTriangle(const MeshAnswer& a) {
  json out = toJson(static_cast<const Convex&>(a));
  out["triangle"] = a.triangle;
  return out;
}

}  // namespace

json toJson(const MeshRayHit3& r) {
  return withTriangle<RayHit3>(r);
}

json toJson(const MeshDistanceOutput3& d) {
  return withTriangle<DistanceOutput3>(d);
}

json toJson(const MeshShapeCastOutput3& c) {
  return withTriangle<ShapeCastOutput3>(c);
}

json toJson(const MeshToiOutput3& t) {
  return withTriangle<ToiOutput3>(t);
}

json toJson(const MeshPenetrationOutput3& p) {
  return withTriangle<PenetrationOutput3>(p);
}

json toJson(const std::vector<MeshContact3>& contacts) {
  json manifolds = json::array();
  for (const MeshContact3& c : contacts) {
    json m = toJson(c.manifold);
    m["triangle"] = c.triangle;
    manifolds.push_back(std::move(m));
  }
  return {{"manifolds", manifolds}};
}

}  // namespace quack
