// Fuzzes the runtime's journal (bk_runtime_apply_journal), two ways, chosen
// by byte 0:
//   even: the rest is a journal from an unknown sender, applied to a
//     runtime holding a cube in 27 pieces (refinable). A journal is either
//     refused with a one-line error or applied; either way every leaf is
//     then in exactly one live cluster, and refused bytes that were
//     malformed (not a divergence) changed nothing.
//   odd: the rest drives a leader runtime (hits, splits, refinement calls,
//     material changes, removals: each op one byte % 6 and its arguments),
//     and a follower that applies only the leader's journal after each op
//     must have the leader's state hash and cluster count every time.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_journal";

typedef struct side {
  bk_body_state states[1024];
  bk_runtime* rt;
  bk_breakable_id id;
} side;

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  side* s = context;
  return cluster.index < 1024 ? s->states[cluster.index] : (bk_body_state){0};
}

static const bk_mesh_tree* cube_tree(void) {
  static bk_mesh_tree tree;
  static bool built = false;
  if (!built) {
    bk_mesh mesh = {0};
    bk_shape_build(BK_SHAPE_CUBE, &mesh);
    bk_fracture_def def = bk_default_fracture_def();
    def.pieces = 27;
    def.seed = 5;
    bk_error err = {0};
    if (!bk_mesh_tree_build(&mesh, &def, &tree, &err)) bk_fuzz_fail("tree: %s", err.message);
    bk_mesh_free(&mesh);
    built = true;
  }
  return &tree;
}

static void take_events(side* s) {
  bk_cluster_created created[256];
  uint32_t n = bk_runtime_created_clusters(s->rt, created, 256);
  for (uint32_t i = 0; i < n && i < 256; ++i)
    if (created[i].cluster.id.index < 1024) s->states[created[i].cluster.id.index] = created[i].body;
  bk_runtime_clear_events(s->rt);
  bk_runtime_refined_leaves(s->rt, NULL, 0);
}

static void make_side(side* s, bool journal) {
  memset(s, 0, sizeof *s);
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = s;
  def.refine_threads = 0;
  s->rt = bk_runtime_create(&def, NULL);
  bk_breakable_def b = bk_default_breakable_def();
  b.tree = cube_tree();
  b.material = *bk_material_find("stone");
  b.material.refine_strength = b.material.bond_strength / 8.0;
  b.refine.pieces = 6;
  b.refine.min_size = 0.01;
  s->id = bk_runtime_add_breakable(s->rt, &b, NULL);
  take_events(s);
  bk_runtime_set_journal(s->rt, journal);
}

// Every leaf of the (possibly grown) tree in exactly one live cluster.
static void check_leaves(const side* s) {
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(s->rt, s->id);
  if (!tree) return;
  bk_cluster_id ids[512];
  uint32_t n = bk_runtime_clusters(s->rt, ids, 512);
  uint32_t covered = 0;
  for (uint32_t i = 0; i < n && i < 512; ++i) {
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(s->rt, ids[i], &info)) bk_fuzz_fail("cluster %u listed but not live", i);
    for (uint32_t k = 0; k < info.leaf_count; ++k)
      if (!bk_cluster_equal(bk_runtime_leaf_cluster(s->rt, s->id, info.leaves[k]), ids[i]))
        bk_fuzz_fail("leaf %u is not in its cluster", info.leaves[k]);
    covered += info.leaf_count;
  }
  if (covered > tree->leaf_count) bk_fuzz_fail("%u leaves covered of %u", covered, tree->leaf_count);
}

static void raw_journal(const uint8_t* data, size_t size) {
  side* s = calloc(1, sizeof *s);
  make_side(s, false);
  uint64_t before = bk_runtime_state_hash(s->rt);
  bk_error err = {0};
  bool ok = bk_runtime_apply_journal(s->rt, data, size, &err);
  if (!ok && (!err.message[0] || strchr(err.message, '\n'))) bk_fuzz_fail("refusal without one line");
  if (!ok && !strstr(err.message, "diverged") && !strstr(err.message, "was added") &&
      !strstr(err.message, "not a valid material") && bk_runtime_state_hash(s->rt) != before)
    bk_fuzz_fail("malformed journal changed the state: %s", err.message);
  take_events(s);
  check_leaves(s);
  bk_runtime_destroy(s->rt);
  free(s);
}

static double number(const uint8_t* data, size_t size, size_t* at, double scale) {
  uint8_t b = *at < size ? data[(*at)++] : 0;
  return ((double)b - 128.0) / 128.0 * scale;
}

static void lockstep(const uint8_t* data, size_t size) {
  side* leader = calloc(1, sizeof *leader);
  side* follower = calloc(1, sizeof *follower);
  make_side(leader, true);
  make_side(follower, false);
  size_t at = 0;
  for (uint32_t op = 0; at < size && op < 64; ++op) {
    uint8_t code = data[at++] % 6;
    if (code == 0) {
      bk_vec3 p = {number(data, size, &at, 1.0), number(data, size, &at, 1.0), number(data, size, &at, 1.0)};
      bk_runtime_damage_at(leader->rt, p, 50.0 + 20.0 * fabs(number(data, size, &at, 100.0)));
    } else if (code == 1) {
      bk_runtime_split(leader->rt);
    } else if (code == 2) {
      bk_runtime_refine(leader->rt);
    } else if (code == 3) {
      bk_runtime_set_frailty(leader->rt, leader->id, fabs(number(data, size, &at, 10.0)));
    } else if (code == 4) {
      bk_cluster_id ids[512];
      uint32_t n = bk_runtime_clusters(leader->rt, ids, 512);
      uint8_t pick = at < size ? data[at++] : 0;
      if (n) bk_runtime_remove_cluster(leader->rt, ids[pick % (n < 512 ? n : 512)]);
    } else {
      bk_runtime_solve_stress(leader->rt, bk_v3(0, -9.81, 0), NULL, 0, NULL, 0);
    }
    size_t bytes = 0;
    const void* journal = bk_runtime_journal(leader->rt, &bytes);
    bk_error err = {0};
    if (!bk_runtime_apply_journal(follower->rt, journal, bytes, &err))
      bk_fuzz_fail("op %u: the follower refused the leader's journal: %s", op, err.message);
    bk_runtime_clear_journal(leader->rt);
    take_events(leader);
    take_events(follower);
    if (bk_runtime_state_hash(leader->rt) != bk_runtime_state_hash(follower->rt))
      bk_fuzz_fail("op %u (%u): the follower's state hash differs from the leader's", op, code);
    if (bk_runtime_get_stats(leader->rt).clusters != bk_runtime_get_stats(follower->rt).clusters)
      bk_fuzz_fail("op %u: cluster counts differ", op);
  }
  check_leaves(follower);
  bk_runtime_destroy(leader->rt);
  bk_runtime_destroy(follower->rt);
  free(leader);
  free(follower);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  if (data[0] % 2 == 0)
    raw_journal(data + 1, size - 1);
  else
    lockstep(data + 1, size - 1);
  return 0;
}
