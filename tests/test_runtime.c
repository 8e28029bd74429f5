// The runtime without a physics engine: the caller's bodies are an array of
// states indexed by cluster; results pulled after each call must partition
// the fragments, conserve mass, carry the parent's motion (v + w x r), obey
// the split budget and the contact thresholds, follow live parameters, and be
// the same for the same calls.
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "ensure.h"
#include "shape_tree.h"

typedef struct bodies {
  bk_body_state state[4096];
} bodies;

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  return ((bodies*)context)->state[cluster.index];
}

static bk_runtime* make_runtime(bodies* b, uint32_t budget) {
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = b;
  def.max_new_clusters_per_split = budget;
  bk_error err = {0};
  bk_runtime* rt = bk_runtime_create(&def, &err);
  ENSURE_MSG(rt, "%s", err.message);
  return rt;
}

// The caller's side: every created cluster gets a body in the state the
// runtime gives it, and the events are cleared (taken).
static uint32_t take_created(bk_runtime* rt, bodies* b, bk_cluster_created* out, uint32_t capacity) {
  uint32_t n = bk_runtime_created_clusters(rt, out, capacity);
  ENSURE(n <= capacity);
  for (uint32_t i = 0; i < n; ++i)
    b->state[out[i].cluster.id.index] = out[i].body;
  bk_runtime_clear_events(rt);
  return n;
}

static int compare_u32(const void* a, const void* b) {
  uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
  return x < y ? -1 : x > y;
}

static void test_validation(void) {
  bk_error err = {0};
  bk_runtime_def def = bk_default_runtime_def();
  ENSURE(bk_runtime_create(&def, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "body_state"), "%s", err.message);
  bodies* b = calloc(1, sizeof *b);
  def.body_state = body_state;
  def.max_new_clusters_per_split = 1;
  ENSURE(bk_runtime_create(&def, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "max_new_clusters_per_split"), "%s", err.message);
  def = bk_default_runtime_def();
  def.body_state = body_state;
  def.damage_min_distance = 0.0;
  ENSURE(bk_runtime_create(&def, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "damage_min_distance"), "%s", err.message);

  bk_runtime* rt = make_runtime(b, 48);
  bk_breakable_def bd = bk_default_breakable_def();
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)));
  ENSURE_MSG(strstr(err.message, "tree"), "%s", err.message);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 8, 1);
  bd.tree = &tree;
  bd.material.density = 0.0;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)));
  ENSURE_MSG(strstr(err.message, "material.density"), "%s", err.message);
  bd.material.density = 1000.0;
  bd.material.restitution = 1.5;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)));
  ENSURE_MSG(strstr(err.message, "material.restitution"), "%s", err.message);
  ENSURE(bk_runtime_get_stats(rt).breakables == 0); // nothing half-made
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// A breakable starts as one cluster: the root alone, the whole mass, its
// body placed at transform x principal frame, at rest.
static void test_first_cluster(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 48);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 32, 2);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bd.material.density = 1000.0;
  bd.transform.position = bk_v3(1, 2, 3);
  bk_error err = {0};
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, &err);
  ENSURE_MSG(!bk_breakable_is_null(id), "%s", err.message);
  bk_cluster_created created[4];
  ENSURE(take_created(rt, b, created, 4) == 1);
  const bk_cluster_info* c = &created[0].cluster;
  ENSURE(bk_cluster_is_null(created[0].parent));
  ENSURE(c->leaf_count == 32 && c->node_count == 1 && c->nodes[0] == 0);
  ENSURE_REL(c->mass, 1000.0, 1e-12); // unit cube
  ENSURE_REL(c->inertia.x, 1000.0 / 6.0, 1e-9);
  ENSURE_SMALL(bk_v3_length(bk_v3_sub(created[0].body.transform.position, bk_v3(1, 2, 3))), 0.0, 1e-12);
  ENSURE(bk_v3_length(created[0].body.linear_velocity) == 0.0);
  ENSURE(bk_runtime_removed_clusters(rt, NULL, 0) == 0);
  ENSURE(bk_cluster_equal(bk_runtime_leaf_cluster(rt, id, 31), c->id));
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// A blast splits the cluster: the parts partition the fragments, their
// masses add up, each node set is minimal, and each part moves as the
// parent's rigid velocity field at its own centre of mass.
static void test_split_results(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 48);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 64, 3);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, NULL);
  bk_cluster_created created[128];
  take_created(rt, b, created, 128);
  bk_cluster_id parent = created[0].cluster.id;
  double mass = created[0].cluster.mass;
  // The caller's body moves and spins.
  bk_body_state* s = &b->state[parent.index];
  s->linear_velocity = bk_v3(1, 0, 0);
  s->angular_velocity = bk_v3(0, 2, 0);
  bk_runtime_damage_at(rt, bk_v3(0.5, 0.5, 0.5), 5e4);
  uint32_t broken = bk_runtime_broken_bonds(rt, NULL, 0);
  ENSURE(broken > 0);
  bk_bond_break first = {0};
  bk_runtime_broken_bonds(rt, &first, 1);
  ENSURE(bk_cluster_equal(first.cluster, parent));
  // A broken bond's velocity is the body's at that point.
  bk_vec3 r = bk_v3_sub(first.position, s->transform.position);
  bk_vec3 expected = bk_v3_add(s->linear_velocity, bk_v3_cross(s->angular_velocity, r));
  ENSURE_SMALL(bk_v3_length(bk_v3_sub(first.velocity, expected)), 0.0, 1e-12);
  ENSURE(bk_runtime_get_stats(rt).bonds_broken == broken);
  bk_body_state parent_state = *s;

  uint32_t made = bk_runtime_split(rt);
  ENSURE(made >= 2);
  bk_cluster_removed removed[4];
  ENSURE(bk_runtime_removed_clusters(rt, removed, 4) == 1 && bk_cluster_equal(removed[0].cluster, parent));
  ENSURE(take_created(rt, b, created, 128) == made);
  uint32_t* seen = calloc(tree.leaf_count, sizeof(uint32_t));
  double total = 0.0;
  for (uint32_t i = 0; i < made; ++i) {
    const bk_cluster_info* c = &created[i].cluster;
    ENSURE(bk_cluster_equal(created[i].parent, parent));
    for (uint32_t k = 0; k < c->leaf_count; ++k)
      seen[c->leaves[k]]++;
    uint32_t nodes[128];
    ENSURE(bk_minimal_nodes(&tree, c->leaves, c->leaf_count, nodes) == c->node_count);
    ENSURE(memcmp(nodes, c->nodes, sizeof(uint32_t) * c->node_count) == 0);
    total += c->mass;
    bk_vec3 rr = bk_v3_sub(created[i].body.transform.position, parent_state.transform.position);
    bk_vec3 v = bk_v3_add(parent_state.linear_velocity, bk_v3_cross(parent_state.angular_velocity, rr));
    ENSURE_SMALL(bk_v3_length(bk_v3_sub(created[i].body.linear_velocity, v)), 0.0, 1e-12);
    ENSURE(created[i].body.angular_velocity.y == 2.0);
  }
  for (uint32_t l = 0; l < tree.leaf_count; ++l)
    ENSURE_MSG(seen[l] == 1, "leaf %u is in %u clusters", l, seen[l]);
  ENSURE_REL(total, mass, 1e-12);
  ENSURE(bk_runtime_cluster(rt, parent, &(bk_cluster_info){0}) == false); // stale now
  free(seen);
  (void)id;
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// Thresholds: a soft or slow contact does nothing, a stale cluster is
// skipped, a hard fast one breaks bonds.
static void test_contact_thresholds(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 48);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 32, 4);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_runtime_add_breakable(rt, &bd, NULL);
  bk_cluster_created created[64];
  take_created(rt, b, created, 64);
  bk_cluster_id c = created[0].cluster.id;
  bk_damage_contact soft = {c, bk_v3(0.5, 0, 0), 0.4, 10.0}, slow = {c, bk_v3(0.5, 0, 0), 1e5, 0.5},
                    stale = {{c.index, c.generation + 1}, bk_v3(0.5, 0, 0), 1e5, 10.0};
  bk_damage_contact three[3] = {soft, slow, stale};
  bk_runtime_apply_contacts(rt, three, 3);
  ENSURE(bk_runtime_broken_bonds(rt, NULL, 0) == 0);
  bk_damage_contact hard = {c, bk_v3(0.5, 0, 0), 1e5, 10.0};
  bk_runtime_apply_contacts(rt, &hard, 1);
  ENSURE(bk_runtime_broken_bonds(rt, NULL, 0) > 0);
  ENSURE(bk_runtime_get_stats(rt).pending_splits == 1);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// One call creates at most the budget; the rest waits, in order.
static void test_budget(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 4);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 64, 5);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_runtime_add_breakable(rt, &bd, NULL);
  bk_cluster_created created[128];
  take_created(rt, b, created, 128);
  bk_runtime_damage_at(rt, bk_v3(0, 0, 0), 1e9); // every bond
  uint32_t calls = 0, clusters = 0;
  for (; calls < 100 && bk_runtime_get_stats(rt).clusters < 64; ++calls) {
    uint32_t made = bk_runtime_split(rt);
    ENSURE(made <= 4);
    take_created(rt, b, created, 128);
    // What did not fit stays together, in the first part, and says so.
    bk_cluster_info now = {0};
    ENSURE(bk_runtime_cluster(rt, created[0].cluster.id, &now));
    ENSURE(created[0].cluster.split_pending == now.split_pending);
    if (calls == 0) ENSURE(created[0].cluster.split_pending && created[0].cluster.leaf_count > 1);
    clusters = bk_runtime_get_stats(rt).clusters;
  }
  ENSURE(clusters == 64 && calls >= 64 / 3);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

static uint32_t find_root(uint32_t* parent, uint32_t x) {
  while (parent[x] != x)
    x = parent[x] = parent[parent[x]];
  return x;
}

// A cluster left waiting by the budget keeps the components its split found;
// a hit on it meanwhile breaks more bonds, and what it splits into then
// follows them: in the end the clusters are exactly the pieces the intact
// bonds hold together.
static void test_budget_then_hit(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 4);
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 96, 3);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, NULL);
  bk_cluster_created created[128];
  take_created(rt, b, created, 128);
  bk_aabb box = tree.nodes[0].bounds;
  bk_runtime_damage_at(rt, box.min, 2e3); // a corner shatters
  take_created(rt, b, created, 128);
  bk_runtime_split(rt);
  take_created(rt, b, created, 128);
  ENSURE(bk_runtime_get_stats(rt).pending_splits > 0); // the rest waits, as one cluster
  bk_runtime_damage_at(rt, box.max, 2e3);              // the opposite corner shatters meanwhile
  for (uint32_t calls = 0; calls < 200 && bk_runtime_get_stats(rt).pending_splits > 0; ++calls) {
    bk_runtime_split(rt);
    take_created(rt, b, created, 128);
  }
  ENSURE(bk_runtime_get_stats(rt).pending_splits == 0);
  uint32_t* parent = malloc(sizeof(uint32_t) * tree.leaf_count);
  for (uint32_t l = 0; l < tree.leaf_count; ++l)
    parent[l] = l;
  for (uint32_t k = 0; k < tree.bond_count; ++k)
    if (bk_runtime_bond_health(rt, id, k, NULL) > 0.0)
      parent[find_root(parent, tree.bonds[k].leaf_a)] = find_root(parent, tree.bonds[k].leaf_b);
  uint32_t pieces = 0;
  for (uint32_t l = 0; l < tree.leaf_count; ++l) {
    pieces += find_root(parent, l) == l;
    bk_cluster_info info = {0};
    ENSURE(bk_runtime_cluster(rt, bk_runtime_leaf_cluster(rt, id, l), &info));
    ENSURE_MSG(find_root(parent, l) == find_root(parent, info.leaves[0]),
               "fragment %u: its cluster is not one piece", l);
  }
  ENSURE_MSG(bk_runtime_get_stats(rt).clusters == pieces, "%u clusters for %u pieces",
             bk_runtime_get_stats(rt).clusters, pieces);
  ENSURE(pieces > 8);
  free(parent);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// Live parameters: frailty, density, bond strength and material are the
// runtime's and read back through getters.
static void test_live_parameters(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 48);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 16, 6);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bd.material.frailty = 0.0; // unbreakable: zero is zero
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, NULL);
  bk_cluster_created created[32];
  take_created(rt, b, created, 32);
  bk_runtime_damage_at(rt, bk_v3(0, 0, 0), 1e12);
  ENSURE(bk_runtime_broken_bonds(rt, NULL, 0) == 0);

  ENSURE(bk_runtime_set_density(rt, id, 500.0) == BK_OK && bk_runtime_density(rt, id) == 500.0);
  bk_cluster_info info = {0};
  ENSURE(bk_runtime_cluster(rt, created[0].cluster.id, &info));
  ENSURE_REL(info.mass, 500.0, 1e-12);
  ENSURE(bk_runtime_set_density(rt, id, -1.0) == BK_ERROR_INVALID_ARGUMENT &&
         bk_runtime_density(rt, id) == 500.0);

  double initial = 0.0, hp = bk_runtime_bond_health(rt, id, 0, &initial);
  ENSURE(hp == initial && hp > 0.0);
  ENSURE(bk_runtime_set_bond_strength(rt, id, 4e5) == BK_OK && bk_runtime_bond_strength(rt, id) == 4e5);
  double initial2 = 0.0;
  ENSURE_REL(bk_runtime_bond_health(rt, id, 0, &initial2), 2.0 * hp, 1e-12);
  ENSURE_REL(initial2, 2.0 * initial, 1e-12);

  const bk_material* glass = bk_material_find("glass");
  ENSURE(bk_runtime_set_material(rt, id, glass) == BK_OK);
  bk_material m = bk_runtime_material(rt, id);
  ENSURE(strcmp(m.name, "glass") == 0 && m.frailty == glass->frailty && m.density == glass->density);
  ENSURE(bk_runtime_frailty(rt, id) == glass->frailty);
  ENSURE(bk_runtime_cluster(rt, created[0].cluster.id, &info));
  ENSURE_REL(info.mass, glass->density, 1e-12);
  ENSURE(bk_runtime_set_frailty(rt, id, 0.5) == BK_OK && bk_runtime_frailty(rt, id) == 0.5);
  // A material read back and written again (its name is the runtime's own).
  m = bk_runtime_material(rt, id);
  m.accumulate = !m.accumulate;
  ENSURE(bk_runtime_set_material(rt, id, &m) == BK_OK);
  ENSURE(strcmp(bk_runtime_material(rt, id).name, "glass") == 0 &&
         bk_runtime_material(rt, id).accumulate == m.accumulate);
  ENSURE(bk_runtime_set_frailty(rt, (bk_breakable_id){0, 0}, 1.0) == BK_ERROR_STALE_ID);
  // Densities and strengths no material has are refused: a denormal density
  // gave every cluster an inertia of 0, a huge strength infinite hit points.
  ENSURE(bk_runtime_set_density(rt, id, 5e-324) == BK_ERROR_INVALID_ARGUMENT &&
         bk_runtime_set_density(rt, id, 1e300) == BK_ERROR_INVALID_ARGUMENT);
  ENSURE(bk_runtime_set_bond_strength(rt, id, 5e-324) == BK_ERROR_INVALID_ARGUMENT &&
         bk_runtime_set_bond_strength(rt, id, 1e300) == BK_ERROR_INVALID_ARGUMENT);
  ENSURE(bk_runtime_set_density(rt, id, BK_MATERIAL_DENSITY_MIN) == BK_OK &&
         bk_runtime_cluster(rt, created[0].cluster.id, &info));
  ENSURE(info.mass > 0.0 && info.inertia.x > 0.0 && info.inertia.y > 0.0 && info.inertia.z > 0.0);
  bk_error err = {0};
  bd.material.density = 1e-300;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)));
  ENSURE_MSG(strstr(err.message, "material.density must be in [1e-06, 1e+09]"), "%s", err.message);
  bd.material = *glass;
  bd.material.bond_strength = 1e300;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)));
  ENSURE_MSG(strstr(err.message, "material.bond_strength"), "%s", err.message);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// Removing a cluster reports it and frees its fragments.
static void test_remove(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 48);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 8, 7);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, NULL);
  bk_cluster_created created[8];
  take_created(rt, b, created, 8);
  bk_cluster_id c = created[0].cluster.id;
  ENSURE(bk_runtime_remove_cluster(rt, c) == BK_OK);
  bk_cluster_removed removed = {0};
  ENSURE(bk_runtime_removed_clusters(rt, &removed, 1) == 1 && bk_cluster_equal(removed.cluster, c));
  ENSURE(bk_cluster_is_null(bk_runtime_leaf_cluster(rt, id, 0)));
  ENSURE(bk_runtime_remove_cluster(rt, c) == BK_ERROR_STALE_ID);
  ENSURE(bk_runtime_get_stats(rt).clusters == 0 && bk_runtime_clusters(rt, NULL, 0) == 0);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// The first stress solve of an anchored object with no loads and no
// supports (NULL arrays of length 0, as most callers pass them): its load
// array is empty, which once offset a null pointer (clang's UBSan reports
// it). The sound tower stands: it is solved, settles, and breaks nothing.
// The other empty inputs (no contacts, pulls into no buffer) write nothing.
static void test_stress_without_loads(void) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 48);
  bk_mesh_tree tree = make_tree(BK_SHAPE_TOWER, 12, 5);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bd.anchored = true;
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, NULL);
  ENSURE(!bk_breakable_is_null(id));
  bk_cluster_created created[2];
  ENSURE(take_created(rt, b, created, 2) == 1 && created[0].cluster.is_static);
  bk_runtime_solve_stress(rt, bk_v3(0, -9.81, 0), NULL, 0, NULL, 0);
  bk_runtime_stats st = bk_runtime_get_stats(rt);
  ENSURE(st.stress_clusters_solved == 1 && st.bonds_broken == 0);
  for (int call = 0; call < 50 && bk_runtime_get_stats(rt).stress_clusters_pending; ++call)
    bk_runtime_solve_stress(rt, bk_v3(0, -9.81, 0), NULL, 0, NULL, 0);
  st = bk_runtime_get_stats(rt);
  ENSURE(st.stress_clusters_pending == 0 && st.bonds_broken == 0 && st.clusters == 1);
  bk_bond_stress stress = {0};
  ENSURE(bk_runtime_bond_stress(rt, id, 0, &stress) && stress.ratio >= 0.0 && stress.ratio < 1.0);
  bk_runtime_apply_contacts(rt, NULL, 3); // no array: nothing to apply
  ENSURE(bk_runtime_broken_bonds(rt, NULL, 4) == 0 && bk_runtime_get_stats(rt).bonds_broken == 0);
  // Pulls into no buffer give the totals and write nothing, whatever the capacity.
  bk_runtime_damage_at(rt, created[0].body.transform.position, 1e9);
  uint32_t broken = bk_runtime_broken_bonds(rt, NULL, 0);
  ENSURE(broken > 0 && bk_runtime_broken_bonds(rt, NULL, 4) == broken);
  uint32_t made = bk_runtime_split(rt);
  ENSURE(made > 1 && bk_runtime_created_clusters(rt, NULL, 4) == made);
  ENSURE(bk_runtime_removed_clusters(rt, NULL, 4) == 1 && bk_runtime_clusters(rt, NULL, 4) == made);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

// Collider nodes: a node whose hull does not fit is replaced by its children.
static void test_collider_nodes(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 16, 8);
  uint8_t* fits = calloc(tree.node_count, 1);
  uint32_t root = 0, out[64];
  uint32_t n = bk_collider_nodes(&tree, &root, 1, fits, out, 64);
  ENSURE(n == 16);
  uint32_t leaves[16];
  for (uint32_t i = 0; i < n; ++i)
    leaves[i] = out[i];
  qsort(leaves, n, sizeof(uint32_t), compare_u32);
  uint32_t sorted_leaf_nodes[16];
  memcpy(sorted_leaf_nodes, tree.leaf_nodes, sizeof sorted_leaf_nodes);
  qsort(sorted_leaf_nodes, 16, sizeof(uint32_t), compare_u32);
  ENSURE(memcmp(leaves, sorted_leaf_nodes, sizeof leaves) == 0);
  fits[0] = 1;
  ENSURE(bk_collider_nodes(&tree, &root, 1, fits, out, 64) == 1 && out[0] == 0);
  fits[0] = 0;
  ENSURE(bk_collider_nodes(&tree, &root, 1, fits, out, 3) == 16); // count past capacity
  free(fits);
  bk_mesh_tree_free(&tree);
}

// The same calls give the same results, bit for bit.
static void run_script(bk_cluster_created* out, uint32_t* count, uint32_t capacity) {
  bodies* b = calloc(1, sizeof *b);
  bk_runtime* rt = make_runtime(b, 8);
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 64, 9);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bd.anchored = true;
  bk_runtime_add_breakable(rt, &bd, NULL);
  bk_cluster_created scratch[128];
  take_created(rt, b, scratch, 128);
  *count = 0;
  for (int hit = 0; hit < 4; ++hit) {
    bk_runtime_damage_at(rt, bk_v3(-0.5 + 0.3 * hit, 0.3 + 0.2 * hit, 0.0), 2e3);
    for (int i = 0; i < 3; ++i) {
      bk_runtime_split(rt);
      uint32_t n = take_created(rt, b, scratch, 128);
      for (uint32_t k = 0; k < n && *count < capacity; ++k) {
        memcpy(&out[*count], &scratch[k], sizeof scratch[k]); // bytes, padding included
        out[*count].cluster.leaves = NULL;                    // pointers differ between runs
        out[*count].cluster.nodes = NULL;
        (*count)++;
      }
    }
  }
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
  free(b);
}

static void test_determinism(void) {
  static bk_cluster_created a[512], b[512];
  memset(a, 0, sizeof a);
  memset(b, 0, sizeof b);
  uint32_t na = 0, nb = 0;
  run_script(a, &na, 512);
  run_script(b, &nb, 512);
  ENSURE(na > 4 && na == nb);
  ENSURE(memcmp(a, b, sizeof(bk_cluster_created) * na) == 0);
}

int main(void) {
  RUN(test_validation);
  RUN(test_first_cluster);
  RUN(test_split_results);
  RUN(test_contact_thresholds);
  RUN(test_budget);
  RUN(test_budget_then_hit);
  RUN(test_live_parameters);
  RUN(test_remove);
  RUN(test_stress_without_loads);
  RUN(test_collider_nodes);
  RUN(test_determinism);
  return 0;
}
