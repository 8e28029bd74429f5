// Closing a split mesh's sides: the plane edges of each side whose reverse
// it lacks are its open boundary; they are linked by index into loops,
// triangulated once (cap.c) and the triangulation is used by both sides
// when their boundaries mirror each other, so the two caps are the same
// surface and the pieces' volumes add up.
#include <stdlib.h>
#include <string.h>

#include "slicer.h"

// Room for per-global-id lookups (source and cut positions) and for a chain
// link per plane or cap edge; the heads come back empty after each use.
static void reserve_chains(bk_slicer* s, const bk_mesh* m, uint32_t edges) {
  uint32_t globals = m->position_count + s->cut_position_count;
  if (globals > s->global_capacity) {
    uint32_t old = s->global_capacity;
    s->global_capacity = bk_grow_capacity(old, globals);
    s->edge_head = bk_realloc(s->edge_head, sizeof(uint32_t) * s->global_capacity);
    s->local_of_global = bk_realloc(s->local_of_global, sizeof(uint32_t) * s->global_capacity);
    memset(s->edge_head + old, 0xff, sizeof(uint32_t) * (s->global_capacity - old));
    memset(s->local_of_global + old, 0xff, sizeof(uint32_t) * (s->global_capacity - old));
  }
  if (edges > s->edge_next_capacity) {
    s->edge_next_capacity = bk_grow_capacity(s->edge_next_capacity, edges);
    s->edge_next = bk_realloc(s->edge_next, sizeof(uint32_t) * s->edge_next_capacity);
  }
}

// Directed plane edges of `side` whose reverse the same side lacks: the open
// boundary the cap must close. Stored reversed (the cap runs against it).
static void collect_cap_edges(bk_slicer* s, const bk_mesh* m, int side) {
  uint32_t count = s->plane_edge_count[side];
  const uint64_t* edges = s->plane_edges[side];
  reserve_chains(s, m, count);
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t a = (uint32_t)(edges[i] >> 32);
    s->edge_next[i] = s->edge_head[a];
    s->edge_head[a] = i;
  }
  s->cap_edge_count[side] = 0;
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t a = (uint32_t)(edges[i] >> 32), b = (uint32_t)edges[i];
    bool reversed = false;
    for (uint32_t j = s->edge_head[b]; j != BK_SLICE_NONE && !reversed; j = s->edge_next[j])
      reversed = (uint32_t)edges[j] == a;
    if (reversed) continue;
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
  for (uint32_t i = 0; i < count; ++i)
    s->edge_head[(uint32_t)(edges[i] >> 32)] = BK_SLICE_NONE;
}

// True when both sides' boundaries are the same loops run in opposite
// directions (no faces lie in the plane), so one triangulation serves both.
static bool boundaries_mirror(bk_slicer* s, const bk_mesh* m) {
  uint32_t count = s->cap_edge_count[BK_SLICE_ABOVE];
  if (s->cap_edge_count[BK_SLICE_BELOW] != count) return false;
  const uint32_t *above = s->cap_edges[BK_SLICE_ABOVE], *below = s->cap_edges[BK_SLICE_BELOW];
  reserve_chains(s, m, count);
  for (uint32_t i = 0; i < count; ++i) {
    s->edge_next[i] = s->edge_head[above[2 * i]];
    s->edge_head[above[2 * i]] = i;
  }
  bool mirror = true;
  for (uint32_t i = 0; i < count && mirror; ++i) {
    bool found = false; // above's edge below[i + 1] -> below[i]
    for (uint32_t j = s->edge_head[below[2 * i + 1]]; j != BK_SLICE_NONE && !found; j = s->edge_next[j])
      found = above[2 * j + 1] == below[2 * i];
    mirror = found;
  }
  for (uint32_t i = 0; i < count; ++i)
    s->edge_head[above[2 * i]] = BK_SLICE_NONE;
  return mirror;
}

static bk_vec3 global_point(const bk_slicer* s, const bk_mesh* m, uint32_t g) {
  return g < m->position_count ? m->positions[g] : s->cut_positions[g - m->position_count];
}

// Renumbers the cap edges of `side` to local ids with plane coordinates, in
// place (cap_edges then hold local ids).
static uint32_t localize(bk_slicer* s, const bk_mesh* m, int side, bk_vec3 u, bk_vec3 v) {
  uint32_t count = 0;
  uint32_t n = 2u * s->cap_edge_count[side];
  if (n > s->local_capacity) {
    s->local_capacity = bk_grow_capacity(s->local_capacity, n);
    s->global_of_local = bk_realloc(s->global_of_local, sizeof(uint32_t) * s->local_capacity);
    s->source_of_local = bk_realloc(s->source_of_local, s->local_capacity);
    s->xy = bk_realloc(s->xy, sizeof(double) * 2u * s->local_capacity);
  }
  reserve_chains(s, m, 0);
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t g = s->cap_edges[side][i];
    if (s->local_of_global[g] == BK_SLICE_NONE) {
      bk_vec3 p = global_point(s, m, g);
      s->local_of_global[g] = count;
      s->global_of_local[count] = g;
      s->xy[2 * count] = bk_v3_dot(p, u);
      s->xy[2 * count + 1] = bk_v3_dot(p, v);
      s->source_of_local[count] = s->cap_edge_source[side][i / 2];
      count++;
    }
    s->cap_edges[side][i] = s->local_of_global[g];
  }
  for (uint32_t i = 0; i < count; ++i)
    s->local_of_global[s->global_of_local[i]] = BK_SLICE_NONE;
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
  float sign = side == BK_SLICE_BELOW ? 1.0f : -1.0f;
  uint32_t first = out->corner_count;
  bk_mesh_reserve(out, 0, out->corner_count + local_count, out->triangle_count + tri_count);
  for (uint32_t i = 0; i < local_count; ++i) {
    bk_corner c = {0};
    c.position = bk_slicer_side_position(s, m, out, side, s->global_of_local[i]);
    c.normal[0] = sign * (float)n.x, c.normal[1] = sign * (float)n.y, c.normal[2] = sign * (float)n.z;
    c.uv[0] = (float)(s->xy[2 * i] / texture_scale + desc->uv_origin[0]);
    c.uv[1] = (float)(s->xy[2 * i + 1] / texture_scale + desc->uv_origin[1]);
    c.tangent[0] = (float)u.x, c.tangent[1] = (float)u.y, c.tangent[2] = (float)u.z;
    c.tangent[3] = sign; // bitangent = v = n x u below; mirrored above
    bk_slicer_add_corner(out, &c);
  }
  for (uint32_t t = 0; t < tri_count; ++t) {
    const uint32_t* tri = &tris[3 * t];
    uint8_t material = cap_material(s, tri);
    if (reversed)
      bk_slicer_add_triangle(out, first + tri[0], first + tri[2], first + tri[1], material, desc->cap_tag);
    else
      bk_slicer_add_triangle(out, first + tri[0], first + tri[1], first + tri[2], material, desc->cap_tag);
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
  float sign = side == BK_SLICE_BELOW ? 1.0f : -1.0f;
  uint32_t first = out->corner_count;
  bk_mesh_reserve(out, out->position_count + cap->point_count, out->corner_count + cap->point_count,
                  out->triangle_count + cap->triangle_count);
  for (uint32_t i = 0; i < cap->point_count; ++i) {
    bk_corner c = {0};
    c.position = i < local_count ? bk_slicer_side_position(s, m, out, side, s->global_of_local[i])
                                 : bk_slicer_add_position(out, cap->points[i]);
    bk_vec3 normal = s->noise_normals[i];
    c.normal[0] = sign * (float)normal.x, c.normal[1] = sign * (float)normal.y,
    c.normal[2] = sign * (float)normal.z;
    c.uv[0] = (float)(bk_v3_dot(cap->points[i], u) / texture_scale + desc->uv_origin[0]);
    c.uv[1] = (float)(bk_v3_dot(cap->points[i], v) / texture_scale + desc->uv_origin[1]);
    c.tangent[0] = (float)u.x, c.tangent[1] = (float)u.y, c.tangent[2] = (float)u.z;
    c.tangent[3] = sign;
    bk_slicer_add_corner(out, &c);
  }
  for (uint32_t t = 0; t < cap->triangle_count; ++t) {
    const uint32_t* tri = &cap->triangles[3 * t];
    uint8_t material = cap_material(s, &coarse[3 * cap->parents[t]]);
    if (reversed)
      bk_slicer_add_triangle(out, first + tri[0], first + tri[2], first + tri[1], material, desc->cap_tag);
    else
      bk_slicer_add_triangle(out, first + tri[0], first + tri[1], first + tri[2], material, desc->cap_tag);
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
  bk_free(points);
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

bool bk_slicer_close(bk_slicer* s, const bk_mesh* m, const bk_slice_def* desc, bk_mesh* out[2],
                     const double deepest[2], double texture_scale, bk_error* err) {
  bk_vec3 n = desc->plane.normal;
  collect_cap_edges(s, m, BK_SLICE_BELOW);
  collect_cap_edges(s, m, BK_SLICE_ABOVE);
  bk_vec3 u = {0}, v = {0};
  bk_plane_basis(n, &u, &v);
  bool mirror = boundaries_mirror(s, m);
  for (int side = 0; side < 2; ++side) {
    if (s->cap_edge_count[side] == 0) continue;
    uint32_t local_count = localize(s, m, side, u, v);
    const uint32_t* tris = NULL;
    uint32_t tri_count = 0;
    if (!bk_cap_triangulate(s->cap, s->cap_edges[side], s->cap_edge_count[side], s->xy, local_count, &tris,
                            &tri_count, err)) {
      bk_mesh_free(out[BK_SLICE_BELOW]);
      bk_mesh_free(out[BK_SLICE_ABOVE]);
      return false;
    }
    if (mirror && desc->noise_amplitude > 0.0 && desc->noise_frequency > 0.0) {
      // A noisy cap needs one triangulation for both sides (a cap with
      // faces lying in the plane stays flat). The triangles face +n on the
      // side below, -n above.
      double facing = side == BK_SLICE_BELOW ? 1.0 : -1.0;
      make_noisy_cap(s, m, tris, tri_count, local_count, desc,
                     0.25 * fmin(deepest[BK_SLICE_BELOW], deepest[BK_SLICE_ABOVE]), facing);
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
