// Mesh trees for the game and the simulator come from a cache directory, so
// the next start with the same mesh and parameters skips fracturing.
#include <errno.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "app.h"
#include "scene_run.h"

// Every message about a cache file names it, and a bk_error holds 512 bytes:
// paths up to this length leave room for the words and the reason around
// them, so no message is cut. No real cache directory comes near it.
enum { CACHE_PATH_MAX = sizeof(((bk_error*)0)->message) - 160 };

// Where the cache file of one tree lives, and where that came from.
typedef struct cache_location {
  char dir[CACHE_PATH_MAX + 1];
  char path[CACHE_PATH_MAX + 1];
  const char* source; ///< the variable the directory came from, for messages
} cache_location;

// Forms the directory and the file's path; false when either would be longer
// than CACHE_PATH_MAX (*needed gets the length it would have).
static bool cache_location_form(cache_location* at, const char* mesh_spec, uint64_t hash,
                                const bk_fracture_def* desc, size_t* needed) {
  const char* explicit_dir = getenv("BREAKABLES_CACHE_DIR");
  const char* xdg = getenv("XDG_CACHE_HOME");
  const char* home = getenv("HOME");
  int length = 0;
  if (explicit_dir && *explicit_dir) {
    at->source = "$BREAKABLES_CACHE_DIR";
    length = snprintf(at->dir, sizeof at->dir, "%s", explicit_dir);
  } else if (xdg && *xdg) {
    at->source = "$XDG_CACHE_HOME";
    length = snprintf(at->dir, sizeof at->dir, "%s/breakables", xdg);
  } else if (home && *home) {
    at->source = "$HOME";
    length = snprintf(at->dir, sizeof at->dir, "%s/.cache/breakables", home);
  } else {
    at->source = "the default";
    length = snprintf(at->dir, sizeof at->dir, "/tmp/breakables-cache");
  }
  const char* base = strrchr(mesh_spec, '/');
  base = base ? base + 1 : mesh_spec;
  // The key tells every parameter apart; the pattern, pieces and seed are
  // spelled out too, for whoever looks into the directory.
  int path_length =
      snprintf(at->path, sizeof at->path, "%s/%.64s-%016llx-%s-%u-%llu-%016llx.mtree", at->dir, base,
               (unsigned long long)hash, bk_fracture_pattern_name(desc->pattern), desc->pieces,
               (unsigned long long)desc->seed, (unsigned long long)app_fracture_key(desc));
  if (length < 0 || path_length < 0) {
    *needed = SIZE_MAX;
    return false;
  }
  // at->dir holds the directory's first CACHE_PATH_MAX bytes; the file's name follows it.
  *needed = (size_t)path_length - strlen(at->dir) + (size_t)length;
  return *needed <= CACHE_PATH_MAX;
}

// Creates the directory and its parents; false with *code = errno and the
// failing prefix in `failed` (the same size as `path`'s buffer).
static bool make_directories(const char* path, char* failed, size_t failed_size, int* code) {
  snprintf(failed, failed_size, "%s", path); // path is at most CACHE_PATH_MAX: it fits
  for (char* p = failed + 1;; ++p) {
    if (*p != '/' && *p != 0) continue;
    char kept = *p;
    *p = 0;
    if (mkdir(failed, 0755) != 0 && errno != EEXIST) {
      *code = errno;
      return false;
    }
    if (kept == 0) return true;
    *p = kept;
  }
}

// FNV-1a, 64 bits, over the bytes of each value in turn.
static void key_bytes(uint64_t* key, const void* bytes, size_t size) {
  const uint8_t* p = bytes;
  for (size_t i = 0; i < size; ++i)
    *key = (*key ^ p[i]) * 0x100000001b3ull;
}
static void key_u64(uint64_t* key, uint64_t value) { key_bytes(key, &value, sizeof value); }
static void key_f64(uint64_t* key, double value) {
  value = value == 0.0 ? 0.0 : value; // -0 asks for what 0 asks for
  key_bytes(key, &value, sizeof value);
}
static void key_vec3(uint64_t* key, bk_vec3 v) {
  key_f64(key, v.x);
  key_f64(key, v.y);
  key_f64(key, v.z);
}

// The key of the parameters a tree's file keeps (bk_mesh_tree.desc): every
// scalar of the def, counts of the borrowed arrays but not their contents.
static uint64_t stored_key(const bk_fracture_def* d) {
  uint64_t key = 0xcbf29ce484222325ull;
  // A fracture map's regions or the caller's seed points fix the count of a
  // cell pattern's pieces, and the tree's desc then holds the count made, not
  // the one asked for: neither tells trees apart.
  bool cells = d->pattern != BK_PATTERN_PLANES && d->pattern != BK_PATTERN_BRICK;
  bool counted = d->pattern == BK_PATTERN_CUTOUT || (cells && d->seed_point_count > 0);
  key_u64(&key, counted ? 0 : d->pieces);
  key_u64(&key, d->seed);
  key_f64(&key, d->texture_scale);
  key_f64(&key, d->jitter);
  key_f64(&key, d->aspect_bias);
  key_u64(&key, (uint64_t)d->pattern);
  key_u64(&key, d->seed_point_count);
  key_u64(&key, d->clusters);
  key_f64(&key, d->cluster_border);
  key_vec3(&key, d->impact);
  key_f64(&key, d->radial_falloff);
  key_vec3(&key, d->brick_size);
  key_vec3(&key, d->brick_origin);
  key_f64(&key, d->brick_offset);
  key_u64(&key, d->cutout_width);
  key_u64(&key, d->cutout_height);
  key_u64(&key, d->cutout_axis);
  key_f64(&key, d->noise_amplitude);
  key_f64(&key, d->noise_frequency);
  return key;
}

uint64_t app_fracture_key(const bk_fracture_def* d) {
  uint64_t key = stored_key(d);
  key_u64(&key, BK_FRACTURE_GENERATION); // trees of an older build are made again
  // The arrays' contents are not in the file: only the name tells them apart.
  for (uint32_t i = 0; d->seed_points && i < d->seed_point_count; ++i)
    key_vec3(&key, d->seed_points[i]);
  if (d->cutout_pixels) key_bytes(&key, d->cutout_pixels, (size_t)d->cutout_width * d->cutout_height);
  return key;
}

static bool same_parameters(const bk_mesh_tree* tree, uint64_t hash, const bk_fracture_def* d) {
  return tree->source_hash == hash && stored_key(&tree->desc) == stored_key(d);
}

// A scene fractures several objects: say once, not once per object.
static atomic_flag warned_path_too_long = ATOMIC_FLAG_INIT;

bool app_load_tree(const char* mesh_spec, double scale, const bk_fracture_def* desc, bk_mesh_tree* out,
                   bool* from_cache, bk_error* err) {
  *from_cache = false;
  // A tree made earlier (fracture --out) is used as it is: no fracture, its
  // own pieces, leaves and bonds.
  size_t spec_length = strlen(mesh_spec);
  if (spec_length > 6 && strcmp(mesh_spec + spec_length - 6, ".mtree") == 0)
    return bk_mesh_tree_load(mesh_spec, out, err);
  // So is one exported by fracture --export-gltf; any other glTF is a model
  // to fracture.
  bool gltf = (spec_length > 4 && strcmp(mesh_spec + spec_length - 4, ".glb") == 0) ||
              (spec_length > 5 && strcmp(mesh_spec + spec_length - 5, ".gltf") == 0);
  if (gltf) {
    bk_error gltf_err = {{0}};
    if (bk_mesh_tree_load_gltf(mesh_spec, out, &gltf_err)) return true;
    if (!strstr(gltf_err.message, "not a Breakables export"))
      return bk_error_set(err, "%s", gltf_err.message);
  }
  bk_mesh source = {0};
  if (!app_load_mesh(mesh_spec, &source, err)) return false;
  if (scale > 0.0 && scale != 1.0)
    for (uint32_t i = 0; i < source.position_count; ++i)
      source.positions[i] = bk_v3_scale(source.positions[i], scale);
  uint64_t hash = bk_mesh_hash(&source);
  cache_location at = {{0}};
  size_t needed = 0;
  bool cached = cache_location_form(&at, mesh_spec, hash, desc, &needed);
  if (!cached && !atomic_flag_test_and_set(&warned_path_too_long))
    fprintf(stderr,
            "breakables: warning: not caching mesh trees: the cache file's path from %s would be %zu bytes "
            "long, more than %d (set BREAKABLES_CACHE_DIR to a shorter directory)\n",
            at.source, needed, (int)CACHE_PATH_MAX);

  // Only an existing file is worth a warning when it cannot be loaded.
  struct stat st = {0};
  if (cached && stat(at.path, &st) == 0) {
    bk_error load_err = {{0}};
    if (bk_mesh_tree_load(at.path, out, &load_err)) {
      if (same_parameters(out, hash, desc)) {
        bk_mesh_free(&source);
        *from_cache = true;
        return true;
      }
      bk_mesh_tree_free(out);
    } else {
      fprintf(stderr, "breakables: warning: ignoring cache file: %s\n", load_err.message);
    }
  }
  if (!app_check_fracture_memory(mesh_spec, &source, desc, cached, err)) {
    bk_mesh_free(&source);
    return false;
  }
  bool built = bk_mesh_tree_build(&source, desc, out, err);
  bk_mesh_free(&source);
  char shortfall[400];
  if (built && bk_mesh_tree_shortfall_text(out, shortfall, sizeof shortfall))
    fprintf(stderr, "breakables: warning: %s: %s\n", mesh_spec, shortfall);
  if (built && bk_mesh_tree_overlap_text(out, shortfall, sizeof shortfall))
    fprintf(stderr, "breakables: warning: %s: %s\n", mesh_spec, shortfall);
  if (!built || !cached) return built;
  bk_error save_err = {{0}};
  char failed[sizeof at.dir] = {0};
  int code = 0;
  if (!make_directories(at.dir, failed, sizeof failed, &code))
    fprintf(stderr, "breakables: warning: not caching the mesh tree: cannot create directory %s: %s\n",
            failed, strerror(code));
  else if (!bk_mesh_tree_save(out, at.path, &save_err))
    fprintf(stderr, "breakables: warning: not caching the mesh tree: %s\n", save_err.message);
  return true;
}
