// The page's state: which scene, how its object is fractured, the running
// world, and the actions on it (fire, re-fracture, drop a model, download).
import { SCENES, objectFor, sceneShot } from './scenes.js';
import { builtinSource, fileSource } from './sources.js';
import { fracture } from './fracture_plan.js';
import { fractureInWorker } from './refracture.js';
import { World } from './world.js';

export class App {
  constructor(bk, view, params, hooks) {
    this.bk = bk;
    this.view = view;
    this.params = params;
    this.hooks = hooks; // {progress(fraction|null), built()}
    this.world = null;
    this.busy = null; // the fracture under way, if any
    this.fractureMs = 0; // the library's build time of the tree shown
    this.fractureCallMs = 0; // and the whole fracture call's
    this.name = null; // what the download is named after
  }

  get scene() {
    return SCENES[this.sceneName];
  }

  // The fracture options for the current object: its scene's, overridden
  // by the URL's or the panel's pieces, pattern and seed.
  options(overrides = {}) {
    const o = this.object, p = { ...this.params, ...overrides };
    const options = {};
    const pieces = p.pieces ?? o.pieces, pattern = p.pattern ?? o.pattern;
    if (pieces) options.pieces = pieces;
    if (pattern) options.pattern = pattern;
    options.seed = p.seed ?? 3000;
    if (o.aspectBias) options.aspectBias = o.aspectBias;
    return options;
  }

  aim() {
    const { eye, target } = this.placement;
    return { eye, target, position: this.object.position ?? [0, 0, 0] };
  }

  // The first scene, fractured on the main thread (nothing runs yet).
  async start() {
    this.sceneName = this.params.scene;
    this.object = objectFor(this.sceneName, this.params.mesh);
    this.placement = this.scene;
    this.name = this.object.mesh;
    const source = await builtinSource(this.object.mesh);
    const { tree, ms, callMs } = fracture(this.bk, source, this.options(), this.aim());
    this.fractureMs = ms;
    this.fractureCallMs = callMs;
    this.build(tree);
  }

  // A new world for a tree of the current object.
  build(tree) {
    this.world?.destroy();
    this.world = null;
    if (this.object.standOnGround) {
      // A built-in mesh in place of the scene's object: on the ground under
      // the scene's aim, and the shots go at its middle.
      const { min, max } = tree.bounds();
      this.object = { ...this.object, position: [-(min[0] + max[0]) / 2, -min[1], -(min[2] + max[2]) / 2], standOnGround: false };
      this.placement = { ...this.placement, target: [0, (max[1] - min[1]) / 2, 0] };
    }
    const { eye, target } = this.placement;
    this.view.setLook(this.scene.look, this.placement.camera ?? eye, target);
    this.world = new World(this.bk, this.view, tree, this.object);
    this.treeHash = tree.hash;
    this.hooks.built();
  }

  // Re-fractures in the worker while the scene runs; the new tree replaces
  // the object when it comes. sceneName / object / placement: what it is of.
  async refracture(source, overrides, next = {}) {
    if (this.busy) throw new Error('a fracture is already under way: wait for it to finish');
    // The options of what it will be; the running scene stays as it is meanwhile.
    const saved = { sceneName: this.sceneName, object: this.object, placement: this.placement, name: this.name };
    Object.assign(this, next);
    const options = this.options(overrides);
    const aim = this.aim();
    Object.assign(this, saved);
    this.hooks.progress(0);
    this.busy = fractureInWorker(source, options, aim, (f) => this.hooks.progress(f));
    try {
      const { bytes, ms, callMs } = await this.busy;
      const tree = this.bk.loadTree(bytes);
      Object.assign(this, next);
      this.fractureMs = ms;
      this.fractureCallMs = callMs;
      this.params = { ...this.params, ...overrides };
      this.build(tree);
    } finally {
      this.busy = null;
      this.hooks.progress(null);
    }
  }

  // The panel's pieces and pattern (null: the scene's own).
  async refractureCurrent(pieces, pattern) {
    const source = this.dropped ?? (await builtinSource(this.object.mesh));
    return this.refracture(source, { pieces, pattern });
  }

  async switchScene(sceneName) {
    const object = objectFor(sceneName, null);
    this.dropped = null;
    return this.refracture(await builtinSource(object.mesh), { pieces: null, pattern: null, mesh: null },
      { sceneName, object, placement: SCENES[sceneName], name: object.mesh });
  }

  // A user's model: fractured with the last pieces and pattern used, stood on the
  // ground in front of the camera, aimed at by its size.
  async dropFile(name, bytes) {
    const source = await fileSource(name, bytes);
    const bounds = boundsOf(source);
    const size = Math.max(...bounds.max.map((v, i) => v - bounds.min[i]));
    if (!Number.isFinite(size)) throw new Error(`${name}: no vertices found: not a triangle mesh`);
    if (!(size > 0)) throw new Error(`${name}: the model has no extent (all its vertices at one point)`);
    const c = bounds.min.map((v, i) => (v + bounds.max[i]) / 2);
    const position = [-c[0], -bounds.min[1], -c[2]];
    const target = [0, (bounds.max[1] - bounds.min[1]) / 2, 0];
    const eye = [0, target[1] + 0.3 * size, 2.2 * size];
    const object = { mesh: name, material: this.object.material, anchored: false, position };
    const placement = {
      eye, target, camera: null,
      projectile: { speed: 30, radius: 0.06 * size, mass: 20 * size ** 3 },
    };
    await this.refracture(source, {}, { object, placement, name: name.replace(/\.[^.]*$/, '') });
    this.dropped = source;
  }

  fire(origin, direction) {
    this.world.fire(origin, direction, this.placement.projectile);
  }

  // Shot k of a scripted volley, aimed as the game aims its shots.
  fireScripted(k) {
    const { origin, direction } = sceneShot(this.placement, k);
    this.fire(origin, direction);
  }

  download() {
    const bytes = this.world.tree.glb();
    const url = URL.createObjectURL(new Blob([bytes], { type: 'model/gltf-binary' }));
    const a = document.createElement('a');
    a.href = url;
    a.download = `${this.name}_fractured.glb`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(url), 1000);
  }
}

// A source's bounds: a mesh's from its positions, an OBJ's from its vertex lines.
function boundsOf(source) {
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  const add = (x, y, z) => {
    const v = [x, y, z];
    for (let i = 0; i < 3; i++) min[i] = Math.min(min[i], v[i]), max[i] = Math.max(max[i], v[i]);
  };
  if (source.mesh) {
    const p = source.mesh.positions;
    for (let i = 0; i < p.length; i += 3) add(p[i], p[i + 1], p[i + 2]);
  } else {
    const text = new TextDecoder().decode(source.obj);
    for (const line of text.split('\n'))
      if (line.startsWith('v ')) {
        const [x, y, z] = line.trim().split(/\s+/).slice(1, 4).map(Number);
        if ([x, y, z].every(Number.isFinite)) add(x, y, z);
      }
  }
  return { min, max };
}
