// Repair of almost-closed input: each boundary loop of an open mesh is
// triangulated in its own best-fit plane (Newell normal) by the cap
// triangulator, so a mesh with simple holes becomes watertight.
#include <stdlib.h>
#include <string.h>

#include "cap.h"

int bk_mesh_fill_holes(bk_mesh* m, bk_error* err) {
  bk_closure closure = bk_mesh_check_closure(m);
  if (closure.overused_edges || closure.degenerate_edges)
    return bk_error_set(err,
                        "%u edges are used twice in one direction (non-manifold or inconsistent winding)",
                        closure.overused_edges + closure.degenerate_edges),
           -1;
  if (closure.open_edges == 0) return 0;

  // Open directed edges a->b; the fill must run b->a along them.
  bk_index_map edges = {0};
  bk_index_map_init(&edges, 3u * m->triangle_count);
  bool inserted = false;
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (int k = 0; k < 3; ++k)
      bk_index_map_insert(
          &edges,
          bk_directed_edge_key(bk_mesh_tri_position(m, t, k), bk_mesh_tri_position(m, t, (k + 1) % 3)), t,
          &inserted);
  uint32_t open_count = 0;
  uint32_t* next_of = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u)); // fill edge b -> a, keyed by b
  memset(next_of, 0xff, sizeof(uint32_t) * m->position_count);
  // The material of the triangle along each open edge, keyed as next_of: a
  // filled hole takes the source material of the surface around it.
  uint8_t* material_of = bk_calloc(m->position_count + 1u, 1);
  bool branching = false;
  for (uint32_t s = 0; s < edges.capacity; ++s) {
    uint64_t key = edges.keys[s];
    if (key == UINT64_MAX) continue;
    uint32_t a = (uint32_t)(key >> 32), b = (uint32_t)key;
    if (bk_index_map_find(&edges, bk_directed_edge_key(b, a))) continue;
    if (next_of[b] != UINT32_MAX) branching = true;
    next_of[b] = a;
    material_of[b] = m->materials[edges.values[s]];
    open_count++;
  }
  bk_index_map_free(&edges);
  if (branching) {
    bk_free(next_of);
    bk_free(material_of);
    return bk_error_set(err, "holes touch each other at a vertex (not simple loops)"), -1;
  }

  bk_cap* cap = bk_cap_create();
  uint32_t* loop = bk_alloc(sizeof(uint32_t) * (open_count + 1u));
  uint32_t* local_edges = bk_alloc(sizeof(uint32_t) * 2u * (open_count + 1u));
  double* xy = bk_alloc(sizeof(double) * 2u * (open_count + 1u));
  int filled = 0;
  bool ok = true;
  for (uint32_t start = 0; start < m->position_count && ok; ++start) {
    if (next_of[start] == UINT32_MAX) continue;
    uint32_t n = 0;
    for (uint32_t v = start; v != UINT32_MAX && next_of[v] != UINT32_MAX && n <= open_count;) {
      loop[n++] = v;
      uint32_t next = next_of[v];
      next_of[v] = UINT32_MAX; // consumed
      v = next;
    }
    if (n < 3 || loop[0] != start) {
      ok = bk_error_set(err, "a hole boundary is not a closed loop");
      break;
    }
    // Newell's normal gives the loop's best-fit plane even when it is not flat.
    bk_vec3 normal = {0};
    for (uint32_t i = 0; i < n; ++i) {
      bk_vec3 p = m->positions[loop[i]], q = m->positions[loop[(i + 1) % n]];
      normal = bk_v3_add(
          normal, bk_v3((p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x), (p.x - q.x) * (p.y + q.y)));
    }
    normal = bk_v3_normalize(normal);
    bk_vec3 u, v;
    bk_plane_basis(bk_v3_length(normal) > 0 ? normal : bk_v3(0, 0, 1), &u, &v);
    for (uint32_t i = 0; i < n; ++i) {
      xy[2 * i] = bk_v3_dot(m->positions[loop[i]], u);
      xy[2 * i + 1] = bk_v3_dot(m->positions[loop[i]], v);
      local_edges[2 * i] = i;
      local_edges[2 * i + 1] = (i + 1) % n;
    }
    const uint32_t* tris = NULL;
    uint32_t tri_count = 0;
    bk_error cap_err = {0};
    if (!bk_cap_triangulate(cap, local_edges, n, xy, n, &tris, &tri_count, &cap_err)) {
      ok = bk_error_set(err, "cannot fill a hole of %u edges: %s", n, cap_err.message);
      break;
    }
    uint32_t first = m->corner_count;
    for (uint32_t i = 0; i < n; ++i) {
      bk_corner c = {0};
      c.position = loop[i];
      c.normal[0] = (float)normal.x, c.normal[1] = (float)normal.y, c.normal[2] = (float)normal.z;
      c.uv[0] = (float)xy[2 * i], c.uv[1] = (float)xy[2 * i + 1];
      c.tangent[0] = (float)u.x, c.tangent[1] = (float)u.y, c.tangent[2] = (float)u.z, c.tangent[3] = 1.0f;
      bk_mesh_add_corner(m, &c);
    }
    for (uint32_t t = 0; t < tri_count; ++t)
      bk_mesh_add_triangle(m, first + tris[3 * t], first + tris[3 * t + 1], first + tris[3 * t + 2],
                           bk_material_id(bk_material_source(material_of[start]), false), 0);
    filled++;
  }
  bk_free(loop);
  bk_free(material_of);
  bk_free(local_edges);
  bk_free(xy);
  bk_free(next_of);
  bk_cap_destroy(cap);
  if (!ok) return -1;
  if (!bk_mesh_is_closed(m))
    return bk_error_set(err, "mesh is still open after filling %d holes", filled), -1;
  return filled;
}
