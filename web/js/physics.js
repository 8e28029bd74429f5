// The Rapier world: the ground, one rigid body per runtime cluster, and
// projectiles. It knows nothing of the runtime: destruction.js hands it
// hulls and mass properties and takes back contacts, as the Bullet world
// (src/lib/bullet/world.c, physics.cpp) does with its bodies.
import RAPIER from '@dimforge/rapier3d-compat';

export const FIXED_DT = 1 / 60; // the Bullet world's fixed_dt
const PROJECTILE_LIFETIME = 8.0; // s, the Bullet world's projectile_lifetime
const GROUND_FRICTION = 0.5;

let ready = null;
// Rapier's wasm is inlined in its module: instantiating it needs no fetch.
export function loadRapier() {
  ready ??= RAPIER.init().then(warmUp);
  return ready;
}

// The browser compiles each wasm function the first time it runs: the
// first hull-on-hull contacts cost a few hundred ms, which would land in the
// step of the first break. A few steps of hulls falling onto hulls and a
// fast ball pay for that at load time instead.
function warmUp() {
  const world = new RAPIER.World({ x: 0, y: -9.81, z: 0 });
  const events = new RAPIER.EventQueue(true);
  const box = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0, 1, 0, 1, 0, 1, 1, 1, 1, 1]);
  world.createCollider(RAPIER.ColliderDesc.cuboid(5, 0.5, 5).setTranslation(0, -0.5, 0));
  for (let i = 0; i < 3; i++) {
    const body = world.createRigidBody(RAPIER.RigidBodyDesc.dynamic().setTranslation(0.3 * i, 1.2 * i, 0));
    for (const x of [0, 1])
      world.createCollider(RAPIER.ColliderDesc.convexHull(box).setTranslation(x, 0, 0)
        .setActiveEvents(RAPIER.ActiveEvents.CONTACT_FORCE_EVENTS), body);
  }
  const ball = world.createRigidBody(RAPIER.RigidBodyDesc.dynamic().setTranslation(0.5, 0.5, 4).setLinvel(0, 0, -40).setCcdEnabled(true));
  world.createCollider(RAPIER.ColliderDesc.ball(0.1), ball);
  for (let i = 0; i < 40; i++) {
    world.step(events);
    events.drainContactForceEvents((e) => {
      const c1 = world.getCollider(e.collider1()), c2 = world.getCollider(e.collider2());
      world.contactPair(c1, c2, (m) => m.numSolverContacts() && m.solverContactPoint(0));
    });
  }
  events.free();
  world.free();
}

export class Physics {
  constructor({ gravity = [0, -9.81, 0], contactThreshold = 0 } = {}) {
    this.world = new RAPIER.World({ x: gravity[0], y: gravity[1], z: gravity[2] });
    this.world.timestep = FIXED_DT;
    this.events = new RAPIER.EventQueue(true);
    // Contacts whose force over a step stays below this carry less impulse
    // than the runtime's impulse_threshold: it would ignore them anyway.
    this.contactThreshold = contactThreshold;
    this.owners = new Map(); // collider handle -> {kind: 'cluster'|'projectile'|'ground', key, body}
    this.projectiles = []; // {body, radius, expires}
    this.steps = 0;
    this.before = new Map(); // body handle -> velocities before the step (closing speeds)
    const ground = this.world.createRigidBody(RAPIER.RigidBodyDesc.fixed().setTranslation(0, -0.5, 0));
    const collider = this.world.createCollider(
      RAPIER.ColliderDesc.cuboid(100, 0.5, 100).setFriction(GROUND_FRICTION), ground);
    this.owners.set(collider.handle, { kind: 'ground', key: null, body: ground });
  }

  // A cluster's body: its frame is the cluster's principal frame (so its
  // centre of mass is its origin and its inertia diagonal), its colliders
  // the hulls of its collider nodes moved into that frame (Float32Arrays).
  // Colliders carry no mass: the cluster's mass properties are the body's.
  addCluster(key, { isStatic, state, mass, inertia, hulls, friction, restitution }) {
    const { p, q, v, w } = state;
    const desc = isStatic ? RAPIER.RigidBodyDesc.fixed() : RAPIER.RigidBodyDesc.dynamic();
    desc.setTranslation(p[0], p[1], p[2]).setRotation({ x: q[0], y: q[1], z: q[2], w: q[3] });
    if (!isStatic) {
      desc.setLinvel(v[0], v[1], v[2]).setAngvel({ x: w[0], y: w[1], z: w[2] });
      desc.setAdditionalMassProperties(mass, { x: 0, y: 0, z: 0 },
        { x: inertia[0], y: inertia[1], z: inertia[2] }, { x: 0, y: 0, z: 0, w: 1 });
    }
    const body = this.world.createRigidBody(desc);
    let colliders = 0;
    for (const points of hulls) {
      const cd = RAPIER.ColliderDesc.convexHull(points);
      if (!cd) continue; // too flat for a hull: adds nothing, as in the Bullet world
      cd.setDensity(0).setFriction(friction).setRestitution(restitution)
        .setActiveEvents(RAPIER.ActiveEvents.CONTACT_FORCE_EVENTS)
        .setContactForceEventThreshold(this.contactThreshold);
      const collider = this.world.createCollider(cd, body);
      this.owners.set(collider.handle, { kind: 'cluster', key, body });
      colliders++;
    }
    return { body, colliders };
  }

  removeBody(body) {
    for (let i = 0; i < body.numColliders(); i++) this.owners.delete(body.collider(i).handle);
    this.world.removeRigidBody(body);
  }

  // A sphere with continuous collision detection (bk_world_fire).
  fire(origin, velocity, radius, mass) {
    const desc = RAPIER.RigidBodyDesc.dynamic()
      .setTranslation(origin[0], origin[1], origin[2])
      .setLinvel(velocity[0], velocity[1], velocity[2])
      .setCcdEnabled(true);
    const body = this.world.createRigidBody(desc);
    const volume = (4 / 3) * Math.PI * radius ** 3;
    const collider = this.world.createCollider(
      RAPIER.ColliderDesc.ball(radius).setDensity(mass / volume).setFriction(0.5), body);
    this.owners.set(collider.handle, { kind: 'projectile', key: null, body });
    const projectile = { body, radius, expires: this.steps + Math.floor(PROJECTILE_LIFETIME / FIXED_DT) };
    this.projectiles.push(projectile);
    return projectile;
  }

  // Projectiles past their lifetime leave (a long run stays bounded).
  retireProjectiles() {
    const kept = [];
    for (const p of this.projectiles) {
      if (this.steps > p.expires) {
        this.removeBody(p.body);
        p.removed = true;
      } else {
        kept.push(p);
      }
    }
    this.projectiles = kept;
  }

  // One fixed step. Returns the step's contacts on cluster bodies, one per
  // touching collider pair: {a, b (cluster keys or null), point, impulse
  // (N s: the pair's force over the step), closingSpeed (m/s, along the
  // normal before the solve, > 0 approaching)}.
  step() {
    this.snapshotVelocities();
    this.steps++;
    this.world.step(this.events);
    const contacts = [];
    this.events.drainContactForceEvents((event) => {
      const c1 = this.world.getCollider(event.collider1());
      const c2 = this.world.getCollider(event.collider2());
      const o1 = c1 && this.owners.get(c1.handle), o2 = c2 && this.owners.get(c2.handle);
      if (!o1 || !o2) return;
      const contact = this.contactOf(c1, c2, o1.body, o2.body);
      if (!contact) return;
      contact.impulse = event.totalForceMagnitude() * FIXED_DT;
      contact.a = o1.kind === 'cluster' ? o1.key : null;
      contact.b = o2.kind === 'cluster' ? o2.key : null;
      contacts.push(contact);
    });
    return contacts;
  }

  // The middle of the pair's solver contact points and their closing speed.
  contactOf(c1, c2, body1, body2) {
    let x = 0, y = 0, z = 0, n = 0, normal = null;
    this.world.contactPair(c1, c2, (manifold, flipped) => {
      const count = manifold.numSolverContacts();
      if (!count) return;
      for (let i = 0; i < count; i++) {
        const p = manifold.solverContactPoint(i);
        x += p.x, y += p.y, z += p.z, n++;
      }
      const m = manifold.normal(); // from the manifold's first shape towards its second
      normal ??= flipped ? [-m.x, -m.y, -m.z] : [m.x, m.y, m.z];
    });
    if (!n) return null;
    const point = [x / n, y / n, z / n];
    const v1 = this.pointVelocity(body1, point), v2 = this.pointVelocity(body2, point);
    const closingSpeed = (v1[0] - v2[0]) * normal[0] + (v1[1] - v2[1]) * normal[1] + (v1[2] - v2[2]) * normal[2];
    return { point, closingSpeed };
  }

  // Velocities as they were before the solve: the speed a hit came in at.
  snapshotVelocities() {
    this.before.clear();
    this.world.forEachActiveRigidBody((body) => {
      if (!body.isDynamic()) return;
      const v = body.linvel(), w = body.angvel(), c = body.worldCom();
      this.before.set(body.handle, [v.x, v.y, v.z, w.x, w.y, w.z, c.x, c.y, c.z]);
    });
  }

  pointVelocity(body, p) {
    const s = this.before.get(body.handle);
    if (!s) return [0, 0, 0]; // fixed or asleep before the step
    const r = [p[0] - s[6], p[1] - s[7], p[2] - s[8]];
    return [s[0] + s[4] * r[2] - s[5] * r[1], s[1] + s[5] * r[0] - s[3] * r[2], s[2] + s[3] * r[1] - s[4] * r[0]];
  }

  // {p, q, v, w} of a body, as the runtime's setBodyState wants it.
  state(body) {
    const p = body.translation(), q = body.rotation(), v = body.linvel(), w = body.angvel();
    return { p: [p.x, p.y, p.z], q: [q.x, q.y, q.z, q.w], v: [v.x, v.y, v.z], w: [w.x, w.y, w.z] };
  }

  free() {
    this.events.free();
    this.world.free();
  }
}
