#include "quack/io/state.hpp"

#include <cmath>
#include <string_view>

#include <nlohmann/json.hpp>

#include "quack/io/number_text.hpp"
#include "quack/io/scene.hpp"
#include "quack/io/scene3.hpp"

namespace quack {
namespace {

using nlohmann::json;

Result<float> readFloat(const json& j, const std::string& path) {
  if (!j.is_number()) return fail(path + ": must be a number");
  auto f = static_cast<float>(j.get<double>());
  if (!std::isfinite(f)) return fail(path + ": must be finite (as a float)");
  return f;
}

Result<Vec2> readVec(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 2) return fail(path + ": must be [x, y]");
  Result<float> x = readFloat(j[0], path + "[0]");
  if (!x) return x.error();
  Result<float> y = readFloat(j[1], path + "[1]");
  if (!y) return y.error();
  return Vec2{*x, *y};
}

Result<std::uint64_t> readCount(const json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) return fail(path + "." + key + ": missing");
  if (!j.at(key).is_number_unsigned()) return fail(path + "." + key + ": must be a count");
  return j.at(key).get<std::uint64_t>();
}

Result<double> readDouble(const json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) return fail(path + "." + key + ": missing");
  if (!j.at(key).is_number()) return fail(path + "." + key + ": must be a number");
  return j.at(key).get<double>();
}

// A double as the shortest text that reads back as the same double (so a float, widened,
// comes back bit for bit); integers get a ".0" as nlohmann writes them.
void appendDouble(std::string& out, double x) {
  const std::size_t start = out.size();
  appendShortest(out, x);
  if (out.find_first_of(".eEni", start) == std::string::npos) out += ".0";
}

void appendVec(std::string& out, Vec2 v) {
  out += '[';
  appendDouble(out, static_cast<double>(v.x));
  out += ", ";
  appendDouble(out, static_cast<double>(v.y));
  out += ']';
}

// [x, y, z] or [x, y, z, w]: `count` finite floats.
Result<std::vector<float>> readFloats(const json& j, std::size_t count, const std::string& path,
                                      const char* shape) {
  if (!j.is_array() || j.size() != count) return fail(path + ": must be " + shape);
  std::vector<float> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    Result<float> f = readFloat(j[i], path + "[" + std::to_string(i) + "]");
    if (!f) return f.error();
    out[i] = *f;
  }
  return out;
}

void appendFloats(std::string& out, std::initializer_list<float> values) {
  out += '[';
  bool first = true;
  for (float v : values) {
    if (!first) out += ", ";
    first = false;
    appendDouble(out, static_cast<double>(v));
  }
  out += ']';
}

}  // namespace

StateFile captureState(const SceneWorld& scene, const EventTotals& events) {
  StateFile s;
  s.time = scene.world.time();
  s.steps = scene.world.stepCount();
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    BodyId b = scene.bodies[i];
    if (!scene.world.isValid(b)) continue;  // destroyed during the run
    s.bodies.push_back({scene.names[i], scene.world.position(b), scene.world.angle(b),
                        scene.world.linearVelocity(b), scene.world.angularVelocity(b),
                        scene.world.isAwake(b)});
  }
  if (!scene.joints.empty()) {
    s.hasJoints = true;
    std::vector<const std::string*> nameOf;  // by body index
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      const std::uint32_t index = scene.bodies[i].index;
      if (index >= nameOf.size()) nameOf.resize(index + 1, nullptr);
      nameOf[index] = &scene.names[i];
    }
    auto name = [&](BodyId b) {
      return b.index < nameOf.size() && nameOf[b.index] != nullptr ? *nameOf[b.index]
                                                                   : std::string();
    };
    for (JointId j : scene.joints) {
      if (!scene.world.isValid(j)) continue;  // broken, or taken with a body
      const JointDef& d = scene.world.jointDef(j);
      s.joints.push_back({toString(d.type), d.type == JointType::mouse ? "" : name(d.bodyA),
                          name(d.bodyB), scene.world.jointForce(j), scene.world.jointTorque(j)});
    }
  }
  s.events = events;
  return s;
}

// One body per line: a state file of a million bodies is about 100 MB, written in one pass.
std::string writeState(const StateFile& state) {
  std::string out = "{\"time\": ";
  appendDouble(out, state.time);
  out += ",\n \"steps\": " + std::to_string(state.steps) + ",\n \"bodies\": [";
  out.reserve(out.size() + 125 * state.bodies.size() + 128);
  for (std::size_t i = 0; i < state.bodies.size(); ++i) {
    const BodyState& b = state.bodies[i];
    out += i == 0 ? "\n  " : ",\n  ";
    out += "{\"name\": " + json(b.name).dump() + ", \"pos\": ";
    appendVec(out, b.pos);
    out += ", \"angle\": ";
    appendDouble(out, static_cast<double>(b.angle));
    out += ", \"vel\": ";
    appendVec(out, b.vel);
    out += ", \"angvel\": ";
    appendDouble(out, static_cast<double>(b.angvel));
    out += b.awake ? ", \"awake\": true}" : ", \"awake\": false}";
  }
  out += state.bodies.empty() ? "],\n" : "\n ],\n";
  if (state.hasJoints) {
    out += " \"joints\": [";
    for (std::size_t i = 0; i < state.joints.size(); ++i) {
      const JointState& jt = state.joints[i];
      out += i == 0 ? "\n  " : ",\n  ";
      out += "{\"type\": " + json(jt.type).dump() + ", \"a\": " + json(jt.a).dump() +
             ", \"b\": " + json(jt.b).dump() + ", \"force\": ";
      appendVec(out, jt.force);
      out += ", \"torque\": ";
      appendDouble(out, static_cast<double>(jt.torque));
      out += "}";
    }
    out += state.joints.empty() ? "],\n" : "\n ],\n";
  }
  out += " \"events\": {\"begin\": " + std::to_string(state.events.begin) +
         ", \"end\": " + std::to_string(state.events.end) +
         ", \"hit\": " + std::to_string(state.events.hit) +
         ", \"sensor\": " + std::to_string(state.events.sensor) + "}}\n";
  return out;
}

void appendEventLines(std::string& out, std::uint64_t step, const StepEvents& events) {
  const std::string head = "{\"step\": " + std::to_string(step) + ", \"event\": \"";
  auto pair = [&](const char* kind, const char* a, std::uint32_t ia, const char* b,
                  std::uint32_t ib) {
    out += head + kind + "\", \"" + a + "\": " + std::to_string(ia) + ", \"" + b +
           "\": " + std::to_string(ib);
  };
  for (const ContactBeginEvent& e : events.begin) {
    pair("begin", "a", e.shapeA.index, "b", e.shapeB.index);
    out += "}\n";
  }
  for (const ContactEndEvent& e : events.end) {
    pair("end", "a", e.shapeA.index, "b", e.shapeB.index);
    out += "}\n";
  }
  for (const ContactHitEvent& e : events.hit) {
    pair("hit", "a", e.shapeA.index, "b", e.shapeB.index);
    out += ", \"point\": ";
    appendVec(out, e.point);
    out += ", \"normal\": ";
    appendVec(out, e.normal);
    out += ", \"speed\": ";
    appendDouble(out, static_cast<double>(e.approachSpeed));
    out += "}\n";
  }
  for (const SensorEvent& e : events.sensorBegin) {
    pair("sensor-begin", "sensor", e.sensor.index, "visitor", e.visitor.index);
    out += "}\n";
  }
  for (const SensorEvent& e : events.sensorEnd) {
    pair("sensor-end", "sensor", e.sensor.index, "visitor", e.visitor.index);
    out += "}\n";
  }
  for (const ToiEvent& e : events.toi) {
    out += head + "toi\", \"time\": ";
    appendDouble(out, static_cast<double>(e.time));
    out += ", \"a\": " + std::to_string(e.shapeA.index) +
           ", \"b\": " + std::to_string(e.shapeB.index) + ", \"point\": ";
    appendVec(out, e.point);
    out += ", \"normal\": ";
    appendVec(out, e.normal);
    out += "}\n";
  }
  for (BodyId b : events.outOfBounds) {
    out += head + "out-of-bounds\", \"body\": " + std::to_string(b.index) + "}\n";
  }
  for (const JointEndEvent& e : events.jointEnd) {
    out += head + "joint-end\", \"joint\": " + std::to_string(e.joint.index) + ", \"reason\": \"" +
           (e.reason == JointEndReason::broken ? "broken" : "body-destroyed") + "\", \"force\": ";
    appendVec(out, e.force);
    out += ", \"torque\": ";
    appendDouble(out, static_cast<double>(e.torque));
    out += "}\n";
  }
}

namespace {

// The keys both state files begin with: time, steps, and a bodies array (read by the caller).
Status readHeader(const json& j, double& time, std::uint64_t& steps) {
  Result<double> t = readDouble(j, "time", "");
  if (!t) return fail(t.error().message.substr(1));
  Result<std::uint64_t> n = readCount(j, "steps", "");
  if (!n) return fail(n.error().message.substr(1));
  if (!j.contains("bodies") || !j.at("bodies").is_array()) return fail("bodies: must be an array");
  time = *t;
  steps = *n;
  return {};
}

}  // namespace

Result<StateFile> parseState(std::string_view text, const std::string& fileName) {
  auto error = [&](const std::string& what) { return fail(fileName + ": " + what); };
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return error("not a JSON object");
  if (j.contains("dim")) return error("dim: a 3D state file (parseState3 reads it)");
  for (const auto& item : j.items()) {
    const std::string& k = item.key();
    if (k != "time" && k != "steps" && k != "bodies" && k != "joints" && k != "events" &&
        k != "timing") {
      return error(k + ": unknown key");
    }
  }
  StateFile s;
  if (Status h = readHeader(j, s.time, s.steps); !h) return error(h.message());
  const json& bodies = j.at("bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const json& b = bodies[i];
    std::string path = "bodies[" + std::to_string(i) + "]";
    if (!b.is_object()) return error(path + ": must be an object");
    BodyState st;
    if (!b.contains("name") || !b.at("name").is_string())
      return error(path + ".name: must be a string");
    st.name = b.at("name").get<std::string>();
    for (auto [key, target] : {std::pair{"pos", &st.pos}, std::pair{"vel", &st.vel}}) {
      if (!b.contains(key)) return error(path + "." + key + ": missing");
      Result<Vec2> v = readVec(b.at(key), path + "." + key);
      if (!v) return error(v.error().message);
      *target = *v;
    }
    for (auto [key, target] : {std::pair{"angle", &st.angle}, std::pair{"angvel", &st.angvel}}) {
      if (!b.contains(key)) return error(path + "." + key + ": missing");
      Result<float> v = readFloat(b.at(key), path + "." + key);
      if (!v) return error(v.error().message);
      *target = *v;
    }
    // Optional: a file from before sleeping has none, and every body then was simulated.
    if (b.contains("awake")) {
      if (!b.at("awake").is_boolean()) return error(path + ".awake: must be true or false");
      st.awake = b.at("awake").get<bool>();
    }
    s.bodies.push_back(st);
  }
  if (j.contains("joints")) {
    const json& joints = j.at("joints");
    if (!joints.is_array()) return error("joints: must be an array");
    s.hasJoints = true;
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const json& jt = joints[i];
      const std::string path = "joints[" + std::to_string(i) + "]";
      if (!jt.is_object()) return error(path + ": must be an object");
      JointState st;
      for (auto [key, target] :
           {std::pair{"type", &st.type}, std::pair{"a", &st.a}, std::pair{"b", &st.b}}) {
        if (!jt.contains(key) || !jt.at(key).is_string())
          return error(path + "." + key + ": must be a string");
        *target = jt.at(key).get<std::string>();
      }
      if (!jt.contains("force")) return error(path + ".force: missing");
      Result<Vec2> f = readVec(jt.at("force"), path + ".force");
      if (!f) return error(f.error().message);
      st.force = *f;
      if (!jt.contains("torque")) return error(path + ".torque: missing");
      Result<float> t = readFloat(jt.at("torque"), path + ".torque");
      if (!t) return error(t.error().message);
      st.torque = *t;
      s.joints.push_back(st);
    }
  }
  if (!j.contains("events") || !j.at("events").is_object())
    return error("events: must be an object");
  const json& e = j.at("events");
  for (auto [key, target] :
       {std::pair{"begin", &s.events.begin}, std::pair{"end", &s.events.end},
        std::pair{"hit", &s.events.hit}, std::pair{"sensor", &s.events.sensor}}) {
    Result<std::uint64_t> c = readCount(e, key, "events");
    if (!c) return error(c.error().message);
    *target = *c;
  }
  // "timing": written by Quack before state files became a pure function of the scene;
  // accepted and ignored.
  if (j.contains("timing") && !j.at("timing").is_object())
    return error("timing: must be an object");
  return s;
}

// ---- 3D ----------------------------------------------------------------------------------

StateFile3 captureState3(const SceneWorld3& scene, const EventTotals& events) {
  StateFile3 s;
  s.steps = scene.world.stepCount();
  // quack run steps by the world's dt only, so the time is the product (rounded once).
  s.time = static_cast<double>(s.steps) * static_cast<double>(scene.world.def().timeStep);
  s.bodies.reserve(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyId3 b = scene.bodies[i];
    if (!scene.world.isValid(b)) continue;  // destroyed during the run
    s.bodies.push_back({scene.names[i], scene.world.position(b), scene.world.rotation(b),
                        scene.world.linearVelocity(b), scene.world.angularVelocity(b),
                        // World3 keeps a static body's flag set; a state file says what the
                        // 2D one does: a static body is never awake (never simulated).
                        scene.world.isAwake(b) && scene.world.bodyType(b) != BodyType::staticBody});
  }
  s.events = {events.begin, events.end, 0, 0};
  return s;
}

std::string writeState3(const StateFile3& state) {
  std::string out = "{\"dim\": 3,\n \"time\": ";
  appendDouble(out, state.time);
  out += ",\n \"steps\": " + std::to_string(state.steps) + ",\n \"bodies\": [";
  out.reserve(out.size() + 220 * state.bodies.size() + 128);
  for (std::size_t i = 0; i < state.bodies.size(); ++i) {
    const BodyState3& b = state.bodies[i];
    out += i == 0 ? "\n  " : ",\n  ";
    out += "{\"name\": " + json(b.name).dump() + ", \"pos\": ";
    appendFloats(out, {b.pos.x, b.pos.y, b.pos.z});
    out += ", \"quat\": ";
    appendFloats(out, {b.quat.x, b.quat.y, b.quat.z, b.quat.w});
    out += ", \"vel\": ";
    appendFloats(out, {b.vel.x, b.vel.y, b.vel.z});
    out += ", \"angvel\": ";
    appendFloats(out, {b.angvel.x, b.angvel.y, b.angvel.z});
    out += b.awake ? ", \"awake\": true}" : ", \"awake\": false}";
  }
  out += state.bodies.empty() ? "],\n" : "\n ],\n";
  out += " \"events\": {\"begin\": " + std::to_string(state.events.begin) +
         ", \"end\": " + std::to_string(state.events.end) + "}}\n";
  return out;
}

Result<StateFile3> parseState3(std::string_view text, const std::string& fileName) {
  auto error = [&](const std::string& what) { return fail(fileName + ": " + what); };
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return error("not a JSON object");
  if (!j.contains("dim")) {
    return error(
        "dim: missing (a 3D state file starts with \"dim\": 3; a file without it is "
        "2D: parseState reads it)");
  }
  if (!j.at("dim").is_number_integer() || j.at("dim").get<long long>() != 3)
    return error("dim: must be 3");
  for (const auto& item : j.items()) {
    const std::string& k = item.key();
    if (k != "dim" && k != "time" && k != "steps" && k != "bodies" && k != "events")
      return error(k + ": unknown key");
  }
  StateFile3 s;
  if (Status h = readHeader(j, s.time, s.steps); !h) return error(h.message());
  const json& bodies = j.at("bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const json& b = bodies[i];
    const std::string path = "bodies[" + std::to_string(i) + "]";
    if (!b.is_object()) return error(path + ": must be an object");
    for (const auto& item : b.items()) {
      const std::string& k = item.key();
      if (k != "name" && k != "pos" && k != "quat" && k != "vel" && k != "angvel" && k != "awake")
        return error(path + "." + k + ": unknown key");
    }
    BodyState3 st;
    if (!b.contains("name") || !b.at("name").is_string())
      return error(path + ".name: must be a string");
    st.name = b.at("name").get<std::string>();
    for (auto [key, target] :
         {std::pair{"pos", &st.pos}, std::pair{"vel", &st.vel}, std::pair{"angvel", &st.angvel}}) {
      if (!b.contains(key)) return error(path + "." + key + ": missing");
      Result<std::vector<float>> v = readFloats(b.at(key), 3, path + "." + key, "[x, y, z]");
      if (!v) return error(v.error().message);
      *target = Vec3{(*v)[0], (*v)[1], (*v)[2]};
    }
    if (!b.contains("quat")) return error(path + ".quat: missing");
    Result<std::vector<float>> q = readFloats(b.at("quat"), 4, path + ".quat", "[x, y, z, w]");
    if (!q) return error(q.error().message);
    st.quat = Quat{(*q)[0], (*q)[1], (*q)[2], (*q)[3]};
    if (!b.contains("awake") || !b.at("awake").is_boolean())
      return error(path + ".awake: must be true or false");
    st.awake = b.at("awake").get<bool>();
    s.bodies.push_back(std::move(st));
  }
  if (!j.contains("events") || !j.at("events").is_object())
    return error("events: must be an object");
  const json& e = j.at("events");
  for (auto [key, target] :
       {std::pair{"begin", &s.events.begin}, std::pair{"end", &s.events.end}}) {
    Result<std::uint64_t> c = readCount(e, key, "events");
    if (!c) return error(c.error().message);
    *target = *c;
  }
  return s;
}

void appendEventLines3(std::string& out, std::uint64_t step, const StepEvents3& events) {
  const std::string head = "{\"step\": " + std::to_string(step) + ", \"event\": \"";
  for (const ContactEvent3& e : events.begin) {
    out += head + "begin\", \"a\": " + std::to_string(e.shapeA.index) +
           ", \"b\": " + std::to_string(e.shapeB.index) + "}\n";
  }
  for (const ContactEvent3& e : events.end) {
    out += head + "end\", \"a\": " + std::to_string(e.shapeA.index) +
           ", \"b\": " + std::to_string(e.shapeB.index) + "}\n";
  }
}

}  // namespace quack
