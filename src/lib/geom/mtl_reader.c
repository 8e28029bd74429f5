// MTL files (the materials an OBJ file's `mtllib` names): per material its
// diffuse colour (`Kd`, with `d` or `Tr` for opacity) and diffuse texture
// (`map_Kd`, options before the file name skipped). Everything else in the
// format (specular, illumination models, other maps) is skipped.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bk_geom.h"
#include "model_import.h"

static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Reads up to `max` numbers; each must be finite and in [0, 1] (colours).
static int read_unit_numbers(const char* s, float* out, int max) {
  int count = 0;
  while (count < max) {
    while (is_blank(*s))
      ++s;
    if (*s == '\0') break;
    char* end = NULL;
    double v = strtod(s, &end);
    if (end == s || !(v >= 0.0 && v <= 1.0)) return -1;
    out[count++] = (float)v;
    s = end;
  }
  return count;
}

// map_Kd [-option values...] file: options start with '-'; the file name is
// what follows the last of them (it may hold blanks).
static const char* texture_name(const char* s) {
  // Each option's arity: how many values follow it.
  static const struct {
    const char* name;
    int values;
  } options[] = {{"-blendu", 1}, {"-blendv", 1},  {"-bm", 1},  {"-boost", 1}, {"-cc", 1},
                 {"-clamp", 1},  {"-imfchan", 1}, {"-mm", 2},  {"-o", 3},     {"-s", 3},
                 {"-t", 3},      {"-texres", 1},  {"-type", 1}};
  for (;;) {
    while (is_blank(*s))
      ++s;
    if (*s != '-') return s;
    size_t n = 0;
    while (s[n] && !is_blank(s[n]))
      ++n;
    int values = -1;
    for (size_t i = 0; i < sizeof options / sizeof options[0]; ++i)
      if (strlen(options[i].name) == n && strncmp(s, options[i].name, n) == 0) values = options[i].values;
    if (values < 0) return s; // not an option: a file name starting with '-'
    s += n;
    for (int v = 0; v < values; ++v) {
      while (is_blank(*s))
        ++s;
      char* end = NULL;
      (void)strtod(s, &end);
      if (end == s) { // fewer values than the option takes (-o 1 file.png): what is left is the name
        if (*s != '-') break;
      } else {
        s = end;
      }
    }
  }
}

void bk_mtl_parse(const char* text, size_t length, const bk_obj_materials* materials,
                  bk_import_material* list) {
  char line[1024];
  int32_t current = -1; // the material the statements belong to (-1: one the OBJ does not use)
  size_t pos = 0;
  bk_c_locale locale = bk_c_locale_begin();
  while (pos < length) {
    size_t start = pos;
    while (pos < length && text[pos] != '\n' && text[pos] != '\r')
      ++pos;
    size_t n = pos - start;
    while (pos < length && (text[pos] == '\n' || text[pos] == '\r'))
      ++pos;
    if (n >= sizeof line) continue; // longer than any statement we read
    memcpy(line, text + start, n);
    line[n] = '\0';
    if (memchr(line, '\0', n)) continue;
    char* hash = strchr(line, '#');
    if (hash) *hash = '\0';
    size_t end = strlen(line);
    while (end > 0 && is_blank(line[end - 1]))
      line[--end] = '\0';
    const char* s = line;
    while (is_blank(*s))
      ++s;
    size_t k = 0;
    while (s[k] && !is_blank(s[k]))
      ++k;
    const char* rest = s + k;
    while (is_blank(*rest))
      ++rest;
    if (k == 6 && strncmp(s, "newmtl", 6) == 0) {
      current = -1;
      for (uint32_t i = 0; i < materials->count; ++i)
        if (strncmp(materials->names[i], rest, BK_OBJ_MATERIAL_NAME - 1) == 0 &&
            strlen(rest) == strlen(materials->names[i]))
          current = (int32_t)i;
      continue;
    }
    if (current < 0) continue;
    bk_import_material* m = &list[current];
    float v[3] = {0, 0, 0};
    if (k == 2 && strncmp(s, "Kd", 2) == 0) {
      int count = read_unit_numbers(rest, v, 3);
      if (count == 3) memcpy(m->base_color, v, sizeof v);
      if (count == 1) m->base_color[0] = m->base_color[1] = m->base_color[2] = v[0];
    } else if (k == 1 && s[0] == 'd') {
      if (read_unit_numbers(rest, v, 1) == 1) m->base_color[3] = v[0];
    } else if (k == 2 && strncmp(s, "Tr", 2) == 0) {
      if (read_unit_numbers(rest, v, 1) == 1) m->base_color[3] = 1.0f - v[0];
    } else if (k == 6 && strncmp(s, "map_Kd", 6) == 0) {
      const char* file = texture_name(rest);
      if (*file) snprintf(m->texture, sizeof m->texture, "%s", file);
    }
  }
  bk_c_locale_end(&locale);
}

// ---------------------------------------------------------------- an OBJ file's materials

/// MTL files larger than this are not read (the materials stay white, untextured).
#define MTL_MAX_FILE_BYTES ((uint64_t)1 << 24)

bool bk_import_obj_materials(bk_import_info* info, const bk_mesh* mesh, const bk_obj_materials* materials,
                             const char* obj_path, bk_error* err) {
  uint32_t count = materials->count ? materials->count : 1;
  info->materials = count;
  info->materials_merged = materials->merged;
  info->material_list = bk_calloc(count, sizeof(bk_import_material));
  for (uint32_t i = 0; i < count; ++i) {
    bk_import_material* m = &info->material_list[i];
    for (int k = 0; k < 4; ++k)
      m->base_color[k] = 1.0f;
    if (i < materials->count) snprintf(m->name, sizeof m->name, "%s", materials->names[i]);
  }
  bk_import_count_triangles(info, mesh);
  // The library is looked for beside the OBJ file (memory imports have none);
  // one that is missing or unreadable leaves the materials white.
  if (!obj_path || !materials->library[0] || materials->library[0] == '/') return true;
  const char* slash = strrchr(obj_path, '/');
  int dir = slash ? (int)(slash - obj_path) : 0;
  char path[BK_IMPORT_TEXT_MAX * 2];
  if (snprintf(path, sizeof path, "%.*s%s%s", dir, obj_path, slash ? "/" : "", materials->library) >=
      (int)sizeof path)
    return true;
  void* text = NULL;
  size_t length = 0;
  bk_error why = {{0}};
  struct stat st = {0};
  if (!bk_file_read(path, MTL_MAX_FILE_BYTES, "16 MiB", &text, &length, &why))
    return stat(path, &st) != 0 || S_ISREG(st.st_mode) ||
           bk_error_set(err, "%s (mtllib of %s)", why.message, obj_path);
  bk_mtl_parse(text, length, materials, info->material_list);
  bk_free(text);
  // Texture names are relative to the OBJ file's directory.
  for (uint32_t i = 0; i < count; ++i) {
    bk_import_material* m = &info->material_list[i];
    if (!m->texture[0] || m->texture[0] == '/') continue;
    char joined[BK_IMPORT_TEXT_MAX * 2];
    int n = snprintf(joined, sizeof joined, "%.*s%s%s", dir, obj_path, slash ? "/" : "", m->texture);
    if (n > 0 && (size_t)n < sizeof m->texture)
      memcpy(m->texture, joined, (size_t)n + 1);
    else
      m->texture[0] = '\0'; // a path too long to keep is no path
  }
  return true;
}
