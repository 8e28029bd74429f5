// The materials of an imported model (bk_import_info.material_list): which
// source material id each scene material gets, and per material its name,
// base colour factor and base-colour texture (a path beside the model, or
// the bytes of an image embedded in it, ready to be written into a glTF).
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

// Only the PNG writer, with internal linkage: the library exports no stb symbol.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#define STBI_WRITE_NO_STDIO
#if defined(__GNUC__)
// stb declares writers it leaves undefined when static: checked at the end
// of the file, so this one stays off for the whole file.
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

// Copies text, cut to fit and with control characters (assimp's messages
// span lines) made blanks.
void bk_import_copy_text(char* dst, size_t size, const char* src, size_t length) {
  size_t n = length < size - 1 ? length : size - 1;
  for (size_t i = 0; i < n; ++i)
    dst[i] = (unsigned char)src[i] < 0x20 ? ' ' : src[i];
  dst[n] = '\0';
}

// ---------------------------------------------------------------- embedded images

typedef struct byte_buffer {
  uint8_t* data;
  size_t size, capacity;
} byte_buffer;

static void append_bytes(void* context, void* data, int size) {
  byte_buffer* b = context;
  if (size <= 0) return;
  if (b->size + (size_t)size > b->capacity) {
    b->capacity = (b->size + (size_t)size) * 2;
    b->data = bk_realloc(b->data, b->capacity);
  }
  memcpy(b->data + b->size, data, (size_t)size);
  b->size += (size_t)size;
}

const char* bk_image_format(const void* data, size_t size) {
  const uint8_t* p = data;
  if (size >= 8 && memcmp(p, "\x89PNG\r\n\x1a\n", 8) == 0) return "png";
  if (size >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF) return "jpeg";
  return NULL;
}

bool bk_png_encode_rgba(const uint8_t* rgba, uint32_t width, uint32_t height, uint8_t** out, size_t* size) {
  *out = NULL, *size = 0;
  if (width == 0 || height == 0 || width > (1u << 15) || height > (1u << 15)) return false;
  byte_buffer png = {0};
  int ok = stbi_write_png_to_func(append_bytes, &png, (int)width, (int)height, 4, rgba, (int)width * 4);
  if (!ok || !png.size) {
    bk_free(png.data);
    return false;
  }
  *out = png.data, *size = png.size;
  return true;
}

// ---------------------------------------------------------------- the list

// Counts each material's triangles and finds the one of the most.
void bk_import_count_triangles(bk_import_info* info, const bk_mesh* mesh) {
  for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
    uint32_t source = bk_material_source(mesh->materials[t]);
    if (source < info->materials) info->material_list[source].triangles++;
  }
  info->dominant_material = 0;
  for (uint32_t i = 1; i < info->materials; ++i)
    if (info->material_list[i].triangles > info->material_list[info->dominant_material].triangles)
      info->dominant_material = i;
}

void bk_import_single_material(bk_import_info* info, const bk_mesh* mesh) {
  info->materials = 1;
  info->material_list = bk_calloc(1, sizeof(bk_import_material));
  for (int i = 0; i < 4; ++i)
    info->material_list[0].base_color[i] = 1.0f;
  bk_import_count_triangles(info, mesh);
}

// The material list is the caller's only when the import succeeded (and
// the caller asked for the info).
bool bk_import_settle_info(bool ok, bk_import_info* info, bool keep) {
  if (!ok || !keep) {
    for (uint32_t i = 0; i < info->materials && info->material_list; ++i)
      bk_free(info->material_list[i].image);
    bk_free(info->material_list);
    info->material_list = NULL;
    info->materials = 0;
  }
  return ok;
}

void bk_import_info_free(bk_import_info* info) {
  if (!info) return;
  bk_import_settle_info(false, info, false);
  memset(info, 0, sizeof *info);
}
