// The allocator every library allocates through (bk_set_allocator): the C
// library's by default, the embedder's when set. The only file of the
// libraries that calls malloc, realloc or free.
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_base.h"

// The defaults: the C library's, with the user pointer unused.
static void* system_alloc(size_t size, void* user) {
  (void)user;
  return malloc(size);
}
static void* system_realloc(void* memory, size_t size, void* user) {
  (void)user;
  return realloc(memory, size);
}
static void system_free(void* memory, void* user) {
  (void)user;
  free(memory);
}

// Set once at start-up, before any thread of ours runs (bk_set_allocator's
// rule), so plain reads from the worker threads are safe.
static bk_alloc_fn* current_alloc = system_alloc;
static bk_realloc_fn* current_realloc = system_realloc;
static bk_free_fn* current_free = system_free;
static void* current_user = NULL;

// Live blocks, for leak checks (bk_allocation_count): relaxed, as nothing is
// ordered by it, and one atomic add is small beside the allocation itself.
static atomic_int_fast64_t live_blocks;

void bk_set_allocator(bk_alloc_fn* alloc_fn, bk_realloc_fn* realloc_fn, bk_free_fn* free_fn, void* user) {
  // All three or none: a realloc or free of one allocator on the blocks of
  // another would corrupt both.
  bool custom = alloc_fn && realloc_fn && free_fn;
  current_alloc = custom ? alloc_fn : system_alloc;
  current_realloc = custom ? realloc_fn : system_realloc;
  current_free = custom ? free_fn : system_free;
  current_user = custom ? user : NULL;
}

int64_t bk_allocation_count(void) {
  return (int64_t)atomic_load_explicit(&live_blocks, memory_order_relaxed);
}

static void out_of_memory(size_t size) {
  fprintf(stderr, "breakables: out of memory allocating %zu bytes\n", size);
  abort();
}

void* bk_try_alloc(size_t size) {
  void* p = current_alloc(size ? size : 1, current_user);
  if (p) atomic_fetch_add_explicit(&live_blocks, 1, memory_order_relaxed);
  return p;
}

void* bk_try_calloc(size_t count, size_t size) {
  if (count && size > SIZE_MAX / count) return NULL;
  void* p = NULL;
  if (current_alloc == system_alloc) {
    // The C library's calloc gets fresh pages already zeroed: no memset.
    p = calloc(count ? count : 1, size ? size : 1);
    if (p) atomic_fetch_add_explicit(&live_blocks, 1, memory_order_relaxed);
  } else {
    p = bk_try_alloc(count * size);
    if (p) memset(p, 0, count * size);
  }
  return p;
}

void* bk_try_realloc(void* memory, size_t size) {
  if (!memory) return bk_try_alloc(size);
  return current_realloc(memory, size ? size : 1, current_user);
}

void* bk_alloc(size_t size) {
  void* p = bk_try_alloc(size);
  if (!p) out_of_memory(size);
  return p;
}

void* bk_calloc(size_t count, size_t size) {
  void* p = bk_try_calloc(count, size);
  if (!p) out_of_memory(count && size > SIZE_MAX / count ? SIZE_MAX : count * size);
  return p;
}

void* bk_realloc(void* memory, size_t size) {
  void* p = bk_try_realloc(memory, size);
  if (!p) out_of_memory(size);
  return p;
}

void bk_free(void* memory) {
  if (!memory) return;
  current_free(memory, current_user);
  atomic_fetch_sub_explicit(&live_blocks, 1, memory_order_relaxed);
}

uint32_t bk_grow_capacity(uint32_t current, uint32_t need) {
  if (need <= current) return current;
  uint64_t cap = current ? current : 16;
  while (cap < need)
    cap *= 2;
  if (cap > UINT32_MAX) {
    if (need == UINT32_MAX) out_of_memory((size_t)need);
    cap = UINT32_MAX;
  }
  return (uint32_t)cap;
}
