// base (private): what every library shares below geom (the public part is
// <breakables/base.h>): allocation that may fail, index maps, hashing,
// heaps, the C locale for text files, file checks. Includes nothing of the
// layers above it (geom, fracture, runtime, bullet).
#pragma once

#include <locale.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <breakables/base.h>

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- allocation

/// bk_alloc that returns NULL on exhaustion instead of aborting, for the
/// calls that can report "out of memory" (a size of 0 takes 1 byte).
void* bk_try_alloc(size_t size);
/// bk_calloc that returns NULL on exhaustion or overflow.
void* bk_try_calloc(size_t count, size_t size);
/// bk_realloc that returns NULL on exhaustion, `memory` left as it was.
void* bk_try_realloc(void* memory, size_t size);

// ---------------------------------------------------------------- the same result on every machine

/// Sorts like qsort, but stably (equal elements keep their order), so the
/// order does not depend on the C library (sort.c).
void bk_sort(void* base, size_t count, size_t size, int (*compare)(const void*, const void*));

/// The libm functions the libraries use, made of IEEE basic operations only
/// (+ - * / and sqrt, exactly rounded everywhere), so they give the same bits
/// on every machine, C library and CPU (det_math.c): the C library's differ in
/// the last bit between glibc, musl and glibc's own FMA variants, and trees
/// built from them would differ. Within a few ulp of the C library's (test_det_math).
double bk_sin(double x);
double bk_cos(double x);
double bk_atan2(double y, double x);
double bk_cbrt(double x);
double bk_log2(double x);
double bk_exp2(double x);
double bk_pow(double x, double y); ///< x > 0, or x = 0 with y > 0 (0); else NaN
double bk_hypot(double x, double y);

// ---------------------------------------------------------------- index map, hashing, heap

/// Open-addressing map from 64-bit keys to 32-bit values, for index-based
/// topology lookups (edge -> new vertex, directed edge -> triangle).
/// UINT64_MAX marks empty slots and is not a valid key.
typedef struct bk_index_map {
  uint64_t* keys;
  uint32_t* values;
  uint32_t count, capacity; ///< capacity is a power of two
} bk_index_map;

/// Prepares a map for about `expected` keys (may be 0).
void bk_index_map_init(bk_index_map* map, uint32_t expected);
/// Releases the map.
void bk_index_map_free(bk_index_map* map);
/// Removes every key (shrinking storage that the last use left mostly empty).
void bk_index_map_clear(bk_index_map* map);
/// Returns a pointer to the value of key, inserting `value` first if absent;
/// *inserted tells which happened. The pointer is valid until the next insert.
uint32_t* bk_index_map_insert(bk_index_map* map, uint64_t key, uint32_t value, bool* inserted);
/// Returns the value of key or NULL.
uint32_t* bk_index_map_find(const bk_index_map* map, uint64_t key);

/// Key of the undirected edge {a, b}.
static inline uint64_t bk_edge_key(uint32_t a, uint32_t b) {
  return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}
/// Key of the directed edge a -> b.
static inline uint64_t bk_directed_edge_key(uint32_t a, uint32_t b) { return ((uint64_t)a << 32) | b; }

/// fmin and fmax as glibc computes them (a NaN loses; of equal values, such
/// as 0 and -0, the first), without the call.
static inline double bk_min(double x, double y) { return (y < x || x != x) ? y : x; }
static inline double bk_max(double x, double y) { return (y > x || x != x) ? y : x; }

/// 64-bit FNV-1a over bytes, continuing from `hash` (start with BK_FNV_OFFSET).
uint64_t bk_hash_bytes(uint64_t hash, const void* data, size_t size);
#define BK_FNV_OFFSET 0xcbf29ce484222325ull

/// One entry of a bk_heap.
typedef struct bk_heap_item {
  double key;
  uint32_t value;
} bk_heap_item;

/// Binary min-heap: smallest key first, equal keys by smallest value (so the
/// order is deterministic). Zero-initialised is empty.
typedef struct bk_heap {
  bk_heap_item* items;
  uint32_t count, capacity;
} bk_heap;

/// Adds a pair.
void bk_heap_push(bk_heap* heap, double key, uint32_t value);
/// Removes and returns the first pair; the heap must not be empty.
bk_heap_item bk_heap_pop(bk_heap* heap);
/// Releases the heap's storage and empties it.
void bk_heap_free(bk_heap* heap);

// ---------------------------------------------------------------- text and files

/// This thread in the C locale's number format, for reading and writing text
/// files whatever locale the host application chose ("0.5", never "0,5").
typedef struct bk_c_locale {
  locale_t c, previous;
} bk_c_locale;

/// Switches; does nothing if the C locale cannot be made.
bk_c_locale bk_c_locale_begin(void);
/// Restores what the thread had.
void bk_c_locale_end(bk_c_locale* locale);

/// Opens a file for reading only when it is a regular file: anything else is
/// refused without blocking ("<path>: is a directory", "<path>: is not a
/// regular file"; a FIFO or a device is never opened). `size` (may be NULL)
/// gets its size. NULL with the reason in `err` otherwise.
FILE* bk_file_open_read(const char* path, uint64_t* size, bk_error* err);
/// bk_file_open_read's checks for a reader that opens the file itself (assimp).
bool bk_file_check_read(const char* path, bk_error* err);
/// The part of bk_file_check_write about the target itself (bk_file_begin_atomic applies it).
bool bk_file_check_target(const char* path, bk_error* err);

#ifdef __cplusplus
}
#endif
