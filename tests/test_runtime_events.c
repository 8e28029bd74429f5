// The embedder's side of the runtime: events accumulate until cleared (none
// lost between pulls), a cluster created and removed meanwhile is in neither
// list and never asked about, user data rides on breakables, clusters and
// events, the cluster index bound, removing a whole breakable, "up" taken
// from gravity, and the codes errors carry.
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "ensure.h"
#include "shape_tree.h"

enum { MAX_BODIES = 4096 };

// The caller's physics: a body per cluster it was given (known), in the
// state the created event gave it. The runtime must never ask about another.
typedef struct caller {
  bk_body_state state[MAX_BODIES];
  bk_cluster_id known[MAX_BODIES];
  uint32_t asked_unknown;
} caller;

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  caller* c = context;
  if (cluster.index >= MAX_BODIES || !bk_cluster_equal(c->known[cluster.index], cluster)) {
    c->asked_unknown++;
    return (bk_body_state){.transform = {{NAN, NAN, NAN}, {0, 0, 0, 1}}};
  }
  return c->state[cluster.index];
}

static bk_runtime* make_runtime(caller* c, uint32_t budget, bk_vec3 gravity) {
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = c;
  def.max_new_clusters_per_split = budget;
  def.gravity = gravity;
  bk_error err = {0};
  bk_runtime* rt = bk_runtime_create(&def, &err);
  ENSURE_MSG(rt, "%s", err.message);
  return rt;
}

// What one take gave: the three lists, copied.
typedef struct taken {
  bk_cluster_created created[512];
  bk_cluster_removed removed[512];
  bk_bond_break broken[4096];
  uint32_t created_count, removed_count, broken_count;
} taken;

// Takes the events: bodies made for created clusters, dropped for removed
// ones, then cleared. Checks they fit and that the mirror matches the runtime.
static void take(bk_runtime* rt, caller* c, taken* t) {
  t->created_count = bk_runtime_created_clusters(rt, t->created, 512);
  t->removed_count = bk_runtime_removed_clusters(rt, t->removed, 512);
  t->broken_count = bk_runtime_broken_bonds(rt, t->broken, 4096);
  ENSURE(t->created_count <= 512 && t->removed_count <= 512 && t->broken_count <= 4096);
  for (uint32_t i = 0; i < t->removed_count; ++i) {
    bk_cluster_id id = t->removed[i].cluster;
    ENSURE_MSG(bk_cluster_equal(c->known[id.index], id), "removed cluster %u was never given", id.index);
    c->known[id.index] = (bk_cluster_id){0, 0};
  }
  for (uint32_t i = 0; i < t->created_count; ++i) {
    bk_cluster_id id = t->created[i].cluster.id;
    ENSURE(id.index < MAX_BODIES && bk_runtime_cluster(rt, id, &(bk_cluster_info){0}));
    ENSURE_MSG(bk_cluster_is_null(c->known[id.index]), "slot %u given twice", id.index);
    c->known[id.index] = id;
    c->state[id.index] = t->created[i].body;
  }
  bk_runtime_clear_events(rt);
  ENSURE(bk_runtime_created_clusters(rt, NULL, 0) == 0 && bk_runtime_removed_clusters(rt, NULL, 0) == 0 &&
         bk_runtime_broken_bonds(rt, NULL, 0) == 0);
  // The caller's mirror is the runtime's live set.
  bk_cluster_id live[MAX_BODIES];
  uint32_t n = bk_runtime_clusters(rt, live, MAX_BODIES), known = 0;
  for (uint32_t i = 0; i < MAX_BODIES; ++i)
    known += !bk_cluster_is_null(c->known[i]);
  ENSURE_MSG(n == known, "%u live clusters, the caller knows %u", n, known);
  for (uint32_t i = 0; i < n; ++i)
    ENSURE(bk_cluster_equal(c->known[live[i].index], live[i]));
}

static int compare_break(const bk_bond_break* a, const bk_bond_break* b) {
  return a->bond != b->bond ? 1 : memcmp(&a->position, &b->position, sizeof a->position);
}

// Two hits and a split pulled once give the bonds both hits broke, in order,
// as pulling after each call does; the clusters are those of the end.
static void test_events_accumulate(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 64, 3);
  bk_aabb box = tree.nodes[0].bounds;
  static caller each_caller, once_caller;
  static taken each_taken, once_taken;
  memset(&each_caller, 0, sizeof each_caller);
  memset(&once_caller, 0, sizeof once_caller);
  bk_runtime* each = make_runtime(&each_caller, 48, bk_v3(0, -9.81, 0));
  bk_runtime* once = make_runtime(&once_caller, 48, bk_v3(0, -9.81, 0));
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_runtime_add_breakable(each, &bd, NULL);
  bk_runtime_add_breakable(once, &bd, NULL);
  take(each, &each_caller, &each_taken);
  take(once, &once_caller, &once_taken);

  bk_bond_break each_breaks[4096];
  uint32_t each_count = 0;
  bk_runtime_damage_at(each, box.min, 2e3);
  take(each, &each_caller, &each_taken);
  memcpy(each_breaks, each_taken.broken, sizeof(bk_bond_break) * each_taken.broken_count);
  each_count = each_taken.broken_count;
  bk_runtime_damage_at(each, box.max, 2e3);
  take(each, &each_caller, &each_taken);
  memcpy(each_breaks + each_count, each_taken.broken, sizeof(bk_bond_break) * each_taken.broken_count);
  each_count += each_taken.broken_count;
  ENSURE(each_taken.broken_count > 0 && each_count > each_taken.broken_count); // both hits broke bonds
  uint32_t made = bk_runtime_split(each);
  take(each, &each_caller, &each_taken);
  ENSURE(made > 1 && each_taken.created_count == made && each_taken.removed_count == 1);

  bk_runtime_damage_at(once, box.min, 2e3);
  bk_runtime_damage_at(once, box.max, 2e3);
  ENSURE(bk_runtime_split(once) == made);
  // Reading takes nothing away: twice the same.
  ENSURE(bk_runtime_broken_bonds(once, NULL, 0) == each_count);
  take(once, &once_caller, &once_taken);
  ENSURE(once_taken.broken_count == each_count);
  ENSURE(bk_runtime_get_stats(once).bonds_broken == each_count);
  for (uint32_t i = 0; i < each_count; ++i)
    ENSURE_MSG(compare_break(&once_taken.broken[i], &each_breaks[i]) == 0, "break %u differs", i);
  ENSURE(once_taken.created_count == made && once_taken.removed_count == 1);
  for (uint32_t i = 0; i < made; ++i)
    ENSURE(bk_cluster_equal(once_taken.created[i].cluster.id, each_taken.created[i].cluster.id) &&
           once_taken.created[i].cluster.leaf_count == each_taken.created[i].cluster.leaf_count);
  ENSURE(each_caller.asked_unknown == 0 && once_caller.asked_unknown == 0);
  bk_runtime_destroy(each);
  bk_runtime_destroy(once);
  bk_mesh_tree_free(&tree);
}

// A split budget of 2 over a shattered cube, split again and again before
// one take: the remainders created and split meanwhile are in neither list,
// their parts name the parent the caller knew, the runtime never asks where
// an untaken cluster is (it answers from the event: parts inherit the
// motion), and the caller's mirror comes out equal to the live set.
static void test_created_then_removed(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 27, 5);
  static caller c;
  static taken t;
  memset(&c, 0, sizeof c);
  bk_runtime* rt = make_runtime(&c, 2, bk_v3(0, -9.81, 0));
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_runtime_add_breakable(rt, &bd, NULL);
  take(rt, &c, &t);
  bk_cluster_id first = t.created[0].cluster.id;
  c.state[first.index].linear_velocity = bk_v3(0, 0, 3); // it flies
  bk_runtime_damage_at(rt, bk_v3(0, 0, 0), 1e9);         // every bond
  uint32_t calls = 0, made = 0;
  for (; calls < 40 && bk_runtime_get_stats(rt).pending_splits; ++calls)
    made += bk_runtime_split(rt);
  ENSURE(calls > 2 && bk_runtime_get_stats(rt).clusters == tree.leaf_count);
  ENSURE(made > tree.leaf_count); // remainders were made and split again
  take(rt, &c, &t);
  ENSURE_MSG(t.created_count == tree.leaf_count, "%u created for %u fragments", t.created_count,
             tree.leaf_count);
  ENSURE(t.removed_count == 1 && bk_cluster_equal(t.removed[0].cluster, first));
  for (uint32_t i = 0; i < t.created_count; ++i) {
    ENSURE(bk_cluster_equal(t.created[i].parent, first));
    ENSURE_SMALL(t.created[i].body.linear_velocity.z, 3.0, 1e-12);
  }
  ENSURE(c.asked_unknown == 0);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
}

// User data: the breakable's on its first cluster and on every event; a
// cluster's set by the caller, inherited by its parts, carried by its
// bonds' breaks and its removal.
static void test_user_data(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 16, 6);
  static caller c;
  static taken t;
  memset(&c, 0, sizeof c);
  bk_runtime* rt = make_runtime(&c, 48, bk_v3(0, -9.81, 0));
  int breakable_tag = 0, cluster_tag = 0, part_tag = 0;
  bk_breakable_def bd = bk_default_breakable_def();
  ENSURE(bd.user_data == NULL);
  bd.tree = &tree;
  bd.user_data = &breakable_tag;
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, NULL);
  ENSURE(bk_runtime_breakable_user_data(rt, id) == &breakable_tag);
  take(rt, &c, &t);
  bk_cluster_id whole = t.created[0].cluster.id;
  ENSURE(t.created[0].cluster.user_data == &breakable_tag &&
         t.created[0].cluster.breakable_user_data == &breakable_tag);
  ENSURE(bk_runtime_set_cluster_user_data(rt, whole, &cluster_tag) == BK_OK);
  ENSURE(bk_runtime_cluster_user_data(rt, whole) == &cluster_tag);
  bk_runtime_damage_at(rt, bk_v3(0.4, 0.4, 0.4), 1e4);
  uint32_t made = bk_runtime_split(rt);
  take(rt, &c, &t);
  ENSURE(made > 1 && t.broken_count > 0);
  for (uint32_t i = 0; i < t.broken_count; ++i)
    ENSURE(t.broken[i].user_data == &cluster_tag && t.broken[i].breakable_user_data == &breakable_tag);
  ENSURE(t.removed_count == 1 && t.removed[0].user_data == &cluster_tag &&
         t.removed[0].breakable_user_data == &breakable_tag);
  for (uint32_t i = 0; i < made; ++i)
    ENSURE(t.created[i].cluster.user_data == &cluster_tag); // the parent's
  bk_cluster_id part = t.created[0].cluster.id;
  ENSURE(bk_runtime_set_cluster_user_data(rt, part, &part_tag) == BK_OK);
  bk_cluster_info info = {0};
  ENSURE(bk_runtime_cluster(rt, part, &info) && info.user_data == &part_tag);
  ENSURE(bk_runtime_set_cluster_user_data(rt, whole, &part_tag) == BK_ERROR_STALE_ID);
  ENSURE(bk_runtime_cluster_user_data(rt, whole) == NULL);
  ENSURE(bk_runtime_set_breakable_user_data(rt, id, &part_tag) == BK_OK &&
         bk_runtime_breakable_user_data(rt, id) == &part_tag);
  ENSURE(bk_runtime_remove_cluster(rt, part) == BK_OK);
  take(rt, &c, &t);
  ENSURE(t.removed_count == 1 && t.removed[0].user_data == &part_tag &&
         t.removed[0].breakable_user_data == &part_tag);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
}

// The index bound: above every live index, never shrinking, reached by
// slots only (a removed cluster's slot is used again).
static void test_cluster_capacity(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 27, 7);
  static caller c;
  static taken t;
  memset(&c, 0, sizeof c);
  bk_runtime* rt = make_runtime(&c, 48, bk_v3(0, -9.81, 0));
  ENSURE(bk_runtime_cluster_capacity(rt) == 0);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bk_runtime_add_breakable(rt, &bd, NULL);
  take(rt, &c, &t);
  bk_runtime_damage_at(rt, bk_v3(0, 0, 0), 1e9);
  bk_runtime_split(rt);
  take(rt, &c, &t);
  uint32_t capacity = bk_runtime_cluster_capacity(rt);
  bk_cluster_id live[64];
  uint32_t n = bk_runtime_clusters(rt, live, 64);
  ENSURE(n == tree.leaf_count && capacity >= n);
  for (uint32_t i = 0; i < n; ++i)
    ENSURE(live[i].index < capacity);
  for (uint32_t i = 0; i < n; i += 2)
    bk_runtime_remove_cluster(rt, live[i]);
  take(rt, &c, &t);
  ENSURE(bk_runtime_cluster_capacity(rt) == capacity); // never shrinks
  bk_runtime_add_breakable(rt, &bd, NULL);             // reuses a freed slot
  take(rt, &c, &t);
  ENSURE(bk_runtime_cluster_capacity(rt) == capacity && t.created[0].cluster.id.index < capacity);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
}

// Removing a breakable: its clusters reported removed, its id stale for
// every call, the other breakable untouched; its slot is reused with a new
// generation. A breakable added and removed before a take leaves no event.
static void test_remove_breakable(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 8, 8);
  static caller c;
  static taken t;
  memset(&c, 0, sizeof c);
  bk_runtime* rt = make_runtime(&c, 48, bk_v3(0, -9.81, 0));
  int tag_a = 0, tag_b = 0;
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = &tree;
  bd.user_data = &tag_a;
  bk_breakable_id a = bk_runtime_add_breakable(rt, &bd, NULL);
  bd.user_data = &tag_b;
  bd.transform.position = bk_v3(5, 0, 0);
  bk_breakable_id b = bk_runtime_add_breakable(rt, &bd, NULL);
  take(rt, &c, &t);
  bk_runtime_damage_at(rt, bk_v3(0, 0, 0), 1e5); // shatters a, not b 5 m away
  bk_runtime_split(rt);
  take(rt, &c, &t);
  uint32_t a_clusters = t.created_count;
  ENSURE(a_clusters == 8 && bk_runtime_get_stats(rt).clusters == 9);
  ENSURE(bk_runtime_remove_breakable(rt, a) == BK_OK);
  ENSURE(bk_runtime_removed_clusters(rt, t.removed, 512) == a_clusters);
  for (uint32_t i = 0; i < a_clusters; ++i)
    ENSURE(t.removed[i].breakable.index == a.index && t.removed[i].breakable_user_data == &tag_a);
  take(rt, &c, &t);
  bk_runtime_stats st = bk_runtime_get_stats(rt);
  ENSURE(st.breakables == 1 && st.clusters == 1);
  ENSURE(bk_runtime_remove_breakable(rt, a) == BK_ERROR_STALE_ID);
  ENSURE(bk_runtime_set_density(rt, a, 1000.0) == BK_ERROR_STALE_ID);
  ENSURE(bk_runtime_breakable_tree(rt, a) == NULL && bk_runtime_breakable_user_data(rt, a) == NULL);
  ENSURE(bk_cluster_is_null(bk_runtime_leaf_cluster(rt, a, 0)));
  ENSURE(bk_runtime_breakable_tree(rt, b) == &tree && bk_runtime_breakable_user_data(rt, b) == &tag_b);
  // The hit that shattered a breaks nothing now.
  bk_runtime_damage_at(rt, bk_v3(0, 0, 0), 1e5);
  ENSURE(bk_runtime_broken_bonds(rt, NULL, 0) == 0);
  // Its slot again, a new generation: the old id stays stale.
  bk_breakable_id again = bk_runtime_add_breakable(rt, &bd, NULL);
  ENSURE(again.index == a.index && again.generation != a.generation);
  ENSURE(bk_runtime_breakable_tree(rt, a) == NULL && bk_runtime_breakable_tree(rt, again) == &tree);
  // Added and removed before a take: nothing to make, nothing to remove.
  ENSURE(bk_runtime_remove_breakable(rt, again) == BK_OK);
  take(rt, &c, &t);
  ENSURE(t.created_count == 0 && t.removed_count == 0 && c.asked_unknown == 0);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
}

// "Up" is the opposite of gravity: a tower lying along +X under gravity
// along -X anchors the same fragments, at the same height along up, as the
// tower standing under gravity along -Y, carries the same stresses in every
// bond, and breaks the same bonds when its limits are scaled down.
static void anchored_tower(const bk_mesh_tree* tree, bool lying, double limits, uint8_t* is_static,
                           double* ratio, uint32_t* broken) {
  static caller c;
  static taken t;
  memset(&c, 0, sizeof c);
  bk_vec3 gravity = lying ? bk_v3(-9.81, 0, 0) : bk_v3(0, -9.81, 0);
  bk_runtime* rt = make_runtime(&c, 4096, gravity);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = tree;
  bd.anchored = true;
  bd.material = *bk_material_find("stone");
  bd.material.compression_limit *= limits;
  bd.material.tension_limit *= limits;
  bd.material.shear_limit *= limits;
  // -90 degrees about Z takes +Y to +X: its base is on the plane x = 0.
  if (lying)
    bd.transform =
        (bk_transform){{0, 0, 0}, bk_quat_axis_angle(bk_v3(0, 0, 1), -0.5 * 3.14159265358979323846)};
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, NULL);
  take(rt, &c, &t);
  for (uint32_t call = 0; call < 400; ++call) {
    bk_runtime_solve_stress(rt, gravity, NULL, 0, NULL, 0);
    bk_runtime_split(rt);
    take(rt, &c, &t);
    bk_runtime_stats st = bk_runtime_get_stats(rt);
    if (st.stress_clusters_pending == 0 && st.pending_splits == 0) break;
  }
  for (uint32_t k = 0; k < tree->bond_count; ++k) {
    bk_bond_stress s = {0};
    ratio[k] = bk_runtime_bond_stress(rt, id, k, &s) ? s.ratio : -1.0;
  }
  *broken = bk_runtime_get_stats(rt).stress_bonds_broken;
  // Every bond broken by hand: the fragments alone tell which are anchored.
  bk_runtime_damage_at(rt, bk_v3(0, 0, 0), 1e12);
  bk_runtime_split(rt);
  take(rt, &c, &t);
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_cluster_info info = {0};
    ENSURE(bk_runtime_cluster(rt, bk_runtime_leaf_cluster(rt, id, l), &info) && info.leaf_count == 1);
    is_static[l] = info.is_static;
  }
  ENSURE(c.asked_unknown == 0);
  bk_runtime_destroy(rt);
}

static void test_up_from_gravity(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_TOWER, 48, 9);
  uint8_t standing[64] = {0}, lying[64] = {0};
  double standing_ratio[512], lying_ratio[512];
  ENSURE(tree.leaf_count <= 64 && tree.bond_count <= 512);
  for (int weak = 0; weak < 2; ++weak) {
    double limits = weak ? 1e-3 : 1.0;
    uint32_t standing_broken = 0, lying_broken = 0;
    anchored_tower(&tree, false, limits, standing, standing_ratio, &standing_broken);
    anchored_tower(&tree, true, limits, lying, lying_ratio, &lying_broken);
    uint32_t anchored = 0;
    for (uint32_t l = 0; l < tree.leaf_count; ++l) {
      ENSURE_MSG(standing[l] == lying[l], "fragment %u: anchored %d standing, %d lying", l, standing[l],
                 lying[l]);
      anchored += standing[l];
    }
    ENSURE(anchored > 0 && anchored < tree.leaf_count);
    ENSURE_MSG(standing_broken == lying_broken, "%u bonds broken standing, %u lying", standing_broken,
               lying_broken);
    if (weak) {
      ENSURE(standing_broken > 0);
    } else {
      ENSURE(standing_broken == 0);
      for (uint32_t k = 0; k < tree.bond_count; ++k)
        ENSURE_SMALL(lying_ratio[k], standing_ratio[k],
                     1e-3 * fmax(1.0, standing_ratio[k])); // the solve's tolerance
    }
  }
  // The setter: finite only; zero gravity means +Y.
  static caller c;
  bk_runtime* rt = make_runtime(&c, 48, bk_v3(0, 0, 0));
  ENSURE(bk_runtime_set_gravity(rt, bk_v3(NAN, 0, 0)) == BK_ERROR_INVALID_ARGUMENT);
  ENSURE(bk_runtime_gravity(rt).x == 0.0);
  ENSURE(bk_runtime_set_gravity(rt, bk_v3(0, 0, -1e300)) == BK_OK && bk_runtime_gravity(rt).z == -1e300);
  bk_runtime_destroy(rt);
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.gravity = bk_v3(0, INFINITY, 0);
  bk_error err = {0};
  ENSURE(bk_runtime_create(&def, &err) == NULL && err.code == BK_ERROR_INVALID_ARGUMENT);
  ENSURE_MSG(strstr(err.message, "gravity"), "%s", err.message);
  bk_mesh_tree_free(&tree);
}

// Error codes beside the messages: bad fields, a bad tree, stale ids.
static void test_error_codes(void) {
  static caller c;
  bk_error err = {0};
  ENSURE(err.code == BK_OK);
  bk_runtime_def def = bk_default_runtime_def();
  ENSURE(bk_runtime_create(&def, &err) == NULL && err.code == BK_ERROR_INVALID_ARGUMENT);
  bk_runtime* rt = make_runtime(&c, 48, bk_v3(0, -9.81, 0));
  bk_breakable_def bd = bk_default_breakable_def();
  err = (bk_error){{0}};
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)) &&
         err.code == BK_ERROR_INVALID_ARGUMENT);
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 8, 10);
  uint32_t leaf_b = tree.bonds[0].leaf_b;
  tree.bonds[0].leaf_b = tree.leaf_count + 7; // a bond to a leaf that is not there
  bd.tree = &tree;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)) && err.code == BK_ERROR_BAD_TREE);
  ENSURE_MSG(strstr(err.message, "breakable: tree:"), "%s", err.message);
  tree.bonds[0].leaf_b = leaf_b;
  bd.material.friction = -1.0;
  ENSURE(bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err)) &&
         err.code == BK_ERROR_INVALID_ARGUMENT);
  bd.material.friction = 0.5;
  bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, &err);
  ENSURE(!bk_breakable_is_null(id));
  ENSURE(bk_runtime_set_frailty(rt, id, NAN) == BK_ERROR_INVALID_ARGUMENT);
  ENSURE(bk_runtime_set_material(rt, id, NULL) == BK_ERROR_INVALID_ARGUMENT);
  ENSURE(bk_runtime_set_breakable_user_data(rt, (bk_breakable_id){id.index, id.generation + 1}, NULL) ==
         BK_ERROR_STALE_ID);
  ENSURE(bk_runtime_remove_cluster(rt, (bk_cluster_id){0, 0}) == BK_ERROR_STALE_ID);
  ENSURE(strcmp(bk_result_name(BK_ERROR_STALE_ID), "stale id") == 0 &&
         strcmp(bk_result_name(BK_OK), "ok") == 0);
  bk_runtime_destroy(rt);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  RUN(test_events_accumulate);
  RUN(test_created_then_removed);
  RUN(test_user_data);
  RUN(test_cluster_capacity);
  RUN(test_remove_breakable);
  RUN(test_up_from_gravity);
  RUN(test_error_codes);
  return 0;
}
