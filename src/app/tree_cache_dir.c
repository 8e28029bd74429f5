// Mesh trees for the game and the simulator come from a cache directory, so
// the next start with the same mesh and parameters skips fracturing.
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "app.h"

static void cache_directory(char* out, size_t size) {
  const char* explicit_dir = getenv("BREAKABLES_CACHE_DIR");
  const char* xdg = getenv("XDG_CACHE_HOME");
  const char* home = getenv("HOME");
  if (explicit_dir && *explicit_dir)
    snprintf(out, size, "%s", explicit_dir);
  else if (xdg && *xdg)
    snprintf(out, size, "%s/breakables", xdg);
  else if (home && *home)
    snprintf(out, size, "%s/.cache/breakables", home);
  else
    snprintf(out, size, "/tmp/breakables-cache");
}

static bool make_directories(const char* path) {
  char buffer[4096];
  snprintf(buffer, sizeof buffer, "%s", path);
  for (char* p = buffer + 1; *p; ++p) {
    if (*p != '/') continue;
    *p = 0;
    if (mkdir(buffer, 0755) != 0 && errno != EEXIST) return false;
    *p = '/';
  }
  return mkdir(buffer, 0755) == 0 || errno == EEXIST;
}

static bool same_parameters(const bk_mesh_tree* tree, uint64_t hash, const bk_fracture_desc* d) {
  return tree->source_hash == hash && tree->desc.pieces == d->pieces && tree->desc.seed == d->seed &&
         tree->desc.texture_scale == d->texture_scale && tree->desc.jitter == d->jitter &&
         tree->desc.aspect_bias == d->aspect_bias;
}

bool bk_app_load_tree(const char* mesh_spec, double scale, const bk_fracture_desc* desc, bk_mesh_tree* out,
                      bool* from_cache, bk_error* err) {
  *from_cache = false;
  bk_mesh source = {0};
  if (!bk_app_load_mesh(mesh_spec, &source, err)) return false;
  if (scale > 0.0 && scale != 1.0)
    for (uint32_t i = 0; i < source.position_count; ++i)
      source.positions[i] = bk_v3_scale(source.positions[i], scale);
  uint64_t hash = bk_mesh_hash(&source);
  char dir[4096], path[4400];
  cache_directory(dir, sizeof dir);
  const char* base = strrchr(mesh_spec, '/');
  base = base ? base + 1 : mesh_spec;
  snprintf(path, sizeof path, "%s/%.64s-%016llx-%u-%llu.mtree", dir, base, (unsigned long long)hash,
           desc->pieces, (unsigned long long)desc->seed);
  bk_error load_err = {0};
  if (bk_mesh_tree_load(path, out, &load_err)) {
    if (same_parameters(out, hash, desc)) {
      bk_mesh_free(&source);
      *from_cache = true;
      return true;
    }
    bk_mesh_tree_free(out);
  } else if (!strstr(load_err.message, "cannot open")) {
    fprintf(stderr, "breakables: warning: ignoring cache file: %s\n", load_err.message);
  }
  bool built = bk_mesh_tree_build(&source, desc, out, err);
  bk_mesh_free(&source);
  if (!built) return false;
  bk_error save_err = {0};
  if (!make_directories(dir) || !bk_mesh_tree_save(out, path, &save_err))
    fprintf(stderr, "breakables: warning: cannot cache the mesh tree in %s: %s\n", dir,
            save_err.message[0] ? save_err.message : strerror(errno));
  return true;
}
