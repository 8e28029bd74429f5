// Shells that touch at a vertex or along an edge, split apart there. Around an
// edge used by more than two triangles, the triangles are ordered by angle
// and each is paired with the neighbour that closes the solid between them;
// then the triangle corners at each position are grouped into fans joined
// by paired edges, and every fan after the first gets its own copy of the
// position. Two closed cubes sharing an edge or a corner become two closed
// cubes with their own positions; so do two cubes sharing a whole face
// (the importer welds coincident positions, so cubes modelled apart arrive
// with the face's two opposite copies on the same positions): each keeps its
// own copy of the face, and the fracture treats them as touching shells.
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

typedef struct half_edge {
  uint64_t key;  // undirected edge
  uint32_t slot; // 3 * triangle + k: the edge from corner k to corner k + 1
} half_edge;

static int compare_half_edges(const void* a, const void* b) {
  const half_edge *x = a, *y = b;
  if (x->key != y->key) return x->key < y->key ? -1 : 1;
  return x->slot < y->slot ? -1 : x->slot > y->slot;
}

static uint32_t find_root(uint32_t* parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

static void unite(uint32_t* parent, uint32_t a, uint32_t b) {
  a = find_root(parent, a), b = find_root(parent, b);
  if (a != b) parent[a > b ? a : b] = a < b ? a : b;
}

// Joins the corners of two triangles that meet along an edge running
// a -> b in slot s and b -> a in slot o (same positions at both ends).
static void join_edge(const bk_mesh* m, uint32_t* parent, uint32_t s, uint32_t o) {
  uint32_t ts = s / 3, ks = s % 3, to = o / 3, ko = o % 3;
  // s runs corner ks -> ks+1, o runs corner ko -> ko+1 in the other direction.
  (void)m;
  unite(parent, 3 * ts + ks, 3 * to + (ko + 1) % 3);
  unite(parent, 3 * ts + (ks + 1) % 3, 3 * to + ko);
}

typedef struct around {
  double angle;
  uint32_t slot;
  bool forward; // runs lo -> hi
} around;

static int compare_around(const void* a, const void* b) {
  const around *x = a, *y = b;
  if (x->angle != y->angle) return x->angle < y->angle ? -1 : 1;
  return x->slot < y->slot ? -1 : x->slot > y->slot;
}

// Triangles around an edge closer in angle than this (radians) lie in one
// half-plane: coincident up to rounding in their third corners.
#define COINCIDENT_ANGLE 1e-9
#define PI 3.14159265358979323846

// How far `after`, the next triangle round the edge, turns past `before`:
// in the sorted list only the step from the last back to the first is
// negative, and it goes once round.
static double angle_gap(const around* before, const around* after) {
  double gap = after->angle - before->angle;
  return gap < 0.0 ? gap + 2.0 * PI : gap;
}

static void reverse_around(around* a, uint32_t begin, uint32_t end) {
  for (; begin + 1 < end; ++begin, --end) {
    around swap = a[begin];
    a[begin] = a[end - 1];
    a[end - 1] = swap;
  }
}

// Two solids touching along a face both have a triangle in the same
// half-plane about the edge, facing opposite ways; a forward triangle's solid
// lies below its angle and a backward one's above. So in each run of
// coincident triangles the forward ones go first, and each pairs with the
// triangle of its own solid, not with its opposite copy (a solid of no
// thickness). On entry the list is sorted by angle (then slot); it is
// circular, so it is first rotated to start after a gap, which keeps every
// run in one piece.
static void order_coincident(around* a, uint32_t count) {
  uint32_t start = count;
  for (uint32_t i = 0; i < count && start == count; ++i)
    if (angle_gap(&a[(i + count - 1) % count], &a[i]) > COINCIDENT_ANGLE) start = i;
  if (start == count) return; // all in one half-plane: no order pairs them sensibly
  reverse_around(a, 0, start);
  reverse_around(a, start, count);
  reverse_around(a, 0, count);
  for (uint32_t begin = 0; begin < count;) {
    uint32_t end = begin + 1;
    while (end < count && angle_gap(&a[end - 1], &a[end]) <= COINCIDENT_ANGLE)
      ++end;
    // Forward ones first, each kind in its sorted order.
    for (uint32_t i = begin + 1; i < end; ++i)
      for (uint32_t j = i; j > begin && a[j].forward && !a[j - 1].forward; --j) {
        around swap = a[j];
        a[j] = a[j - 1];
        a[j - 1] = swap;
      }
    begin = end;
  }
}

// Pairs the triangles around one edge used more than twice: by angle about
// the edge, a triangle running lo -> hi has its solid on its lower-angle side
// and pairs with the triangle just below it, which must run hi -> lo.
static void pair_fan(const bk_mesh* m, uint32_t* parent, const half_edge* edges, uint32_t count,
                     around* scratch) {
  uint32_t lo = (uint32_t)(edges[0].key >> 32), hi = (uint32_t)edges[0].key;
  bk_vec3 a = m->positions[lo], b = m->positions[hi];
  bk_vec3 axis = bk_v3_normalize(bk_v3_sub(b, a));
  bk_vec3 u, v;
  bk_plane_basis(axis, &u, &v);
  // Angles are measured right-handed about the axis (u x v = axis), or the
  // solid would lie above a forward triangle instead.
  double turn = bk_v3_dot(bk_v3_cross(u, v), axis) > 0.0 ? 1.0 : -1.0;
  uint32_t forward = 0;
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t slot = edges[i].slot, t = slot / 3, k = slot % 3;
    uint32_t from = bk_mesh_tri_position(m, t, k);
    bk_vec3 c = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, (k + 2) % 3)], a);
    scratch[i] = (around){turn * bk_atan2(bk_v3_dot(c, v), bk_v3_dot(c, u)), slot, from == lo};
    forward += from == lo;
  }
  if (2 * forward != count) return; // unbalanced: leave it unpaired (open or overused)
  bk_sort(scratch, count, sizeof *scratch, compare_around);
  order_coincident(scratch, count);
  for (uint32_t i = 0; i < count; ++i) {
    if (!scratch[i].forward) continue;
    if (scratch[(i + count - 1) % count].forward) return; // not alternating: shells cross here, leave it
  }
  for (uint32_t i = 0; i < count; ++i) {
    if (!scratch[i].forward) continue;
    join_edge(m, parent, scratch[i].slot, scratch[(i + count - 1) % count].slot);
  }
}

uint32_t bk_mesh_split_nonmanifold(bk_mesh* m) {
  uint32_t slots = 3u * m->triangle_count;
  if (slots == 0) return 0;
  half_edge* edges = bk_alloc(sizeof(half_edge) * slots);
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (uint32_t k = 0; k < 3; ++k)
      edges[3 * t + k] = (half_edge){
          bk_edge_key(bk_mesh_tri_position(m, t, k), bk_mesh_tri_position(m, t, (k + 1) % 3)), 3 * t + k};
  bk_sort(edges, slots, sizeof *edges, compare_half_edges);
  // Union-find over triangle corners (slots): one class per fan at a position.
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * slots);
  for (uint32_t i = 0; i < slots; ++i)
    parent[i] = i;
  around* scratch = NULL;
  uint32_t scratch_capacity = 0;
  for (uint32_t i = 0; i < slots;) {
    uint32_t j = i;
    while (j < slots && edges[j].key == edges[i].key)
      ++j;
    uint32_t count = j - i;
    if (count == 2) {
      uint32_t s = edges[i].slot, o = edges[i + 1].slot;
      uint32_t s_from = bk_mesh_tri_position(m, s / 3, s % 3), o_from = bk_mesh_tri_position(m, o / 3, o % 3);
      if (s_from != o_from) join_edge(m, parent, s, o); // opposite directions: a manifold edge
    } else if (count > 2) {
      if (count > scratch_capacity) {
        scratch_capacity = bk_grow_capacity(scratch_capacity, count);
        scratch = bk_realloc(scratch, sizeof(around) * scratch_capacity);
      }
      pair_fan(m, parent, edges + i, count, scratch);
    }
    i = j;
  }
  bk_free(edges);
  bk_free(scratch);

  // The first fan at a position keeps it; later fans get copies. A corner
  // shared by triangles of different fans is copied too.
  uint32_t* fan_position = bk_alloc(sizeof(uint32_t) * slots);
  memset(fan_position, 0xff, sizeof(uint32_t) * slots);
  uint8_t* position_taken = bk_calloc(m->position_count + 1u, 1);
  bk_index_map corner_copies = {0};
  bk_index_map_init(&corner_copies, 0);
  uint32_t original_positions = m->position_count, added = 0;
  for (uint32_t slot = 0; slot < slots; ++slot) {
    uint32_t root = find_root(parent, slot);
    uint32_t corner = m->indices[slot];
    uint32_t position = m->corners[corner].position;
    if (fan_position[root] == UINT32_MAX) {
      if (!position_taken[position]) {
        position_taken[position] = 1;
        fan_position[root] = position;
      } else {
        fan_position[root] = bk_mesh_add_position(m, m->positions[position]);
        added++;
      }
    }
    uint32_t target = fan_position[root];
    if (target == position) continue;
    bool inserted = false;
    uint32_t* copy =
        bk_index_map_insert(&corner_copies, ((uint64_t)corner << 32) | target, m->corner_count, &inserted);
    if (inserted) {
      bk_corner c = m->corners[corner];
      c.position = target;
      bk_mesh_add_corner(m, &c);
    }
    m->indices[slot] = *copy;
  }
  (void)original_positions;
  bk_index_map_free(&corner_copies);
  bk_free(position_taken);
  bk_free(fan_position);
  bk_free(parent);
  return added;
}
