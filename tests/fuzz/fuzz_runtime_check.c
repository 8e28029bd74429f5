// fuzz_runtime: the trees, and the checks after every call (see fuzz_runtime.c).
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_runtime.h"

bool bk_fuzz_trace;

// ---------------------------------------------------------------- the trees

bk_mesh_tree bk_fuzz_trees[TREE_COUNT];
static double tree_volume[TREE_COUNT];

static void build_tree(uint32_t index, bk_shape shape, uint32_t pieces, bk_fracture_pattern pattern) {
  bk_mesh mesh = {0};
  bk_shape_build(shape, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = pieces;
  def.pattern = pattern;
  def.seed = 11;
  def.aspect_bias = 1.5;
  def.threads = 1;
  bk_error err = {{0}};
  if (!bk_mesh_tree_build(&mesh, &def, &bk_fuzz_trees[index], &err))
    bk_fuzz_fail("cannot build tree %u: %s", index, err.message);
  bk_mesh_free(&mesh);
  if (bk_fuzz_trees[index].leaf_count > MAX_LEAVES)
    bk_fuzz_fail("tree %u has more than %d leaves", index, MAX_LEAVES);
  tree_volume[index] = bk_mesh_tree_mass(&bk_fuzz_trees[index], bk_fuzz_trees[index].nodes[0].moments).volume;
}

// Built once per process: the runs share them (libFuzzer), the replay's
// children each build their own.
void bk_fuzz_build_trees(void) {
  static bool built = false;
  if (built) return;
  build_tree(0, BK_SHAPE_CUBE, 8, BK_PATTERN_PLANES);
  build_tree(1, BK_SHAPE_CUBE, 27, BK_PATTERN_VORONOI);
  build_tree(2, BK_SHAPE_TOWER, 12, BK_PATTERN_PLANES);
  build_tree(3, BK_SHAPE_CUBE, 1, BK_PATTERN_PLANES);
  built = true;
}

tracked* bk_fuzz_find_tracked(session* s, bk_breakable_id id) {
  for (uint32_t i = 0; i < s->breakable_count; ++i)
    if (s->breakables[i].id.index == id.index && s->breakables[i].id.generation == id.generation)
      return &s->breakables[i];
  return NULL;
}

// ---------------------------------------------------------------- the checks

void bk_fuzz_check_state(session* s, const char* call) {
  bk_runtime* rt = s->rt;
  uint32_t live = bk_runtime_clusters(rt, NULL, 0);
  if (live > MAX_CLUSTERS) bk_fuzz_fail("%s: %u live clusters", call, live);
  if (bk_runtime_clusters(rt, s->live, MAX_CLUSTERS) != live)
    bk_fuzz_fail("%s: the live count changed between two queries", call);
  s->live_count = live;
  bk_runtime_stats st = bk_runtime_get_stats(rt);
  if (st.clusters != live) bk_fuzz_fail("%s: stats count %u clusters, %u are live", call, st.clusters, live);
  if (st.breakables != s->breakable_count)
    bk_fuzz_fail("%s: stats count %u breakables, %u were added", call, st.breakables, s->breakable_count);
  for (uint32_t t = 0; t < s->breakable_count; ++t) {
    const tracked* tb = &s->breakables[t];
    const bk_mesh_tree* tree = &bk_fuzz_trees[tb->tree];
    if (bk_runtime_breakable_tree(rt, tb->id) != tree)
      bk_fuzz_fail("%s: breakable %u lost its tree", call, t);
    uint8_t owners[MAX_LEAVES] = {0};
    double volume = tb->removed_volume, mass = 0.0;
    double density = bk_runtime_density(rt, tb->id);
    for (uint32_t i = 0; i < live; ++i) {
      bk_cluster_info info = {0};
      if (!bk_runtime_cluster(rt, s->live[i], &info))
        bk_fuzz_fail("%s: listed cluster %u is not live", call, s->live[i].index);
      if (info.breakable.index != tb->id.index || info.breakable.generation != tb->id.generation) continue;
      if (info.leaf_count == 0) bk_fuzz_fail("%s: cluster %u has no leaves", call, info.id.index);
      uint32_t covered = 0;
      for (uint32_t k = 0; k < info.node_count; ++k) {
        const bk_mesh_tree_node* node = &tree->nodes[info.nodes[k]];
        covered += node->leaf_end - node->leaf_begin;
      }
      if (covered != info.leaf_count)
        bk_fuzz_fail("%s: cluster %u: its %u nodes cover %u leaves, it has %u", call, info.id.index,
                     info.node_count, covered, info.leaf_count);
      for (uint32_t k = 0; k < info.leaf_count; ++k) {
        uint32_t leaf = info.leaves[k];
        if (leaf >= tree->leaf_count || (k && leaf <= info.leaves[k - 1]))
          bk_fuzz_fail("%s: cluster %u: leaf %u out of order or range", call, info.id.index, leaf);
        owners[leaf]++;
        if (!bk_cluster_equal(bk_runtime_leaf_cluster(rt, tb->id, leaf), info.id))
          bk_fuzz_fail("%s: leaf %u of cluster %u says it is elsewhere", call, leaf, info.id.index);
      }
      bool finite = isfinite(info.mass) && isfinite(info.volume) && bk_v3_is_finite(info.inertia) &&
                    bk_v3_is_finite(info.principal.position);
      if (!finite || !(info.mass > 0.0) || !(info.volume > 0.0) || !(info.inertia.x > 0.0) ||
          !(info.inertia.y > 0.0) || !(info.inertia.z > 0.0))
        bk_fuzz_fail("%s: cluster %u: mass %g, volume %g, inertia %g %g %g", call, info.id.index, info.mass,
                     info.volume, info.inertia.x, info.inertia.y, info.inertia.z);
      if (!(fabs(info.mass - density * info.volume) <= 1e-12 * info.mass))
        bk_fuzz_fail("%s: cluster %u: mass %.17g is not density %.17g x volume %.17g", call, info.id.index,
                     info.mass, density, info.volume);
      volume += info.volume;
      mass += info.mass;
    }
    for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf) {
      uint32_t expected = tb->retired[leaf] ? 0u : 1u;
      if (owners[leaf] != expected)
        bk_fuzz_fail("%s: breakable %u: leaf %u is in %u live clusters (expected %u)", call, t, leaf,
                     owners[leaf], expected);
      if (!expected && !bk_cluster_is_null(bk_runtime_leaf_cluster(rt, tb->id, leaf)))
        bk_fuzz_fail("%s: breakable %u: removed leaf %u still names a cluster", call, t, leaf);
    }
    double whole = tree_volume[tb->tree];
    if (!(fabs(volume - whole) <= REL_TOLERANCE * whole))
      bk_fuzz_fail("%s: breakable %u: cluster volumes add up to %.17g, the tree's is %.17g", call, t, volume,
                   whole);
    double expected_mass = density * (whole - tb->removed_volume);
    if (!(fabs(mass - expected_mass) <= REL_TOLERANCE * density * whole))
      bk_fuzz_fail("%s: breakable %u: cluster masses add up to %.17g, expected %.17g", call, t, mass,
                   expected_mass);
  }
  s->bonds_broken = st.bonds_broken;
}

// Pulls the results of the last call and checks them against what it may
// have done: the live count moved by created - removed, broken bonds are dead.
void bk_fuzz_check_results(session* s, const char* call, uint32_t live_before, uint32_t bonds_before,
                           bool may_break) {
  bk_runtime* rt = s->rt;
  uint32_t created = bk_runtime_created_clusters(rt, NULL, 0);
  uint32_t removed = bk_runtime_removed_clusters(rt, NULL, 0);
  uint32_t broken = bk_runtime_broken_bonds(rt, NULL, 0);
  if (s->live_count + removed != live_before + created)
    bk_fuzz_fail("%s: %u live clusters before, %u after, with %u created and %u removed", call, live_before,
                 s->live_count, created, removed);
  uint32_t delta = s->bonds_broken - bonds_before;
  if (delta != broken || (!may_break && broken))
    bk_fuzz_fail("%s: %u bonds broken by the count, %u reported", call, delta, broken);
  bk_cluster_created* c = calloc(created + 1u, sizeof *c);
  bk_runtime_created_clusters(rt, c, created);
  for (uint32_t i = 0; i < created; ++i) {
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(rt, c[i].cluster.id, &info))
      bk_fuzz_fail("%s: created cluster %u is not live", call, c[i].cluster.id.index);
    if (c[i].cluster.id.index >= MAX_CLUSTERS)
      bk_fuzz_fail("%s: cluster index %u", call, c[i].cluster.id.index);
    s->bodies[c[i].cluster.id.index] = c[i].body; // the caller makes its body
  }
  free(c);
  bk_cluster_id* gone = calloc(removed + 1u, sizeof *gone);
  bk_runtime_removed_clusters(rt, gone, removed);
  for (uint32_t i = 0; i < removed; ++i) {
    if (bk_runtime_cluster(rt, gone[i], &(bk_cluster_info){0}))
      bk_fuzz_fail("%s: removed cluster %u is live", call, gone[i].index);
    s->stale[s->stale_count < STALE_IDS ? s->stale_count++ : gone[i].index % STALE_IDS] = gone[i];
  }
  free(gone);
  bk_bond_break* b = calloc(broken + 1u, sizeof *b);
  bk_runtime_broken_bonds(rt, b, broken);
  for (uint32_t i = 0; i < broken; ++i) {
    const tracked* tb = bk_fuzz_find_tracked(s, b[i].breakable);
    if (!tb || b[i].bond >= bk_fuzz_trees[tb->tree].bond_count)
      bk_fuzz_fail("%s: broken bond %u of an unknown breakable", call, b[i].bond);
    if (b[i].cluster.index >= MAX_CLUSTERS) bk_fuzz_fail("%s: cluster index %u", call, b[i].cluster.index);
    // A body the caller lost (a transform not finite) cannot be hit or loaded anywhere.
    const bk_transform* at = &s->bodies[b[i].cluster.index].transform;
    bk_vec3 turn = {at->rotation.x, at->rotation.y, at->rotation.z};
    if (!bk_v3_is_finite(at->position) || !bk_v3_is_finite(turn) || !isfinite(at->rotation.w))
      bk_fuzz_fail("%s: bond %u broke on cluster %u, whose body's transform is not finite", call, b[i].bond,
                   b[i].cluster.index);
    if (bk_runtime_bond_health(rt, b[i].breakable, b[i].bond, NULL) != 0.0)
      bk_fuzz_fail("%s: broken bond %u has hit points", call, b[i].bond);
  }
  free(b);
  s->created = created, s->removed = removed, s->broken = broken;
  if (bk_fuzz_trace)
    fprintf(stderr, "%s: %u created, %u removed, %u bonds broken; %u live\n", call, created, removed, broken,
            s->live_count);
}

// A call that failed, a setter or a query: the results stay those of the last call.
void bk_fuzz_check_results_kept(session* s, const char* call) {
  if (bk_fuzz_trace) fprintf(stderr, "%s\n", call);
  uint32_t created = bk_runtime_created_clusters(s->rt, NULL, 0);
  uint32_t removed = bk_runtime_removed_clusters(s->rt, NULL, 0);
  uint32_t broken = bk_runtime_broken_bonds(s->rt, NULL, 0);
  if (created != s->created || removed != s->removed || broken != s->broken)
    bk_fuzz_fail("%s: results changed (%u/%u/%u created/removed/broken, were %u/%u/%u)", call, created,
                 removed, broken, s->created, s->removed, s->broken);
}
