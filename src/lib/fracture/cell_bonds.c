// Bonds of the cell patterns' trees. Every cut face is one tag, and both
// leaves it separates carry its triangles (opposite windings, the same
// positions), so a bond is read straight off the leaves: the area, centroid
// and area-weighted normal of the triangles a leaf shares with another. A
// noisy (curved) face is measured as the triangles it is, not as a plane.
// One face (one tag) can cross the source more than once (a cut-out prism
// through both sides of a torus) and so separate different leaves in
// different places: each triangle counts only towards the leaf that carries
// the same triangle, never towards every leaf with that tag.
#include <stdlib.h>
#include <string.h>

#include "cap.h"

typedef struct face_part {
  uint32_t tag, leaf, partner;
  double area;
  bk_vec3 centroid_area; // centroid x area
  bk_vec3 normal_area;   // normal x area
} face_part;

static int compare_parts(const void* pa, const void* pb) {
  const face_part *a = pa, *b = pb;
  if (a->tag != b->tag) return a->tag < b->tag ? -1 : 1;
  if (a->leaf != b->leaf) return a->leaf < b->leaf ? -1 : 1;
  return a->partner < b->partner ? -1 : (a->partner > b->partner);
}

// One cut-face triangle of one leaf, by its tag and its three positions in
// a fixed order (the other leaf's copy winds the other way).
typedef struct face_triangle {
  uint32_t tag, leaf, triangle;
  bk_vec3 p[3];
} face_triangle;

static int compare_positions(bk_vec3 a, bk_vec3 b) {
  if (a.x != b.x) return a.x < b.x ? -1 : 1;
  if (a.y != b.y) return a.y < b.y ? -1 : 1;
  return a.z < b.z ? -1 : (a.z > b.z);
}

static int compare_triangles(const void* pa, const void* pb) {
  const face_triangle *a = pa, *b = pb;
  if (a->tag != b->tag) return a->tag < b->tag ? -1 : 1;
  for (int k = 0; k < 3; ++k) {
    int c = compare_positions(a->p[k], b->p[k]);
    if (c) return c;
  }
  if (a->leaf != b->leaf) return a->leaf < b->leaf ? -1 : 1;
  return a->triangle < b->triangle ? -1 : (a->triangle > b->triangle);
}

static bool is_cut_face(uint32_t tag) { return tag != 0 && tag < BK_SOURCE_FACE_TAG; }

// The leaf across each cut-face triangle: partners[first[leaf] + t] for
// triangle t of a leaf, BK_NULL_INDEX where no other leaf carries it.
static uint32_t* triangle_partners(const bk_mesh_tree* tree, uint32_t* first) {
  uint32_t total = 0;
  for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf) {
    first[leaf] = total;
    total += bk_mesh_tree_leaf(tree, leaf)->mesh.triangle_count;
  }
  uint32_t* partners = bk_alloc(sizeof(uint32_t) * (total ? total : 1u));
  for (uint32_t i = 0; i < total; ++i)
    partners[i] = BK_NULL_INDEX;
  face_triangle* list = NULL;
  uint32_t count = 0, capacity = 0;
  for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf) {
    const bk_mesh* m = &bk_mesh_tree_leaf(tree, leaf)->mesh;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if (!is_cut_face(m->tags[t])) continue;
      if (count == capacity) {
        capacity = bk_grow_capacity(capacity, count + 1);
        list = bk_realloc(list, sizeof(face_triangle) * capacity);
      }
      face_triangle* f = &list[count++];
      *f = (face_triangle){.tag = m->tags[t], .leaf = leaf, .triangle = t};
      for (int k = 0; k < 3; ++k)
        f->p[k] = m->positions[bk_mesh_tri_position(m, t, k)];
      // Sort the three corners (a triangle has no orientation here).
      for (int i = 1; i < 3; ++i)
        for (int j = i; j > 0 && compare_positions(f->p[j - 1], f->p[j]) > 0; --j) {
          bk_vec3 swap = f->p[j];
          f->p[j] = f->p[j - 1];
          f->p[j - 1] = swap;
        }
    }
  }
  if (count) bk_sort(list, count, sizeof(face_triangle), compare_triangles);
  for (uint32_t i = 0; i < count;) {
    uint32_t end = i + 1;
    while (end < count && list[end].tag == list[i].tag &&
           compare_positions(list[end].p[0], list[i].p[0]) == 0 &&
           compare_positions(list[end].p[1], list[i].p[1]) == 0 &&
           compare_positions(list[end].p[2], list[i].p[2]) == 0)
      ++end;
    // Exactly two leaves share a triangle; anything else is no contact.
    if (end == i + 2 && list[i].leaf != list[i + 1].leaf) {
      partners[first[list[i].leaf] + list[i].triangle] = list[i + 1].leaf;
      partners[first[list[i + 1].leaf] + list[i + 1].triangle] = list[i].leaf;
    }
    i = end;
  }
  bk_free(list);
  return partners;
}

static int compare_bonds(const void* pa, const void* pb) {
  const bk_bond *a = pa, *b = pb;
  if (a->leaf_a != b->leaf_a) return a->leaf_a < b->leaf_a ? -1 : 1;
  return a->leaf_b < b->leaf_b ? -1 : (a->leaf_b > b->leaf_b);
}

void bk_cell_tree_compute_bonds(bk_mesh_tree* tree) {
  bk_free(tree->bonds);
  tree->bonds = NULL;
  tree->bond_count = 0;
  uint32_t* first = bk_alloc(sizeof(uint32_t) * (tree->leaf_count + 1u));
  uint32_t* partners = triangle_partners(tree, first);
  face_part* parts = NULL;
  uint32_t count = 0, capacity = 0;
  for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf) {
    const bk_mesh* m = &bk_mesh_tree_leaf(tree, leaf)->mesh;
    uint32_t start = count;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      uint32_t tag = m->tags[t], partner = partners[first[leaf] + t];
      if (!is_cut_face(tag) || partner == BK_NULL_INDEX) continue;
      bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)],
              b = m->positions[bk_mesh_tri_position(m, t, 1)],
              c = m->positions[bk_mesh_tri_position(m, t, 2)];
      bk_vec3 cross = bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
      double area = 0.5 * bk_v3_length(cross);
      bk_vec3 centroid = bk_v3_scale(bk_v3_add(a, bk_v3_add(b, c)), 1.0 / 3.0);
      // Triangles of one face are usually consecutive: extend the last part.
      face_part* last = count > start ? &parts[count - 1] : NULL;
      if (!last || last->tag != tag || last->partner != partner) {
        if (count == capacity) {
          capacity = bk_grow_capacity(capacity, count + 1);
          parts = bk_realloc(parts, sizeof(face_part) * capacity);
        }
        parts[count++] = (face_part){.tag = tag, .leaf = leaf, .partner = partner};
        last = &parts[count - 1];
      }
      last->area += area;
      last->centroid_area = bk_v3_add(last->centroid_area, bk_v3_scale(centroid, area));
      last->normal_area = bk_v3_add(last->normal_area, bk_v3_scale(cross, 0.5));
    }
  }
  bk_free(partners);
  bk_free(first);
  if (count) bk_sort(parts, count, sizeof(face_part), compare_parts);
  // Merge runs of one (tag, leaf, partner); the lower leaf's side of each
  // pair makes the bond.
  uint32_t merged = 0;
  for (uint32_t i = 0; i < count; ++i) {
    if (merged && parts[merged - 1].tag == parts[i].tag && parts[merged - 1].leaf == parts[i].leaf &&
        parts[merged - 1].partner == parts[i].partner) {
      face_part* p = &parts[merged - 1];
      p->area += parts[i].area;
      p->centroid_area = bk_v3_add(p->centroid_area, parts[i].centroid_area);
      p->normal_area = bk_v3_add(p->normal_area, parts[i].normal_area);
    } else {
      parts[merged++] = parts[i];
    }
  }
  bk_bond* bonds = NULL;
  uint32_t bond_count = 0, bond_capacity = 0;
  for (uint32_t i = 0; i < merged; ++i) {
    if (parts[i].leaf > parts[i].partner) continue; // the partner's side
    const face_part* a = &parts[i];
    double normal_length = bk_v3_length(a->normal_area);
    if (!(a->area > 0.0) || !(normal_length > 0.0)) continue;
    if (bond_count == bond_capacity) {
      bond_capacity = bk_grow_capacity(bond_capacity, bond_count + 1);
      bonds = bk_realloc(bonds, sizeof(bk_bond) * bond_capacity);
    }
    bonds[bond_count++] = (bk_bond){.leaf_a = a->leaf,
                                    .leaf_b = a->partner,
                                    .area = a->area,
                                    .centroid = a->centroid_area,
                                    .normal = a->normal_area};
  }
  bk_free(parts);
  // One bond per leaf pair: several faces between two leaves add up.
  if (bond_count) bk_sort(bonds, bond_count, sizeof(bk_bond), compare_bonds);
  uint32_t unique = 0;
  for (uint32_t i = 0; i < bond_count; ++i) {
    if (unique && bonds[unique - 1].leaf_a == bonds[i].leaf_a &&
        bonds[unique - 1].leaf_b == bonds[i].leaf_b) {
      bk_bond* b = &bonds[unique - 1];
      b->area += bonds[i].area;
      b->centroid = bk_v3_add(b->centroid, bonds[i].centroid);
      b->normal = bk_v3_add(b->normal, bonds[i].normal);
    } else {
      bonds[unique++] = bonds[i];
    }
  }
  for (uint32_t i = 0; i < unique; ++i) {
    bk_bond* b = &bonds[i];
    b->centroid = bk_v3_scale(b->centroid, 1.0 / b->area);
    double n = bk_v3_length(b->normal);
    b->normal = n > 0.0 ? bk_v3_scale(b->normal, 1.0 / n) : bk_v3(0, 0, 1);
  }
  tree->bonds = bonds;
  tree->bond_count = unique;
}
