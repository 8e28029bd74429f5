// Removing bodies: bk_physics_destroy_bodies (many in one walk over the
// pairs) leaves the world as destroying them one at a time does: the same
// bodies and pairs, the same neighbours woken (what rested on them falls),
// repeated and stale ids skipped; and it is deterministic. (The pair
// cache's order differs, so the two runs part by millimetres.)
#include <stdint.h>
#include <string.h>

#include <breakables/bullet.h>

#include "ensure.h"

static const double dt = 1.0 / 60.0;

enum { SIDE = 5, LAYERS = 3, BOXES = SIDE * SIDE * LAYERS };
static const double half = 0.1; // 20 cm boxes

static bk_physics* make_world(void) {
  bk_error err = {{0}};
  bk_physics_def desc = bk_default_physics_def();
  bk_physics* w = bk_physics_create(&desc, &err);
  ENSURE_MSG(w, "%s", err.message);
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_plane(w, bk_v3(0, 1, 0), 0.0);
  ENSURE(!bk_body_is_null(bk_physics_create_body(w, &d, &err)));
  return w;
}

// A stack of boxes, layer on layer, each layer resting on the one below;
// settled for two seconds, so that the stack is asleep (frozen) when parts
// of it are taken away.
static bk_physics* make_stack(bk_body_id boxes[BOXES]) {
  bk_physics* w = make_world();
  const bk_vec3 h = bk_v3(half, half, half);
  for (int layer = 0, k = 0; layer < LAYERS; ++layer)
    for (int x = 0; x < SIDE; ++x)
      for (int z = 0; z < SIDE; ++z, ++k) {
        bk_body_def d = bk_default_body_def();
        d.shape = bk_physics_create_box(w, h);
        d.mass = 8.0;
        double i = 8.0 * (2.0 * half * half) / 3.0;
        d.inertia = bk_v3(i, i, i);
        d.transform.position =
            bk_v3((x - SIDE / 2) * 2.0 * half, half + layer * 2.0 * half, (z - SIDE / 2) * 2.0 * half);
        bk_error err = {{0}};
        boxes[k] = bk_physics_create_body(w, &d, &err);
        ENSURE_MSG(!bk_body_is_null(boxes[k]), "%s", err.message);
      }
  for (int step = 0; step < 120; ++step)
    bk_physics_step(w, dt, 1);
  return w;
}

// The bottom layer's middle row (under the boxes above it) and one corner of the top.
static uint32_t doomed(const bk_body_id boxes[BOXES], bk_body_id out[]) {
  uint32_t n = 0;
  for (int z = 0; z < SIDE; ++z)
    out[n++] = boxes[(SIDE / 2) * SIDE + z];
  out[n++] = boxes[BOXES - 1];
  return n;
}

// Removes the doomed boxes of a settled stack with the batch call (with a
// repeat and the id of a body already gone) or one at a time, then lets the
// stack fall for a second.
static bk_physics* remove_and_fall(bool batch, bk_body_id boxes[BOXES], bk_physics_stats* after_removal,
                                   double* above_drop) {
  bk_physics* w = make_stack(boxes);
  uint32_t awake = bk_physics_get_stats(w).awake_bodies;
  ENSURE_MSG(awake == 0, "%u boxes still awake after settling", awake);
  const bk_body_id above = boxes[SIDE * SIDE + (SIDE / 2) * SIDE + 2];
  const double before = bk_physics_body_transform(w, above).position.y;
  bk_body_id gone[BOXES + 2];
  uint32_t n = doomed(boxes, gone);
  bk_physics_destroy_body(w, boxes[0]);
  if (batch) {
    gone[n] = gone[0];
    gone[n + 1] = boxes[0];
    bk_physics_destroy_bodies(w, gone, n + 2);
  } else {
    for (uint32_t i = 0; i < n; ++i)
      bk_physics_destroy_body(w, gone[i]);
  }
  *after_removal = bk_physics_get_stats(w);
  ENSURE_MSG(after_removal->bodies == 1 + BOXES - 1 - n, "%u bodies after removing %u of %d",
             after_removal->bodies, n + 1, BOXES);
  for (uint32_t i = 0; i < n; ++i)
    ENSURE(!bk_physics_body_valid(w, gone[i]));
  ENSURE(bk_physics_body_valid(w, boxes[1]));
  for (int step = 0; step < 60; ++step)
    bk_physics_step(w, dt, 1);
  *above_drop = before - bk_physics_body_transform(w, above).position.y;
  return w;
}

static void test_batch_matches_one_by_one(void) {
  bk_body_id a_boxes[BOXES], b_boxes[BOXES], c_boxes[BOXES];
  bk_physics_stats a_removed, b_removed, c_removed;
  double a_drop = 0.0, b_drop = 0.0, c_drop = 0.0;
  bk_physics* a = remove_and_fall(true, a_boxes, &a_removed, &a_drop);
  bk_physics* b = remove_and_fall(false, b_boxes, &b_removed, &b_drop);
  bk_physics* c = remove_and_fall(true, c_boxes, &c_removed, &c_drop);
  ENSURE_MSG(a_removed.pairs == b_removed.pairs && a_removed.bodies == b_removed.bodies,
             "%u bodies and %u pairs after the batch, %u and %u one by one", a_removed.bodies,
             a_removed.pairs, b_removed.bodies, b_removed.pairs);
  // The box over the removed row was woken with the others and fell.
  ENSURE_MSG(a_drop > half && b_drop > half,
             "the box over the removed row fell %g m (batch), %g m (one by one)", a_drop, b_drop);
  // The batch is deterministic to the bit.
  for (int k = 1; k < BOXES; ++k) {
    ENSURE(bk_physics_body_valid(a, a_boxes[k]) == bk_physics_body_valid(b, b_boxes[k]));
    if (!bk_physics_body_valid(a, a_boxes[k])) continue;
    bk_transform ta = bk_physics_body_transform(a, a_boxes[k]), tc = bk_physics_body_transform(c, c_boxes[k]);
    ENSURE_MSG(memcmp(&ta, &tc, sizeof ta) == 0,
               "box %d at (%.17g, %.17g, %.17g), then (%.17g, %.17g, %.17g)", k, ta.position.x, ta.position.y,
               ta.position.z, tc.position.x, tc.position.y, tc.position.z);
  }
  bk_physics_destroy(a);
  bk_physics_destroy(b);
  bk_physics_destroy(c);
}

static void test_batch_of_everything(void) {
  bk_body_id boxes[BOXES];
  bk_physics* w = make_stack(boxes);
  ENSURE(bk_physics_get_stats(w).pairs > 0);
  bk_physics_destroy_bodies(w, boxes, BOXES);
  bk_physics_destroy_bodies(w, boxes, 0); // nothing to do
  bk_physics_destroy_bodies(w, NULL, 3);  // nor here
  bk_physics_stats s = bk_physics_get_stats(w);
  ENSURE_MSG(s.bodies == 1 && s.pairs == 0, "%u bodies and %u pairs left with the ground alone", s.bodies,
             s.pairs);
  // The slots are reused with new generations.
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_sphere(w, 0.1);
  d.mass = 1.0;
  d.inertia = bk_v3(0.004, 0.004, 0.004);
  d.transform.position = bk_v3(0, 1, 0);
  bk_error err = {{0}};
  bk_body_id ball = bk_physics_create_body(w, &d, &err);
  ENSURE(!bk_body_is_null(ball) && !bk_physics_body_valid(w, boxes[BOXES - 1]));
  for (int step = 0; step < 60; ++step)
    bk_physics_step(w, dt, 1);
  ENSURE(bk_physics_body_transform(w, ball).position.y < 0.2);
  bk_physics_destroy(w);
}

int main(void) {
  RUN(test_batch_matches_one_by_one);
  RUN(test_batch_of_everything);
  fprintf(stderr, "test_physics_removal: all passed\n");
  return 0;
}
