// Following a Bullet world (bk_world_apply_journal, bk_world_apply_motion):
// a follower world that is never stepped, given each step's journal and
// motion of a leader that is shot (and refines where it is hit), has the
// leader's runtime state hash and bodies after every step, each body where
// the leader's is to the motion's precision; a quiet step sends nothing but
// the bodies still moving; malformed motion moves nothing and is refused in
// one line.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ensure.h"
#include "shape_tree.h"
#include <breakables/bullet.h>

static bk_world* make_world(const bk_mesh_tree* tree) {
  bk_world_def def = bk_default_world_def();
  bk_error err = {0};
  bk_world* world = bk_world_create(&def, &err);
  ENSURE_MSG(world != NULL, "%s", err.message);
  bk_world_breakable_def b = bk_default_world_breakable_def();
  b.breakable.tree = tree;
  b.breakable.anchored = true;
  b.breakable.material = *bk_material_find("stone");
  b.breakable.material.refine_strength = b.breakable.material.bond_strength / 8.0;
  b.breakable.refine =
      (bk_refine_def){.pattern = BK_PATTERN_RADIAL, .pieces = 12, .min_size = 0.05, .radial_falloff = 1.0};
  ENSURE_MSG(bk_world_add_breakable(world, &b, &err).generation, "%s", err.message);
  return world;
}

static void shoot(bk_world* world, double x) {
  bk_projectile_def shot = {
      .position = bk_v3(x, 0.7, 2.0), .velocity = bk_v3(0, 0, -40.0), .radius = 0.14, .mass = 40.0};
  bk_error err = {0};
  ENSURE_MSG(!bk_body_is_null(bk_world_fire(world, &shot, &err)), "%s", err.message);
}

// How far the follower's bodies' tree frames are from the leader's (each
// body the same nodes).
static double largest_offset(const bk_world* leader, const bk_world* follower) {
  ENSURE(bk_world_body_count(leader) == bk_world_body_count(follower));
  double worst = 0.0;
  bk_body_view a = {0}, b = {0};
  for (uint32_t i = 0; bk_world_body_view(leader, i, &a); ++i) {
    ENSURE(bk_world_body_view(follower, i, &b));
    ENSURE(a.node_count == b.node_count);
    worst = fmax(worst, bk_v3_length(bk_v3_sub(a.tree_to_world.position, b.tree_to_world.position)));
  }
  return worst;
}

static void test_follows_a_shot_wall(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 64, 3000);
  bk_world* leader = make_world(&tree);
  bk_world* follower = make_world(&tree);
  ENSURE(bk_world_set_journal(leader, true) == BK_OK);
  size_t journal_bytes = 0, motion_bytes = 0, quiet_motion = 0;
  double worst = 0.0;
  uint8_t* motion = NULL;
  for (uint32_t step = 0; step < 240; ++step) {
    if (step == 10) shoot(leader, 0.0);
    if (step == 70) shoot(leader, 1.0);
    bk_world_step(leader);
    size_t size = 0;
    const void* journal = bk_world_journal(leader, &size);
    bk_error err = {0};
    ENSURE_MSG(bk_world_apply_journal(follower, journal, size, &err), "step %u: %s", step, err.message);
    journal_bytes += size;
    bk_world_clear_journal(leader);
    size_t capacity = bk_world_motion_size(leader);
    motion = realloc(motion, capacity);
    size_t written = bk_world_motion(leader, motion, capacity);
    ENSURE(written > 0 && written <= capacity);
    ENSURE(bk_world_motion(leader, motion, 0) == 0); // too small: nothing written
    ENSURE_MSG(bk_world_apply_motion(follower, motion, written, &err), "step %u: %s", step, err.message);
    motion_bytes += written;
    if (step < 10) quiet_motion += written;
    ENSURE_MSG(bk_runtime_state_hash(bk_world_runtime(leader)) ==
                   bk_runtime_state_hash(bk_world_runtime(follower)),
               "step %u: the follower's state hash differs", step);
    // Positions as floats, rotations to 3e-5 rad over the tree frame's
    // lever (the wall's origin lies metres from a piece): 0.2 mm.
    worst = fmax(worst, largest_offset(leader, follower));
    ENSURE_MSG(largest_offset(leader, follower) < 2e-4, "step %u: a body %g m off", step,
               largest_offset(leader, follower));
  }
  bk_world_stats stats = bk_world_get_stats(follower);
  ENSURE_MSG(stats.bonds_broken > 20 && stats.bodies > 3 && stats.refined_leaves >= 1,
             "bonds %u bodies %u refined %u", stats.bonds_broken, stats.bodies, stats.refined_leaves);
  // Before the shot the wall stands: its one body is placed once.
  ENSURE_MSG(quiet_motion < 10 * 25, "%zu motion bytes before the shot", quiet_motion);
  ENSURE(journal_bytes < 64 * (size_t)stats.bonds_broken);
  printf("%u bonds broken, %u bodies: journal %zu bytes, motion %zu bytes; tree frames within %.2g m\n",
         stats.bonds_broken, stats.bodies, journal_bytes, motion_bytes, worst);

  // Malformed motion: refused in one line, nothing moved.
  size_t written = 0;
  for (int k = 0; k < 8 && written < 30; ++k) { // a step in which a few bodies move
    shoot(leader, -1.0 + 0.2 * k);
    bk_world_step(leader);
    size_t size = 0;
    const void* journal = bk_world_journal(leader, &size);
    ENSURE(bk_world_apply_journal(follower, journal, size, NULL));
    bk_world_clear_journal(leader);
    motion = realloc(motion, bk_world_motion_size(leader));
    written = bk_world_motion(leader, motion, bk_world_motion_size(leader));
    if (written < 30) ENSURE(bk_world_apply_motion(follower, motion, written, NULL));
  }
  ENSURE(written >= 30);
  bk_body_view before = {0}, after = {0};
  ENSURE(bk_world_body_view(follower, 0, &before));
  bk_error err = {0};
  for (size_t cut = 0; cut < written; ++cut) {
    ENSURE(!bk_world_apply_motion(follower, motion, cut, &err));
    ENSURE(err.message[0] && !strchr(err.message, '\n'));
  }
  uint8_t* longer = calloc(written + 1, 1);
  memcpy(longer, motion, written);
  ENSURE(!bk_world_apply_motion(follower, longer, written + 1, &err) &&
         strstr(err.message, "after the last body"));
  free(longer);
  ENSURE(bk_world_body_view(follower, 0, &after));
  ENSURE(memcmp(&before.tree_to_world, &after.tree_to_world, sizeof before.tree_to_world) == 0);
  ENSURE(bk_world_apply_motion(follower, motion, written, &err));
  // Applied twice is harmless; a body the follower lacks is reported.
  ENSURE(bk_world_apply_motion(follower, motion, written, &err));
  free(motion);
  bk_world_destroy(leader);
  bk_world_destroy(follower);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  test_follows_a_shot_wall();
  return 0;
}
