// Bonds of the cell patterns' trees. Every cut face is one tag, and both
// leaves it separates carry its triangles (opposite windings), so a bond is
// read straight off the leaves: the area, centroid and area-weighted normal
// of the triangles a leaf shares with another. A noisy (curved) face is
// measured as the triangles it is, not as a plane.
#include <stdlib.h>
#include <string.h>

#include "cap.h"

typedef struct face_part {
  uint32_t tag, leaf;
  double area;
  bk_vec3 centroid_area; // centroid x area
  bk_vec3 normal_area;   // normal x area
} face_part;

static int compare_parts(const void* pa, const void* pb) {
  const face_part *a = pa, *b = pb;
  if (a->tag != b->tag) return a->tag < b->tag ? -1 : 1;
  return a->leaf < b->leaf ? -1 : (a->leaf > b->leaf);
}

static int compare_bonds(const void* pa, const void* pb) {
  const bk_bond *a = pa, *b = pb;
  if (a->leaf_a != b->leaf_a) return a->leaf_a < b->leaf_a ? -1 : 1;
  return a->leaf_b < b->leaf_b ? -1 : (a->leaf_b > b->leaf_b);
}

void bk_cell_tree_compute_bonds(bk_mesh_tree* tree) {
  free(tree->bonds);
  tree->bonds = NULL;
  tree->bond_count = 0;
  face_part* parts = NULL;
  uint32_t count = 0, capacity = 0;
  for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf) {
    const bk_mesh* m = &bk_mesh_tree_leaf(tree, leaf)->mesh;
    uint32_t start = count;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      uint32_t tag = m->tags[t];
      if (tag == 0 || tag >= BK_SOURCE_FACE_TAG) continue;
      bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)],
              b = m->positions[bk_mesh_tri_position(m, t, 1)],
              c = m->positions[bk_mesh_tri_position(m, t, 2)];
      bk_vec3 cross = bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
      double area = 0.5 * bk_v3_length(cross);
      bk_vec3 centroid = bk_v3_scale(bk_v3_add(a, bk_v3_add(b, c)), 1.0 / 3.0);
      // Triangles of one face are usually consecutive: extend the last part.
      face_part* last = count > start ? &parts[count - 1] : NULL;
      if (!last || last->tag != tag) {
        if (count == capacity) {
          capacity = bk_grow_capacity(capacity, count + 1);
          parts = bk_realloc(parts, sizeof(face_part) * capacity);
        }
        parts[count++] = (face_part){.tag = tag, .leaf = leaf};
        last = &parts[count - 1];
      }
      last->area += area;
      last->centroid_area = bk_v3_add(last->centroid_area, bk_v3_scale(centroid, area));
      last->normal_area = bk_v3_add(last->normal_area, bk_v3_scale(cross, 0.5));
    }
  }
  if (count) qsort(parts, count, sizeof(face_part), compare_parts);
  // Merge runs of one (tag, leaf), then pair the two leaves of each tag.
  uint32_t merged = 0;
  for (uint32_t i = 0; i < count; ++i) {
    if (merged && parts[merged - 1].tag == parts[i].tag && parts[merged - 1].leaf == parts[i].leaf) {
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
  for (uint32_t i = 0; i + 1 < merged; ++i) {
    if (parts[i].tag != parts[i + 1].tag) continue;
    if (i + 2 < merged && parts[i + 2].tag == parts[i].tag) continue; // a face on three leaves: corrupt
    const face_part* a = &parts[i];
    double normal_length = bk_v3_length(a->normal_area);
    if (!(a->area > 0.0) || !(normal_length > 0.0)) continue;
    if (bond_count == bond_capacity) {
      bond_capacity = bk_grow_capacity(bond_capacity, bond_count + 1);
      bonds = bk_realloc(bonds, sizeof(bk_bond) * bond_capacity);
    }
    bonds[bond_count++] = (bk_bond){.leaf_a = a->leaf,
                                    .leaf_b = parts[i + 1].leaf,
                                    .area = a->area,
                                    .centroid = a->centroid_area,
                                    .normal = a->normal_area};
    i++;
  }
  free(parts);
  // One bond per leaf pair: several faces between two leaves add up.
  if (bond_count) qsort(bonds, bond_count, sizeof(bk_bond), compare_bonds);
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
