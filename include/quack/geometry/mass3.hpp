#pragma once
/// Mass properties of 3D shapes of uniform density.

#include "quack/geometry/shapes3.hpp"
#include "quack/math/mat3.hpp"

namespace quack {

/// Mass properties of a 3D shape. Shape frame.
struct MassProperties3 {
  float mass = 0.0f;    ///< kg: density times volume
  float volume = 0.0f;  ///< m^3
  Vec3 centroid;        ///< centre of mass, shape frame
  Mat3 inertia;         ///< inertia tensor about `centroid`, shape axes, kg m^2 (symmetric)
};

/// Precondition (asserted): density finite and >= 0, kg/m^3. Closed forms: 4/3 pi r^3 and
/// 2/5 m r^2.
MassProperties3 computeMass(const Sphere& sphere, float density);
/// Exact: a cylinder plus two hemispheres (inertia of each hemisphere about the capsule's
/// centre by the parallel-axis theorem, from its own centre 3r/8 from the flat face).
MassProperties3 computeMass(const Capsule3& capsule, float density);
/// Exact for the polyhedron: a sum over tetrahedra from one vertex to each face's fan of
/// their second moments (the canonical tetrahedron's covariance mapped by each one's
/// affine map; Blow and Binstock, "How to find the inertia tensor (or other mass properties)
/// of a 3D solid body represented by a triangle mesh", 2004), summed in double. A rounded
/// hull (radius r > 0) adds, in closed form and in double, the pieces that tile the
/// rounding: a prism on each face, a cylindrical wedge on each edge (its exterior dihedral
/// angle) and a ball sector on each vertex (its normal cone, whose solid angle is the
/// vertex's angle defect); the volume is Steiner's V + A r + (sum of edge length x exterior
/// angle) r^2 / 2 + 4/3 pi r^3. With r = 0 the answer is the plain polyhedron's, to the bit.
MassProperties3 computeMass(const Hull3& hull, float density);
/// A triangle has no volume: mass, volume and inertia are 0; the centroid is its centroid.
MassProperties3 computeMass(const Triangle3& triangle, float density);
/// Any 3D shape, by its type.
MassProperties3 computeMass(const ShapeGeometry3& geometry, float density);

}  // namespace quack
