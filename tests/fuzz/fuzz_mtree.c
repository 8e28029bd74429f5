// Fuzzes the .mtree loader (bk_mesh_tree_load). Each input is loaded twice:
// as given, which exercises the header checks (magic, version, byte order,
// size, checksum), and with its size and checksum fields rewritten to match
// its payload, so that mutations reach the parser behind the checksum.
//
// Asserted: a refused file gets a one-line message and leaves the tree zeroed;
// an accepted file saves back to exactly the same bytes (the format has one
// encoding per tree, so anything else means the loader dropped or changed data).
#include <stdlib.h>
#include <string.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_mtree";

// Small trees already cover every record type; bigger inputs only slow the search.
enum { FUZZ_MTREE_MAX_BYTES = 1 << 20 };

static bool is_zeroed(const bk_mesh_tree* tree) {
  static const bk_mesh_tree zero = {0};
  return memcmp(tree, &zero, sizeof zero) == 0;
}

static void load_and_check(const uint8_t* data, size_t size, const char* what) {
  const char* path = bk_fuzz_write_scratch("input.mtree", data, size);
  bk_mesh_tree tree = {0};
  bk_error err = {{0}};
  if (!bk_mesh_tree_load(path, &tree, &err)) {
    if (!err.message[0]) bk_fuzz_fail("%s: refused without a message", what);
    if (strchr(err.message, '\n')) bk_fuzz_fail("%s: message is not one line: %s", what, err.message);
    if (!is_zeroed(&tree)) bk_fuzz_fail("%s: refused (%s) but left a tree behind", what, err.message);
    return;
  }
  const char* saved_path = bk_fuzz_scratch_path("saved.mtree");
  if (!bk_mesh_tree_save(&tree, saved_path, &err))
    bk_fuzz_fail("%s: loaded a tree that cannot be saved: %s", what, err.message);
  size_t saved_size = 0;
  uint8_t* saved = bk_fuzz_read_file(saved_path, &saved_size);
  if (!saved) bk_fuzz_fail("%s: cannot read back %s", what, saved_path);
  if (saved_size != size || memcmp(saved, data, size) != 0) {
    size_t at = 0;
    while (at < size && at < saved_size && saved[at] == data[at])
      at++;
    bk_fuzz_fail("%s: saving the loaded tree gives other bytes (%zu vs %zu bytes, first difference at %zu)",
                 what, saved_size, size, at);
  }
  free(saved);
  bk_mesh_tree_free(&tree);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > FUZZ_MTREE_MAX_BYTES) return 0;
  load_and_check(data, size, "as given");
  uint8_t* fixed = bk_alloc(size ? size : 1);
  if (size) memcpy(fixed, data, size);
  if (bk_fuzz_fix_mtree_header(fixed, size) && memcmp(fixed, data, size) != 0)
    load_and_check(fixed, size, "with its size and checksum fixed");
  free(fixed);
  return 0;
}
