// The glTF export's vertex compression in a build without meshoptimizer
// (BK_NO_MESHOPT: the WebAssembly build): a bound of 0 tells the export to
// refuse meshopt_compression in one line; uncompressed exports are the same.
#include "bk_fracture.h"
#include "gltf_internal.h"

#ifdef BK_NO_MESHOPT
size_t bk_gltf_meshopt_bound(size_t count, size_t stride) {
  (void)count, (void)stride;
  return 0;
}

size_t bk_gltf_meshopt_encode(const uint8_t* vertices, size_t count, size_t stride, uint8_t* out,
                              size_t capacity) {
  (void)vertices, (void)count, (void)stride, (void)out, (void)capacity;
  return 0;
}
#else
// A translation unit may not be empty: the native build compresses in gltf_meshopt.c.
typedef int bk_gltf_meshopt_none_unused;
#endif
