// The allocator hook (bk_set_allocator): every allocation of authoring,
// runtime and the bullet world's C side goes through the embedder's
// functions, from the fracture's worker threads too, and every block comes
// back to them; an allocator that fails makes calls fail with "out of
// memory" instead of crashing.
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ensure.h"
#include <breakables/bullet.h>

// Each block this allocator makes starts with a tag and its size (16 bytes,
// so the caller's part keeps malloc's alignment): a block it did not make,
// handed to its free or realloc, is caught at once.
#define BLOCK_TAG 0x6b62616c6c6f6321ull
typedef struct block_header {
  uint64_t tag, size;
} block_header;

typedef struct counting {
  atomic_int_fast64_t allocs, reallocs, frees, live_blocks, live_bytes, peak_bytes;
  atomic_int_fast64_t foreign;       // blocks handed back that it did not make
  atomic_int_fast64_t other_threads; // calls from a thread other than main's
  atomic_int_fast64_t wrong_user;    // calls with another user pointer
} counting;

static pthread_t main_thread;

static void note_call(counting* c, void* user) {
  if (user != c) atomic_fetch_add(&c->wrong_user, 1);
  if (!pthread_equal(pthread_self(), main_thread)) atomic_fetch_add(&c->other_threads, 1);
}

static void add_bytes(counting* c, int64_t bytes) {
  int64_t now = atomic_fetch_add(&c->live_bytes, bytes) + bytes;
  int64_t peak = atomic_load(&c->peak_bytes);
  while (now > peak && !atomic_compare_exchange_weak(&c->peak_bytes, &peak, now)) {
  }
}

static block_header* header_of(counting* c, void* memory) {
  block_header* h = (block_header*)memory - 1;
  if (h->tag != BLOCK_TAG) {
    atomic_fetch_add(&c->foreign, 1);
    fprintf(stderr, "test_allocator: a block the allocator did not make was handed back\n");
    abort(); // freeing it as ours would corrupt the heap
  }
  return h;
}

static void* counting_alloc(size_t size, void* user) {
  counting* c = user;
  note_call(c, user);
  block_header* h = malloc(sizeof *h + size);
  if (!h) return NULL;
  *h = (block_header){BLOCK_TAG, size};
  atomic_fetch_add(&c->allocs, 1);
  atomic_fetch_add(&c->live_blocks, 1);
  add_bytes(c, (int64_t)size);
  return h + 1;
}

static void* counting_realloc(void* memory, size_t size, void* user) {
  counting* c = user;
  note_call(c, user);
  block_header* h = header_of(c, memory);
  uint64_t old_size = h->size;
  block_header* moved = realloc(h, sizeof *h + size);
  if (!moved) return NULL;
  moved->size = size;
  atomic_fetch_add(&c->reallocs, 1);
  add_bytes(c, (int64_t)size - (int64_t)old_size);
  return moved + 1;
}

static void counting_free(void* memory, void* user) {
  counting* c = user;
  note_call(c, user);
  block_header* h = header_of(c, memory);
  add_bytes(c, -(int64_t)h->size);
  h->tag = 0;
  free(h);
  atomic_fetch_add(&c->frees, 1);
  atomic_fetch_sub(&c->live_blocks, 1);
}

static bk_mesh_tree build_tree(bk_fracture_pattern pattern, uint32_t pieces) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_CUBE, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = pattern;
  def.pieces = pieces;
  def.seed = 7;
  def.threads = 4; // worker threads, whatever the machine's cores
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &def, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

// A fracture on worker threads, a world that breaks the tree apart, the
// runtime under it, files written and read back: every block through the
// hook, none left once all is released.
static void test_counting_allocator_sees_everything(void) {
  counting c = {0};
  main_thread = pthread_self();
  ENSURE(bk_allocation_count() == 0);
  bk_set_allocator(counting_alloc, counting_realloc, counting_free, &c);

  bk_mesh_tree voronoi = build_tree(BK_PATTERN_VORONOI, 48);
  bk_mesh_tree planes = build_tree(BK_PATTERN_PLANES, 32);
  ENSURE(voronoi.leaf_count >= 40 && planes.leaf_count == 32);
  // The cell pattern's workers allocated through the hook too.
  ENSURE(atomic_load(&c.other_threads) > 0);
  int64_t trees_blocks = atomic_load(&c.live_blocks);
  ENSURE(trees_blocks > 0 && trees_blocks == bk_allocation_count());

  bk_world_def world_def = bk_default_world_def();
  bk_error err = {0};
  bk_world* world = bk_world_create(&world_def, &err);
  ENSURE_MSG(world != NULL, "%s", err.message);
  bk_world_breakable_def def = bk_default_world_breakable_def();
  def.breakable.tree = &planes;
  def.breakable.transform.position = bk_v3(0, 0.5, 0);
  ENSURE_MSG(bk_world_add_breakable(world, &def, &err).generation != 0, "%s", err.message);
  def.breakable.tree = &voronoi;
  def.breakable.transform.position = bk_v3(3, 0.5, 0);
  ENSURE_MSG(bk_world_add_breakable(world, &def, &err).generation != 0, "%s", err.message);
  ENSURE(atomic_load(&c.live_blocks) > trees_blocks);
  bk_projectile_def shot = bk_default_projectile_def();
  shot.position = bk_v3(0, 0.5, -3);
  shot.velocity = bk_v3(0, 0, 60);
  ENSURE_MSG(bk_world_fire(world, &shot, &err).generation != 0, "%s", err.message);
  for (int i = 0; i < 60; ++i)
    bk_world_step(world);
  bk_world_impact(world, bk_v3(3, 0.5, 0), 5e4);
  for (int i = 0; i < 30; ++i)
    bk_world_step(world);
  // The hit broke the trees apart: the world holds more bodies than it started with.
  ENSURE(bk_world_get_stats(world).bodies > 2);
  bk_world_destroy(world);
  ENSURE(atomic_load(&c.live_blocks) == trees_blocks);

  // A file written atomically and read back (the file helpers of base.h).
  char path[512];
  snprintf(path, sizeof path, "%s/test_allocator.mtree", BK_TEST_TMP);
  ENSURE_MSG(bk_mesh_tree_save(&planes, path, &err), "%s", err.message);
  void* data = NULL;
  size_t size = 0;
  ENSURE_MSG(bk_file_read(path, 1u << 30, "1 GiB", &data, &size, &err), "%s", err.message);
  ENSURE(size > 0 && atomic_load(&c.live_blocks) == trees_blocks + 1);
  bk_free(data);
  remove(path);
  // A glTF export read back (its JSON reader and writer).
  snprintf(path, sizeof path, "%s/test_allocator.gltf", BK_TEST_TMP);
  ENSURE_MSG(bk_mesh_tree_save_gltf(&voronoi, path, NULL, &err), "%s", err.message);
  bk_mesh_tree loaded = {0};
  ENSURE_MSG(bk_mesh_tree_load_gltf(path, &loaded, &err), "%s", err.message);
  ENSURE(loaded.leaf_count == voronoi.leaf_count);
  bk_mesh_tree_free(&loaded);
  remove(path);
  ENSURE(atomic_load(&c.live_blocks) == trees_blocks);

  bk_mesh_tree_free(&voronoi);
  bk_mesh_tree_free(&planes);
  bk_set_allocator(NULL, NULL, NULL, NULL);
  printf("allocator: %lld allocations, %lld reallocations, %lld frees, %lld calls from worker threads, peak "
         "%.1f MiB\n",
         (long long)atomic_load(&c.allocs), (long long)atomic_load(&c.reallocs),
         (long long)atomic_load(&c.frees), (long long)atomic_load(&c.other_threads),
         (double)atomic_load(&c.peak_bytes) / (1 << 20));
  ENSURE(atomic_load(&c.allocs) > 1000 && atomic_load(&c.frees) == atomic_load(&c.allocs));
  ENSURE(atomic_load(&c.live_blocks) == 0 && atomic_load(&c.live_bytes) == 0);
  ENSURE(bk_allocation_count() == 0);
  ENSURE(atomic_load(&c.foreign) == 0 && atomic_load(&c.wrong_user) == 0);
}

static bk_body_state resting_body(bk_cluster_id cluster, void* context) {
  (void)cluster;
  (void)context;
  return (bk_body_state){0};
}

static void* failing_alloc(size_t size, void* user) {
  (void)size;
  atomic_fetch_add((atomic_int_fast64_t*)user, 1);
  return NULL;
}
static void* failing_realloc(void* memory, size_t size, void* user) {
  (void)memory;
  (void)size;
  atomic_fetch_add((atomic_int_fast64_t*)user, 1);
  return NULL;
}
static void failing_free(void* memory, void* user) {
  (void)memory;
  (void)user;
  abort(); // nothing was ever allocated
}

// An allocator with no memory: creating a runtime or a world and reading a
// file fail with one line saying so, and nothing is left allocated.
static void test_failing_allocator_reports_out_of_memory(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/test_allocator.obj", BK_TEST_TMP);
  FILE* f = fopen(path, "w");
  ENSURE(f != NULL);
  fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", f);
  fclose(f);

  atomic_int_fast64_t calls = 0;
  bk_set_allocator(failing_alloc, failing_realloc, failing_free, &calls);
  bk_error err = {0};
  bk_runtime_def runtime_def = bk_default_runtime_def();
  runtime_def.body_state = resting_body;
  ENSURE(bk_runtime_create(&runtime_def, &err) == NULL);
  ENSURE_MSG(strcmp(err.message, "runtime: out of memory") == 0 && err.code == BK_ERROR_OUT_OF_MEMORY, "%s",
             err.message);
  err = (bk_error){0};
  bk_world_def world_def = bk_default_world_def();
  bk_world* world = bk_world_create(&world_def, &err);
  ENSURE(world == NULL);
  ENSURE_MSG(strcmp(err.message, "world: out of memory") == 0 && err.code == BK_ERROR_OUT_OF_MEMORY, "%s",
             err.message);
  void* data = NULL;
  size_t size = 0;
  err = (bk_error){0};
  ENSURE(!bk_file_read(path, 1u << 20, "1 MiB", &data, &size, &err) && data == NULL);
  ENSURE_MSG(strstr(err.message, "out of memory reading") != NULL &&
                 strstr(err.message, path) == err.message && err.code == BK_ERROR_OUT_OF_MEMORY,
             "%s", err.message);
  bk_mesh mesh = {0};
  err = (bk_error){0};
  ENSURE(!bk_obj_load(path, &mesh, &err) && mesh.triangle_count == 0);
  ENSURE_MSG(strstr(err.message, "out of memory") != NULL && err.code == BK_ERROR_OUT_OF_MEMORY, "%s",
             err.message);
  bk_set_allocator(NULL, NULL, NULL, NULL);
  ENSURE(atomic_load(&calls) >= 3 && bk_allocation_count() == 0);

  // The same calls succeed once the C library's allocator is back.
  ENSURE_MSG(bk_obj_load(path, &mesh, &err) && mesh.triangle_count == 4, "%s", err.message);
  bk_mesh_free(&mesh);
  remove(path);
  ENSURE(bk_allocation_count() == 0);
}

int main(void) {
  RUN(test_counting_allocator_sees_everything);
  RUN(test_failing_allocator_reports_out_of_memory);
  return 0;
}
