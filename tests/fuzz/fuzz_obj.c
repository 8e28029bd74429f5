// Fuzzes the OBJ reader (bk_obj_parse) straight from memory. A file the reader
// accepts must be a valid mesh whose derived quantities stay finite (the
// reader bounds coordinates for that); a file it refuses must get a one-line
// message. Crashes, undefined behaviour and leaks are findings too.
#include <math.h>
#include <string.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_obj";

// Larger inputs only slow the search down: every OBJ feature fits in far less.
enum { FUZZ_OBJ_MAX_BYTES = 1 << 16 };

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > FUZZ_OBJ_MAX_BYTES) return 0;
  bk_mesh mesh = {0};
  bk_error err = {{0}};
  if (!bk_obj_parse((const char*)data, size, "input.obj", &mesh, &err)) {
    if (!err.message[0]) bk_fuzz_fail("refused without a message");
    if (strchr(err.message, '\n')) bk_fuzz_fail("message is not one line: %s", err.message);
    if (mesh.triangle_count || mesh.positions || mesh.corners)
      bk_fuzz_fail("refused but left a mesh behind (%u triangles)", mesh.triangle_count);
    return 0;
  }
  if (!bk_mesh_validate(&mesh, &err)) bk_fuzz_fail("accepted an invalid mesh: %s", err.message);
  double volume = bk_mesh_volume(&mesh), area = bk_mesh_area(&mesh);
  if (!isfinite(volume) || !isfinite(area))
    bk_fuzz_fail("accepted a mesh with volume %g and area %g", volume, area);
  bk_mesh_free(&mesh);
  return 0;
}
