// Plane slicing of a closed mesh. Positions are classified once; a cut edge
// gets exactly one new position shared by both sides (looked up by the index
// pair, never by comparing coordinates), so each side's open boundary is a
// set of index loops that the cap closes exactly. Index pairs are looked up
// in short chains hung on their lower index (a vertex has a few neighbours),
// not hashed.
#include <stdlib.h>
#include <string.h>

#include "slicer.h"

bk_slicer* bk_slicer_create(void) {
  bk_slicer* s = bk_calloc(1, sizeof *s);
  s->cap = bk_cap_create();
  if (!s->cap) {
    bk_free(s);
    return NULL;
  }
  return s;
}

void bk_slicer_destroy(bk_slicer* s) {
  if (!s) return;
  bk_cap_destroy(s->cap);
  bk_cap_noise_free(&s->noise);
  bk_free(s->noise_normals);
  bk_free(s->dist);
  bk_free(s->cls);
  for (int k = 0; k < 2; ++k) {
    bk_free(s->pos_map[k]);
    bk_free(s->corner_map[k]);
    bk_free(s->cut_pos_map[k]);
    bk_free(s->cut_corner_map[k]);
    bk_free(s->plane_edges[k]);
    bk_free(s->plane_edge_source[k]);
    bk_free(s->cap_edges[k]);
    bk_free(s->cap_edge_source[k]);
  }
  bk_free(s->cut_position_head);
  bk_free(s->cut_corner_head);
  bk_free(s->cut_positions);
  bk_free(s->cut_position_end);
  bk_free(s->cut_position_next);
  bk_free(s->cut_corners);
  bk_free(s->cut_corner_end);
  bk_free(s->cut_corner_next);
  bk_free(s->edge_head);
  bk_free(s->edge_next);
  bk_free(s->local_of_global);
  bk_free(s->global_of_local);
  bk_free(s->source_of_local);
  bk_free(s->xy);
  bk_free(s);
}

static void reserve_source(bk_slicer* s, const bk_mesh* m) {
  if (m->position_count > s->position_capacity) {
    s->position_capacity = bk_grow_capacity(s->position_capacity, m->position_count);
    s->dist = bk_realloc(s->dist, sizeof(double) * s->position_capacity);
    s->cls = bk_realloc(s->cls, s->position_capacity);
    s->cut_position_head = bk_realloc(s->cut_position_head, sizeof(uint32_t) * s->position_capacity);
    for (int k = 0; k < 2; ++k)
      s->pos_map[k] = bk_realloc(s->pos_map[k], sizeof(uint32_t) * s->position_capacity);
  }
  if (m->corner_count > s->corner_capacity) {
    s->corner_capacity = bk_grow_capacity(s->corner_capacity, m->corner_count);
    s->cut_corner_head = bk_realloc(s->cut_corner_head, sizeof(uint32_t) * s->corner_capacity);
    for (int k = 0; k < 2; ++k)
      s->corner_map[k] = bk_realloc(s->corner_map[k], sizeof(uint32_t) * s->corner_capacity);
  }
  for (int k = 0; k < 2; ++k) {
    memset(s->pos_map[k], 0xff, sizeof(uint32_t) * m->position_count);
    memset(s->corner_map[k], 0xff, sizeof(uint32_t) * m->corner_count);
  }
  memset(s->cut_position_head, 0xff, sizeof(uint32_t) * m->position_count);
  memset(s->cut_corner_head, 0xff, sizeof(uint32_t) * m->corner_count);
  s->cut_position_count = 0;
  s->cut_corner_count = 0;
  s->plane_edge_count[0] = s->plane_edge_count[1] = 0;
}

// Global corner id: source corners first, then cut corners.
static uint32_t side_corner(bk_slicer* s, const bk_mesh* m, bk_mesh* out, int side, uint32_t global) {
  bool source = global < m->corner_count;
  uint32_t* slot = source ? &s->corner_map[side][global] : &s->cut_corner_map[side][global - m->corner_count];
  if (*slot == UINT32_MAX) {
    bk_corner c = source ? m->corners[global] : s->cut_corners[global - m->corner_count];
    c.position = bk_slicer_side_position(s, m, out, side, c.position);
    *slot = bk_slicer_add_corner(out, &c);
  }
  return *slot;
}

static uint32_t global_position_of_corner(const bk_slicer* s, const bk_mesh* m, uint32_t global_corner) {
  return global_corner < m->corner_count ? m->corners[global_corner].position
                                         : s->cut_corners[global_corner - m->corner_count].position;
}

static bool on_plane(const bk_slicer* s, const bk_mesh* m, uint32_t global_position) {
  return global_position >= m->position_count || s->cls[global_position] == 0;
}

static void push_plane_edge(bk_slicer* s, int side, uint32_t a, uint32_t b, uint8_t material) {
  if (s->plane_edge_count[side] == s->plane_edge_capacity[side]) {
    s->plane_edge_capacity[side] =
        bk_grow_capacity(s->plane_edge_capacity[side], s->plane_edge_count[side] + 1);
    s->plane_edges[side] = bk_realloc(s->plane_edges[side], sizeof(uint64_t) * s->plane_edge_capacity[side]);
    s->plane_edge_source[side] = bk_realloc(s->plane_edge_source[side], s->plane_edge_capacity[side]);
  }
  s->plane_edge_source[side][s->plane_edge_count[side]] = (uint8_t)bk_material_source(material);
  s->plane_edges[side][s->plane_edge_count[side]++] = bk_directed_edge_key(a, b);
}

static void emit(bk_slicer* s, const bk_mesh* m, bk_mesh* out, int side, const uint32_t c[3],
                 uint8_t material, uint32_t tag) {
  uint32_t gp[3];
  for (int k = 0; k < 3; ++k)
    gp[k] = global_position_of_corner(s, m, c[k]);
  for (int k = 0; k < 3; ++k) {
    uint32_t a = gp[k], b = gp[(k + 1) % 3];
    if (on_plane(s, m, a) && on_plane(s, m, b)) push_plane_edge(s, side, a, b, material);
  }
  // Last corner first: the order the sides' corners and positions have
  // always been numbered in (saved trees record it).
  uint32_t c2 = side_corner(s, m, out, side, c[2]), c1 = side_corner(s, m, out, side, c[1]);
  bk_slicer_add_triangle(out, side_corner(s, m, out, side, c[0]), c1, c2, material, tag);
}

static uint32_t cut_position(bk_slicer* s, const bk_mesh* m, uint32_t pa, uint32_t pb) {
  uint32_t lo = pa < pb ? pa : pb, hi = pa < pb ? pb : pa;
  for (uint32_t i = s->cut_position_head[lo]; i != BK_SLICE_NONE; i = s->cut_position_next[i])
    if (s->cut_position_end[i] == hi) return m->position_count + i;
  // Interpolate from the lower index so the point does not depend on which
  // triangle reached the edge first.
  double t = s->dist[lo] / (s->dist[lo] - s->dist[hi]);
  if (s->cut_position_count == s->cut_position_capacity) {
    s->cut_position_capacity = bk_grow_capacity(s->cut_position_capacity, s->cut_position_count + 1);
    s->cut_positions = bk_realloc(s->cut_positions, sizeof(bk_vec3) * s->cut_position_capacity);
    s->cut_position_end = bk_realloc(s->cut_position_end, sizeof(uint32_t) * s->cut_position_capacity);
    s->cut_position_next = bk_realloc(s->cut_position_next, sizeof(uint32_t) * s->cut_position_capacity);
    for (int k = 0; k < 2; ++k)
      s->cut_pos_map[k] = bk_realloc(s->cut_pos_map[k], sizeof(uint32_t) * s->cut_position_capacity);
  }
  uint32_t i = s->cut_position_count++;
  s->cut_positions[i] = bk_v3_lerp(m->positions[lo], m->positions[hi], t);
  s->cut_pos_map[0][i] = s->cut_pos_map[1][i] = UINT32_MAX;
  s->cut_position_end[i] = hi;
  s->cut_position_next[i] = s->cut_position_head[lo];
  s->cut_position_head[lo] = i;
  return m->position_count + i;
}

static void normalize3(float* v) {
  float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (len > 0.0f)
    for (int i = 0; i < 3; ++i)
      v[i] /= len;
}

// The corner where the edge between source corners ca and cb crosses the plane.
static uint32_t cut_corner(bk_slicer* s, const bk_mesh* m, uint32_t ca, uint32_t cb) {
  uint32_t lo = ca < cb ? ca : cb, hi = ca < cb ? cb : ca;
  for (uint32_t i = s->cut_corner_head[lo]; i != BK_SLICE_NONE; i = s->cut_corner_next[i])
    if (s->cut_corner_end[i] == hi) return m->corner_count + i;
  const bk_corner *a = &m->corners[lo], *b = &m->corners[hi];
  float t = (float)(s->dist[a->position] / (s->dist[a->position] - s->dist[b->position]));
  bk_corner c = {0};
  c.position = cut_position(s, m, a->position, b->position);
  for (int i = 0; i < 3; ++i)
    c.normal[i] = a->normal[i] + (b->normal[i] - a->normal[i]) * t;
  for (int i = 0; i < 2; ++i)
    c.uv[i] = a->uv[i] + (b->uv[i] - a->uv[i]) * t;
  for (int i = 0; i < 3; ++i)
    c.tangent[i] = a->tangent[i] + (b->tangent[i] - a->tangent[i]) * t;
  c.tangent[3] = a->tangent[3];
  normalize3(c.normal);
  normalize3(c.tangent);
  if (s->cut_corner_count == s->cut_corner_capacity) {
    s->cut_corner_capacity = bk_grow_capacity(s->cut_corner_capacity, s->cut_corner_count + 1);
    s->cut_corners = bk_realloc(s->cut_corners, sizeof(bk_corner) * s->cut_corner_capacity);
    s->cut_corner_end = bk_realloc(s->cut_corner_end, sizeof(uint32_t) * s->cut_corner_capacity);
    s->cut_corner_next = bk_realloc(s->cut_corner_next, sizeof(uint32_t) * s->cut_corner_capacity);
    for (int k = 0; k < 2; ++k)
      s->cut_corner_map[k] = bk_realloc(s->cut_corner_map[k], sizeof(uint32_t) * s->cut_corner_capacity);
  }
  uint32_t i = s->cut_corner_count++;
  s->cut_corners[i] = c;
  s->cut_corner_map[0][i] = s->cut_corner_map[1][i] = UINT32_MAX;
  s->cut_corner_end[i] = hi;
  s->cut_corner_next[i] = s->cut_corner_head[lo];
  s->cut_corner_head[lo] = i;
  return m->corner_count + i;
}

static void split_triangle(bk_slicer* s, const bk_mesh* m, uint32_t t, bk_mesh* out[2], bk_vec3 n) {
  const uint32_t* c = &m->indices[3 * t];
  uint32_t p[3] = {m->corners[c[0]].position, m->corners[c[1]].position, m->corners[c[2]].position};
  int8_t k[3] = {s->cls[p[0]], s->cls[p[1]], s->cls[p[2]]};
  uint8_t mat = m->materials[t];
  uint32_t tag = m->tags[t];
  bool has_below = k[0] < 0 || k[1] < 0 || k[2] < 0;
  bool has_above = k[0] > 0 || k[1] > 0 || k[2] > 0;
  if (!has_below && !has_above) {
    // Lies in the plane: it is the top of the part below when it faces +n.
    bk_vec3 e = bk_v3_cross(bk_v3_sub(m->positions[p[1]], m->positions[p[0]]),
                            bk_v3_sub(m->positions[p[2]], m->positions[p[0]]));
    emit(s, m, out[bk_v3_dot(e, n) >= 0.0 ? BK_SLICE_BELOW : BK_SLICE_ABOVE],
         bk_v3_dot(e, n) >= 0.0 ? BK_SLICE_BELOW : BK_SLICE_ABOVE, c, mat, tag);
    return;
  }
  if (!has_below || !has_above) {
    int side = has_above ? BK_SLICE_ABOVE : BK_SLICE_BELOW;
    emit(s, m, out[side], side, c, mat, tag);
    return;
  }
  // Rotate so corner 0 is the on-plane vertex (one-vertex-on-plane case) or
  // the lone vertex on its side; rotation keeps the winding.
  int r = 0;
  int zeros = (k[0] == 0) + (k[1] == 0) + (k[2] == 0);
  if (zeros == 1) {
    r = k[0] == 0 ? 0 : (k[1] == 0 ? 1 : 2);
  } else {
    r = k[0] == k[1] ? 2 : (k[0] == k[2] ? 1 : 0);
  }
  uint32_t c0 = c[r], c1 = c[(r + 1) % 3], c2 = c[(r + 2) % 3];
  int8_t k1 = k[(r + 1) % 3], k0 = k[r];
  if (zeros == 1) {
    uint32_t x = cut_corner(s, m, c1, c2);
    int side1 = k1 > 0 ? BK_SLICE_ABOVE : BK_SLICE_BELOW, side2 = 1 - side1;
    emit(s, m, out[side1], side1, (uint32_t[3]){c0, c1, x}, mat, tag);
    emit(s, m, out[side2], side2, (uint32_t[3]){c0, x, c2}, mat, tag);
  } else {
    uint32_t x0 = cut_corner(s, m, c0, c1), x1 = cut_corner(s, m, c0, c2);
    int lone = k0 > 0 ? BK_SLICE_ABOVE : BK_SLICE_BELOW, pair = 1 - lone;
    emit(s, m, out[lone], lone, (uint32_t[3]){c0, x0, x1}, mat, tag);
    emit(s, m, out[pair], pair, (uint32_t[3]){x0, c1, c2}, mat, tag);
    emit(s, m, out[pair], pair, (uint32_t[3]){x0, c2, x1}, mat, tag);
  }
}

bool bk_slicer_slice(bk_slicer* s, const bk_mesh* m, const bk_slice_def* desc, bk_mesh* below, bk_mesh* above,
                     bk_error* err) {
  memset(below, 0, sizeof *below);
  memset(above, 0, sizeof *above);
  return bk_slicer_slice_reuse(s, m, desc, below, above, err);
}

bool bk_slicer_slice_reuse(bk_slicer* s, const bk_mesh* m, const bk_slice_def* desc, bk_mesh* below,
                           bk_mesh* above, bk_error* err) {
  below->position_count = below->corner_count = below->triangle_count = 0;
  above->position_count = above->corner_count = above->triangle_count = 0;
  bk_vec3 n = desc->plane.normal;
  double tolerance = desc->tolerance;
  if (!(tolerance > 0.0)) {
    bk_aabb box = bk_mesh_bounds(m);
    tolerance = 1e-9 * fmax(bk_v3_length(bk_v3_sub(box.max, box.min)), 1e-300);
  }
  double texture_scale = desc->texture_scale > 0.0 ? desc->texture_scale : 0.1;
  reserve_source(s, m);
  uint32_t counts[2] = {0, 0};
  double deepest[2] = {0.0, 0.0}; // how far each side reaches from the plane
  for (uint32_t i = 0; i < m->position_count; ++i) {
    double d = bk_plane_distance(desc->plane, m->positions[i]);
    deepest[BK_SLICE_BELOW] = bk_max(deepest[BK_SLICE_BELOW], -d);
    deepest[BK_SLICE_ABOVE] = bk_max(deepest[BK_SLICE_ABOVE], d);
    s->dist[i] = d;
    s->cls[i] = d > tolerance ? 1 : (d < -tolerance ? -1 : 0);
    counts[0] += s->cls[i] < 0;
    counts[1] += s->cls[i] > 0;
  }
  if (counts[BK_SLICE_BELOW] == 0 || counts[BK_SLICE_ABOVE] == 0) {
    // The plane misses (or only touches) the mesh: everything on one side.
    bk_mesh_append(counts[BK_SLICE_ABOVE] ? above : below, m);
    return true;
  }
  bk_mesh* out[2] = {below, above};
  for (int k = 0; k < 2; ++k)
    bk_mesh_reserve(out[k], m->position_count / 2 + 8, m->corner_count / 2 + 8, m->triangle_count / 2 + 8);
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    split_triangle(s, m, t, out, n);
  return bk_slicer_close(s, m, desc, out, deepest, texture_scale, err);
}
