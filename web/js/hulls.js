// Which tree nodes are a cluster's colliders (bk_collider_nodes, as the
// Bullet world chooses them in world_bodies.c): a node of the cluster's node
// set whose convex hull hardly overestimates it (hull volume within 10% of
// the node's) stands for it; otherwise its children do (a hollow egg's hull
// is a solid egg). Leaves always stand for themselves.
const CONVEXITY_TOLERANCE = 0.1; // bk_default_world_breakable_def().convexity_tolerance

export class HullCache {
  constructor(tree, RAPIER) {
    this.tree = tree;
    this.RAPIER = RAPIER;
    this.hulls = new Map(); // node -> Float32Array (tree frame, copied out of wasm memory)
    this.fits = new Map(); // node -> bool
  }

  points(node) {
    let p = this.hulls.get(node);
    if (!p) {
      p = supportPoints(this.tree.nodeHull(node));
      this.hulls.set(node, p);
    }
    return p;
  }

  fitsNode(node) {
    let fits = this.fits.get(node);
    if (fits === undefined) {
      fits = this.tree.isLeaf(node) || hullVolume(this.RAPIER, this.points(node)) <= (1 + CONVEXITY_TOLERANCE) * meshVolume(this.tree.nodeMesh(node));
      this.fits.set(node, fits);
    }
    return fits;
  }
}

// A hull's points: at most the extreme points along 96 fixed directions
// (4 x 4 on each face of a cube), as src/lib/bullet/hull_points.c picks
// them. A piece of the bunny has hundreds of points on its hull; Rapier's
// contacts cost grows with the hull's faces, and this hull lies inside the
// piece's and touches it in every direction. Copied out of wasm memory.
const GRID = 4;
const DIRECTIONS = (() => {
  const out = [];
  for (let index = 0; index < 6 * GRID * GRID; index++) {
    const face = Math.floor(index / (GRID * GRID)), cell = index % (GRID * GRID);
    const a = -1 + (2 * (cell % GRID) + 1) / GRID, b = -1 + (2 * Math.floor(cell / GRID) + 1) / GRID;
    const s = face % 2 ? -1 : 1;
    const d = face >> 1 === 0 ? [s, a, b] : face >> 1 === 1 ? [a, s, b] : [a, b, s];
    const l = Math.hypot(...d);
    out.push(d.map((v) => v / l));
  }
  return out;
})();

function supportPoints(points) {
  const n = points.length / 3;
  if (n <= DIRECTIONS.length) return Float32Array.from(points);
  const chosen = new Set();
  for (const [dx, dy, dz] of DIRECTIONS) {
    let best = 0, bestDot = -Infinity;
    for (let i = 0; i < n; i++) {
      const dot = points[3 * i] * dx + points[3 * i + 1] * dy + points[3 * i + 2] * dz;
      if (dot > bestDot) (bestDot = dot), (best = i);
    }
    chosen.add(best);
  }
  const out = new Float32Array(3 * chosen.size);
  let k = 0;
  for (const i of [...chosen].sort((a, b) => a - b)) out.set(points.subarray(3 * i, 3 * i + 3), 3 * k++);
  return out;
}

export function colliderNodes(tree, cache, nodes) {
  const out = [];
  const visit = (node) => {
    if (cache.fitsNode(node)) out.push(node);
    else for (const child of tree.children(node)) visit(child);
  };
  for (const node of nodes) visit(node);
  return out;
}

// A closed mesh's volume by the divergence theorem.
function meshVolume({ positions: p, indices }) {
  let v = 0;
  for (let t = 0; t < indices.length; t += 3) {
    const a = 3 * indices[t], b = 3 * indices[t + 1], c = 3 * indices[t + 2];
    v += p[a] * (p[b + 1] * p[c + 2] - p[b + 2] * p[c + 1]) - p[a + 1] * (p[b] * p[c + 2] - p[b + 2] * p[c]) +
      p[a + 2] * (p[b] * p[c + 1] - p[b + 1] * p[c]);
  }
  return v / 6;
}

// Rapier computes the hull and its volume: a collider in a world of its own.
let scratch = null;
function hullVolume(RAPIER, points) {
  const desc = RAPIER.ColliderDesc.convexHull(points);
  if (!desc) return Infinity; // too flat for a hull
  scratch ??= new RAPIER.World({ x: 0, y: 0, z: 0 });
  const collider = scratch.createCollider(desc);
  const volume = collider.volume();
  scratch.removeCollider(collider, false);
  return volume;
}
