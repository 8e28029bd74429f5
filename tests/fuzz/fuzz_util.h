// Shared by the fuzz harnesses: scratch files for the path-based loaders, the
// .mtree header fix-up that lets mutations reach the parser, and the checks
// every harness asserts on the trees it gets. A failed check prints one line
// and aborts, which libFuzzer (and the replay driver) report as a crash.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "bk_fracture.h"

/// The libFuzzer entry point each harness defines.
int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

/// The harness's name for messages ("fuzz_obj"); each harness defines it.
extern const char bk_fuzz_harness[];

/// Prints "<harness>: <message>" on stderr and aborts.
_Noreturn void bk_fuzz_fail(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

/// Path of a file named `name` in this process's scratch directory (created on
/// first use under $BK_FUZZ_TMP, else $TMPDIR, else /tmp; removed at exit).
/// The returned string is valid until the next call.
const char* bk_fuzz_scratch_path(const char* name);

/// Writes bytes to a scratch file and returns its path (aborts if it cannot:
/// that is a broken machine, not a finding).
const char* bk_fuzz_write_scratch(const char* name, const uint8_t* data, size_t size);

/// Reads a whole file into a fresh buffer (free() it); NULL if it cannot.
uint8_t* bk_fuzz_read_file(const char* path, size_t* size);

/// Rewrites the payload size and checksum fields of an .mtree header (the
/// first 32 bytes) to match the payload that follows, so a mutated file gets
/// past those checks to the parser behind them. Returns false (nothing
/// changed) when there is no complete header, true when the fields now match.
bool bk_fuzz_fix_mtree_header(uint8_t* data, size_t size);

/// Asserts what every bond list must satisfy: leaf_a < leaf_b < leaf_count,
/// finite area > 0, finite centroid, unit normal, each pair listed once.
/// `what` names the tree in the failure message.
void bk_fuzz_check_bonds(const bk_mesh_tree* tree, const char* what);
