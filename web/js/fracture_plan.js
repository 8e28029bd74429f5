// A fracture as the game's scenes make it (scene_fracture_def): the radial
// pattern centred where the shot line from the eye through the aim point
// meets the object's surface. Used on the main thread and in the worker.
import { firstHit } from './impact.js';

// aim: {eye, target, position} in the world (the object unrotated at position), or null.
// Returns the tree, the library's own build time (tree.buildMs: what
// `breakables fracture --json` reports as ms) and the whole call's time
// (reading the source, hashing, handing the tree over; the aim's probe not
// counted), both in ms.
export function fracture(bk, source, options, aim) {
  const opts = { ...options };
  if (opts.pattern === 'radial' && aim && !opts.impact) opts.impact = impactOf(bk, source, aim);
  const start = performance.now();
  const tree = bk.fracture(source, opts);
  return { tree, ms: tree.buildMs, callMs: performance.now() - start };
}

function impactOf(bk, source, { eye, target, position }) {
  const toTree = (v) => [v[0] - position[0], v[1] - position[1], v[2] - position[2]];
  const from = toTree(eye), aim = toTree(target);
  // The tree's root is the source mesh as the fracture sees it (an OBJ
  // bunny already scaled): a one-piece fracture makes it and cuts nothing.
  const probe = bk.fracture(source, { pieces: 1, pattern: 'planes' });
  try {
    const root = probe.nodeMesh(0);
    const direction = [aim[0] - from[0], aim[1] - from[1], aim[2] - from[2]];
    return firstHit(root, from, direction) ?? aim;
  } finally {
    probe.free();
  }
}
