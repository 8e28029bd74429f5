// The fracture command's pattern options, run as a user would: --help with
// the library's defaults, the fragment quality in --json and the summary,
// the pattern parameters reported, and one-line errors naming the option,
// the file and line, or the library's field.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "bk_fracture.h"
#include "ensure.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/cli_patterns_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"

// Every option is described with the default bk_default_fracture_def gives.
static void test_help(void) {
  run_result* r = run("fracture --help");
  ENSURE(r->status == 0);
  bk_fracture_def d = bk_default_fracture_def();
  char expected[16][96];
  int n = 0;
  snprintf(expected[n++], sizeof expected[0], "(default: %s)", bk_fracture_pattern_name(d.pattern));
  snprintf(expected[n++], sizeof expected[0], "(default: %u)", d.clusters);
  snprintf(expected[n++], sizeof expected[0], "(default: %g)", d.cluster_border);
  snprintf(expected[n++], sizeof expected[0], "default: %g)", d.radial_falloff);
  snprintf(expected[n++], sizeof expected[0], "default: %g,%g,%g)", d.brick_size.x, d.brick_size.y,
           d.brick_size.z);
  snprintf(expected[n++], sizeof expected[0], "(default: %g)", d.brick_offset);
  snprintf(expected[n++], sizeof expected[0], "(default: %c)", "xyz"[d.cutout_axis]);
  snprintf(expected[n++], sizeof expected[0], "not 0 (default: %g)", d.noise_frequency);
  snprintf(expected[n++], sizeof expected[0], "(default: %u)", d.pieces);
  snprintf(expected[n++], sizeof expected[0], "(default: %llu)", (unsigned long long)d.seed);
  for (int i = 0; i < n; ++i)
    ENSURE_MSG(strstr(r->out, expected[i]) != NULL, "help lacks '%s'", expected[i]);
  const char* options[] = {"--pattern NAME",
                           "--seeds FILE",
                           "--clusters N",
                           "--cluster-border F",
                           "--impact X,Y,Z",
                           "--radial-falloff F",
                           "--brick-size L,H,D",
                           "--brick-origin X,Y,Z",
                           "--brick-offset F",
                           "--cutout FILE.png",
                           "--cutout-axis x|y|z",
                           "--noise AMPLITUDE",
                           "--noise-frequency F",
                           "--threads N",
                           "0..1.4",
                           "1..1048576",
                           "0..1024",
                           "sliver"};
  for (size_t i = 0; i < sizeof options / sizeof *options; ++i)
    ENSURE_MSG(strstr(r->out, options[i]) != NULL, "help does not describe %s", options[i]);
  for (int p = 0; p < BK_PATTERN_COUNT; ++p)
    ENSURE(strstr(r->out, bk_fracture_pattern_name((bk_fracture_pattern)p)) != NULL);
}

// The ranges --help states are the ones enforced, by the command or by the
// library (a stale help would be caught here): each bound stated is taken
// (unless the help says "not" it), a little beyond it is refused. Options
// that pass get as far as loading the mesh, which is missing on purpose.
static void test_help_ranges_hold(void) {
  static const struct {
    const char* option;
    const char* pattern;
    bool whole; // a count: beyond = bound +- 1
  } checks[] = {
      {"--clusters", "clustered", true},     {"--cluster-border", "clustered", false},
      {"--radial-falloff", "radial", false}, {"--brick-offset", "brick", false},
      {"--noise", "voronoi", false},         {"--noise-frequency", "voronoi", false},
      {"--noise", "planes", false},          {"--noise-frequency", "planes", false},
      {"--threads", "planes", true},
  };
  static char help[sizeof run_result_storage.out];
  snprintf(help, sizeof help, "%s", run("fracture --help")->out);
  for (size_t i = 0; i < sizeof checks / sizeof *checks; ++i) {
    char head[64];
    snprintf(head, sizeof head, "\n  %s ", checks[i].option);
    const char* text = strstr(help, head);
    ENSURE_MSG(text != NULL, "help lacks %s", checks[i].option);
    const char* end = strstr(text + 1, "\n  --");
    const char* dots = strstr(text, "..");
    ENSURE_MSG(dots && (!end || dots < end), "help states no range for %s", checks[i].option);
    const char* low_text = dots;
    while (low_text > text && low_text[-1] != ' ')
      --low_text;
    double low = strtod(low_text, NULL), high = strtod(dots + 2, NULL);
    size_t block = end ? (size_t)(end - text) : strlen(text);
    char body[1024];
    snprintf(body, sizeof body, "%.*s", (int)(block < sizeof body ? block : sizeof body - 1), text);
    bool open_low = strstr(body, ", not 0") != NULL, open_high = strstr(body, ", not 1") != NULL;
    double step = checks[i].whole ? 1.0 : fmax(1e-3, 1e-3 * fabs(high));
    const struct {
      double value;
      bool taken;
    } tries[] = {{low, !open_low},   {open_low ? low + step : low, true},    {low - step, false},
                 {high, !open_high}, {open_high ? high - step : high, true}, {high + step, false}};
    for (size_t t = 0; t < sizeof tries / sizeof *tries; ++t) {
      char args[256];
      snprintf(args, sizeof args, "fracture --mesh '%s/no_such_mesh.obj' --pattern %s %s %.17g", BK_TEST_TMP,
               checks[i].pattern, checks[i].option, tries[t].value);
      run_result* r = run(args);
      ENSURE_MSG(r->status == (tries[t].taken ? 1 : 2), "'%s' (help: %.*s): exit %d: %s", args, (int)block,
                 text, r->status, r->err);
      if (tries[t].taken) ENSURE_MSG(strstr(r->err, "no_such_mesh.obj"), "'%s': %s", args, r->err);
    }
  }
}

// The planes pattern on the cube: the pattern and the quality numbers are in
// --json, sane, and those of the library on the tree written.
static void test_json_quality(void) {
  run_result* r = run("fracture --mesh cube --pieces 64 --json --out '" BK_TEST_TMP "/planes64.mtree'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->out, "\"pattern\": \"planes\""), "%s", r->out);
  ENSURE(strstr(r->out, "\"pieces\": 64") && strstr(r->out, "\"watertight\": true")); // old keys kept
  double slivers = json_number(r->out, "slivers"), fraction = json_number(r->out, "sliver_fraction");
  double ratio = json_number(r->out, "volume_ratio_p95_p5");
  double min_aspect = json_number(r->out, "min_aspect"), median = json_number(r->out, "median_aspect");
  ENSURE_MSG(fraction >= 0.0 && fraction < 0.5 && fraction == slivers / 64.0, "%s", r->out);
  ENSURE_MSG(ratio >= 1.0 && ratio < 10.0, "%s", r->out);
  ENSURE(min_aspect > 0.0 && min_aspect <= median && median <= 1.0);
  // The planes pattern reports its noise (none here), no other pattern's parameters.
  ENSURE(!strstr(r->out, "\"clusters\"") && !strstr(r->out, "\"impact\""));
  ENSURE_MSG(strstr(r->out, "\"noise_amplitude\": 0") && json_number(r->out, "noise_frequency") > 0.0, "%s",
             r->out);
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_load(BK_TEST_TMP "/planes64.mtree", &tree, &err), "%s", err.message);
  bk_mesh_tree_quality q = bk_mesh_tree_measure_quality(&tree);
  bk_mesh_tree_free(&tree);
  // Numbers are written to read back exactly.
  ENSURE(q.slivers == slivers && q.sliver_fraction == fraction && q.volume_ratio_p95_p5 == ratio);
  ENSURE(q.min_aspect == min_aspect && q.median_aspect == median);
  // The summary has one line with them.
  r = run("fracture --mesh cube --pieces 64");
  ENSURE_MSG(r->status == 0 && strstr(r->out, "planes pattern: ") && strstr(r->out, " slivers (") &&
                 strstr(r->out, "p95/p5"),
             "%s", r->out);
}

static void test_pattern_errors(void) {
  run_result* r = run("fracture --pattern shatter");
  ENSURE_MSG(r->status == 2 && strstr(r->err, "unknown pattern 'shatter'"), "%s", r->err);
  for (int p = 0; p < BK_PATTERN_COUNT; ++p)
    ENSURE_MSG(strstr(r->err, bk_fracture_pattern_name((bk_fracture_pattern)p)), "%s", r->err);
  expect_error("fracture --pattern shatter", 2, "use planes, voronoi, clustered, radial, brick or cutout");
  expect_error("fracture --pattern", 2, "--pattern needs a value");
  // An option of another pattern names the option and the pattern it needs.
  expect_error("fracture --mesh cube --impact 0,0,0", 2, "--impact needs --pattern radial");
  expect_error("fracture --mesh cube --pattern voronoi --radial-falloff 0.5", 2,
               "--radial-falloff needs --pattern radial (the pattern is voronoi)");
  expect_error("fracture --seeds '" BK_TEST_TMP "/x.txt'", 2, "--seeds needs --pattern voronoi");
  expect_error("fracture --pattern radial --clusters 3", 2, "--clusters needs --pattern clustered");
  expect_error("fracture --brick-offset 0.25", 2, "--brick-offset needs --pattern brick");
  expect_error("fracture --pattern brick --noise 0.1", 2,
               "--noise needs --pattern planes, voronoi, clustered, radial or cutout (the pattern is brick)");
  expect_error("fracture --cutout-axis x", 2, "--cutout-axis needs --pattern cutout");
  expect_error("fracture --pattern cutout", 2, "--pattern cutout needs --cutout FILE.png");
  // Values are read strictly and within the ranges --help states.
  expect_error("fracture --pattern radial --radial-falloff nan", 2,
               "--radial-falloff 'nan' is not a decimal number (0..1.4)");
  expect_error("fracture --pattern radial --radial-falloff 4.5", 2,
               "--radial-falloff '4.5' is out of range (0..1.4)");
  expect_error("fracture --pattern radial --radial-falloff '1 '", 2,
               "--radial-falloff '1 ' is not a decimal number");
  expect_error("fracture --pattern radial --impact 1,2", 2,
               "--impact '1,2' is not three decimal numbers separated by commas (each -1e30..1e30)");
  expect_error("fracture --pattern radial --impact 1,2,3,", 2,
               "--impact '1,2,3,' is not three decimal numbers");
  expect_error("fracture --pattern radial --impact 1,inf,3", 2,
               "--impact '1,inf,3' is not three decimal numbers");
  expect_error("fracture --pattern radial --impact 1,2,3e31", 2, "--impact '1,2,3e31' is out of range");
  expect_error("fracture --pattern clustered --clusters 2x", 2,
               "--clusters '2x' is not a whole number (1..1048576)");
  expect_error("fracture --threads 1025", 2, "--threads '1025' is out of range (0..1024)");
  expect_error("fracture --pattern cutout --cutout-axis w", 2, "--cutout-axis must be x, y or z");
  // What only the library rules out reaches the user with the field it names.
  expect_error("fracture --pattern clustered --cluster-border 0", 2,
               "cluster_border must be in (0, 1] (got 0)");
  expect_error("fracture --pattern brick --brick-offset 1", 2, "brick_offset must be in [0, 1) (got 1)");
  expect_error("fracture --pattern brick --brick-size 0.2,0,0", 2, "brick_size must have a positive length");
  expect_error("fracture --pattern voronoi --noise-frequency 0", 2, "noise_frequency must be a positive");
}

// Seed files: a line that does not parse, a non-finite number or no point
// at all is one line naming the file and the line; good points make cells.
static void test_seeds(void) {
  write_file("bad_seeds.txt", "# x y z\n0 0 0\n0.1 0.2\n");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/bad_seeds.txt'", 1,
               "bad_seeds.txt:3: expected 3 numbers x y z, found 2");
  write_file("junk_seeds.txt", "0 0 0\n\n0.1 0.2 0.3junk\n");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/junk_seeds.txt'", 1,
               "junk_seeds.txt:3: '0.3junk' is not a finite decimal number");
  write_file("nan_seeds.txt", "0 0 0\n0 nan 0\n");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/nan_seeds.txt'", 1,
               "nan_seeds.txt:2: 'nan' is not a finite decimal number");
  write_file("big_seeds.txt", "0 0 1e400\n");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/big_seeds.txt'", 1,
               "big_seeds.txt:1: '1e400' is not a finite decimal number");
  write_file("four_seeds.txt", "0 0 0 0\n");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/four_seeds.txt'", 1,
               "four_seeds.txt:1: expected 3 numbers x y z, found more ('0')");
  write_file("empty_seeds.txt", "");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/empty_seeds.txt'", 1,
               "empty_seeds.txt: no points (the file is empty)");
  write_file("comment_seeds.txt", "# nothing\n\n  \t\n");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/comment_seeds.txt'", 1,
               "comment_seeds.txt: no points (only blank lines and comments)");
  expect_error("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP "/missing_seeds.txt'", 1,
               "missing_seeds.txt: cannot open");

  write_file("seeds.txt", "# four cells\n-0.25 -0.25 0\n0.25 -0.25 0   # a comment\r\n\n-0.25 0.25 0.1\n"
                          "0.25 0.25 -0.1");
  run_result* r = run("fracture --mesh cube --pattern voronoi --seeds '" BK_TEST_TMP
                      "/seeds.txt' --noise-frequency 4 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->out, "\"pattern\": \"voronoi\"") && json_number(r->out, "seed_points") == 4 &&
                 json_number(r->out, "pieces_made") == 4 && json_number(r->out, "noise_frequency") == 4 &&
                 json_number(r->out, "noise_amplitude") == 0 && strstr(r->out, "seeds.txt\""),
             "%s", r->out);
}

// A grey PNG with a cross of lines: four regions.
static void write_cross_png(const char* path) {
  enum { SIZE = 64 };
  static unsigned char pixels[SIZE * SIZE];
  for (int y = 0; y < SIZE; ++y)
    for (int x = 0; x < SIZE; ++x)
      pixels[y * SIZE + x] = (x == SIZE / 2 || y == SIZE / 2) ? 255 : 0;
  ENSURE(stbi_write_png(path, SIZE, SIZE, 1, pixels, SIZE));
}

static void test_cutout(void) {
  write_file("not_png.png", "GIF89a");
  expect_error("fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP "/not_png.png'", 1,
               "not_png.png: not a PNG file");
  write_file("truncated.png", "\x89PNG\r\n\x1a\n"); // the signature, then nothing
  expect_error("fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP "/truncated.png'", 1,
               "truncated.png: broken PNG");
  expect_error("fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP "/missing.png'", 1,
               "missing.png: cannot open");
  expect_error("fracture --mesh cube --cutout '" BK_TEST_TMP "/missing.png'", 2,
               "--cutout needs --pattern cutout");
  // A map the library refuses by its size, before it is decoded.
  static unsigned char big[8192 * 2049];
  ENSURE(stbi_write_png(BK_TEST_TMP "/too_big.png", 8192, 2049, 1, big, 8192));
  expect_error("fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP "/too_big.png'", 1,
               "too_big.png: cutout map 8192 x 2049 is too large");

  write_cross_png(BK_TEST_TMP "/cross.png");
  run_result* r = run("fracture --mesh cube --pattern cutout --cutout '" BK_TEST_TMP
                      "/cross.png' --cutout-axis y --json");
  // The cross's four regions are the four pieces.
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->out, "\"pattern\": \"cutout\"") && strstr(r->out, "\"cutout_axis\": \"y\"") &&
                 json_number(r->out, "cutout_width") == 64 && json_number(r->out, "cutout_height") == 64 &&
                 json_number(r->out, "pieces_made") == 4 && strstr(r->out, "\"watertight\": true"),
             "%s", r->out);
}

// The brick pattern on the wall, with its parameters reported.
static void test_brick_wall(void) {
  run_result* r =
      run("fracture --mesh wall --pieces 64 --pattern brick --brick-offset 0.25 --threads 2 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->out, "\"pattern\": \"brick\"") && strstr(r->out, "\"watertight\": true") &&
                 json_number(r->out, "pieces_made") == 64 && json_number(r->out, "brick_offset") == 0.25 &&
                 json_number(r->out, "volume_rel_error") < 1e-9,
             "%s", r->out);
  bk_fracture_def d = bk_default_fracture_def();
  char size[96];
  snprintf(size, sizeof size, "\"brick_size\": [%g, %g, %g]", d.brick_size.x, d.brick_size.y, d.brick_size.z);
  ENSURE_MSG(strstr(r->out, size) && strstr(r->out, "\"brick_origin\": [0, 0, 0]"), "%s", r->out);
  // Other patterns' parameters are not reported.
  ENSURE(!strstr(r->out, "\"clusters\"") && !strstr(r->out, "\"noise_amplitude\""));
  // The parameters given are the ones used.
  r = run("fracture --mesh wall --pieces 32 --pattern brick --brick-size 0.5,0.15,0 --brick-origin 0.1,0,-2 "
          "--json");
  ENSURE_MSG(r->status == 0 && strstr(r->out, "\"brick_size\": [0.5, 0.15, 0]") &&
                 strstr(r->out, "\"brick_origin\": [0.1, 0, -2]"),
             "%s%s", r->out, r->err);
  // Radial and clustered report theirs.
  r = run("fracture --mesh cube --pieces 32 --pattern radial --impact 0.5,0.25,-0.5 --radial-falloff 1.25 "
          "--json");
  ENSURE_MSG(r->status == 0 && strstr(r->out, "\"impact\": [0.5, 0.25, -0.5]") &&
                 json_number(r->out, "radial_falloff") == 1.25,
             "%s%s", r->out, r->err);
  r = run("fracture --mesh cube --pieces 32 --pattern clustered --clusters 3 --cluster-border 0.2 --json");
  ENSURE_MSG(r->status == 0 && json_number(r->out, "clusters") == 3 &&
                 json_number(r->out, "cluster_border") == 0.2,
             "%s%s", r->out, r->err);
}

int main(void) {
  RUN(test_help);
  RUN(test_help_ranges_hold);
  RUN(test_json_quality);
  RUN(test_pattern_errors);
  RUN(test_seeds);
  RUN(test_cutout);
  RUN(test_brick_wall);
  return 0;
}
