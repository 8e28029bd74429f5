// Merging the pieces of one split down to a count. A cut through a concave
// piece, or through a piece made of separate shells, gives more than two
// pieces; when that is more than the tree may still take, some are merged so
// that it ends with exactly the pieces asked for. Merging only joins closed
// shells (bk_mesh_append), so a merged piece is still closed and its moments
// are the sum of its parts'.
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

// Bounds of a piece's cap triangles of one cut; empty (min > max) when it
// has none there or when cap_tag is 0 (no cut made the pieces).
static bk_aabb cap_bounds(const bk_mesh* m, uint32_t cap_tag) {
  bk_aabb box = {bk_v3(INFINITY, INFINITY, INFINITY), bk_v3(-INFINITY, -INFINITY, -INFINITY)};
  if (cap_tag == 0) return box;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    if (m->tags[t] != cap_tag) continue;
    for (uint32_t k = 0; k < 3; ++k) {
      bk_vec3 p = m->positions[bk_mesh_tri_position(m, t, k)];
      box.min = bk_v3_min(box.min, p);
      box.max = bk_v3_max(box.max, p);
    }
  }
  return box;
}

// Closed boxes: caps of opposite sides that meet share their cut vertices'
// exact coordinates, so touching needs no tolerance. An empty box touches nothing.
static bool boxes_touch(bk_aabb a, bk_aabb b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

static bk_vec3 centroid_of(bk_moments m) { return bk_v3(m.x / m.v, m.y / m.v, m.z / m.v); }

// How far piece `to` is from piece `from` as a merge partner: first the
// class (0: same side of the cut; 1: other side with caps that meet, so the
// merged piece is one connected chunk; 2: other side, apart), then the
// squared centroid distance. Lower is nearer.
typedef struct partner_rank {
  int side_class;
  double distance2;
} partner_rank;

static bool rank_less(partner_rank a, partner_rank b) {
  if (a.side_class != b.side_class) return a.side_class < b.side_class;
  return a.distance2 < b.distance2;
}

uint32_t bk_merge_pieces(bk_mesh* pieces, bk_moments* moments, uint32_t count, uint32_t below_count,
                         uint32_t cap_tag, uint32_t target) {
  if (target == 0 || count <= target) return count;
  uint8_t* above = bk_alloc(count);
  bk_aabb* caps = bk_alloc(sizeof(bk_aabb) * count);
  for (uint32_t i = 0; i < count; ++i) {
    above[i] = i >= below_count;
    caps[i] = cap_bounds(&pieces[i], cap_tag);
  }
  while (count > target) {
    // The smallest piece moves (ties: the lower index), so the pieces the
    // cut made stay as even in size as they can.
    uint32_t smallest = 0;
    for (uint32_t i = 1; i < count; ++i)
      if (moments[i].v < moments[smallest].v) smallest = i;
    bk_vec3 from = centroid_of(moments[smallest]);
    uint32_t partner = UINT32_MAX;
    partner_rank best = {3, INFINITY};
    for (uint32_t j = 0; j < count; ++j) {
      if (j == smallest) continue;
      bk_vec3 d = bk_v3_sub(centroid_of(moments[j]), from);
      partner_rank r = {above[j] == above[smallest] ? 0 : (boxes_touch(caps[j], caps[smallest]) ? 1 : 2),
                        bk_v3_dot(d, d)};
      if (partner == UINT32_MAX || rank_less(r, best)) partner = j, best = r; // ties: the lower index
    }
    bk_mesh_append(&pieces[partner], &pieces[smallest]);
    moments[partner] = bk_moments_add(moments[partner], moments[smallest]);
    caps[partner].min = bk_v3_min(caps[partner].min, caps[smallest].min);
    caps[partner].max = bk_v3_max(caps[partner].max, caps[smallest].max);
    bk_mesh_free(&pieces[smallest]);
    // Close the gap keeping the others' order, so the result depends only on the input.
    uint32_t after = count - smallest - 1;
    memmove(&pieces[smallest], &pieces[smallest + 1], sizeof(bk_mesh) * after);
    memmove(&moments[smallest], &moments[smallest + 1], sizeof(bk_moments) * after);
    memmove(&above[smallest], &above[smallest + 1], after);
    memmove(&caps[smallest], &caps[smallest + 1], sizeof(bk_aabb) * after);
    count--;
  }
  bk_free(above);
  bk_free(caps);
  return count;
}
