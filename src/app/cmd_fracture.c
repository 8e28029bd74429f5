// breakables fracture: build a mesh tree from a mesh and report on it.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app.h"

static const char* const fracture_usage =
    "usage: breakables fracture [--mesh NAME|PATH] [--node NAME] [--pieces N] [--seed S]\n"
    "                           [--texture-scale X] [--out FILE.mtree] [--export-obj FILE.obj] [--json]\n"
    "                           [--export-gltf FILE.glb|FILE.gltf] [--gltf-levels all|leaves]\n"
    "                           [--max-memory MIB]\n"
    "\n"
    "Cuts a closed mesh by random planes through the centroid of the largest\n"
    "piece, recursively, closing every cut with a triangulated cap, and keeps\n"
    "every intermediate piece in a mesh tree (root = source, leaves = fragments).\n"
    "\n"
    "options:\n"
    "  --mesh NAME|PATH      cube, torus, eggshell, bunny, wall, slab, pillar, or a model\n"
    "                        file (default: bunny): .obj (with its .mtl) and .ply (read\n"
    "                        by Breakables itself), .gltf, .glb, .fbx, .dae, .stl, .3ds,\n"
    "                        .off, .3mf, .blend, .x, .ac, .ase (read by assimp). A scene's\n"
    "                        meshes are combined with their node transforms, each\n"
    "                        keeping its material. Shells sharing a vertex, an edge\n"
    "                        or a face are split apart and simple holes closed, with a\n"
    "                        warning; other open meshes are refused with the count and\n"
    "                        place of the open edges. Closed shells that overlap\n"
    "                        (nested or interpenetrating) or touch along a line or a\n"
    "                        face are fractured each on its own, with a warning naming\n"
    "                        them.\n"
    "  --node NAME           take only this node of the model's scene (and its children)\n"
    "  --pieces N            number of fragments, 1..1048576 (default: 256). Exactly N\n"
    "                        unless no cut of a piece keeps it closed with its volume\n"
    "                        (fewer: a warning on stderr and in --json says why); a cut\n"
    "                        that would make more (a concave piece, separate shells)\n"
    "                        keeps the nearest of them together\n"
    "  --seed S              random seed, 0..18446744073709551615; the same seed gives the\n"
    "                        same tree (default: 3000)\n"
    "  --texture-scale X     world size of one interior texture tile on cut faces, in\n"
    "                        metres, 1e-6..1e6 (default: 0.1)\n"
    "  --out FILE.mtree      save the mesh tree (with bonds and parameters) as a cache file\n"
    "  --export-obj FILE.obj write the fragments as OBJ, one 'o fragment_<i>' each, in the\n"
    "                        source mesh's frame (--pieces 1 exports the source itself)\n"
    "  --export-gltf FILE.glb|FILE.gltf\n"
    "                        write the mesh tree as glTF 2.0 (.glb binary, .gltf JSON with\n"
    "                        the buffer inside): node hierarchy, pivots at the centres of\n"
    "                        mass, two materials per source material (<name> and\n"
    "                        <name>_interior) with their textures inside the file,\n"
    "                        bonds and the tree in extras (docs/gltf.md); loads back exactly\n"
    "  --gltf-levels all|leaves\n"
    "                        export every node of the tree (default) or the fragments only\n"
    "  --json                print one JSON object instead of the summary: mesh, pieces,\n"
    "                        nodes, max_depth, ms, leaf_triangles, bonds, watertight,\n"
    "                        volume_rel_error, child_volume_rel_error, seed, texture_scale,\n"
    "                        source_triangles, source_materials, peak_rss_mb,\n"
    "                        pieces_requested, pieces_made,\n"
    "                        warnings (why fewer pieces were made than asked for,\n"
    "                        which shells overlapped) and\n"
    "                        export_gltf (the path written, or null)\n"
    "  --max-memory MIB      memory the fracture may use, 1..1073741824 MiB (default: the\n"
    "                        available memory); a request estimated to need more is refused\n"
    "  -h, --help            show this help\n"
    "\n"
    "A progress bar is drawn on stderr when it is a terminal.\n";

typedef struct progress_state {
  double last_ms;
} progress_state;

static bool draw_progress(void* user, uint32_t leaves, uint32_t target) {
  progress_state* state = user;
  double now = bk_now_ms();
  if (now - state->last_ms < 100.0 && leaves < target) return true;
  state->last_ms = now;
  int width = 40, filled = (int)((double)width * leaves / (target ? target : 1));
  if (filled > width) filled = width;
  fprintf(stderr, "\r[%.*s%*s] %u/%u", filled, "########################################", width - filled, "",
          leaves, target);
  fflush(stderr);
  return true;
}

// A JSON string literal: quotes, backslashes and control characters escaped.
static void print_json_string(const char* text) {
  putchar('"');
  for (const unsigned char* c = (const unsigned char*)text; *c; ++c) {
    if (*c == '"' || *c == '\\')
      printf("\\%c", *c);
    else if (*c < 0x20)
      printf("\\u%04x", *c);
    else
      putchar(*c);
  }
  putchar('"');
}

static int fail(const char* message) {
  fprintf(stderr, "breakables fracture: %s\n", message);
  return 1;
}

static int usage_error(const char* option, const char* what) {
  fprintf(stderr, "breakables fracture: %s %s (see 'breakables fracture --help')\n", option, what);
  return 2;
}

int bk_cmd_fracture(int argc, char** argv) {
  const char* mesh_spec = "bunny";
  const char* node = NULL;
  const char* out_path = NULL;
  const char* obj_path = NULL;
  const char* gltf_path = NULL;
  bk_gltf_def gltf = bk_default_gltf_def();
  bool json = false;
  bk_fracture_def desc = bk_default_fracture_def();
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    const char* value = i + 1 < argc ? argv[i + 1] : NULL;
    bool takes_value = true;
    if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
      fputs(fracture_usage, stdout);
      return 0;
    } else if (strcmp(arg, "--json") == 0) {
      json = true;
      takes_value = false;
    } else if (!value && (strcmp(arg, "--mesh") == 0 || strcmp(arg, "--node") == 0 ||
                          strcmp(arg, "--pieces") == 0 || strcmp(arg, "--seed") == 0 ||
                          strcmp(arg, "--texture-scale") == 0 || strcmp(arg, "--out") == 0 ||
                          strcmp(arg, "--export-obj") == 0 || strcmp(arg, "--max-memory") == 0 ||
                          strcmp(arg, "--export-gltf") == 0 || strcmp(arg, "--gltf-levels") == 0)) {
      return usage_error(arg, "needs a value");
    } else if (strcmp(arg, "--mesh") == 0) {
      mesh_spec = value;
    } else if (strcmp(arg, "--node") == 0) {
      node = value;
    } else if (strcmp(arg, "--pieces") == 0) {
      uint64_t pieces = 0;
      if (!bk_option_u64("fracture", arg, value, 1, 1u << 20, &pieces)) return 2;
      desc.pieces = (uint32_t)pieces;
    } else if (strcmp(arg, "--seed") == 0) {
      if (!bk_option_u64("fracture", arg, value, 0, UINT64_MAX, &desc.seed)) return 2;
    } else if (strcmp(arg, "--texture-scale") == 0) {
      // Cut-face UVs are floats equal to coordinate / texture_scale: a micrometre
      // to a thousand kilometres covers any real tile and keeps them finite for
      // coordinates under 1e32 (the fracture checks the scale against the mesh).
      if (!bk_option_double("fracture", arg, value, 1e-6, 1e6, &desc.texture_scale)) return 2;
    } else if (strcmp(arg, "--out") == 0) {
      out_path = value;
    } else if (strcmp(arg, "--export-obj") == 0) {
      obj_path = value;
    } else if (strcmp(arg, "--export-gltf") == 0) {
      gltf_path = value;
    } else if (strcmp(arg, "--gltf-levels") == 0) {
      if (strcmp(value, "all") == 0)
        gltf.levels = BK_GLTF_LEVELS_ALL;
      else if (strcmp(value, "leaves") == 0)
        gltf.levels = BK_GLTF_LEVELS_LEAVES;
      else
        return usage_error(arg, "must be 'all' or 'leaves'");
    } else if (strcmp(arg, "--max-memory") == 0) {
      if (!bk_app_parse_max_memory("fracture", value)) return 2;
    } else {
      fprintf(stderr, "breakables fracture: unknown option '%s' (see 'breakables fracture --help')\n", arg);
      return 2;
    }
    if (takes_value) ++i;
  }

  bk_error err = {0};
  bk_mesh source = {0};
  bk_import_info imported = {0};
  if (!bk_app_load_model(mesh_spec, node, &source, &imported, &err)) return fail(err.message);
  // The model's own materials (names, colours, textures) become the
  // export's, two per source material; texture files go into the file.
  bk_app_export_materials materials = {0};
  if (gltf_path) {
    bk_app_export_materials_from_import(&imported, mesh_spec, &materials);
    gltf.materials = materials.list;
    gltf.material_count = materials.count;
  }
  uint32_t source_materials = imported.materials ? imported.materials : 1;
  bk_import_info_free(&imported);
  if (!bk_app_check_fracture_memory(mesh_spec, &source, &desc, out_path != NULL, &err)) {
    bk_mesh_free(&source);
    bk_app_export_materials_free(&materials);
    return fail(err.message);
  }

  progress_state progress = {bk_now_ms()};
  if (isatty(STDERR_FILENO)) {
    desc.progress = draw_progress;
    desc.progress_user = &progress;
  }
  bk_mesh_tree tree = {0};
  double start = bk_now_ms();
  bool built = bk_mesh_tree_build(&source, &desc, &tree, &err);
  double ms = bk_now_ms() - start;
  if (desc.progress) fputs("\r\033[K", stderr);
  uint32_t source_triangles = source.triangle_count;
  bk_mesh_free(&source);
  if (!built) {
    bk_app_export_materials_free(&materials);
    char message[600];
    snprintf(message, sizeof message, "%s: %s", mesh_spec, err.message);
    return fail(message);
  }

  bk_mesh_tree_stats st = bk_mesh_tree_measure(&tree);
  double volume_error = fabs(st.leaf_volume_sum - st.source_volume) / st.source_volume;
  int status = 0;
  // The builder keeps only cuts whose pieces are closed; an open node here
  // would be a broken invariant, and a broken tree is never written.
  if (st.open_nodes) {
    char message[160];
    snprintf(message, sizeof message, "%u of %u nodes came out open; nothing was written", st.open_nodes,
             tree.node_count);
    bk_mesh_tree_free(&tree);
    bk_app_export_materials_free(&materials);
    return fail(message);
  }
  char shortfall[400];
  bool short_of_pieces = bk_mesh_tree_shortfall_text(&tree, shortfall, sizeof shortfall);
  if (short_of_pieces) fprintf(stderr, "breakables fracture: warning: %s: %s\n", mesh_spec, shortfall);
  char overlap[400];
  bool overlapped = bk_mesh_tree_overlap_text(&tree, overlap, sizeof overlap);
  if (overlapped) fprintf(stderr, "breakables fracture: warning: %s: %s\n", mesh_spec, overlap);
  if (out_path && !bk_mesh_tree_save(&tree, out_path, &err)) status = fail(err.message);
  if (status == 0 && obj_path) {
    bk_mesh* leaves = bk_alloc(sizeof(bk_mesh) * tree.leaf_count);
    for (uint32_t i = 0; i < tree.leaf_count; ++i)
      leaves[i] = bk_mesh_tree_leaf(&tree, i)->mesh;
    if (!bk_obj_save(obj_path, leaves, tree.leaf_count, &err)) status = fail(err.message);
    free(leaves);
  }
  if (status == 0 && gltf_path && !bk_mesh_tree_save_gltf(&tree, gltf_path, &gltf, &err))
    status = fail(err.message);
  bk_app_export_materials_free(&materials);

  if (json) {
    fputs("{\"mesh\": ", stdout);
    print_json_string(mesh_spec);
    printf(", \"pieces\": %u, \"pieces_requested\": %u, \"pieces_made\": %u, \"nodes\": %u, "
           "\"max_depth\": %u, \"ms\": %.3f, "
           "\"leaf_triangles\": %u, \"bonds\": %u, \"watertight\": %s, \"volume_rel_error\": %.3e, "
           "\"child_volume_rel_error\": %.3e, \"seed\": %llu, \"texture_scale\": %g, "
           "\"source_triangles\": %u, \"source_materials\": %u, \"peak_rss_mb\": %.1f, \"warnings\": [",
           tree.leaf_count, desc.pieces, tree.leaf_count, tree.node_count, tree.max_depth, ms,
           st.leaf_triangles, tree.bond_count, st.open_nodes == 0 ? "true" : "false", volume_error,
           st.max_child_rel_error, (unsigned long long)tree.desc.seed, tree.desc.texture_scale,
           source_triangles, source_materials, bk_peak_rss_mb());
    if (short_of_pieces) print_json_string(shortfall);
    if (overlapped) {
      if (short_of_pieces) fputs(", ", stdout);
      print_json_string(overlap);
    }
    fputs("], \"export_gltf\": ", stdout);
    if (gltf_path && status == 0)
      print_json_string(gltf_path);
    else
      fputs("null", stdout);
    fputs("}\n", stdout);
  } else {
    printf("%s: %u fragments (%u nodes, depth %u) in %.1f ms\n", mesh_spec, tree.leaf_count, tree.node_count,
           tree.max_depth, ms);
    printf("  leaf triangles %u, bonds %u, watertight %s, volume error %.2e (leaf volumes %.3g..%.3g)\n",
           st.leaf_triangles, tree.bond_count, st.open_nodes == 0 ? "yes" : "NO", volume_error,
           st.min_leaf_volume, st.max_leaf_volume);
    if (out_path && status == 0) printf("  saved %s\n", out_path);
    if (obj_path && status == 0) printf("  exported %s\n", obj_path);
    if (gltf_path && status == 0) printf("  exported %s\n", gltf_path);
  }
  bk_mesh_tree_free(&tree);
  return status;
}
