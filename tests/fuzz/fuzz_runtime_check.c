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
    if (!s->breakables[i].removed && s->breakables[i].id.index == id.index &&
        s->breakables[i].id.generation == id.generation)
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
  uint32_t live_breakables = 0;
  for (uint32_t t = 0; t < s->breakable_count; ++t)
    live_breakables += !s->breakables[t].removed;
  if (st.breakables != live_breakables)
    bk_fuzz_fail("%s: stats count %u breakables, %u are live", call, st.breakables, live_breakables);
  for (uint32_t t = 0; t < s->breakable_count; ++t) {
    const tracked* tb = &s->breakables[t];
    if (tb->removed) {
      if (bk_runtime_breakable_tree(rt, tb->id) || bk_runtime_breakable_user_data(rt, tb->id))
        bk_fuzz_fail("%s: removed breakable %u still answers", call, t);
      continue;
    }
    // Its tree is the one it was made from until a fragment of it was
    // refined, then the runtime's own copy, grown from it.
    const bk_mesh_tree* tree = bk_runtime_breakable_tree(rt, tb->id);
    if (!tree || (!tb->refined && tree != &bk_fuzz_trees[tb->tree]) ||
        (tb->refined &&
         (tree == &bk_fuzz_trees[tb->tree] || tree->leaf_count <= bk_fuzz_trees[tb->tree].leaf_count)))
      bk_fuzz_fail("%s: breakable %u lost its tree", call, t);
    if (tree->leaf_count > MAX_LEAVES)
      bk_fuzz_fail("%s: breakable %u has %u leaves", call, t, tree->leaf_count);
    static uint8_t owners[MAX_LEAVES];
    memset(owners, 0, sizeof owners);
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

// Reads the events after a call: they are those since the last take, the
// call's own at their end.
void bk_fuzz_check_results(session* s, const char* call, uint32_t live_before, uint32_t bonds_before,
                           bool may_break) {
  bk_runtime* rt = s->rt;
  uint32_t created = bk_runtime_created_clusters(rt, NULL, 0);
  uint32_t removed = bk_runtime_removed_clusters(rt, NULL, 0);
  uint32_t broken = bk_runtime_broken_bonds(rt, NULL, 0);
  if (s->live_count + removed != s->live_at_take + created)
    bk_fuzz_fail("%s: %u live clusters at the take, %u now, with %u created and %u removed since", call,
                 s->live_at_take, s->live_count, created, removed);
  if (broken != s->bonds_broken - s->bonds_at_take)
    bk_fuzz_fail("%s: %u bonds broken by the count since the take, %u reported", call,
                 s->bonds_broken - s->bonds_at_take, broken);
  if (broken < s->broken)
    bk_fuzz_fail("%s: broken bonds were taken back (%u, were %u)", call, broken, s->broken);
  uint32_t delta = s->bonds_broken - bonds_before;
  if (delta != broken - s->broken || (!may_break && delta))
    bk_fuzz_fail("%s: %u bonds broken by the count, %u reported", call, delta, broken - s->broken);
  (void)live_before;
  bk_cluster_created* c = calloc(created + 1u, sizeof *c);
  bk_runtime_created_clusters(rt, c, created);
  for (uint32_t i = 0; i < created; ++i) {
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(rt, c[i].cluster.id, &info))
      bk_fuzz_fail("%s: created cluster %u is not live", call, c[i].cluster.id.index);
    if (c[i].cluster.id.index >= MAX_CLUSTERS)
      bk_fuzz_fail("%s: cluster index %u", call, c[i].cluster.id.index);
    if (bk_cluster_equal(s->known[c[i].cluster.id.index], c[i].cluster.id))
      bk_fuzz_fail("%s: cluster %u reported created twice", call, c[i].cluster.id.index);
    if (c[i].cluster.id.index >= bk_runtime_cluster_capacity(rt))
      bk_fuzz_fail("%s: cluster index %u past the capacity %u", call, c[i].cluster.id.index,
                   bk_runtime_cluster_capacity(rt));
  }
  bk_cluster_removed* gone = calloc(removed + 1u, sizeof *gone);
  bk_runtime_removed_clusters(rt, gone, removed);
  for (uint32_t i = 0; i < removed; ++i) {
    if (bk_runtime_cluster(rt, gone[i].cluster, &(bk_cluster_info){0}))
      bk_fuzz_fail("%s: removed cluster %u is live", call, gone[i].cluster.index);
    if (gone[i].cluster.index >= MAX_CLUSTERS ||
        !bk_cluster_equal(s->known[gone[i].cluster.index], gone[i].cluster))
      bk_fuzz_fail("%s: removed cluster %u was never given to the caller", call, gone[i].cluster.index);
  }
  free(gone);
  bk_bond_break* b = calloc(broken + 1u, sizeof *b);
  bk_runtime_broken_bonds(rt, b, broken);
  for (uint32_t i = s->broken; i < broken; ++i) { // this call's
    const tracked* tb = bk_fuzz_find_tracked(s, b[i].breakable);
    const bk_mesh_tree* tree = tb ? bk_runtime_breakable_tree(rt, tb->id) : NULL;
    if (!tb || (tree && b[i].bond >= tree->bond_count))
      bk_fuzz_fail("%s: broken bond %u of an unknown breakable", call, b[i].bond);
    if (b[i].breakable_user_data != &tb->tag)
      bk_fuzz_fail("%s: broken bond %u: not its breakable's user data", call, b[i].bond);
    if (b[i].cluster.index >= MAX_CLUSTERS) bk_fuzz_fail("%s: cluster index %u", call, b[i].cluster.index);
    // A body the caller lost (a transform not finite) cannot be hit or
    // loaded anywhere; one the caller was not given yet is where its
    // created event put it.
    const bk_transform* at = NULL;
    if (bk_cluster_equal(s->known[b[i].cluster.index], b[i].cluster))
      at = &s->bodies[b[i].cluster.index].transform;
    for (uint32_t k = 0; k < created && !at; ++k)
      if (bk_cluster_equal(c[k].cluster.id, b[i].cluster)) at = &c[k].body.transform;
    bk_vec3 turn = at ? (bk_vec3){at->rotation.x, at->rotation.y, at->rotation.z} : bk_v3(0, 0, 0);
    if (at && (!bk_v3_is_finite(at->position) || !bk_v3_is_finite(turn) || !isfinite(at->rotation.w)))
      bk_fuzz_fail("%s: bond %u broke on cluster %u, whose body's transform is not finite", call, b[i].bond,
                   b[i].cluster.index);
    if (bk_runtime_bond_health(rt, b[i].breakable, b[i].bond, NULL) != 0.0)
      bk_fuzz_fail("%s: broken bond %u has hit points", call, b[i].bond);
  }
  free(b);
  free(c);
  s->created = created, s->removed = removed, s->broken = broken;
  if (bk_fuzz_trace)
    fprintf(stderr, "%s: %u created, %u removed, %u bonds broken since the take; %u live\n", call, created,
            removed, broken, s->live_count);
}

// Events into buffers smaller than them: the total comes back, at most
// capacity entries are written, the same as a full read's first ones.
void bk_fuzz_check_short_pulls(session* s, uint32_t capacity) {
  enum { GUARD = 4 };
  bk_cluster_created created[3 + GUARD], created_all[64];
  bk_cluster_removed removed[3 + GUARD], removed_all[64];
  bk_bond_break broken[3 + GUARD];
  memset(created, 0xA5, sizeof created);
  memset(removed, 0xA5, sizeof removed);
  memset(broken, 0xA5, sizeof broken);
  uint8_t canary[sizeof created + sizeof removed + sizeof broken]; // longer than each guard
  memset(canary, 0xA5, sizeof canary);
  if (bk_runtime_created_clusters(s->rt, created, capacity) != s->created ||
      bk_runtime_removed_clusters(s->rt, removed, capacity) != s->removed ||
      bk_runtime_broken_bonds(s->rt, broken, capacity) != s->broken)
    bk_fuzz_fail("a pull into %u entries returned another total", capacity);
  if (memcmp(&created[capacity], canary, sizeof(bk_cluster_created) * GUARD) ||
      memcmp(&removed[capacity], canary, sizeof(bk_cluster_removed) * GUARD) ||
      memcmp(&broken[capacity], canary, sizeof(bk_bond_break) * GUARD))
    bk_fuzz_fail("a pull into %u entries wrote past them", capacity);
  uint32_t n = s->created < 64 ? s->created : 64;
  bk_runtime_created_clusters(s->rt, created_all, n);
  for (uint32_t i = 0; i < capacity && i < n; ++i)
    if (memcmp(&created[i], &created_all[i], sizeof *created))
      bk_fuzz_fail("a short pull gave another created cluster %u", i);
  n = s->removed < 64 ? s->removed : 64;
  bk_runtime_removed_clusters(s->rt, removed_all, n);
  for (uint32_t i = 0; i < capacity && i < n; ++i)
    if (!bk_cluster_equal(removed[i].cluster, removed_all[i].cluster))
      bk_fuzz_fail("a short pull gave another removed cluster %u", i);
  bk_fuzz_check_results_kept(s, "pull");
}

void bk_fuzz_take(session* s) {
  bk_runtime* rt = s->rt;
  uint32_t created = bk_runtime_created_clusters(rt, NULL, 0);
  uint32_t removed = bk_runtime_removed_clusters(rt, NULL, 0);
  bk_cluster_created* c = calloc(created + 1u, sizeof *c);
  bk_runtime_created_clusters(rt, c, created);
  bk_cluster_removed* gone = calloc(removed + 1u, sizeof *gone);
  bk_runtime_removed_clusters(rt, gone, removed);
  // What each new cluster must carry, from the caller's side before the
  // take changes it: its parent's user data, or its breakable's.
  void** expected = calloc(created + 1u, sizeof *expected);
  for (uint32_t i = 0; i < created; ++i) {
    const tracked* tb = bk_fuzz_find_tracked(s, c[i].cluster.breakable);
    if (!tb || c[i].cluster.breakable_user_data != &tb->tag)
      bk_fuzz_fail("take: created cluster %u: not its breakable's user data", c[i].cluster.id.index);
    bk_cluster_id parent = c[i].parent;
    if (bk_cluster_is_null(parent)) {
      expected[i] = (void*)&tb->tag;
    } else {
      if (parent.index >= MAX_CLUSTERS || !bk_cluster_equal(s->known[parent.index], parent))
        bk_fuzz_fail("take: cluster %u's parent %u was never given to the caller", c[i].cluster.id.index,
                     parent.index);
      expected[i] = s->user_data[parent.index];
    }
    if (c[i].cluster.user_data != expected[i])
      bk_fuzz_fail("take: created cluster %u does not carry its parent's user data", c[i].cluster.id.index);
  }
  for (uint32_t i = 0; i < removed; ++i) {
    uint32_t index = gone[i].cluster.index; // known: checked after the call
    if (gone[i].user_data != s->user_data[index])
      bk_fuzz_fail("take: removed cluster %u does not carry its user data", index);
    s->known[index] = (bk_cluster_id){0, 0};
    s->stale[s->stale_count < STALE_IDS ? s->stale_count++ : index % STALE_IDS] = gone[i].cluster;
  }
  for (uint32_t i = 0; i < created; ++i) {
    uint32_t index = c[i].cluster.id.index;
    s->known[index] = c[i].cluster.id;
    s->user_data[index] = c[i].cluster.user_data;
    s->bodies[index] = c[i].body; // the caller makes its body
  }
  free(expected);
  free(gone);
  free(c);
  bk_runtime_clear_events(rt);
  if (bk_runtime_created_clusters(rt, NULL, 0) || bk_runtime_removed_clusters(rt, NULL, 0) ||
      bk_runtime_broken_bonds(rt, NULL, 0))
    bk_fuzz_fail("take: events left after the clear");
  // The caller's mirror is the live set.
  uint32_t known = 0;
  for (uint32_t i = 0; i < MAX_CLUSTERS; ++i)
    known += !bk_cluster_is_null(s->known[i]);
  if (known != s->live_count)
    bk_fuzz_fail("take: the caller knows %u clusters, %u are live", known, s->live_count);
  for (uint32_t i = 0; i < s->live_count; ++i)
    if (!bk_cluster_equal(s->known[s->live[i].index], s->live[i]))
      bk_fuzz_fail("take: live cluster %u unknown to the caller", s->live[i].index);
  s->created = s->removed = s->broken = 0;
  s->live_at_take = s->live_count;
  s->bonds_at_take = s->bonds_broken;
  if (bk_fuzz_trace)
    fprintf(stderr, "take: %u created, %u removed; %u live\n", created, removed, s->live_count);
}

// A call that failed, a setter or a query: the events are unchanged.
void bk_fuzz_check_results_kept(session* s, const char* call) {
  if (bk_fuzz_trace) fprintf(stderr, "%s\n", call);
  uint32_t created = bk_runtime_created_clusters(s->rt, NULL, 0);
  uint32_t removed = bk_runtime_removed_clusters(s->rt, NULL, 0);
  uint32_t broken = bk_runtime_broken_bonds(s->rt, NULL, 0);
  if (created != s->created || removed != s->removed || broken != s->broken)
    bk_fuzz_fail("%s: results changed (%u/%u/%u created/removed/broken, were %u/%u/%u)", call, created,
                 removed, broken, s->created, s->removed, s->broken);
}
