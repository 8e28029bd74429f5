// A flat contact side's outline (see mesh_contact.h): the boundary of its
// triangles (the edges whose reverse no other triangle has), walked into a
// loop; when it is one convex loop, a piece's triangles are clipped against
// it once each instead of against every triangle of the side (a face's
// triangulation is often a fan of hundreds of slivers, every one of whose
// boxes overlaps most others).
#include <stdlib.h>
#include <string.h>

#include "mesh_contact.h"

typedef struct edge {
  bk_vec3 from, to;
  bool used;
} edge;

static int compare_points(bk_vec3 a, bk_vec3 b) {
  if (a.x != b.x) return a.x < b.x ? -1 : 1;
  if (a.y != b.y) return a.y < b.y ? -1 : 1;
  if (a.z != b.z) return a.z < b.z ? -1 : 1;
  return 0;
}

static int compare_edges(const void* pa, const void* pb) {
  const edge *a = pa, *b = pb;
  int c = compare_points(a->from, b->from);
  return c ? c : compare_points(a->to, b->to);
}

// The edge (from, to) in the sorted list, or NULL.
static edge* find_edge(edge* edges, uint32_t count, bk_vec3 from, bk_vec3 to) {
  edge key = {from, to, false};
  return bsearch(&key, edges, count, sizeof(edge), compare_edges);
}

// The first unused edge leaving `from`: edges are sorted by their start.
static edge* edge_from(edge* edges, uint32_t count, bk_vec3 from) {
  uint32_t lo = 0, hi = count;
  while (lo < hi) {
    uint32_t mid = lo + (hi - lo) / 2;
    if (compare_points(edges[mid].from, from) < 0)
      lo = mid + 1;
    else
      hi = mid;
  }
  for (uint32_t i = lo; i < count && compare_points(edges[i].from, from) == 0; ++i)
    if (!edges[i].used) return &edges[i];
  return NULL;
}

bool bk_contact_outline_make(const bk_contact_side* side, bk_plane plane, double tolerance,
                             bk_contact_outline* out) {
  memset(out, 0, sizeof *out);
  const tri_info* t = side->tris;
  uint32_t count = 3u * side->count;
  if (!count) return false;
  edge* edges = bk_alloc(sizeof(edge) * count);
  for (uint32_t i = 0; i < side->count; ++i)
    for (int k = 0; k < 3; ++k)
      edges[3 * i + (uint32_t)k] = (edge){t[i].p[k], t[i].p[(k + 1) % 3], false};
  bk_sort(edges, count, sizeof(edge), compare_edges);
  // Boundary edges: no triangle has their reverse (the positions of one
  // mesh are shared, so equal points are equal bits).
  edge* boundary = bk_alloc(sizeof(edge) * count);
  uint32_t kept = 0;
  for (uint32_t i = 0; i < count; ++i)
    if (!find_edge(edges, count, edges[i].to, edges[i].from)) boundary[kept++] = edges[i];
  bk_free(edges);
  // One loop, walked against the side's turn (its triangles face away from
  // the plane's normal), so it turns counter-clockwise seen from that side.
  bk_plane_basis(plane.normal, &out->u, &out->v);
  out->origin = kept ? boundary[0].from : bk_v3(0, 0, 0);
  out->points = bk_alloc(sizeof(double[2]) * (kept + 1u));
  bool ok = kept >= 3;
  edge* at = ok ? &boundary[0] : NULL;
  while (at && !at->used) {
    at->used = true;
    bk_vec3 d = bk_v3_sub(at->from, out->origin);
    out->points[out->count][0] = bk_v3_dot(d, out->u);
    out->points[out->count][1] = bk_v3_dot(d, out->v);
    out->count++;
    at = edge_from(boundary, kept, at->to);
  }
  ok = ok && out->count == kept; // every boundary edge on the one loop
  // Reverse it, then check that it turns one way only (straight runs allowed).
  for (uint32_t i = 0; ok && i < out->count / 2; ++i) {
    double x = out->points[i][0], y = out->points[i][1];
    out->points[i][0] = out->points[out->count - 1 - i][0],
    out->points[i][1] = out->points[out->count - 1 - i][1];
    out->points[out->count - 1 - i][0] = x, out->points[out->count - 1 - i][1] = y;
  }
  for (uint32_t i = 0; ok && i < out->count; ++i) {
    const double* a = out->points[i];
    const double* b = out->points[(i + 1) % out->count];
    const double* c = out->points[(i + 2) % out->count];
    double cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
    double scale = bk_hypot(b[0] - a[0], b[1] - a[1]) * bk_hypot(c[0] - b[0], c[1] - b[1]);
    ok = cross >= -tolerance * scale;
  }
  bk_free(boundary);
  if (!ok) {
    bk_contact_outline_free(out);
    return false;
  }
  out->lo[0] = out->lo[1] = INFINITY;
  out->hi[0] = out->hi[1] = -INFINITY;
  for (uint32_t i = 0; i < out->count; ++i)
    for (int axis = 0; axis < 2; ++axis) {
      out->lo[axis] = fmin(out->lo[axis], out->points[i][axis]);
      out->hi[axis] = fmax(out->hi[axis], out->points[i][axis]);
    }
  return true;
}

// Clips a convex polygon to the left of a->b (buffers hold n + 1 points);
// UINT32_MAX when all of it is on the left already (nothing written).
static uint32_t clip_left(const double (*in)[2], uint32_t n, const double a[2], const double b[2],
                          double (*out)[2]) {
  double ex = b[0] - a[0], ey = b[1] - a[1];
  bool inside = true;
  for (uint32_t i = 0; i < n && inside; ++i)
    inside = ex * (in[i][1] - a[1]) - ey * (in[i][0] - a[0]) >= 0.0;
  if (inside) return UINT32_MAX;
  uint32_t m = 0;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t j = i + 1 == n ? 0 : i + 1;
    double si = ex * (in[i][1] - a[1]) - ey * (in[i][0] - a[0]);
    double sj = ex * (in[j][1] - a[1]) - ey * (in[j][0] - a[0]);
    if (si >= 0.0) {
      out[m][0] = in[i][0], out[m][1] = in[i][1];
      m++;
    }
    if ((si >= 0.0) != (sj >= 0.0)) {
      double s = si / (si - sj);
      out[m][0] = in[i][0] + (in[j][0] - in[i][0]) * s;
      out[m][1] = in[i][1] + (in[j][1] - in[i][1]) * s;
      m++;
    }
  }
  return m;
}

bk_contact_measure bk_contact_outline_clip(const bk_contact_side* a, const bk_contact_outline* outline,
                                           bk_plane plane, double tolerance) {
  const tri_info* t = a->tris;
  uint32_t room = outline->count + 4u;
  double(*buffer[2])[2] = {bk_alloc(sizeof(double[2]) * room), bk_alloc(sizeof(double[2]) * room)};
  double area = 0.0;
  bk_vec3 moment = {0}, normal = {0};
  for (uint32_t i = 0; i < a->count; ++i) {
    if (!bk_tri_on_plane(&t[i], plane, tolerance)) continue;
    uint32_t n = 3, cur = 0;
    for (int k = 0; k < 3; ++k) {
      bk_vec3 d = bk_v3_sub(t[i].p[k], outline->origin);
      buffer[0][k][0] = bk_v3_dot(d, outline->u);
      buffer[0][k][1] = bk_v3_dot(d, outline->v);
    }
    bool apart = false; // outside the outline's box: no contact
    for (int axis = 0; axis < 2 && !apart; ++axis) {
      double lo = fmin(buffer[0][0][axis], fmin(buffer[0][1][axis], buffer[0][2][axis]));
      double hi = fmax(buffer[0][0][axis], fmax(buffer[0][1][axis], buffer[0][2][axis]));
      apart = hi < outline->lo[axis] || lo > outline->hi[axis];
    }
    if (apart) continue;
    for (uint32_t e = 0; e < outline->count && n >= 3; ++e) {
      uint32_t m = clip_left((const double(*)[2])buffer[cur], n, outline->points[e],
                             outline->points[(e + 1) % outline->count], buffer[1 - cur]);
      if (m == UINT32_MAX) continue; // wholly inside this edge: kept as it is
      n = m;
      cur = 1 - cur;
    }
    double part = 0.0;
    bk_vec3 centroid = {0};
    if (!bk_polygon_lift((const double(*)[2])buffer[cur], n, outline->origin, outline->u, outline->v, &part,
                         &centroid))
      continue;
    area += part;
    moment = bk_v3_add(moment, bk_v3_scale(centroid, part));
    normal = bk_v3_add(normal, bk_v3_scale(t[i].normal, part));
  }
  bk_free(buffer[0]);
  bk_free(buffer[1]);
  return bk_contact_finish(area, moment, normal);
}

void bk_contact_outline_free(bk_contact_outline* outline) {
  bk_free(outline->points);
  memset(outline, 0, sizeof *outline);
}
