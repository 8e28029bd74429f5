// The runtime and the Rapier bodies, kept in step by the Bullet world's
// rules (src/lib/bullet/world.c, world_bodies.c, world_hits.c): one body
// per cluster in its principal frame, colliders from the cluster's node set,
// contacts on cluster bodies become damage contacts, the split's removed
// and created clusters become bodies in the runtime's order.
import { colliderNodes } from './hulls.js';
import { mul, inverse, apply } from './transform.js';

// bk_default_world_def().max_hit_fragments_per_step: a step applies hits
// on clusters of at most this many fragments in all (oldest first, at least
// one); the rest wait and hold that step's split.
const MAX_HIT_FRAGMENTS_PER_STEP = 1024;
// bk_default_runtime_def(): contacts below these do nothing in the runtime.
const IMPULSE_THRESHOLD = 0.5; // N s
const IMPACT_SPEED = 1.0; // m/s

export class Destruction {
  constructor(bk, physics, { onCreated = () => {}, onRemoved = () => {} } = {}) {
    this.bk = bk;
    this.physics = physics;
    this.rt = bk.createRuntime({ gravity: [0, -9.81, 0] });
    this.onCreated = onCreated;
    this.onRemoved = onRemoved;
    this.clusters = new Map(); // key -> {key, breakable, body, principal, nodes, leaves, isStatic}
    this.objects = new Map(); // breakable -> {tree, hulls (hulls.js cache), material}
    this.hits = []; // waiting hits {cluster, point, local, impulse, closingSpeed, step}
    this.hitsHeldLast = false;
    this.timings = { physics: 0, break: 0, breakMax: 0, splitMax: 0 }; // ms: last step's, and the most a step took
    // The runtime asks where a cluster's body is while it works.
    this.rt.setBodyState((key) => {
      const c = this.clusters.get(key);
      return this.physics.state(c.body);
    });
  }

  // Adds a fractured object and makes bodies for its first clusters.
  add(tree, { position = [0, 0, 0], rotation = [0, 0, 0, 1], material, anchored = false, hullCache }) {
    const props = this.bk.material(material);
    if (!props) throw new Error(`unknown material '${material}' (known: ${this.bk.materials.join(', ')})`);
    const breakable = this.rt.addBreakable(tree, { position, rotation, material, anchored, anchorHeight: 0 });
    this.objects.set(breakable, { tree, hullCache, material: props });
    this.applyResults();
    return breakable;
  }

  // One fixed step: physics, the step's hits, the split, the bodies.
  step() {
    const t0 = performance.now();
    this.physics.retireProjectiles();
    const contacts = this.physics.step();
    const t1 = performance.now();
    const damage = [];
    for (const c of contacts) {
      if (c.a !== null) damage.push({ cluster: c.a, point: c.point, impulse: c.impulse, closingSpeed: c.closingSpeed });
      if (c.b !== null) damage.push({ cluster: c.b, point: c.point, impulse: c.impulse, closingSpeed: c.closingSpeed });
    }
    const holdSplits = this.applyHits(damage);
    // A step that leaves hits waiting splits nothing: the next one will.
    if (!holdSplits) {
      const s0 = performance.now();
      this.rt.split();
      this.timings.splitMax = Math.max(this.timings.splitMax, performance.now() - s0);
      this.applyResults();
    } else {
      this.takeBreaks();
    }
    const t2 = performance.now();
    this.timings.physics = t1 - t0;
    this.timings.break = t2 - t1;
    this.timings.breakMax = Math.max(this.timings.breakMax, t2 - t1);
  }

  // world_hits.c: the step's hits join the queue (those past the runtime's
  // thresholds, on clusters with bonds to break) and are applied oldest
  // first within the step's budget. Returns whether waiting hits hold this
  // step's split. When hits waited last step and splits wait too, this step
  // is the splits' (neither queue starves the other).
  applyHits(damage) {
    const splitTurn = this.hits.length > 0 && this.hitsHeldLast && (this.rt.stats().pendingSplits ?? 0) > 0;
    const step = this.physics.steps;
    for (const d of damage) {
      if (!(d.impulse >= IMPULSE_THRESHOLD) || !(d.closingSpeed >= IMPACT_SPEED) || !Number.isFinite(d.impulse)) continue;
      const info = this.clusters.get(d.cluster);
      if (!info || info.leaves.length < 2) continue;
      this.hits.push({ cluster: d.cluster, point: d.point, local: null, impulse: d.impulse, closingSpeed: d.closingSpeed, step });
    }
    if (splitTurn) {
      this.hitsHeldLast = false;
      this.keepWaiting(0);
      return false;
    }
    let used = 0, next = 0;
    const batch = [];
    for (; next < this.hits.length; next++) {
      const hit = this.hits[next];
      const info = this.clusters.get(hit.cluster);
      if (!info) continue; // split meanwhile: dropped
      if (used > 0 && used + info.leaves.length > MAX_HIT_FRAGMENTS_PER_STEP) break;
      used += info.leaves.length;
      const point = hit.step === step ? hit.point : apply(this.treeToWorld(info), hit.local);
      batch.push({ cluster: hit.cluster, point, impulse: hit.impulse, closingSpeed: hit.closingSpeed });
    }
    if (batch.length) this.rt.applyContacts(batch);
    this.keepWaiting(next);
    this.hitsHeldLast = this.hits.length > 0;
    return this.hitsHeldLast;
  }

  // A hit that waits keeps its place on the object (tree frame), not in the world.
  keepWaiting(from) {
    this.hits = this.hits.slice(from);
    for (const hit of this.hits) {
      if (hit.local) continue;
      const info = this.clusters.get(hit.cluster);
      if (info) hit.local = apply(inverse(this.treeToWorld(info)), hit.point);
    }
  }

  // The cluster's tree frame in the world: its body's transform after the
  // inverse of its principal frame.
  treeToWorld(info) {
    const s = this.physics.state(info.body);
    return mul({ p: s.p, q: s.q }, inverse(info.principal));
  }

  // Breaks without a split (damage only): their events are taken and dropped.
  takeBreaks() {
    this.rt.clearEvents();
  }

  // bk_world_apply_results: each removed cluster's body goes, then the
  // clusters made from it come, in the runtime's order; then those with no
  // parent (a new object's first clusters).
  applyResults() {
    const ev = this.rt.events();
    this.rt.clearEvents();
    const failed = [];
    let next = 0;
    for (let r = 0; r <= ev.removed.length; r++) {
      const removed = r < ev.removed.length ? ev.removed[r].cluster : null;
      if (removed !== null) this.release(removed);
      while (next < ev.created.length && (removed === null || ev.created[next].parent === removed)) {
        if (!this.build(ev.created[next])) failed.push(ev.created[next].cluster);
        next++;
      }
    }
    // A cluster that got no collider (every hull too flat) leaves the
    // simulation rather than fall through the ground.
    for (const key of failed) {
      this.release(key);
      this.rt.removeCluster(key);
    }
    if (failed.length) this.rt.clearEvents();
  }

  build(created) {
    const object = this.objects.get(created.breakable);
    const { tree, hullCache, material } = object;
    const toBody = inverse(created.principal);
    const hulls = [];
    for (const node of colliderNodes(tree, hullCache, created.nodes)) {
      const points = hullCache.points(node);
      const moved = new Float32Array(points.length);
      for (let i = 0; i < points.length; i += 3) {
        const p = apply(toBody, [points[i], points[i + 1], points[i + 2]]);
        moved[i] = p[0], moved[i + 1] = p[1], moved[i + 2] = p[2];
      }
      hulls.push(moved);
    }
    const { body, colliders } = this.physics.addCluster(created.cluster, {
      isStatic: created.isStatic, state: created.body, mass: created.mass, inertia: created.inertia, hulls,
      friction: material.friction, restitution: material.restitution,
    });
    const info = {
      key: created.cluster, breakable: created.breakable, body, principal: created.principal,
      nodes: Array.from(created.nodes), leaves: created.leaves, isStatic: created.isStatic,
    };
    this.clusters.set(created.cluster, info);
    if (colliders === 0) return false;
    this.onCreated(info, tree);
    return true;
  }

  release(key) {
    const info = this.clusters.get(key);
    if (!info) return;
    this.physics.removeBody(info.body);
    this.clusters.delete(key);
    this.onRemoved(info);
  }

  destroy() {
    this.rt.destroy();
  }
}

