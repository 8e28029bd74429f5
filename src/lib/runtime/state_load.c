// Loading a saved destruction state (bk_runtime_load_state). The bytes may be
// damaged or hostile: the header is checked first (each kind of damage its
// own message), then the whole payload is parsed and checked into
// temporaries (every index in range, leaves ascending and each in exactly
// one cluster, counts bounded by the bytes left before anything is
// allocated for them, hit points finite and within their bond's), and only
// then does the runtime change: refinements cancelled, clusters made again
// from their leaves (node sets and mass as a split makes them), the
// refinements that waited made again as a hit makes them, events cleared.
#include <inttypes.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "runtime_internal.h"
#include "state_format.h"

typedef struct ld_breakable {
  bool alive;
  uint32_t generation;
  bk_material material;
  char name[BK_MATERIAL_NAME_MAX + 1];
  bk_mesh_tree grown;       // a refined breakable's tree (node_count 0: not refined)
  const bk_mesh_tree* tree; // what its bonds and leaves index: grown, or the caller's
  uint8_t* broken;
  double* hp;
  uint8_t* flags;    // 1 anchored, 2 refining
  uint32_t* owner;   // each leaf's cluster slot (UINT32_MAX: none), to check
  uint32_t refining; // leaves marked
} ld_breakable;

typedef struct ld_cluster {
  bool alive;
  uint32_t generation, breakable, flags, leaf_count;
  uint32_t* leaves;
} ld_cluster;

typedef struct ld_job {
  uint32_t breakable, node, due_call;
  bk_aabb bounds;
  uint32_t neighbour_count, hit_count;
  uint32_t* neighbour_nodes;
  double* neighbour_areas;
  rt_refine_hit* hits;
} ld_job;

enum { LD_COUNTERS = 10 };

typedef struct ld_state {
  ld_breakable* breakables;
  uint32_t breakable_count;
  ld_cluster* clusters;
  uint32_t cluster_count;
  uint32_t *free_slots, *queue;
  uint32_t free_count, queue_count;
  ld_job* jobs;
  uint32_t job_count;
  uint32_t counters[LD_COUNTERS];
  uint64_t hit_sequence;
} ld_state;

static void ld_free(ld_state* s) {
  for (uint32_t i = 0; s->breakables && i < s->breakable_count; ++i) {
    ld_breakable* b = &s->breakables[i];
    bk_mesh_tree_free(&b->grown);
    bk_free(b->broken);
    bk_free(b->hp);
    bk_free(b->flags);
    bk_free(b->owner);
  }
  for (uint32_t i = 0; s->clusters && i < s->cluster_count; ++i)
    bk_free(s->clusters[i].leaves);
  for (uint32_t i = 0; s->jobs && i < s->job_count; ++i) {
    bk_free(s->jobs[i].neighbour_nodes);
    bk_free(s->jobs[i].neighbour_areas);
    bk_free(s->jobs[i].hits);
  }
  bk_free(s->breakables);
  bk_free(s->clusters);
  bk_free(s->free_slots);
  bk_free(s->queue);
  bk_free(s->jobs);
  memset(s, 0, sizeof *s);
}

// Checks the header in a fixed order so that each kind of damage gets its own message.
static bool check_header(const uint8_t* data, size_t size, bk_error* err) {
  if (!data || size < RT_STATE_HEADER_BYTES)
    return bk_error_set(err, "state: truncated header (%zu bytes, needs %u)", data ? size : 0,
                        RT_STATE_HEADER_BYTES);
  if (memcmp(data, rt_state_magic, sizeof rt_state_magic) != 0)
    return bk_error_set(err, "state: not a saved destruction state (bad magic)");
  bk_byte_reader r = {.data = data, .size = size, .pos = 8};
  uint32_t version = bk_get_u32(&r), marker = bk_get_u32(&r);
  bool swapped = marker == 0x04030201u;
  if (version != RT_STATE_VERSION && !swapped)
    return bk_error_set(err, "state: version %" PRIu32 " is not supported (expected %u)", version,
                        RT_STATE_VERSION);
  if (marker != RT_STATE_ENDIAN_MARKER)
    return bk_error_set(err, "state: wrong byte order (marker 0x%08" PRIx32 ", expected 0x%08x)", marker,
                        RT_STATE_ENDIAN_MARKER);
  uint64_t declared = bk_get_u64(&r), checksum = bk_get_u64(&r);
  uint64_t actual = (uint64_t)(size - RT_STATE_HEADER_BYTES);
  if (actual < declared)
    return bk_error_set(err, "state: truncated: payload is %" PRIu64 " bytes, header says %" PRIu64, actual,
                        declared);
  if (actual > declared)
    return bk_error_set(err, "state: size mismatch: payload is %" PRIu64 " bytes, header says %" PRIu64,
                        actual, declared);
  if (XXH3_64bits(data + RT_STATE_HEADER_BYTES, (size_t)actual) != checksum)
    return bk_error_set(err, "state: checksum mismatch (the state is corrupt)");
  return true;
}

static bool corrupt_end(const bk_byte_reader* r, const char* what, uint32_t index, bk_error* err) {
  return bk_error_set(err, "state: corrupt: ends inside %s %" PRIu32 " (at byte %zu of %zu)", what, index,
                      r->pos, r->size);
}

static bool get_material(bk_byte_reader* r, ld_breakable* b, uint32_t index, bk_error* err) {
  uint32_t length = bk_get_u32(r);
  if (length > BK_MATERIAL_NAME_MAX)
    return bk_error_set(
        err, "state: corrupt: breakable %" PRIu32 "'s material name is %" PRIu32 " bytes (at most %d)", index,
        length, BK_MATERIAL_NAME_MAX);
  bk_get_bytes(r, b->name, length);
  b->name[length] = '\0';
  if (strlen(b->name) != length)
    return bk_error_set(err, "state: corrupt: breakable %" PRIu32 "'s material name holds a NUL", index);
  bk_material* m = &b->material;
  m->name = b->name;
  m->density = bk_get_f64(r);
  m->frailty = bk_get_f64(r);
  m->bond_strength = bk_get_f64(r);
  uint32_t accumulate = bk_get_u32(r);
  m->accumulate = accumulate != 0;
  m->friction = bk_get_f64(r);
  m->restitution = bk_get_f64(r);
  m->compression_limit = bk_get_f64(r);
  m->tension_limit = bk_get_f64(r);
  m->shear_limit = bk_get_f64(r);
  m->refine_strength = bk_get_f64(r);
  if (r->failed) return corrupt_end(r, "the material of breakable", index, err);
  bk_error why = {{0}};
  if (accumulate > 1 || !bk_material_validate(m, &why))
    return bk_error_set(err, "state: corrupt: breakable %" PRIu32 "'s material: %s", index,
                        accumulate > 1 ? "accumulate is not 0 or 1" : why.message);
  return true;
}

// A breakable's slot: the same as the runtime's, for the same tree.
static bool get_breakable(const bk_runtime* rt, bk_byte_reader* r, ld_breakable* b, uint32_t i,
                          bk_error* err) {
  b->alive = bk_get_u32(r) != 0;
  b->generation = bk_get_u32(r);
  if (r->failed) return corrupt_end(r, "breakable", i, err);
  const rt_breakable* here = &rt->breakables[i];
  if (b->alive != here->alive)
    return bk_error_set(err, "state: breakable %" PRIu32 " is %s here but %s in the state", i,
                        here->alive ? "alive" : "removed", b->alive ? "alive" : "removed");
  if (!b->alive) return true;
  if (b->generation != here->generation)
    return bk_error_set(
        err, "state: breakable %" PRIu32 " is generation %" PRIu32 " here, %" PRIu32 " in the state", i,
        here->generation, b->generation);
  uint64_t source_hash = bk_get_u64(r);
  uint32_t nodes = bk_get_u32(r), leaves = bk_get_u32(r), bonds = bk_get_u32(r);
  if (r->failed) return corrupt_end(r, "breakable", i, err);
  const bk_mesh_tree* t = here->source;
  if (source_hash != t->source_hash || nodes != t->node_count || leaves != t->leaf_count ||
      bonds != t->bond_count)
    return bk_error_set(err,
                        "state: breakable %" PRIu32 " is another tree: %016" PRIx64 " (%" PRIu32
                        " nodes, %" PRIu32 " leaves, %" PRIu32 " bonds) here, %016" PRIx64 " (%" PRIu32
                        " nodes, %" PRIu32 " leaves, %" PRIu32 " bonds) in the state",
                        i, t->source_hash, t->node_count, t->leaf_count, t->bond_count, source_hash, nodes,
                        leaves, bonds);
  if (!get_material(r, b, i, err)) return false;
  uint64_t grown_size = bk_get_u64(r);
  if (r->failed || grown_size > bk_bytes_left(r))
    return corrupt_end(r, "the refined tree of breakable", i, err);
  b->tree = t;
  if (grown_size) {
    char name[64] = {0};
    snprintf(name, sizeof name, "state: breakable %" PRIu32 "'s refined tree", i);
    if (!bk_mesh_tree_load_memory(r->data + r->pos, (size_t)grown_size, name, &b->grown, err)) return false;
    r->pos += (size_t)grown_size;
    const bk_mesh_tree* g = &b->grown;
    if (g->source_hash != t->source_hash || g->node_count < t->node_count || g->leaf_count < t->leaf_count ||
        g->bond_count < t->bond_count)
      return bk_error_set(err, "state: breakable %" PRIu32 "'s refined tree did not grow from its tree", i);
    b->tree = g;
  }
  const bk_mesh_tree* tree = b->tree;
  if ((uint64_t)tree->bond_count * 9u + tree->leaf_count > bk_bytes_left(r))
    return corrupt_end(r, "the bonds of breakable", i, err);
  b->broken = bk_alloc(tree->bond_count + 1u);
  b->hp = bk_alloc(sizeof(double) * (tree->bond_count + 1u));
  for (uint32_t j = 0; j < tree->bond_count; ++j) {
    bk_get_bytes(r, &b->broken[j], 1);
    b->hp[j] = bk_get_f64(r);
    double initial = b->material.bond_strength * tree->bonds[j].area;
    if (b->broken[j] > 1 || !(b->hp[j] >= 0.0 && b->hp[j] <= initial))
      return bk_error_set(err, "state: corrupt: breakable %" PRIu32 " bond %" PRIu32 ": %s", i, j,
                          b->broken[j] > 1 ? "broken flag is not 0 or 1" : "hit points outside [0, initial]");
  }
  b->flags = bk_alloc(tree->leaf_count + 1u);
  b->owner = bk_alloc(sizeof(uint32_t) * (tree->leaf_count + 1u));
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_get_bytes(r, &b->flags[l], 1);
    if (b->flags[l] > 3)
      return bk_error_set(err, "state: corrupt: breakable %" PRIu32 " leaf %" PRIu32 ": flags %u", i, l,
                          b->flags[l]);
    b->refining += b->flags[l] >> 1;
    b->owner[l] = UINT32_MAX;
  }
  return true;
}

static bool get_cluster(bk_byte_reader* r, ld_state* s, uint32_t slot, bk_error* err) {
  ld_cluster* c = &s->clusters[slot];
  c->alive = bk_get_u32(r) != 0;
  c->generation = bk_get_u32(r);
  if (!c->alive) return r->failed ? corrupt_end(r, "cluster", slot, err) : true;
  c->breakable = bk_get_u32(r);
  c->flags = bk_get_u32(r);
  c->leaf_count = bk_get_u32(r);
  if (r->failed) return corrupt_end(r, "cluster", slot, err);
  if (c->generation == 0 || c->flags > 3 || c->breakable >= s->breakable_count ||
      !s->breakables[c->breakable].alive)
    return bk_error_set(err, "state: corrupt: cluster %" PRIu32 ": %s", slot,
                        c->generation == 0 ? "generation 0"
                        : c->flags > 3     ? "unknown flags"
                                           : "its breakable is not in the state");
  ld_breakable* b = &s->breakables[c->breakable];
  if (c->leaf_count == 0 || c->leaf_count > b->tree->leaf_count ||
      (uint64_t)c->leaf_count * 4u > bk_bytes_left(r))
    return bk_error_set(err, "state: corrupt: cluster %" PRIu32 " has %" PRIu32 " leaves", slot,
                        c->leaf_count);
  c->leaves = bk_alloc(sizeof(uint32_t) * c->leaf_count);
  for (uint32_t k = 0; k < c->leaf_count; ++k) {
    uint32_t leaf = c->leaves[k] = bk_get_u32(r);
    if (leaf >= b->tree->leaf_count || (k && leaf <= c->leaves[k - 1]) || b->owner[leaf] != UINT32_MAX)
      return bk_error_set(err, "state: corrupt: cluster %" PRIu32 " leaf %" PRIu32 ": %s", slot, leaf,
                          leaf >= b->tree->leaf_count     ? "out of range"
                          : k && leaf <= c->leaves[k - 1] ? "not ascending"
                                                          : "in another cluster too");
    b->owner[leaf] = slot;
  }
  return true;
}

// A u32 list (free slots, split queue): each entry a cluster slot.
static uint32_t* get_slots(bk_byte_reader* r, uint32_t slots, uint32_t* count, const char* what,
                           bk_error* err) {
  *count = bk_get_u32(r);
  if (r->failed || (uint64_t)*count * 4u > bk_bytes_left(r)) {
    bk_error_set(err, "state: corrupt: %s of %" PRIu32 " entries", what, *count);
    *count = 0;
    return NULL;
  }
  uint32_t* list = bk_alloc(sizeof(uint32_t) * (*count + 1u));
  for (uint32_t k = 0; k < *count; ++k)
    if ((list[k] = bk_get_u32(r)) >= slots) {
      bk_error_set(err, "state: corrupt: %s entry %" PRIu32 " is slot %" PRIu32 " of %" PRIu32, what, k,
                   list[k], slots);
      bk_free(list);
      *count = 0;
      return NULL;
    }
  return list;
}

static bool finite_aabb(bk_aabb a) { return bk_v3_is_finite(a.min) && bk_v3_is_finite(a.max); }

static bool get_job(bk_byte_reader* r, ld_state* s, uint32_t k, bk_error* err) {
  ld_job* job = &s->jobs[k];
  job->breakable = bk_get_u32(r);
  job->node = bk_get_u32(r);
  job->due_call = bk_get_u32(r);
  double v[6] = {0};
  for (int a = 0; a < 6; ++a)
    v[a] = bk_get_f64(r);
  job->bounds = (bk_aabb){bk_v3(v[0], v[1], v[2]), bk_v3(v[3], v[4], v[5])};
  job->neighbour_count = bk_get_u32(r);
  if (r->failed) return corrupt_end(r, "refinement", k, err);
  ld_breakable* b = job->breakable < s->breakable_count ? &s->breakables[job->breakable] : NULL;
  if (!b || !b->alive || job->node >= b->tree->node_count || b->tree->nodes[job->node].child_count != 0 ||
      !finite_aabb(job->bounds))
    return bk_error_set(err, "state: corrupt: refinement %" PRIu32 ": %s", k,
                        !b || !b->alive             ? "its breakable is not in the state"
                        : !finite_aabb(job->bounds) ? "bounds not finite"
                                                    : "its node is not a leaf");
  uint32_t leaf = b->tree->nodes[job->node].leaf_begin;
  if (!(b->flags[leaf] & 2))
    return bk_error_set(err, "state: corrupt: refinement %" PRIu32 ": leaf %" PRIu32 " is not marked", k,
                        leaf);
  b->flags[leaf] |= 4; // taken: a second job of the leaf is refused
  if ((uint64_t)job->neighbour_count * 12u > bk_bytes_left(r)) return corrupt_end(r, "refinement", k, err);
  job->neighbour_nodes = bk_alloc(sizeof(uint32_t) * (job->neighbour_count + 1u));
  job->neighbour_areas = bk_alloc(sizeof(double) * (job->neighbour_count + 1u));
  for (uint32_t n = 0; n < job->neighbour_count; ++n) {
    job->neighbour_nodes[n] = bk_get_u32(r);
    job->neighbour_areas[n] = bk_get_f64(r);
    if (job->neighbour_nodes[n] >= b->tree->node_count || !(job->neighbour_areas[n] > 0.0) ||
        !isfinite(job->neighbour_areas[n]))
      return bk_error_set(err, "state: corrupt: refinement %" PRIu32 " neighbour %" PRIu32, k, n);
  }
  job->hit_count = bk_get_u32(r);
  if (r->failed || job->hit_count == 0 || (uint64_t)job->hit_count * 48u > bk_bytes_left(r))
    return bk_error_set(err, "state: corrupt: refinement %" PRIu32 " has %" PRIu32 " hits", k,
                        job->hit_count);
  job->hits = bk_alloc(sizeof(rt_refine_hit) * job->hit_count);
  for (uint32_t h = 0; h < job->hit_count; ++h) {
    rt_refine_hit* hit = &job->hits[h];
    hit->sequence = bk_get_u64(r);
    hit->local.x = bk_get_f64(r);
    hit->local.y = bk_get_f64(r);
    hit->local.z = bk_get_f64(r);
    hit->impulse = bk_get_f64(r);
    hit->frailty = bk_get_f64(r);
    if ((h && hit->sequence <= job->hits[h - 1].sequence) || !bk_v3_is_finite(hit->local) ||
        !(hit->impulse >= 0.0 && isfinite(hit->impulse)) || !(hit->frailty >= 0.0 && isfinite(hit->frailty)))
      return bk_error_set(err, "state: corrupt: refinement %" PRIu32 " hit %" PRIu32, k, h);
  }
  return true;
}

// The whole payload into s, checked.
static bool parse(const bk_runtime* rt, bk_byte_reader* r, ld_state* s, bk_error* err) {
  uint32_t count = bk_get_u32(r);
  if (r->failed) return corrupt_end(r, "the breakables", 0, err);
  if (count != rt->breakable_count)
    return bk_error_set(err, "state: the runtime has %" PRIu32 " breakable slots, the state %" PRIu32,
                        rt->breakable_count, count);
  s->breakables = bk_calloc(count + 1u, sizeof(ld_breakable));
  s->breakable_count = count;
  for (uint32_t i = 0; i < count; ++i)
    if (!get_breakable(rt, r, &s->breakables[i], i, err)) return false;
  count = bk_get_u32(r);
  if (r->failed || (uint64_t)count * 8u > bk_bytes_left(r))
    return bk_error_set(err, "state: corrupt: %" PRIu32 " cluster slots", count);
  s->clusters = bk_calloc(count + 1u, sizeof(ld_cluster));
  s->cluster_count = count;
  uint32_t dead = 0;
  for (uint32_t slot = 0; slot < count; ++slot) {
    if (!get_cluster(r, s, slot, err)) return false;
    dead += !s->clusters[slot].alive;
  }
  // Every removed slot in the free list once: the order slots are reused in.
  if (!(s->free_slots = get_slots(r, count, &s->free_count, "free slot list", err))) return false;
  if (s->free_count != dead)
    return bk_error_set(err, "state: corrupt: %" PRIu32 " free slots listed, %" PRIu32 " removed",
                        s->free_count, dead);
  for (uint32_t k = 0; k < s->free_count; ++k) {
    ld_cluster* c = &s->clusters[s->free_slots[k]];
    if (c->alive || c->flags == 8)
      return bk_error_set(err, "state: corrupt: free slot %" PRIu32 " is live or listed twice",
                          s->free_slots[k]);
    c->flags = 8;
  }
  if (!(s->queue = get_slots(r, count, &s->queue_count, "split queue", err))) return false;
  s->job_count = bk_get_u32(r);
  if (r->failed || (uint64_t)s->job_count * 68u > bk_bytes_left(r))
    return bk_error_set(err, "state: corrupt: %" PRIu32 " refinements", s->job_count);
  s->jobs = bk_calloc(s->job_count + 1u, sizeof(ld_job));
  for (uint32_t k = 0; k < s->job_count; ++k)
    if (!get_job(r, s, k, err)) return false;
  for (uint32_t i = 0; i < s->breakable_count; ++i) {
    const ld_breakable* b = &s->breakables[i];
    for (uint32_t l = 0; b->alive && l < b->tree->leaf_count; ++l)
      if ((b->flags[l] & 2) && !(b->flags[l] & 4))
        return bk_error_set(err,
                            "state: corrupt: breakable %" PRIu32 " leaf %" PRIu32
                            " is marked for refinement without one",
                            i, l);
  }
  for (int k = 0; k < LD_COUNTERS; ++k)
    s->counters[k] = bk_get_u32(r);
  s->hit_sequence = bk_get_u64(r);
  if (r->failed) return corrupt_end(r, "the statistics", 0, err);
  if (r->pos != r->size)
    return bk_error_set(err, "state: corrupt: %zu bytes after the state", r->size - r->pos);
  return true;
}

// The runtime takes the parsed state (nothing can fail from here).
static void install_breakable(rt_breakable* b, ld_breakable* from) {
  rt_breakable_free_tree(b);
  b->tree = b->source;
  if (from->grown.node_count) {
    // Loaded whole: the runtime owns every mesh of it (none is the caller's).
    b->own_tree = bk_alloc(sizeof *b->own_tree);
    *b->own_tree = from->grown;
    memset(&from->grown, 0, sizeof from->grown);
    b->shared_nodes = 0;
    b->tree = b->own_tree;
  }
  memcpy(b->material_name, from->name, sizeof b->material_name);
  b->material = from->material;
  b->material.name = b->material_name;
  const bk_mesh_tree* tree = b->tree;
  rt_breakable_build_adjacency(b);
  uint32_t bonds = tree->bond_count, leaves = tree->leaf_count;
  bk_free(b->bond_hp);
  bk_free(b->bond_broken);
  b->bond_hp = from->hp;
  b->bond_broken = from->broken;
  from->hp = NULL;
  from->broken = NULL;
  b->bond_hp_initial = bk_realloc(b->bond_hp_initial, sizeof(double) * (bonds + 1u));
  for (uint32_t j = 0; j < bonds; ++j)
    b->bond_hp_initial[j] = b->material.bond_strength * tree->bonds[j].area;
  b->leaf_cluster = bk_realloc(b->leaf_cluster, sizeof(uint32_t) * (leaves + 1u));
  b->leaf_anchored = bk_realloc(b->leaf_anchored, leaves + 1u);
  for (uint32_t l = 0; l < leaves; ++l) {
    b->leaf_cluster[l] = UINT32_MAX;
    b->leaf_anchored[l] = from->flags[l] & 1;
  }
  bk_free(b->leaf_refining); // the jobs mark their leaves again
  b->leaf_refining = NULL;
  // The stress stage's per-leaf state is made again at its next solve.
  rt_stress_forget_leaves(b);
}

static void install(bk_runtime* rt, ld_state* s) {
  rt_refine_cancel(rt, UINT32_MAX); // their workers read the trees about to change
  for (uint32_t slot = 0; slot < rt->cluster_count; ++slot) {
    rt_cluster* c = &rt->clusters[slot];
    bk_free(c->leaves);
    bk_free(c->nodes);
    bk_free(c->split_labels);
    rt_stress_release(c);
  }
  for (uint32_t i = 0; i < rt->breakable_count; ++i) {
    rt_breakable* b = &rt->breakables[i];
    if (b->alive)
      install_breakable(b, &s->breakables[i]);
    else
      b->generation = s->breakables[i].generation;
  }
  uint32_t count = s->cluster_count;
  if (count > rt->cluster_capacity) {
    rt->cluster_capacity = count;
    rt->clusters = bk_realloc(rt->clusters, sizeof(rt_cluster) * count);
    rt->free_clusters = bk_realloc(rt->free_clusters, sizeof(uint32_t) * count);
  }
  rt->cluster_count = count;
  rt->live_count = 0;
  for (uint32_t slot = 0; slot < count; ++slot) {
    ld_cluster* from = &s->clusters[slot];
    rt_cluster* c = &rt->clusters[slot];
    memset(c, 0, sizeof *c);
    c->generation = from->generation;
    if (!from->alive) continue;
    c->alive = true;
    c->breakable = from->breakable;
    c->leaves = from->leaves;
    c->leaf_count = from->leaf_count;
    from->leaves = NULL;
    c->user_data = rt->breakables[c->breakable].user_data;
    rt_cluster_finish(rt, slot);
    c->queued = from->flags & 1;
    c->dirty = (from->flags & 2) != 0;
    c->stress_stale = true; // solved again from rest: its warm start was not saved
    rt->live_count++;
  }
  memcpy(rt->free_clusters, s->free_slots, sizeof(uint32_t) * s->free_count);
  rt->free_cluster_count = s->free_count;
  if (s->queue_count > rt->split_queue_capacity) {
    rt->split_queue_capacity = s->queue_count;
    rt->split_queue = bk_realloc(rt->split_queue, sizeof(uint32_t) * s->queue_count);
  }
  if (s->queue_count) memcpy(rt->split_queue, s->queue, sizeof(uint32_t) * s->queue_count);
  rt->split_queue_count = s->queue_count;
  for (uint32_t k = 0; k < s->job_count; ++k) {
    ld_job* job = &s->jobs[k];
    rt_refine_restore(rt, job->breakable, job->node, job->due_call, job->bounds, job->neighbour_nodes,
                      job->neighbour_areas, job->neighbour_count, job->hits, job->hit_count);
    job->hits = NULL; // the runtime's now
  }
  const uint32_t* n = s->counters;
  rt->refine_calls = n[0];
  rt->refine_marked = n[1];
  rt->bonds_broken = n[2];
  rt->splits = n[3];
  rt->stress_bonds_broken = n[4];
  rt->stress_clusters_solved = n[5];
  rt->stress_iterations = n[6];
  rt->stress_cursor = n[7];
  rt->refined_leaves = n[8];
  rt->refine_failed = n[9];
  rt->hit_sequence = s->hit_sequence;
  // The old clusters' events mean nothing now (no created_event points at them).
  rt->created_count = 0;
  rt->removed_count = 0;
  rt->broken_count = 0;
  rt->refined_count = 0;
  rt_refine_start(rt, rt->refine_calls); // the jobs not due yet go to the workers, as after a refine call
}

bool bk_runtime_load_state(bk_runtime* rt, const void* data, size_t size, bk_error* err) {
  if (!rt) return bk_error_set(err, "state: runtime is NULL");
  if (!check_header(data, size, err)) return false;
  bk_byte_reader r = {.data = (const uint8_t*)data + RT_STATE_HEADER_BYTES,
                      .size = size - RT_STATE_HEADER_BYTES};
  ld_state s = {0};
  bool ok = parse(rt, &r, &s, err);
  if (ok) install(rt, &s);
  ld_free(&s);
  return ok;
}
