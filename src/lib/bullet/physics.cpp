// bk_physics: the C interface of <breakables/bullet.h> implemented over Bullet (single
// precision). This file holds the world: create, destroy, gravity, step and stats,
// the tick callbacks and the near callback, contacts and ray casts. Shapes are in
// physics_shapes.cpp, bodies in physics_bodies.cpp, the hull pair algorithm in
// physics_pairs.cpp and the shared types in physics_internal.hpp.
//
// Contacts are gathered in Bullet's internal tick callbacks (one pair of calls
// per substep) and kept as a plain array until the next step.
#include "physics_internal.hpp"

#include <cmath>
#include <cstdint>
#include <new>
#include <vector>

namespace {

const double default_gravity_y = -9.81;

bk_vec3 point_velocity(const BodySlot& s, bk_vec3 point) {
  bk_vec3 arm = bk_v3_sub(point, to_bk(s.center));
  return bk_v3_add(to_bk(s.linear_velocity), bk_v3_cross(to_bk(s.angular_velocity), arm));
}

bool reshaped_proxy(const void* user, const btBroadphaseProxy* proxy) {
  const bk_physics* w = static_cast<const bk_physics*>(user);
  const BodySlot* s = w->slot_of(static_cast<const btCollisionObject*>(proxy->m_clientObject));
  return s && s->reshaped;
}

/// Finds the pairs a body left out while it was debris.
struct PairSearch : public btDbvt::ICollide {
  btDbvtProxy* proxy = nullptr;
  btOverlappingPairCache* cache = nullptr;
  void Process(const btDbvtNode* leaf) override {
    btDbvtProxy* other = static_cast<btDbvtProxy*>(leaf->data);
    if (other != proxy) cache->addOverlappingPair(proxy, other);
  }
};

} // namespace

void bk_physics::snapshot_velocities() {
  const btCollisionObjectArray& objects = world.getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    BodySlot* s = slot_of(objects[i]);
    if (!s) continue;
    s->linear_velocity = s->body->getLinearVelocity();
    s->angular_velocity = s->body->getAngularVelocity();
    s->center = s->body->getCenterOfMassPosition();
  }
}

/// Records every contact point the solver just pushed on. Manifolds whose
/// bodies are all asleep or static were not solved this substep (their
/// impulses are stale) and are skipped.
void bk_physics::collect_contacts() {
  int manifolds = dispatcher.getNumManifolds();
  for (int m = 0; m < manifolds; ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    const btCollisionObject* o0 = manifold->getBody0();
    const btCollisionObject* o1 = manifold->getBody1();
    bool solved = (!o0->isStaticOrKinematicObject() && o0->isActive()) ||
                  (!o1->isStaticOrKinematicObject() && o1->isActive());
    BodySlot* a = slot_of(o0);
    BodySlot* b = slot_of(o1);
    if (!solved || !a || !b) continue;
    for (int i = 0; i < manifold->getNumContacts(); ++i) {
      const btManifoldPoint& pt = manifold->getContactPoint(i);
      if (!(pt.getAppliedImpulse() > 0)) continue;
      ++contact_total;
      if (contacts.size() >= contact_capacity) continue;
      bk_contact c;
      c.a = id_of(a);
      c.b = id_of(b);
      // Bullet's compound algorithm tags each point with the child it touched.
      c.child_a = o0->getCollisionShape()->isCompound() ? pt.m_index0 : -1;
      c.child_b = o1->getCollisionShape()->isCompound() ? pt.m_index1 : -1;
      // Bullet's normal on B points from B towards A, as bk_contact wants.
      c.normal = to_bk(pt.m_normalWorldOnB);
      if (pt.m_localPointA.isZero() && o0->getCcdSweptSphereRadius() > 0) {
        // A predictive (CCD) contact: Bullet stores A's centre and the
        // centre of A's swept sphere at impact; use where that sphere touches B.
        c.point =
            bk_v3_sub(to_bk(pt.getPositionWorldOnB()), bk_v3_scale(c.normal, o0->getCcdSweptSphereRadius()));
      } else {
        c.point =
            bk_v3_scale(bk_v3_add(to_bk(pt.getPositionWorldOnA()), to_bk(pt.getPositionWorldOnB())), 0.5);
      }
      c.impulse = pt.getAppliedImpulse();
      bk_vec3 relative = bk_v3_sub(point_velocity(*a, c.point), point_velocity(*b, c.point));
      c.approach_speed = -bk_v3_dot(relative, c.normal);
      try {
        contacts.push_back(c);
      } catch (...) {
        // Out of memory: the contact stays counted but is dropped.
      }
    }
  }
}

/// Before a step: one walk over the pair cache for every filter and shape
/// changed since the last, then a tree query per body that left debris.
void bk_physics::refresh_pairs() {
  btOverlappingPairCache* cache = broadphase.getOverlappingPairCache();
  if (!changed_pairs.empty()) {
    PairRefresh refresh;
    refresh.cache = cache;
    refresh.dispatcher = &dispatcher;
    refresh.reshaped = any_reshaped ? reshaped_proxy : nullptr;
    refresh.user = this;
    cache->processAllOverlappingPairs(&refresh, &dispatcher);
    for (uint32_t index : changed_pairs)
      bodies.slots[index].reshaped = false;
  }
  for (uint32_t index : gained_pairs) {
    BodySlot& s = bodies.slots[index];
    btDbvtProxy* proxy = s.body ? static_cast<btDbvtProxy*>(s.body->getBroadphaseHandle()) : nullptr;
    if (!proxy || is_debris(s)) continue;
    PairSearch search;
    search.proxy = proxy;
    search.cache = cache;
    for (btDbvt& set : broadphase.m_sets)
      set.collideTV(set.m_root, proxy->leaf->volume, search);
  }
  changed_pairs.clear();
  gained_pairs.clear();
  any_reshaped = false;
}

namespace bk_bullet {

void freeze_calm_bodies(bk_physics* w) { w->freeze_calm_bodies(); }

} // namespace bk_bullet

namespace {

void pre_tick(btDynamicsWorld* world, btScalar) {
  static_cast<bk_physics*>(world->getWorldUserInfo())->snapshot_velocities();
}

void post_tick(btDynamicsWorld* world, btScalar) {
  static_cast<bk_physics*>(world->getWorldUserInfo())->collect_contacts();
}

// The dynamic AABB tree pairs proxies by their fattened volumes (5 cm of
// margin plus predicted motion, so the tree is rebuilt less often). A pile of
// 10 cm fragments then has ~35 pairs per body, most of them several
// centimetres apart, and each would pay for a GJK query every substep. The
// exact boxes (shape bounds grown by the contact threshold) are kept on the
// proxies: pairs whose exact boxes are apart skip the narrowphase, and an
// algorithm left from an earlier touch is freed with its manifold (its points
// are further apart than any contact threshold), so that the solver, the
// island builder and the contact report walk only pairs that can touch.
const btScalar pair_gap = btScalar(0.005);

void free_algorithm(btBroadphasePair& pair, btCollisionDispatcher& dispatcher) {
  if (!pair.m_algorithm) return;
  pair.m_algorithm->~btCollisionAlgorithm();
  dispatcher.freeCollisionAlgorithm(pair.m_algorithm);
  pair.m_algorithm = nullptr;
}

void near_callback(btBroadphasePair& pair, btCollisionDispatcher& dispatcher, const btDispatcherInfo& info) {
  const btBroadphaseProxy* a = pair.m_pProxy0;
  const btBroadphaseProxy* b = pair.m_pProxy1;
  const auto* object_a = static_cast<const btCollisionObject*>(a->m_clientObject);
  const auto* object_b = static_cast<const btCollisionObject*>(b->m_clientObject);
  // Two sleepers (frozen, asleep or static) keep no manifold: thousands of
  // them in a settled heap were walked every step by the island builder and
  // the contact report. Contacts come back within a step of a wake.
  if (!object_a->isActive() && !object_b->isActive()) {
    free_algorithm(pair, dispatcher);
    return;
  }
  // A body moving near a watched one (whose box is grown by its margin).
  if (object_a->getUserIndex2() == watched_tag || object_b->getUserIndex2() == watched_tag)
    note_watched_pair(static_cast<Dispatcher&>(dispatcher).owner, object_a, object_b);
  // Bullet grows every box by gContactBreakingThreshold (2 cm); 5 mm of that
  // is kept: contact points of resting fragments are born within ~2 mm, and
  // fast bodies' boxes already cover their motion over the substep.
  const btScalar shrink = btMax(gContactBreakingThreshold - pair_gap, btScalar(0));
  const btVector3 s(shrink, shrink, shrink);
  if (!TestAabbAgainstAabb2(a->m_aabbMin + s, a->m_aabbMax - s, b->m_aabbMin + s, b->m_aabbMax - s)) {
    free_algorithm(pair, dispatcher);
    return;
  }
  static_cast<Dispatcher&>(dispatcher).narrow_pairs++;
  btCollisionDispatcher::defaultNearCallback(pair, dispatcher, info);
}

} // namespace

// ---------------------------------------------------------------- world

bk_physics_def bk_default_physics_def(void) {
  bk_physics_def d = {};
  d.gravity = bk_v3(0, default_gravity_y, 0);
  d.fixed_dt = default_fixed_dt;
  d.contact_capacity = default_contact_capacity;
  d.default_margin = default_margin;
  return d;
}

bk_physics* bk_physics_create(const bk_physics_def* desc, bk_error* err) {
  bk_physics_def d = desc ? *desc : bk_default_physics_def();
  if (!bk_v3_is_finite(d.gravity)) {
    bk_error_set(err, "physics: gravity must be finite (got %g, %g, %g)", d.gravity.x, d.gravity.y,
                 d.gravity.z);
    return nullptr;
  }
  if (!(d.fixed_dt > 0.0 && d.fixed_dt <= 0.1)) {
    bk_error_set(err, "physics: fixed_dt must be in (0, 0.1] s (got %g)", d.fixed_dt);
    return nullptr;
  }
  if (!(std::isfinite(d.default_margin) && d.default_margin >= 0.0)) {
    bk_error_set(err, "physics: default_margin must be finite and >= 0 (got %g)", d.default_margin);
    return nullptr;
  }

  bk_physics* w = new (std::nothrow) bk_physics;
  if (!w) {
    bk_error_set(err, "physics: out of memory");
    return nullptr;
  }
  w->gravity = d.gravity;
  w->fixed_dt = d.fixed_dt;
  w->margin = d.default_margin;
  w->contact_capacity = d.contact_capacity;
  w->world.setGravity(to_bt(d.gravity));
  // Split impulse for every penetration (threshold 0 instead of Bullet's
  // -0.04): positional recovery goes through the separate push velocity, so
  // the applied impulses reported as contacts hold no recovery impulse.
  btContactSolverInfo& solver_info = w->world.getSolverInfo();
  solver_info.m_splitImpulse = 1;
  solver_info.m_splitImpulsePenetrationThreshold = 0;
  // Full contact manifolds from the first touch against the ground (a box
  // landing flat gets its corners at once, not one point per step), so bodies
  // do not tip over on a single deepest point. Not for convex pairs: there it
  // multiplies the GJK work of every pair (a pile of 300 fragments went from
  // ~10 ms to ~100 ms a step), and persistent manifolds fill up within a few
  // steps anyway.
  w->configuration.setPlaneConvexMultipointIterations();
  // Bullet keeps this one setting in a global; every world here uses the same value.
  gDeactivationTime = (btScalar)sleep_time;
  w->dispatcher.setNearCallback(near_callback);
  w->dispatcher.owner = w;
  w->broadphase.getOverlappingPairCache()->setOverlapFilterCallback(&w->overlaps);
  w->dispatcher.registerCollisionCreateFunc(CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE,
                                            &w->hull_pair_create);
  // The broadphase grows every box by 5 cm so that a moving body updates the
  // tree less often; among 5 cm shards that made ~26 pairs per body (45k
  // pairs for 1.7k bodies, all walked each step). 1 cm halves the pairs; a
  // global in Bullet, like the deactivation time.
  gDbvtMargin = btScalar(0.01);
  // Sleeping bodies keep their boxes (Bullet's default recomputes all).
  w->world.setForceUpdateAllAabbs(false);
  static_cast<ContactIslandManager*>(w->world.getSimulationIslandManager())->owner = w;
  w->world.setInternalTickCallback(pre_tick, w, true);
  w->world.setInternalTickCallback(post_tick, w, false);
  return w;
}

void bk_physics_destroy(bk_physics* w) {
  if (!w) return;
  std::vector<uint32_t> all;
  for (uint32_t i = 0; i < w->bodies.slots.size(); ++i)
    if (w->bodies.slots[i].body) all.push_back(i);
  w->destroy_body_slots(all.data(), (uint32_t)all.size(), false);
  for (uint32_t i = 0; i < w->shapes.slots.size(); ++i)
    if (w->shapes.slots[i].shape && w->shapes.slots[i].kind == ShapeKind::compound) w->destroy_shape_slot(i);
  for (uint32_t i = 0; i < w->shapes.slots.size(); ++i)
    if (w->shapes.slots[i].shape) w->destroy_shape_slot(i);
  delete w;
}

void bk_physics_set_gravity(bk_physics* w, bk_vec3 gravity) {
  if (!w || !bk_v3_is_finite(gravity)) return;
  w->gravity = gravity;
  w->world.setGravity(to_bt(gravity));
  for (BodySlot& s : w->bodies.slots)
    if (s.body && s.mass > 0.0) {
      w->thaw(s, true);
      s.body->activate(true);
    }
}

bk_vec3 bk_physics_gravity(const bk_physics* w) { return w ? w->gravity : bk_v3(0, 0, 0); }

int bk_physics_step(bk_physics* w, double dt, int max_substeps) {
  if (!w) return 0;
  w->contacts.clear();
  w->contact_total = 0;
  w->dispatcher.narrow_pairs = 0;
  if (!(std::isfinite(dt) && dt > 0.0)) return 0;
  try {
    w->refresh_pairs();
  } catch (...) {
    // Out of memory in Bullet's pair cache: the pairs are refreshed by the
    // broadphase as the boxes move instead.
  }
  w->overlaps.tests = 0; // the step's own, not the refresh's
  if (max_substeps < 1) max_substeps = 1;
  // The accumulator is kept in double here rather than in Bullet's float
  // clock, so that dt = k * fixed_dt always gives exactly k substeps. Time
  // beyond max_substeps is dropped, as Bullet does.
  w->accumulator += dt;
  double due = floor(w->accumulator / w->fixed_dt + 1e-6);
  int substeps = due < (double)max_substeps ? (int)due : max_substeps;
  w->accumulator -= due * w->fixed_dt;
  if (!(w->accumulator > 0.0 && w->accumulator < w->fixed_dt)) w->accumulator = 0.0;
  btScalar h = (btScalar)w->fixed_dt;
  for (int i = 0; i < substeps; ++i)
    w->world.stepSimulation(h, 1, h);
  return substeps;
}

bk_physics_stats bk_physics_get_stats(const bk_physics* w) {
  bk_physics_stats s = {};
  if (!w) return s;
  const btCollisionObjectArray& objects = w->world.getCollisionObjectArray();
  s.bodies = (uint32_t)objects.size();
  for (int i = 0; i < objects.size(); ++i)
    s.awake_bodies += !objects[i]->isStaticOrKinematicObject() && objects[i]->isActive();
  // Bullet's getters are not const; nothing is changed here.
  bk_physics* m = const_cast<bk_physics*>(w);
  s.pairs = (uint32_t)m->broadphase.getOverlappingPairCache()->getNumOverlappingPairs();
  s.manifolds = (uint32_t)m->dispatcher.getNumManifolds();
  for (int i = 0; i < m->dispatcher.getNumManifolds(); ++i)
    s.contact_points += (uint32_t)m->dispatcher.getManifoldByIndexInternal(i)->getNumContacts();
  s.narrow_pairs = w->dispatcher.narrow_pairs;
  s.box_overlaps = w->overlaps.tests;
  return s;
}

// ---------------------------------------------------------------- queries

uint32_t bk_physics_contacts(const bk_physics* w, bk_contact* out, uint32_t capacity) {
  if (!w) return 0;
  for (uint32_t i = 0; out && i < capacity && i < w->contacts.size(); ++i)
    out[i] = w->contacts[i];
  return w->contact_total;
}

bool bk_physics_ray_cast(const bk_physics* w, bk_vec3 from, bk_vec3 to, bk_ray_hit* hit) {
  if (!w || !bk_v3_is_finite(from) || !bk_v3_is_finite(to) || !(bk_v3_length(bk_v3_sub(to, from)) > 0.0))
    return false;
  btVector3 a = to_bt(from), b = to_bt(to);
  btCollisionWorld::ClosestRayResultCallback callback(a, b);
  w->world.rayTest(a, b, callback);
  if (!callback.hasHit()) return false;
  const BodySlot* s = w->slot_of(callback.m_collisionObject);
  if (!s) return false;
  if (hit) {
    hit->body = w->id_of(s);
    hit->fraction = callback.m_closestHitFraction;
    hit->point = bk_v3_lerp(from, to, hit->fraction);
    hit->normal = bk_v3_normalize(to_bk(callback.m_hitNormalWorld));
  }
  return true;
}
