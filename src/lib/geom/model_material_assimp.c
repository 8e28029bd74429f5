// The materials of a scene assimp read (bk_import_info.material_list): which
// source material id each scene material gets, and per material its name,
// base colour factor and base-colour texture (a path beside the model, or
// the bytes of an image embedded in it, kept as glTF can hold it).
#include <assimp/material.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

/// Embedded images larger than this are not kept (a 16k x 16k RGBA texture).
#define IMPORT_MAX_IMAGE_BYTES ((size_t)1 << 30)

uint32_t bk_import_material_source(import_state* s, uint32_t index) {
  uint32_t slot = index < s->scene->mNumMaterials ? index : s->scene->mNumMaterials;
  if (s->source_of_material[slot] == UINT32_MAX) {
    if (s->source_count < BK_MATERIAL_SOURCES_MAX) {
      s->scene_material_of_source[s->source_count] = slot;
      s->source_of_material[slot] = s->source_count++;
    } else {
      s->source_of_material[slot] = 0;
      s->info->materials_merged++;
    }
  }
  return s->source_of_material[slot];
}

// Keeps an embedded texture as glTF can hold it: PNG and JPEG files as they
// are (told by their bytes, not the file's format hint), TGA, BMP and GIF
// files and uncompressed texels encoded as PNG; any other format is only noted.
static void keep_image(bk_import_material* out, const struct aiTexture* t) {
  if (!t->pcData || t->mWidth == 0) return;
  if (t->mHeight == 0) { // compressed: mWidth bytes of a file
    const uint8_t* bytes = (const uint8_t*)t->pcData;
    size_t size = t->mWidth;
    const char* format = bk_image_format(bytes, size);
    if (!format) { // a TGA, BMP or GIF file is converted; anything else only noted
      uint8_t* png = NULL;
      size_t png_size = 0;
      out->image_unsupported = !bk_image_convert_to_png(bytes, size, &png, &png_size);
      if (out->image_unsupported) return;
      out->image = png;
      out->image_size = png_size;
      snprintf(out->image_format, sizeof out->image_format, "png");
      return;
    }
    out->image = bk_alloc(size);
    memcpy(out->image, bytes, size);
    out->image_size = size;
    snprintf(out->image_format, sizeof out->image_format, "%s", format);
    return;
  }
  uint64_t texels = (uint64_t)t->mWidth * t->mHeight;
  if (t->mWidth > (1u << 15) || t->mHeight > (1u << 15) || texels * 4u > IMPORT_MAX_IMAGE_BYTES) {
    out->image_unsupported = true;
    return;
  }
  // aiTexel is b, g, r, a; PNG wants r, g, b, a.
  uint8_t* rgba = bk_alloc((size_t)texels * 4u);
  for (uint64_t i = 0; i < texels; ++i) {
    const struct aiTexel* x = &t->pcData[i];
    rgba[4 * i] = x->r, rgba[4 * i + 1] = x->g, rgba[4 * i + 2] = x->b, rgba[4 * i + 3] = x->a;
  }
  uint8_t* png = NULL;
  size_t png_size = 0;
  bool ok = bk_png_encode_rgba(rgba, t->mWidth, t->mHeight, &png, &png_size);
  bk_free(rgba);
  if (!ok) {
    out->image_unsupported = true;
    return;
  }
  out->image = png;
  out->image_size = png_size;
  snprintf(out->image_format, sizeof out->image_format, "png");
}

// ---------------------------------------------------------------- one material

// The texture of the material: embedded ("*<index>" or a file name the
// scene carries an image for) or a path relative to the model's directory.
static void read_texture(const import_state* s, const struct aiMaterial* mat, bk_import_material* out) {
  const enum aiTextureType types[2] = {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE};
  struct aiString path = {0};
  bool found = false;
  for (int i = 0; i < 2 && !found; ++i)
    found =
        aiGetMaterialTextureCount(mat, types[i]) > 0 &&
        aiGetMaterialTexture(mat, types[i], 0, &path, NULL, NULL, NULL, NULL, NULL, NULL) == aiReturn_SUCCESS;
  if (!found || path.length == 0 || path.length >= MAXLEN) return;
  const struct aiScene* sc = s->scene;
  const char* text = path.data;
  uint32_t embedded = UINT32_MAX;
  if (text[0] == '*') {
    char* end = NULL;
    unsigned long index = strtoul(text + 1, &end, 10);
    if (end != text + 1 && *end == '\0' && index < sc->mNumTextures) embedded = (uint32_t)index;
  } else {
    for (uint32_t i = 0; i < sc->mNumTextures && sc->mTextures; ++i)
      if (sc->mTextures[i] && strcmp(sc->mTextures[i]->mFilename.data, text) == 0) embedded = i;
  }
  if (embedded != UINT32_MAX && sc->mTextures && sc->mTextures[embedded]) {
    keep_image(out, sc->mTextures[embedded]);
    return;
  }
  if (text[0] == '*') return; // names an image the file does not have
  if (text[0] == '/' || !s->base_dir[0]) {
    bk_import_copy_text(out->texture, sizeof out->texture, text, path.length);
  } else {
    char joined[BK_IMPORT_TEXT_MAX * 2];
    int n = snprintf(joined, sizeof joined, "%s/%s", s->base_dir, text);
    if (n > 0) bk_import_copy_text(out->texture, sizeof out->texture, joined, (size_t)n);
  }
}

static void read_material(const import_state* s, const struct aiMaterial* mat, bk_import_material* out) {
  for (int i = 0; i < 4; ++i)
    out->base_color[i] = 1.0f;
  if (!mat) return;
  struct aiString name = {0};
  if (aiGetMaterialString(mat, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length < MAXLEN)
    bk_import_copy_text(out->name, sizeof out->name, name.data, name.length);
  struct aiColor4D color = {0};
  if (aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &color) == aiReturn_SUCCESS ||
      aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &color) == aiReturn_SUCCESS) {
    float rgba[4] = {color.r, color.g, color.b, color.a};
    bool valid = true;
    for (int i = 0; i < 4; ++i)
      valid &= isfinite(rgba[i]) && rgba[i] >= 0.0f;
    if (valid)
      for (int i = 0; i < 4; ++i)
        out->base_color[i] = rgba[i] < 1.0f ? rgba[i] : 1.0f;
  }
  read_texture(s, mat, out);
}

void bk_import_read_materials(import_state* s) {
  bk_import_info* info = s->info;
  uint32_t count = s->source_count ? s->source_count : 1;
  info->materials = count;
  info->material_list = bk_calloc(count, sizeof(bk_import_material));
  for (uint32_t i = 0; i < s->source_count; ++i) {
    uint32_t index = s->scene_material_of_source[i];
    const struct aiMaterial* mat =
        index < s->scene->mNumMaterials && s->scene->mMaterials ? s->scene->mMaterials[index] : NULL;
    read_material(s, mat, &info->material_list[i]);
  }
  if (!s->source_count) read_material(s, NULL, &info->material_list[0]);
  bk_import_count_triangles(info, &s->mesh);
}
