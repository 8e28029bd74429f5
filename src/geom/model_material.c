// The material an imported model reports (bk_import_info): name, base colour
// factor and base-colour texture (a path beside the model, or an image
// embedded in it) of the material covering the most triangles.
#include <assimp/material.h>
#include <assimp/scene.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

// Copies text, cut to fit and with control characters (assimp's messages
// span lines) made blanks.
void bk_import_copy_text(char* dst, size_t size, const char* src, size_t length) {
  size_t n = length < size - 1 ? length : size - 1;
  for (size_t i = 0; i < n; ++i)
    dst[i] = (unsigned char)src[i] < 0x20 ? ' ' : src[i];
  dst[n] = '\0';
}

// ---------------------------------------------------------------- material

// The texture of the material: embedded ("*<index>" or a file name the
// scene carries an image for) or a path relative to the model's directory.
static void read_texture(import_state* s, const struct aiMaterial* mat) {
  bk_import_info* info = s->info;
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
  if (embedded != UINT32_MAX && sc->mTextures[embedded]) {
    info->texture_embedded = true;
    info->embedded_index = embedded;
    const struct aiTexture* t = sc->mTextures[embedded];
    bk_import_copy_text(info->embedded_format, sizeof info->embedded_format, t->achFormatHint,
                        t->mHeight == 0 ? strnlen(t->achFormatHint, sizeof t->achFormatHint) : 0);
    return;
  }
  if (text[0] == '*') return; // names an image the file does not have
  if (text[0] == '/' || !s->base_dir[0]) {
    bk_import_copy_text(info->texture, sizeof info->texture, text, path.length);
  } else {
    char joined[BK_IMPORT_TEXT_MAX * 2];
    int n = snprintf(joined, sizeof joined, "%s/%s", s->base_dir, text);
    if (n > 0) bk_import_copy_text(info->texture, sizeof info->texture, joined, (size_t)n);
  }
}

// Reports the material of the most triangles: name, base colour, texture.
void bk_import_read_material(import_state* s) {
  const struct aiScene* sc = s->scene;
  bk_import_info* info = s->info;
  for (int i = 0; i < 4; ++i)
    info->base_color[i] = 1.0f;
  uint32_t best = UINT32_MAX;
  for (uint32_t i = 0; i < sc->mNumMaterials; ++i) {
    if (!s->material_triangles[i]) continue;
    info->materials++;
    if (best == UINT32_MAX || s->material_triangles[i] > s->material_triangles[best]) best = i;
  }
  if (best == UINT32_MAX || !sc->mMaterials || !sc->mMaterials[best]) return;
  const struct aiMaterial* mat = sc->mMaterials[best];
  struct aiString name = {0};
  if (aiGetMaterialString(mat, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length < MAXLEN)
    bk_import_copy_text(info->material, sizeof info->material, name.data, name.length);
  struct aiColor4D color = {0};
  if (aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &color) == aiReturn_SUCCESS ||
      aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &color) == aiReturn_SUCCESS) {
    float rgba[4] = {color.r, color.g, color.b, color.a};
    bool finite = true;
    for (int i = 0; i < 4; ++i)
      finite &= isfinite(rgba[i]) != 0;
    if (finite) memcpy(info->base_color, rgba, sizeof rgba);
  }
  read_texture(s, mat);
}
