// Cap triangulation: link cut edges into loops by vertex index, triangulate
// all loops of one cut together with GLU's tessellator (ODD winding), and
// verify the result closes exactly the given edges.
#include "cap.h"

#include <GL/glu.h>
#include <stdlib.h>
#include <string.h>

struct bk_cap {
  GLUtesselator* tess;
  // Loop linking: outgoing edges per vertex in CSR form.
  uint32_t* out_start;
  uint32_t* out_edges;
  uint8_t* edge_used;
  uint32_t vertex_capacity, edge_capacity;
  // Tessellator input coordinates (must live until gluTessEndPolygon).
  GLdouble* coords;
  uint32_t coord_capacity;
  // Linked loops: vertices in order, loop i spans [loop_start[i], loop_start[i + 1]).
  uint32_t* loop_vertices;
  uint32_t* loop_start;
  uint32_t loop_count;
  // Output.
  uint32_t* tris;
  uint32_t tri_count, tri_capacity;
  uint32_t pending[3];
  uint32_t pending_count;
  bool failed;
  uint32_t* ring; // the convex loop being clipped
  // closes_exactly: triangle half-edges (h = 3t + k) by start vertex, marks per vertex.
  uint32_t* tri_start;
  uint32_t* mark;
  uint32_t* slot;
  uint32_t* tri_around;
  uint8_t* outer;
  uint32_t half_capacity;
};

static void push_triangle(bk_cap* cap, uint32_t a, uint32_t b, uint32_t c) {
  if (cap->tri_count == cap->tri_capacity) {
    cap->tri_capacity = bk_grow_capacity(cap->tri_capacity, cap->tri_count + 1);
    cap->tris = bk_realloc(cap->tris, sizeof(uint32_t) * 3u * cap->tri_capacity);
  }
  uint32_t* t = &cap->tris[3 * cap->tri_count++];
  t[0] = a, t[1] = b, t[2] = c;
}

static void tess_begin(GLenum type, void* user) {
  bk_cap* cap = user;
  // With an edge-flag callback registered GLU only emits GL_TRIANGLES.
  if (type != GL_TRIANGLES) cap->failed = true;
  cap->pending_count = 0;
}

static void tess_vertex(void* vertex, void* user) {
  bk_cap* cap = user;
  cap->pending[cap->pending_count++] = (uint32_t)((uintptr_t)vertex - 1u);
  if (cap->pending_count < 3) return;
  cap->pending_count = 0;
  push_triangle(cap, cap->pending[0], cap->pending[1], cap->pending[2]);
}

static void tess_end(void* user) { (void)user; }

static void tess_edge_flag(GLboolean flag, void* user) {
  (void)flag;
  (void)user;
}

static void tess_combine(GLdouble coords[3], void* vertex_data[4], GLfloat weight[4], void** out,
                         void* user) {
  (void)coords;
  (void)user;
  // Caps may only use existing vertices (a new one would open a seam), so a
  // merge of coincident vertices snaps to the heaviest contributor.
  int best = 0;
  for (int i = 1; i < 4; ++i)
    if (vertex_data[i] && weight[i] > weight[best]) best = i;
  *out = vertex_data[best];
}

static void tess_error(GLenum code, void* user) {
  (void)code;
  ((bk_cap*)user)->failed = true;
}

bk_cap* bk_cap_create(void) {
  bk_cap* cap = bk_calloc(1, sizeof *cap);
  cap->tess = gluNewTess();
  if (!cap->tess) {
    bk_free(cap);
    return NULL;
  }
  gluTessProperty(cap->tess, GLU_TESS_WINDING_RULE, GLU_TESS_WINDING_ODD);
  gluTessProperty(cap->tess, GLU_TESS_BOUNDARY_ONLY, GL_FALSE);
  gluTessCallback(cap->tess, GLU_TESS_BEGIN_DATA, (_GLUfuncptr)tess_begin);
  gluTessCallback(cap->tess, GLU_TESS_VERTEX_DATA, (_GLUfuncptr)tess_vertex);
  gluTessCallback(cap->tess, GLU_TESS_END_DATA, (_GLUfuncptr)tess_end);
  gluTessCallback(cap->tess, GLU_TESS_EDGE_FLAG_DATA, (_GLUfuncptr)tess_edge_flag);
  gluTessCallback(cap->tess, GLU_TESS_COMBINE_DATA, (_GLUfuncptr)tess_combine);
  gluTessCallback(cap->tess, GLU_TESS_ERROR_DATA, (_GLUfuncptr)tess_error);
  gluTessNormal(cap->tess, 0.0, 0.0, 1.0);
  return cap;
}

void bk_cap_destroy(bk_cap* cap) {
  if (!cap) return;
  gluDeleteTess(cap->tess);
  bk_free(cap->out_start);
  bk_free(cap->out_edges);
  bk_free(cap->edge_used);
  bk_free(cap->coords);
  bk_free(cap->loop_vertices);
  bk_free(cap->loop_start);
  bk_free(cap->tris);
  bk_free(cap->ring);
  bk_free(cap->tri_start);
  bk_free(cap->mark);
  bk_free(cap->slot);
  bk_free(cap->tri_around);
  bk_free(cap->outer);
  bk_free(cap);
}

static void reserve(bk_cap* cap, uint32_t vertices, uint32_t edges) {
  if (vertices + 1 > cap->vertex_capacity) {
    cap->vertex_capacity = bk_grow_capacity(cap->vertex_capacity, vertices + 1);
    cap->out_start = bk_realloc(cap->out_start, sizeof(uint32_t) * cap->vertex_capacity);
    cap->tri_start = bk_realloc(cap->tri_start, sizeof(uint32_t) * cap->vertex_capacity);
    cap->mark = bk_realloc(cap->mark, sizeof(uint32_t) * cap->vertex_capacity);
    cap->slot = bk_realloc(cap->slot, sizeof(uint32_t) * cap->vertex_capacity);
  }
  if (edges > cap->edge_capacity) {
    cap->edge_capacity = bk_grow_capacity(cap->edge_capacity, edges);
    cap->out_edges = bk_realloc(cap->out_edges, sizeof(uint32_t) * cap->edge_capacity);
    cap->edge_used = bk_realloc(cap->edge_used, cap->edge_capacity);
    cap->ring = bk_realloc(cap->ring, sizeof(uint32_t) * cap->edge_capacity);
  }
  if (3u * edges > cap->coord_capacity) {
    cap->coord_capacity = bk_grow_capacity(cap->coord_capacity, 3u * edges);
    cap->coords = bk_realloc(cap->coords, sizeof(GLdouble) * cap->coord_capacity);
    cap->loop_vertices = bk_realloc(cap->loop_vertices, sizeof(uint32_t) * cap->coord_capacity);
    cap->loop_start = bk_realloc(cap->loop_start, sizeof(uint32_t) * (cap->coord_capacity + 1u));
  }
}

// Outer edges of the triangles must be exactly the input edges, each once,
// in the input direction; every other edge must be shared by two triangles.
// Triangle half-edges are grouped by start vertex: a vertex marks where its
// half-edges go (twice to one place: overlapping triangles), and a half-edge
// arriving there is outer when the way back is unmarked. Input edges are
// grouped by start vertex too (out_start, out_edges).
static bool closes_exactly(bk_cap* cap, const uint32_t* edges, uint32_t edge_count, uint32_t vertex_count) {
  uint32_t half_count = 3u * cap->tri_count;
  if (half_count > cap->half_capacity) {
    cap->half_capacity = bk_grow_capacity(cap->half_capacity, half_count);
    cap->tri_around = bk_realloc(cap->tri_around, sizeof(uint32_t) * cap->half_capacity);
    cap->outer = bk_realloc(cap->outer, cap->half_capacity);
  }
  const uint32_t* tris = cap->tris;
  uint32_t* start = cap->tri_start;
  memset(start, 0, sizeof(uint32_t) * (vertex_count + 1u));
  for (uint32_t h = 0; h < half_count; ++h)
    start[tris[h] + 1]++;
  for (uint32_t v = 0; v < vertex_count; ++v)
    start[v + 1] += start[v];
  for (uint32_t h = 0; h < half_count; ++h)
    cap->tri_around[start[tris[h]]++] = h;
  for (uint32_t v = vertex_count; v > 0; --v)
    start[v] = start[v - 1];
  start[0] = 0;
  uint32_t outer = 0;
  memset(cap->mark, 0xff, sizeof(uint32_t) * vertex_count);
  for (uint32_t b = 0; b < vertex_count; ++b) {
    for (uint32_t i = start[b]; i < start[b + 1]; ++i) {
      uint32_t x = tris[bk_half_next(cap->tri_around[i])];
      if (cap->mark[x] == b) return false; // a directed edge used twice: overlapping triangles
      cap->mark[x] = b;
    }
    for (uint32_t i = start[b]; i < start[b + 1]; ++i) {
      uint32_t h = bk_half_prev(cap->tri_around[i]);
      cap->outer[h] = cap->mark[tris[h]] != b;
      outer += cap->outer[h];
    }
  }
  if (outer != edge_count) return false;
  // Every input edge a -> b is an outer triangle edge.
  memset(cap->mark, 0xff, sizeof(uint32_t) * vertex_count);
  for (uint32_t a = 0; a < vertex_count; ++a) {
    for (uint32_t i = start[a]; i < start[a + 1]; ++i) {
      uint32_t h = cap->tri_around[i], x = tris[bk_half_next(h)];
      cap->mark[x] = a;
      cap->slot[x] = h;
    }
    for (uint32_t i = cap->out_start[a]; i < cap->out_start[a + 1]; ++i) {
      uint32_t b = edges[2 * cap->out_edges[i] + 1];
      if (cap->mark[b] != a || !cap->outer[cap->slot[b]]) return false;
    }
  }
  return true;
}

static double turn2(const double* xy, uint32_t a, uint32_t b, uint32_t c) {
  const double *pa = &xy[2 * a], *pb = &xy[2 * b], *pc = &xy[2 * c];
  return (pb[0] - pa[0]) * (pc[1] - pb[1]) - (pb[1] - pa[1]) * (pc[0] - pb[0]);
}

// Fast path for the common case, a single convex loop (every cut of a convex
// piece). Collinear vertices on its sides must stay (the side faces share
// them), so instead of a fan, which would put zero-area triangles along the
// apex's own sides, clip strictly convex ears: each clipped triangle has
// positive area and never contains another vertex. Returns false (nothing
// emitted) when the loop is not convex.
static bool clip_convex_loop(bk_cap* cap, const double* xy) {
  uint32_t n = cap->loop_start[1];
  if (n < 3) return false;
  // Work on a copy so a give-up leaves the loop intact for the tessellator.
  uint32_t* ring = cap->ring;
  memcpy(ring, cap->loop_vertices, sizeof(uint32_t) * n);
  double area2 = 0.0, scale = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    const double *p = &xy[2 * ring[i]], *q = &xy[2 * ring[i + 1 == n ? 0 : i + 1]];
    area2 += p[0] * q[1] - q[0] * p[1];
    scale = bk_max(scale, bk_max(fabs(q[0] - p[0]), fabs(q[1] - p[1])));
  }
  double orientation = area2 > 0.0 ? 1.0 : -1.0;
  double eps = 1e-12 * scale * scale;
  for (uint32_t i = 0; i < n; ++i)
    if (orientation * turn2(xy, ring[i == 0 ? n - 1 : i - 1], ring[i], ring[i + 1 == n ? 0 : i + 1]) < -eps)
      return false;
  uint32_t i = 0, misses = 0;
  while (n > 3) {
    uint32_t prev = i == 0 ? n - 1 : i - 1, next = i + 1 == n ? 0 : i + 1;
    if (orientation * turn2(xy, ring[prev], ring[i], ring[next]) > eps) {
      push_triangle(cap, ring[prev], ring[i], ring[next]);
      memmove(&ring[i], &ring[i + 1], sizeof(uint32_t) * (n - i - 1));
      n--;
      if (i >= n) i = 0;
      misses = 0;
    } else {
      i = i + 1 == n ? 0 : i + 1;
      if (++misses > n) break; // only collinear vertices left: give up
    }
  }
  if (n != 3 || !(orientation * turn2(xy, ring[0], ring[1], ring[2]) > eps)) {
    cap->tri_count = 0;
    return false;
  }
  push_triangle(cap, ring[0], ring[1], ring[2]);
  return true;
}

// Ear clipping a loop that visits no vertex twice closes it exactly, by
// construction: each ear's triangle runs along two ring edges and back
// along the diagonal that replaces them, which joins two vertices not
// adjacent on the ring (and never adjacent before), so the triangles' outer
// edges are the loop's edges, each once, and every diagonal is used once
// each way. Only a loop through a vertex twice needs closes_exactly.
static bool loop_is_simple(bk_cap* cap, uint32_t vertex_count) {
  memset(cap->mark, 0, sizeof(uint32_t) * vertex_count);
  for (uint32_t i = 0; i < cap->loop_start[1]; ++i) {
    uint32_t v = cap->loop_vertices[i];
    if (cap->mark[v]) return false;
    cap->mark[v] = 1;
  }
  return true;
}

// GLU may emit zero-area triangles where loop vertices are collinear. A later
// cut through such a sliver would create a second vertex at an existing point,
// so split it away: a zero-area triangle (a, b, c) with c on its long edge
// a-b and the neighbour (b, a, d) become (b, c, d) and (c, a, d), which cover
// the same region with the same outline.
static void repair_zero_area(bk_cap* cap, const double* xy, double eps) {
  for (uint32_t pass = 0; pass < cap->tri_count; ++pass) {
    uint32_t bad = UINT32_MAX;
    for (uint32_t t = 0; t < cap->tri_count && bad == UINT32_MAX; ++t) {
      const uint32_t* tri = &cap->tris[3 * t];
      if (fabs(turn2(xy, tri[0], tri[1], tri[2])) <= eps) bad = t;
    }
    if (bad == UINT32_MAX) return;
    uint32_t* tri = &cap->tris[3 * bad];
    // Rotate so the long edge is a->b (c lies between a and b).
    uint32_t r = 0;
    double best = -1.0;
    for (uint32_t k = 0; k < 3; ++k) {
      const double *p = &xy[2 * tri[k]], *q = &xy[2 * tri[(k + 1) % 3]];
      double len = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]);
      if (len > best) best = len, r = k;
    }
    uint32_t a = tri[r], b = tri[(r + 1) % 3], c = tri[(r + 2) % 3];
    uint32_t neighbour = UINT32_MAX, d = 0;
    for (uint32_t t = 0; t < cap->tri_count && neighbour == UINT32_MAX; ++t)
      for (uint32_t k = 0; k < 3; ++k)
        if (cap->tris[3 * t + k] == b && cap->tris[3 * t + (k + 1) % 3] == a) {
          neighbour = t;
          d = cap->tris[3 * t + (k + 2) % 3];
          break;
        }
    if (neighbour == UINT32_MAX) return; // long edge on the outline: leave it
    uint32_t* nt = &cap->tris[3 * neighbour];
    tri[0] = b, tri[1] = c, tri[2] = d;
    nt[0] = c, nt[1] = a, nt[2] = d;
  }
}

bool bk_cap_triangulate(bk_cap* cap, const uint32_t* edges, uint32_t edge_count, const double* xy,
                        uint32_t vertex_count, const uint32_t** triangles, uint32_t* triangle_count,
                        bk_error* err) {
  *triangles = NULL;
  *triangle_count = 0;
  if (edge_count < 3)
    return bk_error_set(err, "cap has %u edges; a closed loop needs at least 3", edge_count);
  reserve(cap, vertex_count, edge_count);

  // Outgoing edges per vertex (counting sort), so loops link by index in O(E).
  memset(cap->out_start, 0, sizeof(uint32_t) * (vertex_count + 1u));
  for (uint32_t e = 0; e < edge_count; ++e)
    cap->out_start[edges[2 * e] + 1]++;
  for (uint32_t v = 0; v < vertex_count; ++v)
    cap->out_start[v + 1] += cap->out_start[v];
  for (uint32_t e = 0; e < edge_count; ++e)
    cap->out_edges[cap->out_start[edges[2 * e]]++] = e;
  for (uint32_t v = vertex_count; v > 0; --v)
    cap->out_start[v] = cap->out_start[v - 1];
  cap->out_start[0] = 0;
  memset(cap->edge_used, 0, edge_count);

  // Link the edges into closed loops. Where several loops touch at a vertex
  // any unused outgoing edge will do: with the ODD rule the region is the same.
  uint32_t linked = 0;
  cap->loop_count = 0;
  for (uint32_t first = 0; first < edge_count; ++first) {
    if (cap->edge_used[first]) continue;
    cap->loop_start[cap->loop_count++] = linked;
    uint32_t start = edges[2 * first], e = first;
    for (;;) {
      cap->edge_used[e] = 1;
      cap->loop_vertices[linked++] = edges[2 * e];
      uint32_t next_vertex = edges[2 * e + 1];
      if (next_vertex == start) break;
      uint32_t next = UINT32_MAX;
      for (uint32_t i = cap->out_start[next_vertex]; i < cap->out_start[next_vertex + 1]; ++i)
        if (!cap->edge_used[cap->out_edges[i]]) {
          next = cap->out_edges[i];
          break;
        }
      if (next == UINT32_MAX)
        return bk_error_set(err, "cut edges do not form closed loops (open at vertex %u)", next_vertex);
      e = next;
    }
  }
  cap->loop_start[cap->loop_count] = linked;

  cap->tri_count = 0;
  cap->failed = false;
  if (cap->loop_count == 1 && clip_convex_loop(cap, xy)) {
    if (loop_is_simple(cap, vertex_count) || closes_exactly(cap, edges, edge_count, vertex_count)) {
      *triangles = cap->tris;
      *triangle_count = cap->tri_count;
      return true;
    }
    cap->tri_count = 0; // not what it looked like: let the tessellator decide
  }
  gluTessBeginPolygon(cap->tess, cap);
  for (uint32_t l = 0; l < cap->loop_count; ++l) {
    gluTessBeginContour(cap->tess);
    for (uint32_t i = cap->loop_start[l]; i < cap->loop_start[l + 1]; ++i) {
      uint32_t v = cap->loop_vertices[i];
      GLdouble* c = &cap->coords[3 * i];
      c[0] = xy[2 * v], c[1] = xy[2 * v + 1], c[2] = 0.0;
      gluTessVertex(cap->tess, c, (void*)(uintptr_t)(v + 1u));
    }
    gluTessEndContour(cap->tess);
  }
  gluTessEndPolygon(cap->tess);
  if (cap->failed) return bk_error_set(err, "cap tessellation failed");

  // Drop triangles that snapping made degenerate.
  uint32_t kept = 0;
  for (uint32_t t = 0; t < cap->tri_count; ++t) {
    uint32_t* tri = &cap->tris[3 * t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;
    memmove(&cap->tris[3 * kept++], tri, sizeof(uint32_t) * 3);
  }
  cap->tri_count = kept;
  if (kept == 0) return bk_error_set(err, "cap tessellation produced no triangles");

  // GLU orients every triangle the same way (counter-clockwise about its
  // normal); flip all if that disagrees with the direction of the loops.
  bool along = false;
  for (uint32_t h = 0; h < 3u * kept && !along; ++h)
    along = cap->tris[h] == edges[0] && cap->tris[bk_half_next(h)] == edges[1];
  if (!along) {
    for (uint32_t t = 0; t < kept; ++t) {
      uint32_t tmp = cap->tris[3 * t + 1];
      cap->tris[3 * t + 1] = cap->tris[3 * t + 2];
      cap->tris[3 * t + 2] = tmp;
    }
  }
  double scale = 0.0;
  for (uint32_t e = 0; e < edge_count; ++e) {
    const double *p = &xy[2 * edges[2 * e]], *q = &xy[2 * edges[2 * e + 1]];
    scale = bk_max(scale, bk_max(fabs(q[0] - p[0]), fabs(q[1] - p[1])));
  }
  repair_zero_area(cap, xy, 1e-12 * scale * scale);
  if (!closes_exactly(cap, edges, edge_count, vertex_count))
    return bk_error_set(err, "cap triangulation does not close the cut (%u loop edges, %u triangles)",
                        edge_count, kept);
  *triangles = cap->tris;
  *triangle_count = kept;
  return true;
}
