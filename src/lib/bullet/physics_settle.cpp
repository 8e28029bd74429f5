// bk_physics for settled debris: parking bodies (out of Bullet's world, their
// state kept) and bringing them back, and watching the static compound that
// stands in for them, so that it is known when something comes near it
// fast or what held it up goes.
#include "physics_internal.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

// Whether a world box (grown by margin) meets a child of the watched body's
// compound: the compound's own tree of child boxes (its body is at the
// origin), so that a body near the cell's box but far from every piece in
// it passes by.
// `near`, if given, is set to the middle of the children met.
bool meets_child(const BodySlot& watched, btVector3 lo, btVector3 hi, btScalar margin,
                 btVector3* near = nullptr) {
  const btCollisionShape* shape = watched.body->getCollisionShape();
  if (near) *near = (lo + hi) * btScalar(0.5);
  if (!shape->isCompound()) return true;
  const btDbvt* tree = static_cast<const btCompoundShape*>(shape)->getDynamicAabbTree();
  if (!tree || !tree->m_root) return true;
  struct Found : public btDbvt::ICollide {
    bool found = false;
    btVector3 lo{BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT},
        hi{-BT_LARGE_FLOAT, -BT_LARGE_FLOAT, -BT_LARGE_FLOAT};
    void Process(const btDbvtNode* leaf) override {
      found = true;
      lo.setMin(leaf->volume.Mins());
      hi.setMax(leaf->volume.Maxs());
    }
  } found;
  btVector3 m(margin, margin, margin);
  btDbvtVolume volume = btDbvtVolume::FromMM(lo - m, hi + m);
  tree->collideTV(tree->m_root, volume, found);
  if (found.found && near) *near = (found.lo + found.hi) * btScalar(0.5);
  return found.found;
}

} // namespace

namespace bk_bullet {

void note_watched_pair(bk_physics* w, const btCollisionObject* a, const btCollisionObject* b) {
  if (!w) return;
  BodySlot* watched = a->getUserIndex2() == watched_tag ? w->slot_of(a) : w->slot_of(b);
  const btCollisionObject* other = a->getUserIndex2() == watched_tag ? b : a;
  if (!watched || watched->disturbed || other->isStaticOrKinematicObject() || !other->isActive()) return;
  const btRigidBody* body = btRigidBody::upcast(other);
  if (!body || !(body->getLinearVelocity().length() >= (btScalar)watched->watch_speed)) return;
  const btBroadphaseProxy* proxy = other->getBroadphaseHandle();
  btVector3 near(0, 0, 0);
  if (!meets_child(*watched, proxy->m_aabbMin, proxy->m_aabbMax, (btScalar)watched->watch_margin, &near))
    return;
  watched->disturbed = true;
  // Moving away from the pieces it is near: it may have held them up.
  btVector3 from = body->getCenterOfMassPosition() - near;
  if (body->getLinearVelocity().dot(from) > 0) watched->undermined = true;
}

void note_removed(bk_physics* w, uint32_t index, bool disturb) {
  if (w->watched_slots.empty()) return;
  BodySlot& gone = w->bodies.slots[index];
  if (gone.watched) {
    auto& list = w->watched_slots;
    for (size_t i = 0; i < list.size(); ++i)
      if (list[i] == index) {
        list.erase(list.begin() + (std::ptrdiff_t)i);
        break;
      }
    return;
  }
  if (!disturb) return;
  btVector3 lo, hi;
  gone.body->getCollisionShape()->getAabb(gone.body->getWorldTransform(), lo, hi);
  for (uint32_t watched : w->watched_slots) {
    BodySlot& s = w->bodies.slots[watched];
    if (s.undermined) continue;
    const btBroadphaseProxy* proxy = s.body->getBroadphaseHandle();
    if (proxy && !TestAabbAgainstAabb2(lo, hi, proxy->m_aabbMin, proxy->m_aabbMax)) continue;
    if (meets_child(s, lo, hi, gContactBreakingThreshold)) s.disturbed = s.undermined = true;
  }
}

} // namespace bk_bullet

void bk_physics_park_bodies(bk_physics* w, const bk_body_id* ids, uint32_t count) {
  if (!w || !ids || count == 0) return;
  std::vector<uint32_t> indices;
  try {
    indices.reserve(count);
  } catch (...) {
    return; // out of memory: they stay bodies
  }
  for (uint32_t i = 0; i < count; ++i) {
    BodySlot* s = w->body(ids[i]);
    if (!s || s->parked || s->body->getUserIndex() == removing_index) continue;
    s->body->setUserIndex(removing_index); // so that a repeat is skipped
    indices.push_back(ids[i].index);
  }
  if (indices.empty()) return;
  // One walk drops every pair of theirs; what touched them stays as it is
  // (the stand-in holds it up as they did).
  struct DropPairs : public btOverlapCallback {
    bool processOverlap(btBroadphasePair& pair) override {
      const auto* a = static_cast<const btCollisionObject*>(pair.m_pProxy0->m_clientObject);
      const auto* b = static_cast<const btCollisionObject*>(pair.m_pProxy1->m_clientObject);
      return a->getUserIndex() == removing_index || b->getUserIndex() == removing_index;
    }
  } drop;
  btOverlappingPairCache* cache = w->broadphase.m_paircache;
  cache->processAllOverlappingPairs(&drop, &w->dispatcher);
  // Out of the bodies Bullet integrates in one pass, keeping the others'
  // order (Bullet's removal is a linear search and a swap per body).
  btAlignedObjectArray<btRigidBody*>& moving = w->world.non_static_bodies();
  int kept = 0;
  for (int i = 0; i < moving.size(); ++i)
    if (moving[i]->getUserIndex() != removing_index) moving[kept++] = moving[i];
  moving.resize(kept);
  btNullPairCache emptied;
  w->broadphase.m_paircache = &emptied;
  for (uint32_t index : indices) {
    BodySlot& s = w->bodies.slots[index];
    const btBroadphaseProxy* proxy = s.body->getBroadphaseHandle();
    s.park_group = proxy ? proxy->m_collisionFilterGroup : btBroadphaseProxy::DefaultFilter;
    s.park_mask = proxy ? proxy->m_collisionFilterMask : btBroadphaseProxy::AllFilter;
    s.reshaped = false;
    w->world.btCollisionWorld::removeCollisionObject(s.body); // its box and its place in the list
    s.body->setUserIndex((int)index);
    s.body->setLinearVelocity(btVector3(0, 0, 0));
    s.body->setAngularVelocity(btVector3(0, 0, 0));
    s.pinned = false;
    s.parked = true;
  }
  w->broadphase.m_paircache = cache;
}

void bk_physics_unpark_bodies(bk_physics* w, const bk_body_id* ids, uint32_t count, bool moving) {
  if (!w || !ids) return;
  for (uint32_t i = 0; i < count; ++i) {
    BodySlot* s = w->body(ids[i]);
    if (!s || !s->parked) continue;
    // Dynamic again before Bullet takes it back: a body added static is
    // never integrated, even once its mass returns.
    w->thaw(*s, moving);
    s->body->setLinearVelocity(btVector3(0, 0, 0));
    s->body->setAngularVelocity(btVector3(0, 0, 0));
    s->body->clearForces();
    try {
      w->world.addRigidBody(s->body, s->park_group, s->park_mask);
    } catch (...) {
      continue; // out of memory in Bullet's arrays: it stays parked
    }
    s->parked = false;
    if (s->mass > 0.0) {
      // Moving, it falls if nothing holds it and sleeps again after
      // sleep_time at rest. Calm, it is as a frozen body a touch wakes: its
      // island goes back to sleep at once unless a restless body touches it.
      s->body->forceActivationState(moving ? ACTIVE_TAG : WANTS_DEACTIVATION);
      s->body->setDeactivationTime(0);
    }
  }
}

void bk_physics_body_unpin_at_rest(bk_physics* w, bk_body_id body) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || !s->pinned) return;
  // Pinned bodies are frozen (bk_physics_body_set_pinned): without the pin
  // it is a frozen body as a sleeping one becomes, thawed by touches.
  s->pinned = false;
  if (!s->parked) s->body->forceActivationState(ISLAND_SLEEPING);
}

bool bk_physics_body_parked(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s && s->parked;
}

void bk_physics_destroy_bodies_quietly(bk_physics* w, const bk_body_id* ids, uint32_t count) {
  if (!w || !ids) return;
  std::vector<uint32_t> indices;
  try {
    indices.reserve(count);
  } catch (...) {
    return;
  }
  for (uint32_t i = 0; i < count; ++i)
    if (w->body(ids[i]) && w->bodies.slots[ids[i].index].body->getUserIndex() != removing_index) {
      w->bodies.slots[ids[i].index].body->setUserIndex(removing_index);
      indices.push_back(ids[i].index);
    }
  w->destroy_body_slots(indices.data(), (uint32_t)indices.size(), false);
}

void bk_physics_body_watch(bk_physics* w, bk_body_id body, double margin, double speed) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass > 0.0 || s->parked || !std::isfinite(margin) || !std::isfinite(speed)) return;
  if (!s->watched) {
    try {
      w->watched_slots.push_back(body.index);
    } catch (...) {
      return; // out of memory: not watched
    }
  }
  s->watched = true;
  s->disturbed = false;
  s->watch_speed = speed;
  s->watch_margin = margin > 0.0 ? margin : 0.0;
  s->body->setUserIndex2(watched_tag);
  // A static box is not computed again (setForceUpdateAllAabbs is off), so
  // the grown one stays until the body goes.
  btBroadphaseProxy* proxy = s->body->getBroadphaseHandle();
  if (!proxy) return;
  btVector3 lo, hi;
  s->body->getCollisionShape()->getAabb(s->body->getWorldTransform(), lo, hi);
  btScalar m = (btScalar)(margin > 0.0 ? margin : 0.0);
  w->broadphase.setAabb(proxy, lo - btVector3(m, m, m), hi + btVector3(m, m, m), &w->dispatcher);
}

int bk_physics_body_take_disturbed(bk_physics* w, bk_body_id body) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || !s->disturbed) return 0;
  int how = s->undermined ? 2 : 1;
  s->disturbed = s->undermined = false;
  return how;
}

void bk_physics_body_bounds(const bk_physics* w, bk_body_id body, bk_vec3* lo, bk_vec3* hi) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  btVector3 a(0, 0, 0), b(0, 0, 0);
  if (s) s->body->getCollisionShape()->getAabb(s->body->getWorldTransform(), a, b);
  if (lo) *lo = to_bk(a);
  if (hi) *hi = to_bk(b);
}
