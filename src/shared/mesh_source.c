// Where fracture input comes from: built-in shapes, the bundled bunny, or a
// model file given by path (OBJ by our reader, glTF, FBX, PLY, STL... by assimp).
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "app.h"

// Why `spec` is neither a shape nor a model file: a file that is there is
// named for what it is, anything else is taken for a misspelt shape name.
static bool unsupported(const char* spec, bk_error* err) {
  struct stat st = {0};
  if (stat(spec, &st) != 0)
    return bk_error_set(
        err,
        "unknown mesh '%s': use cube, torus, eggshell, bunny, wall, slab, pillar, tower, bridge, "
        "balcony or a model file (%s)",
        spec, BK_IMPORT_EXTENSIONS);
  if (S_ISDIR(st.st_mode)) return bk_error_set(err, "%s: is a directory", spec);
  if (!S_ISREG(st.st_mode)) return bk_error_set(err, "%s: is not a regular file", spec);
  char known[256] = "";
  size_t used = 0;
  for (const char* p = BK_IMPORT_EXTENSIONS; *p && used + 3 < sizeof known; ++p)
    used += (size_t)snprintf(known + used, sizeof known - used, *p == ' ' ? ", " : "%c", *p);
  const char* slash = strrchr(spec, '/');
  const char* dot = strrchr(slash ? slash + 1 : spec, '.');
  char format[40] = "no extension";
  if (dot && dot[1]) snprintf(format, sizeof format, "%.30s", dot);
  return bk_error_set(err, "%s: unsupported model format (%s); known: %s", spec, format, known);
}

// What the last model loaded on this thread was repaired of (zeroed for a
// built-in shape), for the reports that list their warnings.
static _Thread_local bk_repair_info last_repair;

const bk_repair_info* app_last_repair(void) { return &last_repair; }

// Appends "; " (after the first) and a formatted note to out.
static void append_note(char* out, size_t size, size_t* used, const char* format, ...) {
  if (*used + 1 >= size) return;
  if (*used) *used += (size_t)snprintf(out + *used, size - *used, "; ");
  if (*used + 1 >= size) return;
  va_list args;
  va_start(args, format);
  int n = vsnprintf(out + *used, size - *used, format, args);
  va_end(args);
  *used += n > 0 ? (size_t)n : 0;
  if (*used >= size) *used = size - 1;
}

static const char* plural(uint32_t n) { return n == 1 ? "" : "s"; }

size_t app_repair_text(const bk_repair_info* r, char* out, size_t size) {
  size_t used = 0;
  if (size == 0) return 0;
  out[0] = 0;
  if (r->duplicates_removed)
    append_note(out, size, &used, "removed %u triangle%s given twice", r->duplicates_removed,
                plural(r->duplicates_removed));
  if (r->faces_turned)
    append_note(out, size, &used, "turned %u triangle%s wound against their neighbours", r->faces_turned,
                plural(r->faces_turned));
  if (r->positions_split)
    append_note(out, size, &used, "split %u position%s where shells touched", r->positions_split,
                plural(r->positions_split));
  if (r->holes_closed)
    append_note(out, size, &used, "closed %u hole%s (%u open edges)", r->holes_closed,
                plural(r->holes_closed), r->open_edges);
  if (r->sheets_removed)
    append_note(out, size, &used, "removed %u shell%s enclosing no volume (the first near (%g, %g, %g))",
                r->sheets_removed, plural(r->sheets_removed), r->sheet_near.x, r->sheet_near.y,
                r->sheet_near.z);
  return used;
}

bool app_load_mesh(const char* spec, bk_mesh* out, bk_error* err) {
  return app_load_model(spec, NULL, out, NULL, err);
}

bool app_load_model(const char* spec, const char* node, bk_mesh* out, bk_import_info* info_out,
                    bk_error* err) {
  bk_shape shape = BK_SHAPE_CUBE;
  memset(&last_repair, 0, sizeof last_repair);
  if (bk_shape_from_name(spec, &shape)) {
    if (node) return bk_error_set(err, "--node needs a model file, not the built-in '%s'", spec);
    bk_shape_build(shape, out);
    return true;
  }
  bool bunny = strcmp(spec, "bunny") == 0;
  char path[4096];
  if (bunny) {
    snprintf(path, sizeof path, "%s/meshes/bunny.obj", app_asset_dir());
  } else {
    if (!bk_model_import_supports(spec)) return unsupported(spec, err);
    snprintf(path, sizeof path, "%s", spec);
  }
  // .obj goes to our own reader, every other format to assimp (bk_model_import).
  bk_import_def def = bk_default_import_def();
  def.node = node;
  bk_import_info info = {0};
  if (!bk_model_import(path, &def, out, &info, err)) return false;
  if (bunny)
    bk_mesh_fit_unit_height(out);
  else
    app_apply_model_units(path, out, &info);
  if (info.note[0]) app_warning("%s: %s", path, info.note); // the note may quote the file
  if (info.flipped)
    fprintf(stderr, "breakables: warning: %s: mesh was inside out; its winding was reversed\n", path);
  bk_repair_info repair = {0};
  bk_error repair_err = {0};
  if (!bk_mesh_repair(out, &repair, &repair_err)) {
    bk_mesh_free(out);
    bk_import_info_free(&info);
    return bk_error_set(err, "%s: %s", path, repair_err.message);
  }
  if (repair.faces_turned)
    fprintf(stderr, "breakables: warning: %s: %u triangle%s wound against %s neighbours; turned\n", path,
            repair.faces_turned, repair.faces_turned == 1 ? " was" : "s were",
            repair.faces_turned == 1 ? "its" : "their");
  if (repair.positions_split)
    fprintf(stderr,
            "breakables: warning: %s: shells touched at a vertex, an edge or a face; split %u position%s (%u "
            "shell%s)\n",
            path, repair.positions_split, repair.positions_split == 1 ? "" : "s", repair.shells,
            repair.shells == 1 ? "" : "s");
  if (repair.holes_closed)
    fprintf(stderr, "breakables: warning: %s: mesh was not watertight; closed %u hole%s (%u open edges)\n",
            path, repair.holes_closed, repair.holes_closed == 1 ? "" : "s", repair.open_edges);
  if (repair.duplicates_removed)
    fprintf(stderr, "breakables: warning: %s: %u triangle%s given twice; removed\n", path,
            repair.duplicates_removed, repair.duplicates_removed == 1 ? " was" : "s were");
  if (repair.sheets_removed)
    fprintf(stderr,
            "breakables: warning: %s: %u shell%s enclosed no volume (a face closed against its own back, the "
            "first near (%g, %g, %g)); removed\n",
            path, repair.sheets_removed, repair.sheets_removed == 1 ? "" : "s", repair.sheet_near.x,
            repair.sheet_near.y, repair.sheet_near.z);
  last_repair = repair;
  if (info_out)
    *info_out = info; // the caller releases it (bk_import_info_free)
  else
    bk_import_info_free(&info);
  return true;
}
