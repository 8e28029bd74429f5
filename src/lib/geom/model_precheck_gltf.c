// Checks a glTF 2.0 document before assimp reads it. assimp's glTF 2 reader
// trusts much of the JSON: a well-formed document that leaves out a required
// member (an accessor's "type", a bufferView's "byteLength") or points past an
// array crashes it (assimp 5.2). So the JSON (a .gltf's text, a .glb's JSON
// chunk) is parsed here with the project's own bounds-checked reader, and
// every member the specification requires and assimp relies on is checked:
// types, ranges, indices into the other arrays, the node hierarchy (no cycle,
// one parent at most) and the byte ranges of buffers, views and accessors.
// A failure names the file and the field: "model.glb: accessors[2].type is missing".
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "bk_json.h"
#include "model_import.h"

// Counts beyond this are refused (no byte range in a 4 GiB file needs more).
#define GLTF_MAX_COUNT (1ull << 32)
// JSON values beyond this are refused before anything is allocated for
// them (48 bytes each here, about 33 in assimp): a scene's structure needs
// far fewer (our own export of 8,192 fragments about 2 million), while 64 MiB
// of "0," would otherwise take 1.6 GB.
#define GLTF_MAX_JSON_VALUES (1u << 23)

typedef struct gltf_check {
  const char* name;
  const bk_json_doc* doc;
  bk_error* err;
  uint32_t root;
  // The top-level arrays (BK_JSON_NONE if absent) and their lengths.
  uint32_t accessors, buffer_views, buffers, meshes, nodes, images, textures, materials, samplers, scenes,
      skins, cameras, animations;
  uint32_t n_accessors, n_buffer_views, n_buffers, n_meshes, n_nodes, n_images, n_textures, n_materials,
      n_samplers, n_scenes, n_skins, n_cameras, n_animations;
} gltf_check;

__attribute__((format(printf, 2, 3))) static bool fail(const gltf_check* c, const char* fmt, ...) {
  char text[400];
  va_list args;
  va_start(args, fmt);
  vsnprintf(text, sizeof text, fmt, args);
  va_end(args);
  return bk_error_set(c->err, "%s: %s", c->name, text);
}

// A string's contents for a message: cut short, control characters blanked.
static const char* quoted(const gltf_check* c, uint32_t value, char* buffer, size_t size) {
  const bk_json_value* v = &c->doc->values[value];
  bk_import_copy_text(buffer, size, c->doc->text + v->start, v->length);
  return buffer;
}

// A top-level array; absent is an empty one, anything else is an error.
static bool top_array(gltf_check* c, const char* key, uint32_t* array, uint32_t* count) {
  *array = bk_json_get(c->doc, c->root, key);
  *count = 0;
  if (*array == BK_JSON_NONE) return true;
  if (bk_json_type_of(c->doc, *array) != BK_JSON_ARRAY) return fail(c, "%s is not an array", key);
  *count = bk_json_count(c->doc, *array);
  for (uint32_t i = 0, e = bk_json_first(c->doc, *array); e != BK_JSON_NONE; e = bk_json_next(c->doc, e), ++i)
    if (bk_json_type_of(c->doc, e) != BK_JSON_OBJECT) return fail(c, "%s[%u] is not an object", key, i);
  return true;
}

// An optional member that must be an object when present.
static bool optional_object(const gltf_check* c, uint32_t object, const char* key, const char* where,
                            uint32_t* out) {
  *out = bk_json_get(c->doc, object, key);
  if (*out != BK_JSON_NONE && bk_json_type_of(c->doc, *out) != BK_JSON_OBJECT)
    return fail(c, "%s.%s is not an object", where, key);
  return true;
}

// "where.key", or "key" at the top level (where "").
static const char* field_name(char* buffer, size_t size, const char* where, const char* key) {
  snprintf(buffer, size, "%s%s%s", where, where[0] ? "." : "", key);
  return buffer;
}

// A whole number member in [min, max]; `*present` false (and `*out` 0) when
// absent and not required.
static bool get_uint(const gltf_check* c, uint32_t object, const char* key, const char* where, bool required,
                     uint64_t min, uint64_t max, uint64_t* out, bool* present) {
  uint32_t v = bk_json_get(c->doc, object, key);
  char field[112];
  field_name(field, sizeof field, where, key);
  *out = 0;
  if (present) *present = v != BK_JSON_NONE;
  if (v == BK_JSON_NONE) return required ? fail(c, "%s is missing", field) : true;
  if (!bk_json_uint(c->doc, v, UINT64_MAX, out) || *out > GLTF_MAX_COUNT)
    return fail(c, "%s is not a whole number", field);
  if (*out < min || *out > max)
    return fail(c, "%s is %llu, not in %llu..%llu", field, (unsigned long long)*out, (unsigned long long)min,
                (unsigned long long)max);
  return true;
}

// An index into a top-level array of `count` elements called `what`.
static bool check_index(const gltf_check* c, uint32_t value, const char* where, uint32_t count,
                        const char* what, uint64_t* out) {
  uint64_t index = 0;
  if (!bk_json_uint(c->doc, value, UINT64_MAX, &index)) return fail(c, "%s is not an index", where);
  if (index >= count) {
    if (count == 0) return fail(c, "%s is %llu, but there are no %s", where, (unsigned long long)index, what);
    return fail(c, "%s is %llu, out of range (%u %s)", where, (unsigned long long)index, count, what);
  }
  if (out) *out = index;
  return true;
}

// An index member; `*present` false when absent and not required.
static bool get_index(const gltf_check* c, uint32_t object, const char* key, const char* where, bool required,
                      uint32_t count, const char* what, uint64_t* out, bool* present) {
  uint32_t v = bk_json_get(c->doc, object, key);
  if (present) *present = v != BK_JSON_NONE;
  if (out) *out = 0;
  char field[112];
  field_name(field, sizeof field, where, key);
  if (v == BK_JSON_NONE) return required ? fail(c, "%s is missing", field) : true;
  return check_index(c, v, field, count, what, out);
}

// An optional array of exactly `n` numbers (0: any length), all finite.
static bool number_array(const gltf_check* c, uint32_t object, const char* key, const char* where,
                         uint32_t n) {
  uint32_t a = bk_json_get(c->doc, object, key);
  if (a == BK_JSON_NONE) return true;
  if (bk_json_type_of(c->doc, a) != BK_JSON_ARRAY || (n && bk_json_count(c->doc, a) != n))
    return n ? fail(c, "%s.%s is not an array of %u numbers", where, key, n)
             : fail(c, "%s.%s is not an array of numbers", where, key);
  for (uint32_t e = bk_json_first(c->doc, a); e != BK_JSON_NONE; e = bk_json_next(c->doc, e)) {
    double x = 0.0;
    if (!bk_json_number(c->doc, e, &x) || !isfinite(x))
      return fail(c, "%s.%s holds something other than a finite number", where, key);
  }
  return true;
}

static bool check_asset(const gltf_check* c) {
  uint32_t asset = bk_json_get(c->doc, c->root, "asset");
  if (asset == BK_JSON_NONE) return fail(c, "asset is missing");
  if (bk_json_type_of(c->doc, asset) != BK_JSON_OBJECT) return fail(c, "asset is not an object");
  uint32_t version = bk_json_get(c->doc, asset, "version");
  if (version == BK_JSON_NONE) return fail(c, "asset.version is missing");
  if (bk_json_type_of(c->doc, version) != BK_JSON_STRING) return fail(c, "asset.version is not a string");
  const bk_json_value* v = &c->doc->values[version];
  const char* s = c->doc->text + v->start;
  bool ok = v->length >= 3 && s[0] == '2' && s[1] == '.';
  for (size_t i = 2; ok && i < v->length; ++i)
    ok = s[i] >= '0' && s[i] <= '9';
  char text[24];
  if (!ok)
    return fail(c, "asset.version '%s' is not 2.x (only glTF 2 is read)",
                quoted(c, version, text, sizeof text));
  return true;
}

// Byte lengths of the buffers and views, for the range checks.
typedef struct gltf_sizes {
  uint64_t* buffer_bytes;
  uint64_t* view_bytes;
  uint64_t* view_stride; // 0 when not given
} gltf_sizes;

static bool check_buffers(const gltf_check* c, gltf_sizes* sizes, bool binary, uint64_t bin_bytes,
                          bool has_bin) {
  uint32_t i = 0;
  for (uint32_t b = bk_json_first(c->doc, c->buffers); b != BK_JSON_NONE; b = bk_json_next(c->doc, b), ++i) {
    char where[48];
    snprintf(where, sizeof where, "buffers[%u]", i);
    uint64_t length = 0;
    if (!get_uint(c, b, "byteLength", where, true, 1, GLTF_MAX_COUNT, &length, NULL)) return false;
    sizes->buffer_bytes[i] = length;
    uint32_t uri = bk_json_get(c->doc, b, "uri");
    if (uri != BK_JSON_NONE && bk_json_type_of(c->doc, uri) != BK_JSON_STRING)
      return fail(c, "%s.uri is not a string", where);
    if (uri == BK_JSON_NONE) {
      if (!binary || i != 0)
        return fail(c, "%s.uri is missing (only a .glb's buffer 0 may go without)", where);
      if (!has_bin) return fail(c, "%s has no uri and the file has no BIN chunk", where);
      if (length > bin_bytes)
        return fail(c, "%s.byteLength is %llu, more than the BIN chunk's %llu bytes", where,
                    (unsigned long long)length, (unsigned long long)bin_bytes);
    }
  }
  return true;
}

static bool check_buffer_views(const gltf_check* c, gltf_sizes* sizes) {
  uint32_t i = 0;
  for (uint32_t v = bk_json_first(c->doc, c->buffer_views); v != BK_JSON_NONE;
       v = bk_json_next(c->doc, v), ++i) {
    char where[48];
    snprintf(where, sizeof where, "bufferViews[%u]", i);
    uint64_t buffer = 0, offset = 0, length = 0, stride = 0;
    if (!get_index(c, v, "buffer", where, true, c->n_buffers, "buffers", &buffer, NULL) ||
        !get_uint(c, v, "byteLength", where, true, 1, GLTF_MAX_COUNT, &length, NULL) ||
        !get_uint(c, v, "byteOffset", where, false, 0, GLTF_MAX_COUNT, &offset, NULL) ||
        !get_uint(c, v, "byteStride", where, false, 4, 252, &stride, NULL))
      return false;
    if (offset + length > sizes->buffer_bytes[buffer])
      return fail(c, "%s: byteOffset %llu + byteLength %llu is past the end of buffers[%llu] (%llu bytes)",
                  where, (unsigned long long)offset, (unsigned long long)length, (unsigned long long)buffer,
                  (unsigned long long)sizes->buffer_bytes[buffer]);
    sizes->view_bytes[i] = length;
    sizes->view_stride[i] = stride;
  }
  return true;
}

// Bytes per component of a componentType; 0 if it is none.
static uint64_t component_bytes(uint64_t type) {
  switch (type) {
  case 5120:
  case 5121:
    return 1;
  case 5122:
  case 5123:
    return 2;
  case 5125:
  case 5126:
    return 4;
  default:
    return 0;
  }
}

// Components of an accessor type; 0 if it is none.
static uint64_t type_components(const gltf_check* c, uint32_t type) {
  static const char* const names[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
  static const uint64_t components[] = {1, 2, 3, 4, 4, 9, 16};
  for (size_t i = 0; i < sizeof components / sizeof components[0]; ++i)
    if (bk_json_string_is(c->doc, type, names[i])) return components[i];
  return 0;
}

// `count` elements of `element` bytes, `stride` apart (0: packed), from
// `offset` in a view of `view_bytes`.
static bool fits_view(uint64_t offset, uint64_t count, uint64_t element, uint64_t stride,
                      uint64_t view_bytes) {
  uint64_t step = stride ? stride : element;
  if (stride && stride < element) return false;
  return offset <= view_bytes && count <= GLTF_MAX_COUNT && element <= view_bytes - offset &&
         (count - 1) <= (view_bytes - offset - element) / step;
}

static bool check_sparse(const gltf_check* c, uint32_t accessor, const char* where, uint64_t element,
                         const gltf_sizes* sizes) {
  uint32_t sparse = BK_JSON_NONE;
  if (!optional_object(c, accessor, "sparse", where, &sparse)) return false;
  if (sparse == BK_JSON_NONE) return true;
  char here[80];
  snprintf(here, sizeof here, "%s.sparse", where);
  uint64_t count = 0;
  if (!get_uint(c, sparse, "count", here, true, 1, GLTF_MAX_COUNT, &count, NULL)) return false;
  const char* parts[2] = {"indices", "values"};
  for (int k = 0; k < 2; ++k) {
    uint32_t part = bk_json_get(c->doc, sparse, parts[k]);
    if (part == BK_JSON_NONE) return fail(c, "%s.%s is missing", here, parts[k]);
    if (bk_json_type_of(c->doc, part) != BK_JSON_OBJECT)
      return fail(c, "%s.%s is not an object", here, parts[k]);
    char at[96];
    snprintf(at, sizeof at, "%s.%s", here, parts[k]);
    uint64_t view = 0, offset = 0, bytes = element, type = 0;
    if (!get_index(c, part, "bufferView", at, true, c->n_buffer_views, "bufferViews", &view, NULL) ||
        !get_uint(c, part, "byteOffset", at, false, 0, GLTF_MAX_COUNT, &offset, NULL))
      return false;
    if (k == 0) {
      if (!get_uint(c, part, "componentType", at, true, 0, UINT32_MAX, &type, NULL)) return false;
      if (type != 5121 && type != 5123 && type != 5125)
        return fail(c, "%s.componentType %llu is not an unsigned integer type (5121, 5123, 5125)", at,
                    (unsigned long long)type);
      bytes = component_bytes(type);
    }
    if (!fits_view(offset, count, bytes, 0, sizes->view_bytes[view]))
      return fail(
          c, "%s: %llu elements of %llu bytes from byteOffset %llu do not fit bufferViews[%llu] (%llu bytes)",
          at, (unsigned long long)count, (unsigned long long)bytes, (unsigned long long)offset,
          (unsigned long long)view, (unsigned long long)sizes->view_bytes[view]);
  }
  return true;
}

static bool check_accessors(const gltf_check* c, const gltf_sizes* sizes, uint64_t* components) {
  uint32_t i = 0;
  for (uint32_t a = bk_json_first(c->doc, c->accessors); a != BK_JSON_NONE;
       a = bk_json_next(c->doc, a), ++i) {
    char where[48];
    snprintf(where, sizeof where, "accessors[%u]", i);
    uint64_t component = 0, count = 0, view = 0, offset = 0;
    bool has_view = false;
    if (!get_uint(c, a, "componentType", where, true, 0, UINT32_MAX, &component, NULL)) return false;
    if (!component_bytes(component))
      return fail(c, "%s.componentType %llu is not one of 5120, 5121, 5122, 5123, 5125, 5126", where,
                  (unsigned long long)component);
    if (!get_uint(c, a, "count", where, true, 1, GLTF_MAX_COUNT, &count, NULL)) return false;
    uint32_t type = bk_json_get(c->doc, a, "type");
    if (type == BK_JSON_NONE) return fail(c, "%s.type is missing", where);
    if (bk_json_type_of(c->doc, type) != BK_JSON_STRING) return fail(c, "%s.type is not a string", where);
    components[i] = type_components(c, type);
    char text[24];
    if (!components[i])
      return fail(c, "%s.type '%s' is not one of SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4", where,
                  quoted(c, type, text, sizeof text));
    if (!get_index(c, a, "bufferView", where, false, c->n_buffer_views, "bufferViews", &view, &has_view) ||
        !get_uint(c, a, "byteOffset", where, false, 0, GLTF_MAX_COUNT, &offset, NULL))
      return false;
    uint64_t element = components[i] * component_bytes(component);
    if (has_view && !fits_view(offset, count, element, sizes->view_stride[view], sizes->view_bytes[view]))
      return fail(
          c, "%s: %llu elements of %llu bytes from byteOffset %llu do not fit bufferViews[%llu] (%llu bytes)",
          where, (unsigned long long)count, (unsigned long long)element, (unsigned long long)offset,
          (unsigned long long)view, (unsigned long long)sizes->view_bytes[view]);
    if (!number_array(c, a, "min", where, (uint32_t)components[i]) ||
        !number_array(c, a, "max", where, (uint32_t)components[i]) ||
        !check_sparse(c, a, where, element, sizes))
      return false;
  }
  return true;
}

static bool check_images_textures(const gltf_check* c) {
  uint32_t i = 0;
  for (uint32_t m = bk_json_first(c->doc, c->images); m != BK_JSON_NONE; m = bk_json_next(c->doc, m), ++i) {
    char where[48];
    snprintf(where, sizeof where, "images[%u]", i);
    uint32_t uri = bk_json_get(c->doc, m, "uri");
    bool has_view = false;
    if (!get_index(c, m, "bufferView", where, false, c->n_buffer_views, "bufferViews", NULL, &has_view))
      return false;
    if (uri != BK_JSON_NONE) {
      if (bk_json_type_of(c->doc, uri) != BK_JSON_STRING) return fail(c, "%s.uri is not a string", where);
      if (has_view) return fail(c, "%s has both a uri and a bufferView", where);
      continue;
    }
    if (!has_view) return fail(c, "%s has neither a uri nor a bufferView", where);
    uint32_t mime = bk_json_get(c->doc, m, "mimeType");
    if (mime == BK_JSON_NONE) return fail(c, "%s.mimeType is missing (needed with a bufferView)", where);
    if (bk_json_type_of(c->doc, mime) != BK_JSON_STRING) return fail(c, "%s.mimeType is not a string", where);
    char text[24];
    if (!bk_json_string_is(c->doc, mime, "image/png") && !bk_json_string_is(c->doc, mime, "image/jpeg"))
      return fail(c, "%s.mimeType '%s' is not image/png or image/jpeg", where,
                  quoted(c, mime, text, sizeof text));
  }
  i = 0;
  for (uint32_t t = bk_json_first(c->doc, c->textures); t != BK_JSON_NONE; t = bk_json_next(c->doc, t), ++i) {
    char where[48];
    snprintf(where, sizeof where, "textures[%u]", i);
    if (!get_index(c, t, "source", where, false, c->n_images, "images", NULL, NULL) ||
        !get_index(c, t, "sampler", where, false, c->n_samplers, "samplers", NULL, NULL))
      return false;
  }
  return true;
}

// A textureInfo member of `object` (optional): an object with an index in range.
static bool check_texture_info(const gltf_check* c, uint32_t object, const char* key, const char* where) {
  uint32_t info = BK_JSON_NONE;
  if (!optional_object(c, object, key, where, &info)) return false;
  if (info == BK_JSON_NONE) return true;
  char here[96];
  snprintf(here, sizeof here, "%s.%s", where, key);
  uint64_t unused = 0;
  return get_index(c, info, "index", here, true, c->n_textures, "textures", NULL, NULL) &&
         get_uint(c, info, "texCoord", here, false, 0, 31, &unused, NULL);
}

static bool check_materials(const gltf_check* c) {
  uint32_t i = 0;
  for (uint32_t m = bk_json_first(c->doc, c->materials); m != BK_JSON_NONE;
       m = bk_json_next(c->doc, m), ++i) {
    char where[48];
    snprintf(where, sizeof where, "materials[%u]", i);
    uint32_t pbr = BK_JSON_NONE;
    if (!optional_object(c, m, "pbrMetallicRoughness", where, &pbr)) return false;
    char pbr_where[80];
    snprintf(pbr_where, sizeof pbr_where, "%s.pbrMetallicRoughness", where);
    if (pbr != BK_JSON_NONE && (!check_texture_info(c, pbr, "baseColorTexture", pbr_where) ||
                                !check_texture_info(c, pbr, "metallicRoughnessTexture", pbr_where) ||
                                !number_array(c, pbr, "baseColorFactor", pbr_where, 4)))
      return false;
    if (!check_texture_info(c, m, "normalTexture", where) ||
        !check_texture_info(c, m, "occlusionTexture", where) ||
        !check_texture_info(c, m, "emissiveTexture", where) ||
        !number_array(c, m, "emissiveFactor", where, 3))
      return false;
  }
  return true;
}

// An object whose every member is an accessor index (attributes, a morph target).
static bool check_attribute_object(const gltf_check* c, uint32_t object, const char* where,
                                   const uint64_t* components) {
  if (bk_json_type_of(c->doc, object) != BK_JSON_OBJECT) return fail(c, "%s is not an object", where);
  for (uint32_t a = bk_json_first(c->doc, object); a != BK_JSON_NONE; a = bk_json_next(c->doc, a)) {
    const bk_json_value* v = &c->doc->values[a];
    char field[128];
    snprintf(field, sizeof field, "%s.%.*s", where, (int)(v->key_length < 40 ? v->key_length : 40),
             c->doc->text + v->key_start); // no control characters: the parser refuses them in strings
    uint64_t accessor = 0;
    if (!check_index(c, a, field, c->n_accessors, "accessors", &accessor)) return false;
    bool vec3 = (v->key_length == 8 && memcmp(c->doc->text + v->key_start, "POSITION", 8) == 0) ||
                (v->key_length == 6 && memcmp(c->doc->text + v->key_start, "NORMAL", 6) == 0);
    if (vec3 && components[accessor] != 3)
      return fail(c, "%s: accessors[%llu] is not a VEC3", field, (unsigned long long)accessor);
  }
  return true;
}

static bool check_meshes(const gltf_check* c, const uint64_t* components) {
  uint32_t i = 0;
  for (uint32_t m = bk_json_first(c->doc, c->meshes); m != BK_JSON_NONE; m = bk_json_next(c->doc, m), ++i) {
    char where[48];
    snprintf(where, sizeof where, "meshes[%u]", i);
    uint32_t primitives = bk_json_get(c->doc, m, "primitives");
    if (primitives == BK_JSON_NONE) return fail(c, "%s.primitives is missing", where);
    if (bk_json_type_of(c->doc, primitives) != BK_JSON_ARRAY || bk_json_count(c->doc, primitives) == 0)
      return fail(c, "%s.primitives is not an array of at least one primitive", where);
    uint32_t k = 0;
    for (uint32_t p = bk_json_first(c->doc, primitives); p != BK_JSON_NONE;
         p = bk_json_next(c->doc, p), ++k) {
      char here[80];
      snprintf(here, sizeof here, "%s.primitives[%u]", where, k);
      if (bk_json_type_of(c->doc, p) != BK_JSON_OBJECT) return fail(c, "%s is not an object", here);
      uint32_t attributes = bk_json_get(c->doc, p, "attributes");
      if (attributes == BK_JSON_NONE) return fail(c, "%s.attributes is missing", here);
      char field[112];
      snprintf(field, sizeof field, "%s.attributes", here);
      if (!check_attribute_object(c, attributes, field, components)) return false;
      uint64_t indices = 0, mode = 0;
      bool has_indices = false;
      if (!get_index(c, p, "indices", here, false, c->n_accessors, "accessors", &indices, &has_indices) ||
          !get_index(c, p, "material", here, false, c->n_materials, "materials", NULL, NULL) ||
          !get_uint(c, p, "mode", here, false, 0, 6, &mode, NULL))
        return false;
      if (has_indices && components[indices] != 1)
        return fail(c, "%s.indices: accessors[%llu] is not a SCALAR", here, (unsigned long long)indices);
      uint32_t targets = bk_json_get(c->doc, p, "targets");
      if (targets == BK_JSON_NONE) continue;
      if (bk_json_type_of(c->doc, targets) != BK_JSON_ARRAY)
        return fail(c, "%s.targets is not an array", here);
      uint32_t t = 0;
      for (uint32_t e = bk_json_first(c->doc, targets); e != BK_JSON_NONE; e = bk_json_next(c->doc, e), ++t) {
        snprintf(field, sizeof field, "%s.targets[%u]", here, t);
        if (!check_attribute_object(c, e, field, components)) return false;
      }
    }
    if (!number_array(c, m, "weights", where, 0)) return false;
  }
  return true;
}

// Index arrays: `key` of `object` (optional) must be an array of indices in range.
static bool check_index_array(const gltf_check* c, uint32_t object, const char* key, const char* where,
                              uint32_t count, const char* what) {
  uint32_t a = bk_json_get(c->doc, object, key);
  if (a == BK_JSON_NONE) return true;
  if (bk_json_type_of(c->doc, a) != BK_JSON_ARRAY) return fail(c, "%s.%s is not an array", where, key);
  uint32_t k = 0;
  for (uint32_t e = bk_json_first(c->doc, a); e != BK_JSON_NONE; e = bk_json_next(c->doc, e), ++k) {
    char field[96];
    snprintf(field, sizeof field, "%s.%s[%u]", where, key, k);
    if (!check_index(c, e, field, count, what, NULL)) return false;
  }
  return true;
}

// Nodes: references in range, transforms well formed, and the children form
// a forest: no node has two parents, none is its own ancestor.
static bool check_nodes(const gltf_check* c) {
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * (c->n_nodes + 1u));
  for (uint32_t i = 0; i < c->n_nodes; ++i)
    parent[i] = BK_JSON_NONE;
  bool ok = true;
  uint32_t i = 0;
  for (uint32_t n = bk_json_first(c->doc, c->nodes); ok && n != BK_JSON_NONE;
       n = bk_json_next(c->doc, n), ++i) {
    char where[48];
    snprintf(where, sizeof where, "nodes[%u]", i);
    ok = get_index(c, n, "mesh", where, false, c->n_meshes, "meshes", NULL, NULL) &&
         get_index(c, n, "skin", where, false, c->n_skins, "skins", NULL, NULL) &&
         get_index(c, n, "camera", where, false, c->n_cameras, "cameras", NULL, NULL) &&
         number_array(c, n, "matrix", where, 16) && number_array(c, n, "translation", where, 3) &&
         number_array(c, n, "rotation", where, 4) && number_array(c, n, "scale", where, 3) &&
         number_array(c, n, "weights", where, 0) &&
         check_index_array(c, n, "children", where, c->n_nodes, "nodes");
    uint32_t children = bk_json_get(c->doc, n, "children");
    uint32_t k = 0;
    for (uint32_t e = bk_json_first(c->doc, children); ok && e != BK_JSON_NONE;
         e = bk_json_next(c->doc, e), ++k) {
      uint64_t child = 0;
      bk_json_uint(c->doc, e, c->n_nodes, &child); // checked above
      if (child == i)
        ok = fail(c, "%s.children[%u]: the node is its own child", where, k);
      else if (parent[child] != BK_JSON_NONE)
        ok = fail(c, "%s.children[%u]: nodes[%llu] is already a child of nodes[%u]", where, k,
                  (unsigned long long)child, parent[child]);
      else
        parent[child] = i;
    }
  }
  // Every node has one parent at most: following parents from each node
  // either ends at a root or comes back round (a cycle). Nodes are marked
  // with the walk that first reached them.
  uint32_t* walk = ok ? bk_alloc(sizeof(uint32_t) * (c->n_nodes + 1u)) : NULL;
  for (uint32_t n = 0; ok && n < c->n_nodes; ++n)
    walk[n] = BK_JSON_NONE;
  for (uint32_t n = 0; ok && n < c->n_nodes; ++n) {
    uint32_t at = n;
    while (at != BK_JSON_NONE && walk[at] == BK_JSON_NONE) {
      walk[at] = n;
      at = parent[at];
    }
    if (at != BK_JSON_NONE && walk[at] == n)
      ok = fail(c, "nodes[%u] is its own ancestor (the children form a cycle)", at);
  }
  bk_free(walk);
  bk_free(parent);
  return ok;
}

static bool check_scenes_skins_animations(const gltf_check* c) {
  uint32_t i = 0;
  for (uint32_t s = bk_json_first(c->doc, c->scenes); s != BK_JSON_NONE; s = bk_json_next(c->doc, s), ++i) {
    char where[48];
    snprintf(where, sizeof where, "scenes[%u]", i);
    if (!check_index_array(c, s, "nodes", where, c->n_nodes, "nodes")) return false;
  }
  if (!get_index(c, c->root, "scene", "", false, c->n_scenes, "scenes", NULL, NULL)) return false;
  i = 0;
  for (uint32_t s = bk_json_first(c->doc, c->skins); s != BK_JSON_NONE; s = bk_json_next(c->doc, s), ++i) {
    char where[48];
    snprintf(where, sizeof where, "skins[%u]", i);
    uint32_t joints = bk_json_get(c->doc, s, "joints");
    if (joints == BK_JSON_NONE) return fail(c, "%s.joints is missing", where);
    if (!check_index_array(c, s, "joints", where, c->n_nodes, "nodes") ||
        !get_index(c, s, "skeleton", where, false, c->n_nodes, "nodes", NULL, NULL) ||
        !get_index(c, s, "inverseBindMatrices", where, false, c->n_accessors, "accessors", NULL, NULL))
      return false;
  }
  i = 0;
  for (uint32_t a = bk_json_first(c->doc, c->animations); a != BK_JSON_NONE;
       a = bk_json_next(c->doc, a), ++i) {
    char where[48];
    snprintf(where, sizeof where, "animations[%u]", i);
    uint32_t samplers = bk_json_get(c->doc, a, "samplers"), channels = bk_json_get(c->doc, a, "channels");
    if (bk_json_type_of(c->doc, samplers) != BK_JSON_ARRAY)
      return fail(c, "%s.samplers is not an array", where);
    if (bk_json_type_of(c->doc, channels) != BK_JSON_ARRAY)
      return fail(c, "%s.channels is not an array", where);
    uint32_t k = 0;
    for (uint32_t s = bk_json_first(c->doc, samplers); s != BK_JSON_NONE; s = bk_json_next(c->doc, s), ++k) {
      char here[80];
      snprintf(here, sizeof here, "%s.samplers[%u]", where, k);
      if (bk_json_type_of(c->doc, s) != BK_JSON_OBJECT) return fail(c, "%s is not an object", here);
      if (!get_index(c, s, "input", here, true, c->n_accessors, "accessors", NULL, NULL) ||
          !get_index(c, s, "output", here, true, c->n_accessors, "accessors", NULL, NULL))
        return false;
    }
    k = 0;
    for (uint32_t s = bk_json_first(c->doc, channels); s != BK_JSON_NONE; s = bk_json_next(c->doc, s), ++k) {
      char here[80];
      snprintf(here, sizeof here, "%s.channels[%u]", where, k);
      if (bk_json_type_of(c->doc, s) != BK_JSON_OBJECT) return fail(c, "%s is not an object", here);
      if (!get_index(c, s, "sampler", here, true, bk_json_count(c->doc, samplers), "samplers", NULL, NULL))
        return false;
      uint32_t target = bk_json_get(c->doc, s, "target");
      if (target == BK_JSON_NONE) return fail(c, "%s.target is missing", here);
      if (bk_json_type_of(c->doc, target) != BK_JSON_OBJECT)
        return fail(c, "%s.target is not an object", here);
      char at[96];
      snprintf(at, sizeof at, "%s.target", here);
      if (!get_index(c, target, "node", at, false, c->n_nodes, "nodes", NULL, NULL)) return false;
    }
  }
  return true;
}

static uint32_t glb_u32(const unsigned char* p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

bool bk_import_precheck_gltf(const char* name, const char* ext, const void* data, size_t size,
                             uint64_t file_size, bk_error* err) {
  const char* json = data;
  size_t json_size = size;
  bool binary = strcmp(ext, "glb") == 0, has_bin = false;
  uint64_t bin_bytes = 0;
  if (binary) {
    // bk_import_precheck has checked the header; the JSON chunk must be here whole.
    const unsigned char* bytes = data;
    if (size < 20) return bk_error_set(err, "%s: not a binary glTF file (no 'glTF' header)", name);
    uint32_t length = glb_u32(bytes + 8), chunk = glb_u32(bytes + 12);
    if (chunk > size - 20 || memcmp(bytes + 16, "JSON", 4) != 0)
      return bk_error_set(err, "%s: corrupt binary glTF (JSON chunk of %u bytes in a file of %u)", name,
                          chunk, length);
    json = (const char*)bytes + 20;
    json_size = chunk;
    uint64_t next = 20ull + chunk, end = length < file_size ? length : file_size;
    if (next + 8 <= end && next + 8 <= size && memcmp(bytes + next + 4, "BIN\0", 4) == 0) {
      bin_bytes = glb_u32(bytes + next);
      if (bin_bytes > end - next - 8)
        return bk_error_set(err, "%s: corrupt binary glTF (BIN chunk of %llu bytes past the file's end)",
                            name, (unsigned long long)bin_bytes);
      has_bin = true;
    }
  }
  // Counted before anything is allocated; the contents of "extras" (which
  // nothing here checks, and where our own exports keep their tree) are
  // checked but not stored. assimp parses every value (about 33 bytes
  // each), so the total is limited too.
  static const bk_json_limits limits = {GLTF_MAX_JSON_VALUES, GLTF_MAX_JSON_VALUES, NULL, true};
  bk_json_doc doc;
  char why[160];
  if (!bk_json_parse_limited(json, json_size, &limits, &doc, why, sizeof why))
    return strncmp(why, "more than", 9) == 0
               ? bk_error_set(err, "%s: the glTF JSON holds %s, refusing to load", name, why)
               : bk_error_set(err, "%s: malformed glTF JSON: %s", name, why);
  gltf_check c = {.name = name, .doc = &doc, .err = err, .root = 0};
  gltf_sizes sizes = {0};
  uint64_t* components = NULL;
  bool ok = bk_json_type_of(&doc, 0) == BK_JSON_OBJECT || fail(&c, "the glTF JSON is not an object");
  ok = ok && check_asset(&c) && top_array(&c, "accessors", &c.accessors, &c.n_accessors) &&
       top_array(&c, "bufferViews", &c.buffer_views, &c.n_buffer_views) &&
       top_array(&c, "buffers", &c.buffers, &c.n_buffers) &&
       top_array(&c, "meshes", &c.meshes, &c.n_meshes) && top_array(&c, "nodes", &c.nodes, &c.n_nodes) &&
       top_array(&c, "images", &c.images, &c.n_images) &&
       top_array(&c, "textures", &c.textures, &c.n_textures) &&
       top_array(&c, "materials", &c.materials, &c.n_materials) &&
       top_array(&c, "samplers", &c.samplers, &c.n_samplers) &&
       top_array(&c, "scenes", &c.scenes, &c.n_scenes) && top_array(&c, "skins", &c.skins, &c.n_skins) &&
       top_array(&c, "cameras", &c.cameras, &c.n_cameras) &&
       top_array(&c, "animations", &c.animations, &c.n_animations);
  if (ok) {
    sizes.buffer_bytes = bk_calloc(c.n_buffers + 1u, sizeof(uint64_t));
    sizes.view_bytes = bk_calloc(c.n_buffer_views + 1u, sizeof(uint64_t));
    sizes.view_stride = bk_calloc(c.n_buffer_views + 1u, sizeof(uint64_t));
    components = bk_calloc(c.n_accessors + 1u, sizeof(uint64_t));
  }
  ok = ok && check_buffers(&c, &sizes, binary, bin_bytes, has_bin) && check_buffer_views(&c, &sizes) &&
       check_accessors(&c, &sizes, components) && check_images_textures(&c) && check_materials(&c) &&
       check_meshes(&c, components) && check_nodes(&c) && check_scenes_skins_animations(&c);
  bk_free(sizes.buffer_bytes);
  bk_free(sizes.view_bytes);
  bk_free(sizes.view_stride);
  bk_free(components);
  bk_json_free(&doc);
  return ok;
}
