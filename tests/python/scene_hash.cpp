// For tests/python/test_world.py: loads a scene, takes N steps and prints the world's
// stateHash, so that the Python module's world can be compared with C++'s without Python.
//   quack_python_scene_hash SCENE STEPS

#include <cstdio>
#include <cstdlib>
#include <string>

#include "quack/io/scene.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: quack_python_scene_hash SCENE STEPS\n");
    return 2;
  }
  quack::Result<quack::Scene> scene = quack::loadScene(argv[1]);
  if (!scene) {
    std::fprintf(stderr, "%s\n", scene.error().message.c_str());
    return 1;
  }
  quack::Result<quack::SceneWorld> built = quack::buildWorld(*scene);
  if (!built) {
    std::fprintf(stderr, "%s\n", built.error().message.c_str());
    return 1;
  }
  const long steps = std::strtol(argv[2], nullptr, 10);
  for (long i = 0; i < steps; ++i) {
    quack::Status s = built->world.step();
    if (!s) {
      std::fprintf(stderr, "step %ld: %s\n", i, s.message().c_str());
      return 1;
    }
  }
  std::printf("%llu\n", static_cast<unsigned long long>(built->world.stateHash()));
  return 0;
}
