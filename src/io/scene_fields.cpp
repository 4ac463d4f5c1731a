#include "scene_fields.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "quack/math/aabb.hpp"

namespace quack::detail {

using nlohmann::json;

Status checkSceneKeys(const json& j, const std::string& path,
                      std::initializer_list<const char*> keys) {
  for (const auto& item : j.items()) {
    bool known = false;
    for (const char* k : keys)
      known |= item.key() == k;
    if (!known) return fail((path.empty() ? "" : path + ".") + item.key() + ": unknown key");
  }
  return {};
}

std::string joinPath(const std::string& path, const char* key) {
  return path.empty() ? key : path + "." + key;
}

std::string showNumber(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

const std::string& coordinateLimitText() {
  static const std::string text =
      "the coordinate limit (+-" + showNumber(static_cast<double>(kMaxCoordinate)) + " m)";
  return text;
}

Status atMost(float f, float hi, const std::string& path, const char* unit) {
  if (f > hi) {
    return fail(path + ": must be at most " + showNumber(static_cast<double>(hi)) + unit +
                ", got " + showNumber(static_cast<double>(f)));
  }
  return {};
}

Result<float> readNumber(const json& j, const char* key, const std::string& path, float fallback) {
  if (!j.contains(key)) return fallback;
  const json& v = j.at(key);
  if (!v.is_number()) return fail(joinPath(path, key) + ": must be a number");
  auto f = static_cast<float>(v.get<double>());
  if (!std::isfinite(f)) return fail(joinPath(path, key) + ": must be finite (as a float)");
  return f;
}

Result<float> readNonNegative(const json& j, const char* key, const std::string& path,
                              float fallback) {
  Result<float> f = readNumber(j, key, path, fallback);
  if (f && *f < 0.0f) return fail(joinPath(path, key) + ": must be >= 0");
  return f;
}

Result<int> readInteger(const json& j, const char* key, const std::string& path, int fallback,
                        int lo, int hi) {
  if (!j.contains(key)) return fallback;
  const json& v = j.at(key);
  if (!v.is_number_integer()) return fail(joinPath(path, key) + ": must be an integer");
  long long i = v.get<long long>();
  if (i < lo || i > hi) {
    return fail(joinPath(path, key) + ": must be in " + std::to_string(lo) + ".." +
                std::to_string(hi));
  }
  return static_cast<int>(i);
}

Result<bool> readBoolean(const json& j, const char* key, const std::string& path, bool fallback) {
  if (!j.contains(key)) return fallback;
  if (!j.at(key).is_boolean()) return fail(joinPath(path, key) + ": must be true or false");
  return j.at(key).get<bool>();
}

Result<BodyType> readBodyType(const json& j, const std::string& path, BodyType fallback) {
  if (!j.contains("type")) return fallback;
  const json& v = j.at("type");
  if (v == "static") return BodyType::staticBody;
  if (v == "kinematic") return BodyType::kinematicBody;
  if (v == "dynamic") return BodyType::dynamicBody;
  return fail(joinPath(path, "type") + ": must be \"static\", \"kinematic\" or \"dynamic\"");
}

Result<std::string> readBodyName(const json& j, const std::string& path, std::size_t index) {
  if (!j.contains("name")) return "body" + std::to_string(index);
  if (!j.at("name").is_string()) return fail(path + ".name: must be a string");
  return j.at("name").get<std::string>();
}

Result<std::vector<std::string>> readCategories(const json& c, const std::string& path) {
  if (!c.is_array()) return fail(path + ": must be an array of names");
  if (c.size() > 64) return fail(path + ": at most 64 categories (one bit each)");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    if (!c[i].is_string() || c[i].get<std::string>().empty())
      return fail(at + ": must be a non-empty name");
    std::string name = c[i].get<std::string>();
    for (const std::string& other : names) {
      if (other == name) return fail(at + ": \"" + name + "\" is declared twice");
    }
    names.push_back(std::move(name));
  }
  return names;
}

namespace {

Result<std::uint64_t> categoryBits(const std::vector<std::string>& categories, const json& v,
                                   const std::string& path) {
  auto bit = [&](const json& name, const std::string& at) -> Result<std::uint64_t> {
    if (!name.is_string()) return fail(at + ": must be a category name");
    const std::string n = name.get<std::string>();
    for (std::size_t i = 0; i < categories.size(); ++i) {
      if (categories[i] == n) return std::uint64_t{1} << i;
    }
    return fail(at + ": unknown category \"" + n + "\" (declare it in \"categories\")");
  };
  if (v.is_string()) return bit(v, path);
  if (!v.is_array()) return fail(path + ": must be a category name or an array of names");
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    Result<std::uint64_t> b = bit(v[i], path + "[" + std::to_string(i) + "]");
    if (!b) return b.error();
    bits |= *b;
  }
  return bits;
}

}  // namespace

// A shape with no filter belongs to every category and accepts every category, so it
// collides with everything; a filter's category and mask default to all as well.
Result<Filter> readFilter(const std::vector<std::string>& categories, const json& j,
                          const std::string& path) {
  Filter f{~std::uint64_t{0}, ~std::uint64_t{0}, 0};
  if (!j.is_object()) return fail(path + ": must be an object {\"category\", \"mask\", \"group\"}");
  if (Status s = checkSceneKeys(j, path, {"category", "mask", "group"}); !s)
    return fail(s.message());
  if (j.contains("category")) {
    Result<std::uint64_t> c = categoryBits(categories, j.at("category"), path + ".category");
    if (!c) return c.error();
    f.category = *c;
  }
  if (j.contains("mask")) {
    Result<std::uint64_t> m = categoryBits(categories, j.at("mask"), path + ".mask");
    if (!m) return m.error();
    f.mask = *m;
  }
  Result<int> g = readInteger(j, "group", path, 0, -1000000000, 1000000000);
  if (!g) return g.error();
  f.group = *g;
  return f;
}

Result<json> parseSceneJson(std::string_view text, const std::string& fileName) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    // nlohmann's message says where ("at line 3, column 7") and what it expected; a number
    // too big for a double (1e400) is an out_of_range error, also caught here.
    return fail(fileName + ": not valid JSON: " + e.what());
  }
  if (!root.is_object()) return fail(fileName + ": a scene must be a JSON object");
  return root;
}

Result<std::string> readSceneText(const std::string& path) {
  // A directory opens as a stream on Linux and reads as nothing ("unexpected end of
  // input"); say what it is instead.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return fail(path + ": is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path + ": cannot open the file (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return fail(path + ": cannot read the file (" + std::strerror(errno) + ")");
  return std::move(text).str();
}

Result<int> sceneDimension(const json& root, const std::string& fileName) {
  if (!root.contains("world") || !root.at("world").is_object() ||
      !root.at("world").contains("dim")) {
    return 2;
  }
  const json& dim = root.at("world").at("dim");
  if (dim.is_number_integer() && (dim.get<long long>() == 2 || dim.get<long long>() == 3))
    return static_cast<int>(dim.get<long long>());
  return fail(fileName + ": world.dim: must be 2 or 3 (the dimension of the scene), got " +
              dim.dump());
}

}  // namespace quack::detail
