// bk_physics hull pairs: the collision algorithm for two hulls, which skips
// the narrowphase while a pair provably stays apart.
#include "physics_internal.hpp"

#include <new>

#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

namespace {

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

} // namespace

namespace bk_bullet {

btCollisionAlgorithm* HullPairCreateFunc::CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                                   const btCollisionObjectWrapper* a,
                                                                   const btCollisionObjectWrapper* b) {
  void* memory = ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(HullPairAlgorithm));
  return new (memory) HullPairAlgorithm(ci, a, b, &depth_solver);
}

btDefaultCollisionConstructionInfo collision_info() {
  btDefaultCollisionConstructionInfo info;
  // The algorithm pool's blocks must hold the hull pair algorithm too.
  info.m_customCollisionAlgorithmMaxElementSize = (int)sizeof(HullPairAlgorithm);
  return info;
}

} // namespace bk_bullet
