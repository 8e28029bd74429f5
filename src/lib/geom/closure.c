// Watertightness: every directed edge (by position index) must have exactly
// one opposite edge and be used once.
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"

bk_closure bk_mesh_check_closure(const bk_mesh* m) {
  bk_closure result = {0};
  bk_index_map uses = {0};
  bk_index_map_init(&uses, 3u * m->triangle_count);
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      if (a == b) {
        result.degenerate_edges++;
        continue;
      }
      bool inserted = false;
      uint32_t* count = bk_index_map_insert(&uses, bk_directed_edge_key(a, b), 1, &inserted);
      if (!inserted) ++*count;
    }
  }
  for (uint32_t s = 0; s < uses.capacity; ++s) {
    uint64_t key = uses.keys[s];
    if (key == UINT64_MAX) continue;
    uint32_t a = (uint32_t)(key >> 32), b = (uint32_t)key;
    if (uses.values[s] > 1) result.overused_edges += uses.values[s] - 1;
    if (!bk_index_map_find(&uses, bk_directed_edge_key(b, a))) result.open_edges++;
  }
  bk_index_map_free(&uses);
  return result;
}

void bk_topology_scratch_free(bk_topology_scratch* s) {
  bk_free(s->start);
  bk_free(s->mark);
  bk_free(s->from);
  bk_free(s->around);
  memset(s, 0, sizeof *s);
}

void bk_topology_group(bk_topology_scratch* s, const bk_mesh* m) {
  uint32_t half_count = 3u * m->triangle_count;
  if (m->position_count + 1u > s->position_capacity) {
    s->position_capacity = bk_grow_capacity(s->position_capacity, m->position_count + 1u);
    s->start = bk_realloc(s->start, sizeof(uint32_t) * s->position_capacity);
    s->mark = bk_realloc(s->mark, sizeof(uint32_t) * s->position_capacity);
  }
  if (half_count > s->half_capacity) {
    s->half_capacity = bk_grow_capacity(s->half_capacity, half_count);
    s->from = bk_realloc(s->from, sizeof(uint32_t) * s->half_capacity);
    s->around = bk_realloc(s->around, sizeof(uint32_t) * s->half_capacity);
  }
  // Counting sort by start position; each group keeps increasing h.
  uint32_t* start = s->start;
  memset(start, 0, sizeof(uint32_t) * (m->position_count + 1u));
  for (uint32_t h = 0; h < half_count; ++h) {
    s->from[h] = m->corners[m->indices[h]].position;
    start[s->from[h] + 1]++;
  }
  for (uint32_t p = 0; p < m->position_count; ++p)
    start[p + 1] += start[p];
  for (uint32_t h = 0; h < half_count; ++h)
    s->around[start[s->from[h]]++] = h;
  for (uint32_t p = m->position_count; p > 0; --p)
    start[p] = start[p - 1];
  start[0] = 0;
}

bool bk_mesh_is_closed_with(const bk_mesh* m, bk_topology_scratch* s) {
  if (m->triangle_count == 0) return false;
  bk_topology_group(s, m);
  // Per position b: mark where its half-edges go (a second one to the same
  // place is an overused edge), then every half-edge arriving at b (the one
  // before each leaving b in its triangle) must find its opposite marked.
  memset(s->mark, 0xff, sizeof(uint32_t) * m->position_count);
  for (uint32_t b = 0; b < m->position_count; ++b) {
    for (uint32_t i = s->start[b]; i < s->start[b + 1]; ++i) {
      uint32_t h = s->around[i], x = s->from[bk_half_next(h)];
      if (x == b || s->mark[x] == b) return false;
      s->mark[x] = b;
    }
    for (uint32_t i = s->start[b]; i < s->start[b + 1]; ++i)
      if (s->mark[s->from[bk_half_prev(s->around[i])]] != b) return false;
  }
  return true;
}

bool bk_mesh_is_closed(const bk_mesh* m) {
  bk_topology_scratch scratch = {0};
  bool closed = bk_mesh_is_closed_with(m, &scratch);
  bk_topology_scratch_free(&scratch);
  return closed;
}
