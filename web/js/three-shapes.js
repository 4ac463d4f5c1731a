// Quack's 3D shapes as three.js objects, shared by the 3D pages (gjk3d.html and
// sandbox3d.html): a shape's outline (from the glue's outline3Of, in its shape or body frame:
// core points, rounding radius, a hull's or mesh's faces as vertex-index polygons) becomes
// a group of meshes with their edges.
import * as THREE from 'three';
import { ConvexGeometry } from 'three/addons/geometries/ConvexGeometry.js';

// An opaque fill is pushed back a little in depth, so that its edges draw over it whole.
export const material = (color, opacity = 0.5) => new THREE.MeshLambertMaterial({
  color, transparent: opacity < 1, opacity, side: THREE.DoubleSide, depthWrite: opacity >= 1,
  polygonOffset: opacity >= 1, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
});
export const lineMaterial = (color) => new THREE.LineBasicMaterial({ color });

// Triangles (index triples into points) as a mesh (see-through below opacity 1) with its
// edges (drawn in `edges`, the fill colour unless given).
export function triangles(group, points, faces, color, opacity, edges = color) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(points.flat(), 3));
  g.setIndex(faces.flat());
  g.computeVertexNormals();
  group.add(new THREE.Mesh(g, material(color, opacity)));
  group.add(new THREE.LineSegments(new THREE.EdgesGeometry(g, 1), lineMaterial(edges)));
}

/** A shape (outline: core points, radius, a hull's or a mesh's faces) as a group of
 * meshes: see-through at `opacity` (0.5 unless given), edges in `edges` (the fill colour
 * unless given). */
export function shapeObject(outline, color, { opacity = 0.5, edges = color } = {}) {
  const group = new THREE.Group();
  const pts = outline.points;
  if (outline.type === 'sphere') {
    const m = new THREE.Mesh(new THREE.SphereGeometry(outline.radius, 32, 16), material(color, opacity));
    m.position.set(...pts[0]);
    group.add(m);
  } else if (outline.type === 'capsule') {
    const p = new THREE.Vector3(...pts[0]);
    const q = new THREE.Vector3(...pts[1]);
    const axis = q.clone().sub(p);
    const m = new THREE.Mesh(new THREE.CapsuleGeometry(outline.radius, axis.length(), 8, 24), material(color, opacity));
    m.position.copy(p.clone().add(q).multiplyScalar(0.5));
    if (axis.lengthSq() > 0) m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis.normalize());
    group.add(m);
  } else if (outline.type === 'triangle') {
    triangles(group, pts, [[0, 1, 2]], color, opacity, edges);
  } else {
    // A hull (or a mesh): its faces are polygons of vertex indices; fan them into triangles.
    const faces = [];
    for (const f of outline.faces) for (let k = 1; k + 1 < f.length; ++k) faces.push([f[0], f[k], f[k + 1]]);
    if (outline.radius > 0) {
      // Rounded: the core, faint, inside the hull of a ball about each core vertex (that hull
      // is the rounded solid, the core's Minkowski sum with the ball; here each ball is 64
      // points on its sphere, spread by the golden angle).
      triangles(group, pts, faces, color, Math.min(0.2, opacity), edges);
      const around = [];
      for (const p of pts) {
        for (let k = 0; k < 64; ++k) {
          const y = 1 - (2 * k + 1) / 64;
          const s = Math.sqrt(1 - y * y);
          const a = k * Math.PI * (3 - Math.sqrt(5));
          const r = outline.radius;
          around.push(new THREE.Vector3(p[0] + r * s * Math.cos(a), p[1] + r * y, p[2] + r * s * Math.sin(a)));
        }
      }
      group.add(new THREE.Mesh(new ConvexGeometry(around), material(color, opacity)));
    } else {
      triangles(group, pts, faces, color, opacity, edges);
    }
  }
  group.userData.pickable = true;
  return group;
}
