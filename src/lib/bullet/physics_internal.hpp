// bk_physics (private): the types the physics*.cpp files share, with Bullet
// under them: the slot tables and the conversions, the Bullet world
// subclasses and callbacks, and struct bk_physics itself. Only the
// physics*.cpp files include it (and with it Bullet), and
// tests/test_removal_order.cpp, which checks a removal against Bullet's own.
//
// Ids index slot tables; a slot's generation moves on when its object is
// destroyed, so stale ids are detected and ignored.
#pragma once

#include <breakables/bullet.h>

#include <cmath>
#include <cstdint>
#include <new>
#include <vector>

#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <btBulletDynamicsCommon.h>

// A named namespace: the header is in several translation units.
namespace bk_bullet {

const double default_fixed_dt = 1.0 / 60.0;
const uint32_t default_contact_capacity = 65536;
const double default_margin = 0.004;
// Sleeping: Bullet's speeds, a shorter calm time (2 s by default), and an
// angular threshold that follows the body's size (see bk_physics_create_body).
const double sleep_time = 0.5;
const double freeze_time = 2.0 * sleep_time; // calm this long, a body is frozen even in an awake island
const double sleep_linear_speed = 0.8;
const double sleep_angular_speed = 1.0;
const double sleep_edge_speed = 0.25;

enum class ShapeKind { hull, sphere, box, plane, compound };

struct ShapeSlot {
  btCollisionShape* shape = nullptr;
  uint32_t generation = 1;
  ShapeKind kind = ShapeKind::hull;
  uint32_t uses = 0;              // bodies and compounds referencing this shape
  double inner_radius = 0.0;      // radius of a sphere at the origin inside the shape (CCD default)
  double hull_volume = 0.0;       // hulls: volume of the hull before shrinking by the margin
  std::vector<uint32_t> children; // compound: child slot indices, one per added child
};

struct BodySlot {
  btRigidBody* body = nullptr;
  uint32_t generation = 1;
  uint32_t shape = 0; // shape slot index
  double mass = 0.0;
  btVector3 inertia{0, 0, 0}; // principal moments of a dynamic body (kept while it is frozen)
  uint64_t user_data = 0;
  bool pinned = false;   // frozen until unpinned: touches do not thaw it (bk_physics_body_set_pinned)
  bool reshaped = false; // its shape changed: its pairs' algorithms go before the next step
  // Parked: out of Bullet's world, its state kept (physics_settle.cpp); the
  // filter it goes back in with.
  bool parked = false;
  int park_group = 0, park_mask = 0;
  // Watched (a static body standing in for parked ones): disturbed when a
  // fast body comes near it or a neighbour is destroyed. Its collision
  // object's user index 2 is watched_tag meanwhile, for the near callback.
  bool watched = false, disturbed = false, undermined = false;
  double watch_speed = 0.0, watch_margin = 0.0;
  // Velocities and centre of mass at the start of the current substep.
  btVector3 linear_velocity{0, 0, 0}, angular_velocity{0, 0, 0}, center{0, 0, 0};
};

/// Slots with generations and a free list. `free_list` always has capacity
/// for every slot, so releasing never allocates (and never throws).
template <class Slot> struct SlotTable {
  std::vector<Slot> slots;
  std::vector<uint32_t> free_list;
  uint32_t live = 0;

  bool valid(uint32_t index, uint32_t generation) const {
    return generation != 0 && index < slots.size() && slots[index].generation == generation &&
           is_live(slots[index]);
  }
  static bool is_live(const ShapeSlot& s) { return s.shape != nullptr; }
  static bool is_live(const BodySlot& s) { return s.body != nullptr; }

  /// Returns a free slot index, reset to a default slot with its generation kept. May throw.
  uint32_t allocate() {
    uint32_t index;
    if (!free_list.empty()) {
      index = free_list.back();
      free_list.pop_back();
      uint32_t generation = slots[index].generation;
      slots[index] = Slot();
      slots[index].generation = generation;
    } else {
      if (slots.size() >= UINT32_MAX - 1) throw std::bad_alloc();
      slots.emplace_back();
      free_list.reserve(slots.size());
      index = (uint32_t)(slots.size() - 1);
    }
    ++live;
    return index;
  }
  void release(uint32_t index) {
    Slot& s = slots[index];
    uint32_t generation = s.generation + 1;
    s = Slot();
    s.generation = generation == 0 ? 1 : generation;
    free_list.push_back(index);
    --live;
  }
};

inline btVector3 to_bt(bk_vec3 v) { return btVector3((btScalar)v.x, (btScalar)v.y, (btScalar)v.z); }
inline bk_vec3 to_bk(const btVector3& v) { return bk_v3(v.x(), v.y(), v.z()); }

/// Zero quaternion means identity; others are normalized.
inline btQuaternion to_bt(bk_quat q) {
  if (q.x == 0.0 && q.y == 0.0 && q.z == 0.0 && q.w == 0.0) return btQuaternion::getIdentity();
  bk_quat n = bk_quat_normalize(q);
  return btQuaternion((btScalar)n.x, (btScalar)n.y, (btScalar)n.z, (btScalar)n.w);
}
inline btTransform to_bt(bk_transform t) { return btTransform(to_bt(t.rotation), to_bt(t.position)); }
inline bk_transform to_bk(const btTransform& t) {
  btQuaternion q = t.getRotation();
  return bk_transform{to_bk(t.getOrigin()), bk_quat{q.x(), q.y(), q.z(), q.w()}};
}

inline bool quat_is_finite(bk_quat q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
inline bool transform_is_finite(bk_transform t) {
  return bk_v3_is_finite(t.position) && quat_is_finite(t.rotation);
}

void freeze_calm_bodies(bk_physics* w);

// Bullet forms simulation islands from broadphase pairs, that is from
// overlapping fattened boxes: a field of debris becomes one island, and one
// shard still rocking anywhere keeps every other shard awake. Here islands
// are formed by manifolds that hold contact points, so each pile sleeps on
// its own. Waking is unchanged: a body that touches a sleeping one makes a
// contact, which joins the two islands, and an island with an awake member
// wakes as a whole.
class ContactIslandManager : public btSimulationIslandManager {
public:
  bk_physics* owner = nullptr;

  void updateActivationState(btCollisionWorld* world, btDispatcher* dispatcher) override {
    // Before the islands: frozen bodies count as static from here on.
    if (owner) freeze_calm_bodies(owner);
    btCollisionObjectArray& objects = world->getCollisionObjectArray();
    int index = 0;
    for (int i = 0; i < objects.size(); ++i) {
      btCollisionObject* object = objects[i];
      if (!object->isStaticOrKinematicObject()) object->setIslandTag(index++);
      object->setCompanionId(-1);
      object->setHitFraction(btScalar(1));
    }
    initUnionFind(index);
    for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
      const btCollisionObject* a = manifold->getBody0();
      const btCollisionObject* b = manifold->getBody1();
      if (manifold->getNumContacts() > 0 && a->mergesSimulationIslands() && b->mergesSimulationIslands())
        getUnionFind().unite(a->getIslandTag(), b->getIslandTag());
    }
  }
};

class World : public btDiscreteDynamicsWorld {
public:
  World(btDispatcher* dispatcher, btBroadphaseInterface* broadphase, btConstraintSolver* solver,
        btCollisionConfiguration* configuration)
      : btDiscreteDynamicsWorld(dispatcher, broadphase, solver, configuration) {
    // Replaced the way the base class made it, so that its destructor frees it.
    m_islandManager->~btSimulationIslandManager();
    btAlignedFree(m_islandManager);
    m_islandManager = new (btAlignedAlloc(sizeof(ContactIslandManager), 16)) ContactIslandManager();
  }
  /// The dynamic bodies Bullet integrates (removeRigidBody finds one by a
  /// linear search: bodies leaving by the thousand go through this instead).
  btAlignedObjectArray<btRigidBody*>& non_static_bodies() { return m_nonStaticRigidBodies; }
};

/// Creates the hull pair algorithm (physics_pairs.cpp) for pairs of hulls.
struct HullPairCreateFunc : public btCollisionAlgorithmCreateFunc {
  btGjkEpaPenetrationDepthSolver depth_solver;
  btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                 const btCollisionObjectWrapper* a,
                                                 const btCollisionObjectWrapper* b) override;
};

/// Bullet's defaults, with pool blocks that hold the hull pair algorithm (physics_pairs.cpp).
btDefaultCollisionConstructionInfo collision_info();

/// Counts the pairs that reach the narrowphase (a cost the world's physics
/// budget estimates from).
struct Dispatcher : public btCollisionDispatcher {
  explicit Dispatcher(btCollisionConfiguration* configuration) : btCollisionDispatcher(configuration) {}
  uint32_t narrow_pairs = 0;
  bk_physics* owner = nullptr; // for note_watched_pair
};

/// The user index 2 of a watched body's collision object.
constexpr int watched_tag = 1;
/// In the near callback, a pair with a watched body: disturbs it when the
/// other is a body moving faster than its watch speed (physics_settle.cpp).
void note_watched_pair(bk_physics* w, const btCollisionObject* a, const btCollisionObject* b);
/// A body is being destroyed: disturbs (if `disturb`) the watched bodies one
/// of whose compound's children it touched, whatever their filters (a
/// static support under a static stand-in has no pair with it), and forgets
/// it if it was watched (physics_settle.cpp).
void note_removed(bk_physics* w, uint32_t index, bool disturb);

/// Bullet's own group and mask test, counting the box overlaps the
/// broadphase finds (filtered or not): a moving box's tree query costs
/// about one per overlap, even when the pair is filtered out.
struct OverlapCounter : public btOverlapFilterCallback {
  mutable uint32_t tests = 0;
  bool needBroadphaseCollision(btBroadphaseProxy* a, btBroadphaseProxy* b) const override {
    ++tests;
    return (a->m_collisionFilterGroup & b->m_collisionFilterMask) != 0 &&
           (b->m_collisionFilterGroup & a->m_collisionFilterMask) != 0;
  }
};

/// Drops the pairs a filter change has ruled out and the algorithms of pairs
/// whose shape changed, in one walk over the pair cache (a walk per body
/// would cost the whole cache each time).
struct PairRefresh : public btOverlapCallback {
  btOverlappingPairCache* cache = nullptr;
  btDispatcher* dispatcher = nullptr;
  bool (*reshaped)(const void* user, const btBroadphaseProxy* proxy) = nullptr;
  const void* user = nullptr;
  bool processOverlap(btBroadphasePair& pair) override {
    if (!cache->needsBroadphaseCollision(pair.m_pProxy0, pair.m_pProxy1)) return true; // removed
    if (reshaped && (reshaped(user, pair.m_pProxy0) || reshaped(user, pair.m_pProxy1)))
      cache->cleanOverlappingPair(pair, dispatcher);
    return false;
  }
};

/// The user index of a body being removed (slot_of finds no slot for it).
constexpr int removing_index = -2;

} // namespace bk_bullet

// struct bk_physics is the C API's opaque type, in the global namespace; its
// members and the physics*.cpp files use the names above unqualified.
using namespace bk_bullet;

struct bk_physics {
  btDefaultCollisionConfiguration configuration{collision_info()};
  HullPairCreateFunc hull_pair_create;
  Dispatcher dispatcher{&configuration};
  OverlapCounter overlaps;
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  World world{&dispatcher, &broadphase, &solver, &configuration};

  SlotTable<ShapeSlot> shapes;
  SlotTable<BodySlot> bodies;

  bk_vec3 gravity = {0, 0, 0};
  double fixed_dt = default_fixed_dt;
  double margin = default_margin;
  double accumulator = 0.0; // simulated time not yet covered by a substep
  uint32_t contact_capacity = default_contact_capacity;
  uint32_t contact_total = 0;
  std::vector<bk_contact> contacts;
  // Bodies whose filter or shape changed since the last step (refresh_pairs).
  std::vector<uint32_t> changed_pairs, gained_pairs;
  bool any_reshaped = false;
  std::vector<uint32_t> watched_slots; // bodies watched (physics_settle.cpp), a few
  std::vector<int> removal_pairs;      // destroy_body_slot's scratch: the pairs of the body it removes

  BodySlot* body(bk_body_id id) {
    return bodies.valid(id.index, id.generation) ? &bodies.slots[id.index] : nullptr;
  }
  const BodySlot* body(bk_body_id id) const {
    return bodies.valid(id.index, id.generation) ? &bodies.slots[id.index] : nullptr;
  }
  ShapeSlot* shape(bk_shape_id id) {
    return shapes.valid(id.index, id.generation) ? &shapes.slots[id.index] : nullptr;
  }
  const ShapeSlot* shape(bk_shape_id id) const {
    return shapes.valid(id.index, id.generation) ? &shapes.slots[id.index] : nullptr;
  }

  /// Slot of a collision object created by bk_physics_create_body, or NULL.
  BodySlot* slot_of(const btCollisionObject* object) {
    return const_cast<BodySlot*>(static_cast<const bk_physics*>(this)->slot_of(object));
  }
  const BodySlot* slot_of(const btCollisionObject* object) const {
    int index = object->getUserIndex();
    if (index < 0 || (size_t)index >= bodies.slots.size() || bodies.slots[(size_t)index].body != object)
      return nullptr;
    return &bodies.slots[(size_t)index];
  }
  bk_body_id id_of(const BodySlot* slot) const {
    return bk_body_id{(uint32_t)(slot - bodies.slots.data()), slot->generation};
  }

  bk_shape_id add_shape(btCollisionShape* bt_shape, ShapeKind kind, double inner_radius) {
    uint32_t index;
    try {
      index = shapes.allocate();
    } catch (...) {
      delete bt_shape;
      return bk_shape_id{0, 0};
    }
    ShapeSlot& s = shapes.slots[index];
    s.shape = bt_shape;
    s.kind = kind;
    s.inner_radius = inner_radius;
    return bk_shape_id{index, s.generation};
  }

  // Contacts, gathered in the tick callbacks (physics.cpp).
  void snapshot_velocities();
  void collect_contacts();

  // A calm body is frozen: zero mass and Bullet's static flag, so islands,
  // the solver and the narrowphase treat it like the ground until a
  // restless body touches it. Bullet sleeps whole islands only, and in a
  // heap of debris some shard always rocks: ~15 restless shards kept ~560
  // of ~1340 bodies awake 13 s after the last shot. Frozen, calm shards stop
  // costing anything, and what rests on them is held as by the ground.
  static bool frozen(const BodySlot& s) { return s.mass > 0.0 && s.body->isStaticObject(); }

  void freeze(BodySlot& s) {
    s.body->setLinearVelocity(btVector3(0, 0, 0));
    s.body->setAngularVelocity(btVector3(0, 0, 0));
    s.body->setMassProps(0, btVector3(0, 0, 0)); // also sets CF_STATIC_OBJECT
    s.body->updateInertiaTensor();
    s.body->forceActivationState(ISLAND_SLEEPING);
  }

  /// `moving`: restless at once (its support went), not just awake.
  void thaw(BodySlot& s, bool moving = false) {
    if (!frozen(s) || s.pinned) return;
    s.body->setMassProps((btScalar)s.mass, s.inertia); // clears CF_STATIC_OBJECT
    s.body->updateInertiaTensor();
    s.body->setGravity(world.getGravity()); // it may have changed meanwhile
    // Awake but calm, as Bullet wakes an island: it becomes restless (and
    // wakes what it touches) only if it is really pushed.
    s.body->forceActivationState(moving ? ACTIVE_TAG : WANTS_DEACTIVATION);
    s.body->setDeactivationTime(0);
  }

  static bool restless(const btCollisionObject* o) {
    return o->getActivationState() == ACTIVE_TAG || o->getActivationState() == DISABLE_DEACTIVATION;
  }

  /// Thaws frozen bodies touched by restless ones, then freezes bodies calm
  /// for freeze_time (or put to sleep with their island).
  void freeze_calm_bodies() {
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
      if (manifold->getNumContacts() == 0) continue;
      BodySlot* a = slot_of(manifold->getBody0());
      BodySlot* b = slot_of(manifold->getBody1());
      if (a && frozen(*a) && restless(manifold->getBody1())) thaw(*a);
      if (b && frozen(*b) && restless(manifold->getBody0())) thaw(*b);
    }
    const btCollisionObjectArray& objects = world.getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) {
      BodySlot* s = slot_of(objects[i]);
      if (!s || s->mass == 0.0 || frozen(*s)) continue;
      int state = s->body->getActivationState();
      if (state == ISLAND_SLEEPING ||
          (state == WANTS_DEACTIVATION && s->body->getDeactivationTime() >= freeze_time))
        freeze(*s);
    }
  }

  /// Debris collides with everything but other debris (Bullet's filter
  /// groups); the other values are Bullet's defaults for the body's kind.
  static void filter_of(bool debris, bool dynamic, int* group, int* mask) {
    if (debris) {
      *group = btBroadphaseProxy::DebrisFilter;
      *mask = btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::DebrisFilter;
    } else if (dynamic) {
      *group = btBroadphaseProxy::DefaultFilter;
      *mask = btBroadphaseProxy::AllFilter;
    } else {
      *group = btBroadphaseProxy::StaticFilter;
      *mask = btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter;
    }
  }

  static bool is_debris(const BodySlot& s) {
    if (s.parked) return s.park_group == btBroadphaseProxy::DebrisFilter; // the filter it goes back with
    const btBroadphaseProxy* proxy = s.body->getBroadphaseHandle();
    return proxy && proxy->m_collisionFilterGroup == btBroadphaseProxy::DebrisFilter;
  }

  void set_debris(BodySlot& s, bool debris) {
    if (s.parked) {
      filter_of(debris, s.mass > 0.0, &s.park_group, &s.park_mask);
      return;
    }
    btBroadphaseProxy* proxy = s.body->getBroadphaseHandle();
    if (!proxy || is_debris(s) == debris) return;
    filter_of(debris, s.mass > 0.0, &proxy->m_collisionFilterGroup, &proxy->m_collisionFilterMask);
    // Leaving debris, its pairs with other debris are found again (the
    // broadphase only looks for new pairs when a box moves), and it wakes:
    // two sleepers keep no contacts, and it may lie inside other debris.
    (debris ? changed_pairs : gained_pairs).push_back((uint32_t)(&s - bodies.slots.data()));
    if (!debris && s.mass > 0.0) {
      thaw(s);
      if (!s.pinned) s.body->activate(true);
    }
  }

  void set_shape(BodySlot& s, uint32_t shape_index) {
    --shapes.slots[s.shape].uses;
    ++shapes.slots[shape_index].uses;
    s.shape = shape_index;
    s.body->setCollisionShape(shapes.slots[shape_index].shape);
    if (!s.parked) world.updateSingleAabb(s.body); // a parked body has no box till it is back
    s.reshaped = true;
    any_reshaped = true;
    changed_pairs.push_back((uint32_t)(&s - bodies.slots.data()));
  }

  /// Before a step (physics.cpp).
  void refresh_pairs();

  /// One body, leaving the pair cache exactly as Bullet's removal does: the
  /// order of the pairs left, and with it every later step, is the one the
  /// scenes and their numbers were made with. Bullet walks the whole cache
  /// twice (cleanProxyFromPairs frees the pairs' algorithms in array order;
  /// removeOverlappingPairsContainingProxy then removes them, each taking
  /// the last pair's place), and waking the neighbours took a third walk: a
  /// split's removal cost 0.1-0.2 ms among tens of thousands of pairs. Here
  /// one walk finds the body's pairs and wakes its neighbours; the same
  /// frees and removals follow on those pairs alone, in Bullet's order; and
  /// Bullet removes the body with a pair cache holding nothing of it. Many
  /// bodies at once go through destroy_body_slots.
  void destroy_body_slot(uint32_t index) {
    BodySlot& s = bodies.slots[index];
    btOverlappingPairCache* cache = broadphase.m_paircache;
    btBroadphasePairArray& pairs = cache->getOverlappingPairArray();
    const btBroadphaseProxy* proxy = s.body->getBroadphaseHandle();
    bool listed = true; // every pair of the body is in removal_pairs
    removal_pairs.clear();
    for (int i = 0; i < pairs.size(); ++i) {
      const btBroadphaseProxy* p0 = pairs[i].m_pProxy0;
      const btBroadphaseProxy* p1 = pairs[i].m_pProxy1;
      if (p0 != proxy && p1 != proxy) continue;
      // What rested on it falls. Frozen pairs keep no manifold (see
      // near_callback), so the neighbours are the broadphase's.
      const void* other = (p0 == proxy ? p1 : p0)->m_clientObject;
      BodySlot* neighbour = slot_of(static_cast<const btCollisionObject*>(other));
      if (neighbour) thaw(*neighbour, true);
      try {
        if (listed) removal_pairs.push_back(i);
      } catch (...) {
        listed = false; // out of memory: Bullet's own walks remove its pairs
      }
    }
    if (!listed) removal_pairs.clear();
    for (int i : removal_pairs)
      cache->cleanOverlappingPair(pairs[i], &dispatcher);
    // Bullet's walk: at each of the body's pairs, ascending, the pair goes
    // and the last one takes its place, to be looked at again. A pair of the
    // body past the end by then has been moved down and removed already.
    for (int i : removal_pairs)
      while (i < pairs.size() && (pairs[i].m_pProxy0 == proxy || pairs[i].m_pProxy1 == proxy))
        cache->removeOverlappingPair(pairs[i].m_pProxy0, pairs[i].m_pProxy1, &dispatcher);
    btNullPairCache emptied;
    if (listed) broadphase.m_paircache = &emptied;
    // A slot waiting for refresh_pairs is skipped there once released.
    s.reshaped = false;
    note_removed(this, index, true);
    if (!s.parked) world.removeRigidBody(s.body);
    broadphase.m_paircache = cache;
    delete s.body;
    --shapes.slots[s.shape].uses;
    bodies.release(index);
  }

  /// Removes bodies from the world with one walk over the pair cache for
  /// all of them. Bullet walks the whole cache twice per body it removes
  /// (cleanProxyFromPairs, then the broadphase's
  /// removeOverlappingPairsContainingProxy), and waking the neighbours took
  /// a third: a step that retires hundreds of pieces paid hundreds of walks.
  /// Here the bodies are marked, one walk drops their pairs and wakes what
  /// touched them (`wake_neighbours`: off when the whole world goes), and
  /// Bullet removes them with a pair cache that holds nothing left to drop.
  void destroy_body_slots(const uint32_t* indices, uint32_t count, bool wake_neighbours = true) {
    if (count == 0) return;
    for (uint32_t i = 0; i < count; ++i)
      bodies.slots[indices[i]].body->setUserIndex(removing_index);
    struct DropPairs : public btOverlapCallback {
      bk_physics* w = nullptr;
      bool wake = true;
      bool processOverlap(btBroadphasePair& pair) override {
        const auto* a = static_cast<const btCollisionObject*>(pair.m_pProxy0->m_clientObject);
        const auto* b = static_cast<const btCollisionObject*>(pair.m_pProxy1->m_clientObject);
        bool gone_a = a->getUserIndex() == removing_index, gone_b = b->getUserIndex() == removing_index;
        if (!gone_a && !gone_b) return false;
        // What rested on it falls. Frozen pairs keep no manifold (see
        // near_callback), so the neighbours are the broadphase's.
        BodySlot* neighbour = w->slot_of(gone_a ? b : a); // null when both go
        if (wake && neighbour) w->thaw(*neighbour, true);
        return true; // removed, its algorithm and manifold freed
      }
    } drop;
    drop.w = this;
    drop.wake = wake_neighbours;
    btOverlappingPairCache* cache = broadphase.m_paircache;
    cache->processAllOverlappingPairs(&drop, &dispatcher);
    btNullPairCache emptied;
    broadphase.m_paircache = &emptied;
    for (uint32_t i = 0; i < count; ++i) {
      BodySlot& s = bodies.slots[indices[i]];
      // A slot waiting for refresh_pairs is skipped there once released.
      s.reshaped = false;
      note_removed(this, indices[i], wake_neighbours);
      if (!s.parked) world.removeRigidBody(s.body);
      delete s.body;
      --shapes.slots[s.shape].uses;
      bodies.release(indices[i]);
    }
    broadphase.m_paircache = cache;
  }

  void destroy_shape_slot(uint32_t index) {
    ShapeSlot& s = shapes.slots[index];
    for (uint32_t child : s.children)
      --shapes.slots[child].uses;
    delete s.shape;
    shapes.release(index);
  }
};
