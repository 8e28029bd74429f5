// The fracture command's pattern options. One table names every option, the
// patterns it belongs to, the bk_fracture_def field it sets and its range:
// parsing enforces the range, --help states it, and the defaults shown are
// read from bk_default_fracture_def, so nothing is written down twice here.
// Where the library's own range is open (cluster_border > 0, brick_offset
// < 1, a brick length > 0) the table holds its closure and
// bk_fracture_def_validate refuses the bound itself, naming the field.
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "app.h"
#include "fracture_patterns.h"
#include "scene_run.h"
#include "seed_points.h"

// Fracture maps larger than this are refused before they are decoded (a
// 4096 x 4096 map of lines compresses to far less).
#define CUTOUT_FILE_MAX_BYTES ((uint64_t)1 << 26)

typedef enum option_kind {
  KIND_PATTERN, // a pattern name
  KIND_SEEDS,   // a seed-point file
  KIND_CUTOUT,  // a fracture map
  KIND_AXIS,    // x, y or z into a uint32_t field
  KIND_COUNT,   // a whole number into a uint32_t field
  KIND_NUMBER,  // a decimal number into a double field
  KIND_POINT,   // X,Y,Z into a bk_vec3 field, each coordinate in the range
} option_kind;

#define PATTERN(p) (1u << (p))
#define NOISE_PATTERNS                                                                                       \
  (PATTERN(BK_PATTERN_PLANES) | PATTERN(BK_PATTERN_VORONOI) | PATTERN(BK_PATTERN_CLUSTERED) |                \
   PATTERN(BK_PATTERN_RADIAL) | PATTERN(BK_PATTERN_CUTOUT))
#define FIELD(f) offsetof(bk_fracture_def, f)

typedef struct pattern_option {
  const char* name;
  const char* value; // the value's name in --help
  option_kind kind;
  uint32_t patterns; // PATTERN bits of the patterns it belongs to; 0 = every pattern
  size_t field;      // where it goes in bk_fracture_def (numbers, points, counts, axes)
  double min, max;   // the range of a number, a count or each coordinate of a point
  const char* help;  // lines of --help after the name; {range} and {default} are filled in
} pattern_option;

// Lengths and coordinates are in source units: sources are at most
// BK_FRACTURE_MAX_SIZE across (and imports keep coordinates within it).
static const pattern_option options_table[] = {
    {"--pattern", "NAME", KIND_PATTERN, 0, FIELD(pattern), 0, 0,
     "how the source is cut (default: {default}):\n"
     "planes     random planes through the largest piece\n"
     "voronoi    Voronoi cells of --pieces points spread through\n"
     "           the volume, or of the points of --seeds\n"
     "clustered  a few large chunks with finely broken borders\n"
     "radial     small pieces around --impact, larger further out\n"
     "brick      along the mortar of a brick bond, each brick\n"
     "           then cut into a few pieces\n"
     "cutout     the regions of a fracture map (--cutout)\n"
     "           projected through the source"},
    {"--seeds", "FILE", KIND_SEEDS, PATTERN(BK_PATTERN_VORONOI), FIELD(seed_points), 0, 0,
     "voronoi: one cell per point inside the source, read from a\n"
     "text file of 'x y z' lines ('#' comments and blank lines\n"
     "allowed); --pieces is then ignored (default: --pieces\n"
     "points spread through the volume)"},
    {"--clusters", "N", KIND_COUNT, PATTERN(BK_PATTERN_CLUSTERED), FIELD(clusters), 1, 1u << 20,
     "clustered: how many large chunks, {range} (default: {default})"},
    {"--cluster-border", "F", KIND_NUMBER, PATTERN(BK_PATTERN_CLUSTERED), FIELD(cluster_border), 0, 1,
     "clustered: width of a chunk's finely broken border, as a\n"
     "fraction of the source's size, {range}, not 0 (default: {default})"},
    {"--impact", "X,Y,Z", KIND_POINT, PATTERN(BK_PATTERN_RADIAL), FIELD(impact), -BK_FRACTURE_MAX_SIZE,
     BK_FRACTURE_MAX_SIZE,
     "radial: the impact point in the source's coordinates, each\n"
     "{range} (default: {default})"},
    {"--radial-falloff", "F", KIND_NUMBER, PATTERN(BK_PATTERN_RADIAL), FIELD(radial_falloff), 0, 1.4,
     "radial: how fast pieces grow with distance from the impact,\n"
     "{range} (0 = evenly; default: {default})"},
    {"--brick-size", "L,H,D", KIND_POINT, PATTERN(BK_PATTERN_BRICK), FIELD(brick_size), 0,
     BK_FRACTURE_MAX_SIZE,
     "brick: length (x), height (y) and depth (z) of one brick with\n"
     "its mortar, each {range}, L and H not 0 (D = 0: through the\n"
     "whole source; default: {default})"},
    {"--brick-origin", "X,Y,Z", KIND_POINT, PATTERN(BK_PATTERN_BRICK), FIELD(brick_origin),
     -BK_FRACTURE_MAX_SIZE, BK_FRACTURE_MAX_SIZE,
     "brick: a corner of one brick, each {range}\n"
     "(default: {default})"},
    {"--brick-offset", "F", KIND_NUMBER, PATTERN(BK_PATTERN_BRICK), FIELD(brick_offset), 0, 1,
     "brick: how far each course is shifted against the one below,\n"
     "as a fraction of the brick length, {range}, not 1\n"
     "(default: {default})"},
    {"--cutout", "FILE.png", KIND_CUTOUT, PATTERN(BK_PATTERN_CUTOUT), FIELD(cutout_pixels), 0, 0,
     "cutout: the fracture map, read as grey: pixels of 128 and\n"
     "above are lines, each region they enclose becomes a piece;\n"
     "the map is stretched over the source's bounds and sampled\n"
     "by about 3,000 points whatever its shape, at most one piece\n"
     "each (--pieces is ignored); a map that cannot be decoded\n"
     "within --max-memory is refused before it is"},
    {"--cutout-axis", "x|y|z", KIND_AXIS, PATTERN(BK_PATTERN_CUTOUT), FIELD(cutout_axis), 0, 2,
     "cutout: the axis the map is projected along (default: {default})"},
    {"--noise", "AMPLITUDE", KIND_NUMBER, NOISE_PATTERNS, FIELD(noise_amplitude), 0, BK_FRACTURE_MAX_SIZE,
     "planes, voronoi, clustered, radial, cutout: cut faces are displaced by\n"
     "coherent noise of this amplitude, in source units, {range}\n"
     "(0 = flat; default: {default})"},
    {"--noise-frequency", "F", KIND_NUMBER, NOISE_PATTERNS, FIELD(noise_frequency), 0, BK_FRACTURE_MAX_SIZE,
     "planes, voronoi, clustered, radial, cutout: noise waves per\n"
     "source unit, {range}, not 0 (default: {default})"},
    {"--threads", "N", KIND_COUNT, 0, FIELD(threads), 0, 1024,
     "threads the fracture may use, {range} (0 = every core; the\n"
     "tree is the same for any count: planes and brick split\n"
     "pieces ahead on them, the cell patterns build cells on them;\n"
     "default: {default})"},
};
enum { OPTION_COUNT = sizeof options_table / sizeof options_table[0] };

static const char axis_names[3] = {'x', 'y', 'z'};

// ---------------------------------------------------------------- text

void app_json_string(FILE* out, const char* text) {
  fputc('"', out);
  for (const unsigned char* c = (const unsigned char*)text; *c; ++c) {
    if (*c == '"' || *c == '\\')
      fprintf(out, "\\%c", *c);
    else if (*c < 0x20)
      fprintf(out, "\\u%04x", *c);
    else
      fputc(*c, out);
  }
  fputc('"', out);
}

void app_json_number(FILE* out, double value) {
  if (!isfinite(value)) {
    fputs("null", out);
    return;
  }
  char text[48] = "";
  format_number(value, text, sizeof text);
  fputs(text, out);
}

const char* app_json_text(char* text, size_t size, const char* format, double value) {
  if (!isfinite(value))
    snprintf(text, size, "null");
  else
    snprintf(text, size, format, value);
  return text;
}

// "radial", "voronoi, clustered or radial": the patterns of a PATTERN mask.
static void patterns_of(uint32_t patterns, char* out, size_t size) {
  uint32_t total = 0, written = 0;
  for (int p = 0; p < BK_PATTERN_COUNT; ++p)
    total += (patterns >> p) & 1;
  size_t used = 0;
  out[0] = 0;
  for (int p = 0; p < BK_PATTERN_COUNT; ++p)
    if ((patterns >> p) & 1)
      used = append_name(out, size, used, written++, total, bk_fracture_pattern_name((bk_fracture_pattern)p));
}

static void field_text(const pattern_option* o, const bk_fracture_def* def, char* out, size_t size) {
  const char* base = (const char*)def + o->field;
  char a[48] = "", b[48] = "", c[48] = "";
  if (o->kind == KIND_PATTERN) {
    snprintf(out, size, "%s", bk_fracture_pattern_name(def->pattern));
  } else if (o->kind == KIND_AXIS) {
    uint32_t axis = *(const uint32_t*)(const void*)base;
    snprintf(out, size, "%c", axis < 3 ? axis_names[axis] : '?');
  } else if (o->kind == KIND_COUNT) {
    snprintf(out, size, "%u", *(const uint32_t*)(const void*)base);
  } else if (o->kind == KIND_NUMBER) {
    format_number(*(const double*)(const void*)base, out, size);
  } else if (o->kind == KIND_POINT) {
    bk_vec3 p = *(const bk_vec3*)(const void*)base;
    format_number(p.x, a, sizeof a);
    format_number(p.y, b, sizeof b);
    format_number(p.z, c, sizeof c);
    snprintf(out, size, "%s,%s,%s", a, b, c);
  } else {
    snprintf(out, size, "none");
  }
}

static void range_text(const pattern_option* o, char* out, size_t size) {
  if (o->kind == KIND_COUNT) { // whole numbers in full, as option_u64 writes them
    snprintf(out, size, "%llu..%llu", (unsigned long long)o->min, (unsigned long long)o->max);
    return;
  }
  char low[48] = "", high[48] = "";
  format_number(o->min, low, sizeof low);
  format_number(o->max, high, sizeof high);
  snprintf(out, size, "%s..%s", low, high);
}

// ---------------------------------------------------------------- help

void pattern_options_help(FILE* out) {
  bk_fracture_def defaults = bk_default_fracture_def();
  fputs("\npattern options (an option of another pattern than the one chosen is refused):\n", out);
  for (int i = 0; i < OPTION_COUNT; ++i) {
    const pattern_option* o = &options_table[i];
    char head[64] = "", range[96] = "", fallback[96] = "";
    snprintf(head, sizeof head, "%s %s", o->name, o->value);
    range_text(o, range, sizeof range);
    field_text(o, &defaults, fallback, sizeof fallback);
    // A name too long for the column gets the text on the next line, as in the rest of --help.
    if (strlen(head) > 20)
      fprintf(out, "  %s\n%24s", head, "");
    else
      fprintf(out, "  %-22s", head);
    for (const char* p = o->help; *p; ++p) {
      if (strncmp(p, "{range}", 7) == 0) {
        fputs(range, out);
        p += 6;
      } else if (strncmp(p, "{default}", 9) == 0) {
        fputs(fallback, out);
        p += 8;
      } else if (*p == '\n') {
        fprintf(out, "\n%24s", "");
      } else {
        fputc(*p, out);
      }
    }
    fputc('\n', out);
  }
}

// ---------------------------------------------------------------- parsing

static pattern_option_result refuse(const char* option, const char* what) {
  fprintf(stderr, "breakables fracture: %s %s (see 'breakables fracture --help')\n", option, what);
  return BK_PATTERN_OPTION_REFUSED;
}

// X,Y,Z: exactly three plain decimal numbers, each in the option's range.
static bool parse_point(const pattern_option* o, const char* value, bk_vec3* out) {
  char parts[3][64] = {"", "", ""};
  const char* p = value;
  int count = 0;
  bool malformed = false;
  for (; count < 3; ++count) {
    size_t length = strcspn(p, ",");
    if (length >= sizeof parts[0]) malformed = true;
    snprintf(parts[count], sizeof parts[0], "%.*s", (int)length, p);
    p += length;
    if (*p != ',') break;
    ++p;
  }
  malformed = malformed || count != 2 || *p != 0;
  double xyz[3] = {0.0, 0.0, 0.0};
  bool in_range = true;
  for (int k = 0; k < 3 && !malformed; ++k) {
    if (parse_double(parts[k], o->min, o->max, &xyz[k])) continue;
    // A number out of range is told apart from one that is not a number.
    double any = 0.0;
    if (parse_double(parts[k], -DBL_MAX, DBL_MAX, &any))
      in_range = false;
    else
      malformed = true;
  }
  if (!malformed && in_range) {
    *out = bk_v3(xyz[0], xyz[1], xyz[2]);
    return true;
  }
  char shown[96] = "", range[96] = "";
  quote_text(value, shown, sizeof shown);
  range_text(o, range, sizeof range);
  fprintf(stderr, "breakables fracture: %s '%s' is %s (each %s)\n", o->name, shown,
          malformed ? "not three decimal numbers separated by commas" : "out of range", range);
  return false;
}

pattern_option_result app_pattern_option(const char* arg, const char* value, bk_fracture_def* def,
                                         pattern_options* options) {
  int index = -1;
  for (int i = 0; i < OPTION_COUNT && index < 0; ++i)
    if (strcmp(arg, options_table[i].name) == 0) index = i;
  if (index < 0) return BK_PATTERN_OPTION_NOT_MINE;
  const pattern_option* o = &options_table[index];
  if (!value) return refuse(arg, "needs a value");
  options->given |= 1u << index;
  char* field = (char*)def + o->field;
  switch (o->kind) {
  case KIND_PATTERN:
    if (!bk_fracture_pattern_from_name(value, &def->pattern)) {
      char shown[96] = "", list[128] = "";
      quote_text(value, shown, sizeof shown);
      patterns_of((1u << BK_PATTERN_COUNT) - 1, list, sizeof list);
      fprintf(stderr, "breakables fracture: unknown pattern '%s': use %s\n", shown, list);
      return BK_PATTERN_OPTION_REFUSED;
    }
    break;
  case KIND_SEEDS:
    options->seeds_path = value;
    break;
  case KIND_CUTOUT:
    options->cutout_path = value;
    break;
  case KIND_AXIS: {
    const char* at = strlen(value) == 1 ? memchr(axis_names, value[0], sizeof axis_names) : NULL;
    if (!at) return refuse(arg, "must be x, y or z");
    *(uint32_t*)(void*)field = (uint32_t)(at - axis_names);
    break;
  }
  case KIND_COUNT: {
    uint64_t count = 0;
    if (!option_u64("fracture", arg, value, (uint64_t)o->min, (uint64_t)o->max, &count))
      return BK_PATTERN_OPTION_REFUSED;
    *(uint32_t*)(void*)field = (uint32_t)count;
    break;
  }
  case KIND_NUMBER:
    if (!option_double("fracture", arg, value, o->min, o->max, (double*)(void*)field))
      return BK_PATTERN_OPTION_REFUSED;
    break;
  case KIND_POINT:
    if (!parse_point(o, value, (bk_vec3*)(void*)field)) return BK_PATTERN_OPTION_REFUSED;
    break;
  }
  return BK_PATTERN_OPTION_TAKEN;
}

// ---------------------------------------------------------------- files

// The fracture map: a PNG decoded as grey. Its size is checked by the
// library's rule before stb_image allocates the pixels.
static bool load_cutout(const char* path, bk_fracture_def* def, uint8_t** pixels, bk_error* err) {
  void* data = NULL;
  size_t size = 0;
  if (!bk_file_read(path, CUTOUT_FILE_MAX_BYTES, "64 MiB", &data, &size, err)) return false;
  const char* format = bk_image_format(data, size);
  int width = 0, height = 0, channels = 0;
  bool ok = false;
  if (!format || strcmp(format, "png") != 0) {
    bk_error_set(err, "%s: not a PNG file", path);
  } else if (!stbi_info_from_memory(data, (int)size, &width, &height, &channels)) {
    bk_error_set(err, "%s: broken PNG (%s)", path, stbi_failure_reason());
  } else {
    // A stand-in pointer lets bk_fracture_def_validate judge the map's size alone.
    static const uint8_t stand_in = 0;
    bk_fracture_def probe = *def;
    probe.cutout_pixels = &stand_in;
    probe.cutout_width = (uint32_t)width;
    probe.cutout_height = (uint32_t)height;
    bk_error size_err = {0};
    if (!bk_fracture_def_validate(&probe, &size_err)) {
      const char* why =
          strncmp(size_err.message, "fracture: ", 10) == 0 ? size_err.message + 10 : size_err.message;
      bk_error_set(err, "%s: %s", path, why);
    } else if (!app_check_map_memory(path, (uint32_t)width, (uint32_t)height, channels,
                                     stbi_is_16_bit_from_memory(data, (int)size) != 0, size, err)) {
      // refused before stb_image allocates the pixels
    } else {
      *pixels = stbi_load_from_memory(data, (int)size, &width, &height, &channels, 1);
      if (!*pixels)
        bk_error_set(err, "%s: broken PNG (%s)", path, stbi_failure_reason());
      else
        ok = true;
    }
  }
  free(data);
  if (!ok) return false;
  def->cutout_pixels = *pixels;
  def->cutout_width = (uint32_t)width;
  def->cutout_height = (uint32_t)height;
  return true;
}

int pattern_options_finish(pattern_options* options, bk_fracture_def* def) {
  char needed[96] = "";
  for (int i = 0; i < OPTION_COUNT; ++i) {
    const pattern_option* o = &options_table[i];
    if (!((options->given >> i) & 1) || o->patterns == 0 || ((o->patterns >> def->pattern) & 1)) continue;
    patterns_of(o->patterns, needed, sizeof needed);
    fprintf(stderr, "breakables fracture: %s needs --pattern %s (the pattern is %s)\n", o->name, needed,
            bk_fracture_pattern_name(def->pattern));
    return 2;
  }
  if (def->pattern == BK_PATTERN_CUTOUT && !options->cutout_path) {
    fputs("breakables fracture: --pattern cutout needs --cutout FILE.png\n", stderr);
    return 2;
  }
  bk_error err = {0};
  if (options->seeds_path) {
    if (!seed_points_load(options->seeds_path, &options->seed_points, &def->seed_point_count, &err)) {
      fprintf(stderr, "breakables fracture: %s\n", err.message);
      return 1;
    }
    def->seed_points = options->seed_points;
  }
  if (options->cutout_path && !load_cutout(options->cutout_path, def, &options->cutout_pixels, &err)) {
    fprintf(stderr, "breakables fracture: %s\n", err.message);
    return 1;
  }
  if (options->cutout_pixels) {
    // Every region is a piece only when a sample falls in it; a map of more
    // regions than samples is said to be, not cut into more pieces.
    uint32_t columns = 0, rows = 0, w = def->cutout_width, h = def->cutout_height;
    uint32_t samples = bk_cutout_grid(w, h, &columns, &rows);
    uint32_t regions = bk_cutout_regions(def->cutout_pixels, w, h);
    if (regions > samples) {
      snprintf(options->cutout_warning, sizeof options->cutout_warning,
               "%.200s: the %u x %u map has %u regions, more than its %u samples (a piece each at most): the "
               "regions no sample falls in join their neighbours",
               options->cutout_path, w, h, regions, samples);
    }
  }
  if (!bk_fracture_def_validate(def, &err)) {
    // The library's message names the field; its own prefix repeats ours.
    const char* why = strncmp(err.message, "fracture: ", 10) == 0 ? err.message + 10 : err.message;
    fprintf(stderr, "breakables fracture: %s (see 'breakables fracture --help')\n", why);
    return 2;
  }
  return 0;
}

void pattern_options_free(pattern_options* options) {
  free(options->seed_points);
  if (options->cutout_pixels) stbi_image_free(options->cutout_pixels);
  memset(options, 0, sizeof *options);
}

// ---------------------------------------------------------------- JSON

static void json_member(FILE* out, const pattern_option* o, const bk_fracture_def* used) {
  const char* base = (const char*)used + o->field;
  // Keys are the option names without dashes, in snake case ("radial_falloff").
  char key[32] = "";
  snprintf(key, sizeof key, "%s", o->name + 2);
  for (char* c = key; *c; ++c)
    if (*c == '-') *c = '_';
  if (strcmp(key, "noise") == 0) snprintf(key, sizeof key, "noise_amplitude");
  fprintf(out, ", \"%s\": ", key);
  if (o->kind == KIND_COUNT) {
    fprintf(out, "%u", *(const uint32_t*)(const void*)base);
  } else if (o->kind == KIND_NUMBER) {
    app_json_number(out, *(const double*)(const void*)base);
  } else if (o->kind == KIND_POINT) {
    bk_vec3 p = *(const bk_vec3*)(const void*)base;
    fputc('[', out);
    app_json_number(out, p.x);
    fputs(", ", out);
    app_json_number(out, p.y);
    fputs(", ", out);
    app_json_number(out, p.z);
    fputc(']', out);
  } else if (o->kind == KIND_AXIS) {
    uint32_t axis = *(const uint32_t*)(const void*)base;
    fprintf(out, "\"%c\"", axis < 3 ? axis_names[axis] : '?');
  }
}

void pattern_options_json(FILE* out, const bk_fracture_def* used, const pattern_options* options) {
  fputs(", \"pattern\": ", out);
  app_json_string(out, bk_fracture_pattern_name(used->pattern));
  for (int i = 0; i < OPTION_COUNT; ++i) {
    const pattern_option* o = &options_table[i];
    // --threads is not a pattern parameter; the rest belong to patterns.
    if (o->patterns == 0 || !((o->patterns >> used->pattern) & 1)) continue;
    if (o->kind == KIND_SEEDS) {
      // The points themselves are the file's; their count says what was used.
      fprintf(out, ", \"seed_points\": %u, \"seeds\": ", used->seed_point_count);
      if (options->seeds_path)
        app_json_string(out, options->seeds_path);
      else
        fputs("null", out);
    } else if (o->kind == KIND_CUTOUT) {
      fputs(", \"cutout\": ", out);
      app_json_string(out, options->cutout_path ? options->cutout_path : "");
      fprintf(out, ", \"cutout_width\": %u, \"cutout_height\": %u", used->cutout_width, used->cutout_height);
    } else {
      json_member(out, o, used);
    }
  }
}
