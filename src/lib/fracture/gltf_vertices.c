// The vertices of a glTF export: a node's mesh corners, placed relative to
// its centre of mass, with unit normals and tangents, welded. The cell
// patterns give every triangle its own three corners, so a Voronoi piece's
// corners repeat each vertex about six times; corners whose exported
// attributes are bit-identical become one vertex (a third of the file).
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "gltf_internal.h"

static void normalize3(float v[3], const float fallback[3]) {
  double l = sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
  if (!(l > 1e-20)) {
    memcpy(v, fallback, 3 * sizeof(float));
    return;
  }
  for (int k = 0; k < 3; ++k)
    v[k] = (float)(v[k] / l);
}

// The attributes a corner exports.
static void corner_vertex(const bk_mesh* m, uint32_t corner, bk_vec3 centroid,
                          float out[BK_GLTF_VERTEX_FLOATS]) {
  const bk_corner* c = &m->corners[corner];
  bk_vec3 p = bk_v3_sub(m->positions[c->position], centroid);
  static const float up[3] = {0, 0, 1}, right[3] = {1, 0, 0};
  float normal[3] = {c->normal[0], c->normal[1], c->normal[2]};
  normalize3(normal, up);
  float tangent[4] = {c->tangent[0], c->tangent[1], c->tangent[2], c->tangent[3] < 0 ? -1.0f : 1.0f};
  normalize3(tangent, fabsf(normal[0]) < 0.9f ? right : up);
  out[0] = (float)p.x;
  out[1] = (float)p.y;
  out[2] = (float)p.z;
  memcpy(out + 3, normal, sizeof normal);
  memcpy(out + 6, c->uv, 2 * sizeof(float));
  memcpy(out + 8, tangent, sizeof tangent);
}

static uint64_t hash_vertex(const float v[BK_GLTF_VERTEX_FLOATS]) {
  uint8_t bytes[BK_GLTF_VERTEX_FLOATS * sizeof(float)];
  memcpy(bytes, v, sizeof bytes);
  uint64_t h = 1469598103934665603ull; // FNV-1a
  for (size_t i = 0; i < sizeof bytes; ++i)
    h = (h ^ bytes[i]) * 1099511628211ull;
  return h;
}

void bk_gltf_weld(const bk_mesh* m, bk_vec3 centroid, gltf_vertices* out) {
  memset(out, 0, sizeof *out);
  uint32_t n = m->corner_count;
  out->data = bk_alloc(sizeof(float) * BK_GLTF_VERTEX_FLOATS * (n ? n : 1));
  out->of_corner = bk_alloc(sizeof(uint32_t) * (n ? n : 1));
  // Open addressing, at most half full: slot = vertex + 1, 0 = empty.
  size_t slots = 16;
  while (slots < 2 * (size_t)n)
    slots *= 2;
  uint32_t* table = bk_calloc(slots, sizeof(uint32_t));
  for (uint32_t i = 0; i < n; ++i) {
    float* v = out->data + (size_t)out->count * BK_GLTF_VERTEX_FLOATS;
    corner_vertex(m, i, centroid, v);
    size_t s = (size_t)hash_vertex(v) & (slots - 1);
    for (;; s = (s + 1) & (slots - 1)) {
      if (!table[s]) {
        table[s] = ++out->count; // a new vertex, already in place
        out->of_corner[i] = out->count - 1;
        break;
      }
      const float* w = out->data + (size_t)(table[s] - 1) * BK_GLTF_VERTEX_FLOATS;
      if (memcmp(w, v, sizeof(float) * BK_GLTF_VERTEX_FLOATS) == 0) {
        out->of_corner[i] = table[s] - 1;
        break;
      }
    }
  }
  bk_free(table);
}

void bk_gltf_vertices_free(gltf_vertices* v) {
  bk_free(v->data);
  bk_free(v->of_corner);
  memset(v, 0, sizeof *v);
}
