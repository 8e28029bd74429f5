// runtime (private): the saved state's format, shared by state_save.c and
// state_load.c, and read by the world's (world_state.c, through its own copy
// of the few helpers it needs).
//
// Layout: a fixed 32-byte header, then the payload.
//   header:  "BKSTATE\0" | u32 version | u32 0x01020304 | u64 payload size | u64 XXH3-64 of the payload
//   payload: u32 breakable_count, per slot { u32 alive | u32 generation | when alive:
//              u64 source_hash | u32 node_count, leaf_count, bond_count (the caller's tree)
//              material { u32 name length | name | f64 density, frailty, bond_strength | u32 accumulate
//                         f64 friction, restitution, compression, tension, shear, refine_strength }
//              u64 grown tree bytes (0: not refined) | .mtree bytes
//              bond_count x { u8 broken | f64 hit points } | leaf_count x u8 (1 anchored, 2 refining) }
//            u32 cluster_count, per slot { u32 alive | u32 generation | when alive:
//              u32 breakable | u32 flags (1 queued, 2 dirty) | u32 leaf_count | leaves (ascending) }
//            u32 free slots, in order | u32 split queue entries
//            u32 jobs, each { u32 breakable, node, due_call | f64 bounds[6]
//              u32 neighbours { u32 node | f64 area } | u32 hits { u64 sequence | f64 local[3], impulse,
//              frailty } }
//            u32 refine_calls, refine_marked, bonds_broken, splits, stress_bonds_broken,
//                stress_clusters_solved, stress_iterations, stress_cursor, refined_leaves, refine_failed
//            u64 hit_sequence
// Every field little endian, a double by its bits: never a struct's bytes.
#pragma once

#include <stdint.h>
#include <string.h>

#include "bk_base.h"

#define RT_STATE_VERSION 1u
#define RT_STATE_HEADER_BYTES 32u
#define RT_STATE_ENDIAN_MARKER 0x01020304u
static const uint8_t rt_state_magic[8] = {'B', 'K', 'S', 'T', 'A', 'T', 'E', '\0'};

/// Writes into out[0..capacity) while it fits, and counts every byte.
typedef struct rt_writer {
  uint8_t* out;
  size_t capacity, size;
} rt_writer;

static inline void rt_put_bytes(rt_writer* w, const void* bytes, size_t n) {
  if (w->size <= w->capacity && n <= w->capacity - w->size && n) memcpy(w->out + w->size, bytes, n);
  w->size += n;
}

static inline void rt_put_u32(rt_writer* w, uint32_t v) {
  uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
  rt_put_bytes(w, b, 4);
}

static inline void rt_put_u64(rt_writer* w, uint64_t v) {
  rt_put_u32(w, (uint32_t)v);
  rt_put_u32(w, (uint32_t)(v >> 32));
}

static inline void rt_put_double(rt_writer* w, double d) {
  uint64_t bits = 0;
  memcpy(&bits, &d, sizeof bits);
  rt_put_u64(w, bits);
}

/// Reads from data[0..size): a read past the end fails (and stays failed).
typedef struct rt_reader {
  const uint8_t* data;
  size_t size, pos;
  bool failed;
} rt_reader;

static inline bool rt_get_bytes(rt_reader* r, void* out, size_t n) {
  if (r->failed || n > r->size - r->pos) {
    r->failed = true;
    if (n) memset(out, 0, n);
    return false;
  }
  if (n) memcpy(out, r->data + r->pos, n);
  r->pos += n;
  return true;
}

static inline uint32_t rt_get_u32(rt_reader* r) {
  uint8_t b[4] = {0};
  rt_get_bytes(r, b, 4);
  return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static inline uint64_t rt_get_u64(rt_reader* r) {
  uint64_t lo = rt_get_u32(r);
  return lo | (uint64_t)rt_get_u32(r) << 32;
}

static inline double rt_get_double(rt_reader* r) {
  uint64_t bits = rt_get_u64(r);
  double d = 0.0;
  memcpy(&d, &bits, sizeof d);
  return d;
}

/// Bytes left to read: what bounds a count before anything is allocated for it.
static inline size_t rt_left(const rt_reader* r) { return r->failed ? 0 : r->size - r->pos; }
