// Fuzzes the glTF reader (bk_mesh_tree_load_gltf_memory): the GLB container,
// the JSON reader, the path from asset.extras.breakables.mtree to the buffer
// bytes (a GLB chunk or a base64 data URI) and the embedded .mtree loader.
// Each input is loaded as given and, when it starts with a GLB header, with
// the header's length rewritten to the input's size, so that mutations reach
// the chunks and the JSON behind that check.
//
// Asserted: a refusal has a one-line message naming the input and leaves the
// tree zeroed; an accepted tree is valid (it saves as .mtree again).
#include <stdlib.h>
#include <string.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_gltf";

enum { FUZZ_GLTF_MAX_BYTES = 1 << 20 };

static bool is_zeroed(const bk_mesh_tree* tree) {
  static const bk_mesh_tree zero = {0};
  return memcmp(tree, &zero, sizeof zero) == 0;
}

static void load_and_check(const uint8_t* data, size_t size, const char* what) {
  bk_mesh_tree tree;
  memset(&tree, 0xab, sizeof tree); // the loader must zero it
  bk_error err = {{0}};
  if (!bk_mesh_tree_load_gltf_memory(data, size, "input.glb", &tree, &err)) {
    if (!err.message[0]) bk_fuzz_fail("%s: refused without a message", what);
    if (strchr(err.message, '\n')) bk_fuzz_fail("%s: message is not one line: %s", what, err.message);
    if (strncmp(err.message, "input.glb: ", 11) != 0)
      bk_fuzz_fail("%s: message does not name the file: %s", what, err.message);
    if (!is_zeroed(&tree)) bk_fuzz_fail("%s: refused (%s) but left a tree behind", what, err.message);
    return;
  }
  uint8_t* saved = NULL;
  size_t saved_size = 0;
  if (!bk_mesh_tree_save_memory(&tree, "saved.mtree", &saved, &saved_size, &err))
    bk_fuzz_fail("%s: loaded a tree that cannot be saved: %s", what, err.message);
  free(saved);
  bk_mesh_tree_free(&tree);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > FUZZ_GLTF_MAX_BYTES) return 0;
  load_and_check(data, size, "as given");
  if (size >= 12 && memcmp(data, "glTF", 4) == 0) {
    uint8_t* fixed = bk_alloc(size);
    memcpy(fixed, data, size);
    for (int i = 0; i < 4; ++i)
      fixed[8 + i] = (uint8_t)((uint64_t)size >> (8 * i));
    if (memcmp(fixed, data, size) != 0) load_and_check(fixed, size, "with its GLB length fixed");
    free(fixed);
  }
  return 0;
}
