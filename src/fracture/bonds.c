// Bonds between leaves that truly touch. Every cap triangle is tagged with
// the cut that made it; two leaves touch when their caps of one cut face
// opposite ways and overlap with positive area. The overlap is measured
// exactly by clipping the cap triangles against each other in the cut plane,
// which gives the contact's area and centroid (not bounding-box overlap).
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

typedef struct cap_entry {
  uint32_t cut;  // node whose split made the cap
  uint32_t side; // 0: leaf lies below the cut (cap faces +n), 1: above
  uint32_t leaf;
  uint32_t triangle;
} cap_entry;

typedef struct tri2 {
  double p[3][2]; // counter-clockwise in the cut plane's (u, v) coordinates
  double min[2], max[2];
} tri2;

typedef struct leaf_group {
  uint32_t leaf;
  uint32_t first, count; // range in the projected triangle array
  double min[2], max[2];
} leaf_group;

static int compare_entries(const void* pa, const void* pb) {
  const cap_entry *a = pa, *b = pb;
  if (a->cut != b->cut) return a->cut < b->cut ? -1 : 1;
  if (a->side != b->side) return a->side < b->side ? -1 : 1;
  if (a->leaf != b->leaf) return a->leaf < b->leaf ? -1 : 1;
  return a->triangle < b->triangle ? -1 : (a->triangle > b->triangle);
}

static int compare_groups_by_min_x(const void* pa, const void* pb) {
  const leaf_group *a = pa, *b = pb;
  if (a->min[0] != b->min[0]) return a->min[0] < b->min[0] ? -1 : 1;
  return a->leaf < b->leaf ? -1 : (a->leaf > b->leaf);
}

static int compare_bonds(const void* pa, const void* pb) {
  const bk_bond *a = pa, *b = pb;
  if (a->leaf_a != b->leaf_a) return a->leaf_a < b->leaf_a ? -1 : 1;
  return a->leaf_b < b->leaf_b ? -1 : (a->leaf_b > b->leaf_b);
}

static bool boxes_overlap(const double amin[2], const double amax[2], const double bmin[2],
                          const double bmax[2]) {
  return amin[0] <= bmax[0] && bmin[0] <= amax[0] && amin[1] <= bmax[1] && bmin[1] <= amax[1];
}

// Clips polygon `in` (n vertices) to the left of the directed line a->b.
static int clip_half_plane(const double (*in)[2], int n, const double a[2], const double b[2],
                           double (*out)[2]) {
  int m = 0;
  double ex = b[0] - a[0], ey = b[1] - a[1];
  for (int i = 0; i < n; ++i) {
    const double* p = in[i];
    const double* q = in[(i + 1) % n];
    double dp = ex * (p[1] - a[1]) - ey * (p[0] - a[0]);
    double dq = ex * (q[1] - a[1]) - ey * (q[0] - a[0]);
    if (dp >= 0.0) out[m][0] = p[0], out[m][1] = p[1], m++;
    if ((dp >= 0.0) != (dq >= 0.0)) {
      double t = dp / (dp - dq);
      out[m][0] = p[0] + (q[0] - p[0]) * t;
      out[m][1] = p[1] + (q[1] - p[1]) * t;
      m++;
    }
  }
  return m;
}

// Area and area-weighted centroid sums of the intersection of two CCW triangles.
static double overlap(const tri2* a, const tri2* b, double* cx, double* cy) {
  double buf0[12][2], buf1[12][2];
  memcpy(buf0, a->p, sizeof a->p);
  int n = 3;
  for (int e = 0; e < 3 && n >= 3; ++e) {
    n = clip_half_plane((const double(*)[2])buf0, n, b->p[e], b->p[(e + 1) % 3], buf1);
    memcpy(buf0, buf1, sizeof(double) * 2 * (size_t)n);
  }
  if (n < 3) return 0.0;
  double area2 = 0.0, sx = 0.0, sy = 0.0;
  for (int i = 0; i < n; ++i) {
    const double* p = buf0[i];
    const double* q = buf0[(i + 1) % n];
    double cross = p[0] * q[1] - q[0] * p[1];
    area2 += cross;
    sx += (p[0] + q[0]) * cross;
    sy += (p[1] + q[1]) * cross;
  }
  if (area2 <= 0.0) return 0.0;
  *cx += sx / 6.0;
  *cy += sy / 6.0;
  return area2 / 2.0;
}

static void project(const bk_mesh* mesh, uint32_t t, bk_vec3 u, bk_vec3 v, bool flip, tri2* out) {
  for (int k = 0; k < 3; ++k) {
    bk_vec3 p = mesh->positions[bk_mesh_tri_position(mesh, t, flip ? 2 - k : k)];
    out->p[k][0] = bk_v3_dot(p, u);
    out->p[k][1] = bk_v3_dot(p, v);
  }
  for (int a = 0; a < 2; ++a) {
    out->min[a] = fmin(out->p[0][a], fmin(out->p[1][a], out->p[2][a]));
    out->max[a] = fmax(out->p[0][a], fmax(out->p[1][a], out->p[2][a]));
  }
}

typedef struct bond_list {
  bk_bond* items;
  uint32_t count, capacity;
  bk_index_map index_of_pair;
} bond_list;

static void add_contact(bond_list* list, uint32_t below_leaf, uint32_t above_leaf, double area,
                        bk_vec3 centroid, bk_vec3 n) {
  uint32_t a = below_leaf < above_leaf ? below_leaf : above_leaf;
  uint32_t b = below_leaf < above_leaf ? above_leaf : below_leaf;
  bool inserted = false;
  uint32_t* slot = bk_index_map_insert(&list->index_of_pair, bk_edge_key(a, b), list->count, &inserted);
  if (inserted) {
    if (list->count == list->capacity) {
      list->capacity = bk_grow_capacity(list->capacity, list->count + 1);
      list->items = bk_realloc(list->items, sizeof(bk_bond) * list->capacity);
    }
    list->items[list->count++] = (bk_bond){a, b, area, centroid, a == below_leaf ? n : bk_v3_scale(n, -1.0)};
    return;
  }
  // Same pair over a second cut (only in degenerate trees): merge by area.
  bk_bond* bond = &list->items[*slot];
  double total = bond->area + area;
  bond->centroid =
      bk_v3_add(bk_v3_scale(bond->centroid, bond->area / total), bk_v3_scale(centroid, area / total));
  bond->area = total;
}

void bk_mesh_tree_compute_bonds(bk_mesh_tree* tree) {
  free(tree->bonds);
  tree->bonds = NULL;
  tree->bond_count = 0;
  if (tree->leaf_count < 2) return;

  // Gather every cap triangle of every leaf, keyed by its cut and side.
  uint32_t entry_count = 0, entry_capacity = 0;
  cap_entry* entries = NULL;
  for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf) {
    const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, leaf)->mesh;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
      uint32_t tag = mesh->tags[t];
      if (mesh->materials[t] != BK_MATERIAL_INTERIOR || tag == 0 || tag > tree->node_count) continue;
      bk_vec3 n = tree->nodes[tag - 1].plane.normal;
      bk_vec3 a = mesh->positions[bk_mesh_tri_position(mesh, t, 0)];
      bk_vec3 e = bk_v3_cross(bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, t, 1)], a),
                              bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, t, 2)], a));
      if (entry_count == entry_capacity) {
        entry_capacity = bk_grow_capacity(entry_capacity, entry_count + 1);
        entries = bk_realloc(entries, sizeof(cap_entry) * entry_capacity);
      }
      entries[entry_count++] = (cap_entry){tag - 1, bk_v3_dot(e, n) > 0.0 ? 0u : 1u, leaf, t};
    }
  }
  qsort(entries, entry_count, sizeof(cap_entry), compare_entries);

  bk_aabb root_box = tree->nodes[0].bounds;
  bk_vec3 diag = bk_v3_sub(root_box.max, root_box.min);
  double min_area = 1e-12 * bk_v3_dot(diag, diag); // below this an overlap is rounding noise
  bond_list list = {0};
  bk_index_map_init(&list.index_of_pair, tree->leaf_count * 4u);
  tri2* tris = bk_alloc(sizeof(tri2) * (entry_count + 1u));
  leaf_group* groups = bk_alloc(sizeof(leaf_group) * (entry_count + 1u));
  uint32_t* active[2] = {bk_alloc(sizeof(uint32_t) * (entry_count + 1u)),
                         bk_alloc(sizeof(uint32_t) * (entry_count + 1u))};

  for (uint32_t begin = 0; begin < entry_count;) {
    uint32_t cut = entries[begin].cut, end = begin;
    while (end < entry_count && entries[end].cut == cut)
      end++;
    bk_vec3 n = tree->nodes[cut].plane.normal, u, v;
    bk_plane_basis(n, &u, &v);
    // Project and group by leaf; above-side caps face -n, so flip them to CCW.
    uint32_t group_count = 0, below_groups = 0;
    for (uint32_t i = begin; i < end; ++i) {
      const cap_entry* e = &entries[i];
      project(&bk_mesh_tree_leaf(tree, e->leaf)->mesh, e->triangle, u, v, e->side == 1, &tris[i]);
      if (i == begin || e->leaf != entries[i - 1].leaf || e->side != entries[i - 1].side) {
        groups[group_count++] = (leaf_group){e->leaf, i, 0, {INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
        if (e->side == 0) below_groups = group_count;
      }
      leaf_group* g = &groups[group_count - 1];
      g->count++;
      for (int a = 0; a < 2; ++a)
        g->min[a] = fmin(g->min[a], tris[i].min[a]), g->max[a] = fmax(g->max[a], tris[i].max[a]);
    }
    // Sweep and prune along u: both sides sorted by min u; a group is tested
    // against the other side's groups still open at its start.
    qsort(groups, below_groups, sizeof(leaf_group), compare_groups_by_min_x);
    qsort(groups + below_groups, group_count - below_groups, sizeof(leaf_group), compare_groups_by_min_x);
    uint32_t next[2] = {0, below_groups}, end_of[2] = {below_groups, group_count};
    uint32_t active_count[2] = {0, 0};
    while (next[0] < end_of[0] || next[1] < end_of[1]) {
      int side =
          next[1] >= end_of[1] || (next[0] < end_of[0] && groups[next[0]].min[0] <= groups[next[1]].min[0])
              ? 0
              : 1;
      const leaf_group* g = &groups[next[side]++];
      // Drop the other side's groups that ended before this one starts.
      uint32_t* other = active[1 - side];
      uint32_t kept = 0;
      for (uint32_t i = 0; i < active_count[1 - side]; ++i) {
        const leaf_group* o = &groups[other[i]];
        if (o->max[0] < g->min[0]) continue;
        other[kept++] = other[i];
        if (o->min[1] > g->max[1] || g->min[1] > o->max[1]) continue;
        const leaf_group* gb = side == 0 ? g : o;
        const leaf_group* ga = side == 0 ? o : g;
        double area = 0.0, cx = 0.0, cy = 0.0;
        for (uint32_t a = gb->first; a < gb->first + gb->count; ++a)
          for (uint32_t b = ga->first; b < ga->first + ga->count; ++b)
            if (boxes_overlap(tris[a].min, tris[a].max, tris[b].min, tris[b].max))
              area += overlap(&tris[a], &tris[b], &cx, &cy);
        if (area <= min_area) continue;
        bk_vec3 centroid = bk_v3_add(bk_v3_scale(n, tree->nodes[cut].plane.offset),
                                     bk_v3_add(bk_v3_scale(u, cx / area), bk_v3_scale(v, cy / area)));
        add_contact(&list, gb->leaf, ga->leaf, area, centroid, n);
      }
      active_count[1 - side] = kept;
      active[side][active_count[side]++] = (uint32_t)(g - groups);
    }
    begin = end;
  }
  free(tris);
  free(groups);
  free(active[0]);
  free(active[1]);
  free(entries);
  bk_index_map_free(&list.index_of_pair);
  qsort(list.items, list.count, sizeof(bk_bond), compare_bonds);
  tree->bonds = list.items;
  tree->bond_count = list.count;
}
