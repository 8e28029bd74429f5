// Noisy cut faces (as APEX's noisy slices): each cut face is refined and its
// inner vertices pushed along the face's normal by coherent noise. The
// face's border never moves and the push tapers to zero towards it, so the
// surface pieces and the neighbouring faces that meet the border still
// match it exactly: every cell stays closed, and since both cells of a face
// use the one refined face, they still fit each other and their volumes
// still add up.
#include <stdlib.h>
#include <string.h>

// stb_perlin's functions are extern; renamed so our library exports none of
// stb's names (a game may link its own copy).
#define stb_perlin_noise3 bk_stb_perlin_noise3
#define stb_perlin_noise3_seed bk_stb_perlin_noise3_seed
#define stb_perlin_noise3_internal bk_stb_perlin_noise3_internal
#define stb_perlin_ridge_noise3 bk_stb_perlin_ridge_noise3
#define stb_perlin_fbm_noise3 bk_stb_perlin_fbm_noise3
#define stb_perlin_turbulence_noise3 bk_stb_perlin_turbulence_noise3
#define stb_perlin_noise3_wrap_nonpow2 bk_stb_perlin_noise3_wrap_nonpow2
#define STB_PERLIN_IMPLEMENTATION
#include <stb/stb_perlin.h>

#include "cap.h"
#include "cell_complex.h"

double bk_noise3(bk_vec3 p, int seed) {
  return stb_perlin_noise3_seed((float)p.x, (float)p.y, (float)p.z, 0, 0, 0, seed);
}

typedef struct tri_list {
  uint32_t* v;
  uint32_t count, capacity; // triangles
} tri_list;

static void push_tri(tri_list* l, uint32_t a, uint32_t b, uint32_t c) {
  if (l->count == l->capacity) {
    l->capacity = bk_grow_capacity(l->capacity, l->count + 1);
    l->v = bk_realloc(l->v, sizeof(uint32_t) * 3 * l->capacity);
  }
  l->v[3 * l->count] = a, l->v[3 * l->count + 1] = b, l->v[3 * l->count + 2] = c;
  l->count++;
}

typedef struct noise_face {
  bk_cell_complex* cx;
  uint32_t face;
  uint32_t next_point;
  bk_index_map border; // undirected edges used once: the face's border
  bk_index_map midpoint;
} noise_face;

static uint32_t midpoint(noise_face* nf, uint32_t a, uint32_t b) {
  bool inserted = false;
  uint32_t* slot = bk_index_map_insert(&nf->midpoint, bk_edge_key(a, b), 0, &inserted);
  if (!inserted) return *slot;
  bk_cell_key key = {.kind = BK_CELL_NOISE_POINT, .a = nf->face, .b = nf->next_point++};
  bk_vec3 p = bk_v3_scale(bk_v3_add(nf->cx->points[a], nf->cx->points[b]), 0.5);
  uint32_t v = bk_cell_vertex_at(nf->cx, &key, p);
  *bk_index_map_find(&nf->midpoint, bk_edge_key(a, b)) = v;
  return v;
}

// One level: inner edges get their midpoint, border edges stay whole.
static void refine(noise_face* nf, const tri_list* in, tri_list* out) {
  out->count = 0;
  for (uint32_t t = 0; t < in->count; ++t) {
    const uint32_t* v = in->v + 3 * t;
    uint32_t m[3];
    int split = 0;
    for (int k = 0; k < 3; ++k) {
      uint32_t a = v[k], b = v[(k + 1) % 3];
      m[k] = bk_index_map_find(&nf->border, bk_edge_key(a, b)) ? UINT32_MAX : midpoint(nf, a, b);
      split += m[k] != UINT32_MAX;
    }
    if (split == 3) {
      push_tri(out, v[0], m[0], m[2]);
      push_tri(out, m[0], v[1], m[1]);
      push_tri(out, m[2], m[1], v[2]);
      push_tri(out, m[0], m[1], m[2]);
    } else if (split == 0) {
      push_tri(out, v[0], v[1], v[2]);
    } else if (split == 1) { // v_k, m_k, v_k+1, v_k+2: two triangles from the far corner
      int k = m[0] != UINT32_MAX ? 0 : (m[1] != UINT32_MAX ? 1 : 2);
      push_tri(out, v[(k + 2) % 3], v[k], m[k]);
      push_tri(out, v[(k + 2) % 3], m[k], v[(k + 1) % 3]);
    } else { // v_u, v_u+1, m_u+1, v_u+2, m_u+2: the corner between the split edges cut off
      int u = m[0] == UINT32_MAX ? 0 : (m[1] == UINT32_MAX ? 1 : 2);
      uint32_t m1 = m[(u + 1) % 3], m2 = m[(u + 2) % 3];
      push_tri(out, m1, v[(u + 2) % 3], m2);
      push_tri(out, v[u], v[(u + 1) % 3], m1);
      push_tri(out, v[u], m1, m2);
    }
  }
}

static double distance_to_segment(bk_vec3 p, bk_vec3 a, bk_vec3 b) {
  bk_vec3 ab = bk_v3_sub(b, a);
  double len2 = bk_v3_dot(ab, ab);
  double t = len2 > 0.0 ? bk_v3_dot(bk_v3_sub(p, a), ab) / len2 : 0.0;
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return bk_v3_length(bk_v3_sub(p, bk_v3_add(a, bk_v3_scale(ab, t))));
}

void bk_cell_faces_add_noise(bk_cell_complex* cx, bk_cell_faces* faces, double amplitude, double frequency,
                             uint64_t seed) {
  tri_list all = {0}, a = {0}, b = {0};
  uint32_t* border_edges = NULL;
  uint32_t border_capacity = 0;
  // A budget: the refined faces may have at most BK_CELL_NOISE_BUDGET
  // times the triangles (or BK_CELL_NOISE_EXTRA more), however fine the noise.
  int max_levels = BK_CELL_NOISE_MAX_LEVELS;
  for (; max_levels > 0; --max_levels) {
    double total = 0.0;
    for (uint32_t f = 0; f < faces->count; ++f) {
      const bk_cell_face* face = &faces->faces[f];
      double longest = 0.0;
      for (uint32_t t = 0; t < face->count; ++t)
        for (int k = 0; k < 3; ++k) {
          const uint32_t* v = faces->triangles + 3 * (face->first + t);
          longest = fmax(longest, bk_v3_length(bk_v3_sub(cx->points[v[k]], cx->points[v[(k + 1) % 3]])));
        }
      int levels = (int)fmin(ceil(bk_log2(fmax(longest * frequency * 2.0, 1.0))), BK_CELL_NOISE_MAX_LEVELS);
      levels = levels < 0 ? 0 : (levels > max_levels ? max_levels : levels);
      total += face->count * bk_pow(4.0, levels);
    }
    if (total <=
        fmax(BK_CELL_NOISE_BUDGET * faces->triangle_count, faces->triangle_count + BK_CELL_NOISE_EXTRA))
      break;
  }
  int noise_seed = (int)(seed & 0xff);
  double offset = (double)((seed >> 8) & 0xffff) * 0.618;
  for (uint32_t f = 0; f < faces->count; ++f) {
    bk_cell_face* face = &faces->faces[f];
    noise_face nf = {.cx = cx, .face = f};
    bk_index_map_init(&nf.border, 64);
    bk_index_map_init(&nf.midpoint, 64);
    // The border: undirected edges used by one triangle.
    bk_index_map uses = {0};
    bk_index_map_init(&uses, 64);
    a.count = 0;
    double area = 0.0, longest = 0.0;
    for (uint32_t t = 0; t < face->count; ++t) {
      const uint32_t* v = faces->triangles + 3 * (face->first + t);
      push_tri(&a, v[0], v[1], v[2]);
      bk_vec3 p0 = cx->points[v[0]], p1 = cx->points[v[1]], p2 = cx->points[v[2]];
      area += 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(p1, p0), bk_v3_sub(p2, p0)));
      for (int k = 0; k < 3; ++k) {
        bool inserted = false;
        uint32_t* n = bk_index_map_insert(&uses, bk_edge_key(v[k], v[(k + 1) % 3]), 0, &inserted);
        (*n)++;
        longest = fmax(longest, bk_v3_length(bk_v3_sub(cx->points[v[k]], cx->points[v[(k + 1) % 3]])));
      }
    }
    uint32_t border_count = 0;
    for (uint32_t s = 0; s <= uses.capacity - 1 && uses.capacity; ++s) {
      if (uses.keys[s] == UINT64_MAX || uses.values[s] != 1) continue;
      bool inserted = false;
      bk_index_map_insert(&nf.border, uses.keys[s], 1, &inserted);
      if (border_count + 2 > border_capacity) {
        border_capacity = bk_grow_capacity(border_capacity, border_count + 2);
        border_edges = bk_realloc(border_edges, sizeof(uint32_t) * border_capacity);
      }
      border_edges[border_count++] = (uint32_t)(uses.keys[s] >> 32);
      border_edges[border_count++] = (uint32_t)uses.keys[s];
    }
    bk_index_map_free(&uses);
    // Enough levels for about two vertices per noise wave, at most
    // BK_CELL_NOISE_MAX_LEVELS (each level makes up to four times the triangles).
    int levels = (int)fmin(ceil(bk_log2(fmax(longest * frequency * 2.0, 1.0))), BK_CELL_NOISE_MAX_LEVELS);
    levels = levels < 0 ? 0 : (levels > max_levels ? max_levels : levels);
    uint32_t first_point = cx->count;
    for (int l = 0; l < levels; ++l) {
      refine(&nf, &a, &b);
      tri_list t = a;
      a = b;
      b = t;
    }
    // Push the new points: never more than a quarter of their distance to
    // the border (no fold at it) nor a tenth of the face's size (no cell
    // turned inside out).
    double limit = fmin(amplitude, 0.1 * sqrt(area));
    for (uint32_t v = first_point; v < cx->count; ++v) {
      bk_vec3 p = cx->points[v];
      double to_border = INFINITY;
      for (uint32_t e = 0; e < border_count; e += 2)
        to_border = fmin(
            to_border, distance_to_segment(p, cx->points[border_edges[e]], cx->points[border_edges[e + 1]]));
      double n = stb_perlin_noise3_seed((float)(p.x * frequency + offset), (float)(p.y * frequency),
                                        (float)(p.z * frequency), 0, 0, 0, noise_seed);
      double push = fmax(fmin(n * limit, 0.25 * to_border), -0.25 * to_border);
      cx->points[v] = bk_v3_add(p, bk_v3_scale(face->normal, push));
    }
    face->first = all.count;
    for (uint32_t t = 0; t < a.count; ++t)
      push_tri(&all, a.v[3 * t], a.v[3 * t + 1], a.v[3 * t + 2]);
    face->count = a.count;
    bk_index_map_free(&nf.border);
    bk_index_map_free(&nf.midpoint);
  }
  bk_free(faces->triangles);
  faces->triangles = all.v;
  faces->triangle_count = all.count;
  faces->triangle_capacity = all.capacity;
  bk_free(a.v);
  bk_free(b.v);
  bk_free(border_edges);
}
