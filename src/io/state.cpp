#include "quack/io/state.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "quack/io/scene.hpp"

namespace quack {
namespace {

using nlohmann::json;

// Floats go out as doubles: every float is exactly a double, and nlohmann prints the
// shortest text that reads back as the same double, so the float comes back bit for bit.
json vec(Vec2 v) {
  return json::array({static_cast<double>(v.x), static_cast<double>(v.y)});
}

Result<float> readFloat(const json& j, const std::string& path) {
  if (!j.is_number()) return fail(path + ": must be a number");
  return static_cast<float>(j.get<double>());
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

}  // namespace

StateFile captureState(const SceneWorld& scene, const EventTotals& events,
                       const RunTiming& timing) {
  StateFile s;
  s.time = scene.world.time();
  s.steps = scene.world.stepCount();
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    BodyId b = scene.bodies[i];
    if (!scene.world.isValid(b)) continue;  // destroyed during the run
    s.bodies.push_back({scene.names[i], scene.world.position(b), scene.world.angle(b),
                        scene.world.linearVelocity(b), scene.world.angularVelocity(b)});
  }
  s.events = events;
  s.timing = timing;
  return s;
}

std::string writeState(const StateFile& state) {
  json bodies = json::array();
  for (const BodyState& b : state.bodies) {
    bodies.push_back({{"name", b.name},
                      {"pos", vec(b.pos)},
                      {"angle", static_cast<double>(b.angle)},
                      {"vel", vec(b.vel)},
                      {"angvel", static_cast<double>(b.angvel)}});
  }
  json j = {
      {"time", state.time},
      {"steps", state.steps},
      {"bodies", bodies},
      {"events",
       {{"begin", state.events.begin},
        {"end", state.events.end},
        {"hit", state.events.hit},
        {"sensor", state.events.sensor}}},
      {"timing", {{"ms_per_step", state.timing.msPerStep}, {"total_ms", state.timing.totalMs}}}};
  return j.dump(1) + "\n";
}

Result<StateFile> parseState(std::string_view text, const std::string& fileName) {
  auto error = [&](const std::string& what) { return fail(fileName + ": " + what); };
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return error("not a JSON object");
  for (const auto& item : j.items()) {
    const std::string& k = item.key();
    if (k != "time" && k != "steps" && k != "bodies" && k != "events" && k != "timing") {
      return error(k + ": unknown key");
    }
  }
  StateFile s;
  Result<double> time = readDouble(j, "time", "");
  if (!time) return error(time.error().message.substr(1));
  s.time = *time;
  Result<std::uint64_t> steps = readCount(j, "steps", "");
  if (!steps) return error(steps.error().message.substr(1));
  s.steps = *steps;
  if (!j.contains("bodies") || !j.at("bodies").is_array()) return error("bodies: must be an array");
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
    s.bodies.push_back(st);
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
  if (!j.contains("timing") || !j.at("timing").is_object())
    return error("timing: must be an object");
  Result<double> ms = readDouble(j.at("timing"), "ms_per_step", "timing");
  if (!ms) return error(ms.error().message);
  Result<double> total = readDouble(j.at("timing"), "total_ms", "timing");
  if (!total) return error(total.error().message);
  s.timing = {*ms, *total};
  return s;
}

}  // namespace quack
