// Breaking many walls in one step: the world's split budget
// (bk_world_def.runtime.max_new_clusters_per_split) spreads the new bodies over steps.
// No step makes more than it; every fragment gets its body in the end (the
// same clusters as with no budget to speak of); a cluster waiting for its
// turn keeps its old body; the same run gives the same state; and the budget
// changes how the work is spread, not what it comes to.
#include <stdlib.h>
#include <string.h>

#include "ensure.h"
#include <breakables/bullet.h>

enum { WALLS = 8, PIECES = 48, STEPS = 40 };

static bk_mesh_tree make_tree(void) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_WALL, &mesh);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = PIECES;
  desc.seed = 5;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &desc, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

// What one run did and where it ended.
typedef struct spread_run {
  uint32_t most_made;    // most bodies made in one step
  uint32_t steps_waited; // steps with splits still waiting after them
  uint32_t clusters;     // at the end
  uint32_t leaves;       // over all clusters at the end
  uint32_t bonds_broken;
  bk_transform* transforms; // every body's, in view order, at the end
  uint32_t body_count;
} spread_run;

static bool has_cluster(const bk_cluster_id* ids, uint32_t count, bk_cluster_id id) {
  for (uint32_t i = 0; i < count; ++i)
    if (ids[i].index == id.index && ids[i].generation == id.generation) return true;
  return false;
}

static void ensure_connected_clusters(const bk_world* world, bk_breakable_id id, const bk_mesh_tree* tree);

// Walls side by side on the ground, not anchored, all shattered in one step.
static spread_run run(const bk_mesh_tree* tree, uint32_t budget) {
  bk_world_def wd = bk_default_world_def();
  wd.runtime.max_new_clusters_per_split = budget;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world != NULL, "%s", err.message);
  for (uint32_t i = 0; i < WALLS; ++i) {
    bk_world_breakable_def desc = bk_default_world_breakable_def();
    desc.breakable.tree = tree;
    desc.breakable.transform.position = bk_v3(3.0 * i, 0.0, 0.0);
    ENSURE_MSG(bk_world_add_breakable(world, &desc, &err).generation != 0, "%s", err.message);
  }
  for (uint32_t i = 0; i < WALLS; ++i)
    bk_world_impact(world, bk_v3(3.0 * i, 1.0, 0.5), 1e12); // every bond of every wall
  spread_run out = {0};
  bk_cluster_id* before = malloc(sizeof(bk_cluster_id) * WALLS * PIECES);
  uint32_t before_count = 0;
  for (uint32_t step = 0; step < STEPS; ++step) {
    before_count = 0;
    for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
      bk_body_view view = {0};
      ENSURE(bk_world_body_view(world, i, &view));
      before[before_count++] = view.cluster;
    }
    bk_world_step(world);
    uint32_t made = 0, waiting_leaves = 0;
    for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
      bk_body_view view = {0};
      ENSURE(bk_world_body_view(world, i, &view));
      // A body is the cluster's: made this step or kept from before.
      ENSURE(bk_physics_body_valid(bk_world_physics(world), view.body));
      made += !has_cluster(before, before_count, view.cluster);
      waiting_leaves += view.leaf_count > 1 ? view.leaf_count : 0;
    }
    bk_world_stats s = bk_world_get_stats(world);
    out.most_made = made > out.most_made ? made : out.most_made;
    out.steps_waited += s.pending_splits > 0;
    // Waiting fragments are in a body that still holds them (no fragment lost).
    ENSURE(s.pending_splits == 0 || waiting_leaves > 0);
  }
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE_MSG(s.pending_splits == 0, "%u splits still waiting after %d steps", s.pending_splits, STEPS);
  // What waited was split from the components found when it first split
  // (kept, not searched again): each cluster is still one connected piece.
  for (uint32_t i = 0; i < WALLS; ++i)
    ensure_connected_clusters(world, bk_world_breakable_at(world, i), tree);
  out.clusters = bk_world_body_count(world);
  out.bonds_broken = s.bonds_broken;
  out.body_count = out.clusters;
  out.transforms = malloc(sizeof(bk_transform) * (out.body_count ? out.body_count : 1u));
  for (uint32_t i = 0; i < out.body_count; ++i) {
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, i, &view));
    out.leaves += view.leaf_count;
    out.transforms[i] = bk_physics_body_transform(bk_world_physics(world), view.body);
  }
  free(before);
  bk_world_destroy(world);
  return out;
}

// What a volley did: per step, the walls whose bonds broke.
typedef struct volley_run {
  uint32_t most_walls;      // most walls broken into in one step
  uint32_t first_walls;     // walls broken into in the step of the hit
  uint32_t steps_waited;    // steps with hits still waiting after them
  uint32_t walls_broken;    // walls with a broken bond at the end
  bool split_while_waiting; // a step applied hits, left some waiting, and split
  uint32_t bonds_broken, bodies;
  bk_transform* transforms; // every body's, in view order, at the end
} volley_run;

// Every cluster is one connected piece: an intact bond joins two fragments
// of one cluster, and the intact bonds inside a cluster reach all of it.
static void ensure_connected_clusters(const bk_world* world, bk_breakable_id id, const bk_mesh_tree* tree) {
  const bk_runtime* rt = bk_world_runtime(world);
  uint32_t* parent = malloc(sizeof(uint32_t) * tree->leaf_count); // union-find over intact bonds
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    parent[l] = l;
  for (uint32_t k = 0; k < tree->bond_count; ++k) {
    const bk_bond* bond = &tree->bonds[k];
    if (bk_world_bond_health(world, id, k, NULL) <= 0.0) continue;
    bk_cluster_id a = bk_runtime_leaf_cluster(rt, id, bond->leaf_a),
                  b = bk_runtime_leaf_cluster(rt, id, bond->leaf_b);
    ENSURE_MSG(a.index == b.index && a.generation == b.generation, "intact bond %u joins two clusters", k);
    uint32_t x = bond->leaf_a, y = bond->leaf_b;
    while (parent[x] != x)
      x = parent[x];
    while (parent[y] != y)
      y = parent[y];
    parent[x] = y;
  }
  // Fragments of one cluster share one root.
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_cluster_id c = bk_runtime_leaf_cluster(rt, id, l);
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(rt, c, &info)) continue;
    uint32_t x = l, y = info.leaves[0];
    while (parent[x] != x)
      x = parent[x];
    while (parent[y] != y)
      y = parent[y];
    ENSURE_MSG(x == y, "fragment %u is not connected to the rest of its cluster", l);
  }
  free(parent);
}

// Anchored walls in a row, each shot by a heavy ball that reaches it in the
// same step as the others.
static volley_run volley(const bk_mesh_tree* tree, uint32_t hit_budget) {
  bk_world_def wd = bk_default_world_def();
  wd.max_hit_fragments_per_step = hit_budget;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world != NULL, "%s", err.message);
  ENSURE(bk_world_max_hit_fragments_per_step(world) == hit_budget);
  bk_breakable_id ids[WALLS];
  for (uint32_t i = 0; i < WALLS; ++i) {
    bk_world_breakable_def desc = bk_default_world_breakable_def();
    desc.breakable.tree = tree;
    desc.breakable.anchored = true;
    desc.breakable.transform.position = bk_v3(3.0 * i, 0.0, 0.0);
    ids[i] = bk_world_add_breakable(world, &desc, &err);
    ENSURE_MSG(ids[i].generation != 0, "%s", err.message);
  }
  for (uint32_t i = 0; i < WALLS; ++i) {
    bk_projectile_def shot = bk_default_projectile_def();
    shot.position = bk_v3(3.0 * i, 0.6, 1.0);
    shot.velocity = bk_v3(0.0, 0.0, -60.0);
    shot.mass = 40.0;
    shot.radius = 0.15;
    ENSURE_MSG(!bk_body_is_null(bk_world_fire(world, &shot, &err)), "%s", err.message);
  }
  volley_run out = {0};
  bool broken[WALLS] = {false};
  bk_break_event events[4096];
  for (uint32_t step = 0; step < STEPS; ++step) {
    uint32_t bodies_before = bk_world_body_count(world);
    bk_world_step(world);
    uint32_t n = bk_world_break_events(world, events, 4096);
    ENSURE(n <= 4096);
    bool walls[WALLS] = {false};
    uint32_t count = 0;
    for (uint32_t e = 0; e < n; ++e)
      for (uint32_t i = 0; i < WALLS; ++i)
        if (events[e].breakable.index == ids[i].index && !walls[i]) walls[i] = broken[i] = true, count++;
    if (count && !out.first_walls) out.first_walls = count;
    out.most_walls = count > out.most_walls ? count : out.most_walls;
    bk_world_stats s = bk_world_get_stats(world);
    out.steps_waited += s.pending_hits > 0;
    // A step that applies hits and leaves some waiting splits nothing: the
    // bodies stay as they were (damage and new bodies never add up).
    if (count && s.pending_hits > 0 && bk_world_body_count(world) != bodies_before)
      out.split_while_waiting = true;
  }
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE_MSG(s.pending_hits == 0 && s.pending_splits == 0, "%u hits, %u splits still waiting after %d steps",
             s.pending_hits, s.pending_splits, STEPS);
  for (uint32_t i = 0; i < WALLS; ++i) {
    out.walls_broken += broken[i];
    ensure_connected_clusters(world, ids[i], tree);
  }
  out.bonds_broken = s.bonds_broken;
  out.bodies = bk_world_body_count(world);
  out.transforms = malloc(sizeof(bk_transform) * (out.bodies ? out.bodies : 1u));
  for (uint32_t i = 0; i < out.bodies; ++i) {
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, i, &view));
    out.transforms[i] = bk_physics_body_transform(bk_world_physics(world), view.body);
  }
  bk_world_destroy(world);
  return out;
}

static bool same_state(const volley_run* a, const volley_run* b) {
  return a->bodies == b->bodies && a->bonds_broken == b->bonds_broken &&
         memcmp(a->transforms, b->transforms, sizeof(bk_transform) * a->bodies) == 0;
}

// The hit budget: walls shot in one step are damaged one a step (each hit
// sweeps a whole wall), every one in the end; no step both applies hits
// and splits while hits wait; the same run gives the same state; and a
// budget no step reaches changes nothing against no budget at all.
static void test_hit_budget(const bk_mesh_tree* tree) {
  volley_run unlimited = volley(tree, 0);
  ENSURE_MSG(unlimited.first_walls == WALLS && unlimited.steps_waited == 0, "%u walls hit at once, %u waited",
             unlimited.first_walls, unlimited.steps_waited);
  volley_run roomy = volley(tree, 1u << 30);
  ENSURE(same_state(&roomy, &unlimited));
  volley_run spread = volley(tree, tree->leaf_count); // one wall's hit a step
  ENSURE_MSG(spread.most_walls == 1, "a step broke into %u walls", spread.most_walls);
  ENSURE_MSG(spread.walls_broken == WALLS, "%u of %d walls broken", spread.walls_broken, WALLS);
  ENSURE_MSG(spread.steps_waited >= WALLS - 1, "%u steps waited", spread.steps_waited);
  ENSURE(!spread.split_while_waiting);
  ENSURE(!same_state(&spread, &unlimited));
  volley_run again = volley(tree, tree->leaf_count);
  ENSURE(same_state(&again, &spread));
  free(unlimited.transforms);
  free(roomy.transforms);
  free(spread.transforms);
  free(again.transforms);
}

int main(void) {
  bk_mesh_tree tree = make_tree();
  const uint32_t fragments = WALLS * tree.leaf_count;
  // A budget no hit reaches: everything splits in the step of the hit.
  spread_run all = run(&tree, 1u << 20);
  ENSURE_MSG(all.clusters == fragments && all.leaves == fragments, "%u clusters, %u leaves of %u",
             all.clusters, all.leaves, fragments);
  ENSURE_MSG(all.steps_waited == 0 && all.most_made == fragments, "%u waited, %u made at most",
             all.steps_waited, all.most_made);

  // A small budget: no step makes more bodies than it, the rest wait their
  // turn, and in the end every fragment has its body, as without the budget.
  const uint32_t budget = 16;
  spread_run spread = run(&tree, budget);
  ENSURE_MSG(spread.most_made <= budget, "a step made %u bodies, over the budget of %u", spread.most_made,
             budget);
  ENSURE_MSG(spread.steps_waited >= fragments / budget - 1, "only %u steps waited for %u fragments",
             spread.steps_waited, fragments);
  ENSURE_MSG(spread.clusters == all.clusters && spread.leaves == fragments, "%u clusters, %u leaves",
             spread.clusters, spread.leaves);
  ENSURE(spread.bonds_broken == all.bonds_broken);

  // The same run twice: the same state, bit for bit.
  spread_run again = run(&tree, budget);
  ENSURE(again.body_count == spread.body_count && again.most_made == spread.most_made &&
         again.steps_waited == spread.steps_waited);
  ENSURE(memcmp(again.transforms, spread.transforms, sizeof(bk_transform) * spread.body_count) == 0);

  test_hit_budget(&tree);

  free(all.transforms);
  free(spread.transforms);
  free(again.transforms);
  bk_mesh_tree_free(&tree);
  return 0;
}
