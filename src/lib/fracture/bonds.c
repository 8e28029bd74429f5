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
// the rough surface the leaves share. The cap triangles come ordered by cut
// with their plane coordinates (bond_caps.c).
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "bond_caps.h"

// The smallest cosine between a cap triangle and its cut for the triangle to
// count as part of the cut's face (noisy caps tilt by far less).
#define BOND_MIN_COSINE 1e-6

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
  double* side; // per clipped vertex
  uint32_t clip_capacity;
} scratch;

static int compare_groups_by_min_x(const void* pa, const void* pb) {
  const leaf_group *a = pa, *b = pb;
  if (a->min[0] != b->min[0]) return a->min[0] < b->min[0] ? -1 : 1;
  return a->leaf < b->leaf ? -1 : (a->leaf > b->leaf);
}

static bool boxes_overlap(const double amin[2], const double amax[2], const double bmin[2],
                          const double bmax[2]) {
  return amin[0] <= bmax[0] && bmin[0] <= amax[0] && amin[1] <= bmax[1] && bmin[1] <= amax[1];
}

// Clips polygon `in` (n vertices) to the left of the directed line a->b
// into `out`; `side` holds each vertex's side, measured once. A polygon
// wholly on the left is left where it is (*kept: `out` unused).
static uint32_t clip_half_plane(const double (*in)[2], uint32_t n, const double a[2], const double b[2],
                                double (*out)[2], double* side, bool* kept) {
  double ex = b[0] - a[0], ey = b[1] - a[1];
  bool all_in = true, all_out = true;
  for (uint32_t i = 0; i < n; ++i) {
    side[i] = ex * (in[i][1] - a[1]) - ey * (in[i][0] - a[0]);
    all_in &= side[i] >= 0.0;
    all_out &= !(side[i] >= 0.0);
  }
  *kept = all_in;
  if (all_in) return n;
  if (all_out) return 0;
  uint32_t m = 0;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t j = i + 1 == n ? 0 : i + 1;
    const double* p = in[i];
    const double* q = in[j];
    double dp = side[i], dq = side[j];
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
    s->side = bk_realloc(s->side, sizeof(double) * s->clip_capacity);
  }
  // The polygon clipped so far: a's own points until an edge of b cuts it.
  const double(*poly)[2] = (const double(*)[2])s->points[a->first];
  uint32_t n = a->count;
  int next = 0; // the clip buffer written next
  for (uint32_t e = 0; e < b->count && n >= 3; ++e) {
    bool kept = false;
    n = clip_half_plane(poly, n, s->points[b->first + e],
                        s->points[b->first + (e + 1 == b->count ? 0 : e + 1)], s->clip[next], s->side, &kept);
    if (!kept) {
      poly = (const double(*)[2])s->clip[next];
      next = 1 - next;
    }
  }
  if (n < 3) return 0.0;
  double area2 = 0.0, sx = 0.0, sy = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    const double* p = poly[i];
    const double* q = poly[i + 1 == n ? 0 : i + 1];
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
      p->min[a] = bk_min(p->min[a], s->points[i][a]), p->max[a] = bk_max(p->max[a], s->points[i][a]);
}

// The outline of a group's triangles as one convex loop, if it is one.
// Above-side caps face -n, so their loops are reversed to run CCW.
static bool add_convex_outline(scratch* s, const bk_cap_entry* entries, uint32_t count, bool flip,
                               bk_vec3 cut_normal, double height) {
  enum { MAX_TRIANGLES = 32 };
  if (count > MAX_TRIANGLES) return false;
  for (uint32_t i = 0; i < count; ++i) // a noisy cap goes triangle by triangle
    if (!entries[i].flat) return false;
  uint32_t edge_count = 0;
  if (12u * count > s->edge_capacity) { // all edges, then the outline after them
    s->edge_capacity = bk_grow_capacity(s->edge_capacity, 12u * count);
    s->edges = bk_realloc(s->edges, sizeof(uint32_t) * s->edge_capacity);
  }
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t k = 0; k < 3; ++k) {
      s->edges[2 * edge_count] = entries[i].position[k];
      s->edges[2 * edge_count + 1] = entries[i].position[(k + 1) % 3];
      edge_count++;
    }
  // Keep the outline: edges whose reverse is not among them (few edges:
  // quadratic is fine), each with the edge it is (3 i + k: where its start
  // point's plane coordinates are).
  uint32_t outline = 0;
  uint32_t* out = s->edges + 2u * edge_count;
  for (uint32_t e = 0; e < edge_count; ++e) {
    bool inner = false;
    for (uint32_t f = 0; f < edge_count && !inner; ++f)
      inner = s->edges[2 * f] == s->edges[2 * e + 1] && s->edges[2 * f + 1] == s->edges[2 * e];
    if (inner) continue;
    out[2 * outline] = e, out[2 * outline + 1] = s->edges[2 * e + 1];
    outline++;
  }
  // Every edge cancelled (triangles folded onto each other): the caps cover
  // no area, so the group adds no piece.
  if (outline < 3) return true;
  // Follow it from the first edge; it must be one loop using every edge.
  uint32_t first_point = s->point_count, used = 0, at = 0;
  uint32_t start = s->edges[2 * out[0]];
  for (;;) {
    const double* uv = entries[out[2 * at] / 3].uv[out[2 * at] % 3];
    add_point(s, uv[0], uv[1]);
    used++;
    uint32_t next_vertex = out[2 * at + 1], next = UINT32_MAX;
    if (next_vertex == start) break;
    for (uint32_t e = 0; e < outline && next == UINT32_MAX; ++e)
      if (s->edges[2 * out[2 * e]] == next_vertex) next = e;
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
  for (uint32_t i = 0; i < n; ++i) {
    const double* q = pts[i + 1 == n ? 0 : i + 1];
    scale = bk_max(scale, bk_max(fabs(q[0] - pts[i][0]), fabs(q[1] - pts[i][1])));
  }
  for (uint32_t i = 0; i < n; ++i) {
    const double *a = pts[i == 0 ? n - 1 : i - 1], *b = pts[i], *c = pts[i + 1 == n ? 0 : i + 1];
    if ((b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < -1e-12 * scale * scale) {
      s->point_count = first_point; // reflex corner: not convex
      return false;
    }
  }
  close_piece(s, first_point, cut_normal, height);
  return true;
}

static void add_triangles(scratch* s, const bk_mesh* mesh, const bk_cap_entry* entries, uint32_t count,
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

// Contacts as met, cut by cut (a pair twice only in degenerate trees).
typedef struct bond_list {
  bk_bond* items;
  uint32_t count, capacity;
} bond_list;

static void add_contact(bond_list* list, uint32_t below_leaf, uint32_t above_leaf, double area,
                        bk_vec3 centroid, bk_vec3 n) {
  uint32_t a = below_leaf < above_leaf ? below_leaf : above_leaf;
  uint32_t b = below_leaf < above_leaf ? above_leaf : below_leaf;
  if (list->count == list->capacity) {
    list->capacity = bk_grow_capacity(list->capacity, list->count + 1);
    list->items = bk_realloc(list->items, sizeof(bk_bond) * list->capacity);
  }
  list->items[list->count++] = (bk_bond){a, b, area, centroid, a == below_leaf ? n : bk_v3_scale(n, -1.0)};
}

// The bonds in (leaf_a, leaf_b) order, a pair met on several cuts merged by
// area in the order of its cuts (the lists hold the contacts in cut order
// and the sort is stable). Returns the count.
static uint32_t merge_contacts(const bond_list* lists, uint32_t list_count, uint32_t leaf_count,
                               bk_bond** out) {
  uint32_t* start = bk_calloc(leaf_count + 1u, sizeof(uint32_t));
  uint32_t count = 0;
  for (uint32_t k = 0; k < list_count; ++k) {
    count += lists[k].count;
    for (uint32_t i = 0; i < lists[k].count; ++i)
      start[lists[k].items[i].leaf_a + 1]++;
  }
  for (uint32_t l = 0; l < leaf_count; ++l)
    start[l + 1] += start[l];
  bk_bond* sorted = bk_alloc(sizeof(bk_bond) * (count + 1u));
  for (uint32_t k = 0; k < list_count; ++k)
    for (uint32_t i = 0; i < lists[k].count; ++i)
      sorted[start[lists[k].items[i].leaf_a]++] = lists[k].items[i];
  // Each leaf's few bonds by leaf_b (insertion sort: stable), then equal pairs merged.
  uint32_t kept = 0, first = 0;
  for (uint32_t l = 0; l < leaf_count; ++l) {
    uint32_t end = start[l];
    for (uint32_t i = first + 1; i < end; ++i) {
      bk_bond bond = sorted[i];
      uint32_t j = i;
      for (; j > first && sorted[j - 1].leaf_b > bond.leaf_b; --j)
        sorted[j] = sorted[j - 1];
      sorted[j] = bond;
    }
    for (uint32_t i = first; i < end; ++i) {
      const bk_bond* c = &sorted[i];
      bk_bond* last = kept > 0 ? &sorted[kept - 1] : NULL;
      if (!last || last->leaf_a != c->leaf_a || last->leaf_b != c->leaf_b) {
        sorted[kept++] = *c;
        continue;
      }
      // Same pair over a second cut: merge by area.
      double total = last->area + c->area;
      last->centroid = bk_v3_add(bk_v3_scale(last->centroid, last->area / total),
                                 bk_v3_scale(c->centroid, c->area / total));
      last->area = total;
    }
    first = end;
  }
  bk_free(start);
  if (kept == 0) {
    bk_free(sorted);
    sorted = NULL;
  }
  *out = sorted;
  return kept;
}

// The bonds made by the caps of entries [first, last) (whole cuts), into `list`.
static void bond_cuts(const bk_mesh_tree* tree, const bk_cut_frame* frames, const bk_cap_entry* entries,
                      uint32_t first, uint32_t last, bond_list* list) {
  // Plane coordinates are taken relative to the tree's origin, so a mesh far
  // from the world origin measures its contacts as precisely as one at it.
  bk_vec3 origin = bk_mesh_tree_origin(tree);

  bk_aabb root_box = tree->nodes[0].bounds;
  bk_vec3 diag = bk_v3_sub(root_box.max, root_box.min);
  double min_area = 1e-12 * bk_v3_dot(diag, diag); // below this an overlap is rounding noise
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
    bk_vec3 n = tree->nodes[cut].plane.normal, u = frames[cut].u, v = frames[cut].v;
    double height = frames[cut].height;
    // One group of convex pieces per (side, leaf).
    s.point_count = s.piece_count = 0;
    uint32_t group_count = 0, below_groups = 0;
    for (uint32_t i = begin; i < end;) {
      uint32_t j = i;
      while (j < end && entries[j].leaf == entries[i].leaf && entries[j].side == entries[i].side)
        j++;
      bool flip = entries[i].side == 1;
      uint32_t first_piece = s.piece_count;
      if (!add_convex_outline(&s, &entries[i], j - i, flip, n, height))
        add_triangles(&s, &bk_mesh_tree_leaf(tree, entries[i].leaf)->mesh, &entries[i], j - i, flip, origin,
                      u, v, n, height);
      leaf_group* g = &groups[group_count++];
      *g = (leaf_group){entries[i].leaf,
                        first_piece,
                        s.piece_count - first_piece,
                        {INFINITY, INFINITY},
                        {-INFINITY, -INFINITY}};
      for (uint32_t k = first_piece; k < s.piece_count; ++k)
        for (int a = 0; a < 2; ++a)
          g->min[a] = bk_min(g->min[a], s.pieces[k].min[a]),
          g->max[a] = bk_max(g->max[a], s.pieces[k].max[a]);
      if (!flip) below_groups = group_count;
      i = j;
    }
    // Sweep and prune along u: both sides sorted by min u; a group is tested
    // against the other side's groups still open at its start.
    if (below_groups > 1) bk_sort(groups, below_groups, sizeof(leaf_group), compare_groups_by_min_x);
    if (group_count - below_groups > 1)
      bk_sort(groups + below_groups, group_count - below_groups, sizeof(leaf_group), compare_groups_by_min_x);
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
            // A triangle standing almost across its cut (possible only in a
            // tree made or edited by hand) is no part of the cut's face:
            // lifted, its area and place would run off to infinity.
            if (!(cosine > BOND_MIN_COSINE)) continue;
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
        bk_vec3 centroid = bk_v3_add(origin, bk_v3_scale(moment, 1.0 / area));
        // The contact is part of both leaves' surfaces; one whose centroid
        // lies outside either leaf (rounding of a degenerate contact in a
        // hand-made tree) is no contact the runtime could use.
        bk_aabb box_a = bk_mesh_tree_leaf(tree, ga->leaf)->bounds,
                box_b = bk_mesh_tree_leaf(tree, gb->leaf)->bounds;
        if (!isfinite(area) || !bk_point_inside(box_a, centroid, bk_inside_slack(box_a)) ||
            !bk_point_inside(box_b, centroid, bk_inside_slack(box_b)))
          continue;
        add_contact(list, gb->leaf, ga->leaf, area, centroid,
                    normal_length > 0.0 ? bk_v3_scale(normal, 1.0 / normal_length) : n);
      }
      active_count[1 - side] = kept;
      active[side][active_count[side]++] = (uint32_t)(g - groups);
    }
    begin = end;
  }
  bk_free(s.points);
  bk_free(s.pieces);
  bk_free(s.edges);
  bk_free(s.clip[0]);
  bk_free(s.clip[1]);
  bk_free(s.side);
  bk_free(groups);
  bk_free(active[0]);
  bk_free(active[1]);
}

// A run of whole cuts and the contacts found on it.
typedef struct bond_job {
  const bk_mesh_tree* tree;
  const bk_cut_frame* frames;
  const bk_cap_entry* entries;
  uint32_t first, last;
  bond_list list;
} bond_job;

// The runs, taken by the threads one at a time as they finish the last.
typedef struct bond_runs {
  bond_job* runs;
  uint32_t count;
  atomic_uint next; // the first run nobody took
} bond_runs;

static void* bond_work(void* arg) {
  bond_runs* r = *(bond_runs**)arg;
  for (uint32_t i = atomic_fetch_add(&r->next, 1u); i < r->count; i = atomic_fetch_add(&r->next, 1u)) {
    bond_job* job = &r->runs[i];
    bond_cuts(job->tree, job->frames, job->entries, job->first, job->last, &job->list);
  }
  return NULL;
}

// Contacts of every cut, on the tree's threads. The cuts are cut into runs
// of whole cuts, many more than threads (the first cuts, whose caps are
// shared by the most leaves, cost the most), each thread taking the next
// run when done; each run keeps its contacts as met, so the runs' lists in
// order hold every contact in cut order, the same bit for bit on any
// thread count. Returns the lists and their count.
static bond_list* bond_all_cuts(const bk_mesh_tree* tree, const bk_cut_frame* frames,
                                const bk_cap_entry* entries, uint32_t entry_count, uint32_t* list_count) {
  uint32_t threads = bk_fracture_thread_count(&tree->desc, entry_count, 4096);
  uint32_t runs = threads > 1 ? 16u * threads : 1u;
  bond_runs r = {bk_calloc(runs, sizeof(bond_job)), 0, 0};
  for (uint32_t at = 0; r.count < runs && (at < entry_count || r.count == 0);) {
    uint32_t end =
        r.count + 1 == runs ? entry_count : (uint32_t)((uint64_t)entry_count * (r.count + 1) / runs);
    end = end < at ? at : end;
    while (end > at && end < entry_count && entries[end].cut == entries[end - 1].cut)
      end++; // whole cuts only
    r.runs[r.count++] = (bond_job){tree, frames, entries, at, end, {0}};
    at = end;
  }
  bond_runs** pullers = bk_alloc(sizeof(bond_runs*) * threads);
  for (uint32_t t = 0; t < threads; ++t)
    pullers[t] = &r;
  bk_fracture_run_jobs(bond_work, pullers, sizeof(bond_runs*), threads);
  bk_free(pullers);
  bond_list* lists = bk_alloc(sizeof(bond_list) * r.count);
  for (uint32_t i = 0; i < r.count; ++i)
    lists[i] = r.runs[i].list;
  bk_free(r.runs);
  *list_count = r.count;
  return lists;
}

void bk_mesh_tree_compute_bonds(bk_mesh_tree* tree) {
  bk_free(tree->bonds);
  tree->bonds = NULL;
  tree->bond_count = 0;
  if (tree->leaf_count < 2) return;
  if (bk_fracture_pattern_is_cellular(tree->desc.pattern)) {
    bk_cell_tree_compute_bonds(tree);
    return;
  }
  // Each cut's plane basis and height above the tree's origin: plane
  // coordinates are taken relative to the origin, so a mesh far from the
  // world origin measures its contacts as precisely as one at it.
  bk_vec3 origin = bk_mesh_tree_origin(tree);
  bk_cut_frame* frames = bk_alloc(sizeof(bk_cut_frame) * tree->node_count);
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    bk_vec3 n = tree->nodes[i].plane.normal;
    bk_plane_basis(n, &frames[i].u, &frames[i].v);
    frames[i].height = tree->nodes[i].plane.offset - bk_v3_dot(n, origin);
  }
  bk_aabb root_box = tree->nodes[0].bounds;
  double flat = 1e-9 * bk_v3_length(bk_v3_sub(root_box.max, root_box.min)); // a cap this close is flat
  // Every cap triangle of every leaf, by cut and side.
  bk_cap_entry* entries = NULL;
  uint32_t entry_count = bk_gather_cap_entries(tree, frames, flat, &entries);
  uint32_t list_count = 0;
  bond_list* lists = bond_all_cuts(tree, frames, entries, entry_count, &list_count);
  bk_free(entries);
  bk_free(frames);
  tree->bond_count = merge_contacts(lists, list_count, tree->leaf_count, &tree->bonds);
  for (uint32_t k = 0; k < list_count; ++k)
    bk_free(lists[k].items);
  bk_free(lists);
}
