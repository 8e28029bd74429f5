// meshoptimizer's vertex codec for the glTF export's attribute views (the
// EXT_meshopt_compression extension, "ATTRIBUTES" mode, no filter: the
// decoded bytes are the floats written, bit for bit).
#include <meshoptimizer.h>

#include "bk_fracture.h"
#include "gltf_internal.h"

size_t bk_gltf_meshopt_bound(size_t count, size_t stride) {
  return meshopt_encodeVertexBufferBound(count, stride);
}

size_t bk_gltf_meshopt_encode(const uint8_t* vertices, size_t count, size_t stride, uint8_t* out,
                              size_t capacity) {
  return meshopt_encodeVertexBuffer(out, capacity, vertices, count, stride);
}
