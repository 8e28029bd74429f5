// Model import: the format told by the extension, the file's size and
// first bytes checked, then OBJ and PLY files to this library's own readers
// (bk_obj_parse, bk_import_ply) and every other format (glTF 2.0, FBX,
// Collada, STL, ...) to assimp (model_import_assimp.c; a build without
// assimp refuses them in one line, model_import_none.c).
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bk_geom.h"
#include "model_import.h"

bk_import_def bk_default_import_def(void) {
  return (bk_import_def){.node = NULL,
                         .max_triangles = 1u << 24,
                         .max_vertices = 1u << 25,
                         .max_file_bytes = BK_IMPORT_MAX_FILE_BYTES};
}

// The extension of `path` in lower case ("" if none or too long).
static void extension_of(const char* path, char out[16]) {
  out[0] = '\0';
  const char* dot = strrchr(path, '.');
  const char* slash = strrchr(path, '/');
  if (!dot || (slash && slash > dot) || strlen(dot + 1) >= 16) return;
  size_t i = 0;
  for (const char* c = dot + 1; *c; ++c)
    out[i++] = (char)tolower((unsigned char)*c);
  out[i] = '\0';
}

static bool extension_supported(const char* ext) {
  static const char list[] = BK_IMPORT_EXTENSIONS;
  if (!ext[0]) return false;
  size_t n = strlen(ext);
  for (const char* s = list; (s = strstr(s, ext)) != NULL; s += n)
    if ((s == list || s[-1] == ' ') && (s[n] == ' ' || s[n] == '\0')) return true;
  return false;
}

bool bk_model_import_supports(const char* path) {
  char ext[16];
  extension_of(path, ext);
  return extension_supported(ext);
}

static const char* limit_text(uint64_t bytes, char* buffer, size_t size) {
  if (bytes >= (1u << 30) && bytes % (1u << 30) == 0)
    snprintf(buffer, size, "%llu GiB", (unsigned long long)(bytes >> 30));
  else if (bytes >= (1u << 20) && bytes % (1u << 20) == 0)
    snprintf(buffer, size, "%llu MiB", (unsigned long long)(bytes >> 20));
  else
    snprintf(buffer, size, "%llu bytes", (unsigned long long)bytes);
  return buffer;
}

static void begin(bk_mesh* out, bk_import_info* info, const char* format) {
  memset(out, 0, sizeof *out);
  memset(info, 0, sizeof *info);
  info->metres_per_unit = 1.0;
  if (strcmp(format, "obj") == 0)
    snprintf(info->format, sizeof info->format, "obj");
  else
    snprintf(info->format, sizeof info->format, "assimp:%s", format);
}

static bool import_memory(const void* data, size_t size, const char* format, const char* name,
                          const bk_import_def* def_in, bk_mesh* out, bk_import_info* info, bk_error* err) {
  bk_import_def def = def_in ? *def_in : bk_default_import_def();
  name = name ? name : "model";
  char ext[16];
  snprintf(ext, sizeof ext, "%s", format ? format : "");
  for (char* c = ext; *c; ++c)
    *c = (char)tolower((unsigned char)*c);
  begin(out, info, ext);
  if (!extension_supported(ext))
    return bk_error_set(err, "%s: unsupported model format '%.15s' (supported: %s)", name, ext,
                        BK_IMPORT_EXTENSIONS);
  char limit[32];
  if (size > def.max_file_bytes || size > UINT_MAX)
    return bk_error_set(
        err, "%s: file larger than %s, refusing to load", name,
        limit_text(def.max_file_bytes < UINT_MAX ? def.max_file_bytes : UINT_MAX, limit, sizeof limit));
  if (size == 0 || !data) return bk_error_set(err, "%s: empty file", name);
  if (strcmp(ext, "obj") == 0) {
    if (def.node) return bk_error_set(err, "%s: node selection is not supported for OBJ files", name);
    bk_obj_materials* materials = bk_calloc(1, sizeof *materials);
    bool ok = bk_obj_parse_materials(data, size, name, out, materials, err);
    if (ok) ok = bk_import_obj_materials(info, out, materials, NULL, err);
    bk_free(materials);
    return ok;
  }
  size_t head = size < BK_IMPORT_PRECHECK_BYTES ? size : BK_IMPORT_PRECHECK_BYTES;
  if (!bk_import_precheck(name, ext, data, head, size, err) ||
      !bk_import_precheck_content(name, ext, data, size, size, err))
    return false;
  if (strcmp(ext, "ply") == 0) {
    if (def.node) return bk_error_set(err, "%s: node selection is not supported for PLY files", name);
    return bk_import_ply(data, size, name, &def, out, info, err);
  }
  return bk_import_assimp_memory(data, size, ext, name, &def, out, info, err);
}

// Reads the first `bytes` of the file (at most its size, which is within
// def.max_file_bytes) for bk_import_precheck_content.
static bool precheck_content(const char* path, const char* ext, uint64_t bytes, uint64_t file_size,
                             bk_error* err) {
  FILE* f = bk_file_open_read(path, NULL, err);
  if (!f) return false;
  char* data = bk_alloc((size_t)bytes);
  size_t got = fread(data, 1, (size_t)bytes, f);
  fclose(f);
  bool ok = got == bytes ? bk_import_precheck_content(path, ext, data, got, file_size, err)
                         : bk_error_set(err, "%s: cannot read: the file changed while it was read", path);
  bk_free(data);
  return ok;
}

static bool import_file(const char* path, const bk_import_def* def_in, bk_mesh* out, bk_import_info* info,
                        bk_error* err) {
  bk_import_def def = def_in ? *def_in : bk_default_import_def();
  char ext[16];
  extension_of(path, ext);
  begin(out, info, ext);
  if (!extension_supported(ext))
    return bk_error_set(err, "%s: unsupported model format '%s' (supported: %s)", path,
                        ext[0] ? ext : "no extension", BK_IMPORT_EXTENSIONS);
  // The same checks and wording as bk_file_read, before assimp opens it.
  // Only a regular file is opened (a FIFO would block here, and in assimp, forever).
  uint64_t file_size = 0;
  FILE* f = bk_file_open_read(path, &file_size, err);
  if (!f) return false;
  char* head = bk_alloc(BK_IMPORT_PRECHECK_BYTES);
  size_t head_size = fread(head, 1, BK_IMPORT_PRECHECK_BYTES, f);
  fclose(f);
  bool plausible = bk_import_precheck(path, ext, head, head_size, file_size, err);
  uint64_t content = plausible ? bk_import_precheck_content_bytes(ext, head, head_size, file_size) : 0;
  bk_free(head);
  if (!plausible) return false;
  char limit[32];
  if (file_size > def.max_file_bytes)
    return bk_error_set(err, "%s: file larger than %s, refusing to load", path,
                        limit_text(def.max_file_bytes, limit, sizeof limit));
  if (file_size == 0) return bk_error_set(err, "%s: empty file", path);
  if (content > 0 && !precheck_content(path, ext, content, file_size, err)) return false;
  if (strcmp(ext, "obj") == 0 || strcmp(ext, "ply") == 0) { // our own readers
    bool ply = ext[0] == 'p';
    if (def.node)
      return bk_error_set(err, "%s: node selection is not supported for %s files", path, ply ? "PLY" : "OBJ");
    void* data = NULL;
    size_t length = 0;
    if (!bk_file_read(path, BK_IMPORT_MAX_FILE_BYTES, "1 GiB", &data, &length, err)) return false;
    bk_obj_materials* materials = bk_calloc(1, sizeof *materials);
    bool ok = ply ? bk_import_ply(data, length, path, &def, out, info, err)
                  : bk_obj_parse_materials(data, length, path, out, materials, err);
    if (ok && !ply && !bk_import_obj_materials(info, out, materials, path, err)) {
      bk_mesh_free(out); // on failure *out is zeroed
      ok = false;
    }
    bk_free(materials);
    bk_free(data);
    return ok;
  }
  return bk_import_assimp_file(path, ext, &def, out, info, err);
}

bool bk_model_import_memory(const void* data, size_t size, const char* format, const char* name,
                            const bk_import_def* def, bk_mesh* out, bk_import_info* info_out, bk_error* err) {
  bk_import_info scratch;
  bk_import_info* info = info_out ? info_out : &scratch;
  return bk_import_settle_info(import_memory(data, size, format, name, def, out, info, err), info,
                               info_out != NULL);
}

bool bk_model_import(const char* path, const bk_import_def* def, bk_mesh* out, bk_import_info* info_out,
                     bk_error* err) {
  bk_import_info scratch;
  bk_import_info* info = info_out ? info_out : &scratch;
  return bk_import_settle_info(import_file(path, def, out, info, err), info, info_out != NULL);
}
