// Shared utilities: errors, the index map, hashing and the C locale.
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_base.h"

static void error_fill(bk_error* err, bk_result code, const char* fmt, va_list args) {
  // Messages quote file names and file content: control bytes are escaped
  // here, once for all of them, so no file can drive the user's terminal.
  char text[sizeof err->message];
  vsnprintf(text, sizeof text, fmt, args);
  bk_escape_text(text, strlen(text), err->message, sizeof err->message);
  err->code = code;
}

bool bk_error_set(bk_error* err, const char* fmt, ...) {
  if (err) {
    va_list args;
    va_start(args, fmt);
    error_fill(err, BK_ERROR_FAILED, fmt, args);
    va_end(args);
  }
  return false;
}

bool bk_error_set_code(bk_error* err, bk_result code, const char* fmt, ...) {
  if (err) {
    va_list args;
    va_start(args, fmt);
    error_fill(err, code, fmt, args);
    va_end(args);
  }
  return false;
}

const char* bk_result_name(bk_result code) {
  switch (code) {
  case BK_OK:
    return "ok";
  case BK_ERROR_FAILED:
    return "failed";
  case BK_ERROR_INVALID_ARGUMENT:
    return "invalid argument";
  case BK_ERROR_STALE_ID:
    return "stale id";
  case BK_ERROR_BAD_TREE:
    return "bad tree";
  case BK_ERROR_IO:
    return "i/o error";
  case BK_ERROR_PHYSICS:
    return "physics engine refused";
  case BK_ERROR_OUT_OF_MEMORY:
    return "out of memory";
  }
  return "unknown code";
}

// ---------------------------------------------------------------- index map

#define BK_EMPTY_KEY UINT64_MAX

static inline uint32_t slot_of(uint64_t key, uint32_t mask) {
  // splitmix64 finaliser: edge keys are highly structured, so mix well.
  key ^= key >> 30;
  key *= 0xbf58476d1ce4e5b9ull;
  key ^= key >> 27;
  key *= 0x94d049bb133111ebull;
  key ^= key >> 31;
  return (uint32_t)key & mask;
}

void bk_index_map_init(bk_index_map* map, uint32_t expected) {
  uint32_t cap = 16;
  while (cap < expected * 2u && cap < (1u << 31))
    cap *= 2;
  map->keys = bk_alloc(sizeof(uint64_t) * cap);
  map->values = bk_alloc(sizeof(uint32_t) * cap);
  memset(map->keys, 0xff, sizeof(uint64_t) * cap);
  map->count = 0;
  map->capacity = cap;
}

void bk_index_map_free(bk_index_map* map) {
  bk_free(map->keys);
  bk_free(map->values);
  memset(map, 0, sizeof *map);
}

void bk_index_map_clear(bk_index_map* map) {
  // A map sized for a big mesh and reused for small ones would spend its time
  // clearing empty slots: shrink to what the last use needed.
  if (map->capacity > 1024 && (uint64_t)map->count * 16 < map->capacity) {
    uint32_t expected = map->count;
    bk_index_map_free(map);
    bk_index_map_init(map, expected);
    return;
  }
  if (map->keys) memset(map->keys, 0xff, sizeof(uint64_t) * map->capacity);
  map->count = 0;
}

static void index_map_rehash(bk_index_map* map, uint32_t capacity) {
  bk_index_map bigger = {0};
  bigger.keys = bk_alloc(sizeof(uint64_t) * capacity);
  bigger.values = bk_alloc(sizeof(uint32_t) * capacity);
  memset(bigger.keys, 0xff, sizeof(uint64_t) * capacity);
  bigger.capacity = capacity;
  for (uint32_t i = 0; i < map->capacity; ++i) {
    if (map->keys[i] == BK_EMPTY_KEY) continue;
    uint32_t s = slot_of(map->keys[i], capacity - 1);
    while (bigger.keys[s] != BK_EMPTY_KEY)
      s = (s + 1) & (capacity - 1);
    bigger.keys[s] = map->keys[i];
    bigger.values[s] = map->values[i];
  }
  bigger.count = map->count;
  bk_free(map->keys);
  bk_free(map->values);
  *map = bigger;
}

uint32_t* bk_index_map_insert(bk_index_map* map, uint64_t key, uint32_t value, bool* inserted) {
  if (!map->keys) bk_index_map_init(map, 16);
  if ((map->count + 1) * 2 > map->capacity) index_map_rehash(map, map->capacity * 2);
  uint32_t mask = map->capacity - 1;
  uint32_t s = slot_of(key, mask);
  while (map->keys[s] != BK_EMPTY_KEY) {
    if (map->keys[s] == key) {
      if (inserted) *inserted = false;
      return &map->values[s];
    }
    s = (s + 1) & mask;
  }
  map->keys[s] = key;
  map->values[s] = value;
  map->count++;
  if (inserted) *inserted = true;
  return &map->values[s];
}

uint32_t* bk_index_map_find(const bk_index_map* map, uint64_t key) {
  if (!map->keys) return NULL;
  uint32_t mask = map->capacity - 1;
  uint32_t s = slot_of(key, mask);
  while (map->keys[s] != BK_EMPTY_KEY) {
    if (map->keys[s] == key) return &map->values[s];
    s = (s + 1) & mask;
  }
  return NULL;
}

uint64_t bk_hash_bytes(uint64_t hash, const void* data, size_t size) {
  const unsigned char* p = data;
  for (size_t i = 0; i < size; ++i) {
    hash ^= p[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

bk_c_locale bk_c_locale_begin(void) {
  // A locale object of our own per call: no shared state between threads,
  // and uselocale only changes the calling thread.
  bk_c_locale l = {newlocale(LC_NUMERIC_MASK, "C", (locale_t)0), (locale_t)0};
  if (l.c != (locale_t)0) l.previous = uselocale(l.c);
  return l;
}

void bk_c_locale_end(bk_c_locale* l) {
  if (l->c == (locale_t)0) return;
  uselocale(l->previous);
  freelocale(l->c);
  l->c = (locale_t)0;
}
