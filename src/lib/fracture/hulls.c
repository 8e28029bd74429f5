// Hull separation: connected components by shared position index
// (union-find). An inward-facing component (negative volume) is a cavity and
// stays with the smallest solid that encloses it.
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

static uint32_t find_root(uint32_t* parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

double bk_mesh_winding_number(const bk_mesh* m, const uint32_t* tri_component, uint32_t component,
                              bk_vec3 q) {
  double total = 0.0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    if (tri_component && tri_component[t] != component) continue;
    bk_vec3 a = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 0)], q);
    bk_vec3 b = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 1)], q);
    bk_vec3 c = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 2)], q);
    double la = bk_v3_length(a), lb = bk_v3_length(b), lc = bk_v3_length(c);
    double num = bk_v3_dot(a, bk_v3_cross(b, c));
    double den = la * lb * lc + bk_v3_dot(a, b) * lc + bk_v3_dot(b, c) * la + bk_v3_dot(c, a) * lb;
    total += 2.0 * bk_atan2(num, den);
  }
  return total / (4.0 * 3.14159265358979323846);
}

// parent[] (one per position) joins the positions of every triangle: the
// roots name the connected components; the smaller index wins, so the roots
// do not depend on the order of the unions.
static void union_triangles(const bk_mesh* m, uint32_t* parent) {
  for (uint32_t i = 0; i < m->position_count; ++i)
    parent[i] = i;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    uint32_t r0 = find_root(parent, bk_mesh_tri_position(m, t, 0));
    for (int k = 1; k < 3; ++k) {
      uint32_t r = find_root(parent, bk_mesh_tri_position(m, t, k));
      if (r != r0) parent[r > r0 ? r : r0] = r < r0 ? r : r0;
      r0 = r < r0 ? r : r0;
    }
  }
}

bool bk_mesh_is_connected_with(const bk_mesh* m, bk_topology_scratch* s) {
  if (m->position_count + 1u > s->position_capacity) {
    s->position_capacity = bk_grow_capacity(s->position_capacity, m->position_count + 1u);
    s->start = bk_realloc(s->start, sizeof(uint32_t) * s->position_capacity);
    s->mark = bk_realloc(s->mark, sizeof(uint32_t) * s->position_capacity);
  }
  uint32_t* parent = s->mark;
  union_triangles(m, parent);
  uint32_t root = m->triangle_count ? find_root(parent, bk_mesh_tri_position(m, 0, 0)) : 0;
  for (uint32_t t = 1; t < m->triangle_count; ++t)
    if (find_root(parent, bk_mesh_tri_position(m, t, 0)) != root) return false;
  return true;
}

uint32_t bk_mesh_split_hulls(bk_mesh* m, bk_mesh** out) {
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  union_triangles(m, parent);
  // Number components in order of first triangle.
  uint32_t* component_of_root = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  memset(component_of_root, 0xff, sizeof(uint32_t) * m->position_count);
  uint32_t* tri_component = bk_alloc(sizeof(uint32_t) * (m->triangle_count + 1u));
  uint32_t components = 0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    uint32_t r = find_root(parent, bk_mesh_tri_position(m, t, 0));
    if (component_of_root[r] == UINT32_MAX) component_of_root[r] = components++;
    tri_component[t] = component_of_root[r];
  }
  // Signed volume of each component decides solid (> 0) or cavity (< 0).
  double* volume = bk_calloc(components, sizeof(double));
  uint32_t* first_position = bk_alloc(sizeof(uint32_t) * components);
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
    bk_vec3 b = m->positions[bk_mesh_tri_position(m, t, 1)];
    bk_vec3 c = m->positions[bk_mesh_tri_position(m, t, 2)];
    volume[tri_component[t]] += bk_v3_dot(a, bk_v3_cross(b, c)) / 6.0;
    first_position[tri_component[t]] = bk_mesh_tri_position(m, t, 0);
  }
  uint32_t solids = 0, largest = 0;
  for (uint32_t k = 0; k < components; ++k) {
    if (volume[k] > 0.0) solids++;
    if (volume[k] > volume[largest]) largest = k;
  }
  if (solids <= 1) {
    // One solid (with or without cavities): nothing to separate.
    bk_free(parent);
    bk_free(component_of_root);
    bk_free(tri_component);
    bk_free(volume);
    bk_free(first_position);
    *out = bk_alloc(sizeof(bk_mesh));
    (*out)[0] = *m;
    memset(m, 0, sizeof *m);
    return 1;
  }
  // Solids become outputs in component order; each cavity joins the smallest
  // solid that encloses it (the largest if none does, which a closed,
  // non-self-intersecting mesh never produces).
  uint32_t* output_of = bk_alloc(sizeof(uint32_t) * components);
  uint32_t next_output = 0;
  for (uint32_t k = 0; k < components; ++k)
    output_of[k] = volume[k] > 0.0 ? next_output++ : UINT32_MAX;
  for (uint32_t k = 0; k < components; ++k) {
    if (volume[k] > 0.0) continue;
    uint32_t best = largest;
    for (uint32_t j = 0; j < components; ++j) {
      if (!(volume[j] > 0.0) || volume[j] >= volume[best]) continue;
      if (bk_mesh_winding_number(m, tri_component, j, m->positions[first_position[k]]) > 0.5) best = j;
    }
    output_of[k] = output_of[best];
  }

  *out = bk_calloc(solids, sizeof(bk_mesh));
  uint32_t* pos_map = parent; // reuse: parent is no longer needed
  memset(pos_map, 0xff, sizeof(uint32_t) * m->position_count);
  uint32_t* corner_map = bk_alloc(sizeof(uint32_t) * (m->corner_count + 1u));
  memset(corner_map, 0xff, sizeof(uint32_t) * m->corner_count);
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_mesh* dst = &(*out)[output_of[tri_component[t]]];
    uint32_t c[3];
    for (int k = 0; k < 3; ++k) {
      uint32_t sc = m->indices[3 * t + k];
      if (corner_map[sc] == UINT32_MAX) {
        bk_corner corner = m->corners[sc];
        if (pos_map[corner.position] == UINT32_MAX)
          pos_map[corner.position] = bk_mesh_add_position(dst, m->positions[corner.position]);
        corner.position = pos_map[corner.position];
        corner_map[sc] = bk_mesh_add_corner(dst, &corner);
      }
      c[k] = corner_map[sc];
    }
    bk_mesh_add_triangle(dst, c[0], c[1], c[2], m->materials[t], m->tags[t]);
  }
  bk_free(parent);
  bk_free(corner_map);
  bk_free(component_of_root);
  bk_free(tri_component);
  bk_free(volume);
  bk_free(first_position);
  bk_free(output_of);
  bk_mesh_free(m);
  return solids;
}
