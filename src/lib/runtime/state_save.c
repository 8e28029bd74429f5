// Saving the destruction state (bk_runtime_save_state): what the state hash
// covers, field by field (state_format.h), plus what the hash covers only
// through its effects: a refined breakable's grown tree as .mtree bytes, the
// waiting refinements' neighbours and bounds, the free cluster slots in the
// order they are reused, and the statistics. The stress solver's warm start
// is left out: a loaded runtime solves its clusters again from rest.
#include <inttypes.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "runtime_internal.h"
#include "state_format.h"

static void put_material(bk_byte_writer* w, const bk_material* m) {
  const char* name = m->name ? m->name : "";
  uint32_t length = (uint32_t)strlen(name);
  bk_put_u32(w, length);
  bk_put_bytes(w, name, length);
  bk_put_f64(w, m->density);
  bk_put_f64(w, m->frailty);
  bk_put_f64(w, m->bond_strength);
  bk_put_u32(w, m->accumulate);
  bk_put_f64(w, m->friction);
  bk_put_f64(w, m->restitution);
  bk_put_f64(w, m->compression_limit);
  bk_put_f64(w, m->tension_limit);
  bk_put_f64(w, m->shear_limit);
  bk_put_f64(w, m->refine_strength);
}

static bool put_breakable(bk_byte_writer* w, const rt_breakable* b, uint32_t index, bk_error* err) {
  bk_put_u32(w, b->alive);
  bk_put_u32(w, b->generation);
  if (!b->alive) return true;
  const bk_mesh_tree* source = b->source;
  bk_put_u64(w, source->source_hash);
  bk_put_u32(w, source->node_count);
  bk_put_u32(w, source->leaf_count);
  bk_put_u32(w, source->bond_count);
  put_material(w, &b->material);
  if (b->own_tree) {
    uint8_t* bytes = NULL;
    size_t size = 0;
    char name[48] = {0};
    snprintf(name, sizeof name, "state: breakable %" PRIu32 "'s refined tree", index);
    if (!bk_mesh_tree_save_memory(b->own_tree, name, &bytes, &size, err)) return false;
    bk_put_u64(w, size);
    bk_put_bytes(w, bytes, size);
    bk_free(bytes);
  } else {
    bk_put_u64(w, 0);
  }
  const bk_mesh_tree* tree = b->tree;
  for (uint32_t j = 0; j < tree->bond_count; ++j) {
    uint8_t broken = b->bond_broken[j];
    bk_put_bytes(w, &broken, 1);
    bk_put_f64(w, broken ? 0.0 : b->bond_hp[j]); // a broken bond's is never read
  }
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    uint8_t flags =
        (uint8_t)((b->leaf_anchored[l] ? 1u : 0u) | (b->leaf_refining && b->leaf_refining[l] ? 2u : 0u));
    bk_put_bytes(w, &flags, 1);
  }
  return true;
}

static void put_job(bk_byte_writer* w, const rt_refine_job* job) {
  bk_put_u32(w, job->breakable);
  bk_put_u32(w, job->node);
  bk_put_u32(w, job->due_call);
  const bk_aabb* bounds = &job->tree_bounds;
  bk_put_f64(w, bounds->min.x);
  bk_put_f64(w, bounds->min.y);
  bk_put_f64(w, bounds->min.z);
  bk_put_f64(w, bounds->max.x);
  bk_put_f64(w, bounds->max.y);
  bk_put_f64(w, bounds->max.z);
  bk_put_u32(w, job->neighbour_count);
  for (uint32_t k = 0; k < job->neighbour_count; ++k) {
    bk_put_u32(w, job->neighbours[k].node);
    bk_put_f64(w, job->neighbours[k].bond_area);
  }
  bk_put_u32(w, job->hit_count);
  for (uint32_t h = 0; h < job->hit_count; ++h) {
    const rt_refine_hit* hit = &job->hits[h];
    bk_put_u64(w, hit->sequence);
    bk_put_f64(w, hit->local.x);
    bk_put_f64(w, hit->local.y);
    bk_put_f64(w, hit->local.z);
    bk_put_f64(w, hit->impulse);
    bk_put_f64(w, hit->frailty);
  }
}

// The whole state, header first; what did not fit in the capacity is only
// counted (w->size is the state's size either way).
static bool put_state(const bk_runtime* rt, bk_byte_writer* w, bk_error* err) {
  uint8_t header[RT_STATE_HEADER_BYTES] = {0};
  bk_put_bytes(w, header, sizeof header); // filled once the payload is known
  bk_put_u32(w, rt->breakable_count);
  for (uint32_t i = 0; i < rt->breakable_count; ++i)
    if (!put_breakable(w, &rt->breakables[i], i, err)) return false;
  bk_put_u32(w, rt->cluster_count);
  for (uint32_t s = 0; s < rt->cluster_count; ++s) {
    const rt_cluster* c = &rt->clusters[s];
    bk_put_u32(w, c->alive);
    bk_put_u32(w, c->generation);
    if (!c->alive) continue;
    bk_put_u32(w, c->breakable);
    bk_put_u32(w, (c->queued ? 1u : 0u) | (c->dirty ? 2u : 0u));
    bk_put_u32(w, c->leaf_count);
    for (uint32_t k = 0; k < c->leaf_count; ++k)
      bk_put_u32(w, c->leaves[k]);
  }
  bk_put_u32(w, rt->free_cluster_count);
  for (uint32_t k = 0; k < rt->free_cluster_count; ++k)
    bk_put_u32(w, rt->free_clusters[k]);
  bk_put_u32(w, rt->split_queue_count);
  for (uint32_t q = 0; q < rt->split_queue_count; ++q)
    bk_put_u32(w, rt->split_queue[q]);
  bk_put_u32(w, rt->refine_job_count);
  for (uint32_t k = 0; k < rt->refine_job_count; ++k)
    put_job(w, rt->refine_jobs[k]);
  const uint32_t counters[] = {
      rt->refine_calls,        rt->refine_marked,          rt->bonds_broken,      rt->splits,
      rt->stress_bonds_broken, rt->stress_clusters_solved, rt->stress_iterations, rt->stress_cursor,
      rt->refined_leaves,      rt->refine_failed};
  for (size_t k = 0; k < sizeof counters / sizeof counters[0]; ++k)
    bk_put_u32(w, counters[k]);
  bk_put_u64(w, rt->hit_sequence);
  if (w->size > w->capacity) return true;
  // The header, over the payload as written.
  bk_byte_writer h = {.out = w->out, .capacity = RT_STATE_HEADER_BYTES};
  bk_put_bytes(&h, rt_state_magic, sizeof rt_state_magic);
  bk_put_u32(&h, RT_STATE_VERSION);
  bk_put_u32(&h, RT_STATE_ENDIAN_MARKER);
  size_t payload = w->size - RT_STATE_HEADER_BYTES;
  bk_put_u64(&h, payload);
  bk_put_u64(&h, XXH3_64bits(w->out + RT_STATE_HEADER_BYTES, payload));
  return true;
}

size_t bk_runtime_state_size(const bk_runtime* rt) {
  bk_byte_writer w = {0};
  return put_state(rt, &w, NULL) ? w.size : 0;
}

size_t bk_runtime_save_state(const bk_runtime* rt, void* out, size_t capacity, bk_error* err) {
  if (!out && capacity) return bk_error_set(err, "state: out is NULL"), 0;
  bk_byte_writer w = {.out = out, .capacity = out ? capacity : 0};
  if (!put_state(rt, &w, err)) return 0;
  if (w.size > w.capacity)
    return bk_error_set(err, "state: buffer of %zu bytes is too small, the state needs %zu", capacity,
                        w.size),
           0;
  return w.size;
}
