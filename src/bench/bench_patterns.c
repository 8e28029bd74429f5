// 'breakables bench', section 7: the fracture patterns side by side. Each
// pattern on the bunny (brick on the wall, with planes on the wall beside it)
// at several piece counts: build time, the tree's size and its fragments'
// quality (bk_mesh_tree_measure_quality), then the cell patterns with noisy
// cut faces; answers whether the cell patterns stay within 2x of planes' time
// and whether Voronoi cells make fewer slivers than planes.
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "app.h"
#include "bench_report.h"
#include "scene_run.h"

enum {
  PATTERN_MAX_RUNS = 3,       ///< timed builds per row in the full run (1 with --quick)
  PATTERN_MAX_COUNTS = 4,     ///< piece counts per series in the full run
  PATTERN_REFERENCE = 1024,   ///< the count the answers quote and the noisy rows use
  PATTERN_CELL_COUNT = 3,     ///< the cell patterns: voronoi, clustered, radial
  PATTERN_SERIES_PLANES = 0,  ///< series index of planes on the bunny, the reference of the answers
  PATTERN_SERIES_VORONOI = 1, ///< series index of voronoi on the bunny (the first cell pattern)
  PATTERN_SERIES_RADIAL = 3,  ///< series index of radial on the bunny
  PATTERN_SERIES_BRICK = 4,   ///< series index of brick on the wall
  PATTERN_SERIES_WALL_PLANES = 5,
};

// Both lists hold PATTERN_REFERENCE: the answers look its rows up.
static const uint32_t full_counts[] = {64, 256, 1024, 4096};
static const uint32_t quick_counts[] = {64, 1024};
_Static_assert(sizeof full_counts / sizeof *full_counts == PATTERN_MAX_COUNTS, "one row per count");

/// Noisy cut faces: amplitude and frequency relative to the bunny's size
/// (the largest side of its bounds), so they scale with it.
static const double noise_amplitude_per_size = 0.02, noise_waves_per_size = 4.0;
/// Time within this factor of planes' meets the cell patterns' target.
static const double time_target_ratio = 2.0;
/// Voronoi's sliver fraction at most this fraction of planes' counts as well below it.
static const double sliver_target_ratio = 0.5;

/// One series of the table: a pattern on a mesh. Brick needs courses of
/// bricks, so it runs on the wall, and planes runs there too for comparison.
typedef struct pattern_series {
  const char* mesh;
  bk_fracture_pattern pattern;
} pattern_series;

static const pattern_series series[] = {{"bunny", BK_PATTERN_PLANES},    {"bunny", BK_PATTERN_VORONOI},
                                        {"bunny", BK_PATTERN_CLUSTERED}, {"bunny", BK_PATTERN_RADIAL},
                                        {"wall", BK_PATTERN_BRICK},      {"wall", BK_PATTERN_PLANES}};
enum { SERIES_COUNT = sizeof series / sizeof *series };

/// The patterns also measured with noisy cut faces, on the bunny at
/// PATTERN_REFERENCE pieces: planes, then the cell patterns.
static const bk_fracture_pattern noisy_patterns[] = {BK_PATTERN_PLANES, BK_PATTERN_VORONOI,
                                                     BK_PATTERN_CLUSTERED, BK_PATTERN_RADIAL};
enum { NOISY_COUNT = sizeof noisy_patterns / sizeof *noisy_patterns };

/// One measured row.
typedef struct pattern_row {
  uint32_t pieces, runs;
  double ms; ///< median wall time of the builds
  uint32_t leaves, nodes, bonds, leaf_triangles, open_nodes;
  bk_mesh_tree_quality quality;
  double volume_error;
} pattern_row;

/// The sources, loaded once, and what the patterns' parameters derive from them.
typedef struct pattern_sources {
  bk_mesh bunny, wall;
  bk_vec3 impact; ///< the bunny's surface vertex of largest z (its front)
  double size;    ///< the largest side of the bunny's bounds
  bk_aabb wall_bounds;
} pattern_sources;

static uint32_t pattern_counts(const bench* b, const uint32_t** counts) {
  *counts = b->quick ? quick_counts : full_counts;
  return b->quick ? sizeof quick_counts / sizeof *quick_counts : sizeof full_counts / sizeof *full_counts;
}

static uint32_t pattern_runs(const bench* b) { return b->quick ? 1 : PATTERN_MAX_RUNS; }

/// The vertex of largest z among those the triangles use: on the surface,
/// which the radial pattern's impact should be (a hit lands there).
static bk_vec3 front_vertex(const bk_mesh* mesh) {
  bk_vec3 best = {0.0, 0.0, -INFINITY};
  for (uint32_t t = 0; t < mesh->triangle_count; ++t)
    for (uint32_t k = 0; k < 3; ++k) {
      bk_vec3 p = mesh->positions[bk_mesh_tri_position(mesh, t, k)];
      if (p.z > best.z) best = p;
    }
  return best;
}

static bool load_sources(pattern_sources* s, bk_error* err) {
  if (!app_load_mesh("bunny", &s->bunny, err) || !app_load_mesh("wall", &s->wall, err)) return false;
  bk_aabb box = bk_mesh_bounds(&s->bunny);
  s->size = fmax(box.max.x - box.min.x, fmax(box.max.y - box.min.y, box.max.z - box.min.z));
  s->impact = front_vertex(&s->bunny);
  s->wall_bounds = bk_mesh_bounds(&s->wall);
  return true;
}

/// The def of a pattern on the bunny or the wall; noise only where asked.
static bk_fracture_def pattern_def(const bench* b, const pattern_sources* s, bk_fracture_pattern pattern,
                                   uint32_t pieces, bool noisy) {
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = pattern;
  def.pieces = pieces;
  def.seed = b->seed;
  if (pattern == BK_PATTERN_RADIAL) def.impact = s->impact;
  if (noisy) {
    def.noise_amplitude = noise_amplitude_per_size * s->size;
    def.noise_frequency = noise_waves_per_size / s->size;
  }
  return def;
}

/// Builds the tree `runs` times (the median time counts), then measures the last tree.
static bool measure_row(const bk_mesh* source, const bk_fracture_def* def, uint32_t runs, pattern_row* row,
                        bk_error* err) {
  double times[PATTERN_MAX_RUNS] = {0};
  bk_mesh_tree tree = {0};
  row->pieces = def->pieces;
  row->runs = runs < PATTERN_MAX_RUNS ? runs : PATTERN_MAX_RUNS;
  for (uint32_t r = 0; r < row->runs; ++r) {
    bk_mesh_tree_free(&tree);
    double start = app_now_ms();
    if (!bk_mesh_tree_build(source, def, &tree, err)) return false;
    times[r] = app_now_ms() - start;
  }
  row->ms = app_median(times, row->runs);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(&tree);
  row->leaves = tree.leaf_count;
  row->nodes = tree.node_count;
  row->bonds = tree.bond_count;
  row->leaf_triangles = st.leaf_triangles;
  row->open_nodes = st.open_nodes;
  row->quality = bk_mesh_tree_measure_quality(&tree);
  row->volume_error = bench_leaf_volume_error(&tree);
  bk_mesh_tree_free(&tree);
  return true;
}

static void row_cells(bench_table* t, const char* mesh, bk_fracture_pattern pattern, double noise,
                      const pattern_row* row) {
  bench_table_cell(t, "%s", mesh);
  bench_table_cell(t, "%s", bk_fracture_pattern_name(pattern));
  bench_table_cell(t, "%.4g", noise);
  bench_table_cell(t, "%u", row->pieces);
  bench_table_cell(t, "%u", row->runs);
  bench_table_cell(t, "%.4g", row->ms);
  bench_table_cell(t, "%u", row->leaves);
  bench_table_cell(t, "%u", row->nodes);
  bench_table_cell(t, "%u", row->bonds);
  bench_table_cell(t, "%u", row->leaf_triangles);
  bench_table_cell(t, "%.4f", row->quality.sliver_fraction);
  bench_table_cell(t, "%.4g", row->quality.volume_ratio_p95_p5);
  bench_table_cell(t, "%u", row->open_nodes);
  bench_table_cell(t, "%.2e", row->volume_error);
}

/// One line of a plot per series, from the rows without noise.
static void series_lines(bench_script* s, const char* key) {
  static const char* const styles[SERIES_COUNT] = {"pt 7 lc 1",  "pt 5 lc 2",  "pt 9 lc 3",
                                                   "pt 11 lc 4", "pt 13 lc 6", "pt 6 dt 2 lc 1"};
  for (uint32_t i = 0; i < SERIES_COUNT; ++i)
    bench_script_add(s,
                     "'patterns.csv' using 'fragments':(strcol('mesh') eq '%s' && strcol('pattern') eq '%s' "
                     "&& column('noise') == 0 ? column('%s') : 1/0) with linespoints %s title '%s (%s)'%s",
                     series[i].mesh, bk_fracture_pattern_name(series[i].pattern), key, styles[i],
                     bk_fracture_pattern_name(series[i].pattern), series[i].mesh,
                     i + 1 < SERIES_COUNT ? ", \\\n     " : "\n");
}

static bool pattern_plots(const bench* b) {
  bench_script s = {0};
  bench_script_add(&s, "set title 'Building the mesh tree, by pattern'\nset xlabel 'pieces'\n"
                       "set ylabel 'time (ms)'\nplot ");
  series_lines(&s, "ms_median");
  if (!bench_plot(b, "patterns_time", "Build time against pieces, per pattern (log-log)", 900, 560, &s))
    return false;
  s = (bench_script){0};
  // A fraction of 0 is common (Voronoi cells), so this plot's y axis is linear.
  bench_script_add(&s,
                   "unset logscale y\nset yrange [0:*]\nset title 'Slivers (aspect < %.2g), by pattern'\n"
                   "set xlabel 'pieces'\nset ylabel 'sliver fraction'\nplot ",
                   BK_SLIVER_ASPECT);
  series_lines(&s, "sliver_fraction");
  return bench_plot(b, "patterns_slivers", "Sliver fraction against pieces, per pattern (log x)", 900, 560,
                    &s);
}

/// The row of series `i` at `pieces`, or NULL when that count was not run.
static const pattern_row* find_row(const pattern_row rows[][PATTERN_MAX_COUNTS], uint32_t count_n, uint32_t i,
                                   uint32_t pieces) {
  for (uint32_t c = 0; c < count_n; ++c)
    if (rows[i][c].pieces == pieces) return &rows[i][c];
  return NULL;
}

/// Whether Voronoi's sliver fraction is well below planes'; where planes make
/// none, Voronoi cannot be below them, and making none as well is the best it can do.
static bool sliver_target_met(double voronoi, double planes) {
  return planes > 0.0 ? voronoi <= sliver_target_ratio * planes : voronoi == 0.0;
}

/// The section's answers, every number from the rows measured.
static void pattern_answers(const bench* b, const pattern_row rows[][PATTERN_MAX_COUNTS], uint32_t count_n,
                            const pattern_row* noisy, const uint32_t* counts) {
  const pattern_row* planes = find_row(rows, count_n, PATTERN_SERIES_PLANES, PATTERN_REFERENCE);
  bench_say(b,
            "**Are the cell patterns fast enough?** At %u pieces on the bunny, planes take %.4g ms; the "
            "target for the cell patterns is within %.0fx of that:",
            PATTERN_REFERENCE, planes->ms, time_target_ratio);
  uint32_t missed[PATTERN_CELL_COUNT] = {0}, missed_n = 0;
  for (uint32_t i = PATTERN_SERIES_VORONOI; i < PATTERN_SERIES_VORONOI + PATTERN_CELL_COUNT; ++i) {
    const pattern_row* r = find_row(rows, count_n, i, PATTERN_REFERENCE);
    double ratio = r->ms / planes->ms;
    const char* name = bk_fracture_pattern_name(series[i].pattern);
    bench_say(b, "%s %s %.4g ms (%.2fx)", i == PATTERN_SERIES_VORONOI ? "" : ";", name, r->ms, ratio);
    if (ratio > time_target_ratio) missed[missed_n++] = i;
    printf("  %s at %u pieces on the bunny: %.2fx planes' time (target within %.0fx: %s)\n", name,
           PATTERN_REFERENCE, ratio, time_target_ratio, ratio <= time_target_ratio ? "met" : "NOT MET");
  }
  if (missed_n == 0) bench_say(b, ". Every cell pattern meets the target");
  for (uint32_t m = 0; m < missed_n; ++m)
    bench_say(b, "%s%s",
              m == 0             ? ". The target is NOT MET by "
              : m + 1 < missed_n ? ", "
                                 : " and ",
              bk_fracture_pattern_name(series[missed[m]].pattern));
  bench_say(b, "; with noisy faces (amplitude %.0f%% of the size; ratios still to flat planes) they take",
            100.0 * noise_amplitude_per_size);
  for (uint32_t n = 0; n < NOISY_COUNT; ++n)
    bench_say(b, "%s %s %.4g ms (%.2fx)", n ? "," : "", bk_fracture_pattern_name(noisy_patterns[n]),
              noisy[n].ms, noisy[n].ms / planes->ms);
  // How the ratio moves with the count says whether the target holds beyond the count it is set at.
  uint32_t largest = counts[count_n - 1];
  if (largest != PATTERN_REFERENCE) {
    const pattern_row* top = find_row(rows, count_n, PATTERN_SERIES_PLANES, largest);
    bench_say(b, ". At %u pieces (planes: %.4g ms) the ratios are", largest, top->ms);
    for (uint32_t i = PATTERN_SERIES_VORONOI; i < PATTERN_SERIES_VORONOI + PATTERN_CELL_COUNT; ++i)
      bench_say(b, "%s %s %.2fx", i == PATTERN_SERIES_VORONOI ? "" : ",",
                bk_fracture_pattern_name(series[i].pattern),
                find_row(rows, count_n, i, largest)->ms / top->ms);
  }
  bench_say(b, ".\n\n");

  bench_say(b,
            "**Do Voronoi cells avoid slivers?** A sliver is a leaf whose thinnest principal extent is under "
            "%.2g of its longest; the target is Voronoi well below planes (at most %.0f%% of planes' "
            "fraction).",
            BK_SLIVER_ASPECT, 100.0 * sliver_target_ratio);
  uint32_t met = 0;
  for (uint32_t c = 0; c < count_n; ++c) {
    const pattern_row* p = find_row(rows, count_n, PATTERN_SERIES_PLANES, counts[c]);
    const pattern_row* v = find_row(rows, count_n, PATTERN_SERIES_VORONOI, counts[c]);
    bool good = sliver_target_met(v->quality.sliver_fraction, p->quality.sliver_fraction);
    met += good;
    const char* verdict = !good ? "NOT MET" : p->quality.sliver_fraction > 0.0 ? "met" : "neither makes any";
    bench_say(b, "%s %u pieces, %.2f%% of Voronoi's leaves are slivers against %.2f%% of planes' (%s)",
              c ? "; at" : " At", counts[c], 100.0 * v->quality.sliver_fraction,
              100.0 * p->quality.sliver_fraction, verdict);
    if (counts[c] == PATTERN_REFERENCE)
      printf("  slivers at %u pieces on the bunny: voronoi %.2f%%, planes %.2f%% (target well below: %s)\n",
             counts[c], 100.0 * v->quality.sliver_fraction, 100.0 * p->quality.sliver_fraction,
             good ? "met" : "NOT MET");
  }
  bench_say(b,
            ". The target is %s at %u of %u counts; Voronoi's smallest aspect at %u pieces is %.2f "
            "(planes': %.2f).",
            met == count_n ? "met" : "NOT MET", met, count_n, PATTERN_REFERENCE,
            find_row(rows, count_n, PATTERN_SERIES_VORONOI, PATTERN_REFERENCE)->quality.min_aspect,
            planes->quality.min_aspect);

  const pattern_row* brick = find_row(rows, count_n, PATTERN_SERIES_BRICK, PATTERN_REFERENCE);
  const pattern_row* wall = find_row(rows, count_n, PATTERN_SERIES_WALL_PLANES, PATTERN_REFERENCE);
  const pattern_row* radial = find_row(rows, count_n, PATTERN_SERIES_RADIAL, PATTERN_REFERENCE);
  bench_say(b,
            " On the wall at %u pieces, brick takes %.4g ms against planes' %.4g ms, with %.2f%% slivers "
            "against %.2f%%. Radial's spread of sizes (p95/p5 %.3g against planes' %.3g) is by design: "
            "pieces are small near the impact and grow away from it.\n",
            PATTERN_REFERENCE, brick->ms, wall->ms, 100.0 * brick->quality.sliver_fraction,
            100.0 * wall->quality.sliver_fraction, radial->quality.volume_ratio_p95_p5,
            planes->quality.volume_ratio_p95_p5);
}

/// The method text, with every parameter as used.
static void pattern_method(const bench* b, const pattern_sources* s, const uint32_t* counts,
                           uint32_t count_n) {
  bk_fracture_def d = bk_default_fracture_def();
  char list[64] = "";
  for (uint32_t c = 0; c < count_n; ++c)
    snprintf(list + strlen(list), sizeof list - strlen(list), "%s%u",
             c == 0            ? ""
             : c + 1 < count_n ? ", "
                               : " and ",
             counts[c]);
  char method[3072];
  snprintf(method, sizeof method,
           "Each fracture pattern on the bunny (%u triangles, %.3g units across) into %s pieces%s: planes, "
           "voronoi (seeds spread through the volume), clustered (%u chunks, border %.3g), radial (impact on "
           "the bunny's front-most surface vertex (%.3f, %.3f, %.3f), falloff %.3g); brick (bricks of %.3g x "
           "%.3g, offset %.3g) on the wall (%.3g x %.3g x %.3g), with planes on the wall for comparison. "
           "Then planes and each cell pattern at %u pieces with noisy cut faces (amplitude %.0f%% of the "
           "bunny's size, "
           "%.4g; frequency %.0f waves per size, %.4g). *Median ms* is the wall time of %u build%s with the "
           "default threads (every core, %ld here: the cell patterns build their cells in parallel, planes "
           "and brick split pieces ahead on them, so the ratios depend on the cores free); *slivers* are "
           "leaves whose "
           "aspect (thinnest over longest principal extent) is "
           "under %.2g; *p95/p5 volume* is the 95th over the 5th percentile of leaf volumes "
           "(`bk_mesh_tree_measure_quality`); open nodes must be 0; the volume error is |sum of the leaves' "
           "mesh volumes - source| / source.",
           s->bunny.triangle_count, s->size, list,
           b->quick ? " (`--quick`; the full run adds 256 and 4096)" : "", d.clusters, d.cluster_border,
           s->impact.x, s->impact.y, s->impact.z, d.radial_falloff, d.brick_size.x, d.brick_size.y,
           d.brick_offset, s->wall_bounds.max.x - s->wall_bounds.min.x,
           s->wall_bounds.max.y - s->wall_bounds.min.y, s->wall_bounds.max.z - s->wall_bounds.min.z,
           PATTERN_REFERENCE, 100.0 * noise_amplitude_per_size, noise_amplitude_per_size * s->size,
           noise_waves_per_size, noise_waves_per_size / s->size, pattern_runs(b),
           pattern_runs(b) == 1 ? "" : "s", sysconf(_SC_NPROCESSORS_ONLN), BK_SLIVER_ASPECT);
  bench_section(b, "7. Fracture patterns", method);
}

bool bench_section_patterns(const bench* b) {
  static const bench_column columns[] = {{"mesh", "mesh"},
                                         {"pattern", "pattern"},
                                         {"noise", "noise amplitude"},
                                         {"fragments", "pieces"},
                                         {"runs", "runs"},
                                         {"ms_median", "median ms"},
                                         {"leaves", "leaves"},
                                         {"nodes", "nodes"},
                                         {"bonds", "bonds"},
                                         {"leaf_triangles", "leaf triangles"},
                                         {"sliver_fraction", "slivers"},
                                         {"volume_ratio_p95_p5", "p95/p5 volume"},
                                         {"open_nodes", "open nodes"},
                                         {"volume_rel_error", "volume error"}};
  const uint32_t* counts = NULL;
  uint32_t count_n = pattern_counts(b, &counts);
  pattern_sources sources = {0};
  bk_error err = {0};
  bool ok = load_sources(&sources, &err);
  if (!ok) {
    fprintf(stderr, "breakables bench: fracture patterns: %s\n", err.message);
  } else {
    pattern_method(b, &sources, counts, count_n);
  }
  pattern_row rows[SERIES_COUNT][PATTERN_MAX_COUNTS] = {0};
  pattern_row noisy[NOISY_COUNT] = {0};
  uint32_t open_nodes = 0;
  bench_table t = bench_table_make("patterns", columns, sizeof columns / sizeof *columns);
  // Series by series, counts rising, so each plotted line is one run of rows.
  for (uint32_t i = 0; ok && i < SERIES_COUNT; ++i) {
    const bk_mesh* source = strcmp(series[i].mesh, "bunny") == 0 ? &sources.bunny : &sources.wall;
    for (uint32_t c = 0; ok && c < count_n; ++c) {
      bk_fracture_def def = pattern_def(b, &sources, series[i].pattern, counts[c], false);
      ok = measure_row(source, &def, pattern_runs(b), &rows[i][c], &err);
      if (!ok) {
        fprintf(stderr, "breakables bench: %s into %u pieces (%s): %s\n", series[i].mesh, counts[c],
                bk_fracture_pattern_name(series[i].pattern), err.message);
        break;
      }
      row_cells(&t, series[i].mesh, series[i].pattern, 0.0, &rows[i][c]);
      open_nodes += rows[i][c].open_nodes;
    }
  }
  for (uint32_t n = 0; ok && n < NOISY_COUNT; ++n) {
    bk_fracture_pattern pattern = noisy_patterns[n];
    bk_fracture_def def = pattern_def(b, &sources, pattern, PATTERN_REFERENCE, true);
    ok = measure_row(&sources.bunny, &def, pattern_runs(b), &noisy[n], &err);
    if (!ok) {
      fprintf(stderr, "breakables bench: bunny into %u pieces (%s with noise): %s\n", PATTERN_REFERENCE,
              bk_fracture_pattern_name(pattern), err.message);
      break;
    }
    row_cells(&t, "bunny", pattern, def.noise_amplitude, &noisy[n]);
    open_nodes += noisy[n].open_nodes;
  }
  bk_mesh_free(&sources.bunny);
  bk_mesh_free(&sources.wall);
  ok = ok && bench_table_write(b, &t);
  bench_table_free(&t);
  if (!ok || !pattern_plots(b)) return false;
  if (open_nodes)
    bench_say(b, "SOME TREES HAVE OPEN NODES (%u in all): see *open nodes*.\n\n", open_nodes);
  else
    bench_say(b, "Every tree is closed: no open node in any row.\n\n");
  pattern_answers(b, rows, count_n, noisy, counts);
  return true;
}
