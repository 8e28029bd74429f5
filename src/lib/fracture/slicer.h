// Internal: the slicer's state, shared by slice.c (classifying and
// splitting triangles) and slice_cap.c (closing each side with its cap).
#pragma once

#include "cap.h"

enum { BK_SLICE_BELOW = 0, BK_SLICE_ABOVE = 1 };
#define BK_SLICE_NONE UINT32_MAX

struct bk_slicer {
  bk_cap* cap;
  bk_cap_noise noise;     // a noisy cap (meshed at the noise resolution, pushed)
  bk_vec3* noise_normals; // per noisy cap point
  uint32_t noise_normal_capacity;
  // Per source position / corner (grown on demand).
  double* dist;
  int8_t* cls; // -1 below, 0 on the plane, +1 above
  uint32_t* pos_map[2];
  uint32_t* corner_map[2];
  uint32_t position_capacity, corner_capacity;
  // Cut vertices, numbered after the source positions ("global ids"), each
  // on the chain of its edge's lower position (corner) index.
  uint32_t* cut_position_head; // per source position: first cut position of an edge it is the lower end of
  uint32_t* cut_corner_head;   // per source corner: the same for cut corners
  bk_vec3* cut_positions;
  uint32_t* cut_pos_map[2];
  uint32_t* cut_position_end;  // the edge's higher position
  uint32_t* cut_position_next; // the chain
  uint32_t cut_position_count, cut_position_capacity;
  bk_corner* cut_corners; // .position holds the global position id
  uint32_t* cut_corner_map[2];
  uint32_t* cut_corner_end;
  uint32_t* cut_corner_next;
  uint32_t cut_corner_count, cut_corner_capacity;
  // Directed edges with both ends on the plane, per side (global ids).
  uint64_t* plane_edges[2];
  uint8_t* plane_edge_source[2]; // the source material of the triangle each plane edge came from
  uint32_t plane_edge_count[2], plane_edge_capacity[2];
  // Per global id: an edge chain's head (edges by start vertex), and the local id.
  uint32_t* edge_head;
  uint32_t* edge_next; // per plane or cap edge
  uint32_t* local_of_global;
  uint32_t global_capacity, edge_next_capacity;
  // Cap input and output scratch.
  uint32_t* cap_edges[2];
  uint8_t* cap_edge_source[2]; // per cap edge (not per id pair)
  uint32_t cap_edge_count[2], cap_edge_capacity[2];
  uint32_t* global_of_local;
  uint8_t* source_of_local; // the source material of a cap edge leaving each local vertex
  double* xy;
  uint32_t local_capacity;
};

// bk_mesh_add_* without the call when there is room (outputs are reused
// between slices, so there nearly always is).
static inline uint32_t bk_slicer_add_position(bk_mesh* m, bk_vec3 p) {
  if (m->position_count == m->position_capacity) return bk_mesh_add_position(m, p);
  m->positions[m->position_count] = p;
  return m->position_count++;
}

static inline uint32_t bk_slicer_add_corner(bk_mesh* m, const bk_corner* c) {
  if (m->corner_count == m->corner_capacity) return bk_mesh_add_corner(m, c);
  m->corners[m->corner_count] = *c;
  return m->corner_count++;
}

static inline void bk_slicer_add_triangle(bk_mesh* m, uint32_t a, uint32_t b, uint32_t c, uint8_t material,
                                          uint32_t tag) {
  if (m->triangle_count == m->triangle_capacity) {
    bk_mesh_add_triangle(m, a, b, c, material, tag);
    return;
  }
  uint32_t t = m->triangle_count++;
  m->indices[3 * t + 0] = a;
  m->indices[3 * t + 1] = b;
  m->indices[3 * t + 2] = c;
  m->materials[t] = material;
  m->tags[t] = tag;
}

/// The side's position for a global id (source positions first, then cut
/// positions), added to `out` on first use. Here, beside the other adders,
/// because both the slicing and the caps take positions through it.
static inline uint32_t bk_slicer_side_position(bk_slicer* s, const bk_mesh* m, bk_mesh* out, int side,
                                               uint32_t global) {
  uint32_t* slot = global < m->position_count ? &s->pos_map[side][global]
                                              : &s->cut_pos_map[side][global - m->position_count];
  if (*slot == UINT32_MAX) {
    bk_vec3 p =
        global < m->position_count ? m->positions[global] : s->cut_positions[global - m->position_count];
    *slot = bk_slicer_add_position(out, p);
  }
  return *slot;
}

/// Closes both sides of a split mesh with their caps (the plane edges
/// emit gathered); false (both sides freed) when a cap cannot be closed.
bool bk_slicer_close(bk_slicer* s, const bk_mesh* m, const bk_slice_def* desc, bk_mesh* out[2],
                     const double deepest[2], double texture_scale, bk_error* err);
