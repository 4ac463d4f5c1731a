#include "quack/io/render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "quack/geometry/bounds.hpp"
#include "render_text.hpp"
#include "replay_page.hpp"

namespace quack {

void detail::appendPictureNumber(std::string& out, double x) {
  char buf[32];
  if (!std::isfinite(x)) x = 0.0;
  int n = std::snprintf(buf, sizeof buf, "%.4f", x);
  while (n > 1 && buf[n - 1] == '0')
    --n;
  if (n > 1 && buf[n - 1] == '.') --n;
  if (n == 2 && buf[0] == '-' && buf[1] == '0') {
    buf[0] = '0';
    n = 1;
  }
  out.append(buf, static_cast<std::size_t>(n));
}

std::string detail::scriptJsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '<':
        out += "\\u003c";
        break;
      case '>':
        out += "\\u003e";
        break;
      case '&':
        out += "\\u0026";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string detail::xmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

namespace {

void appendNumber(std::string& out, double x) {
  detail::appendPictureNumber(out, x);
}

void appendVec(std::string& out, Vec2 v) {
  appendNumber(out, static_cast<double>(v.x));
  out += ',';
  appendNumber(out, static_cast<double>(v.y));
}

std::string jsonString(const std::string& s) {
  return detail::scriptJsonString(s);
}

using detail::xmlEscape;

// Arc of radius r about c from direction `from` turning counter-clockwise to `to`.
void appendArc(std::vector<Vec2>& out, Vec2 c, float r, Vec2 from, Vec2 to, float maxStep,
               bool fullTurn) {
  float a0 = std::atan2(from.y, from.x);
  float sweep = fullTurn ? 2.0f * kPi : std::atan2(cross(from, to), dot(from, to));
  if (!fullTurn && sweep < 0.0f) sweep += 2.0f * kPi;
  int steps = std::max(1, static_cast<int>(std::ceil(sweep / maxStep)));
  if (fullTurn) steps = std::max(steps, 24);
  for (int k = 0; k <= steps - (fullTurn ? 1 : 0); ++k) {
    float a = a0 + sweep * static_cast<float>(k) / static_cast<float>(steps);
    out.push_back(c + r * Vec2{std::cos(a), std::sin(a)});
  }
}

// Outline of a rounded convex core (points with outward edge normals, plus a radius).
Outline roundedOutline(const Vec2* v, const Vec2* n, int count, float r, float maxStep) {
  Outline o;
  if (r == 0.0f) {
    o.points.assign(v, v + count);
    return o;
  }
  for (int i = 0; i < count; ++i) {
    Vec2 prev = n[(i + count - 1) % count];
    appendArc(o.points, v[i], r, prev, n[i], maxStep, false);
  }
  return o;
}

Aabb worldBounds(const SceneWorld& scene) {
  Aabb b{{1e30f, 1e30f}, {-1e30f, -1e30f}};
  for (BodyId body : scene.bodies) {
    if (!scene.world.isValid(body)) continue;
    for (ShapeId s : scene.world.shapes(body)) {
      b = merge(b, computeAabb(scene.world.geometry(s), scene.world.transform(body)));
    }
  }
  if (b.lower.x > b.upper.x) b = {{-1, -1}, {1, 1}};
  return b;
}

// Shapes on the world's valid bodies, and the stride that keeps at most `most` of them.
std::size_t shapeCount(const SceneWorld& scene) {
  std::size_t n = 0;
  for (BodyId body : scene.bodies) {
    if (scene.world.isValid(body)) n += scene.world.shapes(body).size();
  }
  return n;
}

std::size_t strideFor(std::size_t total, std::size_t most) {
  most = std::max<std::size_t>(most, 1);
  return std::max<std::size_t>(1, (total + most - 1) / most);
}

}  // namespace

namespace {
// A joint drawn as body A's centre -> its anchor -> B's anchor -> B's centre (a mouse
// joint: the target twice).
std::array<Vec2, 4> jointLine(const World& world, JointId j) {
  const JointDef& d = world.jointDef(j);
  const auto [onA, onB] = world.jointAnchors(j);
  const Vec2 cA = d.type == JointType::mouse ? onA : world.worldCenterOfMass(d.bodyA);
  return {cA, onA, onB, world.worldCenterOfMass(d.bodyB)};
}
}  // namespace

Outline outlineOf(const ShapeGeometry& geometry, float maxArcStep) {
  struct Visitor {
    float step;
    Outline operator()(const Circle& c) const {
      Outline o;
      appendArc(o.points, c.center, c.radius, {1, 0}, {1, 0}, step, true);
      return o;
    }
    Outline operator()(const Capsule& c) const {
      Vec2 n = normalize(rightPerp(c.p2 - c.p1));
      const Vec2 v[2] = {c.p1, c.p2};
      const Vec2 normals[2] = {n, -n};
      return roundedOutline(v, normals, 2, c.radius, step);
    }
    Outline operator()(const Segment& s) const { return {{s.p1, s.p2}, false}; }
    Outline operator()(const Polygon& p) const {
      return roundedOutline(p.vertices, p.normals, p.count, p.radius, step);
    }
  };
  return std::visit(Visitor{maxArcStep}, geometry);
}

std::string renderSvg(const SceneWorld& scene, const std::string& title,
                      const SvgOptions& options) {
  Aabb b = inflate(worldBounds(scene), 0.5f);
  float w = b.upper.x - b.lower.x, h = b.upper.y - b.lower.y;
  // About 1000 pixels across the longer side; strokes stay a fixed share of the view.
  float stroke = 0.0015f * maxf(w, h);
  std::string out;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"%g %g %g %g\" width=\"%d\" "
                "height=\"%d\">\n",
                static_cast<double>(b.lower.x), static_cast<double>(-b.upper.y),
                static_cast<double>(w), static_cast<double>(h),
                static_cast<int>(1000.0f * w / maxf(w, h)),
                static_cast<int>(1000.0f * h / maxf(w, h)));
  out += buf;
  out += "<title>" + xmlEscape(title) + "</title>\n";
  out += "<rect x=\"" + std::to_string(b.lower.x) + "\" y=\"" + std::to_string(-b.upper.y) +
         "\" width=\"" + std::to_string(w) + "\" height=\"" + std::to_string(h) +
         "\" fill=\"#fbfaf7\"/>\n";
  out += "<g transform=\"scale(1,-1)\" stroke-width=\"" + std::to_string(stroke) +
         "\" stroke-linejoin=\"round\">\n";
  // The size budget: every k-th shape, and nothing more once the shapes' text would leave
  // too little room for the contacts and the note (a quarter of the budget).
  const std::size_t total = shapeCount(scene);
  const std::size_t stride = strideFor(total, options.maxShapes);
  const std::size_t shapeBytes = options.maxBytes - options.maxBytes / 4;
  std::size_t index = 0, drawn = 0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    BodyId body = scene.bodies[i];
    if (!scene.world.isValid(body)) continue;
    Transform xf = scene.world.transform(body);
    BodyType type = scene.world.bodyType(body);
    for (ShapeId s : scene.world.shapes(body)) {
      if (index++ % stride != 0 || out.size() >= shapeBytes) continue;
      Outline o = outlineOf(scene.world.geometry(s));
      bool sensor = scene.world.shapeDef(s).sensor;
      const char* fill = sensor                            ? "#7fb8ff33"
                         : type == BodyType::staticBody    ? "#b9b4a8"
                         : type == BodyType::kinematicBody ? "#9cc3e6"
                                                           : "#f2b45a";
      std::string d;
      for (std::size_t k = 0; k < o.points.size(); ++k) {
        d += k == 0 ? 'M' : 'L';
        appendVec(d, transformPoint(xf, o.points[k]));
      }
      if (o.closed) d += 'Z';
      std::string path = "<path d=\"" + d + "\" fill=\"" + (o.closed ? fill : "none") +
                         "\" stroke=\"" + (sensor ? "#3b82f6" : "#4a4536") + "\"" +
                         (sensor ? " stroke-dasharray=\"0.1 0.1\"" : "") + "/>\n";
      if (out.size() + path.size() > shapeBytes) continue;
      out += path;
      ++drawn;
    }
  }
  std::size_t contacts = 0, contactsTotal = 0;
  for (const World::ContactView& c : scene.world.touchingContacts()) {
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      ++contactsTotal;
      if (contacts >= options.maxContacts) continue;
      ++contacts;
      Vec2 p = c.manifold.points[k].point;
      Vec2 q = p + 0.3f * c.manifold.normal;
      std::string line = "<line x1=\"";
      appendNumber(line, static_cast<double>(p.x));
      line += "\" y1=\"";
      appendNumber(line, static_cast<double>(p.y));
      line += "\" x2=\"";
      appendNumber(line, static_cast<double>(q.x));
      line += "\" y2=\"";
      appendNumber(line, static_cast<double>(q.y));
      line += "\" stroke=\"#d62828\"/><circle cx=\"";
      appendNumber(line, static_cast<double>(p.x));
      line += "\" cy=\"";
      appendNumber(line, static_cast<double>(p.y));
      line += "\" r=\"" + std::to_string(2.5f * stroke) + "\" fill=\"#d62828\"/>\n";
      out += line;
    }
  }
  for (JointId j : scene.world.joints()) {
    const std::array<Vec2, 4> line = jointLine(scene.world, j);
    std::string path = "<polyline points=\"";
    for (const Vec2& p : line) {
      appendNumber(path, static_cast<double>(p.x));
      path += ',';
      appendNumber(path, static_cast<double>(p.y));
      path += ' ';
    }
    path += "\" fill=\"none\" stroke=\"#2a9d8f\"/>";
    for (int k = 1; k <= 2; ++k) {
      path += "<circle cx=\"";
      appendNumber(path, static_cast<double>(line[k].x));
      path += "\" cy=\"";
      appendNumber(path, static_cast<double>(line[k].y));
      path += "\" r=\"" + std::to_string(2.5f * stroke) + "\" fill=\"#2a9d8f\"/>";
    }
    if (out.size() + path.size() > options.maxBytes) break;
    out += path + "\n";
  }
  out += "</g>\n";
  if (drawn < total || contacts < contactsTotal) {
    // Said in the picture, top left, so a thinned picture is never mistaken for the scene.
    std::string note = "drew " + std::to_string(drawn) + " of " + std::to_string(total) +
                       " shapes and " + std::to_string(contacts) + " of " +
                       std::to_string(contactsTotal) + " contact points (the SVG size budget)";
    std::snprintf(buf, sizeof buf, "<text x=\"%g\" y=\"%g\" font-size=\"%g\" fill=\"#222\">",
                  static_cast<double>(b.lower.x + 0.01f * w),
                  static_cast<double>(-b.upper.y + 0.03f * h),
                  static_cast<double>(0.02f * maxf(w, h)));
    out += buf + xmlEscape(note) + "</text>\n";
  }
  out += "</svg>\n";
  return out;
}

void detail::ReplayFrames::start(std::uint64_t totalCalls, int maxFrames) {
  totalCalls_ = totalCalls;
  // At most maxFrames to begin with (a call every `every_`); thin() halves them whenever
  // their text outgrows the budget.
  const std::uint64_t cap = std::max<std::uint64_t>(2, static_cast<std::uint64_t>(maxFrames));
  every_ = std::max<std::uint64_t>(1, (totalCalls + cap - 1) / cap);
}

bool detail::ReplayFrames::due() {
  call_ = calls_++;
  // Every `every_`-th call, and the last one: the replay always ends where the run did.
  return call_ % every_ == 0 || call_ + 1 == totalCalls_;
}

void detail::ReplayFrames::add(std::string frame, std::size_t budget) {
  bytes_ += frame.size() + 2;
  frames_.emplace_back(call_, std::move(frame));
  while (bytes_ > budget && frames_.size() > 2)
    thin();
}

void detail::ReplayFrames::thin() {
  std::uint64_t every = 2 * every_;
  std::vector<std::pair<std::uint64_t, std::string>> kept;
  std::size_t bytes = 0;
  for (auto& f : frames_) {
    if (f.first % every == 0 || f.first + 1 == totalCalls_) {
      bytes += f.second.size() + 2;
      kept.push_back(std::move(f));
    }
  }
  frames_ = std::move(kept);
  bytes_ = bytes;
  every_ = every;
}

void detail::ReplayFrames::appendJoined(std::string& out) const {
  out.reserve(out.size() + bytes_ + 8);
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    if (k) out += ",\n";
    out += frames_[k].second;
  }
}

ReplayRecorder::ReplayRecorder(const SceneWorld& scene, std::uint64_t totalSteps,
                               ReplayOptions options)
    : options_(options) {
  shapesTotal_ = shapeCount(scene);
  const std::size_t stride = strideFor(shapesTotal_, options_.maxShapes);
  const std::size_t shapeBytes = options_.maxBytes / 4;
  std::string shapes = "[";
  std::size_t index = 0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    BodyId body = scene.bodies[i];
    if (!scene.world.isValid(body)) continue;
    BodyType type = scene.world.bodyType(body);
    int moving = -1;
    Transform xf = scene.world.transform(body);
    for (ShapeId s : scene.world.shapes(body)) {
      if (index++ % stride != 0 || shapes.size() >= shapeBytes) continue;
      Outline o = outlineOf(scene.world.geometry(s));
      float reach = 0.0f;
      for (Vec2 p : o.points)
        reach = maxf(reach, length(p));
      if (type != BodyType::staticBody && moving < 0) {
        moving = static_cast<int>(moving_.size());
        moving_.push_back(static_cast<std::uint32_t>(i));
        reach_.push_back(0.0f);
      }
      if (moving >= 0)
        reach_[static_cast<std::size_t>(moving)] =
            maxf(reach_[static_cast<std::size_t>(moving)], reach);
      std::string entry = shapesDrawn_ > 0 ? "," : "";
      entry += "{\"b\":" + std::to_string(moving) + ",\"k\":\"" + toString(type) +
               "\",\"s\":" + (scene.world.shapeDef(s).sensor ? "1" : "0") +
               ",\"c\":" + (o.closed ? "1" : "0") + ",\"n\":" + jsonString(scene.names[i]) +
               ",\"x\":[";
      appendVec(entry, xf.p);
      entry += ',';
      appendNumber(entry, static_cast<double>(xf.q.angle()));
      entry += "],\"o\":[";
      for (std::size_t k = 0; k < o.points.size(); ++k) {
        if (k) entry += ',';
        appendVec(entry, o.points[k]);
      }
      entry += "]}";
      if (shapes.size() + entry.size() > shapeBytes) continue;
      shapes += entry;
      ++shapesDrawn_;
      if (type == BodyType::staticBody)
        bounds_ = merge(bounds_, computeAabb(scene.world.geometry(s), xf));
    }
  }
  shapes_ = shapes + "]";
  frames_.start(totalSteps, options_.maxFrames);
}

void ReplayRecorder::record(const SceneWorld& scene) {
  if (!frames_.due()) return;
  std::string f = "{\"t\":";
  appendNumber(f, scene.world.time());
  f += ",\"p\":[";
  for (std::size_t k = 0; k < moving_.size(); ++k) {
    BodyId body = scene.bodies[moving_[k]];
    if (k) f += ',';
    if (!scene.world.isValid(body)) {
      f += "null,null,null";  // destroyed: not drawn from here on
      continue;
    }
    Transform xf = scene.world.transform(body);
    appendVec(f, xf.p);
    f += ',';
    appendNumber(f, static_cast<double>(xf.q.angle()));
    bounds_ =
        merge(bounds_, Aabb{xf.p - Vec2{reach_[k], reach_[k]}, xf.p + Vec2{reach_[k], reach_[k]}});
  }
  // Which bodies sleep, as run lengths over the moving bodies (awake first, then asleep,
  // alternately): islands sleep together and scene order keeps them together, so a settled
  // pile costs a few numbers a frame, and a frame stays whole when thin() drops others.
  f += "],\"w\":[";
  std::size_t run = 0;
  bool awake = true, first = true;
  for (std::uint32_t i : moving_) {
    if (scene.world.isAwake(scene.bodies[i]) != awake) {
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
  for (const World::ContactView& c : scene.world.touchingContacts()) {
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      if (contacts == options_.maxContactsPerFrame) {
        contactsCapped_ = true;
        break;
      }
      if (contacts++) f += ',';
      appendVec(f, c.manifold.points[k].point);
      f += ',';
      appendVec(f, c.manifold.normal);
    }
    if (contacts == options_.maxContactsPerFrame) break;
  }
  f += ']';
  if (scene.world.jointCount() > 0) {
    f += ",\"j\":[";
    bool firstJoint = true;
    for (JointId j : scene.world.joints()) {
      for (const Vec2& p : jointLine(scene.world, j)) {
        if (!firstJoint) f += ',';
        firstJoint = false;
        appendVec(f, p);
      }
    }
    f += ']';
  }
  if (options_.broadPhaseBoxes) {
    f += ",\"a\":[";
    std::size_t boxes = 0;
    scene.world.broadPhase().queryAabb(Aabb{{-1e9f, -1e9f}, {1e9f, 1e9f}},
                                       [&](ProxyId id, std::uint64_t) {
                                         if (boxes == options_.maxBoxesPerFrame) {
                                           contactsCapped_ = true;
                                           return false;
                                         }
                                         Aabb fat = scene.world.broadPhase().fatBox(id);
                                         if (boxes++) f += ',';
                                         appendVec(f, fat.lower);
                                         f += ',';
                                         appendVec(f, fat.upper);
                                         return true;
                                       });
    f += ']';
  }
  f += '}';
  // The frames' share of the budget: what the shapes and the page leave.
  const std::size_t fixed = shapes_.size() + std::strlen(kReplayPage) + 4096;
  frames_.add(std::move(f), options_.maxBytes > fixed ? options_.maxBytes - fixed : 0);
}

std::string ReplayRecorder::html(const std::string& title) const {
  std::string data = "{\"title\":" + jsonString(title) + ",\"bounds\":[";
  Aabb bounds = bounds_.lower.x <= bounds_.upper.x ? bounds_ : Aabb{{-1, -1}, {1, 1}};
  appendVec(data, bounds.lower);
  data += ',';
  appendVec(data, bounds.upper);
  data += "],\"boxes\":" + std::string(options_.broadPhaseBoxes ? "true" : "false") +
          ",\"drawn\":" + std::to_string(shapesDrawn_) +
          ",\"total\":" + std::to_string(shapesTotal_) +
          ",\"capped\":" + (contactsCapped_ ? "true" : "false") + ",\"shapes\":" + shapes_ +
          ",\"frames\":[\n";
  frames_.appendJoined(data);
  data += "]}";
  std::string page = kReplayPage;
  const std::string titleMark = "@TITLE@", dataMark = "@DATA@";
  page.replace(page.find(titleMark), titleMark.size(), xmlEscape(title));
  page.replace(page.find(dataMark), dataMark.size(), data);
  return page;
}

}  // namespace quack
