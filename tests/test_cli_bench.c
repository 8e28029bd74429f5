// breakables bench --quick, run as a user would: every section's table,
// its CSV file and plots, the report's parts, and the command's errors.
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <breakables/bullet.h>

#include "ensure.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/cli_bench_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"

typedef struct csv_table {
  char header[1024];
  char rows[32][1024];
  uint32_t row_count;
} csv_table;

static csv_table csv_data;

// Reads BK_TEST_TMP/bench/<name>.csv, checking its header and row count.
static const csv_table* read_csv(const char* name, const char* header, uint32_t rows) {
  char path[512];
  snprintf(path, sizeof path, "%s/bench/%s.csv", BK_TEST_TMP, name);
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "missing %s", path);
  memset(&csv_data, 0, sizeof csv_data);
  ENSURE(fgets(csv_data.header, sizeof csv_data.header, f) != NULL);
  csv_data.header[strcspn(csv_data.header, "\n")] = 0;
  ENSURE_MSG(strcmp(csv_data.header, header) == 0, "%s: header '%s', expected '%s'", name, csv_data.header,
             header);
  char line[1024];
  while (fgets(line, sizeof line, f)) {
    ENSURE(csv_data.row_count < 32);
    line[strcspn(line, "\n")] = 0;
    snprintf(csv_data.rows[csv_data.row_count++], sizeof line, "%s", line);
  }
  fclose(f);
  ENSURE_MSG(csv_data.row_count == rows, "%s: %u rows, expected %u", name, csv_data.row_count, rows);
  return &csv_data;
}

// The field of a row under a header key, as text.
static const char* csv_field(const csv_table* t, uint32_t row, const char* key) {
  static char field[128];
  uint32_t column = 0;
  const char* h = t->header;
  size_t key_length = strlen(key);
  while (!(strncmp(h, key, key_length) == 0 && (h[key_length] == ',' || h[key_length] == 0))) {
    h = strchr(h, ',');
    ENSURE_MSG(h != NULL, "no column %s in %s", key, t->header);
    ++h;
    ++column;
  }
  const char* f = t->rows[row];
  for (uint32_t c = 0; c < column; ++c) {
    f = strchr(f, ',');
    ENSURE_MSG(f != NULL, "row %u is short: %s", row, t->rows[row]);
    ++f;
  }
  snprintf(field, sizeof field, "%.*s", (int)strcspn(f, ","), f);
  return field;
}

static double csv_number(const csv_table* t, uint32_t row, const char* key) {
  const char* text = csv_field(t, row, key);
  char* end = NULL;
  double value = strtod(text, &end);
  ENSURE_MSG(end != text && *end == 0, "%s of row %u is not a number: '%s'", key, row, text);
  return value;
}

// Every row's value of each key is finite and > 0.
static void ensure_positive(const csv_table* t, const char* const* keys, size_t count) {
  for (uint32_t r = 0; r < t->row_count; ++r)
    for (size_t k = 0; k < count; ++k) {
      double value = csv_number(t, r, keys[k]);
      ENSURE_MSG(isfinite(value) && value > 0.0, "%s of row %u is %g", keys[k], r, value);
    }
}

static bool bench_file_exists(const char* name) {
  char path[512];
  snprintf(path, sizeof path, "%s/bench/%s", BK_TEST_TMP, name);
  FILE* f = fopen(path, "rb");
  if (f) fclose(f);
  return f != NULL;
}

// 7. Fracture patterns (--quick): each pattern at 64 and 1024 pieces (brick
// and planes on the wall, the others on the bunny) and planes and each cell
// pattern with noise at 1024; every row's tree closed, with all its pieces and its volume.
static void test_bench_patterns(const char* out, const char* report) {
  static const struct {
    const char* mesh;
    const char* pattern;
    uint32_t pieces;
    bool noisy;
  } expected[] = {{"bunny", "planes", 64, false},     {"bunny", "planes", 1024, false},
                  {"bunny", "voronoi", 64, false},    {"bunny", "voronoi", 1024, false},
                  {"bunny", "clustered", 64, false},  {"bunny", "clustered", 1024, false},
                  {"bunny", "radial", 64, false},     {"bunny", "radial", 1024, false},
                  {"wall", "brick", 64, false},       {"wall", "brick", 1024, false},
                  {"wall", "planes", 64, false},      {"wall", "planes", 1024, false},
                  {"bunny", "planes", 1024, true},    {"bunny", "voronoi", 1024, true},
                  {"bunny", "clustered", 1024, true}, {"bunny", "radial", 1024, true}};
  enum { EXPECTED = sizeof expected / sizeof *expected };
  const csv_table* t =
      read_csv("patterns",
               "mesh,pattern,noise,fragments,runs,ms_median,leaves,nodes,bonds,leaf_triangles,"
               "sliver_fraction,volume_ratio_p95_p5,open_nodes,volume_rel_error",
               EXPECTED);
  const char* keys[] = {"ms_median", "leaves", "nodes", "bonds", "leaf_triangles", "volume_ratio_p95_p5"};
  ensure_positive(t, keys, sizeof keys / sizeof *keys);
  for (uint32_t e = 0; e < EXPECTED; ++e) {
    uint32_t found = 0;
    for (uint32_t i = 0; i < t->row_count; ++i)
      found += strcmp(csv_field(t, i, "mesh"), expected[e].mesh) == 0 &&
               strcmp(csv_field(t, i, "pattern"), expected[e].pattern) == 0 &&
               csv_number(t, i, "fragments") == expected[e].pieces &&
               (csv_number(t, i, "noise") > 0.0) == expected[e].noisy;
    ENSURE_MSG(found == 1, "patterns.csv has %u rows of %s on the %s at %u pieces%s", found,
               expected[e].pattern, expected[e].mesh, expected[e].pieces,
               expected[e].noisy ? " with noise" : "");
  }
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE_MSG(csv_number(t, i, "open_nodes") == 0.0, "patterns.csv row %u (%s) has open nodes", i,
               csv_field(t, i, "pattern"));
    ENSURE(csv_number(t, i, "runs") == 1.0 && csv_number(t, i, "leaves") == csv_number(t, i, "fragments"));
    ENSURE(csv_number(t, i, "nodes") >= csv_number(t, i, "leaves"));
    double slivers = csv_number(t, i, "sliver_fraction");
    ENSURE(slivers >= 0.0 && slivers <= 1.0 && csv_number(t, i, "volume_ratio_p95_p5") >= 1.0);
    ENSURE(csv_number(t, i, "volume_rel_error") < 1e-9);
  }
  // The answers: planes' time against each cell pattern's, Voronoi's slivers against planes'.
  const char* answers[] = {"**Are the cell patterns fast enough?** At 1024 pieces on the bunny, planes take",
                           "**Do Voronoi cells avoid slivers?**", "Every tree is closed"};
  for (size_t i = 0; i < sizeof answers / sizeof *answers; ++i)
    ENSURE_MSG(strstr(report, answers[i]) != NULL, "report lacks %s", answers[i]);
  const char* lines[] = {
      "voronoi at 1024 pieces on the bunny: ", "clustered at 1024 pieces on the bunny: ",
      "radial at 1024 pieces on the bunny: ", "slivers at 1024 pieces on the bunny: voronoi"};
  for (size_t i = 0; i < sizeof lines / sizeof *lines; ++i)
    ENSURE_MSG(strstr(out, lines[i]) != NULL, "stdout lacks '%s'", lines[i]);
}

// 9. Physics budget: each load without a budget, with the world's default
// one, and with it keeping nothing of a new piece (fidelity 0 s).
static void test_bench_budget(const char* report) {
  const csv_table* t = read_csv(
      "budget",
      "load,fragments,shots,budget_ms,fidelity_s,bodies_peak,physics_ms_p50,physics_ms_p95,physics_ms_max,"
      "physics_ms_p95_first_second,physics_ms_p95_later,break_ms_p50,break_ms_p99,break_ms_max,"
      "break_wait_steps_max,settled_physics_ms,debris,simplified,frozen,retired,demotions,restorations,"
      "mass_retired_fraction,debris_mass_ratio,debris_momentum_ratio,debris_net_momentum_ratio,near_mass_"
      "ratio,near_momentum_ratio,near_net_momentum_ratio,target_met,settled_met,near_fidelity_kept",
      9);
  const char* keys[] = {
      "bodies_peak",  "physics_ms_p50", "physics_ms_p95", "physics_ms_max", "physics_ms_p95_first_second",
      "break_ms_p50", "break_ms_p99",   "break_ms_max"};
  ensure_positive(t, keys, sizeof keys / sizeof *keys);
  const char* tiers[] = {"debris", "simplified", "frozen", "retired", "demotions", "restorations"};
  static const char* const loads[] = {"showcase volley", "walls", "cube"};
  const double fragments[] = {384, 4096, 512}; // --quick: 3 objects of 128, 4 walls and a cube of 512
  const double budget = bk_default_world_def().physics_budget_ms;
  double demotions = 0.0;
  for (uint32_t i = 0; i < t->row_count; ++i) {
    uint32_t load = i / 3, off = 3 * load;
    ENSURE(strcmp(csv_field(t, i, "load"), loads[load]) == 0);
    ENSURE_MSG(csv_number(t, i, "fragments") >= fragments[load], "row %u: %s fragments", i,
               csv_field(t, i, "fragments"));
    ENSURE(csv_number(t, i, "fragments") == csv_number(t, off, "fragments"));
    ENSURE(csv_number(t, i, "physics_ms_p50") <= csv_number(t, i, "physics_ms_p95") &&
           csv_number(t, i, "physics_ms_p95") <= csv_number(t, i, "physics_ms_max"));
    // Each window's p95 is one of the steps', and the steps before the first shot are not in any.
    ENSURE(csv_number(t, i, "physics_ms_p95_first_second") <= csv_number(t, i, "physics_ms_max") &&
           csv_number(t, i, "physics_ms_p95_later") <= csv_number(t, i, "physics_ms_max"));
    ENSURE(csv_number(t, i, "break_ms_p50") <= csv_number(t, i, "break_ms_p99") &&
           csv_number(t, i, "break_ms_p99") <= csv_number(t, i, "break_ms_max"));
    ENSURE(csv_number(t, i, "settled_physics_ms") >= 0.0 && csv_number(t, i, "break_wait_steps_max") >= 0.0);
    double fraction = csv_number(t, i, "mass_retired_fraction");
    ENSURE(fraction >= 0.0 && fraction <= 1.0);
    if (i == off) {
      // Without a budget nothing is made cheaper, and the ratios are to itself.
      const char* dashes[] = {"fidelity_s", "target_met", "settled_met", "near_fidelity_kept"};
      for (size_t k = 0; k < sizeof dashes / sizeof *dashes; ++k)
        ENSURE_MSG(strcmp(csv_field(t, i, dashes[k]), "-") == 0, "row %u: %s '%s'", i, dashes[k],
                   csv_field(t, i, dashes[k]));
      ENSURE(csv_number(t, i, "budget_ms") == 0.0);
      for (size_t k = 0; k < sizeof tiers / sizeof *tiers; ++k)
        ENSURE_MSG(csv_number(t, i, tiers[k]) == 0.0, "row %u: %s without a budget", i, tiers[k]);
      ENSURE(fraction == 0.0 && csv_number(t, i, "debris_mass_ratio") == 1.0 &&
             csv_number(t, i, "near_mass_ratio") == 1.0);
      continue;
    }
    ENSURE(csv_number(t, i, "budget_ms") == budget);
    ENSURE(csv_number(t, i, "fidelity_s") == (i == off + 1 ? 1.0 : 0.0));
    const char* flags[] = {"target_met", "settled_met", "near_fidelity_kept"};
    for (int k = 0; k < 3; ++k) {
      const char* flag = csv_field(t, i, flags[k]);
      ENSURE_MSG(strcmp(flag, "yes") == 0 || strcmp(flag, "no") == 0, "%s of row %u is '%s'", flags[k], i,
                 flag);
    }
    // "yes" exactly when all three near ratios are within 5%, and the settled cost under 1 ms.
    bool kept = true;
    const char* ratios[3] = {"near_mass_ratio", "near_momentum_ratio", "near_net_momentum_ratio"};
    for (int k = 0; k < 3; ++k)
      kept = kept && fabs(csv_number(t, i, ratios[k]) - 1.0) <= 0.05;
    ENSURE_MSG(kept == (strcmp(csv_field(t, i, "near_fidelity_kept"), "yes") == 0), "row %u: '%s'", i,
               csv_field(t, i, "near_fidelity_kept"));
    ENSURE((csv_number(t, i, "settled_physics_ms") < 1.0) ==
           (strcmp(csv_field(t, i, "settled_met"), "yes") == 0));
    ENSURE(csv_number(t, i, "debris_mass_ratio") > 0.0 && csv_number(t, i, "debris_momentum_ratio") > 0.0);
    demotions += csv_number(t, i, "demotions");
  }
  ENSURE_MSG(demotions > 0.0, "the budget made nothing cheaper in any load");
  // Keeping nothing of a new piece lets the budget make more of the walls
  // cheaper, sooner (which tier takes them depends on when the pieces come
  // loose: hits spread over steps reach the pieces later).
  ENSURE_MSG(csv_number(t, 5, "demotions") > csv_number(t, 4, "demotions"),
             "the walls' pieces were made cheaper %s times keeping nothing, %s keeping 1 s",
             csv_field(t, 5, "demotions"), csv_field(t, 4, "demotions"));
  ENSURE(strstr(report, "and does what the player sees stay?**") != NULL);
}

// 10. Refinement (--quick): four arcs of a torus each hit once, through the
// world and the runtime alone, on a worker and synchronous, and the walls of
// 64 (refined and not) and 1024 shot alike.
static void test_bench_refine(const char* report) {
  const csv_table* t =
      read_csv("refine_speed",
               "setup,latency,hits,refined,leaf_triangles,refine_ms_p50,refine_ms_p99,refine_ms_"
               "max,start_ms_max,bodies_ms_p50,bodies_ms_p99,bodies_ms_max,step_ms_p99,steps_"
               "to_bodies_max,target_met",
               5);
  static const char* const setups[] = {"world: on a worker", "world: synchronous", "runtime: on a worker",
                                       "runtime: synchronous", "worker: the fracture alone"};
  const char* times[] = {"refine_ms_p50", "refine_ms_p99", "refine_ms_max", "leaf_triangles"};
  ensure_positive(t, times, sizeof times / sizeof *times);
  for (uint32_t i = 0; i < 5; ++i) {
    ENSURE_MSG(strcmp(csv_field(t, i, "setup"), setups[i]) == 0, "row %u: %s", i, csv_field(t, i, "setup"));
    // Each hit refines the arc it strikes, and no other.
    ENSURE(csv_number(t, i, "hits") == 4.0 && csv_number(t, i, "refined") == 4.0);
    ENSURE(csv_number(t, i, "refine_ms_p50") <= csv_number(t, i, "refine_ms_p99") &&
           csv_number(t, i, "refine_ms_p99") <= csv_number(t, i, "refine_ms_max"));
    if (i == 4) {
      ENSURE(strcmp(csv_field(t, i, "latency"), "-") == 0 && strcmp(csv_field(t, i, "target_met"), "-") == 0);
      continue;
    }
    // On a worker the pieces have bodies in the step after the hit's, synchronous in the hit's own.
    double latency = csv_number(t, i, "latency");
    ENSURE(latency == (i % 2 == 0 ? 1.0 : 0.0));
    ENSURE_MSG(csv_number(t, i, "steps_to_bodies_max") == latency + 1.0, "row %u: %s steps", i,
               csv_field(t, i, "steps_to_bodies_max"));
    ENSURE(csv_number(t, i, "bodies_ms_p50") > 0.0 &&
           csv_number(t, i, "bodies_ms_p50") <= csv_number(t, i, "bodies_ms_max"));
    ENSURE(csv_number(t, i, "step_ms_p99") >= csv_number(t, i, "bodies_ms_p50"));
    bool met = csv_number(t, i, "step_ms_p99") <= 2.0;
    ENSURE_MSG(strcmp(csv_field(t, i, "target_met"), met ? "yes" : "no") == 0, "row %u: target_met '%s'", i,
               csv_field(t, i, "target_met"));
  }
  // What the worker buys: the landing call no longer fractures.
  ENSURE_MSG(csv_number(t, 2, "refine_ms_p50") < csv_number(t, 3, "refine_ms_p50"),
             "the runtime lands a refinement in %s ms on a worker, %s synchronous",
             csv_field(t, 2, "refine_ms_p50"), csv_field(t, 3, "refine_ms_p50"));
  ENSURE(csv_number(t, 3, "refine_ms_p50") > csv_number(t, 4, "refine_ms_p50") * 0.5);

  t = read_csv(
      "refine_walls",
      "wall,refine,fragments_load,fragments_end,refined_leaves,tree_kb_load,tree_kb_end,fracture_ms,cached_"
      "load_ms,bodies_max,bodies_end,colliders_max,colliders_end,near_shot_mean,near_shot_min,near_shot_"
      "max,physics_ms_mean,physics_ms_p99,refine_ms_p99,refine_ms_max,bodies_ms_p99,bodies_ms_max",
      3);
  const char* positive[] = {"fragments_load", "tree_kb_load",  "fracture_ms",    "cached_load_ms",
                            "bodies_end",     "colliders_end", "near_shot_mean", "physics_ms_p99"};
  ensure_positive(t, positive, sizeof positive / sizeof *positive);
  const double pieces[] = {64, 64, 1024};
  for (uint32_t i = 0; i < 3; ++i) {
    bool refined = i == 1;
    ENSURE(csv_number(t, i, "wall") == pieces[i] && csv_number(t, i, "fragments_load") == pieces[i]);
    ENSURE(strcmp(csv_field(t, i, "refine"), refined ? "yes" : "no") == 0);
    ENSURE(csv_number(t, i, "bodies_max") >= csv_number(t, i, "bodies_end") &&
           csv_number(t, i, "colliders_max") >= csv_number(t, i, "colliders_end"));
    ENSURE(csv_number(t, i, "near_shot_min") <= csv_number(t, i, "near_shot_mean") &&
           csv_number(t, i, "near_shot_mean") <= csv_number(t, i, "near_shot_max") &&
           csv_number(t, i, "near_shot_max") <= csv_number(t, i, "fragments_end"));
    if (!refined) {
      // Without refinement the tree is the one loaded, to the end.
      ENSURE(csv_number(t, i, "refined_leaves") == 0.0 && csv_number(t, i, "refine_ms_max") == 0.0);
      ENSURE(csv_number(t, i, "fragments_end") == pieces[i]);
      ENSURE(strcmp(csv_field(t, i, "tree_kb_end"), csv_field(t, i, "tree_kb_load")) == 0);
    }
  }
  // Refinement grew the coarse wall where it was shot: more fragments near
  // the shots than the coarse wall has, fewer in all than the fine wall.
  ENSURE(csv_number(t, 1, "refined_leaves") > 0.0 && csv_number(t, 1, "refine_ms_max") > 0.0);
  ENSURE(csv_number(t, 1, "fragments_end") > 64.0 &&
         csv_number(t, 1, "tree_kb_end") > csv_number(t, 1, "tree_kb_load"));
  ENSURE_MSG(csv_number(t, 1, "near_shot_mean") > 2.0 * csv_number(t, 0, "near_shot_mean"),
             "near the shots: %s fragments refined, %s coarse", csv_field(t, 1, "near_shot_mean"),
             csv_field(t, 0, "near_shot_mean"));
  ENSURE_MSG(csv_number(t, 1, "fragments_end") < csv_number(t, 2, "fragments_end"),
             "the refined wall ends with %s fragments, the 1024 wall %s", csv_field(t, 1, "fragments_end"),
             csv_field(t, 2, "fragments_end"));
  ENSURE(csv_number(t, 2, "fracture_ms") > csv_number(t, 0, "fracture_ms") &&
         csv_number(t, 2, "tree_kb_load") > csv_number(t, 0, "tree_kb_load"));
  const char* answers[] = {"**Does refining a fragment of about 10,000 triangles into 32 pieces keep to 2 ms",
                           "**What does refinement buy against a finer pre-fractured wall?**", "Here J was"};
  for (size_t i = 0; i < sizeof answers / sizeof *answers; ++i)
    ENSURE_MSG(strstr(report, answers[i]) != NULL, "report lacks %s", answers[i]);
  ENSURE(!bench_file_exists("refine_wall_64.mtree") && !bench_file_exists("refine_wall_1024.mtree"));
}

static void test_bench_quick(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  run_result* r = run("bench --quick --out '" BK_TEST_TMP "/bench'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  const char* sections[] = {"1. Fracture speed",    "2. Meshes",
                            "3. Maximum fragments", "4. Runtime",
                            "5. Scaling",           "6. Asset pipeline",
                            "7. Fracture patterns", "8. Structural stress",
                            "9. Physics budget",    "10. Refinement at the impact"};
  for (size_t i = 0; i < sizeof sections / sizeof *sections; ++i)
    ENSURE_MSG(strstr(r->out, sections[i]) != NULL, "stdout lacks %s", sections[i]);

  // The report: command, machine, every section, and the plots (or why they are missing).
  static char report[1 << 17];
  FILE* f = fopen(BK_TEST_TMP "/bench/report.md", "rb");
  ENSURE(f != NULL);
  report[fread(report, 1, sizeof report - 1, f)] = 0;
  fclose(f);
  const char* report_parts[] = {"bench --quick --out",
                                "| processor |",
                                "| memory |",
                                "| build |",
                                "| date |",
                                "## 1. Fracture speed",
                                "## 5. Scaling",
                                "## 6. Asset pipeline",
                                "## 7. Fracture patterns",
                                "## 9. Physics budget",
                                "## 10. Refinement at the impact",
                                "| ---: |"};
  for (size_t i = 0; i < sizeof report_parts / sizeof *report_parts; ++i)
    ENSURE_MSG(strstr(report, report_parts[i]) != NULL, "report lacks %s", report_parts[i]);
  bool gnuplot = system("command -v gnuplot >/dev/null 2>&1") == 0;
  const char* plots[] = {"fracture_speed.png",   "runtime.png", "colliders.png",    "patterns_time.png",
                         "patterns_slivers.png", "budget.png",  "refine_speed.png", "refine_walls.png"};
  for (size_t i = 0; i < sizeof plots / sizeof *plots; ++i) {
    char embedded[64];
    snprintf(embedded, sizeof embedded, "](%s)", plots[i]);
    if (gnuplot) {
      ENSURE_MSG(bench_file_exists(plots[i]), "missing %s", plots[i]);
      ENSURE_MSG(strstr(report, embedded) != NULL, "report does not embed %s", plots[i]);
    } else {
      ENSURE(strstr(report, "gnuplot is not on PATH") != NULL);
    }
  }

  // 1. Fracture speed: 2 .. 1024 fragments.
  const csv_table* t = read_csv(
      "fracture_speed", "fragments,leaves,nodes,leaf_triangles,runs,ms_median,ms_min,us_per_fragment", 10);
  const char* speed_keys[] = {"ms_median", "ms_min", "us_per_fragment", "leaf_triangles"};
  ensure_positive(t, speed_keys, 4);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE(csv_number(t, i, "fragments") == (double)(2u << i));
    ENSURE(csv_number(t, i, "leaves") >= csv_number(t, i, "fragments"));
    ENSURE(csv_number(t, i, "nodes") == 2.0 * csv_number(t, i, "leaves") - 1.0);
  }
  // 2. Meshes: four, all watertight.
  t = read_csv(
      "meshes",
      "mesh,source_triangles,leaves,runs,ms_median,leaf_triangles,volume_spread,tiny_leaves,watertight", 4);
  const char* mesh_keys[] = {"ms_median", "leaf_triangles", "volume_spread"};
  ensure_positive(t, mesh_keys, 3);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE(strcmp(csv_field(t, i, "watertight"), "true") == 0);
    ENSURE(csv_number(t, i, "volume_spread") >= 1.0 && csv_number(t, i, "leaves") >= 256);
  }
  ENSURE(strcmp(csv_field(t, 3, "mesh"), "bunny") == 0);
  // 3. Maximum fragments: 2 .. 2048, every level watertight with exact volumes.
  t = read_csv("max_fragments",
               "fragments,leaves,nodes,ms,watertight,open_nodes,volume_rel_error,child_volume_rel_error", 11);
  const char* max_keys[] = {"ms", "leaves", "nodes"};
  ensure_positive(t, max_keys, 3);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE_MSG(strcmp(csv_field(t, i, "watertight"), "true") == 0, "level %u is not watertight", i);
    ENSURE(csv_number(t, i, "open_nodes") == 0.0);
    ENSURE(csv_number(t, i, "volume_rel_error") < 1e-9 && csv_number(t, i, "child_volume_rel_error") < 1e-9);
  }
  ENSURE(strstr(r->out, "first failure: none up to 2048") != NULL);
  // 4. Runtime: wall and cube, 2 .. 256 fragments each.
  t = read_csv(
      "runtime",
      "object,fragments,bodies,colliders,naive_colliders,collider_ratio,before_ms,naive_before_ms,"
      "before_ratio,hit_physics_ms,hit_break_ms,naive_hit_physics_ms,naive_hit_break_ms,hit_median_ms,"
      "naive_hit_median_ms,step_ratio,after_ms,naive_after_ms",
      16);
  const char* runtime_keys[] = {"before_ms",      "naive_before_ms",      "hit_physics_ms",
                                "hit_break_ms",   "naive_hit_physics_ms", "naive_hit_break_ms",
                                "hit_median_ms",  "naive_hit_median_ms",  "after_ms",
                                "naive_after_ms", "step_ratio",           "before_ratio",
                                "colliders"};
  ensure_positive(t, runtime_keys, sizeof runtime_keys / sizeof *runtime_keys);
  for (uint32_t i = 0; i < t->row_count; ++i) {
    ENSURE(strcmp(csv_field(t, i, "object"), i < 8 ? "wall" : "cube") == 0);
    ENSURE(csv_number(t, i, "collider_ratio") >= 1.0);
    ENSURE(csv_number(t, i, "naive_colliders") == csv_number(t, i, "fragments"));
    ENSURE(csv_number(t, i, "colliders") <= csv_number(t, i, "naive_colliders"));
  }
  // The largest wall breaks into several bodies.
  ENSURE(csv_number(t, 7, "bodies") > 1.0);
  // 5. Scaling: 1 and 4 walls.
  t = read_csv(
      "scaling",
      "walls,fragments,bodies,colliders,step_ms_median,step_ms_max,break_ms_max,start_rss_mb,peak_rss_mb", 2);
  const char* scaling_keys[] = {"step_ms_median", "step_ms_max", "break_ms_max", "peak_rss_mb"};
  ensure_positive(t, scaling_keys, 4);
  ENSURE(csv_number(t, 0, "walls") == 1.0 && csv_number(t, 1, "walls") == 4.0);
  ENSURE(csv_number(t, 1, "step_ms_max") >= csv_number(t, 1, "step_ms_median"));
  // 6. Asset pipeline: export and load-back of the cube of 1024 fragments, import of 100,000 triangles.
  t = read_csv("assets", "step,source,nodes,triangles,file_mb,runs,ms_median,ms_min,target_ms,target_met", 3);
  const char* asset_keys[] = {"nodes", "triangles", "file_mb", "runs", "ms_median", "ms_min"};
  ensure_positive(t, asset_keys, sizeof asset_keys / sizeof *asset_keys);
  ENSURE(strcmp(csv_field(t, 0, "step"), "export .glb") == 0 && csv_number(t, 0, "nodes") == 2047.0);
  ENSURE(strcmp(csv_field(t, 1, "step"), "load back .glb") == 0 &&
         strcmp(csv_field(t, 1, "target_met"), "-") == 0);
  ENSURE(strcmp(csv_field(t, 2, "step"), "import .glb") == 0 && csv_number(t, 2, "triangles") == 100000.0);
  ENSURE(csv_number(t, 0, "target_ms") == 1000.0 && csv_number(t, 2, "target_ms") == 500.0);
  for (uint32_t i = 0; i < 3; i += 2) {
    const char* met = csv_field(t, i, "target_met");
    ENSURE_MSG(strcmp(met, "yes") == 0 || strcmp(met, "no") == 0, "target_met of row %u is '%s'", i, met);
  }
  ENSURE_MSG(strstr(report, "the target of under 1 s for 4096 fragments is ") != NULL &&
                 strstr(report, "`--quick`; run without it to measure 4096") != NULL,
             "the report does not state the export target and the quick cube");
  ENSURE(!bench_file_exists("cube_1024.glb") && !bench_file_exists("torus_100000.glb"));
  test_bench_patterns(r->out, report);
  test_bench_budget(report);
  test_bench_refine(report);

  r = run("bench --help");
  const char* options[] = {"--quick", "--out", "--seed"};
  for (size_t i = 0; i < sizeof options / sizeof *options; ++i)
    ENSURE_MSG(strstr(r->out, options[i]) != NULL, "bench help does not describe %s", options[i]);
  write_file("not_a_dir", "x");
  expect_error("bench --quick --out '" BK_TEST_TMP "/not_a_dir/bench'", 1, "cannot create directory");
  expect_error("bench --seed x", 2, "--seed 'x' is not a whole number (0..18446744073709551615)");
  expect_error("bench --out", 2, "--out needs a value");
  expect_error("bench --slow", 2, "unknown option '--slow'");
  expect_error("bench --only 11", 2, "breakables bench: --only '11' is out of range (1..10)");

  // --only: that section alone.
  r = run("bench --quick --only 1 --out '" BK_TEST_TMP "/bench_only'");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(strstr(r->out, "1. Fracture speed") != NULL);
  for (size_t i = 1; i < sizeof sections / sizeof *sections; ++i)
    ENSURE_MSG(strstr(r->out, sections[i]) == NULL, "--only 1 ran %s", sections[i]);
}

int main(void) {
  RUN(test_bench_quick);
  return 0;
}
