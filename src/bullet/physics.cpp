// bk_physics: the C interface of <breakables/bullet.h> implemented over Bullet (single
// precision). This is the only translation unit that includes Bullet.
//
// Ids index slot tables; a slot's generation moves on when its object is
// destroyed, so stale ids are detected and ignored. Contacts are gathered in
// Bullet's internal tick callbacks (one pair of calls per substep) and kept
// as a plain array until the next step.
#include <breakables/bullet.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <vector>

#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <LinearMath/btConvexHull.h>
#include <LinearMath/btConvexHullComputer.h>
#include <btBulletDynamicsCommon.h>

namespace {

const double default_gravity_y = -9.81;
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
const double default_friction = 0.6;
const double default_restitution = 0.1;
const uint32_t max_hull_vertices = 64;

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

btVector3 to_bt(bk_vec3 v) { return btVector3((btScalar)v.x, (btScalar)v.y, (btScalar)v.z); }
bk_vec3 to_bk(const btVector3& v) { return bk_v3(v.x(), v.y(), v.z()); }

/// Zero quaternion means identity; others are normalized.
btQuaternion to_bt(bk_quat q) {
  if (q.x == 0.0 && q.y == 0.0 && q.z == 0.0 && q.w == 0.0) return btQuaternion::getIdentity();
  bk_quat n = bk_quat_normalize(q);
  return btQuaternion((btScalar)n.x, (btScalar)n.y, (btScalar)n.z, (btScalar)n.w);
}
btTransform to_bt(bk_transform t) { return btTransform(to_bt(t.rotation), to_bt(t.position)); }
bk_transform to_bk(const btTransform& t) {
  btQuaternion q = t.getRotation();
  return bk_transform{to_bk(t.getOrigin()), bk_quat{q.x(), q.y(), q.z(), q.w()}};
}

bool quat_is_finite(bk_quat q) {
  return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
}
bool transform_is_finite(bk_transform t) { return bk_v3_is_finite(t.position) && quat_is_finite(t.rotation); }

/// Exact convex hull of points (double precision): volume, vertex count and the
/// distance from the origin to the nearest face plane (negative when the
/// origin is outside). Flat or degenerate input gives volume 0.
struct HullInfo {
  double volume = 0.0;
  double inner_radius = 0.0;
  std::vector<uint32_t> vertices; // indices into the input of the hull's vertices
};

HullInfo analyze_hull(const double* xyz, uint32_t count) {
  HullInfo info;
  if (count < 4 || count > (uint32_t)std::numeric_limits<int>::max()) return info;
  btConvexHullComputer hc;
  hc.compute(xyz, 3 * (int)sizeof(double), (int)count, 0, 0);
  int nv = hc.vertices.size();
  if (nv < 4 || hc.original_vertex_index.size() != nv) return info;
  info.vertices.reserve((size_t)nv);
  bk_vec3 ref = bk_v3(0, 0, 0);
  auto point = [&](int v) {
    const double* p = xyz + 3 * (size_t)hc.original_vertex_index[v];
    return bk_v3(p[0], p[1], p[2]);
  };
  for (int v = 0; v < nv; ++v) {
    info.vertices.push_back((uint32_t)hc.original_vertex_index[v]);
    ref = bk_v3_add(ref, point(v));
  }
  ref = bk_v3_scale(ref, 1.0 / nv);

  // Faces are polygons; fan them from their first vertex. Each face also
  // gives a plane (Newell normal) for the inner radius.
  double volume6 = 0.0, min_distance = INFINITY;
  for (int f = 0; f < hc.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &hc.edges[hc.faces[f]];
    bk_vec3 a = point(first->getSourceVertex());
    bk_vec3 normal = bk_v3(0, 0, 0);
    const btConvexHullComputer::Edge* e = first;
    do {
      bk_vec3 p = point(e->getSourceVertex()), q = point(e->getTargetVertex());
      normal = bk_v3_add(normal, bk_v3_cross(p, q));
      e = e->getNextEdgeOfFace();
    } while (e != first);
    e = first->getNextEdgeOfFace();
    bk_vec3 b = point(e->getSourceVertex());
    for (e = e->getNextEdgeOfFace(); e != first; e = e->getNextEdgeOfFace()) {
      bk_vec3 c = point(e->getSourceVertex());
      volume6 += bk_v3_dot(bk_v3_sub(a, ref), bk_v3_cross(bk_v3_sub(b, ref), bk_v3_sub(c, ref)));
      b = c;
    }
    double length = bk_v3_length(normal);
    if (length > 0.0) min_distance = fmin(min_distance, bk_v3_dot(normal, a) / length);
  }
  // Bullet lists face edges counter-clockwise seen from outside, so the
  // volume is positive; guard against the opposite order anyway.
  double sign = volume6 < 0.0 ? -1.0 : 1.0;
  info.volume = fabs(volume6) / 6.0;
  info.inner_radius = std::isfinite(min_distance) ? sign * min_distance : 0.0;
  return info;
}

HullInfo analyze_hull(const std::vector<btVector3>& points) {
  std::vector<double> xyz;
  xyz.reserve(points.size() * 3);
  for (const btVector3& p : points) {
    xyz.push_back(p.x());
    xyz.push_back(p.y());
    xyz.push_back(p.z());
  }
  return analyze_hull(xyz.data(), (uint32_t)points.size());
}

/// At most max_vertices of the hull vertices, chosen by Bullet's incremental
/// hull builder (it adds the farthest point first until the limit).
std::vector<btVector3> simplify_hull(const std::vector<btVector3>& points, uint32_t max_vertices) {
  HullDesc desc(QF_TRIANGLES, (unsigned)points.size(), points.data(), sizeof(btVector3));
  desc.mMaxVertices = max_vertices;
  HullLibrary library;
  HullResult result;
  std::vector<btVector3> out;
  if (library.CreateConvexHull(desc, result) == QE_OK) {
    for (unsigned i = 0; i < result.mNumOutputVertices && i < max_vertices; ++i)
      out.push_back(result.m_OutputVertices[(int)i]);
  }
  library.ReleaseResult(result);
  return out;
}

} // namespace

namespace {

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
};

// Pairs of hulls that are apart skip the narrowphase while they provably stay
// apart. In a heap of debris most broadphase pairs are close but not touching
// (in a 40-shot showcase, 78% of the pairs tested each substep held no
// contact point), and each paid for a full GJK query every substep. When a
// query finds no contact, the gap along its separating axis is kept together
// with the pair's relative pose. While the relative motion since then (the
// translation plus the rotation's chord times the hull's radius) is smaller
// than the gap less the contact threshold, no contact can have appeared and
// the query is skipped. When the motion has used the gap up, the gap is
// measured again along the same axis (two support points) before a full query
// runs. Touching pairs always take the full query, so contacts are exactly
// Bullet's. (Bullet has a similar cache, btConvexSeparatingDistanceUtil,
// compiled out.)
class HullPairAlgorithm : public btActivatingCollisionAlgorithm {
public:
  HullPairAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* a,
                    const btCollisionObjectWrapper* b, btConvexPenetrationDepthSolver* depth_solver)
      : btActivatingCollisionAlgorithm(ci, a, b), manifold_(ci.m_manifold), depth_solver_(depth_solver),
        // Where Bullet's manifold drops a point (btCollisionDispatcher::getNewManifold);
        // bodies never change shape.
        threshold_(btMin(a->getCollisionObject()->getCollisionShape()->getContactBreakingThreshold(
                             gContactBreakingThreshold),
                         b->getCollisionObject()->getCollisionShape()->getContactBreakingThreshold(
                             gContactBreakingThreshold))) {}

  ~HullPairAlgorithm() override { release_manifold(); }

  void processCollision(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b,
                        const btDispatcherInfo& info, btManifoldResult* out) override {
    const btConvexShape* shape_a = static_cast<const btConvexShape*>(a->getCollisionShape());
    const btConvexShape* shape_b = static_cast<const btConvexShape*>(b->getCollisionShape());
    const btTransform& pose_a = a->getWorldTransform();
    const btTransform relative = pose_a.inverseTimes(b->getWorldTransform());
    const btScalar threshold = threshold_ + out->m_closestPointDistanceThreshold + tolerance;

    // The pose kept below is B's in A's frame: it is only meaningful when the
    // pair comes in the same order as when it was kept.
    // A pair known to be apart has no manifold (released below).
    bool known = a->getCollisionShape() == first_shape_ && a->getCollisionObject() == first_object_;
    if (known && gap_ > threshold) {
      if (gap_ - motion_since(relative) > threshold) return;
      btScalar gap = gap_along(axis_, relative, shape_a, shape_b);
      if (gap > threshold) {
        gap_ = gap;
        reference_ = relative;
        return;
      }
    }

    if (!manifold_) {
      manifold_ = m_dispatcher->getNewManifold(a->getCollisionObject(), b->getCollisionObject());
      own_manifold_ = true;
    }
    out->setPersistentManifold(manifold_);
    btVoronoiSimplexSolver simplex;
    btGjkPairDetector gjk(shape_a, shape_b, &simplex, depth_solver_);
    btGjkPairDetector::ClosestPointInput input;
    btScalar reach =
        shape_a->getMargin() + shape_b->getMargin() + threshold_ + out->m_closestPointDistanceThreshold;
    input.m_maximumDistanceSquared = reach * reach;
    input.m_transformA = pose_a;
    input.m_transformB = b->getWorldTransform();
    gjk.getClosestPoints(input, *out, info.m_debugDraw);
    if (own_manifold_) out->refreshContactPoints();

    if (!known) {
      first_shape_ = a->getCollisionShape();
      first_object_ = a->getCollisionObject();
      btVector3 lo, hi;
      shape_b->getAabb(btTransform::getIdentity(), lo, hi);
      btVector3 corner = lo.absolute();
      corner.setMax(hi.absolute());
      radius_b_ = corner.length();
    }
    gap_ = 0;
    if (!own_manifold_ || manifold_->getNumContacts() > 0) return;

    // GJK's axis points from B towards A; measure the gap along it from A.
    btVector3 v = gjk.getCachedSeparatingAxis();
    if (!(v.length2() > SIMD_EPSILON)) return;
    btVector3 axis = -(v * pose_a.getBasis()).normalized();
    btScalar gap = gap_along(axis, relative, shape_a, shape_b);
    if (!(gap > threshold)) return;
    axis_ = axis;
    gap_ = gap;
    reference_ = relative;
    // An empty manifold would still be walked by the islands, the solver and
    // the contact report every substep.
    release_manifold();
  }

  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return btScalar(1); // continuous collision is the world's swept-sphere test
  }

  void getAllContactManifolds(btManifoldArray& manifolds) override {
    if (manifold_ && own_manifold_) manifolds.push_back(manifold_);
  }

private:
  // Single-precision rounding of the support points and the poses.
  static constexpr btScalar tolerance = btScalar(1e-5);

  /// Lower bound of the distance between the two surfaces: the gap between
  /// their extents along `axis` (unit, in A's frame, pointing from A to B).
  static btScalar gap_along(const btVector3& axis, const btTransform& relative, const btConvexShape* a,
                            const btConvexShape* b) {
    btScalar far_a = axis.dot(a->localGetSupportVertexWithoutMarginNonVirtual(axis));
    btVector3 axis_in_b = axis * relative.getBasis();
    btScalar near_b = axis_in_b.dot(b->localGetSupportVertexWithoutMarginNonVirtual(-axis_in_b)) +
                      axis.dot(relative.getOrigin());
    return near_b - far_a - a->getMarginNonVirtual() - b->getMarginNonVirtual();
  }

  /// Farthest any point of B has moved relative to A since the gap was measured.
  btScalar motion_since(const btTransform& relative) const {
    const btMatrix3x3& r = relative.getBasis();
    const btMatrix3x3& r0 = reference_.getBasis();
    // |(R - R0) p| <= 2 sin(angle / 2) |p|, and ||R - R0||_F = 2 sqrt(2) sin(angle / 2).
    btScalar frobenius2 = (r[0] - r0[0]).length2() + (r[1] - r0[1]).length2() + (r[2] - r0[2]).length2();
    btScalar chord = btSqrt(btScalar(0.5) * frobenius2);
    return (relative.getOrigin() - reference_.getOrigin()).length() + chord * radius_b_;
  }

  void release_manifold() {
    if (!own_manifold_) return; // a shared manifold stays with its owner
    m_dispatcher->releaseManifold(manifold_);
    manifold_ = nullptr;
    own_manifold_ = false;
  }

  btPersistentManifold* manifold_ = nullptr;
  bool own_manifold_ = false;
  btConvexPenetrationDepthSolver* depth_solver_ = nullptr;
  btScalar threshold_ = 0;
  btScalar gap_ = 0; // lower bound of the distance at reference_ (0: touching or unknown)
  btScalar radius_b_ = 0;
  btVector3 axis_{0, 0, 0};
  btTransform reference_ = btTransform::getIdentity();
  const btCollisionShape* first_shape_ = nullptr;
  const btCollisionObject* first_object_ = nullptr;
};

struct HullPairCreateFunc : public btCollisionAlgorithmCreateFunc {
  btGjkEpaPenetrationDepthSolver depth_solver;
  btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                 const btCollisionObjectWrapper* a,
                                                 const btCollisionObjectWrapper* b) override {
    void* memory = ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(HullPairAlgorithm));
    return new (memory) HullPairAlgorithm(ci, a, b, &depth_solver);
  }
};

btDefaultCollisionConstructionInfo collision_info() {
  btDefaultCollisionConstructionInfo info;
  // The algorithm pool's blocks must hold the hull pair algorithm too.
  info.m_customCollisionAlgorithmMaxElementSize = (int)sizeof(HullPairAlgorithm);
  return info;
}

/// Counts the pairs that reach the narrowphase (a cost the world's physics
/// budget estimates from).
struct Dispatcher : public btCollisionDispatcher {
  explicit Dispatcher(btCollisionConfiguration* configuration) : btCollisionDispatcher(configuration) {}
  uint32_t narrow_pairs = 0;
};

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

} // namespace

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

  void snapshot_velocities() {
    const btCollisionObjectArray& objects = world.getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) {
      BodySlot* s = slot_of(objects[i]);
      if (!s) continue;
      s->linear_velocity = s->body->getLinearVelocity();
      s->angular_velocity = s->body->getAngularVelocity();
      s->center = s->body->getCenterOfMassPosition();
    }
  }

  static bk_vec3 point_velocity(const BodySlot& s, bk_vec3 point) {
    bk_vec3 arm = bk_v3_sub(point, to_bk(s.center));
    return bk_v3_add(to_bk(s.linear_velocity), bk_v3_cross(to_bk(s.angular_velocity), arm));
  }

  /// Records every contact point the solver just pushed on. Manifolds whose
  /// bodies are all asleep or static were not solved this substep (their
  /// impulses are stale) and are skipped.
  void collect_contacts() {
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
        // Bullet's normal on B points from B towards A, as bk_contact wants.
        c.normal = to_bk(pt.m_normalWorldOnB);
        if (pt.m_localPointA.isZero() && o0->getCcdSweptSphereRadius() > 0) {
          // A predictive (CCD) contact: Bullet stores A's centre and the
          // centre of A's swept sphere at impact; use where that sphere touches B.
          c.point = bk_v3_sub(to_bk(pt.getPositionWorldOnB()),
                              bk_v3_scale(c.normal, o0->getCcdSweptSphereRadius()));
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
    const btBroadphaseProxy* proxy = s.body->getBroadphaseHandle();
    return proxy && proxy->m_collisionFilterGroup == btBroadphaseProxy::DebrisFilter;
  }

  void set_debris(BodySlot& s, bool debris) {
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
    world.updateSingleAabb(s.body);
    s.reshaped = true;
    any_reshaped = true;
    changed_pairs.push_back((uint32_t)(&s - bodies.slots.data()));
  }

  static bool reshaped_proxy(const void* user, const btBroadphaseProxy* proxy) {
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

  /// Before a step: one walk over the pair cache for every filter and shape
  /// changed since the last, then a tree query per body that left debris.
  void refresh_pairs() {
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

  /// `wake_neighbours`: off when the whole world goes (the walk below is
  /// over every pair, once per body).
  void destroy_body_slot(uint32_t index, bool wake_neighbours = true) {
    BodySlot& s = bodies.slots[index];
    // What rested on it falls. Frozen pairs keep no manifold (see
    // near_callback), so the neighbours are the broadphase's.
    const btBroadphasePairArray& pairs = broadphase.getOverlappingPairCache()->getOverlappingPairArray();
    for (int i = 0; wake_neighbours && i < pairs.size(); ++i) {
      const void* a = pairs[i].m_pProxy0->m_clientObject;
      const void* b = pairs[i].m_pProxy1->m_clientObject;
      const void* other = a == s.body ? b : b == s.body ? a : nullptr;
      BodySlot* neighbour = other ? slot_of(static_cast<const btCollisionObject*>(other)) : nullptr;
      if (neighbour) thaw(*neighbour, true);
    }
    // A slot waiting for refresh_pairs is skipped there once released.
    s.reshaped = false;
    world.removeRigidBody(s.body);
    delete s.body;
    --shapes.slots[s.shape].uses;
    bodies.release(index);
  }

  void destroy_shape_slot(uint32_t index) {
    ShapeSlot& s = shapes.slots[index];
    for (uint32_t child : s.children)
      --shapes.slots[child].uses;
    delete s.shape;
    shapes.release(index);
  }
};

namespace {

void pre_tick(btDynamicsWorld* world, btScalar) {
  static_cast<bk_physics*>(world->getWorldUserInfo())->snapshot_velocities();
}

void freeze_calm_bodies(bk_physics* w) { w->freeze_calm_bodies(); }

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
  // Two sleepers (frozen, asleep or static) keep no manifold: thousands of
  // them in a settled heap were walked every step by the island builder and
  // the contact report. Contacts come back within a step of a wake.
  if (!static_cast<const btCollisionObject*>(a->m_clientObject)->isActive() &&
      !static_cast<const btCollisionObject*>(b->m_clientObject)->isActive()) {
    free_algorithm(pair, dispatcher);
    return;
  }
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
  for (uint32_t i = 0; i < w->bodies.slots.size(); ++i)
    if (w->bodies.slots[i].body) w->destroy_body_slot(i, false);
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

// ---------------------------------------------------------------- shapes

bk_shape_id bk_physics_create_hull(bk_physics* w, const bk_vec3* points, uint32_t count,
                                   uint32_t max_vertices) {
  const bk_shape_id null_id = {0, 0};
  if (!w || !points || count < 4) return null_id;
  for (uint32_t i = 0; i < count; ++i)
    if (!bk_v3_is_finite(points[i])) return null_id;
  if (max_vertices == 0 || max_vertices > max_hull_vertices) max_vertices = max_hull_vertices;
  if (max_vertices < 4) max_vertices = 4;
  try {
    static_assert(sizeof(bk_vec3) == 3 * sizeof(double), "bk_vec3 must be three packed doubles");
    HullInfo exact = analyze_hull(&points[0].x, count);
    if (exact.vertices.size() < 4) return null_id;
    std::vector<btVector3> vertices;
    vertices.reserve(exact.vertices.size());
    for (uint32_t v : exact.vertices)
      vertices.push_back(to_bt(points[v]));
    if (vertices.size() > max_vertices) vertices = simplify_hull(vertices, max_vertices);

    // Judge flatness on the single-precision vertices Bullet will use.
    HullInfo final_hull = analyze_hull(vertices);
    btVector3 lo = vertices.empty() ? btVector3(0, 0, 0) : vertices[0], hi = lo;
    for (const btVector3& p : vertices) {
      lo.setMin(p);
      hi.setMax(p);
    }
    double extent = (hi - lo).length();
    if (final_hull.vertices.size() < 4 || !(final_hull.volume > 1e-9 * extent * extent * extent))
      return null_id;
    // Rounding to float may have pushed a nearly coplanar vertex inside.
    std::vector<btVector3> kept;
    kept.reserve(final_hull.vertices.size());
    for (uint32_t v : final_hull.vertices)
      kept.push_back(vertices[v]);
    vertices.swap(kept);

    // Shrink the hull by the collision margin so its rounded surface is the
    // fragment's own. Fragments share faces exactly: unshrunk, neighbouring
    // cores would touch at distance zero, and every such pair would take
    // Bullet's slow penetration-depth path (EPA) instead of GJK. The clamp
    // keeps slivers from collapsing; the margin becomes the actual shrink.
    double margin = w->margin;
    if (margin > 0.0) {
      btConvexHullComputer shrunk;
      btScalar applied = shrunk.compute(&vertices[0].x(), (int)sizeof(btVector3), (int)vertices.size(),
                                        (btScalar)margin, (btScalar)0.3);
      if (applied > 0 && shrunk.vertices.size() >= 4) {
        vertices.assign(&shrunk.vertices[0], &shrunk.vertices[0] + shrunk.vertices.size());
        margin = applied;
        // Moving faces inward splits corners where more than three faces
        // meet; keep the vertex budget (the result stays inside the core).
        if (vertices.size() > max_vertices) vertices = simplify_hull(vertices, max_vertices);
      }
    }
    btConvexHullShape* hull =
        new btConvexHullShape(&vertices[0].x(), (int)vertices.size(), sizeof(btVector3));
    hull->setMargin((btScalar)margin);
    // The constructor cached the bounds with Bullet's default 4 cm margin;
    // stale, they made every fragment overlap dozens of neighbours.
    hull->recalcLocalAabb();
    double inner =
        final_hull.inner_radius > 0.0 ? final_hull.inner_radius : 0.25 * (hi - lo)[(hi - lo).minAxis()];
    bk_shape_id id = w->add_shape(hull, ShapeKind::hull, inner);
    ShapeSlot* slot = w->shape(id);
    if (slot) slot->hull_volume = final_hull.volume;
    return id;
  } catch (...) {
    return null_id;
  }
}

bk_shape_id bk_physics_create_sphere(bk_physics* w, double radius) {
  if (!w || !(std::isfinite(radius) && radius > 0.0)) return bk_shape_id{0, 0};
  return w->add_shape(new btSphereShape((btScalar)radius), ShapeKind::sphere, radius);
}

bk_shape_id bk_physics_create_box(bk_physics* w, bk_vec3 half_extents) {
  bk_vec3 h = half_extents;
  if (!w || !bk_v3_is_finite(h) || !(h.x > 0.0 && h.y > 0.0 && h.z > 0.0)) return bk_shape_id{0, 0};
  double smallest = fmin(h.x, fmin(h.y, h.z));
  btBoxShape* box = new btBoxShape(to_bt(h));
  // Bullet keeps the box's outer size and puts the margin inside it, so the
  // margin must stay below the smallest half extent.
  box->setMargin((btScalar)fmin(w->margin, 0.5 * smallest));
  return w->add_shape(box, ShapeKind::box, smallest);
}

bk_shape_id bk_physics_create_plane(bk_physics* w, bk_vec3 normal, double offset) {
  double length = bk_v3_length(normal);
  if (!w || !bk_v3_is_finite(normal) || !std::isfinite(offset) || !(length > 0.0 && std::isfinite(length)))
    return bk_shape_id{0, 0};
  btStaticPlaneShape* plane =
      new btStaticPlaneShape(to_bt(bk_v3_scale(normal, 1.0 / length)), (btScalar)(offset / length));
  return w->add_shape(plane, ShapeKind::plane, 0.0);
}

bk_shape_id bk_physics_create_compound(bk_physics* w, uint32_t expected_children) {
  if (!w) return bk_shape_id{0, 0};
  int capacity = expected_children < 1024 ? (int)expected_children : 1024;
  return w->add_shape(new btCompoundShape(true, capacity), ShapeKind::compound, 0.0);
}

void bk_physics_compound_add(bk_physics* w, bk_shape_id compound, bk_shape_id child, bk_transform local) {
  if (!w) return;
  ShapeSlot* parent = w->shape(compound);
  ShapeSlot* c = w->shape(child);
  // Children are convex (planes are infinite; nested compounds are not supported).
  if (!parent || !c || parent->kind != ShapeKind::compound || c->kind == ShapeKind::plane ||
      c->kind == ShapeKind::compound || !transform_is_finite(local))
    return;
  try {
    parent->children.push_back(child.index);
  } catch (...) {
    return;
  }
  ++c->uses;
  static_cast<btCompoundShape*>(parent->shape)->addChildShape(to_bt(local), c->shape);
}

void bk_physics_destroy_shape(bk_physics* w, bk_shape_id shape) {
  if (!w) return;
  ShapeSlot* s = w->shape(shape);
  // A shape still used by a body or a compound is left alone (destroying it
  // would leave them pointing at freed memory).
  if (!s || s->uses > 0) return;
  w->destroy_shape_slot(shape.index);
}

bool bk_physics_shape_valid(const bk_physics* w, bk_shape_id shape) { return w && w->shape(shape); }

uint32_t bk_physics_hull_vertices(const bk_physics* w, bk_shape_id hull, bk_vec3* out, uint32_t capacity) {
  const ShapeSlot* s = w ? w->shape(hull) : nullptr;
  if (!s || s->kind != ShapeKind::hull) return 0;
  const btConvexHullShape* shape = static_cast<const btConvexHullShape*>(s->shape);
  uint32_t n = (uint32_t)shape->getNumPoints();
  for (uint32_t i = 0; out && i < n && i < capacity; ++i)
    out[i] = to_bk(shape->getUnscaledPoints()[i]);
  return n;
}

double bk_physics_hull_volume(const bk_physics* w, bk_shape_id hull) {
  const ShapeSlot* s = w ? w->shape(hull) : nullptr;
  if (!s || s->kind != ShapeKind::hull) return 0.0;
  return s->hull_volume;
}

uint32_t bk_physics_shape_count(const bk_physics* w) { return w ? w->shapes.live : 0; }

// ---------------------------------------------------------------- bodies

bk_body_def bk_default_body_def(void) {
  bk_body_def d = {};
  d.transform = bk_transform_identity();
  d.friction = default_friction;
  d.restitution = default_restitution;
  return d;
}

namespace {

bool check_finite(double value, const char* field, bk_error* err) {
  if (std::isfinite(value)) return true;
  return bk_error_set(err, "body: %s must be finite (got %g)", field, value);
}

bool check_finite(bk_vec3 v, const char* field, bk_error* err) {
  if (bk_v3_is_finite(v)) return true;
  return bk_error_set(err, "body: %s must be finite (got %g, %g, %g)", field, v.x, v.y, v.z);
}

bool validate_body(const bk_physics* w, const bk_body_def* d, bk_error* err) {
  if (!w) return bk_error_set(err, "body: world is NULL");
  if (!d) return bk_error_set(err, "body: description is NULL");
  const ShapeSlot* shape = w->shape(d->shape);
  if (!shape)
    return bk_error_set(err, "body: shape {%u, %u} is not a valid shape id", d->shape.index,
                        d->shape.generation);
  if (!(std::isfinite(d->mass) && d->mass >= 0.0))
    return bk_error_set(err, "body: mass must be finite and >= 0 (got %g)", d->mass);
  if (shape->kind == ShapeKind::plane && d->mass != 0.0)
    return bk_error_set(err, "body: mass must be 0 for a plane shape (planes are static only; got %g)",
                        d->mass);
  bk_vec3 I = d->inertia;
  if (!check_finite(I, "inertia", err)) return false;
  if (d->mass > 0.0 && !(I.x > 0.0 && I.y > 0.0 && I.z > 0.0))
    return bk_error_set(err, "body: inertia must be > 0 on a dynamic body (got %g, %g, %g)", I.x, I.y, I.z);
  if (!check_finite(d->transform.position, "transform.position", err)) return false;
  if (!quat_is_finite(d->transform.rotation))
    return bk_error_set(err, "body: transform.rotation must be finite");
  bk_quat q = d->transform.rotation;
  double q_length = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (!(q_length > 0.5 && q_length < 2.0))
    return bk_error_set(err, "body: transform.rotation must be a unit quaternion (length %g)", q_length);
  if (!check_finite(d->linear_velocity, "linear_velocity", err) ||
      !check_finite(d->angular_velocity, "angular_velocity", err) ||
      !check_finite(d->friction, "friction", err) || !check_finite(d->restitution, "restitution", err) ||
      !check_finite(d->rolling_friction, "rolling_friction", err) ||
      !check_finite(d->linear_damping, "linear_damping", err) ||
      !check_finite(d->angular_damping, "angular_damping", err) ||
      !check_finite(d->ccd_radius, "ccd_radius", err))
    return false;
  if (d->friction < 0.0) return bk_error_set(err, "body: friction must be >= 0 (got %g)", d->friction);
  if (!(d->restitution >= 0.0 && d->restitution <= 1.0))
    return bk_error_set(err, "body: restitution must be in [0, 1] (got %g)", d->restitution);
  if (d->rolling_friction < 0.0)
    return bk_error_set(err, "body: rolling_friction must be >= 0 (got %g)", d->rolling_friction);
  if (!(d->linear_damping >= 0.0 && d->linear_damping <= 1.0))
    return bk_error_set(err, "body: linear_damping must be in [0, 1] (got %g)", d->linear_damping);
  if (!(d->angular_damping >= 0.0 && d->angular_damping <= 1.0))
    return bk_error_set(err, "body: angular_damping must be in [0, 1] (got %g)", d->angular_damping);
  if (d->ccd_radius < 0.0) return bk_error_set(err, "body: ccd_radius must be >= 0 (got %g)", d->ccd_radius);
  return true;
}

/// Radius of a sphere around the body origin that stays inside the shape:
/// Bullet sweeps it for continuous collision detection.
double embedded_radius(const ShapeSlot& s) {
  if (s.inner_radius > 0.0) return s.inner_radius;
  btVector3 lo, hi;
  s.shape->getAabb(btTransform::getIdentity(), lo, hi);
  btVector3 size = hi - lo;
  return 0.25 * size[size.minAxis()];
}

} // namespace

bk_body_id bk_physics_create_body(bk_physics* w, const bk_body_def* desc, bk_error* err) {
  const bk_body_id null_id = {0, 0};
  if (!validate_body(w, desc, err)) return null_id;
  const bk_body_def& d = *desc;
  uint32_t index;
  try {
    index = w->bodies.allocate();
  } catch (...) {
    bk_error_set(err, "body: out of memory");
    return null_id;
  }
  ShapeSlot& shape = w->shapes.slots[d.shape.index];
  bool dynamic = d.mass > 0.0;
  btVector3 inertia = dynamic ? to_bt(d.inertia) : btVector3(0, 0, 0);
  btRigidBody::btRigidBodyConstructionInfo info((btScalar)d.mass, nullptr, shape.shape, inertia);
  info.m_startWorldTransform = to_bt(d.transform);
  info.m_friction = (btScalar)d.friction;
  info.m_restitution = (btScalar)d.restitution;
  info.m_linearDamping = (btScalar)d.linear_damping;
  info.m_angularDamping = (btScalar)d.angular_damping;
  info.m_rollingFriction = (btScalar)d.rolling_friction;
  info.m_spinningFriction = (btScalar)d.rolling_friction;
  if (dynamic) {
    // A body sleeps after sleep_time below both thresholds. Bullet's angular
    // threshold (1 rad/s) is fixed whatever the size, but a pile of 5 cm
    // shards buzzes at 1-3 rad/s (up to 0.2 m/s at their bounding spheres) and never
    // sleeps. The angular threshold here is the same edge speed for every
    // size, never below Bullet's: shards settle, a toppling slab does not
    // freeze mid-fall.
    btVector3 center;
    btScalar radius = 0;
    shape.shape->getBoundingSphere(center, radius);
    info.m_linearSleepingThreshold = (btScalar)sleep_linear_speed;
    info.m_angularSleepingThreshold =
        (btScalar)std::max(sleep_angular_speed, sleep_edge_speed / std::max((double)radius, 1e-3));
  }
  btRigidBody* body = new btRigidBody(info);
  body->setUserIndex((int)index);
  if (dynamic) {
    body->setLinearVelocity(to_bt(d.linear_velocity));
    body->setAngularVelocity(to_bt(d.angular_velocity));
    if (d.ccd) {
      double radius = d.ccd_radius > 0.0 ? d.ccd_radius : embedded_radius(shape);
      body->setCcdMotionThreshold((btScalar)(0.5 * radius));
      body->setCcdSweptSphereRadius((btScalar)radius);
    }
    if (d.disable_sleep) body->setActivationState(DISABLE_DEACTIVATION);
  }
  BodySlot& s = w->bodies.slots[index];
  s.body = body;
  s.shape = d.shape.index;
  s.mass = dynamic ? d.mass : 0.0;
  s.inertia = inertia;
  s.user_data = d.user_data;
  ++shape.uses;
  if (d.debris) {
    // Filtered from its birth: a body added to the broadphase pairs with
    // every box it overlaps at once.
    int group = 0, mask = 0;
    bk_physics::filter_of(true, dynamic, &group, &mask);
    w->world.addRigidBody(body, group, mask);
  } else {
    w->world.addRigidBody(body);
  }
  return bk_body_id{index, s.generation};
}

void bk_physics_destroy_body(bk_physics* w, bk_body_id body) {
  if (w && w->body(body)) w->destroy_body_slot(body.index);
}

bool bk_physics_body_valid(const bk_physics* w, bk_body_id body) { return w && w->body(body); }

uint32_t bk_physics_body_count(const bk_physics* w) { return w ? w->bodies.live : 0; }

bk_transform bk_physics_body_transform(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? to_bk(s->body->getCenterOfMassTransform()) : bk_transform_identity();
}

void bk_physics_body_set_transform(bk_physics* w, bk_body_id body, bk_transform transform) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || !transform_is_finite(transform)) return;
  w->thaw(*s, true);
  s->body->setCenterOfMassTransform(to_bt(transform));
  w->world.updateSingleAabb(s->body);
  if (s->mass > 0.0 && !s->pinned) s->body->activate(true);
}

bk_vec3 bk_physics_body_linear_velocity(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? to_bk(s->body->getLinearVelocity()) : bk_v3(0, 0, 0);
}

bk_vec3 bk_physics_body_angular_velocity(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? to_bk(s->body->getAngularVelocity()) : bk_v3(0, 0, 0);
}

void bk_physics_body_set_velocity(bk_physics* w, bk_body_id body, bk_vec3 linear, bk_vec3 angular) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0 || s->pinned || !bk_v3_is_finite(linear) || !bk_v3_is_finite(angular)) return;
  w->thaw(*s, true);
  s->body->setLinearVelocity(to_bt(linear));
  s->body->setAngularVelocity(to_bt(angular));
  s->body->activate(true);
}

void bk_physics_body_set_mass(bk_physics* w, bk_body_id body, double mass, bk_vec3 inertia) {
  BodySlot* s = w ? w->body(body) : nullptr;
  // Static bodies stay static: turning one dynamic would need new broadphase filters.
  if (!s || s->mass == 0.0 || !(std::isfinite(mass) && mass > 0.0) || !bk_v3_is_finite(inertia) ||
      !(inertia.x > 0.0 && inertia.y > 0.0 && inertia.z > 0.0))
    return;
  s->mass = mass;
  s->inertia = to_bt(inertia);
  if (s->pinned) return; // it takes them when unpinned
  w->thaw(*s, true);
  s->body->setMassProps((btScalar)mass, to_bt(inertia));
  s->body->updateInertiaTensor();
  s->body->activate(true);
}

void bk_physics_body_set_surface(bk_physics* w, bk_body_id body, double friction, double restitution) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || !(std::isfinite(friction) && friction >= 0.0) || !(restitution >= 0.0 && restitution <= 1.0))
    return;
  s->body->setFriction((btScalar)friction);
  s->body->setRestitution((btScalar)restitution);
}

double bk_physics_body_mass(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? s->mass : 0.0;
}

bk_vec3 bk_physics_body_inertia(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0) return bk_v3(0, 0, 0);
  return to_bk(s->inertia);
}

void bk_physics_body_apply_impulse(bk_physics* w, bk_body_id body, bk_vec3 impulse, bk_vec3 world_point) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0 || s->pinned || !bk_v3_is_finite(impulse) || !bk_v3_is_finite(world_point)) return;
  w->thaw(*s, true);
  bk_vec3 arm = bk_v3_sub(world_point, to_bk(s->body->getCenterOfMassPosition()));
  s->body->applyImpulse(to_bt(impulse), to_bt(arm));
  s->body->activate(true);
}

bool bk_physics_body_awake(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s && s->mass > 0.0 && s->body->isActive();
}

uint64_t bk_physics_body_user_data(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? s->user_data : 0;
}

void bk_physics_body_set_debris(bk_physics* w, bk_body_id body, bool debris) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s) return;
  try {
    w->changed_pairs.reserve(w->changed_pairs.size() + 1);
    w->gained_pairs.reserve(w->gained_pairs.size() + 1);
  } catch (...) {
    return; // out of memory: the filter stays as it was
  }
  w->set_debris(*s, debris);
}

bool bk_physics_body_debris(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s && bk_physics::is_debris(*s);
}

bool bk_physics_body_set_shape(bk_physics* w, bk_body_id body, bk_shape_id shape) {
  BodySlot* s = w ? w->body(body) : nullptr;
  const ShapeSlot* n = w ? w->shape(shape) : nullptr;
  if (!s || !n || (n->kind == ShapeKind::plane && s->mass > 0.0)) return false;
  if (s->shape == shape.index) return true;
  try {
    w->changed_pairs.reserve(w->changed_pairs.size() + 1);
  } catch (...) {
    return false;
  }
  w->set_shape(*s, shape.index);
  return true;
}

bk_shape_id bk_physics_body_shape(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? bk_shape_id{s->shape, w->shapes.slots[s->shape].generation} : bk_shape_id{0, 0};
}

void bk_physics_body_set_pinned(bk_physics* w, bk_body_id body, bool pinned) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0 || s->pinned == pinned) return;
  if (pinned) {
    if (!bk_physics::frozen(*s)) w->freeze(*s);
    s->pinned = true;
  } else {
    // Restless, so that it falls if what held it went meanwhile; resting,
    // it sleeps again within sleep_time.
    s->pinned = false;
    w->thaw(*s, true);
  }
}

bool bk_physics_body_pinned(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s && s->pinned;
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
