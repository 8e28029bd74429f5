// What a user's own input may not do: a fracture map of any shape stays
// within the memory guard and the piece cap (refused before decoding when
// it cannot fit), a face flipped or given twice never becomes a fragment
// that encloses no volume, every option takes the GNU form --name=value,
// and --json reports what was asked for.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "bk_fracture.h"
#include "ensure.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/cli_trust_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"

#include "under_sanitizer.h"

/// The cut-out's samples, about 3,000 on any map of at least as many pixels.
#define SAMPLES_MAX 3000u
#define SAMPLES_MIN 2600u

// ---------------------------------------------------------------- maps

// A grey map of w x h whose pixel (x, y) is a line when line(x, y)
// (malloc'd).
static unsigned char* draw_map(uint32_t w, uint32_t h, bool (*line)(uint32_t x, uint32_t y)) {
  unsigned char* pixels = malloc((size_t)w * h);
  ENSURE(pixels != NULL);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      pixels[(size_t)y * w + x] = line(x, y) ? 255 : 0;
  return pixels;
}

static void write_map(const char* path, uint32_t w, uint32_t h, bool (*line)(uint32_t x, uint32_t y)) {
  unsigned char* pixels = draw_map(w, h, line);
  ENSURE(stbi_write_png(path, (int)w, (int)h, 1, pixels, (int)w));
  free(pixels);
}

// Every other row a line: one region per two rows.
static bool odd_rows(uint32_t x, uint32_t y) { return (void)x, y % 2 == 1; }
// Rows or columns of period 4, two pixels open and two of line.
static bool row_stripes(uint32_t x, uint32_t y) { return (void)x, y % 4 >= 2; }
static bool column_stripes(uint32_t x, uint32_t y) { return (void)y, x % 4 >= 2; }
// Squares of 2 x 2 open pixels on a grid of lines 2 wide.
static bool grid_cells(uint32_t x, uint32_t y) { return x % 4 >= 2 || y % 4 >= 2; }

// The grid holds its budget on every shape of map: as many samples on a
// 2 x 8,388,608 map (112,173 before) as on a square one.
static void test_cutout_grid(void) {
  static const uint32_t shapes[][2] = {{2, 8388608}, {8388608, 2}, {4096, 4096}, {3, 1100},  {1100, 3},
                                       {1000, 10},   {10, 1000},   {256, 256},   {2, 65536}, {65536, 2},
                                       {9, 334},     {7, 100000},  {512, 256},   {3000, 1},  {64, 47}};
  for (size_t i = 0; i < sizeof shapes / sizeof *shapes; ++i) {
    uint32_t w = shapes[i][0], h = shapes[i][1], columns = 0, rows = 0;
    uint32_t n = bk_cutout_grid(w, h, &columns, &rows);
    ENSURE_MSG(n == columns * rows && columns <= w && rows <= h, "%u x %u: %u x %u", w, h, columns, rows);
    if ((uint64_t)w * h >= SAMPLES_MAX)
      ENSURE_MSG(n >= SAMPLES_MIN && n <= SAMPLES_MAX, "%u x %u map: %u samples", w, h, n);
    else
      ENSURE_MSG(n == w * h, "%u x %u map: %u samples", w, h, n);
  }
}

// The 36 KiB map of 2 x 8,388,608 pixels: refused before decoding when the
// decoding cannot fit, and otherwise a fracture of at most the samples
// (the same as a square map's) in a bounded peak (3.9 GB and 112,173
// pieces before).
static void test_thin_map(void) {
  const char* path = BK_TEST_TMP "/trust_thin.png";
  write_map(path, 2, 8388608, odd_rows);
  expect_error(
      "fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP "/trust_thin.png' --max-memory 100", 1,
      "trust_thin.png: the 2 x 8388608 map needs about 144 MiB to decode and use, more than --max-memory "
      "allows (100 MiB)");
  // The estimate counts the map: its pixels and the cells of its samples.
  expect_error("fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP
               "/trust_thin.png' --max-memory 200",
               1, "the 2 x 8388608 cutout map on cube needs about ");
  run_result* r = run("fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP
                      "/trust_thin.png' --max-memory 1000 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  double pieces = json_number(r->out, "pieces"), peak = json_number(r->out, "peak_rss_mb");
  printf("  2 x 8388608 map: %.0f pieces, peak %.0f MiB\n", pieces, peak);
  ENSURE_MSG(pieces >= 2000 && pieces <= SAMPLES_MAX, "%.0f pieces", pieces);
  ENSURE_MSG(UNDER_SANITIZER || peak < 400.0, "peak %.0f MiB", peak);
  ENSURE_MSG(strstr(r->out, "\"pieces_requested\": null"), "%s", r->out);
  // Said, on stderr and in --json: the map has more regions than samples.
  const char* said = "trust_thin.png: the 2 x 8388608 map has 4194304 regions, more than its 3000 samples (a "
                     "piece each at most): the regions no sample falls in join their neighbours";
  ENSURE_MSG(strstr(r->err, said) && strstr(r->out, said), "%s%s", r->err, r->out);
  remove(path);
}

// The same content in maps of different shapes gives piece counts within
// 25% of each other (one piece per region a sample falls in; every map has
// more regions than samples).
static void test_map_shapes(void) {
  struct {
    const char* name;
    uint32_t w, h;
    bool (*line)(uint32_t, uint32_t);
  } maps[] = {
      {"rows", 2, 65536, row_stripes}, {"columns", 65536, 2, column_stripes}, {"grid", 512, 256, grid_cells}};
  double counts[3] = {0, 0, 0}, low = 1e300, high = 0;
  for (int i = 0; i < 3; ++i) {
    char path[512], args[1024];
    snprintf(path, sizeof path, "%s/trust_%s.png", BK_TEST_TMP, maps[i].name);
    write_map(path, maps[i].w, maps[i].h, maps[i].line);
    snprintf(args, sizeof args, "fracture --mesh cube --pattern cutout --cutout '%s' --json", path);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s: %s", args, r->err);
    counts[i] = json_number(r->out, "pieces");
    low = counts[i] < low ? counts[i] : low;
    high = counts[i] > high ? counts[i] : high;
    printf("  %s map %u x %u: %.0f pieces\n", maps[i].name, maps[i].w, maps[i].h, counts[i]);
    ENSURE_MSG(counts[i] <= SAMPLES_MAX, "%s: %.0f pieces", maps[i].name, counts[i]);
    remove(path);
  }
  ENSURE_MSG(high <= 1.25 * low, "piece counts %.0f, %.0f, %.0f", counts[0], counts[1], counts[2]);
}

// The estimate counts a map's cells, regions and pixels: above the peak
// `breakables fracture` measures (by less than 2.5 times) for a map of many
// regions and one of few, on a flat and a curved source.
static void test_map_estimate(void) {
  struct {
    const char* mesh;
    uint32_t w, h;
    bool (*line)(uint32_t, uint32_t);
  } cases[] = {
      {"cube", 2, 8388608, odd_rows}, {"torus", 2, 8388608, odd_rows}, {"torus", 64, 64, grid_cells}};
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    unsigned char* pixels = draw_map(cases[i].w, cases[i].h, cases[i].line);
    const char* path = BK_TEST_TMP "/trust_estimate.png";
    ENSURE(stbi_write_png(path, (int)cases[i].w, (int)cases[i].h, 1, pixels, (int)cases[i].w));
    bk_mesh source = {0};
    bk_shape shape = BK_SHAPE_CUBE;
    ENSURE(bk_shape_from_name(cases[i].mesh, &shape));
    bk_shape_build(shape, &source);
    bk_fracture_def d = bk_default_fracture_def();
    d.pattern = BK_PATTERN_CUTOUT;
    d.cutout_pixels = pixels, d.cutout_width = cases[i].w, d.cutout_height = cases[i].h;
    double estimate = (double)bk_mesh_tree_estimate_bytes(&source, &d) / 1048576.0;
    char args[512];
    snprintf(args, sizeof args, "fracture --mesh %s --pattern cutout --cutout '%s' --json", cases[i].mesh,
             path);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s: %s", args, r->err);
    double peak = json_number(r->out, "peak_rss_mb");
    printf("  %s, %u x %u map: estimate %.0f MiB, peak %.0f MiB\n", cases[i].mesh, cases[i].w, cases[i].h,
           estimate, peak);
    ENSURE_MSG(UNDER_SANITIZER || (estimate >= peak && estimate <= 2.5 * peak),
               "estimate %.1f, peak %.1f MiB", estimate, peak);
    bk_mesh_free(&source);
    free(pixels);
    remove(path);
  }
}

// ---------------------------------------------------------------- piece cap

// A flat source of separate bars crossed by one region: each sample's cell
// meets several bars, so it is several solids; the pieces still never
// outnumber the samples or the points.
static void test_piece_cap(void) {
  bk_mesh source = {0};
  for (int bar = 0; bar < 16; ++bar) {
    bk_mesh box = {0};
    bk_shape_build(BK_SHAPE_CUBE, &box);
    for (uint32_t i = 0; i < box.position_count; ++i)
      box.positions[i] =
          bk_v3(box.positions[i].x * 0.02 + bar * 0.0625, box.positions[i].y, box.positions[i].z * 0.1);
    bk_mesh_append(&source, &box);
    bk_mesh_free(&box);
  }
  // Cut-out along z with a map of one region: every sample cell spans bars.
  static uint8_t open_map[2 * 2];
  for (int p = 0; p < 6; ++p) {
    bk_fracture_def d = bk_default_fracture_def();
    d.pattern = (bk_fracture_pattern)p;
    d.pieces = 24;
    // Three points, in bars 0, 7 and 15: each cell holds several bars.
    bk_vec3 points[3] = {{0.0, 0.0, 0.0}, {7 * 0.0625, 0.0, 0.0}, {15 * 0.0625, 0.0, 0.0}};
    if (p == BK_PATTERN_CUTOUT) d.cutout_pixels = open_map, d.cutout_width = 2, d.cutout_height = 2;
    uint32_t cap = d.pieces;
    if (p == BK_PATTERN_VORONOI) d.seed_points = points, d.seed_point_count = 3, cap = 3;
    if (p == BK_PATTERN_CUTOUT) cap = 4; // a 2 x 2 map: 4 samples
    bk_mesh_tree tree = {0};
    bk_error err = {{0}};
    bool built = bk_mesh_tree_build(&source, &d, &tree, &err);
    printf("  %s: %s, %u pieces (at most %u)\n", bk_fracture_pattern_name(d.pattern),
           built ? "built" : err.message, built ? tree.leaf_count : 0, cap);
    if (built)
      ENSURE_MSG(tree.leaf_count <= cap, "%s: %u pieces, more than %u", bk_fracture_pattern_name(d.pattern),
                 tree.leaf_count, cap);
    bk_mesh_tree_free(&tree);
  }
  bk_mesh_free(&source);
}

// ---------------------------------------------------------------- zero volume

static const char* const cube_vertices =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n";
// The unit cube's 12 triangles, outward.
static const int cube_faces[12][3] = {{1, 4, 3}, {1, 3, 2}, {5, 6, 7}, {5, 7, 8}, {1, 2, 6}, {1, 6, 5},
                                      {2, 3, 7}, {2, 7, 6}, {3, 4, 8}, {3, 8, 7}, {4, 1, 5}, {4, 5, 8}};

// Writes the cube with face f flipped when flip[f], and the faces of
// `extra` (negative: flipped) after them.
static void write_cube(const char* name, const bool flip[12], const int* extra, int extra_count) {
  char text[2048];
  size_t n = (size_t)snprintf(text, sizeof text, "%s", cube_vertices);
  for (int f = 0; f < 12; ++f) {
    const int* v = cube_faces[f];
    n += (size_t)snprintf(text + n, sizeof text - n, "f %d %d %d\n", v[0], flip[f] ? v[2] : v[1],
                          flip[f] ? v[1] : v[2]);
  }
  for (int i = 0; i < extra_count; ++i) {
    const int* v = cube_faces[abs(extra[i]) - 1];
    bool turned = extra[i] < 0;
    n += (size_t)snprintf(text + n, sizeof text - n, "f %d %d %d\n", v[0], turned ? v[2] : v[1],
                          turned ? v[1] : v[2]);
  }
  write_file(name, text);
}

// Every leaf encloses a real share of the source, and the leaves add up to it.
static void check_leaves(const char* what, const bk_mesh_tree* tree, double source_volume) {
  // Above 1e-10 of the source (the zero-volume piece was 1e-18 of it; the
  // bunny's smallest chip at 64 pieces is 5e-9), and above what a sheet
  // of the leaf's own size encloses.
  double sum = 0.0;
  for (uint32_t i = 0; i < tree->leaf_count; ++i) {
    const bk_mesh_tree_node* leaf = bk_mesh_tree_leaf(tree, i);
    double v = leaf->moments.v;
    ENSURE_MSG(v > 1e-10 * source_volume && !bk_mesh_encloses_no_volume(&leaf->mesh, v),
               "%s: leaf %u of %u has volume %g", what, i, tree->leaf_count, v);
    sum += v;
  }
  ENSURE_MSG(fabs(sum - source_volume) <= 1e-9 * source_volume, "%s: leaves add up to %.17g of %.17g", what,
             sum, source_volume);
}

typedef struct cube_case {
  const char* file;
  bool flip[12];
  int extra[2];
  int extra_count;
  const char* warning;      ///< on stderr
  const char* json_warning; ///< in --json's warnings
} cube_case;

static const cube_case cube_cases[] = {
    {"trust_flip_quad.obj",
     {[2] = true, [3] = true},
     {0},
     0,
     "2 triangles were wound against their neighbours; turned",
     "turned 2 triangles wound against their neighbours"},
    {"trust_flip_one.obj",
     {[7] = true},
     {0},
     0,
     "1 triangle was wound against its neighbours; turned",
     "turned 1 triangle wound against their neighbours"},
    {"trust_dup_one.obj",
     {0},
     {7},
     1,
     "1 triangle was given twice; removed",
     "removed 1 triangle given twice"},
    {"trust_dup_quad.obj",
     {0},
     {3, 4},
     2,
     "2 triangles were given twice; removed",
     "removed 2 triangles given twice"},
    {"trust_dup_back.obj",
     {0},
     {-7},
     1,
     "enclosed no volume (a face closed against its own back",
     "removed 2 shells enclosing no volume (the first near ("},
};

// A cube with a face flipped or given twice (either way round): repaired
// with a warning on stderr and in --json, and fractured by every pattern
// into pieces that each enclose volume and add up to the cube.
static void test_zero_volume_faces(void) {
  for (size_t c = 0; c < sizeof cube_cases / sizeof *cube_cases; ++c) {
    const cube_case* k = &cube_cases[c];
    write_cube(k->file, k->flip, k->extra, k->extra_count);
    char args[1024];
    snprintf(args, sizeof args, "fracture --mesh '%s/%s' --pieces 8 --json", BK_TEST_TMP, k->file);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s: %s", args, r->err);
    ENSURE_MSG(strstr(r->err, k->warning), "%s: expected '%s' in %s", args, k->warning, r->err);
    ENSURE_MSG(json_number(r->out, "pieces") == 8 && strstr(r->out, k->json_warning),
               "%s: expected '%s' in %s", args, k->json_warning, r->out);
    // The library: repaired, then every pattern.
    char path[512];
    snprintf(path, sizeof path, "%s/%s", BK_TEST_TMP, k->file);
    bk_mesh source = {0};
    bk_error err = {{0}};
    ENSURE_MSG(bk_obj_load(path, &source, &err), "%s", err.message);
    bk_repair_info info = {0};
    ENSURE_MSG(bk_mesh_repair(&source, &info, &err), "%s: %s", k->file, err.message);
    ENSURE_MSG(info.shells == 1 && fabs(bk_mesh_volume(&source) - 1.0) < 1e-12, "%s: %u shells, volume %g",
               k->file, info.shells, bk_mesh_volume(&source));
    static uint8_t cross[16 * 16];
    for (int i = 0; i < 16 * 16; ++i)
      cross[i] = (i % 16 == 8 || i / 16 == 8) ? 255 : 0;
    for (int p = 0; p < 6; ++p) {
      bk_fracture_def d = bk_default_fracture_def();
      d.pattern = (bk_fracture_pattern)p;
      d.pieces = 8;
      if (p == BK_PATTERN_CUTOUT) d.cutout_pixels = cross, d.cutout_width = 16, d.cutout_height = 16;
      bk_mesh_tree tree = {0};
      ENSURE_MSG(bk_mesh_tree_build(&source, &d, &tree, &err), "%s, %s: %s", k->file,
                 bk_fracture_pattern_name(d.pattern), err.message);
      char what[128];
      snprintf(what, sizeof what, "%s, %s", k->file, bk_fracture_pattern_name(d.pattern));
      check_leaves(what, &tree, 1.0);
      bk_mesh_tree_free(&tree);
    }
    bk_mesh_free(&source);
  }
}

// The bunny with a patch of faces flipped comes back whole, and fractures
// as the bunny does.
static void test_bunny_flipped(void) {
  bk_mesh bunny = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_obj_load(BK_ASSET_DIR "/meshes/bunny.obj", &bunny, &err), "%s", err.message);
  double volume = bk_mesh_volume(&bunny);
  // Triangle 100 and those sharing a position with it.
  uint32_t p0 = bk_mesh_tri_position(&bunny, 100, 0), flipped = 0;
  for (uint32_t t = 0; t < bunny.triangle_count; ++t) {
    bool near = false;
    for (uint32_t k = 0; k < 3; ++k)
      near = near || bk_mesh_tri_position(&bunny, t, k) == p0;
    if (!near) continue;
    uint32_t swap = bunny.indices[3 * t + 1];
    bunny.indices[3 * t + 1] = bunny.indices[3 * t + 2];
    bunny.indices[3 * t + 2] = swap;
    flipped++;
  }
  bk_repair_info info = {0};
  ENSURE_MSG(bk_mesh_repair(&bunny, &info, &err), "%s", err.message);
  ENSURE_MSG(flipped > 2 && info.faces_turned == flipped && info.shells == 1 && info.sheets_removed == 0,
             "%u flipped, %u turned, %u shells", flipped, info.faces_turned, info.shells);
  ENSURE(fabs(bk_mesh_volume(&bunny) - volume) <= 1e-12 * fabs(volume));
  bk_fracture_def d = bk_default_fracture_def();
  d.pieces = 64;
  bk_mesh_tree tree = {0};
  ENSURE_MSG(bk_mesh_tree_build(&bunny, &d, &tree, &err), "%s", err.message);
  ENSURE(tree.leaf_count == 64);
  check_leaves("bunny", &tree, volume);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&bunny);
}

// A caller's source with a sheet beside the solid (no repair): a quad
// closed against its own back over the other diagonal, a hair from planar,
// so that it encloses 1.7e-13 (a positive volume, as the 1e-18 of the
// zero-volume fragment was). No leaf is the sheet: a cut piece that is
// joins its nearest neighbour, and the tree says so.
static void test_sheet_never_a_leaf(void) {
  bk_mesh source = {0};
  bk_shape_build(BK_SHAPE_CUBE, &source);
  double volume = bk_mesh_volume(&source);
  bk_corner c = {0};
  uint32_t q[4];
  const bk_vec3 corners[4] = {{2, 0, 0}, {3, 0, 0}, {3, 1, 1e-12}, {2, 1, 0}};
  for (int k = 0; k < 4; ++k) {
    c.position = bk_mesh_add_position(&source, corners[k]);
    q[k] = bk_mesh_add_corner(&source, &c);
  }
  bk_mesh_add_triangle(&source, q[0], q[1], q[2], 0, 0); // the front over 0-2
  bk_mesh_add_triangle(&source, q[0], q[2], q[3], 0, 0);
  bk_mesh_add_triangle(&source, q[0], q[3], q[1], 0, 0); // the back over 1-3
  bk_mesh_add_triangle(&source, q[1], q[3], q[2], 0, 0);
  ENSURE_MSG(bk_mesh_is_closed(&source) && bk_mesh_volume(&source) > volume, "volume %.17g",
             bk_mesh_volume(&source));
  for (int p = 0; p < 2; ++p) {
    bk_fracture_def d = bk_default_fracture_def();
    d.pieces = 8;
    d.pattern = p ? BK_PATTERN_BRICK : BK_PATTERN_PLANES;
    bk_mesh_tree tree = {0};
    bk_error err = {{0}};
    ENSURE_MSG(bk_mesh_tree_build(&source, &d, &tree, &err), "%s", err.message);
    {
      double sum = 0.0;
      for (uint32_t i = 0; i < tree.leaf_count; ++i) {
        const bk_mesh_tree_node* leaf = bk_mesh_tree_leaf(&tree, i);
        ENSURE_MSG(!bk_mesh_encloses_no_volume(&leaf->mesh, leaf->moments.v), "%s: leaf %u of %u: volume %g",
                   bk_fracture_pattern_name(d.pattern), i, tree.leaf_count, leaf->moments.v);
        sum += leaf->moments.v;
      }
      ENSURE(fabs(sum - bk_mesh_volume(&source)) <= 1e-9 * volume);
      // The sheet joined a piece, with a warning; the pieces are all there.
      char text[400] = "";
      ENSURE_MSG(tree.leaf_count == 8 && tree.shortfall.sheets_merged > 0 &&
                     bk_mesh_tree_shortfall_text(&tree, text, sizeof text) &&
                     strstr(text, "enclosed no volume (a face of the source closed against its own back) and "
                                  "joined the nearest piece"),
                 "%s: %u pieces, %u sheets merged: %s", bk_fracture_pattern_name(d.pattern), tree.leaf_count,
                 tree.shortfall.sheets_merged, text);
    }
    bk_mesh_tree_free(&tree);
  }
  // The repair removes the sheet, with where it was.
  bk_repair_info info = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_repair(&source, &info, &err), "%s", err.message);
  ENSURE_MSG(info.sheets_removed == 1 && info.shells == 1 && source.triangle_count == 12 &&
                 source.position_count == 8,
             "%u sheets, %u shells, %u triangles", info.sheets_removed, info.shells, source.triangle_count);
  ENSURE(fabs(info.sheet_near.x - 2.5) < 1e-12 && fabs(info.sheet_near.y - 0.5) < 1e-12);
  bk_mesh_free(&source);
}

// ---------------------------------------------------------------- options

// `--name=value` is `--name value` for every command: the same output or
// the same one-line error, exit status and all.
static void test_option_equals(void) {
  static const char* const pairs[][2] = {
      {"sim --pieces=65537", "sim --pieces 65537"},
      {"play --pieces=0", "play --pieces 0"},
      {"editor --pieces=65537", "editor --pieces 65537"},
      {"bench --only=99", "bench --only 99"},
      {"fracture --mesh=cube --seed=abc", "fracture --mesh cube --seed abc"},
      {"fracture --pieces=", "fracture --pieces ''"},
      {"sim --scene=nowhere", "sim --scene nowhere"},
      {"fracture --mesh=cube --pattern=cutout --cutout=" BK_TEST_TMP "/missing.png",
       "fracture --mesh cube --pattern cutout --cutout " BK_TEST_TMP "/missing.png"},
  };
  static char first_err[1 << 14];
  for (size_t i = 0; i < sizeof pairs / sizeof *pairs; ++i) {
    run_result* r = run(pairs[i][0]);
    int status = r->status;
    snprintf(first_err, sizeof first_err, "%s", r->err);
    r = run(pairs[i][1]);
    ENSURE_MSG(status == r->status && strcmp(first_err, r->err) == 0 && status != 0,
               "'%s' (%d: %s) vs '%s' (%d: %s)", pairs[i][0], status, first_err, pairs[i][1], r->status,
               r->err);
  }
  run_result* r = run("fracture --mesh=cube --pieces=5 --seed=7 --texture-scale=0.5 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "pieces") == 5 && json_number(r->out, "seed") == 7 &&
                 json_number(r->out, "texture_scale") == 0.5,
             "%s%s", r->out, r->err);
  // A flag given a value is not taken for the flag.
  r = run("fracture --mesh cube --json=1");
  ENSURE_MSG(r->status == 2, "%d: %s", r->status, r->err);
}

// With --seeds the points are what was asked for, not the --pieces default.
static void test_pieces_requested(void) {
  write_file("trust_seeds.txt", "0.2 0.2 0.2\n-0.2 0.2 0.2\n0.2 -0.2 0.2\n0.2 0.2 -0.2\n-0.2 -0.2 -0.2\n");
  run_result* r =
      run("fracture --mesh cube --pattern=voronoi --seeds=" BK_TEST_TMP "/trust_seeds.txt --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(json_number(r->out, "pieces_requested") == 5 && json_number(r->out, "pieces_made") == 5, "%s",
             r->out);
  r = run("fracture --mesh cube --pieces 12 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "pieces_requested") == 12, "%s", r->out);
}

int main(void) {
  RUN(test_cutout_grid);
  RUN(test_thin_map);
  RUN(test_map_shapes);
  RUN(test_map_estimate);
  RUN(test_piece_cap);
  RUN(test_zero_volume_faces);
  RUN(test_bunny_flipped);
  RUN(test_sheet_never_a_leaf);
  RUN(test_option_equals);
  RUN(test_pieces_requested);
  return 0;
}
