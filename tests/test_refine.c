// Refinement in the runtime (no physics engine): a hit on a coarse wall
// fractures the fragments it strikes again around the hit, the grown tree is
// exact (valid, closed, bonds against a brute-force measure), the hit's
// damage breaks the pieces' bonds as if they had been there, the result is
// the same on any thread count, and the settings (latency, per-call limit,
// pieces) do what they say.
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "ensure.h"
#include "runtime_caller.h"
#include "tree_bonds.h"
#include "tree_bytes.h"

static bk_mesh_tree wall_tree(uint32_t pieces) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_WALL, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = BK_PATTERN_VORONOI;
  def.pieces = pieces;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &def, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

typedef struct setup {
  uint32_t latency, threads, per_call, pieces;
  bool refine;
} setup;

static bk_runtime* make_runtime(bodies* b, setup s) {
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = b;
  def.refine_latency = s.latency;
  def.refine_threads = s.threads;
  def.max_refinements_per_call = s.per_call;
  bk_error err = {0};
  bk_runtime* rt = bk_runtime_create(&def, &err);
  ENSURE_MSG(rt, "%s", err.message);
  return rt;
}

static bk_breakable_def wall_def(const bk_mesh_tree* tree, setup s) {
  bk_breakable_def def = bk_default_breakable_def();
  def.tree = tree;
  def.material = *bk_material_find("stone");
  if (s.refine) def.material.refine_strength = def.material.bond_strength / 8.0;
  def.refine.pieces = s.pieces;
  def.refine.min_size = 0.01;
  return def;
}

// The hit: a blast on the wall's face, a little off its centre.
static const bk_vec3 hit_point = {0.3, 1.1, 0.12};

// Hits once and calls refine and split once a step, as a game does; returns
// the refine calls that landed something, in a bit mask.
static uint32_t run(bk_runtime* rt, bodies* b, uint32_t steps) {
  uint32_t landed_at = 0;
  bk_runtime_damage_at(rt, hit_point, 400.0);
  for (uint32_t step = 0; step < steps; ++step) {
    if (bk_runtime_refine(rt)) landed_at |= 1u << step;
    bk_runtime_split(rt);
    take_created(rt, b);
  }
  return landed_at;
}

// Every leaf is in exactly one live cluster, whose node set is the minimal
// one of its leaves; masses add up to the whole's.
static void check_clusters(bk_runtime* rt, bk_breakable_id id, double whole_mass) {
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(rt, id);
  uint32_t n = bk_runtime_clusters(rt, NULL, 0);
  bk_cluster_id* ids = calloc(n + 1u, sizeof *ids);
  bk_runtime_clusters(rt, ids, n);
  uint8_t* seen = calloc(tree->leaf_count, 1);
  uint32_t* nodes = calloc(tree->leaf_count, sizeof(uint32_t));
  double mass = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    bk_cluster_info info = {0};
    ENSURE(bk_runtime_cluster(rt, ids[i], &info));
    if (info.breakable.index != id.index) continue;
    mass += info.mass;
    for (uint32_t k = 0; k < info.leaf_count; ++k) {
      ENSURE(info.leaves[k] < tree->leaf_count && !seen[info.leaves[k]]);
      ENSURE(k == 0 || info.leaves[k] > info.leaves[k - 1]);
      seen[info.leaves[k]] = 1;
      ENSURE(bk_cluster_equal(bk_runtime_leaf_cluster(rt, id, info.leaves[k]), ids[i]));
    }
    uint32_t count = bk_minimal_nodes(tree, info.leaves, info.leaf_count, nodes);
    ENSURE(count == info.node_count && memcmp(nodes, info.nodes, sizeof(uint32_t) * count) == 0);
  }
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    ENSURE_MSG(seen[l], "leaf %u is in no cluster", l);
  ENSURE_REL(mass, whole_mass, 1e-9);
  free(ids);
  free(seen);
  free(nodes);
}

static double smallest_cluster_volume(bk_runtime* rt) {
  uint32_t n = bk_runtime_clusters(rt, NULL, 0);
  bk_cluster_id* ids = calloc(n + 1u, sizeof *ids);
  bk_runtime_clusters(rt, ids, n);
  double smallest = INFINITY;
  for (uint32_t i = 0; i < n; ++i) {
    bk_cluster_info info = {0};
    bk_runtime_cluster(rt, ids[i], &info);
    smallest = fmin(smallest, info.volume);
  }
  free(ids);
  return smallest;
}

static void test_refines_and_is_exact(void) {
  bk_mesh_tree tree = wall_tree(16);
  bk_mesh_tree untouched = wall_tree(16);
  setup s = {.latency = 1, .threads = 1, .per_call = 4, .pieces = 24, .refine = true};
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, s);
  bk_breakable_def def = wall_def(&tree, s);
  bk_error err = {0};
  bk_breakable_id id = bk_runtime_add_breakable(rt, &def, &err);
  ENSURE_MSG(!bk_breakable_is_null(id), "%s", err.message);
  // A second instance of the same tree is not changed by the first's refinement.
  def.transform.position = bk_v3(10, 0, 0);
  bk_breakable_id other = bk_runtime_add_breakable(rt, &def, &err);
  take_created(rt, b);
  bk_cluster_info whole = {0};
  ENSURE(bk_runtime_cluster(rt, bk_runtime_leaf_cluster(rt, id, 0), &whole));
  double whole_mass = whole.mass;
  bk_vec3 whole_inertia = whole.inertia;

  // Latency 1: marked by the hit, started by the first call, landed by the second.
  bk_runtime_damage_at(rt, hit_point, 400.0);
  ENSURE(bk_runtime_get_stats(rt).refine_pending >= 1);
  uint32_t pending = bk_runtime_get_stats(rt).refine_pending;
  uint32_t broken_at_hit = bk_runtime_broken_bonds(rt, NULL, 0); // bonds of fragments not refined
  ENSURE(bk_runtime_refine(rt) == 0);
  ENSURE(bk_runtime_refine(rt) == pending);
  ENSURE(bk_runtime_get_stats(rt).refine_pending == 0);
  const bk_mesh_tree* grown = bk_runtime_breakable_tree(rt, id);
  ENSURE(grown != &tree && grown->leaf_count > tree.leaf_count);
  ENSURE(bk_runtime_breakable_tree(rt, other) == &tree);
  ENSURE(trees_same_bytes(&tree, &untouched)); // the caller's tree is as it was
  uint32_t events = bk_runtime_refined_leaves(rt, NULL, 0);
  ENSURE(events == pending);
  bk_leaf_refined* refined = calloc(events, sizeof *refined);
  bk_runtime_refined_leaves(rt, refined, events);
  uint32_t added = 0;
  for (uint32_t i = 0; i < events; ++i) {
    ENSURE(refined[i].splice.leaf_count >= 2 && refined[i].splice.leaf_count <= s.pieces);
    ENSURE(bk_cluster_equal(refined[i].cluster, whole.id)); // the whole wall's cluster holds them
    added += refined[i].splice.leaf_count - 1;
  }
  ENSURE(grown->leaf_count == tree.leaf_count + added);
  free(refined);
  // Exact: valid, closed, volumes, bonds against the brute force.
  ENSURE_MSG(bk_mesh_tree_validate(grown, &err), "%s", err.message);
  ENSURE(bk_mesh_tree_measure(grown).open_nodes == 0);
  check_bonds_brute_force(grown, 1e-9);
  // The cluster kept its body: the same node set, mass and inertia, bit for bit.
  bk_cluster_info after = {0};
  ENSURE(bk_runtime_cluster(rt, whole.id, &after));
  ENSURE(after.node_count == 1 && after.nodes[0] == 0);
  ENSURE(after.mass == whole_mass && memcmp(&after.inertia, &whole_inertia, sizeof whole_inertia) == 0);
  // The waiting damage broke the pieces' bonds near the hit; the split makes them bodies.
  ENSURE(bk_runtime_broken_bonds(rt, NULL, 0) > broken_at_hit);
  ENSURE(bk_runtime_split(rt) > 0);
  take_created(rt, b);
  check_clusters(rt, id, whole_mass);
  // Hit points: a divided bond's parts are whole (the hit broke or spared them).
  for (uint32_t j = 0; j < grown->bond_count; ++j) {
    double initial = 0.0;
    bk_runtime_bond_health(rt, id, j, &initial);
    ENSURE_REL(initial, def.material.bond_strength * grown->bonds[j].area, 1e-12);
  }
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&untouched);
  bk_mesh_tree_free(&tree);
  free(b);
}

// Runs the hit with these settings; returns the grown tree's bytes' equality
// with `reference` (if given) and fills the counts.
typedef struct outcome {
  uint32_t leaves, clusters, broken, landed_at;
  double smallest;
  bk_mesh_tree tree_copy; // saved and loaded back, to compare
} outcome;

static outcome run_with(const bk_mesh_tree* tree, setup s) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, s);
  bk_breakable_def def = wall_def(tree, s);
  bk_error err = {0};
  bk_breakable_id id = bk_runtime_add_breakable(rt, &def, &err);
  ENSURE_MSG(!bk_breakable_is_null(id), "%s", err.message);
  take_created(rt, b);
  outcome o = {0};
  o.landed_at = run(rt, b, 6);
  const bk_mesh_tree* grown = bk_runtime_breakable_tree(rt, id);
  o.leaves = grown->leaf_count;
  o.clusters = bk_runtime_get_stats(rt).clusters;
  o.broken = bk_runtime_get_stats(rt).bonds_broken;
  o.smallest = smallest_cluster_volume(rt);
  uint8_t* bytes = NULL;
  size_t size = 0;
  ENSURE_MSG(bk_mesh_tree_save_memory(grown, "grown", &bytes, &size, &err), "%s", err.message);
  ENSURE_MSG(bk_mesh_tree_load_memory(bytes, size, "grown", &o.tree_copy, &err), "%s", err.message);
  free(bytes);
  bk_runtime_destroy(rt);
  free(b);
  return o;
}

static void test_outcome_and_determinism(void) {
  bk_mesh_tree tree = wall_tree(16);
  setup base = {.latency = 1, .threads = 1, .per_call = 4, .pieces = 24, .refine = true};
  outcome refined = run_with(&tree, base);
  setup coarse_setup = base;
  coarse_setup.refine = false;
  outcome coarse = run_with(&tree, coarse_setup);
  // Without refinement the wall breaks into its coarse fragments.
  ENSURE(coarse.leaves == tree.leaf_count && coarse.landed_at == 0);
  ENSURE(refined.leaves > tree.leaf_count);
  ENSURE_MSG(refined.clusters > coarse.clusters, "%u clusters refined, %u coarse", refined.clusters,
             coarse.clusters);
  ENSURE(refined.smallest < 0.5 * coarse.smallest);
  ENSURE(refined.landed_at == 2u); // the second call after the hit
  // The same on the calling thread as on a worker, bit for bit.
  setup here = base;
  here.threads = 0;
  outcome same = run_with(&tree, here);
  ENSURE(trees_same_bytes(&refined.tree_copy, &same.tree_copy));
  ENSURE(same.clusters == refined.clusters && same.broken == refined.broken);
  // Latency: 0 lands in the first call, 2 in the third.
  setup now = base;
  now.latency = 0;
  outcome immediate = run_with(&tree, now);
  ENSURE(immediate.landed_at == 1u);
  bk_mesh_tree_free(&immediate.tree_copy);
  setup later = base;
  later.latency = 2;
  outcome late = run_with(&tree, later);
  ENSURE(late.landed_at == 4u);
  ENSURE(trees_same_bytes(&late.tree_copy, &refined.tree_copy)); // the same pieces, later
  // One refinement per call: one fragment refined.
  setup one = base;
  one.per_call = 1;
  outcome single = run_with(&tree, one);
  ENSURE(single.leaves < refined.leaves);
  // More pieces per refinement: more leaves.
  setup more = base;
  more.pieces = 48;
  outcome finer = run_with(&tree, more);
  ENSURE(finer.leaves > refined.leaves);
  bk_mesh_tree_free(&finer.tree_copy);
  bk_mesh_tree_free(&refined.tree_copy);
  bk_mesh_tree_free(&coarse.tree_copy);
  bk_mesh_tree_free(&same.tree_copy);
  bk_mesh_tree_free(&late.tree_copy);
  bk_mesh_tree_free(&single.tree_copy);
  bk_mesh_tree_free(&tree);
}

// Removing a breakable while its fragments are being refined, or destroying
// the runtime then, waits for the workers and leaks nothing.
static void test_removed_while_refining(void) {
  bk_mesh_tree tree = wall_tree(16);
  setup s = {.latency = 3, .threads = 2, .per_call = 4, .pieces = 24, .refine = true};
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, s);
  bk_breakable_def def = wall_def(&tree, s);
  bk_breakable_id id = bk_runtime_add_breakable(rt, &def, NULL);
  take_created(rt, b);
  bk_runtime_damage_at(rt, hit_point, 400.0);
  bk_runtime_refine(rt); // started on the workers
  ENSURE(bk_runtime_get_stats(rt).refine_pending > 0);
  ENSURE(bk_runtime_remove_breakable(rt, id) == BK_OK);
  ENSURE(bk_runtime_get_stats(rt).refine_pending == 0);
  ENSURE(bk_runtime_refine(rt) == 0);
  id = bk_runtime_add_breakable(rt, &def, NULL);
  bk_runtime_damage_at(rt, hit_point, 400.0);
  bk_runtime_refine(rt);
  bk_runtime_destroy(rt); // workers still running
  bk_mesh_tree_free(&tree);
  free(b);
}

// A body the caller's physics lost (a transform not finite) between the hit
// and the landing takes none of the waiting damage: its breaks would be
// nowhere (as a hit on it breaks nothing). The pieces still land.
static void test_lost_body_takes_no_waiting_damage(void) {
  bk_mesh_tree tree = wall_tree(16);
  setup s = {.latency = 1, .threads = 0, .per_call = 4, .pieces = 24, .refine = true};
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, s);
  bk_breakable_def def = wall_def(&tree, s);
  bk_breakable_id id = bk_runtime_add_breakable(rt, &def, NULL);
  take_created(rt, b);
  bk_runtime_damage_at(rt, hit_point, 400.0);
  uint32_t broken = bk_runtime_broken_bonds(rt, NULL, 0);
  bk_cluster_id whole = bk_runtime_leaf_cluster(rt, id, 0);
  b->state[whole.index].transform.position.x = NAN;
  bk_runtime_refine(rt);
  ENSURE(bk_runtime_refine(rt) > 0);
  ENSURE_MSG(bk_runtime_broken_bonds(rt, NULL, 0) == broken, "%u bonds broke at the landing",
             bk_runtime_broken_bonds(rt, NULL, 0) - broken);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

static void test_bad_settings(void) {
  bk_mesh_tree tree = wall_tree(8);
  bodies* b = calloc(1, sizeof *b);
  setup s = {.latency = 1, .threads = 1, .per_call = 4, .pieces = 24, .refine = true};
  bk_runtime* rt = make_runtime(b, s);
  bk_breakable_def def = wall_def(&tree, s);
  bk_error err = {0};
  def.refine.pieces = 1;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &def, &err)));
  ENSURE_MSG(strcmp(err.message, "breakable: refine.pieces must be in [2, 1024] (got 1)") == 0, "%s",
             err.message);
  ENSURE(err.code == BK_ERROR_INVALID_ARGUMENT);
  def.refine.pieces = 8;
  def.refine.pattern = BK_PATTERN_BRICK;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &def, &err)));
  ENSURE_MSG(strstr(err.message, "refine.pattern must be radial, voronoi or planes (got brick)"), "%s",
             err.message);
  def.refine.pattern = BK_PATTERN_RADIAL;
  def.material.refine_strength = NAN;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &def, &err)));
  ENSURE_MSG(strstr(err.message, "material.refine_strength must be finite and >= 0 (got nan)"), "%s",
             err.message);
  // Off (0), a bad refine def does not matter.
  def.material.refine_strength = 0.0;
  def.refine.pieces = 0;
  ENSURE(!bk_breakable_is_null(bk_runtime_add_breakable(rt, &def, &err)));
  bk_runtime_destroy(rt);
  bk_runtime_def rdef = bk_default_runtime_def();
  rdef.body_state = body_state;
  rdef.refine_latency = 9;
  ENSURE(!bk_runtime_create(&rdef, &err));
  ENSURE_MSG(strcmp(err.message, "runtime: refine_latency must be in [0, 8] (got 9)") == 0, "%s",
             err.message);
  rdef.refine_latency = 1;
  rdef.max_refinements_per_call = 0;
  ENSURE(!bk_runtime_create(&rdef, &err));
  ENSURE_MSG(strstr(err.message, "max_refinements_per_call must be at least 1"), "%s", err.message);
  bk_mesh_tree_free(&tree);
  free(b);
}

int main(void) {
  test_refines_and_is_exact();
  test_outcome_and_determinism();
  test_removed_while_refining();
  test_lost_body_takes_no_waiting_damage();
  test_bad_settings();
  printf("refine ok\n");
  return 0;
}
