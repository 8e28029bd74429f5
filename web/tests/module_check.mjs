// Checks the WebAssembly build of the libraries under node, without a
// browser: its trees are the native build's bytes (tests/tree_hashes.txt,
// and `breakables fracture --json` when a native build is given), trees
// round-trip through .mtree bytes, the .glb export is a glTF file, bad input
// is refused in one line, and the runtime breaks and splits a wall as its
// parameters say. Prints the fracture times for the note.
//   node --no-experimental-fetch web/tests/module_check.mjs web/dist [--native build/breakables]
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';

const args = process.argv.slice(2);
const dist = path.resolve(args[0] || 'web/dist');
const nativeAt = args.indexOf('--native');
const native = nativeAt >= 0 ? args[nativeAt + 1] : null;
const root = path.resolve(path.dirname(new URL(import.meta.url).pathname), '../..');

// emscripten 3.1.6's ES module output looks for these under node.
globalThis.require = createRequire(import.meta.url);
globalThis.__dirname = path.join(dist, 'wasm');

let failures = 0;
function check(ok, what) {
  if (!ok) {
    console.error(`module_check: FAILED: ${what}`);
    failures++;
  }
}

const { loadBreakables } = await import(path.join(dist, 'js/breakables.js'));
const bk = await loadBreakables({ wasmBinary: readFileSync(path.join(dist, 'wasm/breakables_web.wasm')) });
const bunnyObj = readFileSync(path.join(root, 'assets/meshes/bunny.obj'));

// The committed tree hashes (the ones without noise: the module takes no cap noise).
const lines = readFileSync(path.join(root, 'tests/tree_hashes.txt'), 'utf8').split('\n');
let compared = 0;
for (const line of lines) {
  const m = /^([0-9a-f]{16}) (.*)$/.exec(line);
  if (!m || line.includes('--noise')) continue;
  const opts = {};
  const words = m[2].split(' ');
  for (let i = 0; i < words.length; i += 2) opts[words[i].slice(2)] = words[i + 1];
  const source = opts.mesh === 'bunny' ? { obj: bunnyObj, name: 'bunny.obj', bunny: true } : { shape: opts.mesh };
  const tree = bk.fracture(source, { pieces: Number(opts.pieces), pattern: opts.pattern, seed: Number(opts.seed) });
  console.log(`${m[2]}: ${tree.hash} (${tree.buildMs.toFixed(0)} ms in WebAssembly)`);
  check(tree.hash === m[1], `${m[2]}: tree_hash ${tree.hash}, tests/tree_hashes.txt has ${m[1]}`);
  compared++;
  tree.free();
}
check(compared >= 3, `only ${compared} trees compared`);

// The bunny against a native build's fracture, and both times.
const bunny = bk.fracture({ obj: bunnyObj, name: 'bunny.obj', bunny: true }, { pieces: 256, seed: 3000 });
if (native) {
  const out = JSON.parse(execFileSync(native, ['fracture', '--mesh', 'bunny', '--pieces', '256', '--seed', '3000',
    '--json'], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] }));
  check(out.tree_hash === bunny.hash, `bunny 256: WebAssembly ${bunny.hash}, native ${out.tree_hash}`);
  console.log(`bunny 256: native ${out.ms.toFixed(0)} ms, WebAssembly ${bunny.buildMs.toFixed(0)} ms ` +
    `(${(bunny.buildMs / out.ms).toFixed(2)}x)`);
}

// Bytes round trip; the glb export is a binary glTF of its stated length.
const bytes = bunny.bytes();
const again = bk.loadTree(bytes);
check(again.hash === bunny.hash && again.leafCount === 256, `loaded tree: ${again.hash}, ${again.leafCount} leaves`);
const glb = bunny.glb();
const view = new DataView(glb.buffer, glb.byteOffset, glb.byteLength);
check(glb.length > 1000 && view.getUint32(0, true) === 0x46546c67 && view.getUint32(8, true) === glb.length,
  `glb: ${glb.length} bytes, magic ${view.getUint32(0, true).toString(16)}`);
const fromGlb = bk.loadGlb(glb);
check(fromGlb.hash === bunny.hash, `the tree read back from the .glb: ${fromGlb.hash}, not ${bunny.hash}`);
fromGlb.free();
const mesh = bunny.nodeMesh(bunny.leafNode(0));
check(mesh.indices.length % 3 === 0 && mesh.positions.length === mesh.normals.length && mesh.indices.length > 0,
  'a leaf mesh has whole triangles and a normal per position');
check(mesh.indices.every((i) => 3 * i < mesh.positions.length), 'a leaf mesh indexes its own positions');
check(bunny.nodeHull(0).length > 0, 'the root has hull points');
again.free();

// Bad input: one line naming the problem, nothing built.
function refused(fn, pattern, what) {
  try {
    fn();
    check(false, `${what}: accepted`);
  } catch (e) {
    check(pattern.test(e.message) && !e.message.includes('\n'), `${what}: "${e.message}"`);
  }
}
refused(() => bk.fracture({ obj: new TextEncoder().encode('v 1 2\nf 1 2 3\n'), name: 'bad.obj' }), /bad\.obj/,
  'a broken OBJ');
refused(() => bk.fracture({ shape: 'teapot' }), /unknown shape 'teapot'/, 'an unknown shape');
refused(() => bk.fracture({ shape: 'cube' }, { pieces: 1000000 }), /1000000 pieces would need about \d+ MiB/,
  'a fracture beyond the module\'s memory');
refused(() => bk.fracture({ shape: 'cube' }, { pattern: 'stars' }), /unknown pattern 'stars'/, 'an unknown pattern');
refused(() => bk.loadTree(bytes.slice(0, 100)), /tree/, 'a cut .mtree');
refused(() => bk.loadGlb(glb.slice(0, glb.length - 9)), /glb/, 'a cut .glb');
refused(() => bk.fracture({ mesh: { positions: [0, 0, 0, 1, 0, 0, NaN, 1, 0, 0, 0, 1], indices: [0, 1, 2, 0, 2, 3,
  0, 3, 1, 1, 3, 2] }, name: 'nan' }), /nan: position 2 is not a finite number/, 'a NaN position');

// The runtime: a hit breaks bonds and splits the wall; frailty 0 breaks none.
function hitWall(frailty) {
  const wall = bk.fracture({ shape: 'wall' }, { pieces: 64, pattern: 'voronoi', seed: 3000 });
  const rt = bk.createRuntime({ gravity: [0, -9.81, 0] });
  rt.setBodyState(() => null); // every body where it started, at rest
  const b = rt.addBreakable(wall, { material: 'stone', anchored: true });
  const first = rt.events();
  rt.clearEvents();
  rt.setFrailty(b, frailty);
  const box = wall.bounds();
  rt.damageAt([(box.min[0] + box.max[0]) / 2, (box.min[1] + box.max[1]) / 2, box.max[2]], 400);
  rt.split();
  const ev = rt.events();
  const result = { first, ev, hash: rt.stateHash(), stats: rt.stats() };
  rt.destroy();
  wall.free();
  return result;
}
const hit = hitWall(1);
check(hit.first.created.length === 1 && hit.first.created[0].leaves.length === 64, 'the wall starts as one cluster');
check(hit.ev.broken.length > 0 && hit.ev.created.length > 1 && hit.ev.removed.length === 1,
  `a hit: ${hit.ev.broken.length} bonds broken, ${hit.ev.created.length} clusters made`);
const leaves = hit.ev.created.reduce((n, c) => n + c.leaves.length, 0);
check(leaves === 64, `the new clusters hold ${leaves} fragments, not 64`);
check(hit.ev.created.every((c) => c.nodes.length >= 1 && c.nodes.length <= c.leaves.length && c.mass > 0),
  'each new cluster has a node set no larger than its fragments and a mass');
const unbreakable = hitWall(0);
check(unbreakable.ev.broken.length === 0, `frailty 0 broke ${unbreakable.ev.broken.length} bonds`);
check(hitWall(1).hash === hit.hash, 'the same calls give the same state hash');
console.log(`wall 64 hit: ${hit.ev.broken.length} bonds broken, ${hit.ev.created.length} clusters, state ${hit.hash}`);

if (failures) {
  console.error(`module_check: ${failures} check(s) failed`);
  process.exit(1);
}
console.log('module_check: ok');
