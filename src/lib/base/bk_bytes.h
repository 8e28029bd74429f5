// base (private): little-endian bytes out and in, for the libraries' binary
// formats (.mtree files, saved runtime and world states). One writer, into
// a caller's buffer (capacity in; what does not fit is counted, not
// written, so a first call with no buffer tells the size) or growing its own
// (bk_realloc); one bounded reader, whose reads past the end give zeros and
// set `failed` for the caller to check.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <breakables/base.h>
#include <breakables/types.h>

typedef struct bk_byte_writer {
  uint8_t* out;
  size_t capacity, size;
  bool grows; ///< the writer owns `out` and grows it; else the caller's buffer
} bk_byte_writer;

static inline void bk_store_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

static inline void bk_store_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

static inline uint32_t bk_load_u32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i)
    v |= (uint32_t)p[i] << (8 * i);
  return v;
}

static inline uint64_t bk_load_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i)
    v |= (uint64_t)p[i] << (8 * i);
  return v;
}

/// Where the next n bytes go (the size counts them either way); NULL when a
/// caller's buffer has no room for them.
static inline uint8_t* bk_bytes_room(bk_byte_writer* w, size_t n) {
  if (w->grows && w->size + n > w->capacity) {
    size_t capacity = w->capacity ? w->capacity : 4096;
    while (capacity < w->size + n)
      capacity *= 2;
    w->out = (uint8_t*)bk_realloc(w->out, capacity);
    w->capacity = capacity;
  }
  uint8_t* at = w->out && w->size <= w->capacity && n <= w->capacity - w->size ? w->out + w->size : NULL;
  w->size += n;
  return at;
}

static inline void bk_put_bytes(bk_byte_writer* w, const void* bytes, size_t n) {
  uint8_t* at = bk_bytes_room(w, n);
  if (at && n) memcpy(at, bytes, n);
}

static inline void bk_put_u8(bk_byte_writer* w, uint8_t v) {
  uint8_t* at = bk_bytes_room(w, 1);
  if (at) *at = v;
}

static inline void bk_put_u32(bk_byte_writer* w, uint32_t v) {
  uint8_t* at = bk_bytes_room(w, 4);
  if (at) bk_store_u32(at, v);
}

static inline void bk_put_u64(bk_byte_writer* w, uint64_t v) {
  uint8_t* at = bk_bytes_room(w, 8);
  if (at) bk_store_u64(at, v);
}

static inline void bk_put_f32(bk_byte_writer* w, float v) {
  uint32_t bits = 0;
  memcpy(&bits, &v, sizeof bits);
  bk_put_u32(w, bits);
}

/// A double by its bits (-0 stays -0: a saved value, not a hashed one).
static inline void bk_put_f64(bk_byte_writer* w, double v) {
  uint64_t bits = 0;
  memcpy(&bits, &v, sizeof bits);
  bk_put_u64(w, bits);
}

static inline void bk_put_vec3(bk_byte_writer* w, bk_vec3 v) {
  bk_put_f64(w, v.x);
  bk_put_f64(w, v.y);
  bk_put_f64(w, v.z);
}

typedef struct bk_byte_reader {
  const uint8_t* data;
  size_t size, pos;
  bool failed; ///< a read went past the end (and every later one gives zeros)
} bk_byte_reader;

static inline bool bk_get_bytes(bk_byte_reader* r, void* out, size_t n) {
  if (r->failed || n > r->size - r->pos) {
    r->failed = true;
    if (n) memset(out, 0, n);
    return false;
  }
  if (n) memcpy(out, r->data + r->pos, n);
  r->pos += n;
  return true;
}

static inline uint32_t bk_get_u32(bk_byte_reader* r) {
  uint8_t b[4] = {0};
  bk_get_bytes(r, b, 4);
  return bk_load_u32(b);
}

static inline uint64_t bk_get_u64(bk_byte_reader* r) {
  uint8_t b[8] = {0};
  bk_get_bytes(r, b, 8);
  return bk_load_u64(b);
}

static inline double bk_get_f64(bk_byte_reader* r) {
  uint64_t bits = bk_get_u64(r);
  double d = 0.0;
  memcpy(&d, &bits, sizeof d);
  return d;
}

/// Bytes left to read (0 once a read failed): what bounds a count before
/// anything is allocated for it.
static inline size_t bk_bytes_left(const bk_byte_reader* r) { return r->failed ? 0 : r->size - r->pos; }
