// The source's surface inside each cell: every source triangle that may meet
// the cell is clipped by the cell's bisectors (a convex polygon clip). New
// vertices are named by what made them (a source edge and two seeds, or a
// triangle and three seeds), so the neighbour cell that clips the same
// triangle from the other side makes the very same vertices.
#include <stdlib.h>
#include <string.h>

#include "cell_complex.h"

typedef struct poly {
  uint32_t* v;
  int32_t* sup; // edge k: >= 0 the bisector with that seed, -1 - e along triangle edge e
  uint32_t count, capacity;
} poly;

static void poly_push(poly* p, uint32_t v, int32_t sup) {
  if (p->count == p->capacity) {
    p->capacity = bk_grow_capacity(p->capacity, p->count + 1);
    p->v = bk_realloc(p->v, sizeof(uint32_t) * p->capacity);
    p->sup = bk_realloc(p->sup, sizeof(int32_t) * p->capacity);
  }
  p->v[p->count] = v;
  p->sup[p->count] = sup;
  p->count++;
}

static void sort3(int32_t* s) {
  for (int i = 1; i < 3; ++i)
    for (int j = i; j > 0 && s[j - 1] > s[j]; --j) {
      int32_t t = s[j];
      s[j] = s[j - 1];
      s[j - 1] = t;
    }
}

// The vertex where edge k of the polygon (of triangle t) crosses the bisector
// of `cell` and m.
static uint32_t edge_crossing(bk_cell_complex* cx, uint32_t t, int32_t sup, uint32_t cell, int32_t m) {
  bk_cell_key k = {0};
  if (sup < 0) {
    int e = -1 - sup;
    uint32_t pa = bk_mesh_tri_position(cx->source, t, e),
             pb = bk_mesh_tri_position(cx->source, t, (e + 1) % 3);
    k.kind = BK_CELL_CROSSING;
    k.a = pa < pb ? pa : pb;
    k.b = pa < pb ? pb : pa;
    k.s[0] = (int32_t)cell < m ? (int32_t)cell : m;
    k.s[1] = (int32_t)cell < m ? m : (int32_t)cell;
  } else {
    k.kind = BK_CELL_PIERCING;
    k.a = t;
    k.s[0] = (int32_t)cell, k.s[1] = sup, k.s[2] = m;
    sort3(k.s);
  }
  return bk_cell_vertex(cx, &k);
}

void bk_cell_clip_surface(bk_cell_complex* cx, uint32_t cell, const bk_cell_polytope* cp,
                          const uint32_t* triangles, uint32_t triangle_count, bk_cell_surface* out) {
  poly a = {0}, b = {0};
  uint8_t* inside = NULL;
  uint32_t inside_capacity = 0;
  // The cell's bisectors, and its bounds to skip triangles that miss it.
  bk_cell_side* sides = bk_alloc(sizeof(bk_cell_side) * (cp->faces ? cp->faces : 1));
  for (uint32_t f = 0; f < cp->faces; ++f)
    if (cp->planes[f] >= 0) sides[f] = bk_cell_side_of(cx, (int32_t)cell, cp->planes[f]);
  bk_aabb bounds = {cx->points[cp->loop[0]], cx->points[cp->loop[0]]};
  for (uint32_t i = 1; i < cp->loop_count; ++i) {
    bounds.min = bk_v3_min(bounds.min, cx->points[cp->loop[i]]);
    bounds.max = bk_v3_max(bounds.max, cx->points[cp->loop[i]]);
  }
  for (uint32_t ti = 0; ti < triangle_count; ++ti) {
    uint32_t t = triangles[ti];
    bk_vec3 p0 = cx->source->positions[bk_mesh_tri_position(cx->source, t, 0)];
    bk_vec3 p1 = cx->source->positions[bk_mesh_tri_position(cx->source, t, 1)];
    bk_vec3 p2 = cx->source->positions[bk_mesh_tri_position(cx->source, t, 2)];
    bk_vec3 lo = bk_v3_min(p0, bk_v3_min(p1, p2)), hi = bk_v3_max(p0, bk_v3_max(p1, p2));
    if (lo.x > bounds.max.x || lo.y > bounds.max.y || lo.z > bounds.max.z || hi.x < bounds.min.x ||
        hi.y < bounds.min.y || hi.z < bounds.min.z)
      continue;
    a.count = 0;
    for (int k = 0; k < 3; ++k) {
      bk_cell_key key = {.kind = BK_CELL_SOURCE, .a = bk_mesh_tri_position(cx->source, t, k)};
      poly_push(&a, bk_cell_vertex(cx, &key), -1 - k);
    }
    for (uint32_t f = 0; f < cp->faces && a.count; ++f) {
      int32_t m = cp->planes[f];
      if (m < 0) continue; // box planes lie outside the source
      if (inside_capacity < a.count) {
        inside_capacity = a.count;
        inside = bk_realloc(inside, inside_capacity);
      }
      bool any_out = false, any_in = false;
      for (uint32_t k = 0; k < a.count; ++k) {
        inside[k] = bk_cell_side_keeps(&sides[f], cx->points[a.v[k]]);
        any_out |= !inside[k];
        any_in |= inside[k];
      }
      if (!any_out) continue;
      if (!any_in) {
        a.count = 0;
        break;
      }
      b.count = 0;
      for (uint32_t k = 0; k < a.count; ++k) {
        uint32_t next = (k + 1) % a.count;
        if (inside[k] && inside[next]) {
          poly_push(&b, a.v[k], a.sup[k]);
        } else if (inside[k]) { // leaving: this edge ends at the crossing, then runs along m
          poly_push(&b, a.v[k], a.sup[k]);
          poly_push(&b, edge_crossing(cx, t, a.sup[k], cell, m), m);
        } else if (inside[next]) { // entering: from the crossing on along this edge
          poly_push(&b, edge_crossing(cx, t, a.sup[k], cell, m), a.sup[k]);
        }
      }
      poly tmp = a;
      a = b;
      b = tmp;
      if (a.count < 3) a.count = 0;
    }
    if (a.count < 3) continue;
    if (out->polygon_count == out->polygon_capacity) {
      out->polygon_capacity = bk_grow_capacity(out->polygon_capacity, out->polygon_count + 1);
      out->polygons = bk_realloc(out->polygons, sizeof(bk_cell_polygon) * out->polygon_capacity);
    }
    if (out->vertex_count + a.count > out->vertex_capacity) {
      out->vertex_capacity = bk_grow_capacity(out->vertex_capacity, out->vertex_count + a.count);
      out->vertices = bk_realloc(out->vertices, sizeof(uint32_t) * out->vertex_capacity);
      out->supports = bk_realloc(out->supports, sizeof(int32_t) * out->vertex_capacity);
    }
    out->polygons[out->polygon_count++] = (bk_cell_polygon){t, out->vertex_count, a.count};
    memcpy(out->vertices + out->vertex_count, a.v, sizeof(uint32_t) * a.count);
    memcpy(out->supports + out->vertex_count, a.sup, sizeof(int32_t) * a.count);
    out->vertex_count += a.count;
  }
  free(sides);
  free(a.v);
  free(a.sup);
  free(b.v);
  free(b.sup);
  free(inside);
}

void bk_cell_surface_free(bk_cell_surface* s) {
  free(s->polygons);
  free(s->vertices);
  free(s->supports);
  memset(s, 0, sizeof *s);
}

// ---------------------------------------------------------------- inside test

// Parity of the crossings of a ray from each point towards +z, with the
// points binned on an x-y grid so each triangle only meets the points under
// it. A point exactly on a projected edge counts for one side only (the
// half-open rule), so shared edges are not counted twice.
static bool covers(double ax, double ay, double bx, double by, double px, double py) {
  double e = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
  if (e != 0.0) return e > 0.0;
  return bx < ax || (bx == ax && by < ay);
}

void bk_points_inside(const bk_mesh* m, const bk_vec3* pts, uint32_t count, uint8_t* inside) {
  memset(inside, 0, count);
  if (!count) return;
  bk_aabb box = bk_mesh_bounds(m);
  int n = (int)fmin(fmax(sqrt((double)count) / 2.0, 1.0), 512.0);
  double sx = (box.max.x - box.min.x) / n, sy = (box.max.y - box.min.y) / n;
  if (!(sx > 0.0) || !(sy > 0.0)) return;
  uint32_t* start = bk_calloc((size_t)n * n + 1, sizeof(uint32_t));
  uint32_t* order = bk_alloc(sizeof(uint32_t) * count);
  int32_t* bin = bk_alloc(sizeof(int32_t) * count);
  for (uint32_t i = 0; i < count; ++i) {
    // Compared as doubles first: a point far away (or not finite) has no bin.
    double fx = floor((pts[i].x - box.min.x) / sx), fy = floor((pts[i].y - box.min.y) / sy);
    bin[i] = !(fx >= 0.0 && fy >= 0.0 && fx < n && fy < n) ? -1 : (int32_t)fy * n + (int32_t)fx;
    if (bin[i] >= 0) start[bin[i] + 1]++;
  }
  for (int b = 0; b < n * n; ++b)
    start[b + 1] += start[b];
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * ((size_t)n * n));
  memcpy(fill, start, sizeof(uint32_t) * (size_t)n * n);
  for (uint32_t i = 0; i < count; ++i)
    if (bin[i] >= 0) order[fill[bin[i]]++] = i;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = m->positions[bk_mesh_tri_position(m, t, k)];
    double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
    if (area == 0.0) continue; // seen edge-on: no ray goes through it
    if (area < 0.0) {
      bk_vec3 s = p[1];
      p[1] = p[2];
      p[2] = s;
      area = -area;
    }
    double minx = fmin(p[0].x, fmin(p[1].x, p[2].x)), maxx = fmax(p[0].x, fmax(p[1].x, p[2].x));
    double miny = fmin(p[0].y, fmin(p[1].y, p[2].y)), maxy = fmax(p[0].y, fmax(p[1].y, p[2].y));
    int x0 = (int)fmax(floor((minx - box.min.x) / sx), 0),
        x1 = (int)fmin(floor((maxx - box.min.x) / sx), n - 1);
    int y0 = (int)fmax(floor((miny - box.min.y) / sy), 0),
        y1 = (int)fmin(floor((maxy - box.min.y) / sy), n - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (uint32_t k = start[y * n + x]; k < start[y * n + x + 1]; ++k) {
          uint32_t i = order[k];
          double px = pts[i].x, py = pts[i].y;
          if (!covers(p[0].x, p[0].y, p[1].x, p[1].y, px, py) ||
              !covers(p[1].x, p[1].y, p[2].x, p[2].y, px, py) ||
              !covers(p[2].x, p[2].y, p[0].x, p[0].y, px, py))
            continue;
          double w0 = ((p[1].x - px) * (p[2].y - py) - (p[1].y - py) * (p[2].x - px)) / area;
          double w1 = ((p[2].x - px) * (p[0].y - py) - (p[2].y - py) * (p[0].x - px)) / area;
          double z = w0 * p[0].z + w1 * p[1].z + (1.0 - w0 - w1) * p[2].z;
          if (z > pts[i].z) inside[i] ^= 1;
        }
  }
  free(fill);
  free(start);
  free(order);
  free(bin);
}
