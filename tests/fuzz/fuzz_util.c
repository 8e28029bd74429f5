// Code shared by the fuzz harnesses; see fuzz_util.h.
#include "fuzz_util.h"

#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

_Noreturn void bk_fuzz_fail(const char* fmt, ...) {
  char message[1024] = {0};
  va_list args;
  va_start(args, fmt);
  vsnprintf(message, sizeof message, fmt, args);
  va_end(args);
  fprintf(stderr, "%s: %s\n", bk_fuzz_harness, message);
  fflush(stderr);
  abort();
}

// ---------------------------------------------------------------- scratch files

static char scratch_dir[4096];
static char scratch_file[4200];

// Removes the scratch directory and what the harnesses put in it (only plain
// files, one level). Runs at a normal exit; a crash leaves it behind, which is
// why scripts/fuzz.sh points BK_FUZZ_TMP into its own scratch tree.
static void remove_scratch(void) {
  if (!scratch_dir[0]) return;
  DIR* dir = opendir(scratch_dir);
  if (dir) {
    char path[4400];
    for (struct dirent* e = readdir(dir); e; e = readdir(dir)) {
      if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
      snprintf(path, sizeof path, "%s/%s", scratch_dir, e->d_name);
      unlink(path);
    }
    closedir(dir);
  }
  rmdir(scratch_dir);
  scratch_dir[0] = 0;
}

const char* bk_fuzz_scratch_path(const char* name) {
  if (!scratch_dir[0]) {
    const char* base = getenv("BK_FUZZ_TMP");
    if (!base || !*base) base = getenv("TMPDIR");
    if (!base || !*base) base = "/tmp";
    snprintf(scratch_dir, sizeof scratch_dir, "%s/bk-fuzz-XXXXXX", base);
    if (!mkdtemp(scratch_dir)) {
      scratch_dir[0] = 0;
      bk_fuzz_fail("cannot create a scratch directory under %s", base);
    }
    atexit(remove_scratch);
  }
  snprintf(scratch_file, sizeof scratch_file, "%s/%s", scratch_dir, name);
  return scratch_file;
}

const char* bk_fuzz_write_scratch(const char* name, const uint8_t* data, size_t size) {
  const char* path = bk_fuzz_scratch_path(name);
  FILE* f = fopen(path, "wb");
  if (!f) bk_fuzz_fail("cannot create scratch file %s", path);
  bool ok = fwrite(data, 1, size, f) == size;
  ok = fclose(f) == 0 && ok;
  if (!ok) bk_fuzz_fail("cannot write scratch file %s", path);
  return path;
}

uint8_t* bk_fuzz_read_file(const char* path, size_t* size) {
  *size = 0;
  FILE* f = fopen(path, "rb");
  if (!f) return NULL;
  size_t length = 0, capacity = 4096;
  uint8_t* data = bk_alloc(capacity);
  for (;;) {
    if (length == capacity) {
      capacity *= 2;
      data = bk_realloc(data, capacity);
    }
    size_t got = fread(data + length, 1, capacity - length, f);
    length += got;
    if (got == 0) break;
  }
  bool ok = !ferror(f);
  fclose(f);
  if (!ok) {
    free(data);
    return NULL;
  }
  *size = length;
  return data;
}

// ---------------------------------------------------------------- .mtree header

enum { MTREE_HEADER_BYTES = 32, MTREE_SIZE_OFFSET = 16, MTREE_CHECKSUM_OFFSET = 24 };

static void store_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

bool bk_fuzz_fix_mtree_header(uint8_t* data, size_t size) {
  if (size < MTREE_HEADER_BYTES) return false;
  size_t payload = size - MTREE_HEADER_BYTES;
  store_u64(data + MTREE_SIZE_OFFSET, (uint64_t)payload);
  store_u64(data + MTREE_CHECKSUM_OFFSET, bk_hash_bytes(BK_FNV_OFFSET, data + MTREE_HEADER_BYTES, payload));
  return true;
}

// ---------------------------------------------------------------- checks

void bk_fuzz_check_bonds(const bk_mesh_tree* tree, const char* what) {
  bk_index_map pairs = {0};
  bk_index_map_init(&pairs, tree->bond_count);
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const bk_bond* b = &tree->bonds[i];
    if (!(b->leaf_a < b->leaf_b && b->leaf_b < tree->leaf_count))
      bk_fuzz_fail("%s: bond %u joins leaves %u and %u of %u", what, i, b->leaf_a, b->leaf_b,
                   tree->leaf_count);
    if (!(isfinite(b->area) && b->area > 0.0))
      bk_fuzz_fail("%s: bond %u (leaves %u, %u) has area %g", what, i, b->leaf_a, b->leaf_b, b->area);
    if (!bk_v3_is_finite(b->centroid))
      bk_fuzz_fail("%s: bond %u (leaves %u, %u) has a non-finite centroid", what, i, b->leaf_a, b->leaf_b);
    // Normals come from unit plane normals; 1e-9 leaves room for rounding only.
    double length = bk_v3_length(b->normal);
    if (!(fabs(length - 1.0) <= 1e-9))
      bk_fuzz_fail("%s: bond %u (leaves %u, %u) has a normal of length %.17g", what, i, b->leaf_a, b->leaf_b,
                   length);
    bool inserted = false;
    bk_index_map_insert(&pairs, bk_edge_key(b->leaf_a, b->leaf_b), i, &inserted);
    if (!inserted) bk_fuzz_fail("%s: leaves %u and %u have two bonds", what, b->leaf_a, b->leaf_b);
  }
  bk_index_map_free(&pairs);
  // What the library makes, the runtime and the cache file must take.
  bk_error err = {{0}};
  if (!bk_mesh_tree_validate(tree, &err))
    bk_fuzz_fail("%s: bk_mesh_tree_validate refuses it: %s", what, err.message);
}
