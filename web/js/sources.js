// What gets fractured: a built-in shape, the bunny's OBJ (fetched from the
// built folder), or a dropped .obj / .glb. Sources are plain data so they can
// be posted to the fracture worker.
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import * as THREE from 'three';

let bunnyBytes = null;

export async function builtinSource(mesh) {
  if (mesh !== 'bunny') return { shape: mesh };
  if (!bunnyBytes) {
    const response = await fetch('assets/bunny.obj');
    if (!response.ok) throw new Error(`assets/bunny.obj: HTTP ${response.status}`);
    bunnyBytes = new Uint8Array(await response.arrayBuffer());
  }
  // bunny: scaled to unit height as the command line's built-in bunny.
  return { obj: bunnyBytes.slice(), name: 'bunny.obj', bunny: true };
}

// A dropped file's bytes as a fracture source: an OBJ as it is, a glTF
// binary as one mesh of every triangle in world space (merged).
export async function fileSource(name, bytes) {
  const lower = name.toLowerCase();
  if (lower.endsWith('.obj')) return { obj: bytes, name };
  if (lower.endsWith('.glb')) return { mesh: await glbMesh(bytes), name };
  throw new Error(`${name}: expected an .obj or .glb file`);
}

async function glbMesh(bytes) {
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const gltf = await new Promise((resolve, reject) =>
    new GLTFLoader().parse(buffer, '', resolve, (e) => reject(new Error(`glTF: ${e.message ?? e}`))));
  gltf.scene.updateMatrixWorld(true);
  // glTF splits a vertex wherever its normal or uv changes: the fracture
  // needs a closed surface, so corners at the same place become one vertex.
  const positions = [], indices = [], welded = new Map();
  const v = new THREE.Vector3();
  const vertex = (x, y, z) => {
    const key = `${x},${y},${z}`;
    let i = welded.get(key);
    if (i === undefined) {
      i = positions.length / 3;
      welded.set(key, i);
      positions.push(x, y, z);
    }
    return i;
  };
  gltf.scene.traverse((object) => {
    if (!object.isMesh || !object.geometry.attributes.position) return;
    const g = object.geometry, p = g.attributes.position, map = new Uint32Array(p.count);
    for (let i = 0; i < p.count; i++) {
      v.fromBufferAttribute(p, i).applyMatrix4(object.matrixWorld);
      map[i] = vertex(Math.fround(v.x), Math.fround(v.y), Math.fround(v.z));
    }
    // A mirrored node flips its triangles: keep them facing out.
    const flip = object.matrixWorld.determinant() < 0;
    const index = g.index ? g.index.array : Array.from({ length: p.count }, (_, i) => i);
    for (let t = 0; t + 2 < index.length; t += 3) {
      const a = map[index[t]], b = map[index[t + 1]], c = map[index[t + 2]];
      if (a === b || b === c || a === c) continue; // collapsed by the welding
      if (flip) indices.push(a, c, b);
      else indices.push(a, b, c);
    }
  });
  if (!indices.length) throw new Error('glTF: no triangle mesh in the file');
  return { positions: new Float32Array(positions), indices: new Uint32Array(indices) };
}
