// The materials a glTF export carries: an imported model's own (names,
// colours, textures), or one of the game's materials with its textures.
// Texture files are read here and written into the export, so the .glb or
// .gltf stands alone wherever it is copied.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"

/// Texture files larger than this are left out of an export.
#define EXPORT_MAX_TEXTURE_BYTES ((size_t)256 << 20)

static void reserve(app_export_materials* m, uint32_t count) {
  m->list = bk_calloc(count, sizeof(bk_gltf_material));
  m->names = bk_calloc(count, sizeof *m->names);
  m->files = bk_calloc(2u * count, sizeof(void*));
  m->count = count;
}

// Reads a texture file into the export: PNG and JPEG (glTF's image formats)
// as they are, TGA, BMP and GIF converted to PNG; a file that cannot be read
// or is none of these is left out with a warning.
static void read_texture(app_export_materials* m, uint32_t slot, const char* path, const char* material,
                         const char* spec, bk_gltf_image* out) {
  void* data = NULL;
  size_t size = 0;
  bk_error err = {0};
  if (!bk_file_read(path, EXPORT_MAX_TEXTURE_BYTES, "256 MiB", &data, &size, &err)) {
    app_warning("%s: material '%s': %s; exported without its texture", spec, material, err.message);
    m->textures_left_out++;
    return;
  }
  if (!bk_image_format(data, size)) {
    // TGA, BMP and GIF become PNG; anything else is left out.
    uint8_t* png = NULL;
    size_t png_size = 0;
    bool converted = bk_image_convert_to_png(data, size, &png, &png_size);
    free(data);
    if (!converted) {
      app_warning("%s: material '%s': texture %s is not PNG or JPEG (glTF's image formats) nor TGA, BMP "
                  "or GIF (converted to PNG); exported without it",
                  spec, material, path);
      m->textures_left_out++;
      return;
    }
    data = png, size = png_size;
  }
  m->files[slot] = data;
  *out = (bk_gltf_image){.data = data, .size = size};
}

void app_export_materials_from_import(const bk_import_info* info, const char* spec, app_export_materials* m) {
  memset(m, 0, sizeof *m);
  uint32_t count = info && info->materials ? info->materials : 1;
  reserve(m, count);
  for (uint32_t i = 0; i < count; ++i) {
    const bk_import_material* in = info && info->material_list ? &info->material_list[i] : NULL;
    bk_gltf_material* out = &m->list[i];
    *out = bk_default_gltf_material();
    // Unnamed materials and repeated names get their index, so each
    // exported material can be told apart and swapped in the engine.
    bool repeated = false;
    for (uint32_t j = 0; in && j < i; ++j)
      repeated |= in->name[0] && strcmp(info->material_list[j].name, in->name) == 0;
    if (in && in->name[0] && !repeated)
      snprintf(m->names[i], sizeof m->names[i], "%.63s", in->name);
    else if (in && in->name[0])
      snprintf(m->names[i], sizeof m->names[i], "%.50s_%u", in->name, i);
    else if (i == 0)
      snprintf(m->names[i], sizeof m->names[i], "surface");
    else
      snprintf(m->names[i], sizeof m->names[i], "material_%u", i);
    out->name = m->names[i];
    if (!in) continue;
    memcpy(out->base_color, in->base_color, sizeof out->base_color);
    if (in->image) { // copied: the import info may be released before the export
      m->files[2 * i] = bk_alloc(in->image_size);
      memcpy(m->files[2 * i], in->image, in->image_size);
      out->texture = (bk_gltf_image){.data = m->files[2 * i], .size = in->image_size};
    } else if (in->texture[0])
      read_texture(m, 2 * i, in->texture, out->name, spec, &out->texture);
    else if (in->image_unsupported) {
      app_warning("%s: material '%s': its embedded texture is neither PNG nor JPEG; exported without it",
                  spec, out->name);
      m->textures_left_out++;
    }
  }
}

void app_export_materials_from_look(const char* look, app_export_materials* m) {
  memset(m, 0, sizeof *m);
  reserve(m, 1);
  bk_gltf_material* out = &m->list[0];
  *out = bk_default_gltf_material();
  snprintf(m->names[0], sizeof m->names[0], "%.63s", look);
  out->name = m->names[0];
  char path[4200];
  snprintf(path, sizeof path, "%s/textures/%s_albedo.png", app_asset_dir(), look);
  read_texture(m, 0, path, look, "export", &out->texture);
  snprintf(path, sizeof path, "%s/textures/%s_interior.png", app_asset_dir(), look);
  read_texture(m, 1, path, look, "export", &out->interior_texture);
}

void app_export_materials_free(app_export_materials* m) {
  for (uint32_t i = 0; i < 2u * m->count && m->files; ++i)
    free(m->files[i]);
  free(m->files);
  free(m->names);
  free(m->list);
  memset(m, 0, sizeof *m);
}
