// breakables fracture: build a mesh tree from a mesh and report on it.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "app.h"
#include "commands.h"
#include "fracture_patterns.h"
#include "scene_run.h"
#include "tree_export.h"

// The ranges of the general options, stated by --help and enforced by parsing.
#define PIECES_MAX (1u << 20)
// Cut-face UVs are floats equal to coordinate / texture_scale: a micrometre
// to a thousand kilometres covers any real tile and keeps them finite for
// coordinates under 1e32 (the fracture checks the scale against the mesh).
#define TEXTURE_SCALE_MIN 1e-6
#define TEXTURE_SCALE_MAX 1e6

// --help: the defaults are bk_default_fracture_def's, the ranges those above.
static void print_usage(void) {
  bk_fracture_def d = bk_default_fracture_def();
  char scale_min[32] = "", scale_max[32] = "", texture_scale[32] = "";
  format_number(TEXTURE_SCALE_MIN, scale_min, sizeof scale_min);
  format_number(TEXTURE_SCALE_MAX, scale_max, sizeof scale_max);
  format_number(d.texture_scale, texture_scale, sizeof texture_scale);
  printf(
      "usage: breakables fracture [--mesh NAME|PATH] [--node NAME] [--scale S] [--units U]\n"
      "                           [--pieces N] [--seed S]\n"
      "                           [--texture-scale X] [--out FILE.mtree] [--export-obj FILE.obj] [--json]\n"
      "                           [--export-gltf FILE.glb|FILE.gltf] [--gltf-levels hierarchy|leaves|all]\n"
      "                           [--gltf-no-tree] [--gltf-meshopt]\n"
      "                           [--max-memory MIB] [--pattern NAME] [pattern options]\n"
      "                           [--threads N]\n"
      "\n"
      "Cuts a closed mesh into fragments (by default by random planes through the\n"
      "centroid of the largest piece, recursively, closing every cut with a\n"
      "triangulated cap; --pattern chooses another way) and keeps every\n"
      "intermediate piece in a mesh tree (root = source, leaves = fragments).\n"
      "\n"
      "options:\n"
      "  --mesh NAME|PATH      cube, torus, eggshell, bunny, wall, slab, pillar, tower,\n"
      "                        bridge, balcony, or a model file (default: bunny): .obj (with\n"
      "                        its .mtl) and .ply (read by Breakables itself), .gltf, .glb,\n"
      "                        .fbx, .dae, .stl, .3ds, .off, .3mf, .blend, .x, .ac, .ase\n"
      "                        (read by assimp). A scene's meshes are combined with their\n"
      "                        node transforms, each keeping its material. Shells sharing a\n"
      "                        vertex, an edge or a face are split apart and simple holes\n"
      "                        closed, with a warning; other open meshes are refused with the\n"
      "                        count and place of the open edges. Closed shells that overlap\n"
      "                        (nested or interpenetrating) or touch along a line or a face\n"
      "                        are fractured each on its own, with a warning naming them.\n"
      "  --node NAME           take only this node of the model's scene (and its "
      "children)\n" BK_MODEL_UNITS_USAGE
      "  --pieces N            number of fragments, 1..%u (default: %u). Exactly N\n"
      "                        unless no cut of a piece keeps it closed with its volume\n"
      "                        (fewer: a warning on stderr and in --json says why); a cut\n"
      "                        that would make more (a concave piece, separate shells)\n"
      "                        keeps the nearest of them together\n"
      "  --seed S              random seed, 0..%llu; the same seed gives the\n"
      "                        same tree (default: %llu)\n"
      "  --texture-scale X     world size of one interior texture tile on cut faces, in\n"
      "                        metres, %s..%s (default: %s)\n"
      "  --out FILE.mtree      save the mesh tree (with bonds and parameters) as a cache file\n"
      "  --export-obj FILE.obj write the fragments as OBJ, one 'o fragment_<i>' each, in the\n"
      "                        source mesh's frame (--pieces 1 exports the source itself)\n"
      "  --export-gltf FILE.glb|FILE.gltf\n"
      "                        write the mesh tree as glTF 2.0 (.glb binary, .gltf JSON with\n"
      "                        the buffer inside): node hierarchy, pivots at the centres of\n"
      "                        mass, two materials per source material (<name> and\n"
      "                        <name>_interior) with their textures inside the file,\n"
      "                        bonds and the tree in extras (docs/gltf.md); loads back exactly\n"
      "  --gltf-levels hierarchy|leaves|all\n"
      "                        hierarchy (default): every node of the tree, meshes on the\n"
      "                        fragments only, so engines draw the object once; leaves: the\n"
      "                        fragments only, flat; all: every node with its own mesh (each\n"
      "                        level draws the whole object: show one level at a time)\n"
      "  --gltf-no-tree        leave the exact mesh tree out of the glTF (most of its size): for\n"
      "                        a shipped game that reads the meshes and extras; it does not\n"
      "                        load back\n"
      "  --gltf-meshopt        compress the glTF's vertices (EXT_meshopt_compression, which\n"
      "                        three.js decodes with its MeshoptDecoder; Blender 3.4 cannot)\n"
      "  --json                print one JSON object instead of the summary: mesh, pieces,\n"
      "                        nodes, max_depth, ms, leaf_triangles, bonds, watertight,\n"
      "                        volume_rel_error, child_volume_rel_error, seed, texture_scale,\n"
      "                        source_triangles, source_materials, peak_rss_mb,\n"
      "                        pieces_requested (the seed points with --seeds, null for\n"
      "                        cutout), pieces_made, pattern and the parameters\n"
      "                        of that pattern (named as its options: clusters,\n"
      "                        cluster_border, impact, ...; seed_points and seeds for\n"
      "                        voronoi, cutout and its width and height for cutout),\n"
      "                        slivers, sliver_fraction, volume_ratio_p95_p5, min_aspect,\n"
      "                        median_aspect (fragment quality, see below),\n"
      "                        warnings (why fewer pieces were made than asked for,\n"
      "                        cells kept together where a cut face could not be made,\n"
      "                        which shells overlapped), export_gltf (the path written,\n"
      "                        or null) and tree_hash (XXH3 of the tree's .mtree bytes,\n"
      "                        16 hex digits: the same on every build)\n"
      "  --max-memory MIB      memory the fracture may use, 1..1073741824 MiB (default: the\n"
      "                        available memory); a request estimated to need more is refused\n"
      "  -h, --help            show this help\n",
      PIECES_MAX, d.pieces, (unsigned long long)UINT64_MAX, (unsigned long long)d.seed, scale_min, scale_max,
      texture_scale);
  pattern_options_help(stdout);
  printf("\n"
         "Fragment quality: a fragment's aspect is its thinnest extent over its longest,\n"
         "measured along its principal axes of inertia; a sliver has an aspect below %g.\n"
         "volume_ratio_p95_p5 is the 95th-percentile fragment volume over the 5th.\n"
         "\n"
         "A progress bar is drawn on stderr when it is a terminal.\n",
         BK_SLIVER_ASPECT);
}

typedef struct progress_state {
  double last_ms;
} progress_state;

static bool draw_progress(void* user, uint32_t leaves, uint32_t target) {
  progress_state* state = user;
  double now = app_now_ms();
  if (now - state->last_ms < 100.0 && leaves < target) return true;
  state->last_ms = now;
  int width = 40, filled = (int)((double)width * leaves / (target ? target : 1));
  if (filled > width) filled = width;
  fprintf(stderr, "\r[%.*s%*s] %u/%u", filled, "########################################", width - filled, "",
          leaves, target);
  fflush(stderr);
  return true;
}

static int fail(const char* message) {
  fprintf(stderr, "breakables fracture: %s\n", message);
  return 1;
}

static int usage_error(const char* option, const char* what) {
  fprintf(stderr, "breakables fracture: %s %s (see 'breakables fracture --help')\n", option, what);
  return 2;
}

// What the command line asked for.
typedef struct fracture_request {
  const char* mesh_spec;
  const char* node;
  const char* out_path;
  const char* obj_path;
  const char* gltf_path;
  bk_gltf_def gltf;
  bool json;
  bk_fracture_def desc;     ///< with --seeds and --cutout read into it (borrowed from patterns)
  pattern_options patterns; ///< owns what desc borrows
} fracture_request;

// What a fracture made, for the report.
typedef struct fracture_result {
  const bk_mesh_tree* tree;
  bk_mesh_tree_stats stats;
  bk_mesh_tree_quality quality;
  double ms, volume_error;
  uint32_t source_triangles, source_materials;
  const char* shortfall; ///< NULL when every piece was made
  const char* overlap;   ///< NULL when no shells overlapped
  const char* size;      ///< NULL when the model is 1 cm..100 m across
  bool written;          ///< every file asked for was written
} fracture_result;

// XXH3 of the tree's .mtree bytes (what --out writes): the same on every
// build and machine that builds the same tree, 0 for a tree that cannot be
// written.
static uint64_t tree_hash(const bk_mesh_tree* tree) {
  uint8_t* bytes = NULL;
  size_t size = 0;
  uint64_t hash = bk_mesh_tree_save_memory(tree, "tree", &bytes, &size, NULL) ? XXH3_64bits(bytes, size) : 0;
  bk_free(bytes);
  return hash;
}

static void print_json(const fracture_request* r, const fracture_result* f) {
  const bk_mesh_tree* tree = f->tree;
  const bk_mesh_tree_stats* st = &f->stats;
  fputs("{\"mesh\": ", stdout);
  app_json_string(stdout, r->mesh_spec);
  // What was asked for: with --seeds one piece per point (--pieces is then
  // ignored); with a fracture map nothing (its regions decide: null).
  char requested[16] = "null";
  if (r->desc.pattern != BK_PATTERN_CUTOUT)
    snprintf(requested, sizeof requested, "%u",
             r->desc.seed_points ? r->desc.seed_point_count : r->desc.pieces);
  printf(", \"pieces\": %u, \"pieces_requested\": %s, \"pieces_made\": %u, \"nodes\": %u, "
         "\"max_depth\": %u, \"ms\": %s, "
         "\"leaf_triangles\": %u, \"bonds\": %u, \"watertight\": %s, \"volume_rel_error\": %s, "
         "\"child_volume_rel_error\": %s, \"seed\": %llu, \"texture_scale\": %s, "
         "\"source_triangles\": %u, \"source_materials\": %u, \"peak_rss_mb\": %s",
         tree->leaf_count, requested, tree->leaf_count, tree->node_count, tree->max_depth,
         BK_APP_JSON_NUMBER("%.3f", f->ms), st->leaf_triangles, tree->bond_count,
         st->open_nodes == 0 ? "true" : "false", BK_APP_JSON_NUMBER("%.3e", f->volume_error),
         BK_APP_JSON_NUMBER("%.3e", st->max_child_rel_error), (unsigned long long)tree->desc.seed,
         BK_APP_JSON_NUMBER("%g", tree->desc.texture_scale), f->source_triangles, f->source_materials,
         BK_APP_JSON_NUMBER("%.1f", app_peak_rss_mb()));
  // The parameters are those the tree was built with: the request's def
  // (the tree's own copy no longer holds the borrowed seed points and map).
  pattern_options_json(stdout, &r->desc, &r->patterns);
  printf(", \"slivers\": %u, \"sliver_fraction\": ", f->quality.slivers);
  app_json_number(stdout, f->quality.sliver_fraction);
  fputs(", \"volume_ratio_p95_p5\": ", stdout);
  app_json_number(stdout, f->quality.volume_ratio_p95_p5);
  fputs(", \"min_aspect\": ", stdout);
  app_json_number(stdout, f->quality.min_aspect);
  fputs(", \"median_aspect\": ", stdout);
  app_json_number(stdout, f->quality.median_aspect);
  fputs(", \"warnings\": [", stdout);
  // What the source was repaired of comes first: the fragments are of the repaired source.
  char repaired[400] = "";
  const char* listed[5] = {NULL, r->patterns.cutout_warning[0] ? r->patterns.cutout_warning : NULL,
                           f->shortfall, f->overlap, f->size};
  if (app_repair_text(app_last_repair(), repaired, sizeof repaired)) listed[0] = repaired;
  for (int i = 0, written = 0; i < 5; ++i) {
    if (!listed[i]) continue;
    if (written++) fputs(", ", stdout);
    app_json_string(stdout, listed[i]);
  }
  fputs("], \"export_gltf\": ", stdout);
  if (r->gltf_path && f->written)
    app_json_string(stdout, r->gltf_path);
  else
    fputs("null", stdout);
  printf(", \"tree_hash\": \"%016llx\"}\n", (unsigned long long)tree_hash(tree));
}

static void print_summary(const fracture_request* r, const fracture_result* f) {
  const bk_mesh_tree* tree = f->tree;
  const bk_mesh_tree_stats* st = &f->stats;
  const bk_mesh_tree_quality* q = &f->quality;
  printf("%s: %u fragments (%u nodes, depth %u) in %.1f ms\n", r->mesh_spec, tree->leaf_count,
         tree->node_count, tree->max_depth, f->ms);
  printf("  leaf triangles %u, bonds %u, watertight %s, volume error %.2e (leaf volumes %.3g..%.3g)\n",
         st->leaf_triangles, tree->bond_count, st->open_nodes == 0 ? "yes" : "NO", f->volume_error,
         st->min_leaf_volume, st->max_leaf_volume);
  printf("  %s pattern: %u slivers (%.1f%%), leaf volume p95/p5 %.3g, aspect min %.3f median %.3f\n",
         bk_fracture_pattern_name(r->desc.pattern), q->slivers, 100.0 * q->sliver_fraction,
         q->volume_ratio_p95_p5, q->min_aspect, q->median_aspect);
  printf("  tree hash %016llx\n", (unsigned long long)tree_hash(tree));
  if (r->out_path && f->written) printf("  saved %s\n", r->out_path);
  if (r->obj_path && f->written) printf("  exported %s\n", r->obj_path);
  if (r->gltf_path && f->written) printf("  exported %s\n", r->gltf_path);
}

// Writes the files asked for; false (with a message printed) at the first that fails.
static bool write_files(const fracture_request* r, const bk_mesh_tree* tree, const bk_gltf_def* gltf) {
  bk_error err = {0};
  if (r->out_path && !bk_mesh_tree_save(tree, r->out_path, &err)) return fail(err.message), false;
  if (r->obj_path && !tree_export_obj(tree, r->obj_path, &err)) return fail(err.message), false;
  if (r->gltf_path && !bk_mesh_tree_save_gltf(tree, r->gltf_path, gltf, &err))
    return fail(err.message), false;
  return true;
}

// The fracture of a command line that parsed: load, build, check, write, report.
static int run_fracture(const fracture_request* r) {
  bk_error err = {0};
  bk_mesh source = {0};
  bk_import_info imported = {0};
  if (!app_load_model(r->mesh_spec, r->node, &source, &imported, &err)) return fail(err.message);
  // The model's own materials (names, colours, textures) become the
  // export's, two per source material; texture files go into the file.
  bk_gltf_def gltf = r->gltf;
  app_export_materials materials = {0};
  if (r->gltf_path) {
    app_export_materials_from_import(&imported, r->mesh_spec, &materials);
    gltf.materials = materials.list;
    gltf.material_count = materials.count;
  }
  fracture_result f = {0};
  char size_note[200];
  if (bk_model_import_supports(r->mesh_spec) && app_model_size_note(&source, size_note, sizeof size_note))
    f.size = size_note;
  f.source_materials = imported.materials ? imported.materials : 1;
  bk_import_info_free(&imported);
  bk_fracture_def desc = r->desc;
  if (!app_check_fracture_memory(r->mesh_spec, &source, &desc, r->out_path != NULL, &err)) {
    bk_mesh_free(&source);
    app_export_materials_free(&materials);
    return fail(err.message);
  }

  progress_state progress = {app_now_ms()};
  if (isatty(STDERR_FILENO)) {
    desc.progress = draw_progress;
    desc.progress_user = &progress;
  }
  bk_mesh_tree tree = {0};
  double start = app_now_ms();
  bool built = bk_mesh_tree_build(&source, &desc, &tree, &err);
  f.ms = app_now_ms() - start;
  if (desc.progress) fputs("\r\033[K", stderr);
  f.source_triangles = source.triangle_count;
  bk_mesh_free(&source);
  if (!built) {
    app_export_materials_free(&materials);
    char message[600];
    snprintf(message, sizeof message, "%s: %s", r->mesh_spec, err.message);
    return fail(message);
  }

  f.tree = &tree;
  f.stats = bk_mesh_tree_measure(&tree);
  f.volume_error = fabs(f.stats.leaf_volume_sum - f.stats.source_volume) / f.stats.source_volume;
  // The builder keeps only cuts whose pieces are closed; an open node here
  // would be a broken invariant, and a broken tree is never written.
  if (f.stats.open_nodes) {
    char message[160];
    snprintf(message, sizeof message, "%u of %u nodes came out open; nothing was written", f.stats.open_nodes,
             tree.node_count);
    bk_mesh_tree_free(&tree);
    app_export_materials_free(&materials);
    return fail(message);
  }
  f.quality = bk_mesh_tree_measure_quality(&tree);
  if (r->patterns.cutout_warning[0])
    fprintf(stderr, "breakables fracture: warning: %s\n", r->patterns.cutout_warning);
  char shortfall[400];
  if (bk_mesh_tree_shortfall_text(&tree, shortfall, sizeof shortfall)) {
    fprintf(stderr, "breakables fracture: warning: %s: %s\n", r->mesh_spec, shortfall);
    f.shortfall = shortfall;
  }
  char overlap[400];
  if (bk_mesh_tree_overlap_text(&tree, overlap, sizeof overlap)) {
    fprintf(stderr, "breakables fracture: warning: %s: %s\n", r->mesh_spec, overlap);
    f.overlap = overlap;
  }
  f.written = write_files(r, &tree, &gltf);
  app_export_materials_free(&materials);
  if (r->json)
    print_json(r, &f);
  else
    print_summary(r, &f);
  bk_mesh_tree_free(&tree);
  return f.written ? 0 : 1;
}

// The output files, checked before anything is read or built: a name the
// writer takes, a place to write it, and no file lost (an input or another output).
static bool check_files(const fracture_request* r) {
  bk_shape shape = BK_SHAPE_CUBE;
  char bunny[4096] = "";
  const char* mesh_path = r->mesh_spec;
  if (bk_shape_from_name(r->mesh_spec, &shape)) {
    mesh_path = NULL;
  } else if (strcmp(r->mesh_spec, "bunny") == 0) {
    snprintf(bunny, sizeof bunny, "%s/meshes/bunny.obj", app_asset_dir());
    mesh_path = bunny;
  }
  const app_file inputs[] = {
      {"--mesh", mesh_path, NULL, false},
      {"--seeds", r->patterns.seeds_path, NULL, false},
      {"--cutout", r->patterns.cutout_path, NULL, false},
  };
  const app_file outputs[] = {
      {"--out", r->out_path, ".mtree", false}, // sim, play and the editor know a tree by this ending
      {"--export-obj", r->obj_path, ".obj", true},
      {"--export-gltf", r->gltf_path, ".glb .gltf", true},
  };
  bk_error err = {0};
  if (app_check_files(inputs, 3, outputs, 3, &err)) return true;
  fail(err.message);
  return false;
}

int cmd_fracture(int argc, char** argv) {
  fracture_request r = {
      .mesh_spec = "bunny", .gltf = bk_default_gltf_def(), .desc = bk_default_fracture_def()};
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : NULL;
    bool takes_value = true;
    pattern_option_result pattern_arg = BK_PATTERN_OPTION_NOT_MINE;
    int units = parse_model_units_option("fracture", argc, argv, &i);
    if (units == 0) continue;
    if (units == 2) return 2;
    if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
      print_usage();
      return 0;
    } else if (strcmp(arg, "--json") == 0) {
      r.json = true;
      takes_value = false;
    } else if (!value && (strcmp(arg, "--mesh") == 0 || strcmp(arg, "--node") == 0 ||
                          strcmp(arg, "--pieces") == 0 || strcmp(arg, "--seed") == 0 ||
                          strcmp(arg, "--texture-scale") == 0 || strcmp(arg, "--out") == 0 ||
                          strcmp(arg, "--export-obj") == 0 || strcmp(arg, "--max-memory") == 0 ||
                          strcmp(arg, "--export-gltf") == 0 || strcmp(arg, "--gltf-levels") == 0)) {
      return usage_error(arg, "needs a value");
    } else if (strcmp(arg, "--mesh") == 0) {
      r.mesh_spec = value;
    } else if (strcmp(arg, "--node") == 0) {
      r.node = value;
    } else if (strcmp(arg, "--pieces") == 0) {
      uint64_t pieces = 0;
      if (!option_u64("fracture", arg, value, 1, PIECES_MAX, &pieces)) return 2;
      r.desc.pieces = (uint32_t)pieces;
    } else if (strcmp(arg, "--seed") == 0) {
      if (!option_u64("fracture", arg, value, 0, UINT64_MAX, &r.desc.seed)) return 2;
    } else if (strcmp(arg, "--texture-scale") == 0) {
      if (!option_double("fracture", arg, value, TEXTURE_SCALE_MIN, TEXTURE_SCALE_MAX, &r.desc.texture_scale))
        return 2;
    } else if (strcmp(arg, "--out") == 0) {
      r.out_path = value;
    } else if (strcmp(arg, "--export-obj") == 0) {
      r.obj_path = value;
    } else if (strcmp(arg, "--export-gltf") == 0) {
      r.gltf_path = value;
    } else if (strcmp(arg, "--gltf-meshopt") == 0) {
      r.gltf.meshopt_compression = true;
      takes_value = false;
    } else if (strcmp(arg, "--gltf-no-tree") == 0) {
      r.gltf.embed_tree = false;
      takes_value = false;
    } else if (strcmp(arg, "--gltf-levels") == 0) {
      if (strcmp(value, "hierarchy") == 0)
        r.gltf.levels = BK_GLTF_LEVELS_HIERARCHY;
      else if (strcmp(value, "all") == 0)
        r.gltf.levels = BK_GLTF_LEVELS_ALL;
      else if (strcmp(value, "leaves") == 0)
        r.gltf.levels = BK_GLTF_LEVELS_LEAVES;
      else
        return usage_error(arg, "must be 'hierarchy', 'leaves' or 'all'");
    } else if (strcmp(arg, "--max-memory") == 0) {
      if (!app_parse_max_memory("fracture", value)) return 2;
    } else if ((pattern_arg = app_pattern_option(arg, value, &r.desc, &r.patterns)) !=
               BK_PATTERN_OPTION_NOT_MINE) {
      if (pattern_arg == BK_PATTERN_OPTION_REFUSED) return 2;
    } else {
      fprintf(stderr, "breakables fracture: unknown option '%s' (see 'breakables fracture --help')\n", arg);
      return 2;
    }
    if (takes_value) ++i;
  }
  if (!check_files(&r)) return 1;
  // Reads --seeds and --cutout into r.desc, which borrows them from r.patterns.
  int status = pattern_options_finish(&r.patterns, &r.desc);
  if (status == 0) status = run_fracture(&r);
  pattern_options_free(&r.patterns);
  return status;
}
