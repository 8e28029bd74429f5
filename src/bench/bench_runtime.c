// Sections 4 and 5 of 'breakables bench': a wall and a cube hit once
// (mesh-tree colliders against plain BCRB), and walls hit at the same time
// (scaling), each run through impact_run.
#include <errno.h>
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app.h"
#include "bench_report.h"
#include "scene_run.h"

enum {
  SCALING_PIECES = 256,    ///< fragments per wall in section 5
  REFERENCE_PIECES = 1024, ///< fragment count the runtime answer quotes (or the largest measured)
};

static const double frame_budget_ms = 1000.0 / 60.0;

const app_scene bench_cube_scene = {
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

// ---------------------------------------------------------------- impacts (sections 4 and 5)

/// Loads the tree and runs the impact in a child process, so that the peak
/// resident memory reported is this run's, not that of earlier sections.
static bool run_isolated(const bench* b, app_impact setup, uint32_t pieces, impact_result* out,
                         bk_error* err) {
  typedef struct message {
    bool ok;
    impact_result result;
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
    double start_rss = app_peak_rss_mb();
    bk_mesh_tree tree = {0};
    setup.tree = &tree;
    m.ok = app_load_scene_tree(b->seed, setup.scene, pieces, &tree, &m.err) &&
           impact_run(&setup, &m.result, &m.err);
    m.result.start_rss_mb = start_rss;
    m.result.peak_rss_mb = app_peak_rss_mb();
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
  impact_result tree, naive;
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

bool bench_section_runtime(const bench* b) {
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
  const app_scene* scenes[2] = {scene_find("wall"), &bench_cube_scene};
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
      app_impact setup = {.scene = scenes[s], .tree = &tree, .copies = 1, .steps_after = impact_steps(b)};
      ok = app_load_scene_tree(b->seed, scenes[s], pieces, &tree, &err) &&
           impact_run(&setup, &row->tree, &err);
      setup.naive = true;
      ok = ok && impact_run(&setup, &row->naive, &err);
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

bool bench_section_scaling(const bench* b) {
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
  const app_scene* wall = scene_find("wall");
  bench_table t = bench_table_make("scaling", columns, sizeof columns / sizeof *columns);
  impact_result results[3] = {0};
  bool ok = wall != NULL;
  for (uint32_t i = 0; ok && i < configurations; ++i) {
    bk_error err = {0};
    app_impact setup = {.scene = wall, .copies = wall_counts[i], .steps_after = impact_steps(b)};
    ok = run_isolated(b, setup, SCALING_PIECES, &results[i], &err);
    if (!ok) {
      fprintf(stderr, "breakables bench: %u walls: %s\n", wall_counts[i], err.message);
      break;
    }
    const impact_result* r = &results[i];
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
  const impact_result* last = &results[configurations - 1];
  bench_say(
      b,
      ". With %u times the walls, the median step costs %.3gx and the worst step %.3gx as much, and the "
      "process needs %.0f MB more at its peak.\n",
      wall_counts[configurations - 1], last->hit_median_ms / results[0].hit_median_ms,
      last->hit_step_ms / results[0].hit_step_ms, last->peak_rss_mb - results[0].peak_rss_mb);
  return true;
}
