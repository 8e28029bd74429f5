// The embedder's API through the Bullet world: a breakable removed with its
// bodies (and its id stale everywhere, its slot reused), user data handed
// back in body views and break events, setters returning the runtime's
// codes, errors keeping the runtime's code, and the runtime's events taken
// by the world after each of its calls (none left between them).
#include <string.h>

#include <breakables/bullet.h>

#include "ensure.h"

static bk_mesh_tree make_tree(uint32_t pieces) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_CUBE, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = pieces;
  def.seed = 4;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &def, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

static uint32_t bodies_of(const bk_world* world, bk_breakable_id id, const void* user_data) {
  uint32_t count = 0;
  for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, i, &view));
    if (view.breakable.index != id.index || view.breakable.generation != id.generation) continue;
    ENSURE(view.user_data == user_data);
    count++;
  }
  return count;
}

static void ensure_no_runtime_events(const bk_world* world) {
  const bk_runtime* rt = bk_world_runtime(world);
  ENSURE(bk_runtime_created_clusters(rt, NULL, 0) == 0 && bk_runtime_removed_clusters(rt, NULL, 0) == 0 &&
         bk_runtime_broken_bonds(rt, NULL, 0) == 0);
}

static void test_remove_and_user_data(void) {
  bk_mesh_tree tree = make_tree(27);
  bk_error err = {0};
  bk_world_def wd = bk_default_world_def();
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  int tag_a = 0, tag_b = 0;
  bk_world_breakable_def bd = bk_default_world_breakable_def();
  bd.breakable.tree = &tree;
  bd.breakable.transform.position = bk_v3(0, 0.5, 0);
  bd.breakable.user_data = &tag_a;
  bk_breakable_id a = bk_world_add_breakable(world, &bd, &err);
  bd.breakable.transform.position = bk_v3(6, 0.5, 0);
  bd.breakable.user_data = &tag_b;
  bk_breakable_id b = bk_world_add_breakable(world, &bd, &err);
  ENSURE(!bk_breakable_is_null(a) && !bk_breakable_is_null(b));
  ensure_no_runtime_events(world);
  // A blast shatters a, and its break events carry a's user data.
  bk_world_impact(world, bk_v3(0, 0.5, 0), 2e5);
  ensure_no_runtime_events(world);
  bk_world_step(world);
  ensure_no_runtime_events(world);
  bk_break_event events[1024];
  uint32_t n = bk_world_break_events(world, events, 1024);
  ENSURE(n > 0 && n <= 1024);
  for (uint32_t i = 0; i < n; ++i)
    ENSURE(events[i].user_data == (events[i].breakable.index == a.index ? (void*)&tag_a : (void*)&tag_b));
  uint32_t a_bodies = bodies_of(world, a, &tag_a), b_bodies = bodies_of(world, b, &tag_b);
  ENSURE(a_bodies > 1 && b_bodies >= 1);
  uint32_t physics_bodies = bk_physics_body_count(bk_world_physics(world));
  // Removed: its bodies leave Bullet, its id is stale, b is untouched.
  ENSURE(bk_world_remove_breakable(world, a) == BK_OK);
  ensure_no_runtime_events(world);
  ENSURE(bodies_of(world, a, &tag_a) == 0 && bodies_of(world, b, &tag_b) == b_bodies);
  ENSURE(bk_physics_body_count(bk_world_physics(world)) == physics_bodies - a_bodies);
  ENSURE(bk_world_remove_breakable(world, a) == BK_ERROR_STALE_ID);
  ENSURE(bk_world_set_density(world, a, 1000.0) == BK_ERROR_STALE_ID);
  ENSURE(bk_world_set_density(world, b, -1.0) == BK_ERROR_INVALID_ARGUMENT);
  ENSURE(bk_world_set_density(world, b, 1000.0) == BK_OK);
  ENSURE(bk_world_set_material(world, b, bk_material_find("glass")) == BK_OK);
  ENSURE(bk_breakable_is_null(bk_world_breakable_at(world, a.index)));
  ENSURE(bk_world_breakable_at(world, b.index).generation == b.generation);
  for (int i = 0; i < 30; ++i)
    bk_world_step(world);
  ensure_no_runtime_events(world);
  ENSURE(bodies_of(world, b, &tag_b) == b_bodies);
  // Its slot again, a new generation.
  bd.breakable.user_data = &tag_a;
  bk_breakable_id again = bk_world_add_breakable(world, &bd, &err);
  ENSURE(again.index == a.index && again.generation != a.generation);
  ENSURE(bk_world_breakable_at(world, a.index).generation == again.generation);
  ENSURE(bodies_of(world, again, &tag_a) == 1);
  bk_world_step(world);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// The world's errors keep the runtime's code.
static void test_error_codes(void) {
  bk_error err = {0};
  bk_world_def wd = bk_default_world_def();
  wd.runtime.max_new_clusters_per_split = 1;
  ENSURE(bk_world_create(&wd, &err) == NULL && err.code == BK_ERROR_INVALID_ARGUMENT);
  wd = bk_default_world_def();
  wd.fixed_dt = 0.0;
  ENSURE(bk_world_create(&wd, &err) == NULL && err.code == BK_ERROR_INVALID_ARGUMENT);
  wd = bk_default_world_def();
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  bk_mesh_tree tree = make_tree(8);
  tree.bonds[0].leaf_a = tree.leaf_count + 3;
  bk_world_breakable_def bd = bk_default_world_breakable_def();
  bd.breakable.tree = &tree;
  ENSURE(bk_breakable_is_null(bk_world_add_breakable(world, &bd, &err)) && err.code == BK_ERROR_BAD_TREE);
  bd.convexity_tolerance = -1.0;
  ENSURE(bk_breakable_is_null(bk_world_add_breakable(world, &bd, &err)) &&
         err.code == BK_ERROR_INVALID_ARGUMENT);
  bk_projectile_def shot = bk_default_projectile_def();
  shot.radius = 0.0;
  ENSURE(bk_body_is_null(bk_world_fire(world, &shot, &err)) && err.code == BK_ERROR_INVALID_ARGUMENT);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  RUN(test_remove_and_user_data);
  RUN(test_error_codes);
  return 0;
}
