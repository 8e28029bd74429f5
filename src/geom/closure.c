// Watertightness: every directed edge (by position index) must have exactly
// one opposite edge and be used once.
#include <stdlib.h>

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

bool bk_mesh_is_closed(const bk_mesh* m) {
  bk_closure c = bk_mesh_check_closure(m);
  return m->triangle_count > 0 && c.open_edges == 0 && c.overused_edges == 0 && c.degenerate_edges == 0;
}
