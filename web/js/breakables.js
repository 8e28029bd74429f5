// Breakables for JavaScript: the authoring and runtime libraries built to
// WebAssembly (web/CMakeLists.txt, bridge in web/src), wrapped in objects.
// The API is the C one's (include/breakables/*.h) in JavaScript's terms:
// fracture a mesh into a tree, read the tree's meshes in place, run a
// runtime whose bodies your physics engine owns. One instance per thread.
import createBreakablesModule from '../wasm/breakables_web.mjs';

const SHAPES = ['cube', 'torus', 'eggshell', 'wall', 'slab', 'pillar', 'tower', 'bridge', 'balcony'];
const PATTERNS = ['planes', 'voronoi', 'clustered', 'radial', 'brick', 'cutout'];
const CREATED_HEAD = 15; // parent (2), body (13), then a cluster record
const CLUSTER_HEAD = 19;

let nextRuntime = 1;

/** Loads one instance of the module; options go to emscripten (locateFile, ...). */
export async function loadBreakables(options = {}) {
  const runtimes = new Map(); // handle -> Runtime, for the body-state calls from C
  const M = await createBreakablesModule({
    ...options,
    bodyState(handle, index, generation, out) {
      const rt = runtimes.get(handle);
      const s = rt && rt.bodyStateFn ? rt.bodyStateFn(`${index}:${generation}`) : null;
      const d = new Float64Array(M.HEAPF64.buffer, out, 13);
      if (!s) return; // the defaults: identity, at rest
      d.set(s.p, 0);
      d.set(s.q, 3);
      d.set(s.v || [0, 0, 0], 7);
      d.set(s.w || [0, 0, 0], 10);
    },
  });
  const f64 = () => M.HEAPF64;
  const u8 = () => M.HEAPU8;

  function fail() {
    throw new Error(M.UTF8ToString(M._web_last_error()));
  }
  function cString(text) {
    const n = M.lengthBytesUTF8(text) + 1;
    const p = M._web_alloc(n);
    M.stringToUTF8(text, p, n);
    return p;
  }
  function withBytes(bytes, fn) {
    const p = M._web_alloc(bytes.length);
    u8().set(bytes, p);
    try {
      return fn(p, bytes.length);
    } finally {
      M._web_free(p);
    }
  }
  function withDoubles(values, fn) {
    const p = M._web_alloc(values.length * 8 + 8);
    f64().set(values, p >> 3);
    try {
      return fn(p);
    } finally {
      M._web_free(p);
    }
  }
  function takeBytes(fn) {
    const sizeP = M._web_alloc(4);
    try {
      const p = fn(sizeP);
      if (!p) fail();
      const size = M.HEAPU32[sizeP >> 2];
      const out = u8().slice(p, p + size);
      M._web_free(p);
      return out;
    } finally {
      M._web_free(sizeP);
    }
  }
  function patternIndex(pattern) {
    if (pattern === undefined || pattern === null || pattern === '') return -1;
    const i = PATTERNS.indexOf(pattern);
    if (i < 0) throw new Error(`unknown pattern '${pattern}' (known: ${PATTERNS.join(', ')})`);
    return i;
  }

  class Tree {
    constructor(ptr) {
      this.ptr = ptr;
      this.nodeCount = M._web_tree_node_count(ptr);
      this.leafCount = M._web_tree_leaf_count(ptr);
      this.bondCount = M._web_tree_bond_count(ptr);
      this.buildMs = M._web_tree_build_ms(ptr);
      const links = M._web_tree_links(ptr);
      this.links = new Uint32Array(M.HEAPU32.buffer, links, this.nodeCount * 4).slice();
      M._web_free(links);
      const h = M._web_alloc(17);
      if (!M._web_tree_hash(ptr, h)) fail();
      this.hash = M.UTF8ToString(h);
      M._web_free(h);
    }
    leafNode(i) {
      return M.HEAPU32[(M._web_tree_leaf_nodes(this.ptr) >> 2) + i];
    }
    isLeaf(node) {
      return this.links[4 * node + 2] === 0;
    }
    children(node) {
      const first = this.links[4 * node + 1];
      return Array.from({ length: this.links[4 * node + 2] }, (_, k) => first + k);
    }
    parent(node) {
      const p = this.links[4 * node];
      return p === 0xffffffff ? -1 : p;
    }
    bounds() {
      return withDoubles(new Float64Array(6), (p) => {
        M._web_tree_bounds(this.ptr, p);
        const d = f64().subarray(p >> 3, (p >> 3) + 6);
        return { min: [d[0], d[1], d[2]], max: [d[3], d[4], d[5]] };
      });
    }
    /** Views into the module's memory (no copy): use them before the next call that may grow it. */
    nodeMesh(node) {
      const r = new Uint32Array(M.HEAPU32.buffer, M._web_tree_ranges(this.ptr) + 16 * node, 4);
      const [c0, cn, i0, n] = r;
      const buf = M.HEAPU8.buffer;
      return {
        positions: new Float32Array(buf, M._web_tree_positions(this.ptr) + 12 * c0, 3 * cn),
        normals: new Float32Array(buf, M._web_tree_normals(this.ptr) + 12 * c0, 3 * cn),
        indices: new Uint32Array(buf, M._web_tree_indices(this.ptr) + 4 * i0, n),
        inside: new Uint8Array(buf, M._web_tree_inside(this.ptr) + i0 / 3, n / 3),
      };
    }
    /** The node's distinct positions (tree frame): a convex-hull collider's points. */
    nodeHull(node) {
      const r = new Uint32Array(M.HEAPU32.buffer, M._web_tree_hull_ranges(this.ptr) + 8 * node, 2);
      return new Float32Array(M.HEAPU8.buffer, M._web_tree_hull_points(this.ptr) + 12 * r[0], 3 * r[1]);
    }
    bytes() {
      return takeBytes((sizeP) => M._web_tree_bytes(this.ptr, sizeP));
    }
    glb() {
      return takeBytes((sizeP) => M._web_tree_glb(this.ptr, sizeP));
    }
    free() {
      if (this.ptr) M._web_tree_free(this.ptr);
      this.ptr = 0;
    }
  }

  function fracture(source, options = {}) {
    const pieces = options.pieces ?? 0;
    if (!Number.isInteger(pieces) || pieces < 0) throw new Error(`fracture: pieces must be a whole number, got ${pieces}`);
    const pattern = patternIndex(options.pattern);
    const seed = options.seed ?? 3000;
    M.onProgress = options.onProgress || null;
    const bias = options.aspectBias ?? NaN; // NaN: the library's default
    if (options.aspectBias !== undefined && !Number.isFinite(bias))
      throw new Error(`fracture: aspectBias must be a finite number, got ${options.aspectBias}`);
    const impact = options.impact || null;
    if (impact && !(impact.length === 3 && impact.every(Number.isFinite)))
      throw new Error(`fracture: impact must be three finite numbers, got ${impact}`);
    // The def's fields as web_tree.c's build() reads them.
    const args = [pieces, pattern, seed, bias, impact ? 1 : 0, ...(impact || [0, 0, 0])];
    const argsP = M._web_alloc(args.length * 8);
    f64().set(args, argsP >> 3);
    try {
      let ptr = 0;
      if (source.shape !== undefined) {
        const name = cString(String(source.shape));
        ptr = M._web_fracture_shape(name, argsP);
        M._web_free(name);
      } else if (source.obj || source.ply) {
        const bytes = source.obj || source.ply;
        const format = cString(source.obj ? 'obj' : 'ply');
        const name = cString(source.name || (source.obj ? 'model.obj' : 'model.ply'));
        ptr = withBytes(bytes, (p, n) =>
          M._web_fracture_file(p, n, format, name, source.bunny ? 1 : 0, argsP));
        M._web_free(format);
        M._web_free(name);
      } else if (source.mesh) {
        const pos = Float32Array.from(source.mesh.positions);
        const idx = Uint32Array.from(source.mesh.indices);
        if (idx.length % 3) throw new Error(`${source.name || 'mesh'}: ${idx.length} indices are not whole triangles`);
        const pp = M._web_alloc(pos.byteLength);
        const ip = M._web_alloc(idx.byteLength);
        M.HEAPF32.set(pos, pp >> 2);
        M.HEAPU32.set(idx, ip >> 2);
        const name = cString(source.name || 'mesh');
        ptr = M._web_fracture_triangles(pp, pos.length / 3, ip, idx.length / 3, name, argsP);
        M._web_free(pp);
        M._web_free(ip);
        M._web_free(name);
      } else {
        throw new Error('fracture: the source needs shape, obj, ply or mesh');
      }
      if (!ptr) fail();
      return new Tree(ptr);
    } finally {
      M._web_free(argsP);
      M.onProgress = null;
    }
  }

  function loadTree(bytes) {
    const ptr = withBytes(bytes, (p, n) => M._web_tree_load(p, n));
    if (!ptr) fail();
    return new Tree(ptr);
  }

  /** The tree inside a .glb that tree.glb() (or `fracture --export-gltf`) wrote. */
  function loadGlb(bytes) {
    const ptr = withBytes(bytes, (p, n) => M._web_tree_load_glb(p, n));
    if (!ptr) fail();
    return new Tree(ptr);
  }

  const keyOf = (i, g) => `${i}:${g}`;
  const parseKey = (key) => {
    const [i, g] = String(key).split(':').map(Number);
    return [i >>> 0, g >>> 0];
  };
  function readCluster(d, at) {
    const leafCount = d[at + 5];
    const nodeCount = d[at + 6];
    const c = {
      cluster: keyOf(d[at], d[at + 1]),
      breakable: keyOf(d[at + 2], d[at + 3]),
      isStatic: d[at + 4] !== 0,
      mass: d[at + 7],
      volume: d[at + 8],
      inertia: [d[at + 9], d[at + 10], d[at + 11]],
      principal: { p: [d[at + 12], d[at + 13], d[at + 14]], q: [d[at + 15], d[at + 16], d[at + 17], d[at + 18]] },
      leaves: Uint32Array.from(d.subarray(at + CLUSTER_HEAD, at + CLUSTER_HEAD + leafCount)),
      nodes: Uint32Array.from(d.subarray(at + CLUSTER_HEAD + leafCount, at + CLUSTER_HEAD + leafCount + nodeCount)),
    };
    return [c, at + CLUSTER_HEAD + leafCount + nodeCount];
  }

  class Runtime {
    constructor(def = {}) {
      const g = def.gravity || [0, -9.81, 0];
      this.handle = nextRuntime++;
      this.ptr = M._web_runtime_create(this.handle, g[0], g[1], g[2]);
      if (!this.ptr) fail();
      this.bodyStateFn = null;
      this.trees = new Set();
      runtimes.set(this.handle, this);
    }
    setBodyState(fn) {
      this.bodyStateFn = fn;
    }
    addBreakable(tree, def = {}) {
      const p = def.position || [0, 0, 0];
      const q = def.rotation || [0, 0, 0, 1];
      const material = cString(def.material || '');
      const id = M._web_alloc(8);
      const ok = withDoubles([...p, ...q], (ptr) =>
        M._web_runtime_add(this.ptr, tree.ptr, ptr, ptr + 24, material, def.anchored ? 1 : 0, def.anchorHeight || 0, id));
      const key = keyOf(M.HEAPU32[id >> 2], M.HEAPU32[(id >> 2) + 1]);
      M._web_free(id);
      M._web_free(material);
      if (!ok) fail();
      this.trees.add(tree);
      return key;
    }
    applyContacts(contacts) {
      if (!contacts.length) return;
      const d = new Float64Array(contacts.length * 7);
      contacts.forEach((c, k) => {
        const [i, g] = parseKey(c.cluster);
        d.set([i, g, c.point[0], c.point[1], c.point[2], c.impulse, c.closingSpeed], 7 * k);
      });
      withDoubles(d, (p) => M._web_runtime_contacts(this.ptr, p, contacts.length));
    }
    damageAt(point, impulse) {
      M._web_runtime_damage_at(this.ptr, point[0], point[1], point[2], impulse);
    }
    split() {
      return M._web_runtime_split(this.ptr);
    }
    events() {
      const counts = M._web_alloc(12);
      const p = M._web_runtime_events(this.ptr, counts);
      const [nc, nr, nb] = new Uint32Array(M.HEAPU32.buffer, counts, 3);
      M._web_free(counts);
      const d = f64().subarray(p >> 3);
      const out = { created: [], removed: [], broken: [] };
      let at = 0;
      for (let k = 0; k < nc; ++k) {
        const parent = d[at + 1] === 0 ? null : keyOf(d[at], d[at + 1]);
        const body = {
          p: [d[at + 2], d[at + 3], d[at + 4]],
          q: [d[at + 5], d[at + 6], d[at + 7], d[at + 8]],
          v: [d[at + 9], d[at + 10], d[at + 11]],
          w: [d[at + 12], d[at + 13], d[at + 14]],
        };
        const [c, next] = readCluster(d, at + CREATED_HEAD);
        out.created.push({ ...c, parent, body });
        at = next;
      }
      for (let k = 0; k < nr; ++k, at += 4)
        out.removed.push({ cluster: keyOf(d[at], d[at + 1]), breakable: keyOf(d[at + 2], d[at + 3]) });
      for (let k = 0; k < nb; ++k, at += 13)
        out.broken.push({
          breakable: keyOf(d[at], d[at + 1]),
          cluster: keyOf(d[at + 2], d[at + 3]),
          bond: d[at + 4],
          position: [d[at + 5], d[at + 6], d[at + 7]],
          velocity: [d[at + 8], d[at + 9], d[at + 10]],
          area: d[at + 11],
          cause: d[at + 12] ? 'stress' : 'damage',
        });
      return out;
    }
    clearEvents() {
      M._web_runtime_clear_events(this.ptr);
    }
    cluster(key) {
      const [i, g] = parseKey(key);
      const p = M._web_runtime_cluster(this.ptr, i, g);
      return p ? readCluster(f64().subarray(p >> 3), 0)[0] : null;
    }
    removeCluster(key) {
      const [i, g] = parseKey(key);
      return M._web_runtime_remove_cluster(this.ptr, i, g) !== 0;
    }
    setFrailty(b, v) {
      const [i, g] = parseKey(b);
      if (!M._web_runtime_set_frailty(this.ptr, i, g, v)) throw new Error(`frailty: ${v} refused (finite, >= 0)`);
    }
    setDensity(b, v) {
      const [i, g] = parseKey(b);
      if (!M._web_runtime_set_density(this.ptr, i, g, v)) throw new Error(`density: ${v} refused (kg/m^3, in range)`);
    }
    frailty(b) {
      const [i, g] = parseKey(b);
      return M._web_runtime_frailty(this.ptr, i, g);
    }
    density(b) {
      const [i, g] = parseKey(b);
      return M._web_runtime_density(this.ptr, i, g);
    }
    stateHash() {
      const h = M._web_alloc(17);
      M._web_runtime_state_hash(this.ptr, h);
      const s = M.UTF8ToString(h);
      M._web_free(h);
      return s;
    }
    stats() {
      return withDoubles(new Float64Array(5), (p) => {
        M._web_runtime_stats(this.ptr, p);
        const d = f64().subarray(p >> 3, (p >> 3) + 5);
        return { clusters: d[0], bondsBroken: d[1], splits: d[2], pendingSplits: d[3], breakables: d[4] };
      });
    }
    destroy() {
      if (this.ptr) M._web_runtime_destroy(this.ptr);
      runtimes.delete(this.handle);
      this.ptr = 0;
    }
  }

  const materials = [];
  const matOut = M._web_alloc(40);
  for (let i = 0; i < M._web_material_count(); ++i) {
    const name = M.UTF8ToString(M._web_material(i, matOut));
    const d = f64().subarray(matOut >> 3, (matOut >> 3) + 5);
    materials.push({ name, density: d[0], frailty: d[1], bondStrength: d[2], friction: d[3], restitution: d[4] });
  }
  M._web_free(matOut);

  return {
    module: M,
    shapes: SHAPES.slice(),
    patterns: PATTERNS.slice(),
    materials: materials.map((m) => m.name),
    material: (name) => materials.find((m) => m.name === name) || null,
    fracture,
    loadTree,
    loadGlb,
    createRuntime: (def) => new Runtime(def),
  };
}
