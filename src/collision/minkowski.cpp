#include "quack/collision/minkowski.hpp"

#include <vector>

namespace quack {

Result<Hull> computeMinkowskiDifference(const ShapeProxy& a, Transform worldFromA,
                                        const ShapeProxy& b, Transform worldFromB) {
  std::vector<Vec2> differences;
  differences.reserve(static_cast<std::size_t>(a.count() * b.count()));
  for (int j = 0; j < b.count(); ++j) {
    Vec2 pb = transformPoint(worldFromB, b.points()[j]);
    for (int i = 0; i < a.count(); ++i) {
      differences.push_back(pb - transformPoint(worldFromA, a.points()[i]));
    }
  }
  Result<Hull> hull = computeHull(differences);
  if (!hull) return fail("Minkowski difference: " + hull.error().message);
  return hull;
}

}  // namespace quack
