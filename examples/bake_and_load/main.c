// bake_and_load: fracture offline, load in the game.
//
// Fracturing takes from milliseconds (a cube) to seconds (a detailed mesh),
// so it belongs in an offline tool, like lightmaps: bake the mesh tree once,
// ship the .mtree file, and have the game load it, which is fast and checked
// (magic, version, checksum, every index). This program does both halves:
//   bake: fracture a mesh (an OBJ file, or the built-in pillar) and save it;
//   game: load the file, handling a bad one through bk_error, and instance
//         it into a runtime (no physics engine needed here), then blast it.
//
//   bake_and_load [mesh.obj [out.mtree]]
#include <breakables/runtime.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_ms(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

// ---- the offline tool
static bool bake(const char* obj_path, const char* mtree_path) {
  bk_error err = {0};
  bk_mesh mesh = {0};
  if (obj_path && !bk_obj_load(obj_path, &mesh, &err))
    return fprintf(stderr, "bake: %s\n", err.message), false;
  if (!obj_path) bk_shape_build(BK_SHAPE_PILLAR, &mesh);
  double start = now_ms();
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = 128;
  def.aspect_bias = 1.5; // chunky pieces from a tall shape (0 for uniform cuts)
  bk_mesh_tree tree = {0};
  bool ok = bk_mesh_tree_build(&mesh, &def, &tree, &err) && bk_mesh_tree_save(&tree, mtree_path, &err);
  if (!ok) fprintf(stderr, "bake: %s\n", err.message);
  char why[256];
  if (ok && bk_mesh_tree_shortfall_text(&tree, why, sizeof why)) printf("bake: note: %s\n", why);
  if (ok)
    printf("bake: %s -> %s: %u fragments in %.0f ms\n", obj_path ? obj_path : "pillar", mtree_path,
           tree.leaf_count, now_ms() - start);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&mesh);
  return ok;
}

// A copy of the file with one byte flipped: what a bad download looks like.
static void write_damaged_copy(const char* from, const char* to) {
  FILE* in = fopen(from, "rb");
  if (!in) return;
  fseek(in, 0, SEEK_END);
  size_t size = (size_t)ftell(in);
  rewind(in);
  unsigned char* bytes = malloc(size + 1);
  size = bytes ? fread(bytes, 1, size, in) : 0;
  fclose(in);
  FILE* out = bytes ? fopen(to, "wb") : NULL;
  if (out) {
    bytes[size / 2] ^= 0x40;
    fwrite(bytes, 1, size, out);
    fclose(out);
  }
  free(bytes);
}

// ---- the game
// Nothing moves here (no physics engine): each cluster stays where it was
// created. examples/own_physics shows bodies that move.
static bk_body_state bodies[4096]; // by cluster index, which stays below the fragment count

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  (void)context;
  return bodies[cluster.index];
}

// The runtime's events accumulate until cleared: take them, then clear.
static uint32_t take_created(bk_runtime* runtime) {
  static bk_cluster_created created[4096];
  uint32_t count = bk_runtime_created_clusters(runtime, created, 4096);
  for (uint32_t i = 0; i < count && i < 4096; ++i)
    bodies[created[i].cluster.id.index] = created[i].body;
  bk_runtime_clear_events(runtime);
  return count;
}

static bool game(const char* mtree_path) {
  bk_error err = {0};
  bk_mesh_tree tree = {0};
  double start = now_ms();
  if (!bk_mesh_tree_load(mtree_path, &tree, &err)) {
    // A game would fall back here: re-bake, or leave the object unbreakable.
    printf("game: cannot load %s: %s\n", mtree_path, err.message);
    return false;
  }
  double load_ms = now_ms() - start;
  bk_mesh_tree_stats stats = bk_mesh_tree_measure(&tree);
  printf("game: loaded %s in %.1f ms: %u leaves, %u bonds, volume %.6f m^3 (leaves sum to %.6f)\n",
         mtree_path, load_ms, tree.leaf_count, tree.bond_count, stats.source_volume, stats.leaf_volume_sum);

  bk_runtime_def runtime_def = bk_default_runtime_def();
  runtime_def.body_state = body_state;
  bk_runtime* runtime = bk_runtime_create(&runtime_def, &err);
  bk_breakable_def object = bk_default_breakable_def();
  object.tree = &tree; // borrowed: must outlive the runtime
  object.material = *bk_material_find("concrete");
  bk_aabb bounds = tree.nodes[0].bounds; // the root node is the whole mesh
  object.anchored = true;                // its foot is held by the ground
  object.anchor_height = bounds.min.y;
  if (!runtime || bk_breakable_is_null(bk_runtime_add_breakable(runtime, &object, &err))) {
    printf("game: %s\n", err.message);
    bk_runtime_destroy(runtime);
    bk_mesh_tree_free(&tree);
    return false;
  }
  take_created(runtime);
  // A charge goes off against its +x side, half way up, as strong as it is big (5000 N s per m^3).
  bk_vec3 side =
      bk_v3(bounds.max.x, 0.5 * (bounds.min.y + bounds.max.y), 0.5 * (bounds.min.z + bounds.max.z));
  bk_runtime_damage_at(runtime, side, 5000.0 * stats.source_volume);
  uint32_t broken = bk_runtime_broken_bonds(runtime, NULL, 0);
  bk_runtime_split(runtime);
  uint32_t created = take_created(runtime);
  if (created)
    printf("game: a blast broke %u bonds and split the object into %u clusters\n", broken, created);
  else
    printf("game: a blast broke %u bonds; the object held together\n", broken);
  bk_runtime_destroy(runtime); // before the tree it borrowed
  bk_mesh_tree_free(&tree);
  return true;
}

int main(int argc, char** argv) {
  const char* obj_path = argc > 1 ? argv[1] : NULL;
  const char* mtree_path = argc > 2 ? argv[2] : "bake_and_load.mtree";
  if (!bake(obj_path, mtree_path)) return 1;
  // Error handling first: a file that is not there, then a damaged one.
  char damaged[1024];
  snprintf(damaged, sizeof damaged, "%s.damaged", mtree_path);
  write_damaged_copy(mtree_path, damaged);
  if (game("no-such-file.mtree") || game(damaged)) return 1; // both must be refused
  remove(damaged);
  return game(mtree_path) ? 0 : 1;
}
