// Replays the cuts of a planes-pattern mesh tree with Manifold's WASM build
// (npm package manifold-3d) and times them, for scripts/manifold_compare.sh.
//
//   node tests/js/manifold_cuts.mjs FILE.mtree [--ours-ms MS] [--runs N] [--check K] [--op split|trim]
//
// FILE.mtree is `breakables fracture --mesh cube --out FILE.mtree` (format
// version 4, see src/fracture/tree_cache.c). Its root must be bk_shape's
// CUBE, [-0.5, 0.5]^3, which Manifold builds as Manifold.cube([1, 1, 1], true).
// Then, for every inner node in node order (a parent always comes before its
// children), that node's manifold is split by the node's plane
// (n . x = offset, unit n, world coordinates) with splitByPlane(n, offset):
// its first result lies on the +n side, so it is the tree's "above" piece, its
// second the "below" piece, and the tree lists the pieces below the plane
// first (mesh_tree.c, cut_node). A cube's pieces are all convex, so every
// cut makes exactly two (a concave source's cut can make more; those trees
// are refused). Only the splitting is timed (`--runs` runs,
// 3 by default, in one process; the median is reported); each run starts
// from a fresh cube and keeps every intermediate piece, as the tree does.
// `--op trim` makes each cut with two trimByPlane calls instead (below:
// trimByPlane(-n, -offset), above: trimByPlane(n, offset)), two Booleans per
// cut where splitByPlane makes one.
//
// Checks, after the first run: the leaf count, and every leaf's volume and
// bounds against ours (our leaf volume is the node's first moment, v):
// volumes within 1e-6 relative, each leaf and their sum. `--check K` checks
// only K leaves spread over the tree (default: all of them).
//
// Prints one JSON line: manifold_ms (median), manifold_runs_ms, ours_ms
// (--ours-ms or the environment variable BK_OURS_MS, else null), ratio
// (manifold_ms / ours_ms), leaf counts, triangle counts and the checks.
// Exits 1 when a check fails.
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import Module from 'manifold-3d';

function fail(message) {
  console.error(`manifold_cuts: ${message}`);
  process.exit(1);
}

// ---------------------------------------------------------------- arguments

const args = process.argv.slice(2);
let file = null;
let oursMs = process.env.BK_OURS_MS ? Number(process.env.BK_OURS_MS) : null;
let runs = 3;
let checkCount = 0; // 0: every leaf
let op = 'split';
for (let i = 0; i < args.length; ++i) {
  const a = args[i];
  const value = () => {
    if (i + 1 >= args.length) fail(`${a} needs a value`);
    return args[++i];
  };
  if (a === '--ours-ms') oursMs = Number(value());
  else if (a === '--runs') runs = Number(value());
  else if (a === '--check') checkCount = Number(value());
  else if (a === '--op') op = value();
  else if (a.startsWith('--')) fail(`unknown option ${a}`);
  else if (file === null) file = a;
  else fail(`unexpected argument ${a}`);
}
if (file === null) fail('usage: manifold_cuts.mjs FILE.mtree [--ours-ms MS] [--runs N] [--check K] [--op split|trim]');
if (oursMs !== null && !(oursMs > 0)) fail('--ours-ms (or BK_OURS_MS) must be a positive number');
if (!(Number.isInteger(runs) && runs >= 1)) fail('--runs must be a positive integer');
if (!(Number.isInteger(checkCount) && checkCount >= 0)) fail('--check must be a non-negative integer');
if (op !== 'split' && op !== 'trim') fail('--op must be split or trim');

// ---------------------------------------------------------------- the .mtree

const MTREE_VERSION = 4;
const HEADER_BYTES = 32;
const NULL_INDEX = 0xffffffff;

// Reads what the replay needs from a version-4 .mtree: per node its bounds,
// volume, split plane, tree links, triangle count and positions (for the
// side check); the rest of each mesh is skipped.
function readTree(filePath) {
  const buf = fs.readFileSync(filePath);
  if (buf.length < HEADER_BYTES || buf.toString('latin1', 0, 8) !== 'BKMTREE\0')
    fail(`${filePath}: not an .mtree file`);
  const version = buf.readUInt32LE(8);
  if (version !== MTREE_VERSION) fail(`${filePath}: format version ${version}, this reads ${MTREE_VERSION}`);
  if (buf.readUInt32LE(12) !== 0x01020304) fail(`${filePath}: bad byte-order marker`);
  const payloadSize = Number(buf.readBigUInt64LE(16));
  if (HEADER_BYTES + payloadSize !== buf.length)
    fail(`${filePath}: payload of ${payloadSize} bytes in a file of ${buf.length}`);
  let pos = HEADER_BYTES;
  const need = (n) => {
    if (pos + n > buf.length) fail(`${filePath}: payload ends early (at byte ${pos})`);
  };
  const u32 = () => (need(4), (pos += 4), buf.readUInt32LE(pos - 4));
  const u64 = () => (need(8), (pos += 8), buf.readBigUInt64LE(pos - 8));
  const f64 = () => (need(8), (pos += 8), buf.readDoubleLE(pos - 8));
  const vec3 = () => [f64(), f64(), f64()];
  const skip = (n) => (need(n), (pos += n));

  // The fracture def: source_hash, pieces, seed, texture_scale, jitter,
  // aspect_bias, pattern, seed_point_count, clusters, cluster_border,
  // impact[3], radial_falloff, brick_size[3], brick_origin[3], brick_offset,
  // cutout_width/height/axis, noise_amplitude, noise_frequency.
  u64();
  const pieces = u32();
  const seed = u64();
  skip(3 * 8);
  const pattern = u32();
  skip(2 * 4 + 8 + 3 * 8 + 8 + 3 * 8 + 3 * 8 + 8 + 3 * 4 + 2 * 8);
  const maxDepth = u32();
  const nodeCount = u32();
  const leafCount = u32();
  u32(); // bond count
  const nodes = new Array(nodeCount);
  for (let i = 0; i < nodeCount; ++i) {
    const min = vec3();
    const max = vec3();
    const volume = f64();
    skip(9 * 8); // the other moments
    const normal = vec3();
    const offset = f64();
    const parent = u32();
    const firstChild = u32();
    const childCount = u32();
    skip(3 * 4); // leaf_begin, leaf_end, depth
    const positionCount = u32();
    const cornerCount = u32();
    const triangleCount = u32();
    need(positionCount * 24);
    const positions = new Float64Array(3 * positionCount);
    for (let k = 0; k < 3 * positionCount; ++k) positions[k] = buf.readDoubleLE(pos + 8 * k);
    pos += positionCount * 24;
    skip(cornerCount * (4 + 9 * 4) + triangleCount * (3 * 4 + 1 + 4));
    nodes[i] = { min, max, volume, normal, offset, parent, firstChild, childCount, triangleCount, positions };
  }
  if (pos + 4 * leafCount > buf.length) fail(`${filePath}: payload ends before the leaf list`);
  const leaves = [];
  for (let l = 0; l < leafCount; ++l) leaves.push(buf.readUInt32LE(pos + 4 * l));
  return { pieces, seed: seed.toString(), pattern, maxDepth, nodes, leaves };
}

const tree = readTree(path.resolve(file));
const { nodes } = tree;

// The source must be the CUBE of src/geom/shapes.c: [-0.5, 0.5]^3, volume 1.
{
  const root = nodes[0];
  const exact = [0, 1, 2].every((k) => root.min[k] === -0.5 && root.max[k] === 0.5);
  if (!exact || Math.abs(root.volume - 1) > 1e-12)
    fail(`the root is not bk_shape's cube [-0.5, 0.5]^3 (bounds ${root.min} to ${root.max}, volume ${root.volume})`);
}

// Does each two-piece cut list its piece below the plane first? (Every
// position of the first child at most, of the second at least, the offset,
// within the slicer's tolerance, 1e-9 of the node's diagonal.)
const inner = [];
let sideViolations = 0;
for (let i = 0; i < nodes.length; ++i) {
  const n = nodes[i];
  if (n.childCount === 0) continue;
  inner.push(i);
  if (n.childCount !== 2) fail(`node ${i} was cut into ${n.childCount} pieces: only two-piece cuts are replayed`);
  const diag = Math.hypot(n.max[0] - n.min[0], n.max[1] - n.min[1], n.max[2] - n.min[2]);
  const tol = 1e-9 * diag;
  for (let c = 0; c < 2; ++c) {
    const p = nodes[n.firstChild + c].positions;
    for (let k = 0; k < p.length; k += 3) {
      const d = n.normal[0] * p[k] + n.normal[1] * p[k + 1] + n.normal[2] * p[k + 2] - n.offset;
      if (c === 0 ? d > tol : d < -tol) {
        ++sideViolations;
        break;
      }
    }
  }
}

// ---------------------------------------------------------------- Manifold

const here = path.dirname(fileURLToPath(import.meta.url));
const manifoldVersion = JSON.parse(
  fs.readFileSync(path.join(here, 'node_modules', 'manifold-3d', 'package.json'), 'utf8'),
).version;
const wasm = await Module();
wasm.setup();
const { Manifold } = wasm;

// One replay of every cut; returns the milliseconds and the pieces (one
// manifold per node).
function replay() {
  const out = new Array(nodes.length).fill(null);
  const start = performance.now();
  out[0] = Manifold.cube([1, 1, 1], true);
  for (const i of inner) {
    const n = nodes[i];
    const m = out[i];
    let above, below;
    if (op === 'split') [above, below] = m.splitByPlane(n.normal, n.offset);
    else {
      below = m.trimByPlane([-n.normal[0], -n.normal[1], -n.normal[2]], -n.offset);
      above = m.trimByPlane(n.normal, n.offset);
    }
    // Forces evaluation, should a result be lazy (it is cheap once evaluated).
    below.numTri();
    above.numTri();
    out[n.firstChild] = below;
    out[n.firstChild + 1] = above;
  }
  const ms = performance.now() - start;
  return { ms, out };
}

function freeAll(out) {
  for (const m of out) if (m !== null) m.delete();
}

// ---------------------------------------------------------------- run and check

const times = [];
let check = null;
for (let r = 0; r < runs; ++r) {
  const { ms, out } = replay();
  times.push(ms);
  if (r === 0) {
    const leaves = tree.leaves;
    let made = 0;
    let manifoldTriangles = 0;
    let ourTriangles = 0;
    let emptyLeaves = 0;
    for (const l of leaves) {
      ourTriangles += nodes[l].triangleCount;
      const m = out[l];
      if (m === null || m.isEmpty()) ++emptyLeaves;
      else {
        ++made;
        manifoldTriangles += m.numTri();
      }
    }
    // Leaves checked: all, or checkCount spread evenly over the leaf list.
    const checked =
      checkCount === 0 || checkCount >= leaves.length
        ? leaves
        : Array.from({ length: checkCount }, (_, k) => leaves[Math.floor((k * leaves.length) / checkCount)]);
    let worstVolume = 0;
    let worstVolumeLeaf = -1;
    let worstBounds = 0;
    for (const l of checked) {
      const m = out[l];
      if (m === null) continue;
      const ours = nodes[l].volume;
      const rel = Math.abs(m.volume() - ours) / ours;
      if (!(rel <= worstVolume)) {
        worstVolume = rel;
        worstVolumeLeaf = l;
      }
      const box = m.boundingBox();
      for (let k = 0; k < 3; ++k)
        worstBounds = Math.max(
          worstBounds,
          Math.abs(box.min[k] - nodes[l].min[k]),
          Math.abs(box.max[k] - nodes[l].max[k]),
        );
    }
    let ourSum = 0;
    let theirSum = 0;
    for (const l of leaves) {
      ourSum += nodes[l].volume;
      if (out[l] !== null) theirSum += out[l].volume();
    }
    const sumRel = Math.abs(theirSum - ourSum) / ourSum;
    const pass =
      made === leaves.length && emptyLeaves === 0 && worstVolume <= 1e-6 && sumRel <= 1e-6;
    check = {
      leaves_ours: leaves.length,
      leaves_manifold: made,
      empty_leaves: emptyLeaves,
      leaves_checked: checked.length,
      leaf_volume_max_rel_error: worstVolume,
      leaf_volume_max_rel_error_node: worstVolumeLeaf,
      leaf_volume_sum_ours: ourSum,
      leaf_volume_sum_manifold: theirSum,
      leaf_volume_sum_rel_error: sumRel,
      leaf_bounds_max_abs_error: worstBounds,
      leaf_triangles_ours: ourTriangles,
      leaf_triangles_manifold: manifoldTriangles,
      volume_check: pass ? 'pass' : 'fail',
    };
  }
  freeAll(out);
}

const sorted = [...times].sort((a, b) => a - b);
const median = sorted[Math.floor((sorted.length - 1) / 2)];
const round = (x) => Math.round(x * 1000) / 1000;
const result = {
  manifold_version: manifoldVersion,
  op: op === 'split' ? 'splitByPlane' : 'trimByPlane x2',
  node: process.version,
  mtree: file,
  pattern: tree.pattern,
  pieces: tree.pieces,
  seed: tree.seed,
  nodes: nodes.length,
  cuts: inner.length,
  below_first_violations: sideViolations,
  manifold_ms: round(median),
  manifold_runs_ms: times.map(round),
  ours_ms: oursMs,
  ratio: oursMs ? round(median / oursMs) : null,
  ...check,
};
console.log(JSON.stringify(result));
if (check.volume_check !== 'pass' || sideViolations) process.exit(1);
