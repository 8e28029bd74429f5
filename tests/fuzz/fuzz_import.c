// Fuzzes model import (bk_model_import_memory: assimp's readers behind our
// checks, our OBJ, PLY and MTL readers) and the repair the CLI runs after it
// (bk_mesh_repair). The first
// byte picks the format (index into `formats`, modulo its length), the rest
// is the file. An accepted model must be a valid mesh with finite volume and
// area; a repair that succeeds must leave it closed; a refusal must get a
// one-line message naming the input. Crashes, undefined behaviour and leaks
// in our code are findings too (assimp itself is not instrumented).
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bk_geom.h"
#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_import";

enum { FUZZ_IMPORT_MAX_BYTES = 1 << 16 };

static const char* const formats[] = {"glb", "gltf", "ply", "stl", "fbx", "off", "dae", "3ds", "obj", "mtl"};

// An MTL file (an OBJ's materials, read by our own reader) for materials
// named "a", "b c" and "": colours stay finite in [0, 1], names NUL-terminated.
static int fuzz_mtl(const uint8_t* data, size_t size) {
  static bk_obj_materials names;
  names.count = 3;
  snprintf(names.names[0], sizeof names.names[0], "a");
  snprintf(names.names[1], sizeof names.names[1], "b c");
  names.names[2][0] = '\0';
  bk_import_material list[3];
  memset(list, 0, sizeof list);
  bk_mtl_parse((const char*)data, size, &names, list);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 4; ++k)
      if (!(list[i].base_color[k] >= 0.0f && list[i].base_color[k] <= 1.0f))
        bk_fuzz_fail("material %d colour %d is %g", i, k, (double)list[i].base_color[k]);
    if (!memchr(list[i].texture, '\0', sizeof list[i].texture)) bk_fuzz_fail("texture name not terminated");
  }
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > FUZZ_IMPORT_MAX_BYTES) return 0;
  const char* format = formats[data[0] % (sizeof formats / sizeof formats[0])];
  if (strcmp(format, "mtl") == 0) return fuzz_mtl(data + 1, size - 1);
  bk_mesh mesh = {0};
  bk_error err = {{0}};
  bk_import_info info;
  if (!bk_model_import_memory(data + 1, size - 1, format, "input", NULL, &mesh, &info, &err)) {
    if (strncmp(err.message, "input", 5) != 0)
      bk_fuzz_fail("refusal does not name the input: %s", err.message);
    if (strchr(err.message, '\n')) bk_fuzz_fail("message is not one line: %s", err.message);
    if (mesh.triangle_count || mesh.positions || mesh.corners)
      bk_fuzz_fail("refused but left a mesh behind (%u triangles)", mesh.triangle_count);
    return 0;
  }
  if (!bk_mesh_validate(&mesh, &err)) bk_fuzz_fail("accepted an invalid %s mesh: %s", format, err.message);
  // Every triangle's source material is one the info lists.
  if (info.materials < 1 || !info.material_list)
    bk_fuzz_fail("accepted a %s mesh with no material list", format);
  for (uint32_t t = 0; t < mesh.triangle_count; ++t)
    if (bk_material_source(mesh.materials[t]) >= info.materials || bk_material_is_interior(mesh.materials[t]))
      bk_fuzz_fail("triangle %u has material id %u, the info lists %u materials", t, mesh.materials[t],
                   info.materials);
  for (uint32_t i = 0; i < info.materials; ++i) {
    const bk_import_material* mat = &info.material_list[i];
    if (mat->image && mat->image_size < 8)
      bk_fuzz_fail("material %u keeps a %zu-byte image", i, mat->image_size);
  }
  bk_import_info_free(&info);
  double volume = bk_mesh_volume(&mesh), area = bk_mesh_area(&mesh);
  if (!isfinite(volume) || !isfinite(area))
    bk_fuzz_fail("accepted a %s mesh with volume %g and area %g", format, volume, area);
  bk_repair_info repair;
  if (bk_mesh_repair(&mesh, &repair, &err)) {
    if (!bk_mesh_is_closed(&mesh)) bk_fuzz_fail("repair succeeded but the %s mesh is open", format);
    if (!bk_mesh_validate(&mesh, &err)) bk_fuzz_fail("repair left an invalid mesh: %s", err.message);
  } else if (strchr(err.message, '\n')) {
    bk_fuzz_fail("repair message is not one line: %s", err.message);
  }
  bk_mesh_free(&mesh);
  return 0;
}
