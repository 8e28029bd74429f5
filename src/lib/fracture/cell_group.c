// The cells' solids grouped into the leaves of a cell-pattern tree: a
// cell's triangles may form several separate solids (atoms); atoms are
// merged, smallest first into the neighbour they share most face with, down
// to the pieces asked for (cut-out: by region first); the leaves are the
// merged groups.
#include <stdlib.h>
#include <string.h>

#include "cell_stages.h"

typedef struct uf {
  uint32_t* parent;
} uf;

static uint32_t uf_find(uint32_t* parent, uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// Triangles of every cell: surface fans and both sides of every cut face.
static void collect_triangles(const bk_cell_complex* cx, const bk_cell_surface* surfaces,
                              const bk_cell_faces* faces, uint32_t cells, bk_cell_parts* parts) {
  uint32_t total = faces->triangle_count * 2;
  for (uint32_t c = 0; c < cells; ++c)
    for (uint32_t q = 0; q < surfaces[c].polygon_count; ++q)
      total += surfaces[c].polygons[q].count - 2;
  parts->tris = bk_alloc(sizeof(bk_cell_tri) * (total ? total : 1));
  parts->cell_start = bk_calloc(cells + 1, sizeof(uint32_t));
  // Faces by cell, both sides.
  uint32_t* face_start = bk_calloc(cells + 1, sizeof(uint32_t));
  for (uint32_t f = 0; f < faces->count; ++f) {
    face_start[faces->faces[f].a + 1]++;
    face_start[faces->faces[f].b + 1]++;
  }
  for (uint32_t c = 0; c < cells; ++c)
    face_start[c + 1] += face_start[c];
  uint32_t* face_of = bk_alloc(sizeof(uint32_t) * (2 * faces->count + 1));
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * (cells + 1));
  memcpy(fill, face_start, sizeof(uint32_t) * (cells + 1));
  for (uint32_t f = 0; f < faces->count; ++f) {
    face_of[fill[faces->faces[f].a]++] = f;
    face_of[fill[faces->faces[f].b]++] = f;
  }
  bk_free(fill);
  uint32_t n = 0;
  for (uint32_t c = 0; c < cells; ++c) {
    parts->cell_start[c] = n;
    const bk_cell_surface* s = &surfaces[c];
    for (uint32_t q = 0; q < s->polygon_count; ++q) {
      const bk_cell_polygon* p = &s->polygons[q];
      const uint32_t* v = s->vertices + p->first;
      for (uint32_t k = 1; k + 1 < p->count; ++k)
        parts->tris[n++] = (bk_cell_tri){{v[0], v[k], v[k + 1]}, c, p->triangle, 0, 0};
    }
    for (uint32_t i = face_start[c]; i < face_start[c + 1]; ++i) {
      const bk_cell_face* f = &faces->faces[face_of[i]];
      bool reversed = f->b == c;
      for (uint32_t t = 0; t < f->count; ++t) {
        const uint32_t* v = faces->triangles + 3 * (f->first + t);
        bk_cell_tri tri = {
            {v[0], reversed ? v[2] : v[1], reversed ? v[1] : v[2]}, c, face_of[i], 1, reversed};
        parts->tris[n++] = tri;
      }
    }
  }
  parts->cell_start[cells] = n;
  parts->tri_count = n;
  bk_free(face_start);
  bk_free(face_of);
  (void)cx;
}

static void add_moments(const bk_cell_complex* cx, const bk_cell_tri* t, double m[4]) {
  bk_vec3 a = cx->points[t->v[0]], b = cx->points[t->v[1]], c = cx->points[t->v[2]];
  double v = bk_v3_dot(a, bk_v3_cross(b, c)) / 6.0;
  m[0] += v;
  m[1] += v * (a.x + b.x + c.x) / 4.0;
  m[2] += v * (a.y + b.y + c.y) / 4.0;
  m[3] += v * (a.z + b.z + c.z) / 4.0;
}

// Atoms: the separate solids of each cell (triangles joined through shared
// vertices).
static void find_atoms(const bk_cell_complex* cx, uint32_t cells, bk_cell_parts* parts) {
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * (cx->count ? cx->count : 1));
  uint32_t* atom_of_root = bk_alloc(sizeof(uint32_t) * (cx->count ? cx->count : 1));
  uint32_t* stamp = bk_alloc(sizeof(uint32_t) * (cx->count ? cx->count : 1));
  memset(stamp, 0xff, sizeof(uint32_t) * cx->count);
  parts->tri_atom = bk_alloc(sizeof(uint32_t) * (parts->tri_count ? parts->tri_count : 1));
  for (uint32_t c = 0; c < cells; ++c) {
    uint32_t begin = parts->cell_start[c], end = parts->cell_start[c + 1];
    for (uint32_t t = begin; t < end; ++t)
      for (int k = 0; k < 3; ++k) {
        uint32_t v = parts->tris[t].v[k];
        if (stamp[v] != c) stamp[v] = c, parent[v] = v, atom_of_root[v] = UINT32_MAX;
      }
    for (uint32_t t = begin; t < end; ++t) {
      uint32_t r0 = uf_find(parent, parts->tris[t].v[0]);
      for (int k = 1; k < 3; ++k) {
        uint32_t r = uf_find(parent, parts->tris[t].v[k]);
        if (r != r0) parent[r] = r0;
      }
    }
    for (uint32_t t = begin; t < end; ++t) {
      uint32_t r = uf_find(parent, parts->tris[t].v[0]);
      if (atom_of_root[r] == UINT32_MAX) {
        if (parts->atom_count == parts->atom_capacity) {
          parts->atom_capacity = bk_grow_capacity(parts->atom_capacity, parts->atom_count + 1);
          parts->atoms = bk_realloc(parts->atoms, sizeof(bk_cell_atom) * parts->atom_capacity);
        }
        atom_of_root[r] = parts->atom_count;
        parts->atoms[parts->atom_count++] = (bk_cell_atom){.cell = c};
      }
      parts->tri_atom[t] = atom_of_root[r];
      add_moments(cx, &parts->tris[t], parts->atoms[atom_of_root[r]].moments);
    }
  }
  bk_free(parent);
  bk_free(atom_of_root);
  bk_free(stamp);
}

typedef struct contact {
  uint32_t a, b; // atoms, a < b
  double area;
} contact;

static int compare_contacts(const void* pa, const void* pb) {
  const contact *a = pa, *b = pb;
  if (a->a != b->a) return a->a < b->a ? -1 : 1;
  return a->b < b->b ? -1 : (a->b > b->b);
}

// Atom pairs that share cut-face area, and how much. The two sides of a face
// triangle are found by position: a face's triangles are listed in the same
// order in both of its cells.
static void find_contacts(const bk_cell_complex* cx, const bk_cell_faces* faces, bk_cell_parts* parts) {
  // First triangle of each face in each of its two cells.
  uint32_t* first_in_a = bk_alloc(sizeof(uint32_t) * (faces->count + 1));
  uint32_t* first_in_b = bk_alloc(sizeof(uint32_t) * (faces->count + 1));
  for (uint32_t t = 0; t < parts->tri_count; ++t) {
    const bk_cell_tri* tri = &parts->tris[t];
    if (!tri->is_face) continue;
    uint32_t f = tri->origin;
    bool first = t == 0 || !parts->tris[t - 1].is_face || parts->tris[t - 1].origin != f ||
                 parts->tris[t - 1].cell != tri->cell;
    if (!first) continue;
    if (tri->reversed)
      first_in_b[f] = t;
    else
      first_in_a[f] = t;
  }
  parts->twin = bk_alloc(sizeof(uint32_t) * (parts->tri_count ? parts->tri_count : 1));
  memset(parts->twin, 0xff, sizeof(uint32_t) * parts->tri_count);
  contact* list = bk_alloc(sizeof(contact) * (faces->triangle_count + 1));
  uint32_t n = 0;
  for (uint32_t f = 0; f < faces->count; ++f)
    for (uint32_t k = 0; k < faces->faces[f].count; ++k) {
      uint32_t ta = first_in_a[f] + k, tb = first_in_b[f] + k;
      parts->twin[ta] = tb;
      parts->twin[tb] = ta;
      uint32_t a = parts->tri_atom[ta], b = parts->tri_atom[tb];
      const uint32_t* v = parts->tris[ta].v;
      double area = 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(cx->points[v[1]], cx->points[v[0]]),
                                                   bk_v3_sub(cx->points[v[2]], cx->points[v[0]])));
      list[n++] = (contact){a < b ? a : b, a < b ? b : a, area};
    }
  bk_free(first_in_a);
  bk_free(first_in_b);
  if (n) bk_sort(list, n, sizeof(contact), compare_contacts);
  uint32_t unique = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (unique && list[unique - 1].a == list[i].a && list[unique - 1].b == list[i].b)
      list[unique - 1].area += list[i].area;
    else
      list[unique++] = list[i];
  }
  parts->contacts_a = bk_alloc(sizeof(uint32_t) * (unique + 1));
  parts->contacts_b = bk_alloc(sizeof(uint32_t) * (unique + 1));
  parts->contact_area = bk_alloc(sizeof(double) * (unique + 1));
  for (uint32_t i = 0; i < unique; ++i) {
    parts->contacts_a[i] = list[i].a;
    parts->contacts_b[i] = list[i].b;
    parts->contact_area[i] = list[i].area;
  }
  parts->contact_count = unique;
  bk_free(list);
}

static bk_vec3 atom_centroid(const bk_cell_atom* a) {
  return a->moments[0] != 0.0 ? bk_v3(a->moments[1] / a->moments[0], a->moments[2] / a->moments[0],
                                      a->moments[3] / a->moments[0])
                              : bk_v3(0, 0, 0);
}

// Atom pairs that must be one piece: for each pair of cells whose cut face
// was left out (faces->joined), the atoms of the two that share a vertex.
// Two cells share only the vertices of their common face, so these are the
// atoms the missing face would have closed; their union is closed without
// it. Returns the count of pairs in *out (2 atoms each).
static uint32_t joined_atoms(const bk_cell_complex* cx, const bk_cell_faces* faces,
                             const bk_cell_parts* parts, uint32_t** out) {
  *out = NULL;
  if (faces->joined_count == 0) return 0;
  uint32_t* stamp = bk_alloc(sizeof(uint32_t) * (cx->count ? cx->count : 1));
  uint32_t* atom_at = bk_alloc(sizeof(uint32_t) * (cx->count ? cx->count : 1));
  memset(stamp, 0xff, sizeof(uint32_t) * cx->count);
  uint32_t count = 0, capacity = 0;
  for (uint32_t i = 0; i < faces->joined_count; ++i) {
    uint32_t a = faces->joined[2 * i], b = faces->joined[2 * i + 1];
    for (uint32_t t = parts->cell_start[a]; t < parts->cell_start[a + 1]; ++t)
      for (int k = 0; k < 3; ++k) {
        stamp[parts->tris[t].v[k]] = i;
        atom_at[parts->tris[t].v[k]] = parts->tri_atom[t];
      }
    for (uint32_t t = parts->cell_start[b]; t < parts->cell_start[b + 1]; ++t)
      for (int k = 0; k < 3; ++k) {
        uint32_t v = parts->tris[t].v[k];
        if (stamp[v] != i) continue;
        uint32_t pair[2] = {atom_at[v], parts->tri_atom[t]};
        if (count && (*out)[2 * count - 2] == pair[0] && (*out)[2 * count - 1] == pair[1]) continue;
        if (count == capacity) {
          capacity = bk_grow_capacity(capacity, count + 1);
          *out = bk_realloc(*out, sizeof(uint32_t) * 2 * capacity);
        }
        (*out)[2 * count] = pair[0];
        (*out)[2 * count + 1] = pair[1];
        count++;
      }
  }
  bk_free(stamp);
  bk_free(atom_at);
  return count;
}

// Puts groups a and b together (the lower root stays); false when they
// already are one.
static bool join_groups(uint32_t* parent, double* volume, bk_vec3* centroid, uint32_t a, uint32_t b) {
  uint32_t ra = uf_find(parent, a), rb = uf_find(parent, b);
  if (ra == rb) return false;
  if (rb < ra) {
    uint32_t t = ra;
    ra = rb;
    rb = t;
  }
  parent[rb] = ra;
  volume[ra] += volume[rb];
  centroid[ra] = bk_v3_scale(
      bk_v3_add(bk_v3_scale(centroid[ra], volume[ra] - volume[rb]), bk_v3_scale(centroid[rb], volume[rb])),
      1.0 / volume[ra]);
  return true;
}

// Joins the atoms that must be one piece (`joined`, `joined_count` pairs),
// and touching atoms of one label (when there are labels), then merges the
// smallest groups into their neighbours down to `target`. Fills
// parts->atom_leaf and parts->leaf_count.
static void group_atoms(bk_cell_parts* parts, uint32_t target, const uint32_t* cell_label,
                        const uint32_t* joined, uint32_t joined_count) {
  uint32_t n = parts->atom_count;
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * (n ? n : 1));
  double* volume = bk_alloc(sizeof(double) * (n ? n : 1));
  bk_vec3* centroid = bk_alloc(sizeof(bk_vec3) * (n ? n : 1));
  for (uint32_t i = 0; i < n; ++i) {
    parent[i] = i;
    volume[i] = parts->atoms[i].moments[0];
    centroid[i] = atom_centroid(&parts->atoms[i]);
  }
  uint32_t groups = n;
  if (joined_count) {
    // An atom that lost its face is open, and its moments mean nothing on
    // their own: a group's are the sum of its atoms', face left out.
    for (uint32_t i = 0; i < joined_count; ++i)
      if (join_groups(parent, volume, centroid, joined[2 * i], joined[2 * i + 1])) groups--;
    double* sums = bk_calloc(4 * (size_t)n, sizeof(double));
    for (uint32_t i = 0; i < n; ++i)
      for (int k = 0; k < 4; ++k)
        sums[4 * (size_t)uf_find(parent, i) + k] += parts->atoms[i].moments[k];
    for (uint32_t i = 0; i < n; ++i)
      if (uf_find(parent, i) == i) {
        const double* m = sums + 4 * (size_t)i;
        volume[i] = m[0];
        centroid[i] = m[0] != 0.0 ? bk_v3(m[1] / m[0], m[2] / m[0], m[3] / m[0]) : bk_v3(0, 0, 0);
      }
    bk_free(sums);
  }
  if (cell_label) {
    for (uint32_t i = 0; i < parts->contact_count; ++i) {
      uint32_t a = parts->contacts_a[i], b = parts->contacts_b[i];
      if (cell_label[parts->atoms[a].cell] != cell_label[parts->atoms[b].cell]) continue;
      if (join_groups(parent, volume, centroid, a, b)) groups--;
    }
  }
  {
    bk_heap heap = {0};
    for (uint32_t i = 0; i < n; ++i)
      if (uf_find(parent, i) == i) bk_heap_push(&heap, volume[i], i);
    double* shared = bk_calloc(n ? n : 1, sizeof(double));
    uint32_t* touched = bk_alloc(sizeof(uint32_t) * (n ? n : 1));
    while (groups > target && heap.count) {
      bk_heap_item item = bk_heap_pop(&heap);
      uint32_t g = item.value;
      if (uf_find(parent, g) != g || item.key != volume[g]) continue; // merged or grown since
      // The neighbour group sharing the most face with g, else the nearest.
      uint32_t touched_count = 0, best = UINT32_MAX;
      for (uint32_t i = 0; i < parts->contact_count; ++i) {
        uint32_t ra = uf_find(parent, parts->contacts_a[i]), rb = uf_find(parent, parts->contacts_b[i]);
        if ((ra == g) == (rb == g)) continue;
        uint32_t other = ra == g ? rb : ra;
        if (shared[other] == 0.0) touched[touched_count++] = other;
        shared[other] += parts->contact_area[i];
      }
      for (uint32_t i = 0; i < touched_count; ++i) {
        uint32_t o = touched[i];
        if (best == UINT32_MAX || shared[o] > shared[best] || (shared[o] == shared[best] && o < best))
          best = o;
      }
      for (uint32_t i = 0; i < touched_count; ++i)
        shared[touched[i]] = 0.0;
      if (best == UINT32_MAX) {
        double best_d = INFINITY;
        for (uint32_t i = 0; i < n; ++i) {
          if (uf_find(parent, i) != i || i == g) continue;
          double d = bk_v3_length(bk_v3_sub(centroid[i], centroid[g]));
          if (d < best_d) best_d = d, best = i;
        }
      }
      if (best == UINT32_MAX) break;
      double v = volume[g] + volume[best];
      centroid[best] = bk_v3_scale(
          bk_v3_add(bk_v3_scale(centroid[best], volume[best]), bk_v3_scale(centroid[g], volume[g])), 1.0 / v);
      parent[g] = best;
      volume[best] = v;
      groups--;
      bk_heap_push(&heap, v, best);
    }
    bk_free(shared);
    bk_free(touched);
    bk_heap_free(&heap);
  }
  // Leaves numbered by their lowest atom.
  parts->atom_leaf = bk_alloc(sizeof(uint32_t) * (n ? n : 1));
  uint32_t* leaf_of_root = bk_alloc(sizeof(uint32_t) * (n ? n : 1));
  memset(leaf_of_root, 0xff, sizeof(uint32_t) * n);
  parts->leaf_count = 0;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t r = uf_find(parent, i);
    if (leaf_of_root[r] == UINT32_MAX) leaf_of_root[r] = parts->leaf_count++;
    parts->atom_leaf[i] = leaf_of_root[r];
  }
  bk_free(leaf_of_root);
  bk_free(parent);
  bk_free(volume);
  bk_free(centroid);
}

bool bk_cell_group(bk_cell_build* b, uint32_t target, const uint32_t* cell_label) {
  collect_triangles(&b->cx, b->surfaces, &b->faces, b->cells, &b->parts);
  find_atoms(&b->cx, b->cells, &b->parts);
  find_contacts(&b->cx, &b->faces, &b->parts);
  uint32_t* joined = NULL;
  uint32_t joined_count = joined_atoms(&b->cx, &b->faces, &b->parts, &joined);
  group_atoms(&b->parts, target, cell_label, joined, joined_count);
  bk_free(joined);
  return true;
}
