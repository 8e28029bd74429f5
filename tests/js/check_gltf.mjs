// Checks a glTF written by bk_mesh_tree_save_gltf with third-party readers:
// Khronos's glTF validator (any error fails; warnings are printed) and
// three.js's GLTFLoader run in node, which must give the expected hierarchy
// and counts, the object drawn once (the triangles three.js would draw are
// the fragments', not every level's on top of each other), every node's
// world position at its centre of mass (from the node records), and
// materials named <material> and <material>_interior.
//
//   node tests/js/check_gltf.mjs FILE.glb|FILE.gltf --nodes N --leaves L --meshes M --materials K
//        --triangles T [--material NAME[,NAME...]] [--textures T] [--tree 0|1] [--meshopt 0|1]
//
// --triangles: the triangles of every mesh in the scene (what a renderer draws);
// --material: each NAME and NAME_interior must be among the materials;
// --textures: how many materials have a base-colour texture three.js loaded;
// --tree 0: the file was written without the embedded mesh tree;
// --meshopt 1: its vertices are compressed (EXT_meshopt_compression, required),
// which three.js decodes with its MeshoptDecoder (WebAssembly, in node too).
//
// Textures: node has no image decoder, so createImageBitmap is stubbed (it
// checks the PNG or JPEG signature of the bytes and returns a 1x1 bitmap), and
// fetch reads file: URLs from disk: a texture that is missing or not an image
// fails the check. Installed by scripts/setup.sh (npm ci --prefix tests/js).
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL, fileURLToPath } from 'node:url';
import validator from 'gltf-validator';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/examples/jsm/libs/meshopt_decoder.module.js';
import * as THREE from 'three';

function fail(message) {
  console.error(`check_gltf: ${message}`);
  process.exit(1);
}

const args = process.argv.slice(2);
if (args.length < 1) fail('usage: check_gltf.mjs FILE --nodes N --leaves L --meshes M --materials K');
const file = path.resolve(args[0]);
const expect = { material: 'surface', textures: 0, tree: 1, meshopt: 0 };
for (let i = 1; i < args.length; i += 2) {
  const key = args[i].replace(/^--/, '');
  if (i + 1 >= args.length) fail(`${args[i]} needs a value`);
  expect[key] = key === 'material' ? args[i + 1] : Number(args[i + 1]);
}
for (const key of ['nodes', 'leaves', 'meshes', 'materials', 'triangles'])
  if (!Number.isInteger(expect[key])) fail(`--${key} N is required`);

const bytes = fs.readFileSync(file);
const name = path.basename(file);

// ---------------------------------------------------------------- Khronos validator
const report = await validator.validateBytes(new Uint8Array(bytes), {
  uri: name,
  maxIssues: 0,
  externalResourceFunction: (uri) =>
    new Promise((resolve, reject) => {
      const target = path.resolve(path.dirname(file), decodeURIComponent(uri));
      fs.readFile(target, (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
    }),
});
const issues = report.issues;
for (const m of issues.messages)
  if (m.severity <= 1)
    console.log(`${name}: validator ${m.severity === 0 ? 'error' : 'warning'} ${m.code} at ${m.pointer}: ${m.message}`);
const infoCodes = {};
for (const m of issues.messages) if (m.severity >= 2) infoCodes[m.code] = (infoCodes[m.code] || 0) + 1;
console.log(
  `${name}: validator: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos, ` +
    `${issues.numHints} hints` +
    (Object.keys(infoCodes).length ? ` (${Object.entries(infoCodes).map(([c, n]) => `${c} x${n}`).join(', ')})` : ''),
);
if (issues.numErrors > 0) fail(`${name}: the glTF validator reports ${issues.numErrors} errors`);

// ---------------------------------------------------------------- three.js
const realFetch = globalThis.fetch;
globalThis.fetch = async (input, init) => {
  const url = typeof input === 'string' ? input : input.url;
  if (url.startsWith('file:')) {
    const data = fs.readFileSync(fileURLToPath(url));
    return new Response(data, { status: 200 });
  }
  return realFetch(input, init);
};
globalThis.createImageBitmap = async (blob) => {
  const head = new Uint8Array(await blob.arrayBuffer()).slice(0, 4);
  const png = head[0] === 0x89 && head[1] === 0x50 && head[2] === 0x4e && head[3] === 0x47;
  const jpeg = head[0] === 0xff && head[1] === 0xd8;
  if (!png && !jpeg) throw new Error('not a PNG or JPEG image');
  return { width: 1, height: 1, close() {} };
};
globalThis.self = globalThis; // GLTFLoader's image path looks at self.URL
// three's FileLoader (the .gltf's data URI) reports progress with a DOM event.
globalThis.ProgressEvent ??= class ProgressEvent {
  constructor(type, init = {}) {
    Object.assign(this, init);
    this.type = type;
  }
};

const loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);
const arrayBuffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const baseUrl = pathToFileURL(path.dirname(file) + path.sep).href;
const gltf = await new Promise((resolve, reject) => loader.parse(arrayBuffer, baseUrl, resolve, reject)).catch(
  (error) => fail(`${name}: three.js GLTFLoader: ${error && error.message ? error.message : error}`),
);

const required = gltf.parser.json.extensionsRequired || [];
if (required.includes('EXT_meshopt_compression') !== (expect.meshopt === 1))
  fail(`${name}: EXT_meshopt_compression is ${required.length ? 'required' : 'not required'}, expected --meshopt ${expect.meshopt}`);
const scene = gltf.scene;
scene.updateMatrixWorld(true);
const ours = gltf.asset.extras && gltf.asset.extras.breakables;
if (!ours) fail(`${name}: three.js sees no asset.extras.breakables`);
const origin = ours.origin;
if (('mtree' in ours) !== (expect.tree === 1))
  fail(`${name}: the embedded mesh tree is ${'mtree' in ours ? 'there' : 'missing'}, expected --tree ${expect.tree}`);

// Our records (docs/gltf.md): per tree node f64 moments[10], f64 bounds[6],
// u32 parent, leaf_begin, leaf_end, depth; per bond u32 leaf_a, leaf_b, f64
// area, centroid[3], normal[3]; little-endian.
async function records(key, stride) {
  const r = ours[key];
  if (!r || r.byteStride !== stride) fail(`${name}: asset.extras.breakables.${key} is not {count, byteStride: ${stride}}`);
  if (r.count === 0) return new DataView(new ArrayBuffer(0));
  const view = await gltf.parser.getDependency('bufferView', r.bufferView);
  if (view.byteLength !== r.count * stride) fail(`${name}: ${key} view holds ${view.byteLength} bytes, not ${r.count} x ${stride}`);
  return new DataView(view);
}
const nodeRecords = await records('nodes', 144);
const bondRecords = await records('bonds', 64);
if (ours.nodes.count !== ours.node_count) fail(`${name}: ${ours.nodes.count} node records for ${ours.node_count} nodes`);
const moments = (node) => [...Array(10).keys()].map((k) => nodeRecords.getFloat64(node * 144 + 8 * k, true));
const bounds = (node) => [...Array(6).keys()].map((k) => nodeRecords.getFloat64(node * 144 + 80 + 8 * k, true));
for (let b = 0; b < ours.bonds.count; b++) {
  const a = bondRecords.getUint32(64 * b, true), c = bondRecords.getUint32(64 * b + 4, true);
  const n = [0, 1, 2].map((k) => bondRecords.getFloat64(64 * b + 40 + 8 * k, true));
  if (!(a < c && c < ours.leaf_count) || !(bondRecords.getFloat64(64 * b + 8, true) > 0) ||
      Math.abs(Math.hypot(...n) - 1) > 1e-9)
    fail(`${name}: bond ${b} (leaves ${a}, ${c}) is not a bond of two fragments with an area and a unit normal`);
}

// Nodes are the objects that carry our extras (a node whose mesh has two
// primitives becomes a Group of two Meshes in three.js).
const nodes = [];
scene.traverse((o) => {
  if (o.userData && o.userData.breakables) nodes.push(o);
});
const leaves = nodes.filter((o) => /^fragment_\d+$/.test(o.name));
const meshes = new Set();
const materials = new Set();
let textured = 0;
const texturedMaterials = new Set();
let primitives = 0;
let triangles = 0;
scene.traverse((o) => {
  if (!o.isMesh) return;
  primitives++;
  if (o.visible) triangles += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3;
  materials.add(o.material.name);
  if (o.material.map) {
    textured++;
    texturedMaterials.add(o.material.name);
  }
  meshes.add(o.parent && o.parent.userData.breakables && !o.userData.breakables ? o.parent : o);
  const g = o.geometry;
  for (const attr of ['position', 'normal', 'uv', 'tangent'])
    if (!g.attributes[attr]) fail(`${name}: ${o.name} has no ${attr} attribute`);
});

const counts = { nodes: nodes.length, leaves: leaves.length, meshes: meshes.size, materials: materials.size, triangles };
for (const key of ['nodes', 'leaves', 'meshes', 'materials', 'triangles'])
  if (counts[key] !== expect[key]) fail(`${name}: three.js loads ${counts[key]} ${key}, expected ${expect[key]}`);
for (const base of expect.material.split(','))
  for (const m of [base, `${base}_interior`])
    if (!materials.has(m)) fail(`${name}: no material named ${m} (have ${[...materials].join(', ')})`);
if (texturedMaterials.size !== expect.textures)
  fail(`${name}: ${texturedMaterials.size} materials have their texture, expected ${expect.textures}`);

// Hierarchy: each node's nearest node ancestor covers its leaves, and an
// inner node's children's volumes add up to its own.
const byIndex = new Map(nodes.map((o) => [o.userData.breakables.node, o]));
for (const o of nodes) {
  const b = o.userData.breakables;
  let p = o.parent;
  while (p && !(p.userData && p.userData.breakables)) p = p.parent;
  if (p) {
    const pb = p.userData.breakables;
    if (b.leaves[0] < pb.leaves[0] || b.leaves[1] > pb.leaves[1])
      fail(`${name}: node ${b.node}'s leaves [${b.leaves}] are outside its parent's [${pb.leaves}]`);
  } else if (ours.levels === 'all' && b.node !== 0) {
    fail(`${name}: node ${b.node} is a root of the scene`);
  }
  const kids = o.children.flatMap((c) => (c.userData.breakables ? [c] : c.children.filter((k) => k.userData.breakables)));
  if (kids.length) {
    const sum = kids.reduce((s, k) => s + k.userData.breakables.volume, 0);
    if (Math.abs(sum - b.volume) > 1e-9 * b.volume) fail(`${name}: node ${b.node}'s children's volumes add to ${sum}, not ${b.volume}`);
  }
  // World position = centre of mass (moments are about the tree's origin).
  const m = moments(b.node);
  if (m[0] !== b.volume) fail(`${name}: node ${b.node}'s record has volume ${m[0]}, its extras ${b.volume}`);
  const box = bounds(b.node);
  const centroid = [origin[0] + m[1] / m[0], origin[1] + m[2] / m[0], origin[2] + m[3] / m[0]];
  const world = new THREE.Vector3().setFromMatrixPosition(o.matrixWorld);
  const size = Math.max(...[0, 1, 2].map((k) => box[k + 3] - box[k]));
  const d = Math.hypot(world.x - centroid[0], world.y - centroid[1], world.z - centroid[2]);
  if (!(d <= 1e-5 * Math.max(size, 1e-30) + 1e-6 * Math.hypot(...centroid)))
    fail(`${name}: node ${b.node} sits at ${world.toArray()} in three.js, its centre of mass is ${centroid}`);
}
if (byIndex.size !== nodes.length) fail(`${name}: node indices in the extras are not unique`);
console.log(
  `${name}: three.js: ${counts.nodes} nodes, ${counts.leaves} leaves, ${counts.meshes} meshes ` +
    `(${primitives} primitives, ${triangles} triangles drawn), ${ours.bonds.count} bonds, materials ${[...materials].sort().join(', ')}, ${textured} textured: ok`,
);
