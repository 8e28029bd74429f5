// The stress solve as a stage that reports fracture commands and the core
// that applies them: the commands reported are the bonds that break when
// applied, bk_runtime_solve_stress is exactly the two halves, not applying
// breaks nothing, a full array defers a cluster, and the core refuses
// commands that no longer hold.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "ensure.h"
#include "runtime_caller.h"

enum { MAX_COMMANDS = 8192 };

static const bk_vec3 gravity = {0.0, -9.81, 0.0};

typedef struct scene {
  bodies* bodies;
  bk_runtime* rt;
  bk_breakable_id id;
} scene;

// The bridge with its limits scaled down 10x: it comes down under its own
// weight over a few hundred calls, breaking bonds in many of them.
static scene make_scene(const bk_mesh_tree* tree) {
  scene s = {.bodies = calloc(1, sizeof(bodies))};
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = s.bodies;
  bk_error err = {0};
  s.rt = bk_runtime_create(&def, &err);
  ENSURE_MSG(s.rt, "%s", err.message);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = tree;
  bd.anchored = true;
  bd.material = *bk_material_find("concrete");
  bd.material.compression_limit *= 0.1;
  bd.material.tension_limit *= 0.1;
  bd.material.shear_limit *= 0.1;
  s.id = bk_runtime_add_breakable(s.rt, &bd, &err);
  ENSURE_MSG(!bk_breakable_is_null(s.id), "%s", err.message);
  take_created(s.rt, s.bodies);
  return s;
}

static void free_scene(scene* s) {
  bk_runtime_destroy(s->rt);
  free(s->bodies);
}

static bk_mesh_tree make_tree(void) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_BRIDGE, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = 256;
  def.pattern = BK_PATTERN_VORONOI;
  def.seed = 7;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &def, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

static uint32_t broken_events(const bk_runtime* rt, bk_bond_break* out) {
  uint32_t n = bk_runtime_broken_bonds(rt, NULL, 0);
  ENSURE(n <= MAX_COMMANDS);
  return bk_runtime_broken_bonds(rt, out, n);
}

static bool same_vec(bk_vec3 a, bk_vec3 b) { return memcmp(&a, &b, sizeof a) == 0; }

// Two runtimes in lockstep: one calls bk_runtime_solve_stress, the other
// the two halves. Each call's commands are the bonds the apply breaks, in
// order, and the same breaks as the convenience's, bit for bit.
static void test_commands_are_the_breaks(const bk_mesh_tree* tree) {
  scene whole = make_scene(tree), halves = make_scene(tree);
  bk_fracture_command* commands = calloc(MAX_COMMANDS, sizeof *commands);
  bk_bond_break* a = calloc(MAX_COMMANDS, sizeof *a);
  bk_bond_break* b = calloc(MAX_COMMANDS, sizeof *b);
  uint32_t total = 0, calls_with_breaks = 0;
  for (uint32_t call = 0; call < 2000; ++call) {
    bk_runtime_solve_stress(whole.rt, gravity, NULL, 0, NULL, 0);
    uint32_t n = bk_runtime_stress_commands(halves.rt, gravity, NULL, 0, NULL, 0, commands, MAX_COMMANDS);
    ENSURE(bk_runtime_broken_bonds(halves.rt, NULL, 0) == 0); // reporting breaks nothing
    ENSURE(bk_runtime_apply_fracture_commands(halves.rt, commands, n) == n);
    uint32_t na = broken_events(whole.rt, a), nb = broken_events(halves.rt, b);
    ENSURE_MSG(na == n && nb == n, "call %u: %u commands, %u and %u breaks", call, n, na, nb);
    for (uint32_t k = 0; k < n; ++k) {
      ENSURE(b[k].bond == commands[k].bond && b[k].cause == BK_BREAK_STRESS);
      ENSURE(bk_cluster_equal(b[k].cluster, commands[k].cluster));
      ENSURE(same_vec(b[k].position, commands[k].position) && same_vec(b[k].velocity, commands[k].velocity));
      ENSURE(a[k].bond == b[k].bond && bk_cluster_equal(a[k].cluster, b[k].cluster));
      ENSURE(same_vec(a[k].position, b[k].position) && same_vec(a[k].velocity, b[k].velocity));
    }
    total += n;
    calls_with_breaks += n > 0;
    bk_runtime_split(whole.rt);
    bk_runtime_split(halves.rt);
    take_created(whole.rt, whole.bodies);
    take_created(halves.rt, halves.bodies);
    bk_runtime_stats sa = bk_runtime_get_stats(whole.rt), sb = bk_runtime_get_stats(halves.rt);
    ENSURE(sa.clusters == sb.clusters && sa.bonds_broken == sb.bonds_broken);
    ENSURE(sa.stress_bonds_broken == sb.stress_bonds_broken && sb.stress_bonds_broken == total);
    if (sa.stress_clusters_pending == 0 && sa.pending_splits == 0 && n == 0) break;
  }
  printf("  bridge, limits / 10: %u commands over %u calls, each the bonds its apply broke\n", total,
         calls_with_breaks);
  ENSURE(total > 0 && calls_with_breaks > 1);
  free(a);
  free(b);
  free(commands);
  free_scene(&whole);
  free_scene(&halves);
}

// Commands not applied break nothing and are not reported again; applied
// later, they break exactly their bonds, once.
static void test_unapplied_commands_break_nothing(const bk_mesh_tree* tree) {
  scene s = make_scene(tree);
  bk_fracture_command* commands = calloc(MAX_COMMANDS, sizeof *commands);
  uint32_t n = 0, call = 0;
  for (; call < 2000 && n == 0; ++call)
    n = bk_runtime_stress_commands(s.rt, gravity, NULL, 0, NULL, 0, commands, MAX_COMMANDS);
  ENSURE_MSG(n > 1, "%u commands after %u calls", n, call);
  for (uint32_t more = 0; more < 50; ++more) // settled: nothing new to report
    ENSURE(bk_runtime_stress_commands(s.rt, gravity, NULL, 0, NULL, 0, commands + n, MAX_COMMANDS - n) == 0);
  bk_runtime_stats st = bk_runtime_get_stats(s.rt);
  ENSURE(st.bonds_broken == 0 && st.stress_bonds_broken == 0 && st.clusters == 1 && st.pending_splits == 0);
  ENSURE(bk_runtime_broken_bonds(s.rt, NULL, 0) == 0);
  for (uint32_t k = 0; k < n; ++k) {
    double initial = 0.0;
    ENSURE(bk_runtime_bond_health(s.rt, s.id, commands[k].bond, &initial) == initial && initial > 0.0);
    bk_bond_stress stress = {0};
    ENSURE(bk_runtime_bond_stress(s.rt, s.id, commands[k].bond, &stress) && stress.ratio > 1.0);
  }
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, commands, n) == n);
  st = bk_runtime_get_stats(s.rt);
  ENSURE(st.bonds_broken == n && st.stress_bonds_broken == n && st.pending_splits == 1);
  for (uint32_t k = 0; k < n; ++k)
    ENSURE(bk_runtime_bond_health(s.rt, s.id, commands[k].bond, NULL) == 0.0);
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, commands, n) == 0); // broken already
  ENSURE(bk_runtime_broken_bonds(s.rt, NULL, 0) == n);
  free(commands);
  free_scene(&s);
}

// A cluster whose commands do not all fit writes none and is reported again,
// whole, on a call with room.
static void test_full_array_defers(const bk_mesh_tree* tree) {
  scene s = make_scene(tree), reference = make_scene(tree);
  bk_fracture_command* commands = calloc(MAX_COMMANDS, sizeof *commands);
  bk_fracture_command* expected = calloc(MAX_COMMANDS, sizeof *expected);
  uint32_t n = 0, call = 0;
  for (; call < 2000 && n == 0; ++call) {
    n = bk_runtime_stress_commands(reference.rt, gravity, NULL, 0, NULL, 0, expected, MAX_COMMANDS);
    bk_runtime_stress_commands(s.rt, gravity, NULL, 0, NULL, 0, NULL, 0);
  }
  ENSURE(n > 1);
  // The call that found them with room finds them again here: too few places.
  ENSURE(bk_runtime_stress_commands(s.rt, gravity, NULL, 0, NULL, 0, commands, n - 1) == 0);
  ENSURE(bk_runtime_get_stats(s.rt).stress_clusters_pending == 1);
  uint32_t again = bk_runtime_stress_commands(s.rt, gravity, NULL, 0, NULL, 0, commands, n);
  ENSURE_MSG(again == n, "%u commands, %u reported with room", n, again);
  for (uint32_t k = 0; k < n; ++k)
    ENSURE(commands[k].bond == expected[k].bond &&
           bk_cluster_equal(commands[k].cluster, expected[k].cluster));
  ENSURE(bk_runtime_get_stats(s.rt).stress_clusters_pending == 0);
  free(commands);
  free(expected);
  free_scene(&s);
  free_scene(&reference);
}

// The core applies only commands that still hold.
static void test_bad_commands_are_skipped(const bk_mesh_tree* tree) {
  scene s = make_scene(tree);
  bk_cluster_id cluster = bk_runtime_leaf_cluster(s.rt, s.id, 0);
  const bk_bond* bond = &tree->bonds[0];
  bk_fracture_command good = {.cluster = cluster, .bond = 0, .cause = BK_BREAK_STRESS};
  bk_fracture_command bad[4] = {good, good, good, good};
  bad[0].bond = tree->bond_count;             // out of range
  bad[1].cluster.generation++;                // stale
  bad[2].cause = (bk_break_cause)7;           // not a cause
  bad[3].cluster = (bk_cluster_id){999u, 1u}; // never made
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, bad, 4) == 0);
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, NULL, 4) == 0);
  ENSURE(bk_runtime_broken_bonds(s.rt, NULL, 0) == 0 && bk_runtime_get_stats(s.rt).bonds_broken == 0);
  // A damage command counts as a break but not as stress.
  good.cause = BK_BREAK_DAMAGE;
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, &good, 1) == 1);
  bk_runtime_stats st = bk_runtime_get_stats(s.rt);
  ENSURE(st.bonds_broken == 1 && st.stress_bonds_broken == 0);
  bk_bond_break event = {0};
  ENSURE(bk_runtime_broken_bonds(s.rt, &event, 1) == 1 && event.bond == 0 && event.cause == BK_BREAK_DAMAGE);
  ENSURE(event.area == bond->area);
  // Leaf 0 cut loose (every bond of it broken, split): a command naming its
  // cluster and an intact bond elsewhere names a bond not inside it.
  for (uint32_t k = 1; k < tree->bond_count; ++k) {
    bk_fracture_command cut = {.cluster = cluster, .bond = k, .cause = BK_BREAK_DAMAGE};
    if (tree->bonds[k].leaf_a == 0 || tree->bonds[k].leaf_b == 0)
      ENSURE(bk_runtime_apply_fracture_commands(s.rt, &cut, 1) == 1);
  }
  bk_runtime_split(s.rt);
  take_created(s.rt, s.bodies);
  bk_cluster_id chip = bk_runtime_leaf_cluster(s.rt, s.id, 0);
  bk_cluster_info info = {0};
  ENSURE(bk_runtime_cluster(s.rt, chip, &info) && info.leaf_count == 1);
  uint32_t elsewhere = 1;
  while (tree->bonds[elsewhere].leaf_a == 0 || tree->bonds[elsewhere].leaf_b == 0)
    elsewhere++;
  bk_fracture_command outside = {.cluster = chip, .bond = elsewhere, .cause = BK_BREAK_STRESS};
  ENSURE(bk_runtime_bond_health(s.rt, s.id, elsewhere, NULL) > 0.0);
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, &outside, 1) == 0);
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, &good, 1) == 0); // its cluster split: stale
  outside.cluster = bk_runtime_leaf_cluster(s.rt, s.id, tree->bonds[elsewhere].leaf_a);
  ENSURE(bk_runtime_apply_fracture_commands(s.rt, &outside, 1) == 1); // named by its own cluster
  free_scene(&s);
}

int main(void) {
  bk_mesh_tree tree = make_tree();
  test_commands_are_the_breaks(&tree);
  test_unapplied_commands_break_nothing(&tree);
  test_full_array_defers(&tree);
  test_bad_commands_are_skipped(&tree);
  bk_mesh_tree_free(&tree);
  printf("test_stress_commands: ok\n");
  return 0;
}
