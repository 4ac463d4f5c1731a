#pragma once
// Reading scene-file fields (internal to the io layer): the checks and messages the 2D
// (scene.cpp) and 3D (scene3.cpp) scene parsers share, so that a key means and says the same
// in both. Every function returns an error that starts with the field's JSON path
// ("bodies[3].friction: must be >= 0"); the caller prefixes the file name.

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "quack/core/result.hpp"
#include "quack/io/scene.hpp"
#include "quack/io/scene3.hpp"
#include "quack/math/vec2.hpp"
#include "quack/world/types.hpp"

namespace quack::detail {

/// An unknown key of `j` (an object) is an error naming it: "bodies[0].velocity: unknown key".
Status checkSceneKeys(const nlohmann::json& j, const std::string& path,
                      std::initializer_list<const char*> keys);
/// "path.key", or "key" at the top.
std::string joinPath(const std::string& path, const char* key);
/// A number for a message: "1e+30", "0.5".
std::string showNumber(double x);
/// "the coordinate limit (+-1e+09 m)".
const std::string& coordinateLimitText();

/// The float `f` (already checked finite) at most `hi`; `unit` ends the message
/// ("world.dt: must be at most 1 s, got 1e+30").
Status atMost(float f, float hi, const std::string& path, const char* unit);
/// j[key] as a float, finite as a float; `fallback` when absent.
Result<float> readNumber(const nlohmann::json& j, const char* key, const std::string& path,
                         float fallback);
/// readNumber, and >= 0.
Result<float> readNonNegative(const nlohmann::json& j, const char* key, const std::string& path,
                              float fallback);
/// j[key] as an integer in lo..hi.
Result<int> readInteger(const nlohmann::json& j, const char* key, const std::string& path,
                        int fallback, int lo, int hi);
Result<bool> readBoolean(const nlohmann::json& j, const char* key, const std::string& path,
                         bool fallback);
/// "type": "static", "kinematic" or "dynamic".
Result<BodyType> readBodyType(const nlohmann::json& j, const std::string& path, BodyType fallback);
/// A body's "name" (a string; "body<index>" when absent).
Result<std::string> readBodyName(const nlohmann::json& j, const std::string& path,
                                 std::size_t index);

/// The scene's "categories": at most 64 distinct non-empty names; category i is bit i.
Result<std::vector<std::string>> readCategories(const nlohmann::json& c, const std::string& path);
/// A shape's "filter" object {"category", "mask", "group"} over the scene's categories;
/// category and mask default to every category.
Result<Filter> readFilter(const std::vector<std::string>& categories, const nlohmann::json& j,
                          const std::string& path);

/// The JSON of a scene file: the parse error says where ("not valid JSON: ... at line 3,
/// column 7"), and the root must be an object. Errors start with `fileName`.
Result<nlohmann::json> parseSceneJson(std::string_view text, const std::string& fileName);
/// The text of a scene file: a missing, unreadable or directory path is an error with the
/// reason.
Result<std::string> readSceneText(const std::string& path);
/// The scene's dimension, from "world": {"dim": 2 or 3} (2 when absent). Any other value is
/// an error naming "world.dim" (after `fileName`).
Result<int> sceneDimension(const nlohmann::json& root, const std::string& fileName);

/// parseScene after the JSON is parsed: a 2D scene (no "dim", or "dim": 2); "dim": 3 is an
/// error that points to parseScene3.
Result<Scene> parseSceneRoot(const nlohmann::json& root, const std::string& fileName,
                             const SceneProgress& progress);
/// parseScene3 after the JSON is parsed: "dim": 3 is required.
Result<Scene3> parseScene3Root(const nlohmann::json& root, const std::string& fileName,
                               const SceneProgress& progress);

}  // namespace quack::detail
