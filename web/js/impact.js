// Where a line first meets a mesh (Moller-Trumbore on every triangle, as
// scene_first_hit in src/scenes/scene_fracture.c): a radial pattern is
// centred where the shot lands on the surface, not at the aim point inside.
export function firstHit({ positions: p, indices }, origin, direction) {
  let nearest = Infinity;
  const d = direction;
  for (let t = 0; t < indices.length; t += 3) {
    const a = 3 * indices[t], b = 3 * indices[t + 1], c = 3 * indices[t + 2];
    const e1 = [p[b] - p[a], p[b + 1] - p[a + 1], p[b + 2] - p[a + 2]];
    const e2 = [p[c] - p[a], p[c + 1] - p[a + 1], p[c + 2] - p[a + 2]];
    const q = cross(d, e2), det = dot(e1, q);
    if (Math.abs(det) < 1e-300) continue; // parallel to the triangle
    const s = [origin[0] - p[a], origin[1] - p[a + 1], origin[2] - p[a + 2]], r = cross(s, e1);
    const u = dot(s, q) / det, v = dot(d, r) / det, along = dot(e2, r) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && along > 0 && along < nearest) nearest = along;
  }
  if (!Number.isFinite(nearest)) return null;
  return [origin[0] + d[0] * nearest, origin[1] + d[1] * nearest, origin[2] + d[2] * nearest];
}

const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
