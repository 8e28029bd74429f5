// The native side of the browser test's split timing (tests/web/split.mjs
// does the same through the WebAssembly module in the page): the wall shape
// fractured into PIECES (brick, seed SEED), added anchored in stone to a
// runtime with no physics engine, hit in the middle of its front face
// (bk_runtime_damage_at, 320 N s: the wall scene's 8 kg ball at 40 m/s), then
// split until nothing is pending. Each of RUNS runs starts from a fresh
// runtime; the mean times are printed as one JSON object.
//   split_native PIECES SEED RUNS
// Built by the browser test against build/'s static libraries.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#define XXH_INLINE_ALL // header only, as the libraries use it
#include <xxhash.h>

#include <breakables/authoring.h>
#include <breakables/runtime.h>

static double now_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

// The mean, not the median: the page's clock is coarse (0.1 ms in a browser
// page without cross-origin isolation), and only a mean of such readings
// stays unbiased; both sides are measured alike.
static double mean(const double* v, int n) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    sum += v[i];
  return sum / n;
}

// Where each cluster's body is: where the runtime said it starts (nothing moves here).
static bk_body_state bodies[65536];

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  (void)context;
  return bodies[cluster.index % 65536u];
}

static void take_created(bk_runtime* rt) {
  uint32_t n = bk_runtime_created_clusters(rt, NULL, 0);
  bk_cluster_created* created = malloc(sizeof *created * (n ? n : 1u));
  bk_runtime_created_clusters(rt, created, n);
  for (uint32_t i = 0; i < n; ++i)
    bodies[created[i].cluster.id.index % 65536u] = created[i].body;
  free(created);
  bk_runtime_clear_events(rt);
}

int main(int argc, char** argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: split_native PIECES SEED RUNS\n");
    return 2;
  }
  uint32_t pieces = (uint32_t)strtoul(argv[1], NULL, 10);
  uint64_t seed = strtoull(argv[2], NULL, 10);
  int runs = atoi(argv[3]);
  if (runs < 1 || runs > 1000) runs = 5;

  bk_mesh wall = {0};
  bk_shape_build(BK_SHAPE_WALL, &wall);
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = pieces;
  def.pattern = BK_PATTERN_BRICK;
  def.seed = seed;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  double start = now_ms();
  if (!bk_mesh_tree_build(&wall, &def, &tree, &err)) {
    fprintf(stderr, "split_native: %s\n", err.message);
    return 1;
  }
  double fracture_ms = now_ms() - start;
  uint8_t* bytes = NULL;
  size_t size = 0;
  unsigned long long hash =
      bk_mesh_tree_save_memory(&tree, "tree", &bytes, &size, NULL) ? XXH3_64bits(bytes, size) : 0;
  bk_free(bytes);

  double* damage = calloc((size_t)runs, sizeof *damage);
  double* split = calloc((size_t)runs, sizeof *split);
  uint32_t calls = 0, created = 0, broken = 0;
  for (int r = 0; r < runs; ++r) {
    bk_runtime_def rd = bk_default_runtime_def();
    rd.body_state = body_state;
    bk_runtime* rt = bk_runtime_create(&rd, &err);
    bk_breakable_def bd = bk_default_breakable_def();
    bd.tree = &tree;
    bd.anchored = true;
    bd.material = *bk_material_find("stone");
    if (!rt || bk_breakable_is_null(bk_runtime_add_breakable(rt, &bd, &err))) {
      fprintf(stderr, "split_native: %s\n", err.message);
      return 1;
    }
    take_created(rt);
    bk_aabb box = tree.nodes[0].bounds;
    bk_vec3 middle = {0.5 * (box.min.x + box.max.x), 0.5 * (box.min.y + box.max.y), box.max.z};
    double t0 = now_ms();
    bk_runtime_damage_at(rt, middle, 320.0);
    double t1 = now_ms();
    broken = bk_runtime_broken_bonds(rt, NULL, 0);
    calls = created = 0;
    for (;;) {
      uint32_t made = bk_runtime_split(rt);
      ++calls;
      created += made;
      if (made == 0 && bk_runtime_get_stats(rt).pending_splits == 0) break;
    }
    double t2 = now_ms();
    take_created(rt);
    damage[r] = t1 - t0;
    split[r] = t2 - t1;
    bk_runtime_destroy(rt);
  }
  printf(
      "{\"pieces\": %u, \"fragments\": %u, \"bonds\": %u, \"tree_hash\": \"%016llx\", \"fracture_ms\": %.3f, "
      "\"damage_ms\": %.4f, \"split_ms\": %.4f, \"split_calls\": %u, \"clusters_created\": %u, "
      "\"bonds_broken\": %u, \"runs\": %d}\n",
      pieces, tree.leaf_count, tree.bond_count, hash, fracture_ms, mean(damage, runs), mean(split, runs),
      calls, created, broken, runs);
  free(damage);
  free(split);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&wall);
  return 0;
}
