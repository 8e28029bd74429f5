// Saving and loading the runtime's destruction state (no physics engine): a
// loaded runtime has the saved one's state hash and clusters bit for bit,
// continues exactly as the saved one does (slot reuse, splits waiting,
// refinements landing), and a state that is damaged, truncated, of another
// version or of another tree is refused in one line leaving the runtime as
// it was.
#include <stdlib.h>
#include <string.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <breakables/runtime.h>

#include "ensure.h"
#include "runtime_caller.h"
#include "shape_tree.h"

/// A runtime with two walls of `tree` (the second refines when `refine`).
typedef struct world {
  bodies* b;
  bk_runtime* rt;
} world;

static world make(const bk_mesh_tree* tree, bool refine) {
  world w = {calloc(1, sizeof(bodies)), NULL};
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = w.b;
  def.refine_latency = 2;
  def.max_new_clusters_per_split = 3; // splits wait for the budget: the queue is state
  bk_error err = {0};
  w.rt = bk_runtime_create(&def, &err);
  ENSURE_MSG(w.rt, "%s", err.message);
  for (int k = 0; k < 2; ++k) {
    bk_breakable_def bd = bk_default_breakable_def();
    bd.tree = tree;
    bd.material = *bk_material_find("stone");
    bd.material.accumulate = true;
    if (refine && k == 1) bd.material.refine_strength = bd.material.bond_strength / 8.0;
    bd.refine.pieces = 12;
    bd.refine.min_size = 0.01;
    bd.transform.position = bk_v3(4.0 * k, 0, 0);
    ENSURE_MSG(!bk_breakable_is_null(bk_runtime_add_breakable(w.rt, &bd, &err)), "%s", err.message);
  }
  take_created(w.rt, w.b);
  return w;
}

static void destroy(world* w) {
  bk_runtime_destroy(w->rt);
  free(w->b);
}

// One step of a game: a hit (k-th of a fixed list), refine, split, bodies taken.
static void step(world* w, uint32_t k) {
  static const bk_vec3 points[] = {{0.3, 1.1, 0.12}, {4.2, 0.6, 0.1}, {-0.4, 0.4, -0.1},
                                   {3.7, 1.4, 0.12}, {0.1, 1.8, 0.1}, {4.5, 1.0, -0.1}};
  bk_runtime_damage_at(w->rt, points[k % 6], 1500.0 + 400.0 * (k % 3));
  bk_runtime_refine(w->rt);
  bk_runtime_split(w->rt);
  take_created(w->rt, w->b);
}

static uint8_t* save(const bk_runtime* rt, size_t* size) {
  *size = bk_runtime_state_size(rt);
  ENSURE(*size > 32);
  uint8_t* bytes = malloc(*size);
  bk_error err = {0};
  ENSURE_MSG(bk_runtime_save_state(rt, bytes, *size, &err) == *size, "%s", err.message);
  return bytes;
}

static bool one_line(const char* s) { return s[0] && !strchr(s, '\n'); }

// The clusters of two runtimes, field by field: ids, leaves, node sets and
// mass properties bit for bit.
static void same_clusters(const bk_runtime* a, const bk_runtime* b) {
  uint32_t n = bk_runtime_clusters(a, NULL, 0);
  ENSURE(n == bk_runtime_clusters(b, NULL, 0));
  bk_cluster_id* ids = calloc(n + 1u, sizeof *ids);
  bk_cluster_id* other = calloc(n + 1u, sizeof *other);
  bk_runtime_clusters(a, ids, n);
  bk_runtime_clusters(b, other, n);
  for (uint32_t i = 0; i < n; ++i) {
    ENSURE(bk_cluster_equal(ids[i], other[i]));
    bk_cluster_info x = {0}, y = {0};
    ENSURE(bk_runtime_cluster(a, ids[i], &x) && bk_runtime_cluster(b, ids[i], &y));
    ENSURE(x.leaf_count == y.leaf_count && x.node_count == y.node_count && x.is_static == y.is_static);
    ENSURE(memcmp(x.leaves, y.leaves, sizeof(uint32_t) * x.leaf_count) == 0);
    ENSURE(memcmp(x.nodes, y.nodes, sizeof(uint32_t) * x.node_count) == 0);
    ENSURE(memcmp(&x.mass, &y.mass, sizeof x.mass) == 0 &&
           memcmp(&x.volume, &y.volume, sizeof x.volume) == 0);
    ENSURE(memcmp(&x.principal, &y.principal, sizeof x.principal) == 0);
    ENSURE(memcmp(&x.inertia, &y.inertia, sizeof x.inertia) == 0);
  }
  free(ids);
  free(other);
}

// Save, load into a runtime built the same way, continue both alike: the
// same hash after every step; the clusters the same bit for bit.
static void test_round_trip_and_continuation(bool refine) {
  bk_mesh_tree tree =
      make_tree_pattern(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 24, bk_default_fracture_def().seed);
  world a = make(&tree, refine), b = make(&tree, refine);
  for (uint32_t k = 0; k < 4; ++k)
    step(&a, k);
  step(&a, 4);
  // Removed clusters leave free slots: the next splits reuse them, the
  // last freed first, so their order is state.
  uint32_t n = bk_runtime_clusters(a.rt, NULL, 0);
  bk_cluster_id* ids = calloc(n + 1u, sizeof *ids);
  bk_runtime_clusters(a.rt, ids, n);
  ENSURE(n >= 4);
  ENSURE(bk_runtime_remove_cluster(a.rt, ids[n - 1]) == BK_OK);
  ENSURE(bk_runtime_remove_cluster(a.rt, ids[1]) == BK_OK);
  bk_runtime_clear_events(a.rt);
  free(ids);
  ENSURE(bk_runtime_cluster_capacity(a.rt) - bk_runtime_clusters(a.rt, NULL, 0) >= 2);
  bk_runtime_damage_at(a.rt, bk_v3(0.2, 0.9, 0.1), 3000.0); // its split waits for the next step
  bk_runtime_stats stats = bk_runtime_get_stats(a.rt);
  ENSURE(stats.pending_splits > 0); // a split waits for the budget
  if (refine) {
    ENSURE(stats.refined_leaves > 0 && stats.refine_pending > 0); // grown, and refinements waiting
    ENSURE(bk_runtime_breakable_tree(a.rt, (bk_breakable_id){1, 1}) != &tree);
  }
  size_t size = 0;
  uint8_t* bytes = save(a.rt, &size);
  uint64_t saved_hash = bk_runtime_state_hash(a.rt);
  // Too small a buffer: refused, naming both sizes.
  bk_error err = {0};
  uint8_t* small = malloc(size);
  ENSURE(bk_runtime_save_state(a.rt, small, size - 1, &err) == 0);
  free(small);
  char expected[128] = {0};
  snprintf(expected, sizeof expected, "state: buffer of %zu bytes is too small, the state needs %zu",
           size - 1, size);
  ENSURE_MSG(strcmp(err.message, expected) == 0, "%s", err.message);

  ENSURE(bk_runtime_state_hash(b.rt) != saved_hash);
  ENSURE_MSG(bk_runtime_load_state(b.rt, bytes, size, &err), "%s", err.message);
  ENSURE(bk_runtime_state_hash(b.rt) == saved_hash);
  ENSURE(bk_runtime_created_clusters(b.rt, NULL, 0) == 0 && bk_runtime_broken_bonds(b.rt, NULL, 0) == 0);
  same_clusters(a.rt, b.rt);
  bk_runtime_stats loaded = bk_runtime_get_stats(b.rt);
  ENSURE(loaded.bonds_broken == stats.bonds_broken && loaded.splits == stats.splits &&
         loaded.refined_leaves == stats.refined_leaves && loaded.refine_pending == stats.refine_pending);
  // Saved again: the same bytes.
  size_t again_size = 0;
  uint8_t* again = save(b.rt, &again_size);
  ENSURE(again_size == size && memcmp(again, bytes, size) == 0);
  free(again);
  // The caller makes a body for every cluster where it had it: here, the same table.
  memcpy(b.b, a.b, sizeof *a.b);
  for (uint32_t k = 5; k < 14; ++k) {
    step(&a, k);
    step(&b, k);
    ENSURE_MSG(bk_runtime_state_hash(a.rt) == bk_runtime_state_hash(b.rt), "step %u", k);
  }
  same_clusters(a.rt, b.rt);
  if (refine) ENSURE(bk_runtime_get_stats(b.rt).refined_leaves > stats.refined_leaves);
  ENSURE(bk_runtime_get_stats(b.rt).splits > stats.splits);
  // Loaded back into the runtime that went on (its tree grown further): as saved.
  ENSURE_MSG(bk_runtime_load_state(a.rt, bytes, size, &err), "%s", err.message);
  ENSURE(bk_runtime_state_hash(a.rt) == saved_hash);
  free(bytes);
  destroy(&a);
  destroy(&b);
  bk_mesh_tree_free(&tree);
}

static uint32_t refusals;

static void expect_refused(bk_runtime* rt, const uint8_t* bytes, size_t size, const char* needle) {
  // The hash (the costly part) on every 61st: a refusal never gets as far as changing anything.
  bool check = refusals++ % 61 == 0;
  uint64_t before = check ? bk_runtime_state_hash(rt) : 0;
  bk_error err = {0};
  ENSURE(!bk_runtime_load_state(rt, bytes, size, &err));
  ENSURE_MSG(one_line(err.message) && strncmp(err.message, "state: ", 7) == 0, "%s", err.message);
  if (needle) ENSURE_MSG(strstr(err.message, needle), "'%s' lacks '%s'", err.message, needle);
  if (check) ENSURE(bk_runtime_state_hash(rt) == before); // nothing changed
}

// Damaged states: each kind refused with its own line, nothing changed.
static void test_refusals(void) {
  bk_mesh_tree tree =
                   make_tree_pattern(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 24, bk_default_fracture_def().seed),
               other_tree =
                   make_tree_pattern(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 20, bk_default_fracture_def().seed);
  world a = make(&tree, false), b = make(&tree, false), c = make(&other_tree, false);
  for (uint32_t k = 0; k < 4; ++k)
    step(&a, k);
  step(&b, 5); // b has a state of its own, which a refusal must leave alone
  size_t size = 0;
  uint8_t* bytes = save(a.rt, &size);
  uint8_t* copy = malloc(size);
  // Every prefix.
  for (size_t n = 0; n < size; ++n)
    expect_refused(b.rt, bytes, n, n < 32 ? "truncated header" : "truncated");
  // A byte flipped anywhere.
  for (size_t at = 0; at < size; ++at) {
    memcpy(copy, bytes, size);
    copy[at] ^= (uint8_t)(1u << (at % 8));
    const char* needle = at < 8    ? "bad magic"
                         : at < 12 ? "version"
                         : at < 16 ? "byte order"
                         : at < 24 ? "payload is"
                                   : "checksum";
    expect_refused(b.rt, copy, size, needle);
  }
  // Another version, and a longer state.
  memcpy(copy, bytes, size);
  copy[8] = 2;
  expect_refused(b.rt, copy, size, "state: version 2 is not supported (expected 1)");
  uint8_t* longer = calloc(size + 1, 1);
  memcpy(longer, bytes, size);
  expect_refused(b.rt, longer, size + 1, "size mismatch");
  free(longer);
  expect_refused(b.rt, NULL, 0, "truncated header");
  // Another tree: named, with both trees' counts.
  expect_refused(c.rt, bytes, size, "state: breakable 0 is another tree: ");
  bk_error err = {0};
  ENSURE(!bk_runtime_load_state(c.rt, bytes, size, &err));
  char counts[96] = {0};
  snprintf(counts, sizeof counts, "(%u nodes, %u leaves, %u bonds) in the state", tree.node_count,
           tree.leaf_count, tree.bond_count);
  ENSURE_MSG(strstr(err.message, counts), "%s", err.message);
  // A runtime with fewer breakables.
  world d = make(&tree, false);
  ENSURE(bk_runtime_remove_breakable(d.rt, (bk_breakable_id){1, 1}) == BK_OK);
  expect_refused(d.rt, bytes, size, "state: breakable 1 is removed here but alive in the state");
  destroy(&d);
  // The untouched runtime still loads it.
  ENSURE_MSG(bk_runtime_load_state(b.rt, bytes, size, &err), "%s", err.message);
  ENSURE(bk_runtime_state_hash(b.rt) == bk_runtime_state_hash(a.rt));
  free(copy);
  free(bytes);
  // A refined one's (its grown tree's bytes inside): a byte in every 509 flipped.
  world e = make(&tree, true), f = make(&tree, true);
  for (uint32_t k = 0; k < 4; ++k)
    step(&e, k);
  bytes = save(e.rt, &size);
  for (size_t at = 32; at < size; at += 509) {
    bytes[at] ^= 0x10;
    expect_refused(f.rt, bytes, size, "checksum mismatch");
    bytes[at] ^= 0x10;
  }
  expect_refused(f.rt, bytes, size / 2, "truncated");
  free(bytes);
  destroy(&e);
  destroy(&f);
  destroy(&a);
  destroy(&b);
  destroy(&c);
  bk_mesh_tree_free(&tree);
  bk_mesh_tree_free(&other_tree);
}

// The header's size and checksum made to match a changed payload: what a
// hostile state (not a damaged one) looks like to the parser.
static void fix_header(uint8_t* bytes, size_t size) {
  uint64_t payload = size - 32, checksum = XXH3_64bits(bytes + 32, payload);
  for (int i = 0; i < 8; ++i) {
    bytes[16 + i] = (uint8_t)(payload >> (8 * i));
    bytes[24 + i] = (uint8_t)(checksum >> (8 * i));
  }
}

// Hostile states: each payload byte set to 0xff (the checksum fixed): refused
// in one line with the runtime unchanged, or loaded into a sound state that
// saves and loads again with its hash.
static void test_hostile(void) {
  bk_mesh_tree tree =
      make_tree_pattern(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 24, bk_default_fracture_def().seed);
  world a = make(&tree, false), b = make(&tree, false), c = make(&tree, false);
  for (uint32_t k = 0; k < 3; ++k)
    step(&a, k);
  size_t size = 0;
  uint8_t* bytes = save(a.rt, &size);
  uint8_t* copy = malloc(size + 8);
  uint32_t corrupt = 0, loaded = 0;
  for (size_t at = 32; at < size; ++at) {
    memcpy(copy, bytes, size);
    if (copy[at] == 0xff) continue;
    copy[at] = 0xff;
    fix_header(copy, size);
    bk_error err = {0};
    if (bk_runtime_load_state(b.rt, copy, size, &err)) {
      // Loaded (a hit point or a counter changed): sound, and it round-trips.
      loaded++;
      size_t again_size = 0;
      uint8_t* again = save(b.rt, &again_size);
      ENSURE_MSG(bk_runtime_load_state(c.rt, again, again_size, &err), "%s", err.message);
      ENSURE(bk_runtime_state_hash(c.rt) == bk_runtime_state_hash(b.rt));
      free(again);
      ENSURE_MSG(bk_runtime_load_state(b.rt, bytes, size, &err), "%s", err.message); // back to the saved one
    } else {
      ENSURE_MSG(one_line(err.message) && strncmp(err.message, "state: ", 7) == 0, "%s", err.message);
      corrupt += strstr(err.message, "state: corrupt: ") != NULL;
    }
  }
  ENSURE(corrupt > 100 && loaded > 0);
  // Bytes after the state, and a state cut short, behind a good checksum.
  memcpy(copy, bytes, size);
  memset(copy + size, 0, 4);
  fix_header(copy, size + 4);
  expect_refused(b.rt, copy, size + 4, "state: corrupt: 4 bytes after the state");
  fix_header(copy, size - 4);
  expect_refused(b.rt, copy, size - 4, "state: corrupt: ends inside the statistics");
  free(copy);
  free(bytes);
  destroy(&a);
  destroy(&b);
  destroy(&c);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  test_round_trip_and_continuation(false);
  test_round_trip_and_continuation(true);
  test_refusals();
  test_hostile();
  return 0;
}
