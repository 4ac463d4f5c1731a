// libFuzzer target over the scene parser: any bytes must give a scene (2D or 3D) or an
// error message, never a crash, a hang or a sanitizer report; a parsed scene must build
// into a world and step once. Sizes are bounded so a generator asking for a million bodies
// stays quick and small: the progress callback stops the parse past a few thousand bodies
// (a million generated bodies hold about 1 GB, beyond libFuzzer's memory limit under ASan).
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <variant>

#include "quack/io/scene3.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return 0;
  std::string_view text(reinterpret_cast<const char*>(data), size);
  quack::Result<quack::AnyScene> scene = quack::parseAnyScene(
      text, "fuzz.json", [](std::size_t done, std::size_t) { return done <= 2000; });
  if (!scene) {
    if (scene.error().message.rfind("fuzz.json: ", 0) != 0)
      __builtin_trap();  // messages name the file
    return 0;
  }
  if (const auto* scene3 = std::get_if<quack::Scene3>(&*scene)) {
    if (scene3->bodies.size() > 2000) return 0;
    quack::Result<quack::SceneWorld3> world = quack::buildWorld3(*scene3);
    if (world) (void)world->world.step();
    return 0;
  }
  const quack::Scene& scene2 = std::get<quack::Scene>(*scene);
  if (scene2.bodies.size() > 2000) return 0;
  quack::Result<quack::SceneWorld> world = quack::buildWorld(scene2);
  if (world) (void)world->world.step();
  return 0;
}
