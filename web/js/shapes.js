// Preset shapes, in the shape JSON of the README ("Formats") and docs/scenes.md: the same
// that `quack query` reads.
// No DOM here, so that the node tests can import it.

const regular = (n, r, phase = 0) =>
  Array.from({ length: n }, (_, i) => {
    const a = phase + (2 * Math.PI * i) / n;
    return [+(r * Math.cos(a)).toFixed(4), +(r * Math.sin(a)).toFixed(4)];
  });

export const PRESETS = {
  'box': { type: 'box', half: [0.9, 0.6] },
  'circle': { type: 'circle', radius: 0.8 },
  'capsule': { type: 'capsule', p1: [-0.8, 0], p2: [0.8, 0], radius: 0.4 },
  'segment': { type: 'segment', p1: [-1.1, -0.3], p2: [1.1, 0.3] },
  'triangle': { type: 'polygon', points: regular(3, 1.0, Math.PI / 2) },
  'pentagon': { type: 'polygon', points: regular(5, 0.9, Math.PI / 2) },
  'rounded box': { type: 'box', half: [0.7, 0.4], radius: 0.25 },
  'rounded hexagon': { type: 'polygon', points: regular(6, 0.7), radius: 0.2 },
  // Concave: cut into convex pieces by the library, as `quack query` and Python do.
  'L (concave)': { type: 'concave', points: [[-0.9, -0.9], [0.9, -0.9], [0.9, -0.3], [-0.3, -0.3], [-0.3, 0.9], [-0.9, 0.9]] },
};
