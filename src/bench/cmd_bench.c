// breakables bench: the measurements of the thesis's chapter 6 (fracture
// speed, meshes, maximum fragment count, the runtime cost of a break in
// bench_runtime.c) plus scaling (bench_runtime.c), the asset pipeline
// (bench_assets.c), the fracture patterns (bench_patterns.c), structural
// stress (bench_stress.c), the physics budget (bench_budget.c) and
// refinement at the impact (bench_refine.c, bench_refine_wall.c), written
// to a directory as a Markdown report with CSV tables and gnuplot plots
// (bench_report.c), and printed as tables.
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "bench_report.h"
#include "commands.h"
#include "scene_run.h"

static const char* const bench_usage =
    "usage: breakables bench [--quick] [--only N] [--out DIR] [--seed S]\n"
    "\n"
    "Runs the tests of the thesis's chapter 6 and writes DIR/report.md (command,\n"
    "machine, build, date, every table, the plots and answers to the thesis's\n"
    "questions), one CSV file per table and PNG plots drawn from the CSV files by\n"
    "gnuplot (skipped, with a note, when gnuplot is not on PATH). The tables are\n"
    "also printed.\n"
    "\n"
    "  1. fracture speed: a cube into 2, 4, ... fragments, median of several runs\n"
    "  2. meshes: cube, torus, eggshell and bunny into 256 fragments\n"
    "  3. maximum fragments: watertightness and volume error of a cube, level by level\n"
    "  4. runtime: an anchored wall and a free cube hit by one projectile; the cost\n"
    "     of the break and of later steps, mesh-tree colliders against plain BCRB\n"
    "  5. scaling: 1, 4 and 16 walls of 256 fragments hit at the same time\n"
    "  6. asset pipeline: the cube of 4096 fragments exported to .glb and loaded\n"
    "     back, and a torus of 100,000 triangles imported from a .glb (assimp),\n"
    "     against issue 15's targets (export under 1 s, import under 0.5 s)\n"
    "  7. fracture patterns: planes, voronoi, clustered and radial on the bunny, brick\n"
    "     and planes on the wall, into 64 to 4096 pieces: time, slivers, sizes\n"
    "  8. structural stress: walls of 256 to 4096 fragments, the stress solve's cost\n"
    "     per call after a hit and at rest, against the bond count\n"
    "  9. physics budget: the showcase shot by a 40-shot volley (512 pieces), 16 walls\n"
    "     of 1024 fragments shot in the same step and a cube of 4096 fragments\n"
    "     shattered, each without a budget and with one (10 ms for the volley, 8 ms\n"
    "     for the others): step and physics time p50, p95 and max, the budget's tiers,\n"
    "     the mass retired, and the debris' mass and momentum over the first second\n"
    "     after each hit against the run without a budget\n"
    " 10. refinement at the impact: a fragment of about 10,000 triangles refined\n"
    "     into 32 pieces where it is hit, the calling thread's cost a step (on a\n"
    "     worker and synchronous) and the steps until its pieces have bodies; the\n"
    "     wall of 64 fragments refined where it is shot against the walls of 64\n"
    "     and 1024: memory, load time, bodies, fragments near the shots, physics\n"
    "\n"
    "options:\n"
    "  --quick     a short run (under a minute): fracture speed up to 1024 fragments,\n"
    "              maximum fragments up to 2048, runtime up to 256, 1 and 4 walls,\n"
    "              the export with a cube of 1024 fragments, the patterns at 64 and\n"
    "              1024 pieces, stress on walls of 256 and 1024, the budget on the showcase\n"
    "              at 256 pieces with 20 shots, 4 walls and a cube of 1024, refinement on\n"
    "              a torus of 9,600 triangles in 4 arcs and the walls shot twice in 90 steps.\n"
    "              The full run goes to 65536, 65536, 4096, 16 walls, 4096 fragments and\n"
    "              4096 pieces, and refines 40 arcs of 10,000 triangles (minutes).\n"
    "  --only N    run section N alone, 1..10 (default: all)\n"
    "  --out DIR   output directory, created if missing (default: bench-out);\n"
    "              files of the same names in it are replaced\n"
    "  --seed S    fracture seed of every mesh, 0..18446744073709551615 (default: 3000)\n"
    "  -h, --help  show this help\n"
    "\n"
    "Mesh trees of sections 4, 5 and 10 (its walls) are cached like those of\n"
    "'breakables sim'.\n";

enum {
  MAX_RUNS = 5, ///< timed builds per fracture measurement
};

// ---------------------------------------------------------------- small statistics

/// Slope of log(y) over log(x) by least squares: the exponent of y ~ x^k.
static double log_log_slope(const double* x, const double* y, uint32_t count) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (uint32_t i = 0; i < count; ++i) {
    double lx = log(x[i]), ly = log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  double d = count * sxx - sx * sx;
  return count >= 2 && d > 0.0 ? (count * sxy - sx * sy) / d : 0.0;
}

// ---------------------------------------------------------------- fracture measurements

/// Timed builds per measurement: more for small counts, where timing is noisy and cheap.
static uint32_t fracture_runs(const bench* b, uint32_t pieces) {
  if (b->quick) return pieces <= 256 ? 3 : 1;
  return pieces <= 1024 ? 5 : pieces <= 8192 ? 3 : 1;
}

/// Builds the tree `runs` times, keeping the last; median and fastest build time.
static bool timed_build(const bk_mesh* source, uint32_t pieces, uint64_t seed, uint32_t runs,
                        bk_mesh_tree* tree, double* median_ms, double* min_ms, bk_error* err) {
  double times[MAX_RUNS] = {0};
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  for (uint32_t r = 0; r < runs && r < MAX_RUNS; ++r) {
    bk_mesh_tree_free(tree);
    double start = app_now_ms();
    if (!bk_mesh_tree_build(source, &desc, tree, err)) return false;
    times[r] = app_now_ms() - start;
  }
  uint32_t count = runs < MAX_RUNS ? runs : MAX_RUNS;
  *min_ms = times[0];
  for (uint32_t r = 1; r < count; ++r)
    *min_ms = fmin(*min_ms, times[r]);
  *median_ms = app_median(times, count);
  return true;
}

static uint32_t leaf_triangles(const bk_mesh_tree* tree) {
  uint32_t sum = 0;
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    sum += bk_mesh_tree_leaf(tree, l)->mesh.triangle_count;
  return sum;
}

// ---------------------------------------------------------------- 1. fracture speed

static bool section_fracture_speed(const bench* b) {
  static const bench_column columns[] = {{"fragments", "fragments"}, {"leaves", "leaves"},
                                         {"nodes", "nodes"},         {"leaf_triangles", "leaf triangles"},
                                         {"runs", "runs"},           {"ms_median", "median ms"},
                                         {"ms_min", "fastest ms"},   {"us_per_fragment", "us/fragment"}};
  uint32_t cap = b->quick ? 1024 : 65536;
  bench_section(
      b, "1. Fracture speed",
      "Time to build the mesh tree of a unit cube (slicing, caps, face simplification, hull "
      "separation, bonds) for 2, 4, 8, ... fragments: the median of several builds (fewer for large "
      "counts, see *runs*), with the tree's size.");
  bk_mesh cube = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bench_table t = bench_table_make("fracture_speed", columns, sizeof columns / sizeof *columns);
  double counts[20] = {0}, times[20] = {0}, ms_256 = 0.0, ms_4096 = 0.0, triangles_per_leaf = 0.0;
  uint32_t levels = 0;
  bool ok = true;
  for (uint32_t pieces = 2; ok && pieces <= cap; pieces *= 2) {
    bk_mesh_tree tree = {0};
    bk_error err = {0};
    double ms = 0.0, fastest = 0.0;
    uint32_t runs = fracture_runs(b, pieces);
    ok = timed_build(&cube, pieces, b->seed, runs, &tree, &ms, &fastest, &err);
    if (!ok) {
      fprintf(stderr, "breakables bench: cube into %u fragments: %s\n", pieces, err.message);
      break;
    }
    uint32_t triangles = leaf_triangles(&tree);
    bench_table_cell(&t, "%u", pieces);
    bench_table_cell(&t, "%u", tree.leaf_count);
    bench_table_cell(&t, "%u", tree.node_count);
    bench_table_cell(&t, "%u", triangles);
    bench_table_cell(&t, "%u", runs);
    bench_table_cell(&t, "%.4g", ms);
    bench_table_cell(&t, "%.4g", fastest);
    bench_table_cell(&t, "%.3g", 1000.0 * ms / tree.leaf_count);
    counts[levels] = pieces;
    times[levels++] = ms;
    triangles_per_leaf = (double)triangles / tree.leaf_count;
    if (pieces == 256) ms_256 = ms;
    if (pieces == 4096) ms_4096 = ms;
    bk_mesh_tree_free(&tree);
  }
  bk_mesh_free(&cube);
  ok = ok && bench_table_write(b, &t);
  bench_table_free(&t);
  if (!ok) return false;

  double last_count = counts[levels - 1], last_ms = times[levels - 1];
  bench_script s = {0};
  bench_script_add(
      &s,
      "set title 'Building the mesh tree of a cube'\nset xlabel 'fragments'\nset ylabel 'time (ms)'\n"
      "plot 'fracture_speed.csv' using 'fragments':'ms_median' with linespoints pt 7 "
      "title 'median build time', \\\n"
      "     %.6g*x with lines dt 2 lc rgb 'gray50' title 'linear (same time per fragment)'",
      last_ms / last_count);
  if (!bench_plot(b, "fracture_speed", "Fracture time against fragment count (log-log)", 800, 540, &s))
    return false;

  // The growth exponent over the counts where fixed costs no longer dominate.
  uint32_t first = 0;
  while (first + 2 < levels && counts[first] < 64)
    ++first;
  double slope = log_log_slope(counts + first, times + first, levels - first);
  bench_say(
      b,
      "**How long does the modeller take for a given number of fragments?** The thesis asked because "
      "every parameter change in the editor starts the modeller over. Here a cube becomes %.0f fragments in "
      "%.4g ms",
      last_count, last_ms);
  if (ms_4096 > 0.0 && last_count != 4096) bench_say(b, " (4096 fragments: %.4g ms)", ms_4096);
  bench_say(
      b,
      ", %.3g us per fragment. From %.0f fragments on, the time grows as fragments^%.2f (%s): the largest "
      "piece is split next and faces stay lean (a fragment keeps %.1f triangles on average), so a cut "
      "costs about the same at any depth. The 256 fragments of the thesis's mesh test take %.3g ms, so "
      "an editor change is redrawn %s.\n",
      1000.0 * last_ms / last_count, counts[first], slope,
      slope < 1.15 ? "close to linear" : "faster than linear", triangles_per_leaf, ms_256,
      ms_256 < 100.0 ? "at once" : "after a short wait");
  return true;
}

// ---------------------------------------------------------------- 2. meshes

/// How even a tree's fragments are.
typedef struct leaf_sizes {
  double spread;           ///< largest over smallest leaf volume
  uint32_t tiny;           ///< leaves under 1% of the mean leaf volume
  double smallest;         ///< smallest leaf volume over the source volume
  uint32_t smallest_hulls; ///< pieces the cut that made the smallest leaf left (2 = a plain split)
} leaf_sizes;

static leaf_sizes measure_leaf_sizes(const bk_mesh_tree* tree) {
  leaf_sizes sizes = {0};
  double source = tree->nodes[0].moments.v, largest = 0.0;
  uint32_t smallest = 0;
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    double v = bk_mesh_tree_leaf(tree, l)->moments.v;
    largest = fmax(largest, v);
    if (v < bk_mesh_tree_leaf(tree, smallest)->moments.v) smallest = l;
    if (v < 0.01 * source / tree->leaf_count) sizes.tiny++;
  }
  const bk_mesh_tree_node* node = bk_mesh_tree_leaf(tree, smallest);
  sizes.spread = largest / node->moments.v;
  sizes.smallest = node->moments.v / source;
  sizes.smallest_hulls = node->parent == BK_NULL_INDEX ? 1 : tree->nodes[node->parent].child_count;
  return sizes;
}

static bool section_meshes(const bench* b) {
  static const bench_column columns[] = {{"mesh", "mesh"},
                                         {"source_triangles", "source triangles"},
                                         {"leaves", "fragments"},
                                         {"runs", "runs"},
                                         {"ms_median", "median ms"},
                                         {"leaf_triangles", "leaf triangles"},
                                         {"volume_spread", "largest/smallest leaf"},
                                         {"tiny_leaves", "leaves < 1% of mean"},
                                         {"watertight", "watertight"}};
  static const char* const meshes[] = {"cube", "torus", "eggshell", "bunny"};
  enum { MESH_COUNT = sizeof meshes / sizeof *meshes, MESH_PIECES = 256 };
  bench_section(
      b, "2. Meshes",
      "The thesis's four meshes of rising complexity, each into 256 fragments: build time (median), "
      "how even the fragments are (largest over smallest leaf volume, and the number of leaves under "
      "1% of the mean leaf volume), leaf triangles, and whether every node of the tree is closed.");
  bench_table t = bench_table_make("meshes", columns, sizeof columns / sizeof *columns);
  leaf_sizes sizes[MESH_COUNT] = {0};
  double ms[MESH_COUNT] = {0};
  bool watertight = true, ok = true;
  for (uint32_t m = 0; ok && m < MESH_COUNT; ++m) {
    bk_mesh source = {0};
    bk_mesh_tree tree = {0};
    bk_error err = {0};
    double fastest = 0.0;
    uint32_t runs = fracture_runs(b, MESH_PIECES);
    ok = app_load_mesh(meshes[m], &source, &err) &&
         timed_build(&source, MESH_PIECES, b->seed, runs, &tree, &ms[m], &fastest, &err);
    if (!ok) {
      fprintf(stderr, "breakables bench: %s into %u fragments: %s\n", meshes[m], MESH_PIECES, err.message);
    } else {
      bk_mesh_tree_stats st = bk_mesh_tree_measure(&tree);
      sizes[m] = measure_leaf_sizes(&tree);
      watertight = watertight && st.open_nodes == 0;
      bench_table_cell(&t, "%s", meshes[m]);
      bench_table_cell(&t, "%u", source.triangle_count);
      bench_table_cell(&t, "%u", tree.leaf_count);
      bench_table_cell(&t, "%u", runs);
      bench_table_cell(&t, "%.4g", ms[m]);
      bench_table_cell(&t, "%u", st.leaf_triangles);
      bench_table_cell(&t, "%.4g", sizes[m].spread);
      bench_table_cell(&t, "%u", sizes[m].tiny);
      bench_table_cell(&t, "%s", st.open_nodes == 0 ? "true" : "false");
    }
    bk_mesh_tree_free(&tree);
    bk_mesh_free(&source);
  }
  ok = ok && bench_table_write(b, &t);
  bench_table_free(&t);
  if (!ok) return false;
  bench_say(
      b,
      "**Does the modeller handle meshes of any complexity, and are the fragments even?** The thesis's "
      "modeller produced fragments for all four meshes but left clusters of very small fragments on "
      "protruding meshes such as the bunny. Here %s, built in %.3g (cube), %.3g (torus), %.3g (eggshell) "
      "and %.3g ms (bunny). The largest leaf holds %.3g times the volume of the smallest on the cube, %.3g "
      "on the torus, %.3g on the eggshell and %.3g on the bunny; the bunny has %u leaves under 1%% of the "
      "mean volume, the cube %u",
      watertight ? "every node of all four trees is watertight" : "SOME NODES ARE NOT WATERTIGHT", ms[0],
      ms[1], ms[2], ms[3], sizes[0].spread, sizes[1].spread, sizes[2].spread, sizes[3].spread, sizes[3].tiny,
      sizes[0].tiny);
  if (sizes[3].spread <= 2.0 * sizes[0].spread)
    bench_say(b, ": splitting the largest piece next keeps the bunny's fragments as even as the cube's");
  bench_say(b, ".");
  for (uint32_t m = 0; m < MESH_COUNT; ++m) {
    if (sizes[m].spread <= 100.0) continue;
    bench_say(b, " The %s has %u tiny leaves; its smallest (%.2g of the mesh's volume) ", meshes[m],
              sizes[m].tiny, sizes[m].smallest);
    if (sizes[m].smallest_hulls > 2)
      bench_say(b,
                "is one of %u hulls that a single cut made of one piece; such slivers are never split again, "
                "since the largest piece always goes first.",
                sizes[m].smallest_hulls);
    else
      bench_say(b, "comes from a plain two-way cut.");
  }
  bench_say(b, "\n");
  return true;
}

// ---------------------------------------------------------------- 3. maximum fragments

static bool section_max_fragments(const bench* b) {
  static const bench_column columns[] = {{"fragments", "fragments"},
                                         {"leaves", "leaves"},
                                         {"nodes", "nodes"},
                                         {"ms", "ms"},
                                         {"watertight", "watertight"},
                                         {"open_nodes", "open nodes"},
                                         {"volume_rel_error", "volume error"},
                                         {"child_volume_rel_error", "worst child volume error"}};
  static const double volume_tolerance = 1e-9;
  uint32_t cap = b->quick ? 2048 : 65536;
  bench_section(
      b, "3. Maximum fragments",
      "A cube into 2, 4, 8, ... fragments, one build per level, as in the thesis. Every node of the "
      "tree is checked for closure (each edge used once in each direction); the volume error compares "
      "the sum of the leaves' mesh volumes with the cube's, and the child error is the worst "
      "|sum of children - parent| / parent over the inner nodes. A level fails if the build fails, a "
      "node is open or the volume error exceeds 1e-9.");
  bk_mesh cube = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bench_table t = bench_table_make("max_fragments", columns, sizeof columns / sizeof *columns);
  char failure[600] = "";
  double worst_error = 0.0;
  for (uint32_t pieces = 2; pieces <= cap; pieces *= 2) {
    bk_mesh_tree tree = {0};
    bk_error err = {0};
    double ms = 0.0, fastest = 0.0;
    bool built = timed_build(&cube, pieces, b->seed, 1, &tree, &ms, &fastest, &err);
    bk_mesh_tree_stats st = bk_mesh_tree_measure(&tree);
    double error = built ? bench_leaf_volume_error(&tree) : NAN;
    bool good = built && st.open_nodes == 0 && error <= volume_tolerance;
    bench_table_cell(&t, "%u", pieces);
    bench_table_cell(&t, "%u", tree.leaf_count);
    bench_table_cell(&t, "%u", tree.node_count);
    bench_table_cell(&t, "%.4g", ms);
    bench_table_cell(&t, "%s", built && st.open_nodes == 0 ? "true" : "false");
    bench_table_cell(&t, "%u", st.open_nodes);
    bench_table_cell(&t, "%.2e", error);
    bench_table_cell(&t, "%.2e", built ? st.max_child_rel_error : NAN);
    if (built) worst_error = fmax(worst_error, error);
    if (!good && !failure[0])
      snprintf(failure, sizeof failure, "%u fragments (%s)", pieces,
               !built          ? err.message
               : st.open_nodes ? "open nodes"
                               : "volume error");
    bk_mesh_tree_free(&tree);
  }
  bk_mesh_free(&cube);
  bool ok = bench_table_write(b, &t);
  bench_table_free(&t);
  if (!ok) return false;
  if (failure[0]) {
    printf("  first failure: %s\n", failure);
    bench_say(b, "First failure: %s.\n\n", failure);
  } else {
    printf("  first failure: none up to %u\n", cap);
    bench_say(b, "First failure: none up to %u.\n\n", cap);
  }
  bench_say(b,
            "**How many fragments can the modeller make?** The thesis's modeller started failing at 2048 "
            "fragments of a cube: its edge linker compared vectors, and floating-point error broke the links "
            "once fragments got small. This one links cut edges by vertex index, so caps always close: ");
  if (failure[0])
    bench_say(b, "the first failure here is at %s; the worst volume error before it is %.2g.\n", failure,
              worst_error);
  else
    bench_say(b,
              "every level up to %u fragments is watertight, with a volume error of at most %.2g (double "
              "precision rounding), so no failure was found up to %u.\n",
              cap, worst_error, cap);
  return true;
}

// ---------------------------------------------------------------- the command

static int usage_error(const char* option, const char* what) {
  fprintf(stderr, "breakables bench: %s %s (see 'breakables bench --help')\n", option, what);
  return 2;
}

int cmd_bench(int argc, char** argv) {
  bench b = {.seed = 3000, .dir = "bench-out"};
  uint64_t only = 0;
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : NULL;
    if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
      fputs(bench_usage, stdout);
      return 0;
    } else if (strcmp(arg, "--quick") == 0) {
      b.quick = true;
    } else if (strcmp(arg, "--out") == 0 || strcmp(arg, "--seed") == 0 || strcmp(arg, "--only") == 0) {
      if (!value) return usage_error(arg, "needs a value");
      ++i;
      if (strcmp(arg, "--only") == 0) {
        if (!option_u64("bench", arg, value, 1, 10, &only)) return 2;
      } else if (strcmp(arg, "--out") == 0) {
        if (!*value) return usage_error(arg, "must not be empty");
        b.dir = value;
      } else if (!option_u64("bench", arg, value, 0, UINT64_MAX, &b.seed)) {
        return 2;
      }
    } else {
      fprintf(stderr, "breakables bench: unknown option '%s' (see 'breakables bench --help')\n", arg);
      return 2;
    }
  }
  if (!bench_make_directories(b.dir)) {
    fprintf(stderr, "breakables bench: cannot create directory %s: %s\n", b.dir, strerror(errno));
    return 1;
  }
  bench_output report = {0};
  if (!bench_output_open(&b, "report.md", &report)) return 1;
  b.report = report.file;
  b.terminal = bench_gnuplot_terminal();
  if (!b.terminal)
    fprintf(stderr, "breakables bench: gnuplot (with a png or pngcairo terminal) is not on PATH: "
                    "writing the CSV files and the report without plots\n");
  bench_report_header(&b, argc, argv);
  double start = app_now_ms();
  bool (*const sections[])(const bench*) = {
      section_fracture_speed, section_meshes,       section_max_fragments,  bench_section_runtime,
      bench_section_scaling,  bench_section_assets, bench_section_patterns, bench_section_stress,
      bench_section_budget,   bench_section_refine};
  bool ok = true;
  for (uint64_t i = 0; ok && i < sizeof sections / sizeof *sections; ++i)
    if (!only || only == i + 1) ok = sections[i](&b);
  if (ok) bench_say(&b, "\n---\n\nThe whole run took %.0f s.\n", (app_now_ms() - start) / 1000.0);
  ok = bench_output_close(&report, ok) && ok;
  if (!ok) return 1;
  printf("\nwrote %s/report.md (%.0f s)\n", b.dir, (app_now_ms() - start) / 1000.0);
  return 0;
}
