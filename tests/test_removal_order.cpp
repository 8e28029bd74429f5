// Removing one body (bk_physics_destroy_body) walks the pair cache once and
// then repeats Bullet's own frees and removals on that body's pairs alone: the
// pair cache, pair by pair, and the manifolds, one by one, must be what
// Bullet's removeRigidBody leaves (the scenes' numbers were made with it),
// and every later step the same, bit for bit.
#include "physics_internal.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#define CHECK(cond, ...)                                                                                     \
  do {                                                                                                       \
    if (!(cond)) {                                                                                           \
      std::fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);                          \
      std::fprintf(stderr, __VA_ARGS__);                                                                     \
      std::fputc('\n', stderr);                                                                              \
      std::exit(1);                                                                                          \
    }                                                                                                        \
  } while (0)

namespace {

const double dt = 1.0 / 60.0;
enum { SIDE = 5, LAYERS = 3, BOXES = SIDE * SIDE * LAYERS };
const double half = 0.1;

// A stack of boxes a few steps after it was made: most pairs touching,
// their manifolds and algorithms alive.
bk_physics* make_stack(bk_body_id boxes[BOXES]) {
  bk_error err = {{0}};
  bk_physics_def desc = bk_default_physics_def();
  bk_physics* w = bk_physics_create(&desc, &err);
  CHECK(w, "%s", err.message);
  bk_body_def ground = bk_default_body_def();
  ground.shape = bk_physics_create_plane(w, bk_v3(0, 1, 0), 0.0);
  CHECK(!bk_body_is_null(bk_physics_create_body(w, &ground, &err)), "%s", err.message);
  for (int layer = 0, k = 0; layer < LAYERS; ++layer)
    for (int x = 0; x < SIDE; ++x)
      for (int z = 0; z < SIDE; ++z, ++k) {
        bk_body_def d = bk_default_body_def();
        d.shape = bk_physics_create_box(w, bk_v3(half, half, half));
        d.mass = 8.0;
        double i = 8.0 * (2.0 * half * half) / 3.0;
        d.inertia = bk_v3(i, i, i);
        d.transform.position =
            bk_v3((x - SIDE / 2) * 2.0 * half, half + layer * 2.0 * half, (z - SIDE / 2) * 2.0 * half);
        boxes[k] = bk_physics_create_body(w, &d, &err);
        CHECK(!bk_body_is_null(boxes[k]), "%s", err.message);
      }
  for (int step = 0; step < 10; ++step)
    bk_physics_step(w, dt, 1);
  return w;
}

// What removing a body was before: what rested on it woken, then Bullet's
// removeRigidBody (cleanProxyFromPairs, then the broadphase's
// removeOverlappingPairsContainingProxy).
void bullet_removal(bk_physics* w, bk_body_id id) {
  BodySlot& s = w->bodies.slots[id.index];
  const btBroadphasePairArray& pairs = w->broadphase.getOverlappingPairCache()->getOverlappingPairArray();
  for (int i = 0; i < pairs.size(); ++i) {
    const void* a = pairs[i].m_pProxy0->m_clientObject;
    const void* b = pairs[i].m_pProxy1->m_clientObject;
    const void* other = a == s.body ? b : b == s.body ? a : nullptr;
    BodySlot* neighbour = other ? w->slot_of(static_cast<const btCollisionObject*>(other)) : nullptr;
    if (neighbour) w->thaw(*neighbour, true);
    if (neighbour && neighbour->watched) neighbour->disturbed = true;
  }
  s.reshaped = false;
  w->world.removeRigidBody(s.body);
  delete s.body;
  --w->shapes.slots[s.shape].uses;
  w->bodies.release(id.index);
}

// The pair cache and the manifolds of two worlds built alike, entry by entry.
void same_caches(bk_physics* a, bk_physics* b, const char* when) {
  const btBroadphasePairArray& pa = a->broadphase.getOverlappingPairCache()->getOverlappingPairArray();
  const btBroadphasePairArray& pb = b->broadphase.getOverlappingPairCache()->getOverlappingPairArray();
  CHECK(pa.size() == pb.size(), "%s: %d pairs against %d", when, pa.size(), pb.size());
  for (int i = 0; i < pa.size(); ++i) {
    CHECK(pa[i].m_pProxy0->m_uniqueId == pb[i].m_pProxy0->m_uniqueId &&
              pa[i].m_pProxy1->m_uniqueId == pb[i].m_pProxy1->m_uniqueId,
          "%s: pair %d is (%d, %d), not (%d, %d)", when, i, pb[i].m_pProxy0->m_uniqueId,
          pb[i].m_pProxy1->m_uniqueId, pa[i].m_pProxy0->m_uniqueId, pa[i].m_pProxy1->m_uniqueId);
    CHECK(!pa[i].m_algorithm == !pb[i].m_algorithm, "%s: pair %d's algorithm", when, i);
  }
  int manifolds = a->dispatcher.getNumManifolds();
  CHECK(manifolds == b->dispatcher.getNumManifolds(), "%s: %d manifolds against %d", when,
        b->dispatcher.getNumManifolds(), manifolds);
  for (int m = 0; m < manifolds; ++m) {
    const btPersistentManifold* ma = a->dispatcher.getManifoldByIndexInternal(m);
    const btPersistentManifold* mb = b->dispatcher.getManifoldByIndexInternal(m);
    CHECK(ma->getBody0()->getUserIndex() == mb->getBody0()->getUserIndex() &&
              ma->getBody1()->getUserIndex() == mb->getBody1()->getUserIndex() &&
              ma->getNumContacts() == mb->getNumContacts(),
          "%s: manifold %d differs", when, m);
  }
}

} // namespace

int main() {
  bk_body_id boxes_a[BOXES], boxes_b[BOXES];
  bk_physics* a = make_stack(boxes_a);
  bk_physics* b = make_stack(boxes_b);
  same_caches(a, b, "before");
  int pairs_before = a->broadphase.getOverlappingPairCache()->getNumOverlappingPairs();
  // The bottom layer's middle row, a corner, and a box of the middle layer.
  const int doomed[] = {10, 11, 12, 13, 14, 0, SIDE * SIDE + 7, BOXES - 1};
  for (int k : doomed) {
    bullet_removal(a, boxes_a[k]);
    bk_physics_destroy_body(b, boxes_b[k]);
    same_caches(a, b, "after a removal");
  }
  CHECK(a->broadphase.getOverlappingPairCache()->getNumOverlappingPairs() < pairs_before, "no pair went");
  for (int step = 0; step < 60; ++step) {
    bk_physics_step(a, dt, 1);
    bk_physics_step(b, dt, 1);
  }
  same_caches(a, b, "a second later");
  for (int k = 0; k < BOXES; ++k) {
    if (!bk_physics_body_valid(a, boxes_a[k])) continue;
    bk_transform ta = bk_physics_body_transform(a, boxes_a[k]), tb = bk_physics_body_transform(b, boxes_b[k]);
    CHECK(std::memcmp(&ta, &tb, sizeof ta) == 0, "box %d moved otherwise", k);
  }
  bk_physics_destroy(a);
  bk_physics_destroy(b);
  std::fprintf(stderr, "test_removal_order: all passed\n");
  return 0;
}
