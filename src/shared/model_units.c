// The size a model file is taken at (--scale S, --units NAME): a format that
// states its unit (FBX, glTF, Collada) is read in metres by the import; the
// numbers of one that does not (OBJ, STL, PLY, ...) are metres unless
// --units says otherwise. --scale multiplies either. A model whose size then
// lies outside 1 cm..100 m is most likely in other units: one warning says so.
#include <stdio.h>
#include <string.h>

#include "app.h"

// One command line's choice, for every model file it loads (the scenes and
// caches pass model paths around, never their sizes).
static double model_scale = 1.0;
static double model_units = 1.0;
static const char* model_units_name = NULL;

static const struct {
  const char* name;
  double metres;
} unit_names[] = {{"mm", 0.001}, {"cm", 0.01}, {"m", 1.0}, {"in", 0.0254}};

int parse_model_units_option(const char* command, int argc, char** argv, int* i) {
  static const char* const names[] = {"--scale", "--units"};
  const char* arg = argv[*i];
  const char* value = NULL;
  int which = take_option(command, argc, argv, i, names, 2, &value);
  if (which < 0) return which == -1 ? 1 : 2;
  if (which == 0)
    return option_double(command, arg, value, BK_MODEL_SCALE_MIN, BK_MODEL_SCALE_MAX, &model_scale) ? 0 : 2;
  for (size_t k = 0; k < sizeof unit_names / sizeof *unit_names; ++k)
    if (strcmp(value, unit_names[k].name) == 0) {
      model_units = unit_names[k].metres;
      model_units_name = unit_names[k].name;
      return 0;
    }
  char shown[96] = "";
  quote_text(value, shown, sizeof shown);
  fprintf(stderr, "breakables %s: %s '%s' is not a unit (use mm, cm, m or in)\n", command, arg, shown);
  return 2;
}

void app_reset_model_units(void) {
  model_scale = 1.0;
  model_units = 1.0;
  model_units_name = NULL;
}

void app_model_units(double* scale, const char** units) {
  *scale = model_scale;
  *units = model_units_name;
}

bool app_model_size_note(const bk_mesh* mesh, char* out, size_t size) {
  bk_aabb box = bk_mesh_bounds(mesh);
  bk_vec3 d = bk_v3_sub(box.max, box.min);
  double across = fmax(d.x, fmax(d.y, d.z));
  if (!(across < BK_MODEL_SIZE_MIN || across > BK_MODEL_SIZE_MAX) || !isfinite(across)) return false;
  char length[32] = "";
  if (across < 0.01)
    snprintf(length, sizeof length, "%.3g mm", across * 1e3);
  else if (across >= 1e3)
    snprintf(length, sizeof length, "%.4g km", across * 1e-3);
  else
    snprintf(length, sizeof length, "%.4g m", across);
  snprintf(out, size,
           "the model is %s across, outside 1 cm..100 m: are its units %s? (--units mm|cm|m|in, --scale S)",
           length, across < BK_MODEL_SIZE_MIN ? "larger" : "smaller");
  return true;
}

void app_apply_model_units(const char* path, bk_mesh* mesh, const bk_import_info* info) {
  double factor = model_scale;
  if (model_units_name && info->units_given)
    fprintf(stderr, "breakables: warning: %s: the file gives its own unit of length; --units %s ignored\n",
            path, model_units_name);
  else
    factor *= model_units;
  if (factor != 1.0)
    for (uint32_t i = 0; i < mesh->position_count; ++i)
      mesh->positions[i] = bk_v3_scale(mesh->positions[i], factor);
  char note[200];
  if (app_model_size_note(mesh, note, sizeof note))
    fprintf(stderr, "breakables: warning: %s: %s\n", path, note);
}
