// Applying a journal (bk_runtime_apply_journal): the entries are read and
// checked whole first, then applied in order through the calls that wrote
// them (see journal.c for the layout).
#include <string.h>

#include "journal_format.h"
#include "runtime_internal.h"

static const char* const entry_names[] = {
    "", "hit", "break", "split", "remove", "refine", "material", "removed breakable", "added breakable"};

// ---------------------------------------------------------------- reading

/// One entry as read, before it is applied.
typedef struct entry {
  uint8_t kind;
  uint32_t index, generation; // the cluster's or the breakable's
  uint32_t value;             // bond (break) or budget (split)
  uint8_t cause, accumulate;
  double values[MATERIAL_DOUBLES]; // hit: x, y, z, impulse; material: its doubles
  char name[BK_MATERIAL_NAME_MAX + 1];
} entry;

typedef struct reader {
  const uint8_t* data;
  size_t size, pos;
} reader;

static bool get_u8(reader* r, uint8_t* out) {
  if (r->pos >= r->size) return false;
  *out = r->data[r->pos++];
  return true;
}

// A varint of at most 32 bits (5 bytes); longer or larger is malformed.
static bool get_varint(reader* r, uint32_t* out) {
  uint64_t v = 0;
  for (int shift = 0; shift < 35; shift += 7) {
    uint8_t byte = 0;
    if (!get_u8(r, &byte)) return false;
    v |= (uint64_t)(byte & 0x7f) << shift;
    if (!(byte & 0x80)) {
      if (v > UINT32_MAX) return false;
      *out = (uint32_t)v;
      return true;
    }
  }
  return false;
}

static bool get_double(reader* r, double* out) {
  if (r->size - r->pos < 8) return false;
  uint64_t bits = 0;
  for (int i = 0; i < 8; ++i)
    bits |= (uint64_t)r->data[r->pos + i] << (8 * i);
  r->pos += 8;
  memcpy(out, &bits, sizeof bits);
  return true;
}

// Reads one entry; false (err says why, with the entry's number and byte
// offset) when the bytes are malformed. Meaning is checked when applied.
static bool read_entry(reader* r, uint32_t number, entry* e, bk_error* err) {
  size_t at = r->pos;
  memset(e, 0, sizeof *e);
  bool ok = get_u8(r, &e->kind);
  if (ok && (e->kind < ENTRY_HIT || e->kind > ENTRY_BREAKABLE_ADDED))
    return bk_error_set(err, "journal: entry %u (byte %zu): unknown kind %u", number, at, e->kind);
  switch (e->kind) {
  case ENTRY_HIT:
    ok = get_varint(r, &e->index) && get_varint(r, &e->generation);
    for (int i = 0; ok && i < 4; ++i)
      ok = get_double(r, &e->values[i]);
    if (ok && (!isfinite(e->values[0]) || !isfinite(e->values[1]) || !isfinite(e->values[2]) ||
               !(e->values[3] > 0.0) || !isfinite(e->values[3])))
      return bk_error_set(err, "journal: entry %u (byte %zu): hit with a point or impulse not finite", number,
                          at);
    break;
  case ENTRY_BREAK:
    ok = get_varint(r, &e->index) && get_varint(r, &e->generation) && get_varint(r, &e->value) &&
         get_u8(r, &e->cause);
    if (ok && e->cause != BK_BREAK_DAMAGE && e->cause != BK_BREAK_STRESS)
      return bk_error_set(err, "journal: entry %u (byte %zu): unknown break cause %u", number, at, e->cause);
    break;
  case ENTRY_SPLIT:
    ok = get_varint(r, &e->value);
    if (ok && e->value < 2)
      return bk_error_set(err, "journal: entry %u (byte %zu): split budget %u is below 2", number, at,
                          e->value);
    break;
  case ENTRY_REMOVE:
  case ENTRY_BREAKABLE_REMOVED:
  case ENTRY_BREAKABLE_ADDED:
    ok = get_varint(r, &e->index) && get_varint(r, &e->generation);
    break;
  case ENTRY_REFINE:
    break;
  case ENTRY_MATERIAL: {
    ok = get_varint(r, &e->index) && get_varint(r, &e->generation);
    for (int i = 0; ok && i < MATERIAL_DOUBLES; ++i)
      ok = get_double(r, &e->values[i]);
    uint8_t length = 0;
    ok = ok && get_u8(r, &e->accumulate) && get_u8(r, &length);
    if (ok && (e->accumulate > 1 || length > BK_MATERIAL_NAME_MAX))
      return bk_error_set(err, "journal: entry %u (byte %zu): malformed material", number, at);
    ok = ok && r->size - r->pos >= length;
    if (ok) {
      memcpy(e->name, r->data + r->pos, length);
      r->pos += length;
      if (memchr(e->name, '\0', length))
        return bk_error_set(err, "journal: entry %u (byte %zu): material name holds a NUL byte", number, at);
    }
    break;
  }
  default:
    break;
  }
  if (!ok)
    return bk_error_set(err, "journal: entry %u (byte %zu): truncated %s entry", number, at,
                        e->kind <= ENTRY_BREAKABLE_ADDED ? entry_names[e->kind] : "");
  return true;
}

// ---------------------------------------------------------------- applying

static bool diverged(bk_error* err, uint32_t number, const entry* e, const char* why) {
  return bk_error_set(err, "journal: entry %u (%s %u/%u): %s: the runtimes have diverged", number,
                      entry_names[e->kind], e->index, e->generation, why);
}

static bool apply_entry(bk_runtime* rt, uint32_t number, const entry* e, bk_error* err) {
  bk_cluster_id cluster = {e->index, e->generation};
  bk_breakable_id breakable = {e->index, e->generation};
  switch (e->kind) {
  case ENTRY_HIT:
    if (!rt_find_cluster(rt, cluster)) return diverged(err, number, e, "no such live cluster here");
    rt_damage_local(rt, e->index, bk_v3(e->values[0], e->values[1], e->values[2]), e->values[3]);
    return true;
  case ENTRY_BREAK: {
    bk_fracture_command command = {.cluster = cluster, .bond = e->value, .cause = (bk_break_cause)e->cause};
    // The break is placed where this runtime's body is (as a hit's are).
    const rt_cluster* c = rt_find_cluster(rt, cluster);
    if (c && e->value < rt->breakables[c->breakable].tree->bond_count) {
      bk_body_state state = rt_body_state(rt, e->index);
      bk_transform tree_to_world = rt_tree_to_world(c, &state);
      command.position =
          bk_transform_point(tree_to_world, rt->breakables[c->breakable].tree->bonds[e->value].centroid);
      command.velocity = state.linear_velocity;
    }
    if (bk_runtime_apply_fracture_commands(rt, &command, 1) != 1)
      return diverged(err, number, e, "its bond is not an intact bond of that live cluster here");
    return true;
  }
  case ENTRY_SPLIT:
    rt_split(rt, e->value);
    return true;
  case ENTRY_REMOVE:
    if (bk_runtime_remove_cluster(rt, cluster) != BK_OK)
      return diverged(err, number, e, "no such live cluster here");
    return true;
  case ENTRY_REFINE:
    bk_runtime_refine(rt);
    return true;
  case ENTRY_MATERIAL: {
    const double* v = e->values;
    bk_material m = {.name = e->name,
                     .density = v[0],
                     .frailty = v[1],
                     .bond_strength = v[2],
                     .accumulate = e->accumulate != 0,
                     .friction = v[3],
                     .restitution = v[4],
                     .compression_limit = v[5],
                     .tension_limit = v[6],
                     .shear_limit = v[7],
                     .refine_strength = v[8]};
    bk_result result = bk_runtime_set_material(rt, breakable, &m);
    if (result == BK_ERROR_STALE_ID) return diverged(err, number, e, "no such live breakable here");
    if (result != BK_OK)
      return bk_error_set(err, "journal: entry %u (material of breakable %u): not a valid material", number,
                          e->index);
    return true;
  }
  case ENTRY_BREAKABLE_REMOVED:
    if (bk_runtime_remove_breakable(rt, breakable) != BK_OK)
      return diverged(err, number, e, "no such live breakable here");
    return true;
  case ENTRY_BREAKABLE_ADDED:
    return bk_error_set(err,
                        "journal: entry %u: breakable %u was added on the runtime that wrote it, which a "
                        "journal cannot carry (it needs the tree): load a saved state instead",
                        number, e->index);
  default:
    return false;
  }
}

bool bk_runtime_apply_journal(bk_runtime* rt, const void* data, size_t size, bk_error* err) {
  if (!rt) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "journal: runtime is NULL");
  if (size && !data) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "journal: data is NULL");
  // Checked whole first: malformed bytes change nothing.
  reader r = {data, size, 0};
  entry e = {0};
  uint32_t count = 0;
  while (r.pos < r.size) {
    if (!read_entry(&r, count, &e, err)) return false;
    count++;
  }
  // The follower writes no journal of its own while it follows.
  bool journal = rt->def.journal;
  rt->def.journal = false;
  r.pos = 0;
  bool ok = true;
  for (uint32_t number = 0; ok && number < count; ++number) {
    read_entry(&r, number, &e, NULL);
    ok = apply_entry(rt, number, &e, err);
  }
  rt->def.journal = journal;
  return ok;
}
