// The runtime's state hash (bk_runtime_state_hash): XXH3 over the
// destruction state, written field by field in a fixed order and little
// endian (never a struct's bytes: padding is not state), so the same calls
// give the same hash on any machine and compiler that computes the same
// doubles. A double is hashed by its bits, with -0 as +0. The bytes are
// gathered in a buffer from the library's allocator (XXH3's streaming state
// would allocate on its own).
#include <string.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "runtime_internal.h"

typedef struct hasher {
  uint8_t* bytes;
  size_t count, capacity;
} hasher;

static void put_u32(hasher* h, uint32_t v) {
  if (h->count + 4 > h->capacity) {
    h->capacity = h->capacity ? 2 * h->capacity : 4096;
    h->bytes = bk_realloc(h->bytes, h->capacity);
  }
  uint8_t* b = h->bytes + h->count;
  b[0] = (uint8_t)v, b[1] = (uint8_t)(v >> 8), b[2] = (uint8_t)(v >> 16), b[3] = (uint8_t)(v >> 24);
  h->count += 4;
}

static void put_u64(hasher* h, uint64_t v) {
  put_u32(h, (uint32_t)v);
  put_u32(h, (uint32_t)(v >> 32));
}

static void put_double(hasher* h, double d) {
  uint64_t bits = 0;
  if (d == 0.0) d = 0.0; // -0 is +0
  memcpy(&bits, &d, sizeof bits);
  put_u64(h, bits);
}

static void put_vec3(hasher* h, bk_vec3 v) {
  put_double(h, v.x);
  put_double(h, v.y);
  put_double(h, v.z);
}

// A tree's shape and bonds (a refined breakable's grows): what the
// clusters' leaves and the bonds' indices mean.
static void put_tree(hasher* h, const bk_mesh_tree* t) {
  put_u64(h, t->source_hash);
  put_u32(h, t->node_count);
  put_u32(h, t->leaf_count);
  put_u32(h, t->bond_count);
  for (uint32_t i = 0; i < t->node_count; ++i) {
    const bk_mesh_tree_node* n = &t->nodes[i];
    put_u32(h, n->parent);
    put_u32(h, n->leaf_begin);
    put_u32(h, n->leaf_end);
    put_double(h, n->moments.v);
  }
  for (uint32_t j = 0; j < t->bond_count; ++j) {
    put_u32(h, t->bonds[j].leaf_a);
    put_u32(h, t->bonds[j].leaf_b);
    put_double(h, t->bonds[j].area);
  }
}

uint64_t bk_runtime_state_hash(const bk_runtime* rt) {
  hasher buffer = {0};
  hasher* h = &buffer;
  put_u32(h, rt->breakable_count);
  for (uint32_t i = 0; i < rt->breakable_count; ++i) {
    const rt_breakable* b = &rt->breakables[i];
    put_u32(h, b->alive);
    put_u32(h, b->generation);
    if (!b->alive) continue;
    put_tree(h, b->tree);
    const bk_material* m = &b->material;
    put_double(h, m->density);
    put_double(h, m->frailty);
    put_double(h, m->bond_strength);
    put_u32(h, m->accumulate);
    put_double(h, m->refine_strength);
    for (uint32_t j = 0; j < b->tree->bond_count; ++j) {
      put_u32(h, b->bond_broken[j]);
      put_double(h, b->bond_broken[j] ? 0.0 : b->bond_hp[j]);
    }
    for (uint32_t l = 0; l < b->tree->leaf_count; ++l)
      put_u32(h, (uint32_t)b->leaf_anchored[l] | (b->leaf_refining && b->leaf_refining[l] ? 2u : 0u));
  }
  put_u32(h, rt->cluster_count);
  for (uint32_t s = 0; s < rt->cluster_count; ++s) {
    const rt_cluster* c = &rt->clusters[s];
    put_u32(h, c->alive);
    put_u32(h, c->generation);
    if (!c->alive) continue;
    put_u32(h, c->breakable);
    put_u32(h, c->is_static);
    put_u32(h, c->queued);
    put_u32(h, c->leaf_count);
    for (uint32_t k = 0; k < c->leaf_count; ++k)
      put_u32(h, c->leaves[k]);
  }
  // Work waiting: splits in order, refinements with their hits.
  put_u32(h, rt->split_queue_count);
  for (uint32_t q = 0; q < rt->split_queue_count; ++q)
    put_u32(h, rt->split_queue[q]);
  put_u32(h, rt->refine_job_count);
  for (uint32_t k = 0; k < rt->refine_job_count; ++k) {
    const rt_refine_job* job = rt->refine_jobs[k];
    put_u32(h, job->breakable);
    put_u32(h, job->node);
    put_u32(h, job->due_call);
    put_u32(h, job->hit_count);
    for (uint32_t x = 0; x < job->hit_count; ++x) {
      put_vec3(h, job->hits[x].local);
      put_double(h, job->hits[x].impulse);
    }
  }
  put_u32(h, rt->refine_calls);
  put_u32(h, rt->bonds_broken);
  uint64_t hash = XXH3_64bits(h->bytes, h->count);
  bk_free(h->bytes);
  return hash;
}
