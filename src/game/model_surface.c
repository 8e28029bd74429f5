// A model's own surface, for drawing it as it is in `play`: the base-colour
// texture and colour of the material most of its triangles use. A model
// with neither of its own (untextured and white or neutral grey: an STL, a
// 3DS "Default" material) is drawn in the chosen material's look.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "model_surface.h"

/// Texture files larger than this are drawn without.
#define SURFACE_MAX_TEXTURE_BYTES ((size_t)256 << 20)

// Reads a material's texture file; a path written with backslashes (an
// export from Windows: ".\\wood.jpg") is tried with slashes too.
static bool read_texture(const char* texture, void** data, size_t* size) {
  bk_error err = {0};
  if (bk_file_read(texture, SURFACE_MAX_TEXTURE_BYTES, "256 MiB", data, size, &err)) return true;
  char path[BK_IMPORT_TEXT_MAX];
  snprintf(path, sizeof path, "%s", texture);
  bool changed = false;
  for (char* c = path; *c; ++c)
    if (*c == '\\') *c = '/', changed = true;
  return changed && bk_file_read(path, SURFACE_MAX_TEXTURE_BYTES, "256 MiB", data, size, &err);
}

bool app_read_model_surface(const char* path, app_model_surface* out) {
  memset(out, 0, sizeof *out);
  if (!bk_model_import_supports(path)) return false;
  bk_mesh mesh = {0};
  bk_import_info info = {0};
  bk_error err = {0};
  if (!bk_model_import(path, NULL, &mesh, &info, &err)) return false; // the scene's load said why
  bk_mesh_free(&mesh);
  // The material of the most triangles whose texture can be read, else the
  // one of the most triangles with its colour alone.
  const bk_import_material* chosen = NULL;
  uint32_t missing = 0;
  bool* tried = bk_calloc(info.materials + 1u, sizeof(bool));
  while (!out->image) {
    uint32_t best = UINT32_MAX;
    for (uint32_t i = 0; i < info.materials; ++i) {
      const bk_import_material* m = &info.material_list[i];
      if (!tried[i] && (m->image || m->texture[0]) &&
          (best == UINT32_MAX || m->triangles > info.material_list[best].triangles))
        best = i;
    }
    if (best == UINT32_MAX) break;
    tried[best] = true;
    const bk_import_material* m = &info.material_list[best];
    if (m->image) {
      out->image = bk_alloc(m->image_size);
      memcpy(out->image, m->image, m->image_size);
      out->image_size = m->image_size;
    } else if (!read_texture(m->texture, &out->image, &out->image_size)) {
      missing++;
    }
    if (out->image) chosen = m;
  }
  free(tried);
  if (!chosen && info.material_list && info.dominant_material < info.materials)
    chosen = &info.material_list[info.dominant_material];
  if (chosen) memcpy(out->color, chosen->base_color, sizeof out->color);
  if (missing && !out->image)
    fprintf(stderr,
            "breakables: warning: %s: drawn without a texture: none of its %u texture file%s can be read\n",
            path, missing, missing == 1 ? "" : "s");
  bk_import_info_free(&info);
  // A neutral grey or white without a texture is a format's default
  // material (3DS's "Default" is 0.78 grey), not a look of the model's own:
  // such a model is drawn in the chosen material's look.
  float lo = fminf(out->color[0], fminf(out->color[1], out->color[2]));
  float hi = fmaxf(out->color[0], fmaxf(out->color[1], out->color[2]));
  bool coloured = chosen && hi - lo > 0.02f;
  return out->image != NULL || coloured;
}

void app_model_surface_free(app_model_surface* surface) {
  free(surface->image);
  memset(surface, 0, sizeof *surface);
}
