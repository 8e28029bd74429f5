// Fuzzes model import (bk_model_import_memory: assimp's readers behind our
// checks) and the repair the CLI runs after it (bk_mesh_repair). The first
// byte picks the format (index into `formats`, modulo its length), the rest
// is the file. An accepted model must be a valid mesh with finite volume and
// area; a repair that succeeds must leave it closed; a refusal must get a
// one-line message naming the input. Crashes, undefined behaviour and leaks
// in our code are findings too (assimp itself is not instrumented).
#include <math.h>
#include <string.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_import";

enum { FUZZ_IMPORT_MAX_BYTES = 1 << 16 };

static const char* const formats[] = {"glb", "gltf", "ply", "stl", "fbx", "off", "dae", "3ds", "obj"};

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > FUZZ_IMPORT_MAX_BYTES) return 0;
  const char* format = formats[data[0] % (sizeof formats / sizeof formats[0])];
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
