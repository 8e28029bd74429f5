// The cut faces of the cell complex. The part of the Voronoi face between
// cells a and b that lies inside the source is bounded by (1) the surface
// pieces' edges on that bisector and (2) the stretches of the face's own
// edges (Voronoi edges) that run inside the source. Whether a Voronoi edge
// runs inside is known without any ray cast: the box corners are outside,
// and walking the Voronoi edges from them the status flips at every point
// where an edge pierces the surface (the surface clipping names those
// points). The loops are triangulated once per face and shared by a and b.
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "cap.h"
#include "cell_complex.h"

// A Voronoi edge named by its three ids (sorted), packed in 63 bits.
static uint64_t edge_key3(const int32_t s[3]) {
  return ((uint64_t)(uint32_t)(s[0] + 8) << 42) | ((uint64_t)(uint32_t)(s[1] + 8) << 21) |
         (uint32_t)(s[2] + 8);
}

// The three ids two corner vertices share (the edge between them); false
// when they do not share exactly three.
static bool common_ids(const bk_cell_key* a, const bk_cell_key* b, int32_t out[3]) {
  int n = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (a->s[i] == b->s[j]) {
        if (n == 3) return false;
        out[n++] = a->s[i];
      }
  return n == 3;
}

typedef struct piercing {
  uint64_t edge;
  uint32_t vertex;
} piercing;

static int compare_piercings(const void* pa, const void* pb) {
  const piercing *a = pa, *b = pb;
  if (a->edge != b->edge) return a->edge < b->edge ? -1 : 1;
  return a->vertex < b->vertex ? -1 : (a->vertex > b->vertex);
}

// Sorts keys[0, count) in increasing order: least significant digit
// first, 11 bits at a time, skipping digits all keys share (the vertex
// numbers use far fewer than 32 bits). The edge lists are long and on the
// one thread, where a comparison sort took most of their time.
static void sort_keys(uint64_t* keys, uint32_t count) {
  uint64_t* tmp = bk_alloc(sizeof(uint64_t) * (count ? count : 1));
  uint32_t* histogram = bk_alloc(sizeof(uint32_t) * 2048);
  uint64_t *from = keys, *to = tmp;
  for (int shift = 0; shift < 64; shift += 11) {
    memset(histogram, 0, sizeof(uint32_t) * 2048);
    for (uint32_t i = 0; i < count; ++i)
      histogram[(from[i] >> shift) & 2047]++;
    if (count == 0 || histogram[(from[0] >> shift) & 2047] == count) continue; // one digit: already in order
    uint32_t sum = 0;
    for (uint32_t d = 0; d < 2048; ++d) {
      uint32_t n = histogram[d];
      histogram[d] = sum;
      sum += n;
    }
    for (uint32_t i = 0; i < count; ++i)
      to[histogram[(from[i] >> shift) & 2047]++] = from[i];
    uint64_t* t = from;
    from = to;
    to = t;
  }
  if (from != keys) memcpy(keys, from, sizeof(uint64_t) * count);
  bk_free(tmp);
  bk_free(histogram);
}

typedef struct graph {
  piercing* piercings;
  uint32_t piercing_count;
  int8_t* status; // per complex vertex: 1 inside the source, 0 outside, -1 not on the Voronoi graph
} graph;

// Range of piercings on one Voronoi edge.
static uint32_t find_piercings(const graph* g, uint64_t edge, uint32_t* first) {
  uint32_t lo = 0, hi = g->piercing_count;
  while (lo < hi) {
    uint32_t mid = (lo + hi) / 2;
    if (g->piercings[mid].edge < edge)
      lo = mid + 1;
    else
      hi = mid;
  }
  uint32_t end = lo;
  while (end < g->piercing_count && g->piercings[end].edge == edge)
    end++;
  *first = lo;
  return end - lo;
}

static uint32_t edge_piercings(const bk_cell_complex* cx, const graph* g, uint32_t u, uint32_t v,
                               uint32_t* first) {
  int32_t ids[3];
  *first = 0;
  if (!common_ids(&cx->keys[u], &cx->keys[v], ids) || ids[0] < 0) return 0;
  return find_piercings(g, edge_key3(ids), first);
}

static bool classify(const bk_cell_complex* cx, const bk_cell_polytope* polys,
                     const bk_cell_surface* surfaces, uint32_t cells, graph* g, bk_error* err) {
  // Piercings, each recorded once (by the lowest of its three cells).
  uint32_t capacity = 0;
  for (uint32_t c = 0; c < cells; ++c)
    for (uint32_t k = 0; k < surfaces[c].vertex_count; ++k) {
      const bk_cell_key* key = &cx->keys[surfaces[c].vertices[k]];
      if (key->kind != BK_CELL_PIERCING || key->s[0] != (int32_t)c) continue;
      if (g->piercing_count == capacity) {
        capacity = bk_grow_capacity(capacity, g->piercing_count + 1);
        g->piercings = bk_realloc(g->piercings, sizeof(piercing) * capacity);
      }
      g->piercings[g->piercing_count++] = (piercing){edge_key3(key->s), surfaces[c].vertices[k]};
    }
  if (g->piercing_count) bk_sort(g->piercings, g->piercing_count, sizeof(piercing), compare_piercings);
  // The Voronoi graph's edges, once each.
  uint32_t pair_count = 0;
  for (uint32_t c = 0; c < cells; ++c)
    pair_count += polys[c].loop_count;
  uint64_t* pairs = bk_alloc(sizeof(uint64_t) * (pair_count ? pair_count : 1));
  pair_count = 0;
  for (uint32_t c = 0; c < cells; ++c) {
    const bk_cell_polytope* p = &polys[c];
    for (uint32_t f = 0; f < p->faces; ++f)
      for (uint32_t k = 0; k < p->face_count[f]; ++k) {
        uint32_t u = p->loop[p->face_first[f] + k],
                 v = p->loop[p->face_first[f] + (k + 1) % p->face_count[f]];
        pairs[pair_count++] = bk_edge_key(u, v);
      }
  }
  sort_keys(pairs, pair_count);
  uint32_t unique = 0;
  for (uint32_t i = 0; i < pair_count; ++i)
    if (unique == 0 || pairs[i] != pairs[unique - 1]) pairs[unique++] = pairs[i];
  // Adjacency (both directions) in compressed rows.
  uint32_t n = cx->count;
  uint32_t* start = bk_calloc(n + 1, sizeof(uint32_t));
  for (uint32_t i = 0; i < unique; ++i) {
    start[(uint32_t)(pairs[i] >> 32) + 1]++;
    start[(uint32_t)pairs[i] + 1]++;
  }
  for (uint32_t i = 0; i < n; ++i)
    start[i + 1] += start[i];
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * (n ? n : 1));
  memcpy(fill, start, sizeof(uint32_t) * n);
  uint32_t* adjacent = bk_alloc(sizeof(uint32_t) * (2 * unique + 1));
  for (uint32_t i = 0; i < unique; ++i) {
    uint32_t a = (uint32_t)(pairs[i] >> 32), b = (uint32_t)pairs[i];
    adjacent[fill[a]++] = b;
    adjacent[fill[b]++] = a;
  }
  bk_free(fill);
  bk_free(pairs);
  g->status = bk_alloc(n ? n : 1);
  memset(g->status, -1, n);
  uint32_t* queue = bk_alloc(sizeof(uint32_t) * (n ? n : 1));
  uint32_t head = 0, tail = 0;
  for (uint32_t v = 0; v < n; ++v) {
    const bk_cell_key* k = &cx->keys[v];
    if (k->kind == BK_CELL_CORNER && k->s[0] < 0 && start[v + 1] > start[v]) {
      g->status[v] = 0; // on the box: outside the source
      queue[tail++] = v;
    }
  }
  bool ok = true;
  while (head < tail && ok) {
    uint32_t u = queue[head++];
    for (uint32_t e = start[u]; e < start[u + 1]; ++e) {
      uint32_t v = adjacent[e], first = 0;
      int8_t expect = (int8_t)(g->status[u] ^ (edge_piercings(cx, g, u, v, &first) & 1u));
      if (g->status[v] < 0) {
        g->status[v] = expect;
        queue[tail++] = v;
      } else if (g->status[v] != expect) {
        ok = false;
        break;
      }
    }
  }
  bk_free(queue);
  bk_free(start);
  bk_free(adjacent);
  if (!ok)
    return bk_error_set(err, "fracture: the cells' edges cross the surface inconsistently (rounding in a "
                             "near-degenerate seed layout); try another seed");
  return true;
}

typedef struct face_scratch {
  uint32_t* edges; // local directed edges
  uint32_t edge_count, edge_capacity;
  uint32_t* global; // local -> complex vertex
  double* xy;
  uint32_t vertex_count, vertex_capacity;
  bk_index_map local;
  double* params;
  uint32_t param_capacity;
} face_scratch;

static uint32_t local_vertex(face_scratch* s, const bk_cell_complex* cx, uint32_t v, bk_vec3 u, bk_vec3 w) {
  bool inserted = false;
  uint32_t* slot = bk_index_map_insert(&s->local, v, s->vertex_count, &inserted);
  if (!inserted) return *slot;
  if (s->vertex_count == s->vertex_capacity) {
    s->vertex_capacity = bk_grow_capacity(s->vertex_capacity, s->vertex_count + 1);
    s->global = bk_realloc(s->global, sizeof(uint32_t) * s->vertex_capacity);
    s->xy = bk_realloc(s->xy, sizeof(double) * 2 * s->vertex_capacity);
  }
  s->global[s->vertex_count] = v;
  s->xy[2 * s->vertex_count] = bk_v3_dot(cx->points[v], u);
  s->xy[2 * s->vertex_count + 1] = bk_v3_dot(cx->points[v], w);
  return s->vertex_count++;
}

static void add_edge(face_scratch* s, const bk_cell_complex* cx, uint32_t a, uint32_t b, bk_vec3 u,
                     bk_vec3 w) {
  if (a == b) return;
  uint32_t la = local_vertex(s, cx, a, u, w), lb = local_vertex(s, cx, b, u, w);
  if (s->edge_count + 2 > s->edge_capacity) {
    s->edge_capacity = bk_grow_capacity(s->edge_capacity, s->edge_count + 2);
    s->edges = bk_realloc(s->edges, sizeof(uint32_t) * s->edge_capacity);
  }
  s->edges[s->edge_count++] = la;
  s->edges[s->edge_count++] = lb;
}

// Appends the stretches of the Voronoi edge a -> b that run inside the source.
static bool add_voronoi_edge(face_scratch* s, const bk_cell_complex* cx, const graph* g, uint32_t a,
                             uint32_t b, bk_vec3 u, bk_vec3 w) {
  uint32_t first = 0, count = edge_piercings(cx, g, a, b, &first);
  if (g->status[a] < 0 || g->status[b] < 0) return false;
  if (count == 0) {
    if (g->status[a] != g->status[b]) return false;
    if (g->status[a]) add_edge(s, cx, a, b, u, w);
    return true;
  }
  // Order the piercings along the edge (insertion sort: a handful at most).
  if (s->param_capacity < 2 * count) {
    s->param_capacity = 2 * count;
    s->params = bk_realloc(s->params, sizeof(double) * s->param_capacity);
  }
  bk_vec3 pa = cx->points[a], d = bk_v3_sub(cx->points[b], pa);
  double len2 = bk_v3_dot(d, d);
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t v = g->piercings[first + i].vertex;
    double t = bk_v3_dot(bk_v3_sub(cx->points[v], pa), d) / len2;
    uint32_t j = i;
    for (; j > 0 && s->params[2 * (j - 1)] > t; --j) {
      s->params[2 * j] = s->params[2 * (j - 1)];
      s->params[2 * j + 1] = s->params[2 * (j - 1) + 1];
    }
    s->params[2 * j] = t;
    s->params[2 * j + 1] = (double)v;
  }
  uint32_t at = a;
  int inside = g->status[a];
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t v = (uint32_t)s->params[2 * i + 1];
    if (inside) add_edge(s, cx, at, v, u, w);
    at = v;
    inside ^= 1;
  }
  if (inside != g->status[b]) return false;
  if (inside) add_edge(s, cx, at, b, u, w);
  return true;
}

static void push_face(bk_cell_faces* out, bk_cell_face face, const face_scratch* s, const uint32_t* tris,
                      uint32_t tri_count) {
  if (out->count == out->capacity) {
    out->capacity = bk_grow_capacity(out->capacity, out->count + 1);
    out->faces = bk_realloc(out->faces, sizeof(bk_cell_face) * out->capacity);
  }
  if (out->triangle_count + tri_count > out->triangle_capacity) {
    out->triangle_capacity = bk_grow_capacity(out->triangle_capacity, out->triangle_count + tri_count);
    out->triangles = bk_realloc(out->triangles, sizeof(uint32_t) * 3 * out->triangle_capacity);
  }
  face.first = out->triangle_count;
  face.count = tri_count;
  for (uint32_t i = 0; i < 3 * tri_count; ++i)
    out->triangles[3 * out->triangle_count + i] = s->global[tris[i]];
  out->triangle_count += tri_count;
  out->faces[out->count++] = face;
}

// The faces of a run of cells on one thread. Cells are taken in increasing
// order from a shared counter, each cell's faces kept together, so joining
// them in cell order gives the same faces for any number of threads.
typedef struct face_worker {
  const bk_cell_complex* cx;
  const graph* g;
  const bk_cell_polytope* polys;
  const bk_cell_surface* surfaces;
  uint32_t cells;
  bool join; // a face that cannot be triangulated joins its cells instead of failing
  atomic_uint* next;
  atomic_bool* failed;
  uint32_t index;
  uint32_t* cell_worker; // per cell: the worker that built its faces
  uint32_t* cell_first;  // per cell: its first face in that worker's list
  uint32_t* cell_count;  // per cell: how many faces it built
  bk_cell_faces out;
  uint32_t failed_cell; // the lowest cell whose faces failed, or UINT32_MAX
  bk_error error;       // why
} face_worker;

// The faces cell c builds (those towards higher cells) into w->out.
static bool cell_faces(face_worker* w, bk_cap* cap, face_scratch* s, uint32_t c) {
  const bk_cell_complex* cx = w->cx;
  const bk_cell_polytope* p = &w->polys[c];
  const bk_cell_surface* sf = &w->surfaces[c];
  for (uint32_t f = 0; f < p->faces; ++f) {
    int32_t other = p->planes[f];
    if (other <= (int32_t)c) continue; // box faces, and faces the lower cell builds
    bk_vec3 n = bk_v3_normalize(bk_v3_sub(cx->seeds[other], cx->seeds[c]));
    bk_vec3 u = bk_v3(0, 0, 0), v = bk_v3(0, 0, 0);
    bk_plane_basis(n, &u, &v);
    s->edge_count = s->vertex_count = 0;
    bk_index_map_clear(&s->local);
    const uint32_t* loop = p->loop + p->face_first[f];
    uint32_t count = p->face_count[f];
    bool ok = true;
    for (uint32_t k = 0; k < count && ok; ++k)
      ok = add_voronoi_edge(s, cx, w->g, loop[k], loop[(k + 1) % count], u, v);
    uint32_t source_triangle = UINT32_MAX;
    for (uint32_t q = 0; q < sf->polygon_count && ok; ++q) {
      const bk_cell_polygon* poly = &sf->polygons[q];
      for (uint32_t k = 0; k < poly->count; ++k)
        if (sf->supports[poly->first + k] == other) {
          // The surface runs a -> b here; the cut face runs back along it.
          uint32_t a = sf->vertices[poly->first + k], b = sf->vertices[poly->first + (k + 1) % poly->count];
          add_edge(s, cx, b, a, u, v);
          if (source_triangle == UINT32_MAX) source_triangle = poly->triangle;
        }
    }
    if (!ok)
      return bk_error_set(
          &w->error, "fracture: a Voronoi edge between cells %u and %d crosses the surface inconsistently", c,
          other);
    if (s->edge_count == 0) continue; // the face lies outside the source
    const uint32_t* tris = NULL;
    uint32_t tri_count = 0;
    bk_error inner = {0};
    if (!bk_cap_triangulate(cap, s->edges, s->edge_count / 2, s->xy, s->vertex_count, &tris, &tri_count,
                            &inner)) {
      if (w->join) {
        // The loops cross (the source's surface crosses itself on this
        // plane): no face of these vertices can close them. The two cells
        // become one piece instead, as the planes pattern leaves a piece
        // uncut whose cuts all fail.
        bk_cell_faces* out = &w->out;
        out->joined = bk_realloc(out->joined, sizeof(uint32_t) * 2 * (out->joined_count + 1));
        out->joined[2 * out->joined_count] = c;
        out->joined[2 * out->joined_count + 1] = (uint32_t)other;
        out->joined_count++;
        continue;
      }
      return bk_error_set(&w->error,
                          "fracture: the cut face between cells %u and %d cannot be triangulated (%s)", c,
                          other, inner.message);
    }
    push_face(&w->out,
              (bk_cell_face){.a = c, .b = (uint32_t)other, .source_triangle = source_triangle, .normal = n},
              s, tris, tri_count);
  }
  return true;
}

static void* face_work(void* arg) {
  face_worker* w = arg;
  bk_cap* cap = bk_cap_create();
  face_scratch s = {0};
  bk_index_map_init(&s.local, 64);
  for (;;) {
    // After a failure only lower cells matter: they were all handed out already.
    if (atomic_load(w->failed)) break;
    uint32_t c = atomic_fetch_add(w->next, 1u);
    if (c >= w->cells) break;
    w->cell_worker[c] = w->index;
    w->cell_first[c] = w->out.count;
    if (!cell_faces(w, cap, &s, c)) {
      w->failed_cell = c;
      atomic_store(w->failed, true);
    }
    w->cell_count[c] = w->out.count - w->cell_first[c];
  }
  bk_cap_destroy(cap);
  bk_index_map_free(&s.local);
  bk_free(s.edges);
  bk_free(s.global);
  bk_free(s.xy);
  bk_free(s.params);
  return NULL;
}

static int compare_u64(const void* pa, const void* pb) {
  uint64_t a = *(const uint64_t*)pa, b = *(const uint64_t*)pb;
  return a < b ? -1 : (a > b);
}

// The workers' joined pairs, in increasing order whatever the threads.
static void collect_joined(const face_worker* workers, uint32_t threads, bk_cell_faces* out) {
  uint32_t total = 0;
  for (uint32_t t = 0; t < threads; ++t)
    total += workers[t].out.joined_count;
  if (total == 0) return;
  uint64_t* keys = bk_alloc(sizeof(uint64_t) * total);
  uint32_t n = 0;
  for (uint32_t t = 0; t < threads; ++t)
    for (uint32_t i = 0; i < workers[t].out.joined_count; ++i)
      keys[n++] = (uint64_t)workers[t].out.joined[2 * i] << 32 | workers[t].out.joined[2 * i + 1];
  bk_sort(keys, total, sizeof(uint64_t), compare_u64);
  out->joined = bk_alloc(sizeof(uint32_t) * 2 * total);
  for (uint32_t i = 0; i < total; ++i) {
    out->joined[2 * i] = (uint32_t)(keys[i] >> 32);
    out->joined[2 * i + 1] = (uint32_t)keys[i];
  }
  out->joined_count = total;
  bk_free(keys);
}

bool bk_cell_build_faces(bk_cell_complex* cx, const bk_cell_polytope* polys, const bk_cell_surface* surfaces,
                         uint32_t cells, uint32_t threads, bool join, bk_cell_faces* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  graph g = {0};
  if (!classify(cx, polys, surfaces, cells, &g, err)) {
    bk_free(g.piercings);
    bk_free(g.status);
    return false;
  }
  threads = threads ? threads : 1;
  face_worker* workers = bk_calloc(threads, sizeof(face_worker));
  uint32_t* cell_worker = bk_alloc(sizeof(uint32_t) * (cells ? cells : 1));
  uint32_t* cell_first = bk_alloc(sizeof(uint32_t) * (cells ? cells : 1));
  uint32_t* cell_count = bk_alloc(sizeof(uint32_t) * (cells ? cells : 1));
  atomic_uint next = 0;
  atomic_bool failed = false;
  for (uint32_t t = 0; t < threads; ++t)
    workers[t] = (face_worker){.cx = cx,
                               .g = &g,
                               .polys = polys,
                               .surfaces = surfaces,
                               .cells = cells,
                               .join = join,
                               .next = &next,
                               .failed = &failed,
                               .index = t,
                               .cell_worker = cell_worker,
                               .cell_first = cell_first,
                               .cell_count = cell_count,
                               .failed_cell = UINT32_MAX};
  bk_fracture_run_jobs(face_work, workers, sizeof *workers, threads);
  const face_worker* first_failure = NULL;
  for (uint32_t t = 0; t < threads; ++t)
    if (workers[t].failed_cell != UINT32_MAX &&
        (!first_failure || workers[t].failed_cell < first_failure->failed_cell))
      first_failure = &workers[t];
  bool ok = first_failure == NULL;
  if (!ok && err) *err = first_failure->error;
  // Join the workers' faces in cell order.
  for (uint32_t t = 0; t < threads && ok; ++t) {
    out->capacity += workers[t].out.count;
    out->triangle_capacity += workers[t].out.triangle_count;
  }
  if (ok) {
    out->faces = bk_alloc(sizeof(bk_cell_face) * (out->capacity ? out->capacity : 1));
    out->triangles = bk_alloc(sizeof(uint32_t) * 3 * (out->triangle_capacity ? out->triangle_capacity : 1));
  }
  for (uint32_t c = 0; c < cells && ok; ++c) {
    const bk_cell_faces* from = &workers[cell_worker[c]].out;
    for (uint32_t i = cell_first[c]; i < cell_first[c] + cell_count[c]; ++i) {
      bk_cell_face face = from->faces[i];
      memcpy(out->triangles + 3 * out->triangle_count, from->triangles + 3 * face.first,
             sizeof(uint32_t) * 3 * face.count);
      face.first = out->triangle_count;
      out->triangle_count += face.count;
      out->faces[out->count++] = face;
    }
  }
  if (ok) collect_joined(workers, threads, out);
  for (uint32_t t = 0; t < threads; ++t)
    bk_cell_faces_free(&workers[t].out);
  bk_free(workers);
  bk_free(cell_worker);
  bk_free(cell_first);
  bk_free(cell_count);
  bk_free(g.piercings);
  bk_free(g.status);
  if (!ok) bk_cell_faces_free(out);
  return ok;
}

void bk_cell_faces_free(bk_cell_faces* f) {
  bk_free(f->faces);
  bk_free(f->triangles);
  bk_free(f->joined);
  memset(f, 0, sizeof *f);
}
