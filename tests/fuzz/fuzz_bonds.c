// Fuzzes bond recomputation (bk_mesh_tree_compute_bonds) on whatever tree the
// .mtree loader accepts. The input's size and checksum fields are rewritten
// to match its payload first, so every mutation that keeps the structure
// valid reaches the bond code with arbitrary geometry, tags and planes.
//
// Asserted: every recomputed bond joins leaves leaf_a < leaf_b < leaf_count,
// has finite area > 0, a finite centroid and a unit normal, and no pair of
// leaves has two bonds.
#include <stdlib.h>
#include <string.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_bonds";

enum { FUZZ_BONDS_MAX_BYTES = 1 << 20 };

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > FUZZ_BONDS_MAX_BYTES) return 0;
  uint8_t* fixed = bk_alloc(size ? size : 1);
  if (size) memcpy(fixed, data, size);
  bk_fuzz_fix_mtree_header(fixed, size);
  const char* path = bk_fuzz_write_scratch("input.mtree", fixed, size);
  free(fixed);
  bk_mesh_tree tree = {0};
  bk_error err = {{0}};
  if (!bk_mesh_tree_load(path, &tree, &err)) return 0; // the loader's own harness checks refusals
  bk_mesh_tree_compute_bonds(&tree);
  bk_fuzz_check_bonds(&tree, "recomputed bonds");
  // Measuring walks every node's closure and volumes: it must cope with any tree the loader accepts.
  (void)bk_mesh_tree_measure(&tree);
  bk_mesh_tree_free(&tree);
  return 0;
}
