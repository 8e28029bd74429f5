// Mesh trees compared as their .mtree bytes: the same bytes, the same tree.
#pragma once

#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"

/// True when both trees save to identical .mtree bytes.
static inline bool trees_same_bytes(const bk_mesh_tree* a, const bk_mesh_tree* b) {
  uint8_t *bytes_a = NULL, *bytes_b = NULL;
  size_t size_a = 0, size_b = 0;
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_save_memory(a, "a", &bytes_a, &size_a, &err), "%s", err.message);
  ENSURE_MSG(bk_mesh_tree_save_memory(b, "b", &bytes_b, &size_b, &err), "%s", err.message);
  bool same = size_a == size_b && memcmp(bytes_a, bytes_b, size_a) == 0;
  free(bytes_a);
  free(bytes_b);
  return same;
}
