// A program outside Quack's tree: links quack::quack and checks one hand-worked answer.
#include <cstdio>

#include "quack/geometry/geometry.hpp"

int main() {
  quack::Result<quack::Polygon> box = quack::makeBox(1.0f, 0.5f);
  if (!box) return 1;
  quack::MassProperties m = quack::computeMass(box.value(), 1.0f);
  // A 2 x 1 box has area 2.
  bool ok = m.area > 1.999f && m.area < 2.001f;
  std::printf("consumer: area %g %s\n", static_cast<double>(m.area), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
