// Bonds between leaves that truly touch. Every cap triangle is tagged with
// the cut that made it; two leaves touch when their caps of one cut face
// opposite ways and overlap with positive area. The overlap is measured
// exactly by clipping the caps against each other in the cut plane, which
// gives the contact's area and centroid (not bounding-box overlap). A leaf's
// cap on one cut is usually a single convex polygon, so it is clipped as one
// piece; other caps are clipped triangle by triangle. A noisy cap (pushed
// along the cut's normal) is a flat triangulation seen along the normal, and
// both sides' triangles are pieces of the same tilted triangles: each
// overlap is measured in the plane, then lifted onto its triangle (area
// over the cosine of its tilt, centroid onto its plane), so the contact is
// the rough surface the leaves share.
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

typedef struct cap_entry {
  uint32_t cut;  // node whose split made the cap
  uint32_t side; // 0: leaf lies below the cut (cap faces +n), 1: above
  uint32_t leaf;
  uint32_t triangle;
} cap_entry;

// A convex polygon, counter-clockwise in the cut plane's (u, v) coordinates.
typedef struct piece {
  uint32_t first, count; // range in the point array
  double min[2], max[2];
  bk_vec3 normal; // of the plane the piece lies in (the cut's, or a noisy cap triangle's), facing +n
  double level;   // that plane: normal . (p - origin) = level
} piece;

// One leaf's caps on one cut.
typedef struct leaf_group {
  uint32_t leaf;
  uint32_t first, count; // range in the piece array
  double min[2], max[2];
} leaf_group;

typedef struct scratch {
  double (*points)[2];
  uint32_t point_count, point_capacity;
  piece* pieces;
  uint32_t piece_count, piece_capacity;
  uint32_t* edges; // outline building: directed position edges of one group
  uint32_t edge_capacity;
  double (*clip[2])[2];
  uint32_t clip_capacity;
} scratch;

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
static uint32_t clip_half_plane(const double (*in)[2], uint32_t n, const double a[2], const double b[2],
                                double (*out)[2]) {
  uint32_t m = 0;
  double ex = b[0] - a[0], ey = b[1] - a[1];
  for (uint32_t i = 0; i < n; ++i) {
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

// Area of the intersection of two convex pieces in the plane; its first
// moments (area times centroid) go to (mx, my).
static double overlap(scratch* s, const piece* a, const piece* b, double* mx, double* my) {
  uint32_t need = 2u * (a->count + b->count) + 2u;
  if (need > s->clip_capacity) {
    s->clip_capacity = bk_grow_capacity(s->clip_capacity, need);
    for (int k = 0; k < 2; ++k)
      s->clip[k] = bk_realloc(s->clip[k], sizeof(double[2]) * s->clip_capacity);
  }
  memcpy(s->clip[0], s->points[a->first], sizeof(double[2]) * a->count);
  uint32_t n = a->count;
  int cur = 0;
  for (uint32_t e = 0; e < b->count && n >= 3; ++e) {
    n = clip_half_plane((const double(*)[2])s->clip[cur], n, s->points[b->first + e],
                        s->points[b->first + (e + 1) % b->count], s->clip[1 - cur]);
    cur = 1 - cur;
  }
  if (n < 3) return 0.0;
  double area2 = 0.0, sx = 0.0, sy = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    const double* p = s->clip[cur][i];
    const double* q = s->clip[cur][(i + 1) % n];
    double cross = p[0] * q[1] - q[0] * p[1];
    area2 += cross;
    sx += (p[0] + q[0]) * cross;
    sy += (p[1] + q[1]) * cross;
  }
  if (area2 <= 0.0) return 0.0;
  *mx = sx / 6.0;
  *my = sy / 6.0;
  return area2 / 2.0;
}

static void add_point(scratch* s, double x, double y) {
  if (s->point_count == s->point_capacity) {
    s->point_capacity = bk_grow_capacity(s->point_capacity, s->point_count + 1);
    s->points = bk_realloc(s->points, sizeof(double[2]) * s->point_capacity);
  }
  s->points[s->point_count][0] = x;
  s->points[s->point_count][1] = y;
  s->point_count++;
}

static void close_piece(scratch* s, uint32_t first, bk_vec3 normal, double level) {
  if (s->piece_count == s->piece_capacity) {
    s->piece_capacity = bk_grow_capacity(s->piece_capacity, s->piece_count + 1);
    s->pieces = bk_realloc(s->pieces, sizeof(piece) * s->piece_capacity);
  }
  piece* p = &s->pieces[s->piece_count++];
  *p = (piece){first, s->point_count - first, {INFINITY, INFINITY}, {-INFINITY, -INFINITY}, normal, level};
  for (uint32_t i = first; i < s->point_count; ++i)
    for (int a = 0; a < 2; ++a)
      p->min[a] = fmin(p->min[a], s->points[i][a]), p->max[a] = fmax(p->max[a], s->points[i][a]);
}

// The outline of a group's triangles as one convex loop, if it is one.
// Above-side caps face -n, so their loops are reversed to run CCW.
static bool add_convex_outline(scratch* s, const bk_mesh* mesh, const cap_entry* entries, uint32_t count,
                               bool flip, bk_vec3 origin, bk_vec3 u, bk_vec3 v, bk_vec3 cut_normal,
                               double height, double flat) {
  enum { MAX_TRIANGLES = 32 };
  if (count > MAX_TRIANGLES) return false;
  for (uint32_t i = 0; i < count; ++i) // a noisy cap goes triangle by triangle
    for (uint32_t k = 0; k < 3; ++k) {
      bk_vec3 p = bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, entries[i].triangle, k)], origin);
      if (!(fabs(bk_v3_dot(p, cut_normal) - height) <= flat)) return false;
    }
  uint32_t edge_count = 0;
  if (12u * count > s->edge_capacity) { // all edges, then the outline after them
    s->edge_capacity = bk_grow_capacity(s->edge_capacity, 12u * count);
    s->edges = bk_realloc(s->edges, sizeof(uint32_t) * s->edge_capacity);
  }
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t k = 0; k < 3; ++k) {
      s->edges[2 * edge_count] = bk_mesh_tri_position(mesh, entries[i].triangle, k);
      s->edges[2 * edge_count + 1] = bk_mesh_tri_position(mesh, entries[i].triangle, (k + 1) % 3);
      edge_count++;
    }
  // Keep the outline: edges whose reverse is not among them (few edges: quadratic is fine).
  uint32_t outline = 0;
  uint32_t* out = s->edges + 2u * edge_count;
  for (uint32_t e = 0; e < edge_count; ++e) {
    bool inner = false;
    for (uint32_t f = 0; f < edge_count && !inner; ++f)
      inner = s->edges[2 * f] == s->edges[2 * e + 1] && s->edges[2 * f + 1] == s->edges[2 * e];
    if (inner) continue;
    out[2 * outline] = s->edges[2 * e], out[2 * outline + 1] = s->edges[2 * e + 1];
    outline++;
  }
  // Every edge cancelled (triangles folded onto each other): the caps cover
  // no area, so the group adds no piece.
  if (outline < 3) return true;
  // Follow it from the first edge; it must be one loop using every edge.
  uint32_t first_point = s->point_count, used = 0, at = 0;
  for (;;) {
    bk_vec3 p = bk_v3_sub(mesh->positions[out[2 * at]], origin);
    add_point(s, bk_v3_dot(p, u), bk_v3_dot(p, v));
    used++;
    uint32_t next_vertex = out[2 * at + 1], next = UINT32_MAX;
    if (next_vertex == out[0]) break;
    for (uint32_t e = 0; e < outline && next == UINT32_MAX; ++e)
      if (out[2 * e] == next_vertex) next = e;
    if (next == UINT32_MAX || used > outline) break;
    at = next;
  }
  uint32_t n = s->point_count - first_point;
  if (used != outline || n < 3) {
    s->point_count = first_point;
    return false;
  }
  double(*pts)[2] = &s->points[first_point];
  if (flip)
    for (uint32_t i = 0; i < n / 2; ++i) {
      double tx = pts[i][0], ty = pts[i][1];
      pts[i][0] = pts[n - 1 - i][0], pts[i][1] = pts[n - 1 - i][1];
      pts[n - 1 - i][0] = tx, pts[n - 1 - i][1] = ty;
    }
  double scale = 0.0;
  for (uint32_t i = 0; i < n; ++i)
    scale = fmax(scale, fmax(fabs(pts[(i + 1) % n][0] - pts[i][0]), fabs(pts[(i + 1) % n][1] - pts[i][1])));
  for (uint32_t i = 0; i < n; ++i) {
    const double *a = pts[(i + n - 1) % n], *b = pts[i], *c = pts[(i + 1) % n];
    if ((b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < -1e-12 * scale * scale) {
      s->point_count = first_point; // reflex corner: not convex
      return false;
    }
  }
  close_piece(s, first_point, cut_normal, height);
  return true;
}

static void add_triangles(scratch* s, const bk_mesh* mesh, const cap_entry* entries, uint32_t count,
                          bool flip, bk_vec3 origin, bk_vec3 u, bk_vec3 v, bk_vec3 n, double height) {
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t first = s->point_count;
    bk_vec3 p[3];
    for (uint32_t k = 0; k < 3; ++k) {
      p[k] = bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, entries[i].triangle, flip ? 2 - k : k)],
                       origin);
      add_point(s, bk_v3_dot(p[k], u), bk_v3_dot(p[k], v));
    }
    // The triangle's own plane (the cut's when it is flat or degenerate).
    bk_vec3 e = bk_v3_cross(bk_v3_sub(p[1], p[0]), bk_v3_sub(p[2], p[0]));
    double length = bk_v3_length(e);
    bk_vec3 normal = length > 0.0 ? bk_v3_scale(e, 1.0 / length) : n;
    if (!(bk_v3_dot(normal, n) > 0.5)) normal = n; // pushes tilt a cap by far less
    double level = bk_v3_dot(normal, n) < 1.0 ? bk_v3_dot(normal, p[0]) : height;
    close_piece(s, first, normal, level);
  }
}

typedef struct bond_list {
  bk_bond* items;
  uint32_t count, capacity;
  bk_index_map index_of_pair;
  bool raw; // every contact kept as met (a thread's share), merged later in cut order
} bond_list;

static void append_bond(bond_list* list, bk_bond bond) {
  if (list->count == list->capacity) {
    list->capacity = bk_grow_capacity(list->capacity, list->count + 1);
    list->items = bk_realloc(list->items, sizeof(bk_bond) * list->capacity);
  }
  list->items[list->count++] = bond;
}

static void add_contact(bond_list* list, uint32_t below_leaf, uint32_t above_leaf, double area,
                        bk_vec3 centroid, bk_vec3 n) {
  uint32_t a = below_leaf < above_leaf ? below_leaf : above_leaf;
  uint32_t b = below_leaf < above_leaf ? above_leaf : below_leaf;
  bk_bond bond = {a, b, area, centroid, a == below_leaf ? n : bk_v3_scale(n, -1.0)};
  if (list->raw) {
    append_bond(list, bond);
    return;
  }
  bool inserted = false;
  uint32_t* slot = bk_index_map_insert(&list->index_of_pair, bk_edge_key(a, b), list->count, &inserted);
  if (inserted) {
    append_bond(list, bond);
    return;
  }
  // Same pair over a second cut (only in degenerate trees): merge by area.
  bk_bond* kept = &list->items[*slot];
  double total = kept->area + area;
  kept->centroid =
      bk_v3_add(bk_v3_scale(kept->centroid, kept->area / total), bk_v3_scale(centroid, area / total));
  kept->area = total;
}

// The bonds made by the caps of entries [first, last) (whole cuts), into `list`.
static void bond_cuts(const bk_mesh_tree* tree, const cap_entry* entries, uint32_t first, uint32_t last,
                      bond_list* list) {
  // Plane coordinates are taken relative to the tree's origin, so a mesh far
  // from the world origin measures its contacts as precisely as one at it.
  bk_vec3 origin = bk_mesh_tree_origin(tree);

  bk_aabb root_box = tree->nodes[0].bounds;
  bk_vec3 diag = bk_v3_sub(root_box.max, root_box.min);
  double min_area = 1e-12 * bk_v3_dot(diag, diag); // below this an overlap is rounding noise
  double flat = 1e-9 * bk_v3_length(diag);         // a cap this close to its cut's plane is flat
  scratch s = {0};
  uint32_t most = 1; // entries of one cut at most
  for (uint32_t begin = first, end = first; begin < last; begin = end) {
    while (end < last && entries[end].cut == entries[begin].cut)
      end++;
    most = end - begin > most ? end - begin : most;
  }
  leaf_group* groups = bk_alloc(sizeof(leaf_group) * (most + 1u));
  uint32_t* active[2] = {bk_alloc(sizeof(uint32_t) * (most + 1u)), bk_alloc(sizeof(uint32_t) * (most + 1u))};

  for (uint32_t begin = first; begin < last;) {
    uint32_t cut = entries[begin].cut, end = begin;
    while (end < last && entries[end].cut == cut)
      end++;
    bk_vec3 n = tree->nodes[cut].plane.normal, u, v;
    bk_plane_basis(n, &u, &v);
    double height = tree->nodes[cut].plane.offset - bk_v3_dot(n, origin);
    // One group of convex pieces per (side, leaf).
    s.point_count = s.piece_count = 0;
    uint32_t group_count = 0, below_groups = 0;
    for (uint32_t i = begin; i < end;) {
      uint32_t j = i;
      while (j < end && entries[j].leaf == entries[i].leaf && entries[j].side == entries[i].side)
        j++;
      const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, entries[i].leaf)->mesh;
      bool flip = entries[i].side == 1;
      uint32_t first_piece = s.piece_count;
      if (!add_convex_outline(&s, mesh, &entries[i], j - i, flip, origin, u, v, n, height, flat))
        add_triangles(&s, mesh, &entries[i], j - i, flip, origin, u, v, n, height);
      leaf_group* g = &groups[group_count++];
      *g = (leaf_group){entries[i].leaf,
                        first_piece,
                        s.piece_count - first_piece,
                        {INFINITY, INFINITY},
                        {-INFINITY, -INFINITY}};
      for (uint32_t k = first_piece; k < s.piece_count; ++k)
        for (int a = 0; a < 2; ++a)
          g->min[a] = fmin(g->min[a], s.pieces[k].min[a]), g->max[a] = fmax(g->max[a], s.pieces[k].max[a]);
      if (!flip) below_groups = group_count;
      i = j;
    }
    // Sweep and prune along u: both sides sorted by min u; a group is tested
    // against the other side's groups still open at its start.
    if (below_groups > 1) qsort(groups, below_groups, sizeof(leaf_group), compare_groups_by_min_x);
    if (group_count - below_groups > 1)
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
        // A leaf on both sides of one cut (a shell that wraps round the cut,
        // or a crafted file) touches itself there: that is no bond.
        if (o->leaf == g->leaf) continue;
        const leaf_group* gb = side == 0 ? g : o;
        const leaf_group* ga = side == 0 ? o : g;
        double area = 0.0;
        bk_vec3 moment = {0}, normal = {0};
        for (uint32_t a = gb->first; a < gb->first + gb->count; ++a)
          for (uint32_t b = ga->first; b < ga->first + ga->count; ++b) {
            if (!boxes_overlap(s.pieces[a].min, s.pieces[a].max, s.pieces[b].min, s.pieces[b].max)) continue;
            double mx = 0.0, my = 0.0, flat_area = overlap(&s, &s.pieces[a], &s.pieces[b], &mx, &my);
            if (!(flat_area > 0.0)) continue;
            // Lifted onto the plane the piece lies in (the cut's: no change).
            const piece* p = &s.pieces[a];
            double cosine = bk_v3_dot(p->normal, n);
            bk_vec3 at = bk_v3_add(bk_v3_scale(n, height),
                                   bk_v3_add(bk_v3_scale(u, mx / flat_area), bk_v3_scale(v, my / flat_area)));
            at = bk_v3_add(at, bk_v3_scale(n, (p->level - bk_v3_dot(p->normal, at)) / cosine));
            double true_area = flat_area / cosine;
            area += true_area;
            moment = bk_v3_add(moment, bk_v3_scale(at, true_area));
            normal = bk_v3_add(normal, bk_v3_scale(p->normal, true_area));
          }
        if (area <= min_area) continue;
        double normal_length = bk_v3_length(normal);
        add_contact(list, gb->leaf, ga->leaf, area, bk_v3_add(origin, bk_v3_scale(moment, 1.0 / area)),
                    normal_length > 0.0 ? bk_v3_scale(normal, 1.0 / normal_length) : n);
      }
      active_count[1 - side] = kept;
      active[side][active_count[side]++] = (uint32_t)(g - groups);
    }
    begin = end;
  }
  free(s.points);
  free(s.pieces);
  free(s.edges);
  free(s.clip[0]);
  free(s.clip[1]);
  free(groups);
  free(active[0]);
  free(active[1]);
}

// One thread's share of the cuts.
typedef struct bond_job {
  const bk_mesh_tree* tree;
  const cap_entry* entries;
  uint32_t first, last;
  bond_list list;
} bond_job;

static void* bond_work(void* arg) {
  bond_job* job = arg;
  bond_cuts(job->tree, job->entries, job->first, job->last, &job->list);
  return NULL;
}

// Bonds of every cut, on the tree's threads: each takes a run of whole cuts
// (about equal entry counts) and keeps its contacts as met; they are joined
// in cut order, so a pair met on several cuts is merged in the same order as
// on one thread and the bonds are the same bit for bit.
static void bond_all_cuts(const bk_mesh_tree* tree, const cap_entry* entries, uint32_t entry_count,
                          bond_list* list) {
  uint32_t threads = bk_fracture_thread_count(&tree->desc, entry_count, 4096);
  if (threads <= 1) {
    bond_cuts(tree, entries, 0, entry_count, list);
    return;
  }
  bond_job* jobs = bk_calloc(threads, sizeof(bond_job));
  pthread_t* ids = bk_calloc(threads, sizeof(pthread_t));
  bool* started = bk_calloc(threads, sizeof(bool));
  uint32_t at = 0;
  for (uint32_t t = 0; t < threads; ++t) {
    uint32_t end = t + 1 == threads ? entry_count : (uint32_t)((uint64_t)entry_count * (t + 1) / threads);
    end = end < at ? at : end;
    while (end > at && end < entry_count && entries[end].cut == entries[end - 1].cut)
      end++; // whole cuts only
    jobs[t] = (bond_job){tree, entries, at, end, {.raw = true}};
    at = end;
  }
  for (uint32_t t = 1; t < threads; ++t)
    started[t] = pthread_create(&ids[t], NULL, bond_work, &jobs[t]) == 0;
  bond_work(&jobs[0]);
  for (uint32_t t = 1; t < threads; ++t)
    if (started[t])
      pthread_join(ids[t], NULL);
    else
      bond_work(&jobs[t]); // no thread: made here
  for (uint32_t t = 0; t < threads; ++t) {
    for (uint32_t i = 0; i < jobs[t].list.count; ++i) {
      const bk_bond* b = &jobs[t].list.items[i];
      // add_contact's pair is (below, above); giving it (leaf_a, leaf_b) with
      // the normal seen from leaf_a keeps the bond's orientation.
      add_contact(list, b->leaf_a, b->leaf_b, b->area, b->centroid, b->normal);
    }
    free(jobs[t].list.items);
  }
  free(jobs);
  free(ids);
  free(started);
}

void bk_mesh_tree_compute_bonds(bk_mesh_tree* tree) {
  free(tree->bonds);
  tree->bonds = NULL;
  tree->bond_count = 0;
  if (tree->leaf_count < 2) return;
  if (bk_fracture_pattern_is_cellular(tree->desc.pattern)) {
    bk_cell_tree_compute_bonds(tree);
    return;
  }

  // Gather every cap triangle of every leaf, keyed by its cut and side.
  uint32_t entry_count = 0, entry_capacity = 0;
  cap_entry* entries = NULL;
  for (uint32_t leaf = 0; leaf < tree->leaf_count; ++leaf) {
    const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, leaf)->mesh;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
      uint32_t tag = mesh->tags[t];
      if (!bk_material_is_interior(mesh->materials[t]) || tag == 0 || tag > tree->node_count) continue;
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
  if (entry_count > 1) qsort(entries, entry_count, sizeof(cap_entry), compare_entries);
  bond_list list = {0};
  bk_index_map_init(&list.index_of_pair, tree->leaf_count * 4u);
  bond_all_cuts(tree, entries, entry_count, &list);
  free(entries);
  bk_index_map_free(&list.index_of_pair);
  if (list.count > 1) qsort(list.items, list.count, sizeof(bk_bond), compare_bonds);
  tree->bonds = list.items;
  tree->bond_count = list.count;
}
