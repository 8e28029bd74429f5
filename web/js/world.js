// One running scene: the Rapier world, the runtime over it and the view of
// its bodies. Rebuilt whole when the object is fractured again.
import RAPIER from '@dimforge/rapier3d-compat';
import { Physics, FIXED_DT } from './physics.js';
import { Destruction } from './destruction.js';
import { HullCache } from './hulls.js';

// The runtime's impulse_threshold (N s) over a step: smaller contact forces
// would be ignored by it, so Rapier need not report them.
const CONTACT_FORCE_THRESHOLD = 0.5 / FIXED_DT;

export class World {
  constructor(bk, view, tree, object) {
    this.bk = bk;
    this.view = view;
    this.tree = tree;
    this.physics = new Physics({ contactThreshold: CONTACT_FORCE_THRESHOLD });
    this.destruction = new Destruction(bk, this.physics, {
      onCreated: (info, t) => view.addCluster(info, t),
      onRemoved: (info) => view.removeCluster(info),
    });
    this.breakable = this.destruction.add(tree, {
      position: object.position ?? [0, 0, 0],
      material: object.material,
      anchored: object.anchored,
      hullCache: new HullCache(tree, RAPIER),
    });
    this.shots = 0;
  }

  get rt() {
    return this.destruction.rt;
  }

  step() {
    this.destruction.step();
  }

  // A projectile along a ray: from its origin at the scene's speed.
  fire(origin, direction, projectile) {
    const l = Math.hypot(...direction);
    if (!(l > 0) || !origin.every(Number.isFinite)) throw new Error('fire: origin and direction must be finite, direction non-zero');
    const v = direction.map((d) => (d / l) * projectile.speed);
    this.physics.fire(origin, v, projectile.radius, projectile.mass);
    this.shots++;
  }

  stats() {
    const s = this.rt.stats();
    return {
      bodies: this.destruction.clusters.size,
      fragments: this.tree.leafCount,
      bonds_broken: s.bondsBroken,
      physics_ms: this.destruction.timings.physics,
      break_ms: this.destruction.timings.break,
      // The costliest step's break handling, and the runtime's split in it
      // (the split of a shot wall happens in one step).
      break_ms_max: this.destruction.timings.breakMax,
      split_ms_max: this.destruction.timings.splitMax,
    };
  }

  destroy() {
    this.view.clear();
    this.destruction.destroy();
    this.physics.free();
    this.tree.free();
  }
}
