// The runtime's journal (bk_runtime_journal, bk_runtime_apply_journal): a
// follower runtime that applies only the leader's journal, with no damage
// of its own, has the same state hash as the leader after every call (hits,
// refinement, splits, stress, a material change, a removal), and the same
// clusters; malformed journals change nothing and are refused in one line;
// a journal applied twice, or to a runtime that went its own way, is
// refused as a divergence; an added breakable cannot be followed.
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "ensure.h"
#include "runtime_caller.h"
#include "shape_tree.h"

typedef struct side {
  bodies* bodies;
  bk_runtime* rt;
  bk_breakable_id id;
} side;

static side make_side(const bk_mesh_tree* tree, bool journal) {
  side s = {calloc(1, sizeof(bodies)), NULL, {0, 0}};
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = s.bodies;
  def.refine_threads = 0;
  bk_error err = {0};
  s.rt = bk_runtime_create(&def, &err);
  ENSURE_MSG(s.rt, "%s", err.message);
  bk_breakable_def bdef = bk_default_breakable_def();
  bdef.tree = tree;
  bdef.material = *bk_material_find("stone");
  bdef.material.refine_strength = bdef.material.bond_strength / 8.0;
  bdef.refine.pieces = 12;
  bdef.refine.min_size = 0.02;
  bdef.anchored = true;
  s.id = bk_runtime_add_breakable(s.rt, &bdef, &err);
  ENSURE_MSG(s.id.generation, "%s", err.message);
  take_created(s.rt, s.bodies);
  // Journaling starts once the scene is set up (adding cannot be followed).
  ENSURE(bk_runtime_set_journal(s.rt, journal) == BK_OK);
  ENSURE(bk_runtime_journal_enabled(s.rt) == journal);
  return s;
}

static void free_side(side* s) {
  bk_runtime_destroy(s->rt);
  free(s->bodies);
}

// The follower takes the leader's journal; both take their events.
static size_t follow(side* leader, side* follower) {
  size_t size = 0;
  const void* bytes = bk_runtime_journal(leader->rt, &size);
  bk_error err = {0};
  ENSURE_MSG(bk_runtime_apply_journal(follower->rt, bytes, size, &err), "%s", err.message);
  bk_runtime_clear_journal(leader->rt);
  take_created(leader->rt, leader->bodies);
  take_created(follower->rt, follower->bodies);
  ENSURE(bk_runtime_state_hash(leader->rt) == bk_runtime_state_hash(follower->rt));
  bk_runtime_stats a = bk_runtime_get_stats(leader->rt), b = bk_runtime_get_stats(follower->rt);
  ENSURE(a.clusters == b.clusters && a.bonds_broken == b.bonds_broken && a.splits == b.splits);
  ENSURE(a.refined_leaves == b.refined_leaves);
  return size;
}

static void test_follows_every_call(void) {
  bk_mesh_tree tree =
      make_tree_pattern(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 48, bk_default_fracture_def().seed);
  side leader = make_side(&tree, true), follower = make_side(&tree, false);
  ENSURE(bk_runtime_state_hash(leader.rt) == bk_runtime_state_hash(follower.rt));
  size_t bytes = 0;
  const bk_vec3 hits[] = {{0.3, 1.1, 0.12}, {-0.6, 0.8, 0.12}, {0.9, 1.6, -0.12}, {0.0, 0.4, 0.12}};
  for (uint32_t step = 0; step < 12; ++step) {
    if (step < 4) {
      bk_runtime_damage_at(leader.rt, hits[step], 3000.0);
      bytes += follow(&leader, &follower);
    }
    bk_runtime_refine(leader.rt);
    bytes += follow(&leader, &follower);
    bk_runtime_solve_stress(leader.rt, bk_v3(0, -9.81, 0), NULL, 0, NULL, 0);
    bytes += follow(&leader, &follower);
    bk_runtime_split(leader.rt);
    bytes += follow(&leader, &follower);
    if (step == 5) {
      ENSURE(bk_runtime_set_frailty(leader.rt, leader.id, 7.5) == BK_OK);
      bytes += follow(&leader, &follower);
      ENSURE(bk_runtime_frailty(follower.rt, follower.id) == 7.5);
      ENSURE(bk_runtime_set_density(leader.rt, leader.id, 1800.0) == BK_OK);
      bytes += follow(&leader, &follower);
    }
    if (step == 7) {
      bk_cluster_id ids[512];
      uint32_t n = bk_runtime_clusters(leader.rt, ids, 512);
      ENSURE(n >= 2);
      ENSURE(bk_runtime_remove_cluster(leader.rt, ids[n - 1]) == BK_OK);
      bytes += follow(&leader, &follower);
    }
  }
  bk_runtime_stats st = bk_runtime_get_stats(follower.rt);
  // The run did what it is meant to test: bonds broke, clusters split,
  // fragments were refined.
  ENSURE_MSG(st.bonds_broken > 20 && st.splits >= 2 && st.refined_leaves >= 1,
             "bonds %u splits %u refined %u", st.bonds_broken, st.splits, st.refined_leaves);
  // The same cluster ids on both sides.
  bk_cluster_id a[512], b[512];
  uint32_t na = bk_runtime_clusters(leader.rt, a, 512), nb = bk_runtime_clusters(follower.rt, b, 512);
  ENSURE(na == nb);
  for (uint32_t i = 0; i < na; ++i)
    ENSURE(bk_cluster_equal(a[i], b[i]));
  // Compact: a few bytes per broken bond (hits, not bonds, are recorded).
  ENSURE_MSG((double)bytes / st.bonds_broken < 64.0, "%zu bytes for %u bonds", bytes, st.bonds_broken);
  free_side(&leader);
  free_side(&follower);
  bk_mesh_tree_free(&tree);
}

// A malformed journal: refused in one line, and the follower unchanged.
static void refuse(side* s, const void* bytes, size_t size, const char* expected) {
  uint64_t before = bk_runtime_state_hash(s->rt);
  bk_error err = {0};
  ENSURE(!bk_runtime_apply_journal(s->rt, bytes, size, &err));
  ENSURE_MSG(strstr(err.message, expected) && !strchr(err.message, '\n'), "'%s' lacks '%s'", err.message,
             expected);
  ENSURE(bk_runtime_state_hash(s->rt) == before);
}

static void test_refuses_bad_journals(void) {
  bk_mesh_tree tree =
      make_tree_pattern(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 24, bk_default_fracture_def().seed);
  side leader = make_side(&tree, true), follower = make_side(&tree, false);
  bk_runtime_damage_at(leader.rt, bk_v3(0.3, 1.1, 0.12), 3000.0);
  bk_runtime_split(leader.rt);
  size_t size = 0;
  const uint8_t* journal = bk_runtime_journal(leader.rt, &size);
  ENSURE(size == 35 + 2 && journal[0] == 1); // a hit (35 bytes), then a split (2)
  uint8_t* copy = malloc(size);
  memcpy(copy, journal, size);
  // Cut inside the hit: truncated, nothing applied.
  for (size_t cut = 1; cut < 35; ++cut)
    refuse(&follower, copy, cut, "truncated hit entry");
  uint8_t saved = copy[0];
  copy[0] = 200;
  refuse(&follower, copy, size, "entry 0 (byte 0): unknown kind 200");
  copy[0] = saved;
  // A NaN impulse.
  uint8_t nan_bytes[8] = {0, 0, 0, 0, 0, 0, 0xf8, 0x7f};
  uint8_t* impulse = copy + 1 + 1 + 1 + 24; // kind, slot, generation (1 byte each here), point
  uint8_t kept[8];
  memcpy(kept, impulse, 8);
  memcpy(impulse, nan_bytes, 8);
  refuse(&follower, copy, size, "not finite");
  memcpy(impulse, kept, 8);
  bk_error err = {0};
  ENSURE(bk_runtime_apply_journal(follower.rt, copy, size, &err));
  // Twice: the cluster it hits is gone (split): the runtimes diverged.
  refuse(&follower, copy, size, "the runtimes have diverged");
  // An added breakable cannot be followed.
  bk_runtime_clear_journal(leader.rt);
  bk_breakable_def bdef = bk_default_breakable_def();
  bdef.tree = &tree;
  ENSURE(bk_runtime_add_breakable(leader.rt, &bdef, NULL).generation);
  journal = bk_runtime_journal(leader.rt, &size);
  refuse(&follower, journal, size, "was added on the runtime that wrote it");
  ENSURE(!bk_runtime_apply_journal(NULL, journal, size, &err));
  ENSURE(!bk_runtime_apply_journal(follower.rt, NULL, 4, &err));
  ENSURE(bk_runtime_apply_journal(follower.rt, NULL, 0, &err)); // nothing to do
  free(copy);
  free_side(&leader);
  free_side(&follower);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  test_follows_every_call();
  test_refuses_bad_journals();
  return 0;
}
