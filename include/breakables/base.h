// Breakables base (part of breakables::authoring, below every other layer):
// the allocator every library allocates through, a deterministic random
// generator, whole-file reads and atomic file replacement. Included by
// authoring.h, so by every other header.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- allocation

/// Allocates `size` bytes (> 0) aligned for any type, as malloc does; NULL
/// when there is no memory. `user` is the pointer given to bk_set_allocator.
typedef void* bk_alloc_fn(size_t size, void* user);
/// Resizes `memory` (from this allocator, never NULL) to `size` bytes (> 0),
/// as realloc does: the contents are kept up to the lesser size, and on
/// failure NULL is returned with `memory` left as it was.
typedef void* bk_realloc_fn(void* memory, size_t size, void* user);
/// Releases `memory` (from this allocator, never NULL).
typedef void bk_free_fn(void* memory, void* user);

/// Routes every allocation of the Breakables libraries (authoring, runtime
/// and the bullet library's C side) through the three functions; all three
/// NULL restores malloc, realloc and free. Bullet keeps its own C++
/// allocations, as do assimp, GLU and stb inside the import and the caps.
/// Call it at start-up, before any other call of the
/// libraries and while none runs: memory allocated before must not be
/// released after. The functions are called from several threads at once
/// (the cell patterns build on every core), so they must be thread-safe. A
/// NULL return makes the call that needed the memory fail with "out of
/// memory" where it can report an error (creating a runtime or a world,
/// reading a file); elsewhere the process prints the size and aborts, as it
/// always did on exhaustion.
void bk_set_allocator(bk_alloc_fn* alloc_fn, bk_realloc_fn* realloc_fn, bk_free_fn* free_fn, void* user);

/// Blocks allocated through the allocator and not yet released (all
/// threads; 0 once everything the libraries made has been freed). Counting
/// bytes would need every release to know its size, which bk_free does not.
int64_t bk_allocation_count(void);

/// The allocator's alloc (a size of 0 takes 1 byte); aborts with a message
/// on exhaustion. Memory the libraries hand out (bk_file_read's data, a
/// PNG's bytes) is released with bk_free.
void* bk_alloc(size_t size);
/// bk_alloc of count * size zeroed bytes (aborts when the product overflows).
void* bk_calloc(size_t count, size_t size);
/// The allocator's realloc (NULL `memory` allocates); aborts on exhaustion.
void* bk_realloc(void* memory, size_t size);
/// Releases memory from bk_alloc, bk_calloc or bk_realloc; NULL is ignored.
void bk_free(void* memory);
/// A capacity >= need for an array grown with bk_realloc: `current` (16 when
/// 0) doubled as often as needed, UINT32_MAX at most; aborts when `need` is
/// UINT32_MAX and the array cannot hold it.
uint32_t bk_grow_capacity(uint32_t current, uint32_t need);

// ---------------------------------------------------------------- random numbers

/// PCG32 random generator (O'Neill, pcg-random.org): the same numbers on
/// every platform for a given seed and stream.
typedef struct bk_rng {
  uint64_t state, inc;
} bk_rng;

/// A generator for `seed` on `stream` (different streams give independent sequences).
bk_rng bk_rng_seed(uint64_t seed, uint64_t stream);
/// Next 32 random bits.
uint32_t bk_rng_next(bk_rng* rng);
/// Uniform double in [0, 1), with 53 random bits.
double bk_rng_unit(bk_rng* rng);
/// Uniformly distributed unit vector.
bk_vec3 bk_rng_direction(bk_rng* rng);

// ---------------------------------------------------------------- files

/// Reads a whole regular file into a fresh buffer (*data, released with
/// bk_free, even for an empty file). A directory, FIFO or device is refused
/// without blocking; files over max_bytes are refused, before anything is
/// allocated, with "<path>: file larger than <limit_text>, refusing to
/// load"; limit_text names the caller's limit ("1 GiB").
bool bk_file_read(const char* path, uint64_t max_bytes, const char* limit_text, void** data, size_t* size,
                  bk_error* err);

/// Checks, before any work, that bk_file_begin_atomic may replace `path`: its
/// directory exists and takes new files, and the target, if there, is a
/// regular file whose mode bits let this process write it (for root: any
/// write bit), so a read-only file is never replaced. One-line reason otherwise.
bool bk_file_check_write(const char* path, bk_error* err);
/// Whether two paths name the same file: by device and inode when both
/// exist (symlinks and hard links included), else by their normalised
/// absolute names ("./x" and "x" are the same).
bool bk_file_same(const char* a, const char* b);
/// Copies `length` bytes of text to `out` (NUL-terminated, at most size - 1
/// bytes) with every byte a terminal could act on (controls, invalid UTF-8,
/// C1 controls) written as \xNN. Returns how many bytes of text it took.
/// bk_error_set applies it to every message, so text quoted from a file
/// never reaches a terminal raw.
size_t bk_escape_text(const char* text, size_t length, char* out, size_t size);

/// Wording of atomic-write failures; each message reads "<path>: <text>: <reason>".
typedef struct bk_atomic_messages {
  const char* open_failed;   ///< the temporary file could not be created
  const char* write_failed;  ///< writing, flushing, syncing or closing failed
  const char* rename_failed; ///< the temporary could not replace the target
} bk_atomic_messages;

/// A file being written beside its target, to replace the target atomically.
typedef struct bk_atomic_file {
  FILE* stream;   ///< write the new contents here
  char* tmp_path; ///< the temporary's name (owned; released by bk_file_commit_atomic)
} bk_atomic_file;

/// Starts replacing `path` atomically: creates a temporary file with a new,
/// unique name in the same directory, exclusively (a file or symlink already
/// there is never opened or followed), with the permissions a new file gets
/// (0666 less the umask). Readers see either the old file or the complete new
/// one, never a partial write, and concurrent writers never share a
/// temporary. A target bk_file_check_write refuses (read-only, a directory,
/// not a regular file) is never replaced. Returns false (err filled, nothing
/// created) on failure. Every file the libraries write goes through here.
bool bk_file_begin_atomic(const char* path, const bk_atomic_messages* messages, bk_atomic_file* out,
                          bk_error* err);
/// Finishes a write begun by bk_file_begin_atomic: checks the stream, flushes,
/// syncs, closes and renames over `path`. Always consumes the file; on any
/// failure the temporary is removed and the target left as it was.
bool bk_file_commit_atomic(bk_atomic_file* file, const char* path, const bk_atomic_messages* messages,
                           bk_error* err);
/// Abandons a write begun by bk_file_begin_atomic: the temporary is removed
/// and the target left as it was.
void bk_file_abort_atomic(bk_atomic_file* file);

#ifdef __cplusplus
}
#endif
