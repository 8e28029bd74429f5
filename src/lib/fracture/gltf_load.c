// Reading back a glTF written by bk_mesh_tree_save_gltf: the GLB container
// (or the .gltf JSON), asset.extras.breakables.mtree's buffer view, and the
// embedded .mtree through its own loader. Every length and index is checked
// against the bytes there are; every refusal is one line naming the file.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "bk_json.h"
#include "gltf_internal.h"

// Files of our own exports stay far below this (a .glb is at most 4 GiB).
#define GLTF_MAX_FILE_BYTES ((uint64_t)4 << 30)

static uint32_t load_u32le(const uint8_t* p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

// The GLB container: the JSON chunk and the binary chunk (if any).
static bool split_glb(const uint8_t* data, size_t size, const char* name, const char** json,
                      size_t* json_size, const uint8_t** bin, size_t* bin_size, bk_error* err) {
  if (size < 12) return bk_error_set(err, "%s: truncated GLB header (%zu bytes)", name, size);
  uint32_t version = load_u32le(data + 4), length = load_u32le(data + 8);
  if (version != BK_GLB_VERSION)
    return bk_error_set(err, "%s: GLB version %u is not supported (expected 2)", name, version);
  if (length > size)
    return bk_error_set(err, "%s: truncated: the GLB header says %u bytes, the file has %zu", name, length,
                        size);
  if (length < size)
    return bk_error_set(err, "%s: corrupt: the GLB header says %u bytes, the file has %zu", name, length,
                        size);
  if (size - 12 < 8) return bk_error_set(err, "%s: truncated: the GLB has no JSON chunk", name);
  uint32_t chunk = load_u32le(data + 12), type = load_u32le(data + 16);
  if (type != BK_GLB_CHUNK_JSON)
    return bk_error_set(err, "%s: corrupt: the first GLB chunk is of type 0x%08x, not JSON", name, type);
  if (chunk > size - 20)
    return bk_error_set(err, "%s: truncated: the JSON chunk says %u bytes, %zu remain", name, chunk,
                        size - 20);
  *json = (const char*)data + 20;
  *json_size = chunk;
  size_t at = 20 + (size_t)chunk;
  *bin = NULL;
  *bin_size = 0;
  if (at == size) return true;
  if (size - at < 8)
    return bk_error_set(err, "%s: truncated: %zu bytes after the JSON chunk, not a chunk header", name,
                        size - at);
  chunk = load_u32le(data + at);
  type = load_u32le(data + at + 4);
  if (type != BK_GLB_CHUNK_BIN)
    return bk_error_set(err, "%s: corrupt: the second GLB chunk is of type 0x%08x, not BIN", name, type);
  if (chunk > size - at - 8)
    return bk_error_set(err, "%s: truncated: the BIN chunk says %u bytes, %zu remain", name, chunk,
                        size - at - 8);
  *bin = data + at + 8;
  *bin_size = chunk;
  return true;
}

static int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Strict base64 (padding required, nothing else allowed); *out is allocated.
static bool decode_base64(const char* text, size_t length, uint8_t** out, size_t* out_size) {
  if (length % 4 != 0) return false;
  size_t padding = 0;
  if (length >= 1 && text[length - 1] == '=') padding++;
  if (length >= 2 && text[length - 2] == '=') padding++;
  uint8_t* bytes = bk_alloc(length / 4 * 3);
  size_t n = 0;
  for (size_t i = 0; i < length; i += 4) {
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) {
      int d = base64_value(text[i + k]);
      bool pad_slot = i + 4 == length && k >= 4 - (int)padding;
      if (pad_slot) d = 0;
      if (d < 0) {
        bk_free(bytes);
        return false;
      }
      v = v << 6 | (uint32_t)d;
    }
    bytes[n++] = (uint8_t)(v >> 16);
    bytes[n++] = (uint8_t)(v >> 8);
    bytes[n++] = (uint8_t)v;
  }
  *out = bytes;
  *out_size = n - padding;
  return true;
}

// A required non-negative integer member of an object.
static bool get_index(const bk_json_doc* doc, uint32_t object, const char* key, uint64_t max, uint64_t* out) {
  return bk_json_uint(doc, bk_json_get(doc, object, key), max, out);
}

// Finds the bytes of the embedded .mtree and loads them.
static bool load_from_json(const bk_json_doc* doc, const uint8_t* bin, size_t bin_size, const char* name,
                           bk_mesh_tree* out, bk_error* err) {
  if (bk_json_type_of(doc, 0) != BK_JSON_OBJECT)
    return bk_error_set(err, "%s: not glTF (the JSON is not an object)", name);
  uint32_t asset = bk_json_get(doc, 0, "asset");
  if (!bk_json_string_is(doc, bk_json_get(doc, asset, "version"), "2.0"))
    return bk_error_set(err, "%s: not a glTF 2.0 file (no asset.version \"2.0\")", name);
  uint32_t ours = bk_json_get(doc, bk_json_get(doc, asset, "extras"), "breakables");
  if (bk_json_type_of(doc, ours) != BK_JSON_OBJECT)
    return bk_error_set(
        err, "%s: not a Breakables export (no asset.extras.breakables); fracture it with --mesh instead",
        name);
  uint64_t version = 0;
  if (!get_index(doc, ours, "version", UINT32_MAX, &version))
    return bk_error_set(err, "%s: corrupt: asset.extras.breakables.version is missing or not a whole number",
                        name);
  // Version 1 kept the bonds and moments as JSON numbers; its tree is found the same way.
  if (version < 1 || version > BK_GLTF_EXTRAS_VERSION)
    return bk_error_set(err, "%s: Breakables glTF extras version %llu is not supported (expected 1 to %d)",
                        name, (unsigned long long)version, BK_GLTF_EXTRAS_VERSION);
  if (bk_json_get(doc, ours, "mtree") == BK_JSON_NONE)
    return bk_error_set(err,
                        "%s: exported without its mesh tree (--gltf-no-tree): it does not load back; export "
                        "it again with the tree",
                        name);
  uint64_t view_index = 0, buffer_index = 0, offset = 0, length = 0;
  if (!get_index(doc, bk_json_get(doc, ours, "mtree"), "bufferView", UINT32_MAX, &view_index))
    return bk_error_set(
        err, "%s: corrupt: asset.extras.breakables.mtree.bufferView is missing or not an index", name);
  uint32_t views = bk_json_get(doc, 0, "bufferViews");
  uint32_t view = bk_json_at(doc, views, (uint32_t)view_index);
  if (bk_json_type_of(doc, view) != BK_JSON_OBJECT)
    return bk_error_set(err, "%s: corrupt: the mesh tree's bufferView %llu is not among the %u bufferViews",
                        name, (unsigned long long)view_index, bk_json_count(doc, views));
  uint32_t offset_value = bk_json_get(doc, view, "byteOffset");
  if (!get_index(doc, view, "buffer", UINT32_MAX, &buffer_index) ||
      !get_index(doc, view, "byteLength", UINT64_MAX, &length) ||
      (offset_value != BK_JSON_NONE && !bk_json_uint(doc, offset_value, UINT64_MAX, &offset)))
    return bk_error_set(err, "%s: corrupt: bufferView %llu has no valid buffer, byteOffset or byteLength",
                        name, (unsigned long long)view_index);
  uint32_t buffers = bk_json_get(doc, 0, "buffers");
  uint32_t buffer = bk_json_at(doc, buffers, (uint32_t)buffer_index);
  uint64_t declared = 0;
  if (buffer_index > UINT32_MAX || bk_json_type_of(doc, buffer) != BK_JSON_OBJECT ||
      !get_index(doc, buffer, "byteLength", UINT64_MAX, &declared))
    return bk_error_set(
        err, "%s: corrupt: bufferView %llu names buffer %llu, which is missing or has no byteLength", name,
        (unsigned long long)view_index, (unsigned long long)buffer_index);

  const uint8_t* bytes = NULL;
  size_t available = 0;
  uint8_t* decoded = NULL;
  uint32_t uri = bk_json_get(doc, buffer, "uri");
  if (uri == BK_JSON_NONE) {
    if (buffer_index != 0 || !bin)
      return bk_error_set(err, "%s: corrupt: buffer %llu has no uri and there is no GLB binary chunk", name,
                          (unsigned long long)buffer_index);
    bytes = bin;
    available = bin_size;
  } else {
    const bk_json_value* u = &doc->values[uri];
    size_t prefix = strlen(BK_GLTF_DATA_URI);
    if (u->type != BK_JSON_STRING || u->length < prefix ||
        memcmp(doc->text + u->start, BK_GLTF_DATA_URI, prefix) != 0)
      return bk_error_set(
          err, "%s: buffer %llu is not an embedded base64 data URI (Breakables exports keep it inside)", name,
          (unsigned long long)buffer_index);
    if (!decode_base64(doc->text + u->start + prefix, u->length - prefix, &decoded, &available))
      return bk_error_set(err, "%s: corrupt: buffer %llu's data URI is not valid base64", name,
                          (unsigned long long)buffer_index);
    bytes = decoded;
  }
  bool ok = true;
  if (declared > available)
    ok = bk_error_set(err, "%s: truncated: buffer %llu says %llu bytes, %zu are there", name,
                      (unsigned long long)buffer_index, (unsigned long long)declared, available);
  else if (offset > declared || length > declared - offset)
    ok = bk_error_set(err, "%s: corrupt: bufferView %llu spans bytes %llu to %llu of a %llu-byte buffer",
                      name, (unsigned long long)view_index, (unsigned long long)offset,
                      (unsigned long long)offset + length, (unsigned long long)declared);
  if (ok) {
    char inner[300];
    snprintf(inner, sizeof inner, "%s: embedded mesh tree", name);
    ok = bk_mesh_tree_load_memory(bytes + offset, (size_t)length, inner, out, err);
  }
  bk_free(decoded);
  if (!ok) return false;
  // The JSON's own counts must describe the tree it carries.
  uint64_t nodes = 0, leaves = 0;
  if (!get_index(doc, ours, "node_count", UINT32_MAX, &nodes) ||
      !get_index(doc, ours, "leaf_count", UINT32_MAX, &leaves) || nodes != out->node_count ||
      leaves != out->leaf_count) {
    bk_error_set(err,
                 "%s: corrupt: asset.extras.breakables counts (%llu nodes, %llu leaves) are not the embedded "
                 "tree's (%u nodes, %u leaves)",
                 name, (unsigned long long)nodes, (unsigned long long)leaves, out->node_count,
                 out->leaf_count);
    bk_mesh_tree_free(out);
    memset(out, 0, sizeof *out);
    return false;
  }
  return true;
}

bool bk_mesh_tree_load_gltf_memory(const void* data, size_t size, const char* name, bk_mesh_tree* out,
                                   bk_error* err) {
  memset(out, 0, sizeof *out);
  const uint8_t* bytes = data;
  const char* json = (const char*)data;
  size_t json_size = size;
  const uint8_t* bin = NULL;
  size_t bin_size = 0;
  if (size == 0) return bk_error_set(err, "%s: empty file, not glTF", name);
  if (size >= 4 && load_u32le(bytes) == BK_GLB_MAGIC) {
    if (!split_glb(bytes, size, name, &json, &json_size, &bin, &bin_size, err)) return false;
  } else if (bytes[0] != '{' && bytes[0] != ' ' && bytes[0] != '\n' && bytes[0] != '\r' && bytes[0] != '\t') {
    return bk_error_set(err, "%s: not glTF (neither a GLB header nor JSON)", name);
  }
  // Only what the loader reads is stored (counted first, allocated once):
  // the rest of a document is checked, not kept, so its size costs nothing.
  static const char* const kept[] = {"asset", "bufferViews", "buffers", NULL};
  static const bk_json_limits limits = {BK_JSON_MAX_VALUES, 0, kept, false};
  bk_json_doc doc = {0};
  char why[160];
  if (!bk_json_parse_limited(json, json_size, &limits, &doc, why, sizeof why))
    return bk_error_set(err, "%s: corrupt glTF JSON: %s", name, why);
  bool ok = load_from_json(&doc, bin, bin_size, name, out, err);
  bk_json_free(&doc);
  return ok;
}

bool bk_mesh_tree_load_gltf(const char* path, bk_mesh_tree* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  void* contents = NULL;
  size_t size = 0;
  if (!bk_file_read(path, GLTF_MAX_FILE_BYTES, "4 GiB", &contents, &size, err)) return false;
  bool ok = bk_mesh_tree_load_gltf_memory(contents, size, path, out, err);
  bk_free(contents);
  return ok;
}
