// The journal: each call that changes the destruction state, as a byte
// entry, so that a second runtime holding the same breakables reaches the
// same state by applying them (bk_runtime_apply_journal) with no damage of
// its own: a watching client, or a replay. Hits are kept as the damage
// formula takes them (cluster, tree-frame point, impulse), never as the
// bonds they broke: one hit breaks any number of bonds, and it also takes
// hit points off the bonds it does not break, which are state too.
//
// Entry layout: a kind byte, then its fields; counts and indices as
// LEB128 varints (small numbers take one byte), doubles as their 8 IEEE-754
// bytes, little endian (bit exact: the follower must compute the same
// damage):
//   1 hit       cluster index, generation | local x, y, z | impulse
//   2 break     cluster index, generation | bond | cause (u8)
//   3 split     budget (clusters it may create)
//   4 remove    cluster index, generation
//   5 refine    (a bk_runtime_refine call)
//   6 material  breakable index, generation | 9 doubles | accumulate (u8) | name length (u8), name
//   7 removed breakable   index, generation
//   8 added breakable     index, generation (a follower cannot follow it)
#include <string.h>

#include "journal_format.h"
#include "runtime_internal.h"

// ---------------------------------------------------------------- writing

static uint8_t* reserve(bk_runtime* rt, size_t n) {
  if (rt->journal_size + n > rt->journal_capacity) {
    size_t capacity = rt->journal_capacity ? rt->journal_capacity : 256;
    while (capacity < rt->journal_size + n)
      capacity *= 2;
    rt->journal = bk_realloc(rt->journal, capacity);
    rt->journal_capacity = capacity;
  }
  uint8_t* at = rt->journal + rt->journal_size;
  rt->journal_size += n;
  return at;
}

static void put_u8(bk_runtime* rt, uint8_t v) { *reserve(rt, 1) = v; }

static void put_varint(bk_runtime* rt, uint64_t v) {
  while (v >= 0x80) {
    put_u8(rt, (uint8_t)(v | 0x80));
    v >>= 7;
  }
  put_u8(rt, (uint8_t)v);
}

static void put_double(bk_runtime* rt, double d) {
  uint64_t bits = 0;
  memcpy(&bits, &d, sizeof bits);
  uint8_t* p = reserve(rt, 8);
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(bits >> (8 * i));
}

static void put_cluster(bk_runtime* rt, uint32_t slot) {
  put_varint(rt, slot);
  put_varint(rt, rt->clusters[slot].generation);
}

void rt_journal_hit(bk_runtime* rt, uint32_t slot, bk_vec3 local, double impulse) {
  if (!rt->def.journal) return;
  put_u8(rt, ENTRY_HIT);
  put_cluster(rt, slot);
  put_double(rt, local.x);
  put_double(rt, local.y);
  put_double(rt, local.z);
  put_double(rt, impulse);
}

void rt_journal_break(bk_runtime* rt, uint32_t slot, uint32_t bond, bk_break_cause cause) {
  if (!rt->def.journal) return;
  put_u8(rt, ENTRY_BREAK);
  put_cluster(rt, slot);
  put_varint(rt, bond);
  put_u8(rt, (uint8_t)cause);
}

void rt_journal_split(bk_runtime* rt, uint32_t budget) {
  if (!rt->def.journal) return;
  put_u8(rt, ENTRY_SPLIT);
  put_varint(rt, budget);
}

void rt_journal_remove(bk_runtime* rt, uint32_t slot) {
  if (!rt->def.journal) return;
  put_u8(rt, ENTRY_REMOVE);
  put_cluster(rt, slot);
}

void rt_journal_refine(bk_runtime* rt) {
  if (rt->def.journal) put_u8(rt, ENTRY_REFINE);
}

void rt_journal_material(bk_runtime* rt, uint32_t breakable_index) {
  if (!rt->def.journal) return;
  const rt_breakable* b = &rt->breakables[breakable_index];
  const bk_material* m = &b->material;
  put_u8(rt, ENTRY_MATERIAL);
  put_varint(rt, breakable_index);
  put_varint(rt, b->generation);
  const double values[MATERIAL_DOUBLES] = {m->density,       m->frailty,     m->bond_strength,
                                           m->friction,      m->restitution, m->compression_limit,
                                           m->tension_limit, m->shear_limit, m->refine_strength};
  for (int i = 0; i < MATERIAL_DOUBLES; ++i)
    put_double(rt, values[i]);
  put_u8(rt, m->accumulate ? 1 : 0);
  size_t length = strlen(b->material_name);
  put_u8(rt, (uint8_t)length);
  memcpy(reserve(rt, length), b->material_name, length);
}

void rt_journal_breakable(bk_runtime* rt, uint32_t breakable_index, bool added) {
  if (!rt->def.journal) return;
  put_u8(rt, added ? ENTRY_BREAKABLE_ADDED : ENTRY_BREAKABLE_REMOVED);
  put_varint(rt, breakable_index);
  put_varint(rt, rt->breakables[breakable_index].generation);
}

bk_result bk_runtime_set_journal(bk_runtime* rt, bool journal) {
  if (!rt) return BK_ERROR_INVALID_ARGUMENT;
  rt->def.journal = journal;
  return BK_OK;
}

bool bk_runtime_journal_enabled(const bk_runtime* rt) { return rt && rt->def.journal; }

const void* bk_runtime_journal(const bk_runtime* rt, size_t* size) {
  if (size) *size = rt && rt->journal_size ? rt->journal_size : 0;
  return rt && rt->journal_size ? rt->journal : NULL;
}

void bk_runtime_clear_journal(bk_runtime* rt) {
  if (rt) rt->journal_size = 0;
}
