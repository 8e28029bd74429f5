// Private to 'breakables bench': the run's state, the output files, tables
// (CSV, aligned text on stdout and Markdown in the report), gnuplot plots and
// the report's header, shared by cmd_bench.c and the section files.
#pragma once

#include <limits.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <breakables/authoring.h>

#include "scene_run.h"
#include "scenes.h"

enum {
  BENCH_CELL_SIZE = 48, ///< characters per table cell
};

/// State of one benchmark run.
typedef struct bench {
  bool quick;
  uint64_t seed;
  const char* dir;
  const char* terminal; ///< gnuplot's PNG terminal (pngcairo or png); NULL when plots are skipped
  FILE* report;         ///< DIR/report.md (its temporary name until the end)
} bench;

// ---------------------------------------------------------------- output files

/// A file written under a temporary name and renamed into place when
/// complete (bk_file_begin_atomic: a file or symlink planted at a temporary
/// name is never opened or followed).
typedef struct bench_output {
  FILE* file; ///< write here
  char path[PATH_MAX];
  bk_atomic_file atomic;
} bench_output;

/// Opens DIR/<name> under its temporary name; prints why on stderr when it cannot.
bool bench_output_open(const bench* b, const char* name, bench_output* out);
/// Closes the file and renames it into place (keep = true), or removes it.
bool bench_output_close(bench_output* out, bool keep);
/// Creates the directory and its parents (like mkdir -p); false with errno set on failure.
bool bench_make_directories(const char* path);

/// Appends text to the report.
void bench_say(const bench* b, const char* format, ...) __attribute__((format(printf, 2, 3)));
/// Starts a section: a heading on stdout, a heading and what is measured in the report.
void bench_section(const bench* b, const char* title, const char* method);
/// Writes the report's title and the table of command, date, machine, build and seed.
void bench_report_header(const bench* b, int argc, char** argv);

// ---------------------------------------------------------------- tables

typedef struct bench_column {
  const char* key;   ///< CSV header
  const char* title; ///< stdout and Markdown header
} bench_column;

/// Rows of formatted cells, written once as CSV, as text on stdout and as Markdown.
typedef struct bench_table {
  const char* name; ///< CSV file DIR/<name>.csv
  const bench_column* columns;
  uint32_t column_count;
  char (*cells)[BENCH_CELL_SIZE];
  uint32_t cell_count, capacity;
} bench_table;

bench_table bench_table_make(const char* name, const bench_column* columns, uint32_t column_count);
/// Appends the next cell (row by row), formatted and cut to BENCH_CELL_SIZE - 1 characters.
void bench_table_cell(bench_table* t, const char* format, ...) __attribute__((format(printf, 2, 3)));
void bench_table_free(bench_table* t);
/// Writes DIR/<name>.csv, prints the table aligned on stdout and appends it to the report as Markdown.
bool bench_table_write(const bench* b, const bench_table* t);

// ---------------------------------------------------------------- measurements shared by sections

/// |sum of the leaves' mesh volumes - source volume| / source volume, from the geometry itself.
double bench_leaf_volume_error(const bk_mesh_tree* tree);
/// A closed ring torus (radii 1 and 0.35, lying in the xz plane round the
/// origin) of 2 * ring * tube triangles: positions are shared across the UV
/// seams, normals are exact, tangents computed (bench_assets.c; sections 6 and 10).
void bench_fine_torus(uint32_t ring, uint32_t tube, bk_mesh* m);

// ---------------------------------------------------------------- plots

/// gnuplot's PNG terminal: pngcairo, else png; NULL if gnuplot is missing or has neither.
const char* bench_gnuplot_terminal(void);

/// A gnuplot script being put together.
typedef struct bench_script {
  char text[8192];
  size_t length;
} bench_script;

/// Appends to the script (cut at its capacity).
void bench_script_add(bench_script* s, const char* format, ...) __attribute__((format(printf, 2, 3)));
/// Renders DIR/<name>.png with gnuplot (run in DIR, so the script names the
/// CSV files plainly; log-log axes) and embeds it in the report; notes it when skipped.
bool bench_plot(const bench* b, const char* name, const char* caption, int width, int height,
                const bench_script* script);

// ---------------------------------------------------------------- sections in files of their own

/// A free glass unit cube resting on the ground, shot at like the wall scene
/// (bench_runtime.c; sections 4 and 9).
extern const app_scene bench_cube_scene;
/// 4. Runtime (bench_runtime.c): an anchored wall and a free cube hit once,
/// mesh-tree colliders against plain BCRB.
bool bench_section_runtime(const bench* b);
/// 5. Scaling (bench_runtime.c): 1, 4 and 16 walls hit in the same step.
bool bench_section_scaling(const bench* b);
/// 6. Asset pipeline (bench_assets.c): glTF export and load-back of the cube
/// tree, and import of a 100k-triangle glTF, against issue 15's targets.
bool bench_section_assets(const bench* b);
/// 7. Fracture patterns (bench_patterns.c): each pattern's build time, tree
/// size and fragment quality against planes', on the bunny and the wall.
bool bench_section_patterns(const bench* b);
/// Section 8: the structural stress solve's cost against the bond count (bench_stress.c).
bool bench_section_stress(const bench* b);
/// 9. Physics budget (bench_budget.c): step and physics time percentiles
/// with the budget off and on, what it retired, and how much of the debris'
/// mass and momentum the player still sees.
bool bench_section_budget(const bench* b);
/// 10. Refinement at the impact (bench_refine.c): what refining a fragment
/// of 10,000 triangles into 32 pieces costs the calling thread a step, and
/// the wall of 64 fragments refined where it is shot against the wall of
/// 1,024 (bench_refine_wall.c).
bool bench_section_refine(const bench* b);
/// Its second part (bench_refine_wall.c): the wall scene of 64 fragments
/// refined where it is shot, against 64 and 1,024 without refinement.
bool bench_refine_walls(const bench* b);
