// breakables bench: the measurements of the thesis's chapter 6 (fracture
// speed, meshes, maximum fragment count, the runtime cost of a break) plus
// scaling, the asset pipeline (bench_assets.c) and the fracture patterns
// (bench_patterns.c), written to a directory as a Markdown report with CSV
// tables and gnuplot plots (bench_report.c), and printed as tables.
#include <errno.h>
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app.h"
#include "bench_report.h"

static const char* const bench_usage =
    "usage: breakables bench [--quick] [--out DIR] [--seed S]\n"
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
    "\n"
    "options:\n"
    "  --quick     a short run (under a minute): fracture speed up to 1024 fragments,\n"
    "              maximum fragments up to 2048, runtime up to 256, 1 and 4 walls,\n"
    "              the export with a cube of 1024 fragments, the patterns at 64 and\n"
    "              1024 pieces, stress on walls of 256 and 1024. The full run goes to 65536, 65536, 4096, 16 "
    "walls,\n"
    "              4096 fragments and 4096 pieces (minutes).\n"
    "  --out DIR   output directory, created if missing (default: bench-out);\n"
    "              files of the same names in it are replaced\n"
    "  --seed S    fracture seed of every mesh, 0..18446744073709551615 (default: 3000)\n"
    "  -h, --help  show this help\n"
    "\n"
    "Mesh trees of sections 4 and 5 are cached like those of 'breakables sim'.\n";

enum {
  MAX_RUNS = 5,            ///< timed builds per fracture measurement
  SCALING_PIECES = 256,    ///< fragments per wall in section 5
  REFERENCE_PIECES = 1024, ///< fragment count the runtime answer quotes (or the largest measured)
};

static const double frame_budget_ms = 1000.0 / 60.0;

/// A free unit cube resting on the ground, shot at like the wall scene.
static const bk_scene cube_scene = {
    .name = "cube",
    .description = "a free glass cube resting on the ground",
    .pieces = 256,
    .objects = {{.mesh = "cube", .position = {0.0, 0.5, 0.0}, .material = "glass"}},
    .object_count = 1,
    .eye = {0.8, 1.1, 3.0},
    .target = {0.0, 0.5, 0.0},
    .projectile_speed = 40.0,
    .projectile_radius = 0.1,
    .projectile_mass = 8.0};

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
    double start = bk_now_ms();
    if (!bk_mesh_tree_build(source, &desc, tree, err)) return false;
    times[r] = bk_now_ms() - start;
  }
  uint32_t count = runs < MAX_RUNS ? runs : MAX_RUNS;
  *min_ms = times[0];
  for (uint32_t r = 1; r < count; ++r)
    *min_ms = fmin(*min_ms, times[r]);
  *median_ms = bk_median(times, count);
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
    ok = bk_app_load_mesh(meshes[m], &source, &err) &&
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

// ---------------------------------------------------------------- impacts (sections 4 and 5)

/// Loads the tree and runs the impact in a child process, so that the peak
/// resident memory reported is this run's, not that of earlier sections.
static bool run_isolated(const bench* b, bk_impact setup, uint32_t pieces, bk_impact_result* out,
                         bk_error* err) {
  typedef struct message {
    bool ok;
    bk_impact_result result;
    bk_error err;
  } message;
  int fds[2] = {-1, -1};
  if (pipe(fds) != 0) return bk_error_set(err, "cannot create a pipe: %s", strerror(errno));
  fflush(NULL);
  malloc_trim(0); // hand freed memory back, so the child does not start with the earlier sections' heap
  pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return bk_error_set(err, "cannot start a process: %s", strerror(errno));
  }
  if (pid == 0) {
    close(fds[0]);
    message m = {0};
    double start_rss = bk_peak_rss_mb();
    bk_mesh_tree tree = {0};
    setup.tree = &tree;
    m.ok = bk_app_load_scene_tree(b->seed, setup.scene, pieces, &tree, &m.err) &&
           bk_impact_run(&setup, &m.result, &m.err);
    m.result.start_rss_mb = start_rss;
    m.result.peak_rss_mb = bk_peak_rss_mb();
    ssize_t written = write(fds[1], &m, sizeof m);
    _exit(written == (ssize_t)sizeof m ? 0 : 1);
  }
  close(fds[1]);
  message m = {0};
  size_t received = 0;
  while (received < sizeof m) {
    ssize_t n = read(fds[0], (char*)&m + received, sizeof m - received);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    received += (size_t)n;
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (received != sizeof m || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return bk_error_set(err, "the measuring process failed");
  if (!m.ok) return bk_error_set(err, "%s", m.err.message);
  *out = m.result;
  return true;
}

// ---------------------------------------------------------------- 4. runtime

/// Steps simulated from the shot on: long enough for most debris to land.
static uint32_t impact_steps(const bench* b) { return b->quick ? 150 : 240; }

typedef struct runtime_row {
  uint32_t pieces;
  bk_impact_result tree, naive;
} runtime_row;

static double before_ratio(const runtime_row* row) { return row->naive.before_ms / row->tree.before_ms; }
static double step_ratio(const runtime_row* row) {
  return row->naive.hit_median_ms / row->tree.hit_median_ms;
}
static double collider_ratio(const runtime_row* row) {
  return (double)row->naive.colliders / row->tree.colliders;
}

static void runtime_cells(bench_table* t, const char* object, const runtime_row* row) {
  bench_table_cell(t, "%s", object);
  bench_table_cell(t, "%u", row->pieces);
  bench_table_cell(t, "%u", row->tree.bodies);
  bench_table_cell(t, "%u", row->tree.colliders);
  bench_table_cell(t, "%u", row->naive.colliders);
  bench_table_cell(t, "%.4g", collider_ratio(row));
  bench_table_cell(t, "%.4g", row->tree.before_ms);
  bench_table_cell(t, "%.4g", row->naive.before_ms);
  bench_table_cell(t, "%.4g", before_ratio(row));
  bench_table_cell(t, "%.4g", row->tree.hit_physics_ms);
  bench_table_cell(t, "%.4g", row->tree.hit_break_ms);
  bench_table_cell(t, "%.4g", row->naive.hit_physics_ms);
  bench_table_cell(t, "%.4g", row->naive.hit_break_ms);
  bench_table_cell(t, "%.4g", row->tree.hit_median_ms);
  bench_table_cell(t, "%.4g", row->naive.hit_median_ms);
  bench_table_cell(t, "%.4g", step_ratio(row));
  bench_table_cell(t, "%.4g", row->tree.after_ms);
  bench_table_cell(t, "%.4g", row->naive.after_ms);
}

/// One line of a runtime plot: a column of runtime.csv on the rows of one object (a
/// gnuplot string expression), with a point style and a title; `more` continues the plot command.
static void runtime_series(bench_script* s, const char* object, const char* key, const char* style,
                           const char* title, bool more) {
  bench_script_add(s,
                   "'runtime.csv' using 'fragments':(strcol('object') eq %s ? column('%s') : 1/0) "
                   "with linespoints %s title '%s'%s",
                   object, key, style, title, more ? ", \\\n     " : "\n");
}

/// Both plots of section 4, from runtime.csv.
static bool runtime_plots(const bench* b) {
  bench_script s = {0};
  bench_script_add(&s, "set multiplot layout 1,2 title 'The worst step after the hit'\n"
                       "set xlabel 'fragments'\nset ylabel 'ms'\nset yrange [0.001:*]\n"
                       "do for [object in 'wall cube'] {\n  set title object\n  plot ");
  runtime_series(&s, "object", "hit_physics_ms", "pt 7 lc 1", "physics, mesh tree", true);
  runtime_series(&s, "object", "hit_break_ms", "pt 5 lc 2", "break handling, mesh tree", true);
  runtime_series(&s, "object", "naive_hit_physics_ms", "pt 6 dt 2 lc 1", "physics, naive", true);
  runtime_series(&s, "object", "naive_hit_break_ms", "pt 4 dt 2 lc 2", "break handling, naive", true);
  bench_script_add(&s, "%.4f with lines dt 3 lc rgb 'gray30' title 'one 60 Hz frame'\n}\nunset multiplot",
                   frame_budget_ms);
  if (!bench_plot(b, "runtime", "Physics and break handling of the worst step after the hit (log-log)", 1200,
                  540, &s))
    return false;

  s = (bench_script){0};
  bench_script_add(&s, "set multiplot layout 1,3 title 'Mesh-tree colliders against plain BCRB (naive)'\n"
                       "set xlabel 'fragments'\n"
                       "set title 'colliders at the end'\nset ylabel 'colliders'\nplot ");
  runtime_series(&s, "'wall'", "colliders", "pt 7 lc 1", "wall, mesh tree", true);
  runtime_series(&s, "'cube'", "colliders", "pt 5 lc 2", "cube, mesh tree", true);
  runtime_series(&s, "'wall'", "naive_colliders", "pt 6 dt 2 lc 3", "naive (one per fragment)", false);
  const char* titles[] = {"median step before the hit", "median step from the shot on"};
  const char* keys[][2] = {{"before_ms", "naive_before_ms"}, {"hit_median_ms", "naive_hit_median_ms"}};
  for (int panel = 0; panel < 2; ++panel) {
    bench_script_add(&s, "set title '%s'\nset ylabel 'ms'\nplot ", titles[panel]);
    runtime_series(&s, "'wall'", keys[panel][0], "pt 7 lc 1", "wall, mesh tree", true);
    runtime_series(&s, "'wall'", keys[panel][1], "pt 6 dt 2 lc 1", "wall, naive", true);
    runtime_series(&s, "'cube'", keys[panel][0], "pt 5 lc 2", "cube, mesh tree", true);
    runtime_series(&s, "'cube'", keys[panel][1], "pt 4 dt 2 lc 2", "cube, naive", false);
  }
  bench_script_add(&s, "unset multiplot");
  return bench_plot(b, "colliders", "Colliders and step time, mesh tree against naive (log-log)", 1500, 540,
                    &s);
}

/// The answer quotes the cube (the thesis's test object) at REFERENCE_PIECES, or the largest count run.
static void runtime_answer(const bench* b, const runtime_row* walls, const runtime_row* cubes,
                           uint32_t levels) {
  uint32_t ref = levels - 1, smooth = 0, smooth_break = 0;
  for (uint32_t i = 0; i < levels; ++i) {
    if (cubes[i].pieces == REFERENCE_PIECES) ref = i;
    if (cubes[i].tree.hit_step_ms < frame_budget_ms && smooth == i) smooth = i + 1;
    if (cubes[i].tree.hit_break_ms < frame_budget_ms && smooth_break == i) smooth_break = i + 1;
  }
  const runtime_row* c = &cubes[ref];
  const runtime_row* w = &walls[ref];
  bench_say(b,
            "**How many fragments before a hit lags?** The thesis's cube lagged noticeably from 64 fragments "
            "(75 ms in physics), mostly from setting up new colliders and rebuilding the edges of connected "
            "parts. Here the cube's worst step after the hit stays within one 60 Hz frame (%.1f ms) ",
            frame_budget_ms);
  if (smooth == levels)
    bench_say(b, "at every count measured, up to %u fragments", cubes[levels - 1].pieces);
  else if (smooth == 0)
    bench_say(b, "at no count measured");
  else
    bench_say(b, "up to %u fragments (%u: %.3g ms)", cubes[smooth - 1].pieces, cubes[smooth].pieces,
              cubes[smooth].tree.hit_step_ms);
  bench_say(b, ", and break handling alone (the thesis's bottleneck) stays within a frame ");
  if (smooth_break == levels)
    bench_say(b, "up to %u fragments", cubes[levels - 1].pieces);
  else if (smooth_break == 0)
    bench_say(b, "at no count measured");
  else
    bench_say(b, "up to %u fragments", cubes[smooth_break - 1].pieces);
  bench_say(
      b,
      ". At %u fragments the worst physics step after the hit takes %.3g ms and the worst break handling "
      "%.3g ms (naive: %.3g and %.3g ms)",
      c->pieces, c->tree.hit_physics_ms, c->tree.hit_break_ms, c->naive.hit_physics_ms,
      c->naive.hit_break_ms);
  if (c->tree.hit_physics_ms > 2.0 * c->tree.hit_break_ms)
    bench_say(b, ": the cost is the physics of the new bodies (%u on the cube at the end), not making them",
              c->tree.bodies);
  bench_say(b, ".\n\n");
  bench_say(
      b,
      "**What do mesh-tree colliders save over plain BCRB?** At %u fragments the mesh tree ends with %u "
      "colliders on the cube and %u on the wall where plain BCRB needs %u: %.3gx and %.3gx fewer. An "
      "unbroken object is one collider, so before the hit a step costs %.3g ms against %.3g ms naive on "
      "the resting cube (%.3gx). From the shot on, the median step is %.3g against %.3g ms on the cube "
      "(%.3gx) and %.3g against %.3g ms on the wall (%.3gx)",
      c->pieces, c->tree.colliders, w->tree.colliders, c->naive.colliders, collider_ratio(c),
      collider_ratio(w), c->tree.before_ms, c->naive.before_ms, before_ratio(c), c->tree.hit_median_ms,
      c->naive.hit_median_ms, step_ratio(c), w->tree.hit_median_ms, w->naive.hit_median_ms, step_ratio(w));
  if (step_ratio(c) < 1.5 && step_ratio(w) < 1.5)
    bench_say(b, ": once many fragments fly free as bodies of their own, both modes pay for about the same "
                 "bodies and contacts, and the saving is in what stays whole");
  bench_say(b, ".\n");
}

static bool section_runtime(const bench* b) {
  static const bench_column columns[] = {{"object", "object"},
                                         {"fragments", "fragments"},
                                         {"bodies", "bodies at end"},
                                         {"colliders", "colliders"},
                                         {"naive_colliders", "naive colliders"},
                                         {"collider_ratio", "collider ratio"},
                                         {"before_ms", "before"},
                                         {"naive_before_ms", "naive before"},
                                         {"before_ratio", "before ratio"},
                                         {"hit_physics_ms", "hit physics"},
                                         {"hit_break_ms", "hit break"},
                                         {"naive_hit_physics_ms", "naive hit physics"},
                                         {"naive_hit_break_ms", "naive hit break"},
                                         {"hit_median_ms", "median"},
                                         {"naive_hit_median_ms", "naive median"},
                                         {"step_ratio", "step ratio"},
                                         {"after_ms", "after"},
                                         {"naive_after_ms", "naive after"}};
  uint32_t cap = b->quick ? 256 : 4096;
  bench_section(
      b, "4. Runtime",
      "An anchored stone wall (scene `wall`) and a free glass unit cube resting on the ground, each hit "
      "by one projectile (8 kg, 40 m/s) after 30 steps of 1/60 s and then simulated for a few seconds "
      "more. Each runs twice: with colliders from the minimal mesh-tree node sets, and as plain BCRB "
      "(one collider per fragment, `--naive`). *Colliders* and *bodies* are counted at the end; "
      "*before* is the median step over the 30 steps before the shot; *hit physics* and *hit break* "
      "are the worst physics part and the worst break handling (damage, components, minimal node sets, "
      "new bodies) of any step after the shot; *median* is the median step from the shot on; *after* "
      "is the median of the last 30 steps. Times are milliseconds per step; ratios are naive over mesh "
      "tree.");
  const bk_scene* scenes[2] = {bk_scene_find("wall"), &cube_scene};
  runtime_row rows[2][16] = {0};
  uint32_t levels = 0;
  bench_table t = bench_table_make("runtime", columns, sizeof columns / sizeof *columns);
  bool ok = scenes[0] != NULL;
  for (uint32_t s = 0; ok && s < 2; ++s) {
    levels = 0;
    for (uint32_t pieces = 2; ok && pieces <= cap; pieces *= 2) {
      bk_mesh_tree tree = {0};
      bk_error err = {0};
      runtime_row* row = &rows[s][levels++];
      row->pieces = pieces;
      bk_impact setup = {.scene = scenes[s], .tree = &tree, .copies = 1, .steps_after = impact_steps(b)};
      ok = bk_app_load_scene_tree(b->seed, scenes[s], pieces, &tree, &err) &&
           bk_impact_run(&setup, &row->tree, &err);
      setup.naive = true;
      ok = ok && bk_impact_run(&setup, &row->naive, &err);
      bk_mesh_tree_free(&tree);
      if (!ok) {
        fprintf(stderr, "breakables bench: %s with %u fragments: %s\n", scenes[s]->name, pieces, err.message);
        break;
      }
      if (row->tree.nan || row->naive.nan)
        fprintf(stderr, "breakables bench: warning: %s with %u fragments: a body became NaN\n",
                scenes[s]->name, pieces);
      runtime_cells(&t, scenes[s]->name, row);
    }
  }
  ok = ok && bench_table_write(b, &t);
  bench_table_free(&t);
  if (!ok || !runtime_plots(b)) return false;
  runtime_answer(b, rows[0], rows[1], levels);
  return true;
}

// ---------------------------------------------------------------- 5. scaling

static bool section_scaling(const bench* b) {
  static const bench_column columns[] = {{"walls", "walls"},
                                         {"fragments", "fragments"},
                                         {"bodies", "bodies after"},
                                         {"colliders", "colliders after"},
                                         {"step_ms_median", "median step ms"},
                                         {"step_ms_max", "max step ms"},
                                         {"break_ms_max", "max break ms"},
                                         {"start_rss_mb", "start RSS MB"},
                                         {"peak_rss_mb", "peak RSS MB"}};
  static const uint32_t wall_counts[] = {1, 4, 16};
  uint32_t configurations = b->quick ? 2 : 3;
  bench_section(
      b, "5. Scaling",
      "1, 4 and 16 walls of 256 fragments side by side (2.5 m apart), each hit by its own projectile "
      "in the same step. Median and worst step from the shot on, the worst break handling, and the "
      "peak resident memory of a process that runs only this configuration (a child process; *start* "
      "is its resident memory when it begins, inherited from the benchmark).");
  const bk_scene* wall = bk_scene_find("wall");
  bench_table t = bench_table_make("scaling", columns, sizeof columns / sizeof *columns);
  bk_impact_result results[3] = {0};
  bool ok = wall != NULL;
  for (uint32_t i = 0; ok && i < configurations; ++i) {
    bk_error err = {0};
    bk_impact setup = {.scene = wall, .copies = wall_counts[i], .steps_after = impact_steps(b)};
    ok = run_isolated(b, setup, SCALING_PIECES, &results[i], &err);
    if (!ok) {
      fprintf(stderr, "breakables bench: %u walls: %s\n", wall_counts[i], err.message);
      break;
    }
    const bk_impact_result* r = &results[i];
    bench_table_cell(&t, "%u", wall_counts[i]);
    bench_table_cell(&t, "%u", wall_counts[i] * SCALING_PIECES);
    bench_table_cell(&t, "%u", r->bodies);
    bench_table_cell(&t, "%u", r->colliders);
    bench_table_cell(&t, "%.4g", r->hit_median_ms);
    bench_table_cell(&t, "%.4g", r->hit_step_ms);
    bench_table_cell(&t, "%.4g", r->hit_break_ms);
    bench_table_cell(&t, "%.1f", r->start_rss_mb);
    bench_table_cell(&t, "%.1f", r->peak_rss_mb);
  }
  ok = ok && bench_table_write(b, &t);
  bench_table_free(&t);
  if (!ok) return false;
  bench_say(b, "**How does the cost grow with the number of objects broken at once?**");
  for (uint32_t i = 0; i < configurations; ++i)
    bench_say(b, "%s %u wall%s: median step %.3g ms, worst %.3g ms, peak memory %.0f MB", i ? ";" : "",
              wall_counts[i], wall_counts[i] == 1 ? "" : "s", results[i].hit_median_ms,
              results[i].hit_step_ms, results[i].peak_rss_mb);
  const bk_impact_result* last = &results[configurations - 1];
  bench_say(
      b,
      ". With %u times the walls, the median step costs %.3gx and the worst step %.3gx as much, and the "
      "process needs %.0f MB more at its peak.\n",
      wall_counts[configurations - 1], last->hit_median_ms / results[0].hit_median_ms,
      last->hit_step_ms / results[0].hit_step_ms, last->peak_rss_mb - results[0].peak_rss_mb);
  return true;
}

// ---------------------------------------------------------------- the command

static int usage_error(const char* option, const char* what) {
  fprintf(stderr, "breakables bench: %s %s (see 'breakables bench --help')\n", option, what);
  return 2;
}

int bk_cmd_bench(int argc, char** argv) {
  bench b = {.seed = 3000, .dir = "bench-out"};
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : NULL;
    if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
      fputs(bench_usage, stdout);
      return 0;
    } else if (strcmp(arg, "--quick") == 0) {
      b.quick = true;
    } else if (strcmp(arg, "--out") == 0 || strcmp(arg, "--seed") == 0) {
      if (!value) return usage_error(arg, "needs a value");
      ++i;
      if (strcmp(arg, "--out") == 0) {
        if (!*value) return usage_error(arg, "must not be empty");
        b.dir = value;
      } else if (!bk_option_u64("bench", arg, value, 0, UINT64_MAX, &b.seed)) {
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
  double start = bk_now_ms();
  bool ok = section_fracture_speed(&b) && section_meshes(&b) && section_max_fragments(&b) &&
            section_runtime(&b) && section_scaling(&b) && bench_section_assets(&b) &&
            bench_section_patterns(&b) && bench_section_stress(&b);
  if (ok) bench_say(&b, "\n---\n\nThe whole run took %.0f s.\n", (bk_now_ms() - start) / 1000.0);
  ok = bench_output_close(&report, ok) && ok;
  if (!ok) return 1;
  printf("\nwrote %s/report.md (%.0f s)\n", b.dir, (bk_now_ms() - start) / 1000.0);
  return 0;
}
