// The 3D page's preset shapes, in the 3D shape JSON of `quack query` (docs/3d.md).
export const PRESETS3 = {
  box: { type: 'box', half: [0.6, 0.4, 0.5] },
  sphere: { type: 'sphere', radius: 0.6 },
  // An irregular convex hull of nine points (one of them inside, dropped by quickhull).
  hull: {
    type: 'hull',
    points: [[0.7, 0, 0], [-0.5, 0.5, 0.1], [-0.4, -0.6, 0.2], [0.1, 0.2, 0.8], [0.2, -0.1, -0.7],
      [0.4, 0.6, -0.3], [-0.3, 0.1, -0.5], [0.5, -0.5, 0.4], [0, 0, 0]],
  },
  capsule: { type: 'capsule', p1: [0, -0.5, 0], p2: [0, 0.5, 0], radius: 0.3 },
  // A box rounded by 0.15: the points within 0.15 of its core.
  'rounded box': { type: 'box', half: [0.45, 0.25, 0.35], radius: 0.15 },
  tetrahedron: { type: 'hull', points: [[0.8, 0, -0.4], [-0.6, 0.6, -0.4], [-0.4, -0.7, -0.4], [0, 0, 0.8]] },
  triangle: { type: 'triangle', points: [[-0.8, -0.5, 0], [0.8, -0.4, 0.1], [0, 0.7, -0.1]] },
};
