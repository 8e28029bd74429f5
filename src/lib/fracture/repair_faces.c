// Face-level repairs of a source before fracture (bk_mesh_repair): faces
// given twice, patches of faces wound against the surface around them, and
// shells that enclose no volume. Each of them otherwise splits off a closed
// sheet (a face and its own back) that encloses nothing, and such a sheet
// became a "watertight" fragment of zero volume.
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

// Rebuilds `m` from the triangles with keep[t] set, with only the corners
// and positions they use (in their first order), so that bounds and sizes
// see no trace of what was dropped.
static void keep_triangles(bk_mesh* m, const uint8_t* keep) {
  bk_mesh out = {0};
  uint32_t* corner_map = bk_alloc(sizeof(uint32_t) * (m->corner_count + 1u));
  uint32_t* position_map = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  memset(corner_map, 0xff, sizeof(uint32_t) * (m->corner_count + 1u));
  memset(position_map, 0xff, sizeof(uint32_t) * (m->position_count + 1u));
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    if (!keep[t]) continue;
    uint32_t c[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      uint32_t old = m->indices[3 * t + k];
      if (corner_map[old] == UINT32_MAX) {
        bk_corner corner = m->corners[old];
        uint32_t p = corner.position;
        if (position_map[p] == UINT32_MAX) position_map[p] = bk_mesh_add_position(&out, m->positions[p]);
        corner.position = position_map[p];
        corner_map[old] = bk_mesh_add_corner(&out, &corner);
      }
      c[k] = corner_map[old];
    }
    bk_mesh_add_triangle(&out, c[0], c[1], c[2], m->materials ? m->materials[t] : 0,
                         m->tags ? m->tags[t] : 0);
  }
  bk_free(corner_map);
  bk_free(position_map);
  bk_mesh_free(m);
  *m = out;
}

// A triangle's positions rotated so the smallest comes first: the same
// triangle listed from another corner gets the same key.
static void canonical(const bk_mesh* m, uint32_t t, uint32_t p[3]) {
  uint32_t a = bk_mesh_tri_position(m, t, 0), b = bk_mesh_tri_position(m, t, 1),
           c = bk_mesh_tri_position(m, t, 2);
  if (b < a && b < c)
    p[0] = b, p[1] = c, p[2] = a;
  else if (c < a && c < b)
    p[0] = c, p[1] = a, p[2] = b;
  else
    p[0] = a, p[1] = b, p[2] = c;
}

static int compare_triples(const void* pa, const void* pb) {
  const uint32_t *a = pa, *b = pb;
  for (int k = 0; k < 4; ++k) // positions, then the triangle (the first kept)
    if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
  return 0;
}

uint32_t bk_mesh_remove_duplicate_triangles(bk_mesh* m) {
  uint32_t n = m->triangle_count;
  uint32_t* rows = bk_alloc(sizeof(uint32_t) * 4 * (n + 1u));
  for (uint32_t t = 0; t < n; ++t) {
    canonical(m, t, rows + 4 * t);
    rows[4 * t + 3] = t;
  }
  if (n) bk_sort(rows, n, 4 * sizeof(uint32_t), compare_triples);
  uint8_t* keep = bk_alloc(n + 1u);
  memset(keep, 1, n + 1u);
  uint32_t removed = 0;
  for (uint32_t i = 1; i < n; ++i)
    if (memcmp(rows + 4 * i, rows + 4 * (i - 1), 3 * sizeof(uint32_t)) == 0)
      keep[rows[4 * i + 3]] = 0, removed++;
  bk_free(rows);
  if (removed) keep_triangles(m, keep);
  bk_free(keep);
  return removed;
}

uint32_t bk_mesh_turn_flipped_patches(bk_mesh* m) {
  uint32_t n = m->triangle_count;
  // Every undirected edge: how many triangle sides use it, and the first two.
  bk_index_map edges = {0};
  bk_index_map_init(&edges, 3u * n);
  uint32_t* uses = bk_calloc(3u * n + 1u, sizeof(uint32_t));
  uint32_t* side = bk_alloc(sizeof(uint32_t) * 2 * (3u * n + 1u)); // 3 t + k of the first two uses
  uint32_t edge_count = 0;
  for (uint32_t t = 0; t < n; ++t)
    for (uint32_t k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      bool inserted = false;
      uint32_t* e = bk_index_map_insert(&edges, bk_directed_edge_key(a < b ? a : b, a < b ? b : a),
                                        edge_count, &inserted);
      if (inserted) edge_count++;
      if (uses[*e] < 2) side[2 * *e + uses[*e]] = 3 * t + k;
      uses[*e]++;
    }
  bk_index_map_free(&edges);
  // Patches: triangles joined across edges of two uses that they wind
  // oppositely (consistently). Conflicts: edges of two uses wound alike.
  uint32_t* patch = bk_alloc(sizeof(uint32_t) * (n + 1u));
  for (uint32_t t = 0; t < n; ++t)
    patch[t] = t;
  uint32_t conflicts = 0;
  for (uint32_t e = 0; e < edge_count; ++e) {
    if (uses[e] != 2) continue; // open, or shells meeting: left to the split and the hole filler
    uint32_t s0 = side[2 * e], s1 = side[2 * e + 1];
    uint32_t t0 = s0 / 3, t1 = s1 / 3;
    uint32_t from0 = bk_mesh_tri_position(m, t0, s0 % 3), from1 = bk_mesh_tri_position(m, t1, s1 % 3);
    if (from0 == from1) {
      conflicts++;
      continue;
    }
    uint32_t r0 = find_root(patch, t0), r1 = find_root(patch, t1);
    if (r0 != r1) patch[r0 > r1 ? r0 : r1] = r0 < r1 ? r0 : r1;
  }
  uint32_t turned = 0;
  if (conflicts) {
    // Two patches across a conflict must be wound oppositely: colour the
    // graph of patches in two (breadth first from the lowest triangle), and
    // in each group turn the colour of less area. A group that cannot be
    // coloured (a one-sided surface) is left as it is, for the closure check.
    uint32_t* colour = bk_alloc(sizeof(uint32_t) * (n + 1u)); // per root: 0/1, UINT32_MAX unseen
    memset(colour, 0xff, sizeof(uint32_t) * (n + 1u));
    // Conflict edges by patch root: the adjacency of the patch graph.
    uint32_t* start = bk_calloc(n + 2u, sizeof(uint32_t));
    uint32_t* next = bk_alloc(sizeof(uint32_t) * (2u * conflicts + 1u));
    for (uint32_t e = 0; e < edge_count; ++e) {
      if (uses[e] != 2) continue;
      uint32_t s0 = side[2 * e], s1 = side[2 * e + 1];
      if (bk_mesh_tri_position(m, s0 / 3, s0 % 3) != bk_mesh_tri_position(m, s1 / 3, s1 % 3)) continue;
      start[find_root(patch, s0 / 3) + 1]++;
      start[find_root(patch, s1 / 3) + 1]++;
    }
    for (uint32_t t = 0; t < n; ++t)
      start[t + 1] += start[t];
    uint32_t* fill = bk_alloc(sizeof(uint32_t) * (n + 1u));
    memcpy(fill, start, sizeof(uint32_t) * (n + 1u));
    for (uint32_t e = 0; e < edge_count; ++e) {
      if (uses[e] != 2) continue;
      uint32_t s0 = side[2 * e], s1 = side[2 * e + 1];
      if (bk_mesh_tri_position(m, s0 / 3, s0 % 3) != bk_mesh_tri_position(m, s1 / 3, s1 % 3)) continue;
      uint32_t r0 = find_root(patch, s0 / 3), r1 = find_root(patch, s1 / 3);
      next[fill[r0]++] = r1;
      next[fill[r1]++] = r0;
    }
    bk_free(fill);
    double* area = bk_calloc(n + 1u, sizeof(double));
    for (uint32_t t = 0; t < n; ++t) {
      bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)],
              b = m->positions[bk_mesh_tri_position(m, t, 1)],
              c = m->positions[bk_mesh_tri_position(m, t, 2)];
      area[find_root(patch, t)] += 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a)));
    }
    uint32_t* queue = bk_alloc(sizeof(uint32_t) * (n + 1u));
    uint8_t* turn_root = bk_calloc(n + 1u, 1);
    for (uint32_t r = 0; r < n; ++r) {
      if (find_root(patch, r) != r || colour[r] != UINT32_MAX || start[r] == start[r + 1]) continue;
      uint32_t head = 0, tail = 0;
      bool two_coloured = true;
      double colour_area[2] = {0.0, 0.0};
      colour[r] = 0;
      queue[tail++] = r;
      while (head < tail) {
        uint32_t p = queue[head++];
        colour_area[colour[p]] += area[p];
        for (uint32_t i = start[p]; i < start[p + 1]; ++i) {
          uint32_t q = next[i];
          if (colour[q] == UINT32_MAX) {
            colour[q] = 1 - colour[p];
            queue[tail++] = q;
          } else if (colour[q] == colour[p]) {
            two_coloured = false;
          }
        }
      }
      if (!two_coloured) continue;
      // The lesser area is the one wound against the rest (ties: the colour
      // of the group's first patch stays).
      uint32_t turn = colour_area[1] <= colour_area[0] ? 1 : 0;
      for (uint32_t i = 0; i < tail; ++i)
        if (colour[queue[i]] == turn) turn_root[queue[i]] = 1;
    }
    for (uint32_t t = 0; t < n; ++t) {
      if (!turn_root[find_root(patch, t)]) continue;
      uint32_t swap = m->indices[3 * t + 1];
      m->indices[3 * t + 1] = m->indices[3 * t + 2];
      m->indices[3 * t + 2] = swap;
      turned++;
    }
    bk_free(queue);
    bk_free(turn_root);
    bk_free(area);
    bk_free(start);
    bk_free(next);
    bk_free(colour);
  }
  bk_free(patch);
  bk_free(uses);
  bk_free(side);
  return turned;
}

bool bk_mesh_encloses_no_volume(const bk_mesh* m, double volume) {
  bk_aabb box = bk_mesh_bounds(m);
  double size = bk_v3_length(bk_v3_sub(box.max, box.min));
  return !(fabs(volume) > BK_FRACTURE_MIN_THICKNESS * bk_mesh_area(m) * size);
}

uint32_t bk_mesh_remove_sheets(bk_mesh* m, bk_vec3* where) {
  uint32_t n = m->triangle_count;
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  for (uint32_t i = 0; i < m->position_count; ++i)
    parent[i] = i;
  for (uint32_t t = 0; t < n; ++t)
    for (uint32_t k = 1; k < 3; ++k) {
      uint32_t a = find_root(parent, bk_mesh_tri_position(m, t, 0)),
               b = find_root(parent, bk_mesh_tri_position(m, t, k));
      if (a != b) parent[a > b ? a : b] = a < b ? a : b;
    }
  // Per shell (by its root position): signed volume, area and bounds.
  uint32_t p_count = m->position_count;
  double* volume = bk_calloc(p_count + 1u, sizeof(double));
  double* area = bk_calloc(p_count + 1u, sizeof(double));
  bk_aabb* box = bk_alloc(sizeof(bk_aabb) * (p_count + 1u));
  for (uint32_t i = 0; i < p_count; ++i)
    box[i] = (bk_aabb){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (uint32_t t = 0; t < n; ++t) {
    uint32_t r = find_root(parent, bk_mesh_tri_position(m, t, 0));
    bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)], b = m->positions[bk_mesh_tri_position(m, t, 1)],
            c = m->positions[bk_mesh_tri_position(m, t, 2)];
    volume[r] += bk_v3_dot(a, bk_v3_cross(b, c)) / 6.0;
    area[r] += 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a)));
    box[r].min = bk_v3_min(box[r].min, bk_v3_min(a, bk_v3_min(b, c)));
    box[r].max = bk_v3_max(box[r].max, bk_v3_max(a, bk_v3_max(b, c)));
  }
  // The same measure as a whole source's (bk_mesh_repair): a shell whose
  // volume is below BK_FRACTURE_MIN_THICKNESS x its area x its size
  // encloses nothing; its volume is relative to the origin, which cancels
  // for a closed shell. Inward shells (cavities) have real negative volume.
  uint8_t* sheet = bk_calloc(p_count + 1u, 1);
  uint32_t sheets = 0;
  bool solid = false;
  for (uint32_t t = 0; t < n; ++t) {
    uint32_t r = find_root(parent, bk_mesh_tri_position(m, t, 0));
    if (sheet[r] || area[r] < 0.0) continue; // seen (area < 0 marks a solid seen)
    double size = bk_v3_length(bk_v3_sub(box[r].max, box[r].min));
    if (fabs(volume[r]) <= BK_FRACTURE_MIN_THICKNESS * area[r] * size) {
      sheet[r] = 1;
      if (sheets++ == 0 && where) *where = bk_v3_scale(bk_v3_add(box[r].min, box[r].max), 0.5);
    } else {
      area[r] = -1.0;
      solid = true;
    }
  }
  // All of it a sheet: the caller refuses the source as a whole.
  if (sheets && solid) {
    uint8_t* keep = bk_alloc(n + 1u);
    for (uint32_t t = 0; t < n; ++t)
      keep[t] = !sheet[find_root(parent, bk_mesh_tri_position(m, t, 0))];
    keep_triangles(m, keep);
    bk_free(keep);
  }
  bk_free(parent);
  bk_free(volume);
  bk_free(area);
  bk_free(box);
  bk_free(sheet);
  return solid ? sheets : 0;
}
