// The materials of a glTF export: two per source material (its surface and
// `<name>_interior` for its cut faces), their base-colour textures and the
// images behind them, written into the binary buffer (so the file stands
// alone) or referenced by URI. Images given twice are written once.
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "gltf_internal.h"

bk_gltf_material bk_default_gltf_material(void) {
  return (bk_gltf_material){.name = "surface", .base_color = {1, 1, 1, 1}};
}

static bool check_image(const bk_gltf_image* image, const char* path, uint32_t i, const char* field,
                        bk_error* err) {
  if (image->data && image->uri)
    return bk_error_set(err, "%s: gltf def: materials[%u].%s has both data and uri (give one)", path, i,
                        field);
  if (image->data) {
    if (image->size == 0)
      return bk_error_set(err, "%s: gltf def: materials[%u].%s.size is 0", path, i, field);
    if (image->size > ((size_t)1 << 30))
      return bk_error_set(err, "%s: gltf def: materials[%u].%s.size is %zu bytes, more than 1 GiB", path, i,
                          field, image->size);
    if (!bk_image_format(image->data, image->size))
      return bk_error_set(
          err, "%s: gltf def: materials[%u].%s.data is neither PNG nor JPEG (glTF's image formats)", path, i,
          field);
  } else if (image->size) {
    return bk_error_set(err, "%s: gltf def: materials[%u].%s.size is %zu but data is NULL", path, i, field,
                        image->size);
  }
  if (image->uri && !image->uri[0])
    return bk_error_set(err, "%s: gltf def: materials[%u].%s.uri is empty", path, i, field);
  return true;
}

bool bk_gltf_check_materials(const bk_gltf_def* def, const char* path, bk_error* err) {
  if (def->material_count && !def->materials)
    return bk_error_set(err, "%s: gltf def: material_count is %u but materials is NULL", path,
                        def->material_count);
  if (def->material_count > BK_MATERIAL_SOURCES_MAX)
    return bk_error_set(err, "%s: gltf def: material_count is %u, more than %d", path, def->material_count,
                        BK_MATERIAL_SOURCES_MAX);
  for (uint32_t i = 0; i < def->material_count; ++i) {
    const bk_gltf_material* m = &def->materials[i];
    size_t length = m->name ? strlen(m->name) : 0;
    if (length < 1 || length > 63)
      return bk_error_set(err, "%s: gltf def: materials[%u].name must be 1 to 63 bytes, got %zu", path, i,
                          length);
    for (int k = 0; k < 4; ++k)
      if (!(m->base_color[k] >= 0.0f && m->base_color[k] <= 1.0f))
        return bk_error_set(err, "%s: gltf def: materials[%u].base_color[%d] must be in [0, 1], got %g", path,
                            i, k, (double)m->base_color[k]);
    if (!check_image(&m->texture, path, i, "texture", err) ||
        !check_image(&m->interior_texture, path, i, "interior_texture", err))
      return false;
  }
  return true;
}

static bool same_image(const bk_gltf_image* a, const bk_gltf_image* b) {
  if (a->data || b->data) return a->data == b->data && a->size == b->size;
  return strcmp(a->uri, b->uri) == 0;
}

// The texture (= image) index of an image, adding it when it is new.
static int32_t add_image(gltf_materials* m, const bk_gltf_image* image, uint64_t* offset, uint32_t* view) {
  if (!image->data && !image->uri) return -1;
  for (uint32_t i = 0; i < m->image_count; ++i)
    if (same_image(m->images[i].image, image)) return (int32_t)i;
  gltf_image_slot* slot = &m->images[m->image_count];
  slot->image = image;
  if (image->data) {
    slot->offset = *offset;
    slot->view = (*view)++;
    uint64_t padded = ((uint64_t)image->size + 3u) & ~(uint64_t)3;
    *offset += padded;
    m->bytes += padded;
  }
  return (int32_t)m->image_count++;
}

void bk_gltf_plan_materials(const bk_gltf_def* def, const bk_gltf_material* fallback, uint64_t binary_offset,
                            uint32_t first_view, gltf_materials* out) {
  memset(out, 0, sizeof *out);
  out->list = def->material_count ? def->materials : fallback;
  out->source_count = def->material_count ? def->material_count : 1;
  out->texture_of = bk_alloc(sizeof(int32_t) * 2u * out->source_count);
  out->images = bk_calloc(2u * out->source_count, sizeof(gltf_image_slot));
  uint64_t offset = binary_offset;
  uint32_t view = first_view;
  for (uint32_t i = 0; i < out->source_count; ++i) {
    out->texture_of[2 * i] = add_image(out, &out->list[i].texture, &offset, &view);
    out->texture_of[2 * i + 1] = add_image(out, &out->list[i].interior_texture, &offset, &view);
  }
}

uint32_t bk_gltf_material_index(const gltf_materials* m, uint8_t id) {
  uint32_t source = bk_material_source(id);
  return 2u * (source < m->source_count ? source : 0u) + (bk_material_is_interior(id) ? 1u : 0u);
}

void bk_gltf_write_image_data(const gltf_materials* m, uint8_t* binary) {
  for (uint32_t i = 0; i < m->image_count; ++i)
    if (m->images[i].image->data)
      memcpy(binary + m->images[i].offset, m->images[i].image->data, m->images[i].image->size);
}

static void write_material(text_buffer* t, const bk_gltf_material* m, bool interior, int32_t texture) {
  char name[96];
  snprintf(name, sizeof name, "%s%s", m->name, interior ? "_interior" : "");
  bk_tb_raw(t, "{\"name\":");
  bk_tb_string(t, name);
  // The interior is the material's body, not its paint: white, so its own texture shows as it is.
  double color[4] = {1, 1, 1, 1};
  if (!interior)
    for (int k = 0; k < 4; ++k)
      color[k] = m->base_color[k];
  bk_tb_raw(t, ",\"pbrMetallicRoughness\":{\"baseColorFactor\":");
  bk_tb_doubles(t, color, 4);
  bk_tb_raw(t, ",\"metallicFactor\":0,\"roughnessFactor\":");
  bk_tb_double(t, interior ? 0.9 : 0.8);
  if (texture >= 0) bk_tb_fmt(t, ",\"baseColorTexture\":{\"index\":%d}", texture);
  bk_tb_raw(t, "}");
  if (color[3] < 1.0) bk_tb_raw(t, ",\"alphaMode\":\"BLEND\"");
  bk_tb_raw(t, "}");
}

void bk_gltf_write_materials_json(text_buffer* t, const gltf_materials* m) {
  bk_tb_raw(t, ",\"materials\":[");
  for (uint32_t i = 0; i < 2u * m->source_count; ++i) {
    if (i) bk_tb_raw(t, ",");
    write_material(t, &m->list[i / 2], i % 2 == 1, m->texture_of[i]);
  }
  bk_tb_raw(t, "]");
  if (!m->image_count) return;
  bk_tb_raw(t, ",\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":10497,\"wrapT\":10497}],"
               "\"images\":[");
  for (uint32_t i = 0; i < m->image_count; ++i) {
    const gltf_image_slot* slot = &m->images[i];
    if (i) bk_tb_raw(t, ",");
    if (slot->image->data) {
      bk_tb_fmt(t, "{\"bufferView\":%u,\"mimeType\":\"image/%s\"}", slot->view,
                bk_image_format(slot->image->data, slot->image->size));
    } else {
      bk_tb_raw(t, "{\"uri\":");
      bk_tb_uri(t, slot->image->uri);
      bk_tb_raw(t, "}");
    }
  }
  bk_tb_raw(t, "],\"textures\":[");
  for (uint32_t i = 0; i < m->image_count; ++i)
    bk_tb_fmt(t, "%s{\"sampler\":0,\"source\":%u}", i ? "," : "", i);
  bk_tb_raw(t, "]");
}

void bk_gltf_write_image_views_json(text_buffer* t, const gltf_materials* m) {
  for (uint32_t i = 0; i < m->image_count; ++i) {
    const gltf_image_slot* slot = &m->images[i];
    if (!slot->image->data) continue;
    bk_tb_fmt(t, ",{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"name\":\"image_%u\"}",
              (unsigned long long)slot->offset, (unsigned long long)slot->image->size, i);
  }
}

void bk_gltf_materials_free(gltf_materials* m) {
  bk_free(m->texture_of);
  bk_free(m->images);
  memset(m, 0, sizeof *m);
}
