// A test mesh by name: a built-in shape (cube, torus, eggshell, wall, ...)
// or an .obj under the assets' meshes (bunny).
#pragma once

#include <stdio.h>

#include "bk_fracture.h"
#include "ensure.h"

static inline bk_mesh load_shape(const char* name) {
  bk_mesh m = {0};
  bk_shape shape = BK_SHAPE_CUBE;
  if (bk_shape_from_name(name, &shape)) {
    bk_shape_build(shape, &m);
  } else {
    char path[512];
    snprintf(path, sizeof path, "%s/meshes/%s.obj", BK_ASSET_DIR, name);
    bk_error err = {0};
    ENSURE_MSG(bk_obj_load(path, &m, &err), "%s", err.message);
  }
  return m;
}
