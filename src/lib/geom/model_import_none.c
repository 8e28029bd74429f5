// The formats assimp reads, in a build without assimp (BK_NO_ASSIMP: the
// WebAssembly build, where OBJ and PLY come to this library's own readers and
// a page hands other models over as triangles): refused in one line, naming
// the file and what the build does read.
#include "bk_geom.h"
#include "model_import.h"

#ifdef BK_NO_ASSIMP
#include <string.h>

static bool refuse(const char* name, const char* ext, bk_mesh* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  return bk_error_set(err,
                      "%s: .%s models are read through assimp, which this build leaves out: use .obj or .ply",
                      name, ext);
}

bool bk_import_assimp_memory(const void* data, size_t size, const char* ext, const char* name,
                             const bk_import_def* def, bk_mesh* out, bk_import_info* info, bk_error* err) {
  (void)data, (void)size, (void)def, (void)info;
  return refuse(name, ext, out, err);
}

bool bk_import_assimp_file(const char* path, const char* ext, const bk_import_def* def, bk_mesh* out,
                           bk_import_info* info, bk_error* err) {
  (void)def, (void)info;
  return refuse(path, ext, out, err);
}
#else
// A translation unit may not be empty: the native build reads these formats in model_import_assimp.c.
typedef int bk_model_import_none_unused;
#endif
