// 'breakables bench', section 6: the speed of the asset pipeline against
// issue 15's targets: the mesh tree of a cube written to .glb and loaded back,
// and a 100k-triangle glTF read by the model importer (assimp).
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "app.h"
#include "bench_report.h"
#include "scene_run.h"

enum {
  ASSET_MAX_RUNS = 5,
  EXPORT_PIECES = 4096,       ///< the target's cube
  QUICK_EXPORT_PIECES = 1024, ///< --quick's cube
  TORUS_RING = 250,           ///< segments around the ring of the import test's torus ...
  TORUS_TUBE = 200,           ///< ... and around its tube: 2 x 250 x 200 = 100,000 triangles
};

static const double export_target_ms = 1000.0, import_target_ms = 500.0;
static const double pi = 3.14159265358979323846;

static uint32_t asset_runs(const bench* b) { return b->quick ? 3 : ASSET_MAX_RUNS; }

void bench_fine_torus(uint32_t ring, uint32_t tube, bk_mesh* m) {
  const double major = 1.0, minor = 0.35;
  bk_mesh_reserve(m, ring * tube, (ring + 1) * (tube + 1), 2 * ring * tube);
  for (uint32_t i = 0; i < ring; ++i) {
    double phi = 2.0 * pi * i / ring;
    for (uint32_t j = 0; j < tube; ++j) {
      double theta = 2.0 * pi * j / tube, rho = major + minor * cos(theta);
      bk_mesh_add_position(m, (bk_vec3){rho * cos(phi), minor * sin(theta), -rho * sin(phi)});
    }
  }
  for (uint32_t i = 0; i <= ring; ++i) {
    double phi = 2.0 * pi * i / ring;
    for (uint32_t j = 0; j <= tube; ++j) {
      double theta = 2.0 * pi * j / tube;
      bk_corner c = {
          .position = (i % ring) * tube + j % tube,
          .normal = {(float)(cos(theta) * cos(phi)), (float)sin(theta), (float)(-cos(theta) * sin(phi))},
          .uv = {(float)(3.0 * i / ring), (float)j / tube}};
      bk_mesh_add_corner(m, &c);
    }
  }
  for (uint32_t i = 0; i < ring; ++i)
    for (uint32_t j = 0; j < tube; ++j) {
      uint32_t c00 = i * (tube + 1) + j, c10 = (i + 1) * (tube + 1) + j;
      bk_mesh_add_triangle(m, c00, c10, c10 + 1, BK_MATERIAL_OUTER, 0);
      bk_mesh_add_triangle(m, c00, c10 + 1, c00 + 1, BK_MATERIAL_OUTER, 0);
    }
  bk_mesh_compute_tangents(m);
}

static double file_mb(const char* path) {
  struct stat st = {0};
  return stat(path, &st) == 0 ? (double)st.st_size / 1e6 : 0.0;
}

/// One timed step: the median and fastest of its runs.
typedef struct asset_timing {
  double times[ASSET_MAX_RUNS];
  uint32_t runs;
  double median_ms, min_ms;
} asset_timing;

static void timing_add(asset_timing* t, double ms) {
  if (t->runs < ASSET_MAX_RUNS) t->times[t->runs++] = ms;
}

static void timing_finish(asset_timing* t) {
  if (t->runs == 0) return;
  t->min_ms = t->times[0];
  for (uint32_t r = 1; r < t->runs; ++r)
    t->min_ms = fmin(t->min_ms, t->times[r]);
  double sorted[ASSET_MAX_RUNS];
  memcpy(sorted, t->times, sizeof sorted);
  t->median_ms = app_median(sorted, t->runs);
}

// The triangles the default export holds: the fragments' (the inner nodes
// of the hierarchy carry no mesh).
static uint32_t tree_triangles(const bk_mesh_tree* tree) {
  uint32_t sum = 0;
  for (uint32_t n = 0; n < tree->node_count; ++n)
    if (tree->nodes[n].child_count == 0) sum += tree->nodes[n].mesh.triangle_count;
  return sum;
}

typedef struct export_result {
  uint32_t pieces, nodes, triangles;
  double mb;
  asset_timing save, load;
  bool same; ///< the loaded tree has the saved tree's nodes and leaves
} export_result;

/// Builds the cube's tree, times its export (the default: the node hierarchy, meshes on the fragments) and
/// its load-back, and deletes the file.
static bool measure_export(const bench* b, uint32_t pieces, export_result* out) {
  bk_mesh cube = {0};
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bk_fracture_def fracture = bk_default_fracture_def();
  fracture.pieces = pieces;
  fracture.seed = b->seed;
  bk_gltf_def gltf = bk_default_gltf_def();
  char path[4096];
  snprintf(path, sizeof path, "%s/cube_%u.glb", b->dir, pieces);
  bool ok = bk_mesh_tree_build(&cube, &fracture, &tree, &err);
  out->pieces = pieces;
  out->nodes = tree.node_count;
  out->triangles = tree_triangles(&tree);
  out->same = true;
  for (uint32_t r = 0; ok && r < asset_runs(b); ++r) {
    double start = app_now_ms();
    ok = bk_mesh_tree_save_gltf(&tree, path, &gltf, &err);
    timing_add(&out->save, app_now_ms() - start);
  }
  out->mb = ok ? file_mb(path) : 0.0;
  for (uint32_t r = 0; ok && r < asset_runs(b); ++r) {
    bk_mesh_tree loaded = {0};
    double start = app_now_ms();
    ok = bk_mesh_tree_load_gltf(path, &loaded, &err);
    timing_add(&out->load, app_now_ms() - start);
    out->same = out->same && loaded.node_count == tree.node_count && loaded.leaf_count == tree.leaf_count;
    bk_mesh_tree_free(&loaded);
  }
  if (!ok)
    fprintf(stderr, "breakables bench: glTF export of the cube of %u fragments: %s\n", pieces, err.message);
  remove(path);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&cube);
  timing_finish(&out->save);
  timing_finish(&out->load);
  return ok;
}

typedef struct import_result {
  uint32_t triangles_written, triangles_in, triangles_out;
  double mb;
  asset_timing import;
} import_result;

/// Writes the fine torus as a .glb (a tree of one piece, its leaf exported)
/// and times bk_model_import of it; deletes the file.
static bool measure_import(const bench* b, import_result* out) {
  bk_mesh torus = {0}, imported = {0};
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  bench_fine_torus(TORUS_RING, TORUS_TUBE, &torus);
  out->triangles_written = torus.triangle_count;
  bk_fracture_def fracture = bk_default_fracture_def();
  fracture.pieces = 1;
  fracture.seed = b->seed;
  bk_gltf_def gltf = bk_default_gltf_def();
  gltf.levels = BK_GLTF_LEVELS_LEAVES;
  bk_import_def import = bk_default_import_def();
  char path[4096];
  snprintf(path, sizeof path, "%s/torus_%u.glb", b->dir, torus.triangle_count);
  bool ok =
      bk_mesh_tree_build(&torus, &fracture, &tree, &err) && bk_mesh_tree_save_gltf(&tree, path, &gltf, &err);
  out->mb = ok ? file_mb(path) : 0.0;
  for (uint32_t r = 0; ok && r < asset_runs(b); ++r) {
    bk_import_info info = {0};
    bk_mesh_free(&imported);
    double start = app_now_ms();
    ok = bk_model_import(path, &import, &imported, &info, &err);
    timing_add(&out->import, app_now_ms() - start);
    out->triangles_in = info.triangles_in;
    out->triangles_out = imported.triangle_count;
    bk_import_info_free(&info);
  }
  if (!ok)
    fprintf(stderr, "breakables bench: glTF import of a torus of %u triangles: %s\n", torus.triangle_count,
            err.message);
  remove(path);
  bk_mesh_free(&imported);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&torus);
  timing_finish(&out->import);
  return ok;
}

static const char* verdict(double ms, double target_ms) { return ms < target_ms ? "met" : "NOT MET"; }

static void asset_cells(bench_table* t, const char* step, const char* source, uint32_t nodes,
                        uint32_t triangles, double mb, const asset_timing* timing, double target_ms) {
  bench_table_cell(t, "%s", step);
  bench_table_cell(t, "%s", source);
  bench_table_cell(t, "%u", nodes);
  bench_table_cell(t, "%u", triangles);
  bench_table_cell(t, "%.3g", mb);
  bench_table_cell(t, "%u", timing->runs);
  bench_table_cell(t, "%.4g", timing->median_ms);
  bench_table_cell(t, "%.4g", timing->min_ms);
  if (target_ms > 0.0) {
    bench_table_cell(t, "%.0f", target_ms);
    bench_table_cell(t, "%s", timing->median_ms < target_ms ? "yes" : "no");
  } else {
    bench_table_cell(t, "-");
    bench_table_cell(t, "-");
  }
}

bool bench_section_assets(const bench* b) {
  static const bench_column columns[] = {{"step", "step"},           {"source", "source"},
                                         {"nodes", "glTF nodes"},    {"triangles", "triangles"},
                                         {"file_mb", "file MB"},     {"runs", "runs"},
                                         {"ms_median", "median ms"}, {"ms_min", "fastest ms"},
                                         {"target_ms", "target ms"}, {"target_met", "target met"}};
  uint32_t pieces = b->quick ? QUICK_EXPORT_PIECES : EXPORT_PIECES;
  char method[1024];
  snprintf(method, sizeof method,
           "Issue 15's speed targets. *Export*: the mesh tree of a unit cube of %u fragments%s (built once, "
           "not timed) written to `.glb` as its node hierarchy with meshes on the fragments and the exact "
           "tree inside (`bk_mesh_tree_save_gltf`, default parameters), "
           "and *load back*: the tree read from that file (`bk_mesh_tree_load_gltf`). *Import*: a closed "
           "ring torus of %u triangles, written to `.glb` as a tree of one piece, read by the model "
           "importer (`bk_model_import`: assimp, then welding and tangents). Median and fastest "
           "of %u runs each; the files are deleted afterwards. MB are 10^6 bytes.",
           pieces, b->quick ? " (`--quick`: the target is for 4096)" : "", 2u * TORUS_RING * TORUS_TUBE,
           asset_runs(b));
  bench_section(b, "6. Asset pipeline", method);
  export_result ex = {0};
  import_result im = {0};
  if (!measure_export(b, pieces, &ex) || !measure_import(b, &im)) return false;

  char cube[64], torus[64];
  snprintf(cube, sizeof cube, "cube of %u fragments", pieces);
  snprintf(torus, sizeof torus, "torus of %u triangles", im.triangles_written);
  bench_table t = bench_table_make("assets", columns, sizeof columns / sizeof *columns);
  asset_cells(&t, "export .glb", cube, ex.nodes, ex.triangles, ex.mb, &ex.save, export_target_ms);
  asset_cells(&t, "load back .glb", cube, ex.nodes, ex.triangles, ex.mb, &ex.load, 0.0);
  asset_cells(&t, "import .glb", torus, 1, im.triangles_in, im.mb, &im.import, import_target_ms);
  bool ok = bench_table_write(b, &t);
  bench_table_free(&t);
  if (!ok) return false;

  const char* export_verdict = verdict(ex.save.median_ms, export_target_ms);
  const char* import_verdict = verdict(im.import.median_ms, import_target_ms);
  printf("  export of %u fragments: %.4g ms, target under %.0f ms %s%s; import of %u triangles: %.4g ms, "
         "target under %.0f ms %s\n",
         pieces, ex.save.median_ms, export_target_ms, export_verdict,
         b->quick ? " (--quick: the target is for 4096 fragments)" : "", im.triangles_in, im.import.median_ms,
         import_target_ms, import_verdict);
  bench_say(b,
            "**Does the asset pipeline meet issue 15's speed targets?** Exporting the cube of %u fragments "
            "(%u nodes, %u triangles) to a %.3g MB `.glb` takes %.4g ms: the target of under 1 s for 4096 "
            "fragments is %s",
            pieces, ex.nodes, ex.triangles, ex.mb, ex.save.median_ms, export_verdict);
  if (b->quick) bench_say(b, " at %u fragments (`--quick`; run without it to measure 4096)", pieces);
  bench_say(b, ". Loading the tree back from the file takes %.4g ms%s. ", ex.load.median_ms,
            ex.same ? "" : " (BUT THE LOADED TREE DIFFERS IN SIZE)");
  bench_say(b,
            "Importing a glTF of %u triangles takes %.4g ms: the target of under 0.5 s is %s. The import "
            "read %u triangles and kept %u%s.\n",
            im.triangles_written, im.import.median_ms, import_verdict, im.triangles_in, im.triangles_out,
            im.triangles_out == im.triangles_written ? ", all of them" : " (NOT ALL OF THOSE WRITTEN)");
  return true;
}
