// Where fracture input comes from: built-in shapes, the bundled bunny, or an
// OBJ file given by path.
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
  bk_shape shape = BK_SHAPE_CUBE;
  if (bk_shape_from_name(spec, &shape)) {
    bk_shape_build(shape, out);
    return true;
  }
  bool bunny = strcmp(spec, "bunny") == 0;
  char path[4096];
  if (bunny) {
    snprintf(path, sizeof path, "%s/meshes/bunny.obj", bk_app_asset_dir());
  } else {
    size_t len = strlen(spec);
    if (len < 4 || strcmp(spec + len - 4, ".obj") != 0)
      return bk_error_set(
          err, "unknown mesh '%s': use cube, torus, eggshell, bunny, wall, slab, pillar or a .obj path",
          spec);
    snprintf(path, sizeof path, "%s", spec);
  }
  if (!bk_obj_load(path, out, err)) return false;
  if (bunny) normalize_to_unit_height(out);
  bk_closure closure = bk_mesh_check_closure(out);
  if (closure.open_edges && !closure.overused_edges) {
    bk_error fill_err = {0};
    int filled = bk_mesh_fill_holes(out, &fill_err);
    if (filled < 0) {
      bk_mesh_free(out);
      return bk_error_set(err, "%s: mesh is not watertight (%u open edges) and cannot be repaired: %s", path,
                          closure.open_edges, fill_err.message);
    }
    fprintf(stderr, "breakables: warning: %s: mesh was not watertight; closed %d hole%s (%u open edges)\n",
            path, filled, filled == 1 ? "" : "s", closure.open_edges);
  }
  return true;
}
