#include "quack/io/render3.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <variant>

#include "render_text.hpp"
#include "replay3_page.hpp"

namespace quack {
namespace {

using detail::appendPictureNumber;

void appendNumbers(std::string& out, std::initializer_list<float> values) {
  bool first = true;
  for (float v : values) {
    if (!first) out += ',';
    first = false;
    appendPictureNumber(out, static_cast<double>(v));
  }
}

void appendVec(std::string& out, Vec3 v) {
  appendNumbers(out, {v.x, v.y, v.z});
}

void appendPose(std::string& out, const Transform3& xf) {
  appendNumbers(out, {xf.p.x, xf.p.y, xf.p.z, xf.q.x, xf.q.y, xf.q.z, xf.q.w});
}

// What a shape's drawing covers: its farthest point from the body origin (for the moving
// bodies' bounds), and its box at the body's pose (for the static shapes' bounds).
struct Extent {
  float reach = 0.0f;
  Aabb3 box{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};

  void add(const Transform3& xf, Vec3 p, float radius) {
    reach = maxf(reach, length(p) + radius);
    const Vec3 w = transformPoint(xf, p);
    const Vec3 r{radius, radius, radius};
    box = {minv(box.lower, w - r), maxv(box.upper, w + r)};
  }
};

// The geometry as the page reads it ("g" of a shape), body frame:
//   {"t": "sphere", "c": [x, y, z], "r": r}
//   {"t": "capsule", "a": [x, y, z], "b": [x, y, z], "r": r}
//   {"t": "hull", "v": [x, y, z, ...], "f": [[i, j, k, ...], ...], "r": r} (boxes too;
//     faces counter-clockwise seen from outside, as Hull3 keeps them)
//   {"t": "mesh", "v": [x, y, z, ...], "i": [i, j, k, ...]} (triangles too)
struct GeometryText {
  const Transform3& xf;
  Extent& extent;
  std::string& out;

  void operator()(const Sphere& s) const {
    out += "{\"t\":\"sphere\",\"c\":[";
    appendVec(out, s.center);
    out += "],\"r\":";
    appendPictureNumber(out, static_cast<double>(s.radius));
    out += '}';
    extent.add(xf, s.center, s.radius);
  }
  void operator()(const Capsule3& c) const {
    out += "{\"t\":\"capsule\",\"a\":[";
    appendVec(out, c.p1);
    out += "],\"b\":[";
    appendVec(out, c.p2);
    out += "],\"r\":";
    appendPictureNumber(out, static_cast<double>(c.radius));
    out += '}';
    extent.add(xf, c.p1, c.radius);
    extent.add(xf, c.p2, c.radius);
  }
  void operator()(const Hull3& h) const {
    out += "{\"t\":\"hull\",\"v\":[";
    for (int i = 0; i < h.vertexCount; ++i) {
      if (i) out += ',';
      appendVec(out, h.vertices[i]);
      extent.add(xf, h.vertices[i], h.radius);
    }
    out += "],\"f\":[";
    for (int f = 0; f < h.faceCount; ++f) {
      out += f ? ",[" : "[";
      const HullFace3& face = h.faces[f];
      for (int k = 0; k < face.count; ++k) {
        if (k) out += ',';
        out += std::to_string(h.faceVertices[face.first + k]);
      }
      out += ']';
    }
    out += "],\"r\":";
    appendPictureNumber(out, static_cast<double>(h.radius));
    out += '}';
  }
  void operator()(const Triangle3& t) const {
    out += "{\"t\":\"mesh\",\"v\":[";
    for (int k = 0; k < 3; ++k) {
      if (k) out += ',';
      appendVec(out, t.v[k]);
      extent.add(xf, t.v[k], 0.0f);
    }
    out += "],\"i\":[0,1,2]}";
  }
  void operator()(const Mesh3& mesh) const {
    out += "{\"t\":\"mesh\",\"v\":[";
    bool first = true;
    for (Vec3 v : mesh.vertices()) {
      if (!first) out += ',';
      first = false;
      appendVec(out, v);
      extent.add(xf, v, 0.0f);
    }
    out += "],\"i\":[";
    first = true;
    for (const MeshTriangle3& t : mesh.triangles()) {
      for (std::int32_t v : t.v) {
        if (!first) out += ',';
        first = false;
        out += std::to_string(v);
      }
    }
    out += "]}";
  }
  void operator()(const ShapeGeometry3& g) const { std::visit(*this, g); }
};

std::size_t strideFor(std::size_t total, std::size_t most) {
  most = std::max<std::size_t>(most, 1);
  return std::max<std::size_t>(1, (total + most - 1) / most);
}

}  // namespace

ReplayRecorder3::ReplayRecorder3(const Scene3& scene, const SceneWorld3& world,
                                 std::uint64_t totalSteps, ReplayOptions3 options)
    : options_(options) {
  for (const SceneBody3& b : scene.bodies)
    shapesTotal_ += b.shapes.size();
  const std::size_t stride = strideFor(shapesTotal_, options_.maxShapes);
  const std::size_t shapeBytes = options_.maxBytes / 4;
  std::string shapes = "[";
  std::size_t index = 0;
  for (std::size_t i = 0; i < scene.bodies.size() && i < world.bodies.size(); ++i) {
    const BodyId3 body = world.bodies[i];
    if (!world.world.isValid(body)) continue;
    const BodyType type = world.world.bodyType(body);
    const Transform3 xf = world.world.transform(body);
    int moving = -1;
    for (const SceneShape3& shape : scene.bodies[i].shapes) {
      if (index++ % stride != 0 || shapes.size() >= shapeBytes) continue;
      std::string entry = shapesDrawn_ > 0 ? "," : "";
      entry += "{\"k\":\"" + std::string(toString(type)) + "\",\"h\":" + std::to_string(i) +
               ",\"n\":" + detail::scriptJsonString(scene.bodies[i].name) + ",\"x\":[";
      appendPose(entry, xf);
      entry += "],\"g\":";
      Extent extent;
      std::visit(GeometryText{xf, extent, entry}, shape.geometry);
      if (shapes.size() + entry.size() + 16 > shapeBytes) continue;  // a huge mesh: left out
      if (type != BodyType::staticBody && moving < 0) {
        moving = static_cast<int>(moving_.size());
        moving_.push_back(static_cast<std::uint32_t>(i));
        reach_.push_back(0.0f);
      }
      entry += ",\"b\":" + std::to_string(moving) + "}";
      if (moving >= 0) {
        float& reach = reach_[static_cast<std::size_t>(moving)];
        reach = maxf(reach, extent.reach);
      } else {
        bounds_ = {minv(bounds_.lower, extent.box.lower), maxv(bounds_.upper, extent.box.upper)};
      }
      shapes += entry;
      ++shapesDrawn_;
    }
  }
  shapes_ = shapes + "]";
  frames_.start(totalSteps, options_.maxFrames);
}

void ReplayRecorder3::record(const SceneWorld3& world) {
  if (!frames_.due()) return;
  const double time = static_cast<double>(world.world.stepCount()) *
                      static_cast<double>(world.world.def().timeStep);
  std::string f = "{\"t\":";
  appendPictureNumber(f, time);
  f += ",\"p\":[";
  for (std::size_t k = 0; k < moving_.size(); ++k) {
    const BodyId3 body = world.bodies[moving_[k]];
    if (k) f += ',';
    if (!world.world.isValid(body)) {
      f += "null,null,null,null,null,null,null";  // destroyed: not drawn from here on
      continue;
    }
    const Transform3 xf = world.world.transform(body);
    appendPose(f, xf);
    const Vec3 r{reach_[k], reach_[k], reach_[k]};
    bounds_ = {minv(bounds_.lower, xf.p - r), maxv(bounds_.upper, xf.p + r)};
    movingBounds_ = {minv(movingBounds_.lower, xf.p - r), maxv(movingBounds_.upper, xf.p + r)};
  }
  // Which bodies sleep, as run lengths over the moving bodies (awake first, then asleep,
  // alternately), as in the 2D replay: a settled pile costs a few numbers a frame.
  f += "],\"w\":[";
  std::size_t run = 0;
  bool awake = true, first = true;
  for (std::uint32_t i : moving_) {
    if (world.world.isAwake(world.bodies[i]) != awake) {
      f += first ? "" : ",";
      f += std::to_string(run);
      first = false;
      run = 0;
      awake = !awake;
    }
    ++run;
  }
  if (run > 0) f += (first ? "" : ",") + std::to_string(run);
  f += "],\"c\":[";
  std::size_t contacts = 0;
  for (const ContactView3& c : world.world.touchingContacts()) {
    for (const Manifold3& m : c.manifolds) {
      for (int k = 0; k < m.pointCount; ++k) {
        if (contacts == options_.maxContactsPerFrame) {
          contactsCapped_ = true;
          break;
        }
        if (contacts++) f += ',';
        appendVec(f, m.points[k].point);
        f += ',';
        appendVec(f, m.normal);
      }
    }
  }
  f += "]}";
  // The frames' share of the budget: what the shapes and the page leave.
  const std::size_t fixed = shapes_.size() + std::strlen(kReplay3Page) + 4096;
  frames_.add(std::move(f), options_.maxBytes > fixed ? options_.maxBytes - fixed : 0);
}

std::string ReplayRecorder3::html(const std::string& title) const {
  // "bounds": everything drawn; "focus": the moving bodies over the whole run (everything
  // when nothing moves), which the camera fits first.
  std::string data = "{\"title\":" + detail::scriptJsonString(title);
  const Aabb3 none{{-1, -1, -1}, {1, 1, 1}};
  const Aabb3 all = bounds_.lower.x <= bounds_.upper.x ? bounds_ : none;
  const Aabb3 focus = movingBounds_.lower.x <= movingBounds_.upper.x ? movingBounds_ : all;
  for (const auto& [key, box] :
       {std::pair{",\"bounds\":[", all}, std::pair{"],\"focus\":[", focus}}) {
    data += key;
    appendVec(data, box.lower);
    data += ',';
    appendVec(data, box.upper);
  }
  data += "],\"drawn\":" + std::to_string(shapesDrawn_) +
          ",\"total\":" + std::to_string(shapesTotal_) +
          ",\"capped\":" + (contactsCapped_ ? "true" : "false") + ",\"shapes\":" + shapes_ +
          ",\"frames\":[\n";
  frames_.appendJoined(data);
  data += "]}";
  std::string page = kReplay3Page;
  const std::string titleMark = "@TITLE@", dataMark = "@DATA@";
  page.replace(page.find(titleMark), titleMark.size(), detail::xmlEscape(title));
  page.replace(page.find(dataMark), dataMark.size(), data);
  return page;
}

}  // namespace quack
