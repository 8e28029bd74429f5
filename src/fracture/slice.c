// Plane slicing of a closed mesh. Positions are classified once; a cut edge
// gets exactly one new position shared by both sides (looked up by the index
// pair, never by comparing coordinates), so each side's open boundary is a
// set of index loops that the cap closes exactly.
#include <stdlib.h>
#include <string.h>

#include "cap.h"

enum { BELOW = 0, ABOVE = 1 };

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
  // Cut vertices, numbered after the source positions ("global ids").
  bk_index_map cut_position_of_edge;
  bk_index_map cut_corner_of_pair;
  bk_vec3* cut_positions;
  uint32_t* cut_pos_map[2];
  uint32_t cut_position_count, cut_position_capacity;
  bk_corner* cut_corners; // .position holds the global position id
  uint32_t* cut_corner_map[2];
  uint32_t cut_corner_count, cut_corner_capacity;
  // Directed edges with both ends on the plane, per side (global ids).
  uint64_t* plane_edges[2];
  uint8_t* plane_edge_source[2]; // the source material of the triangle each plane edge came from
  uint32_t plane_edge_count[2], plane_edge_capacity[2];
  bk_index_map edge_set;
  // Cap input and output scratch.
  uint32_t* cap_edges[2];
  uint8_t* cap_edge_source[2]; // per cap edge (not per id pair)
  uint32_t cap_edge_count[2], cap_edge_capacity[2];
  bk_index_map local_of_global;
  uint32_t* global_of_local;
  uint8_t* source_of_local; // the source material of a cap edge leaving each local vertex
  double* xy;
  uint32_t local_capacity;
};

bk_slicer* bk_slicer_create(void) {
  bk_slicer* s = bk_calloc(1, sizeof *s);
  s->cap = bk_cap_create();
  if (!s->cap) {
    free(s);
    return NULL;
  }
  bk_index_map_init(&s->cut_position_of_edge, 64);
  bk_index_map_init(&s->cut_corner_of_pair, 64);
  bk_index_map_init(&s->edge_set, 64);
  bk_index_map_init(&s->local_of_global, 64);
  return s;
}

void bk_slicer_destroy(bk_slicer* s) {
  if (!s) return;
  bk_cap_destroy(s->cap);
  bk_cap_noise_free(&s->noise);
  free(s->noise_normals);
  free(s->dist);
  free(s->cls);
  for (int k = 0; k < 2; ++k) {
    free(s->pos_map[k]);
    free(s->corner_map[k]);
    free(s->cut_pos_map[k]);
    free(s->cut_corner_map[k]);
    free(s->plane_edges[k]);
    free(s->plane_edge_source[k]);
    free(s->cap_edges[k]);
    free(s->cap_edge_source[k]);
  }
  free(s->cut_positions);
  free(s->cut_corners);
  free(s->global_of_local);
  free(s->source_of_local);
  free(s->xy);
  bk_index_map_free(&s->cut_position_of_edge);
  bk_index_map_free(&s->cut_corner_of_pair);
  bk_index_map_free(&s->edge_set);
  bk_index_map_free(&s->local_of_global);
  free(s);
}

static void reserve_source(bk_slicer* s, const bk_mesh* m) {
  if (m->position_count > s->position_capacity) {
    s->position_capacity = bk_grow_capacity(s->position_capacity, m->position_count);
    s->dist = bk_realloc(s->dist, sizeof(double) * s->position_capacity);
    s->cls = bk_realloc(s->cls, s->position_capacity);
    for (int k = 0; k < 2; ++k)
      s->pos_map[k] = bk_realloc(s->pos_map[k], sizeof(uint32_t) * s->position_capacity);
  }
  if (m->corner_count > s->corner_capacity) {
    s->corner_capacity = bk_grow_capacity(s->corner_capacity, m->corner_count);
    for (int k = 0; k < 2; ++k)
      s->corner_map[k] = bk_realloc(s->corner_map[k], sizeof(uint32_t) * s->corner_capacity);
  }
  for (int k = 0; k < 2; ++k) {
    memset(s->pos_map[k], 0xff, sizeof(uint32_t) * m->position_count);
    memset(s->corner_map[k], 0xff, sizeof(uint32_t) * m->corner_count);
  }
  bk_index_map_clear(&s->cut_position_of_edge);
  bk_index_map_clear(&s->cut_corner_of_pair);
  s->cut_position_count = 0;
  s->cut_corner_count = 0;
  s->plane_edge_count[0] = s->plane_edge_count[1] = 0;
}

// Global position id: source positions first, then cut positions.
static uint32_t side_position(bk_slicer* s, const bk_mesh* m, bk_mesh* out, int side, uint32_t global) {
  uint32_t* slot = global < m->position_count ? &s->pos_map[side][global]
                                              : &s->cut_pos_map[side][global - m->position_count];
  if (*slot == UINT32_MAX) {
    bk_vec3 p =
        global < m->position_count ? m->positions[global] : s->cut_positions[global - m->position_count];
    *slot = bk_mesh_add_position(out, p);
  }
  return *slot;
}

// Global corner id: source corners first, then cut corners.
static uint32_t side_corner(bk_slicer* s, const bk_mesh* m, bk_mesh* out, int side, uint32_t global) {
  bool source = global < m->corner_count;
  uint32_t* slot = source ? &s->corner_map[side][global] : &s->cut_corner_map[side][global - m->corner_count];
  if (*slot == UINT32_MAX) {
    bk_corner c = source ? m->corners[global] : s->cut_corners[global - m->corner_count];
    c.position = side_position(s, m, out, side, c.position);
    *slot = bk_mesh_add_corner(out, &c);
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
  bk_mesh_add_triangle(out, side_corner(s, m, out, side, c[0]), side_corner(s, m, out, side, c[1]),
                       side_corner(s, m, out, side, c[2]), material, tag);
}

static uint32_t cut_position(bk_slicer* s, const bk_mesh* m, uint32_t pa, uint32_t pb) {
  bool inserted = false;
  uint32_t* slot =
      bk_index_map_insert(&s->cut_position_of_edge, bk_edge_key(pa, pb), s->cut_position_count, &inserted);
  if (inserted) {
    // Interpolate from the lower index so the point does not depend on which
    // triangle reached the edge first.
    uint32_t lo = pa < pb ? pa : pb, hi = pa < pb ? pb : pa;
    double t = s->dist[lo] / (s->dist[lo] - s->dist[hi]);
    if (s->cut_position_count == s->cut_position_capacity) {
      s->cut_position_capacity = bk_grow_capacity(s->cut_position_capacity, s->cut_position_count + 1);
      s->cut_positions = bk_realloc(s->cut_positions, sizeof(bk_vec3) * s->cut_position_capacity);
      for (int k = 0; k < 2; ++k)
        s->cut_pos_map[k] = bk_realloc(s->cut_pos_map[k], sizeof(uint32_t) * s->cut_position_capacity);
    }
    s->cut_positions[s->cut_position_count] = bk_v3_lerp(m->positions[lo], m->positions[hi], t);
    s->cut_pos_map[0][s->cut_position_count] = s->cut_pos_map[1][s->cut_position_count] = UINT32_MAX;
    s->cut_position_count++;
  }
  return m->position_count + *slot;
}

static void normalize3(float* v) {
  float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (len > 0.0f)
    for (int i = 0; i < 3; ++i)
      v[i] /= len;
}

// The corner where the edge between source corners ca and cb crosses the plane.
static uint32_t cut_corner(bk_slicer* s, const bk_mesh* m, uint32_t ca, uint32_t cb) {
  bool inserted = false;
  uint32_t* slot =
      bk_index_map_insert(&s->cut_corner_of_pair, bk_edge_key(ca, cb), s->cut_corner_count, &inserted);
  if (inserted) {
    uint32_t lo = ca < cb ? ca : cb, hi = ca < cb ? cb : ca;
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
      for (int k = 0; k < 2; ++k)
        s->cut_corner_map[k] = bk_realloc(s->cut_corner_map[k], sizeof(uint32_t) * s->cut_corner_capacity);
    }
    s->cut_corners[s->cut_corner_count] = c;
    s->cut_corner_map[0][s->cut_corner_count] = s->cut_corner_map[1][s->cut_corner_count] = UINT32_MAX;
    s->cut_corner_count++;
  }
  return m->corner_count + *slot;
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
    emit(s, m, out[bk_v3_dot(e, n) >= 0.0 ? BELOW : ABOVE], bk_v3_dot(e, n) >= 0.0 ? BELOW : ABOVE, c, mat,
         tag);
    return;
  }
  if (!has_below || !has_above) {
    int side = has_above ? ABOVE : BELOW;
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
    int side1 = k1 > 0 ? ABOVE : BELOW, side2 = 1 - side1;
    emit(s, m, out[side1], side1, (uint32_t[3]){c0, c1, x}, mat, tag);
    emit(s, m, out[side2], side2, (uint32_t[3]){c0, x, c2}, mat, tag);
  } else {
    uint32_t x0 = cut_corner(s, m, c0, c1), x1 = cut_corner(s, m, c0, c2);
    int lone = k0 > 0 ? ABOVE : BELOW, pair = 1 - lone;
    emit(s, m, out[lone], lone, (uint32_t[3]){c0, x0, x1}, mat, tag);
    emit(s, m, out[pair], pair, (uint32_t[3]){x0, c1, c2}, mat, tag);
    emit(s, m, out[pair], pair, (uint32_t[3]){x0, c2, x1}, mat, tag);
  }
}

// Directed plane edges of `side` whose reverse the same side lacks: the open
// boundary the cap must close. Stored reversed (the cap runs against it).
static void collect_cap_edges(bk_slicer* s, int side) {
  bk_index_map_clear(&s->edge_set);
  bool inserted = false;
  for (uint32_t i = 0; i < s->plane_edge_count[side]; ++i)
    bk_index_map_insert(&s->edge_set, s->plane_edges[side][i], 0, &inserted);
  s->cap_edge_count[side] = 0;
  for (uint32_t i = 0; i < s->plane_edge_count[side]; ++i) {
    uint64_t key = s->plane_edges[side][i];
    uint32_t a = (uint32_t)(key >> 32), b = (uint32_t)key;
    if (bk_index_map_find(&s->edge_set, bk_directed_edge_key(b, a))) continue;
    if (2u * (s->cap_edge_count[side] + 1) > s->cap_edge_capacity[side]) {
      s->cap_edge_capacity[side] =
          bk_grow_capacity(s->cap_edge_capacity[side], 2u * (s->cap_edge_count[side] + 1));
      s->cap_edges[side] = bk_realloc(s->cap_edges[side], sizeof(uint32_t) * s->cap_edge_capacity[side]);
      s->cap_edge_source[side] = bk_realloc(s->cap_edge_source[side], s->cap_edge_capacity[side] / 2u);
    }
    s->cap_edge_source[side][s->cap_edge_count[side]] = s->plane_edge_source[side][i];
    s->cap_edges[side][2 * s->cap_edge_count[side]] = b;
    s->cap_edges[side][2 * s->cap_edge_count[side] + 1] = a;
    s->cap_edge_count[side]++;
  }
}

// True when both sides' boundaries are the same loops run in opposite
// directions (no faces lie in the plane), so one triangulation serves both.
static bool boundaries_mirror(bk_slicer* s) {
  if (s->cap_edge_count[BELOW] != s->cap_edge_count[ABOVE]) return false;
  bk_index_map_clear(&s->edge_set);
  bool inserted = false;
  for (uint32_t i = 0; i < s->cap_edge_count[ABOVE]; ++i)
    bk_index_map_insert(&s->edge_set,
                        bk_directed_edge_key(s->cap_edges[ABOVE][2 * i], s->cap_edges[ABOVE][2 * i + 1]), 0,
                        &inserted);
  for (uint32_t i = 0; i < s->cap_edge_count[BELOW]; ++i)
    if (!bk_index_map_find(&s->edge_set,
                           bk_directed_edge_key(s->cap_edges[BELOW][2 * i + 1], s->cap_edges[BELOW][2 * i])))
      return false;
  return true;
}

static bk_vec3 global_point(const bk_slicer* s, const bk_mesh* m, uint32_t g) {
  return g < m->position_count ? m->positions[g] : s->cut_positions[g - m->position_count];
}

// Renumbers the cap edges of `side` to local ids with plane coordinates, in
// place (cap_edges then hold local ids).
static uint32_t localize(bk_slicer* s, const bk_mesh* m, int side, bk_vec3 u, bk_vec3 v) {
  bk_index_map_clear(&s->local_of_global);
  uint32_t count = 0;
  uint32_t n = 2u * s->cap_edge_count[side];
  if (n > s->local_capacity) {
    s->local_capacity = bk_grow_capacity(s->local_capacity, n);
    s->global_of_local = bk_realloc(s->global_of_local, sizeof(uint32_t) * s->local_capacity);
    s->source_of_local = bk_realloc(s->source_of_local, s->local_capacity);
    s->xy = bk_realloc(s->xy, sizeof(double) * 2u * s->local_capacity);
  }
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t g = s->cap_edges[side][i];
    bool inserted = false;
    uint32_t* slot = bk_index_map_insert(&s->local_of_global, g, count, &inserted);
    if (inserted) {
      bk_vec3 p = global_point(s, m, g);
      s->global_of_local[count] = g;
      s->xy[2 * count] = bk_v3_dot(p, u);
      s->xy[2 * count + 1] = bk_v3_dot(p, v);
      s->source_of_local[count] = s->cap_edge_source[side][i / 2];
      count++;
    }
    s->cap_edges[side][i] = *slot;
  }
  return count;
}

// A cap triangle is the interior of the source material its corners' cut
// edges came from: that of two or three corners, else of its first corner.
// Every corner of a one-material mesh says 0, so its caps are all
// BK_MATERIAL_INTERIOR.
static uint8_t cap_material(const bk_slicer* s, const uint32_t tri[3]) {
  uint8_t a = s->source_of_local[tri[0]], b = s->source_of_local[tri[1]], c = s->source_of_local[tri[2]];
  uint8_t source = (b == c && a != b) ? b : a;
  return bk_material_id(source, true);
}

static void add_cap(bk_slicer* s, const bk_mesh* m, bk_mesh* out, int side, const uint32_t* tris,
                    uint32_t tri_count, uint32_t local_count, bool reversed, bk_vec3 n, bk_vec3 u,
                    const bk_slice_def* desc, double texture_scale) {
  // One corner per cap vertex: flat normal, planar uv, tangent along u. The
  // same uv on both faces of a crack makes the two halves' textures match.
  float sign = side == BELOW ? 1.0f : -1.0f;
  uint32_t first = out->corner_count;
  bk_mesh_reserve(out, 0, out->corner_count + local_count, out->triangle_count + tri_count);
  for (uint32_t i = 0; i < local_count; ++i) {
    bk_corner c = {0};
    c.position = side_position(s, m, out, side, s->global_of_local[i]);
    c.normal[0] = sign * (float)n.x, c.normal[1] = sign * (float)n.y, c.normal[2] = sign * (float)n.z;
    c.uv[0] = (float)(s->xy[2 * i] / texture_scale + desc->uv_origin[0]);
    c.uv[1] = (float)(s->xy[2 * i + 1] / texture_scale + desc->uv_origin[1]);
    c.tangent[0] = (float)u.x, c.tangent[1] = (float)u.y, c.tangent[2] = (float)u.z;
    c.tangent[3] = sign; // bitangent = v = n x u below; mirrored above
    bk_mesh_add_corner(out, &c);
  }
  for (uint32_t t = 0; t < tri_count; ++t) {
    const uint32_t* tri = &tris[3 * t];
    uint8_t material = cap_material(s, tri);
    if (reversed)
      bk_mesh_add_triangle(out, first + tri[0], first + tri[2], first + tri[1], material, desc->cap_tag);
    else
      bk_mesh_add_triangle(out, first + tri[0], first + tri[1], first + tri[2], material, desc->cap_tag);
  }
}

// The noisy cap (s->noise over the cap's local points, the new points after
// them) on one side. Corner normals follow the pushed surface; uvs stay the
// plane coordinates, so the texture lies as on a flat cap.
static void add_noisy_cap(bk_slicer* s, const bk_mesh* m, bk_mesh* out, int side, uint32_t local_count,
                          bool reversed, bk_vec3 u, bk_vec3 v, const bk_slice_def* desc, double texture_scale,
                          const uint32_t* coarse) {
  const bk_cap_noise* cap = &s->noise;
  // The cap faces +n below and -n above (s->noise_normals face +n).
  float sign = side == BELOW ? 1.0f : -1.0f;
  uint32_t first = out->corner_count;
  bk_mesh_reserve(out, out->position_count + cap->point_count, out->corner_count + cap->point_count,
                  out->triangle_count + cap->triangle_count);
  for (uint32_t i = 0; i < cap->point_count; ++i) {
    bk_corner c = {0};
    c.position = i < local_count ? side_position(s, m, out, side, s->global_of_local[i])
                                 : bk_mesh_add_position(out, cap->points[i]);
    bk_vec3 normal = s->noise_normals[i];
    c.normal[0] = sign * (float)normal.x, c.normal[1] = sign * (float)normal.y,
    c.normal[2] = sign * (float)normal.z;
    c.uv[0] = (float)(bk_v3_dot(cap->points[i], u) / texture_scale + desc->uv_origin[0]);
    c.uv[1] = (float)(bk_v3_dot(cap->points[i], v) / texture_scale + desc->uv_origin[1]);
    c.tangent[0] = (float)u.x, c.tangent[1] = (float)u.y, c.tangent[2] = (float)u.z;
    c.tangent[3] = sign;
    bk_mesh_add_corner(out, &c);
  }
  for (uint32_t t = 0; t < cap->triangle_count; ++t) {
    const uint32_t* tri = &cap->triangles[3 * t];
    uint8_t material = cap_material(s, &coarse[3 * cap->parents[t]]);
    if (reversed)
      bk_mesh_add_triangle(out, first + tri[0], first + tri[2], first + tri[1], material, desc->cap_tag);
    else
      bk_mesh_add_triangle(out, first + tri[0], first + tri[1], first + tri[2], material, desc->cap_tag);
  }
}

// Meshes and pushes the cap `tris` (local ids; they face `facing` x n) into
// s->noise, with unit normals facing +n per point.
static void make_noisy_cap(bk_slicer* s, const bk_mesh* m, const uint32_t* tris, uint32_t tri_count,
                           uint32_t local_count, const bk_slice_def* desc, double limit, double facing) {
  bk_vec3* points = bk_alloc(sizeof(bk_vec3) * (local_count + 1u));
  for (uint32_t i = 0; i < local_count; ++i)
    points[i] = global_point(s, m, s->global_of_local[i]);
  bk_cap_noise_def def = {.normal = desc->plane.normal,
                          .amplitude = desc->noise_amplitude,
                          .frequency = desc->noise_frequency,
                          .limit = limit,
                          .seed = desc->noise_seed};
  bk_cap_noise_make(&def, tris, tri_count, points, local_count, &s->noise);
  free(points);
  const bk_cap_noise* cap = &s->noise;
  if (cap->point_count > s->noise_normal_capacity) {
    s->noise_normal_capacity = bk_grow_capacity(s->noise_normal_capacity, cap->point_count);
    s->noise_normals = bk_realloc(s->noise_normals, sizeof(bk_vec3) * s->noise_normal_capacity);
  }
  memset(s->noise_normals, 0, sizeof(bk_vec3) * cap->point_count);
  for (uint32_t t = 0; t < cap->triangle_count; ++t) {
    const uint32_t* v = &cap->triangles[3 * t];
    bk_vec3 e = bk_v3_cross(bk_v3_sub(cap->points[v[1]], cap->points[v[0]]),
                            bk_v3_sub(cap->points[v[2]], cap->points[v[0]]));
    for (int k = 0; k < 3; ++k)
      s->noise_normals[v[k]] = bk_v3_add(s->noise_normals[v[k]], bk_v3_scale(e, facing));
  }
  for (uint32_t i = 0; i < cap->point_count; ++i) {
    double length = bk_v3_length(s->noise_normals[i]);
    s->noise_normals[i] = length > 0.0 ? bk_v3_scale(s->noise_normals[i], 1.0 / length) : desc->plane.normal;
  }
}

bool bk_slicer_slice(bk_slicer* s, const bk_mesh* m, const bk_slice_def* desc, bk_mesh* below, bk_mesh* above,
                     bk_error* err) {
  memset(below, 0, sizeof *below);
  memset(above, 0, sizeof *above);
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
    deepest[BELOW] = fmax(deepest[BELOW], -d);
    deepest[ABOVE] = fmax(deepest[ABOVE], d);
    s->dist[i] = d;
    s->cls[i] = d > tolerance ? 1 : (d < -tolerance ? -1 : 0);
    counts[0] += s->cls[i] < 0;
    counts[1] += s->cls[i] > 0;
  }
  if (counts[BELOW] == 0 || counts[ABOVE] == 0) {
    // The plane misses (or only touches) the mesh: everything on one side.
    bk_mesh_copy(counts[ABOVE] ? above : below, m);
    return true;
  }
  bk_mesh* out[2] = {below, above};
  for (int k = 0; k < 2; ++k)
    bk_mesh_reserve(out[k], m->position_count / 2 + 8, m->corner_count / 2 + 8, m->triangle_count / 2 + 8);
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    split_triangle(s, m, t, out, n);

  collect_cap_edges(s, BELOW);
  collect_cap_edges(s, ABOVE);
  bk_vec3 u, v;
  bk_plane_basis(n, &u, &v);
  bool mirror = boundaries_mirror(s);
  for (int side = 0; side < 2; ++side) {
    if (s->cap_edge_count[side] == 0) continue;
    uint32_t local_count = localize(s, m, side, u, v);
    const uint32_t* tris = NULL;
    uint32_t tri_count = 0;
    if (!bk_cap_triangulate(s->cap, s->cap_edges[side], s->cap_edge_count[side], s->xy, local_count, &tris,
                            &tri_count, err)) {
      bk_mesh_free(below);
      bk_mesh_free(above);
      return false;
    }
    if (mirror && desc->noise_amplitude > 0.0 && desc->noise_frequency > 0.0) {
      // A noisy cap needs one triangulation for both sides (a cap with
      // faces lying in the plane stays flat). The triangles face +n on the
      // side below, -n above.
      double facing = side == BELOW ? 1.0 : -1.0;
      make_noisy_cap(s, m, tris, tri_count, local_count, desc, 0.25 * fmin(deepest[BELOW], deepest[ABOVE]),
                     facing);
      add_noisy_cap(s, m, out[side], side, local_count, false, u, v, desc, texture_scale, tris);
      add_noisy_cap(s, m, out[1 - side], 1 - side, local_count, true, u, v, desc, texture_scale, tris);
      break;
    }
    add_cap(s, m, out[side], side, tris, tri_count, local_count, false, n, u, desc, texture_scale);
    if (mirror) {
      // The other side's boundary is this one reversed: reuse the
      // triangulation (identical cap surfaces keep volumes additive exactly).
      add_cap(s, m, out[1 - side], 1 - side, tris, tri_count, local_count, true, n, u, desc, texture_scale);
      break;
    }
  }
  return true;
}
