// Where fracture input comes from: built-in shapes, the bundled bunny, or a
// model file given by path (OBJ by our reader, glTF, FBX, PLY, STL... by assimp).
#include <stdio.h>
#include <string.h>

#include "app.h"

static void normalize_to_unit_height(bk_mesh* m) {
  bk_aabb box = bk_mesh_bounds(m);
  double height = box.max.y - box.min.y;
  if (!(height > 0.0)) return;
  double s = 1.0 / height;
  bk_vec3 centre = bk_v3(0.5 * (box.min.x + box.max.x), box.min.y, 0.5 * (box.min.z + box.max.z));
  for (uint32_t i = 0; i < m->position_count; ++i)
    m->positions[i] = bk_v3_scale(bk_v3_sub(m->positions[i], centre), s);
}

bool bk_app_load_mesh(const char* spec, bk_mesh* out, bk_error* err) {
  return bk_app_load_model(spec, NULL, out, NULL, err);
}

bool bk_app_load_model(const char* spec, const char* node, bk_mesh* out, bk_import_info* info_out,
                       bk_error* err) {
  bk_shape shape = BK_SHAPE_CUBE;
  if (bk_shape_from_name(spec, &shape)) {
    if (node) return bk_error_set(err, "--node needs a model file, not the built-in '%s'", spec);
    bk_shape_build(shape, out);
    return true;
  }
  bool bunny = strcmp(spec, "bunny") == 0;
  char path[4096];
  if (bunny) {
    snprintf(path, sizeof path, "%s/meshes/bunny.obj", bk_app_asset_dir());
  } else {
    if (!bk_model_import_supports(spec))
      return bk_error_set(
          err,
          "unknown mesh '%s': use cube, torus, eggshell, bunny, wall, slab, pillar, tower, bridge, "
          "balcony or a model file (%s)",
          spec, BK_IMPORT_EXTENSIONS);
    snprintf(path, sizeof path, "%s", spec);
  }
  // .obj goes to our own reader, every other format to assimp (bk_model_import).
  bk_import_def def = bk_default_import_def();
  def.node = node;
  bk_import_info info = {0};
  if (!bk_model_import(path, &def, out, &info, err)) return false;
  if (bunny) normalize_to_unit_height(out);
  if (info.flipped)
    fprintf(stderr, "breakables: warning: %s: mesh was inside out; its winding was reversed\n", path);
  bk_repair_info repair = {0};
  bk_error repair_err = {0};
  if (!bk_mesh_repair(out, &repair, &repair_err)) {
    bk_mesh_free(out);
    bk_import_info_free(&info);
    return bk_error_set(err, "%s: %s", path, repair_err.message);
  }
  if (repair.positions_split)
    fprintf(stderr,
            "breakables: warning: %s: shells touched at a vertex, an edge or a face; split %u position%s (%u "
            "shell%s)\n",
            path, repair.positions_split, repair.positions_split == 1 ? "" : "s", repair.shells,
            repair.shells == 1 ? "" : "s");
  if (repair.holes_closed)
    fprintf(stderr, "breakables: warning: %s: mesh was not watertight; closed %u hole%s (%u open edges)\n",
            path, repair.holes_closed, repair.holes_closed == 1 ? "" : "s", repair.open_edges);
  if (info_out)
    *info_out = info; // the caller releases it (bk_import_info_free)
  else
    bk_import_info_free(&info);
  return true;
}
