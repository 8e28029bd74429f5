// The named vertices of the cell complex and each cell's convex polytope.
// A vertex's coordinates are a function of its name alone (which source
// position, edge or triangle; which seeds or box planes), evaluated in one
// fixed order, so every cell that reaches a vertex gets bit-identical
// coordinates and the same index.
#include <stdlib.h>
#include <string.h>

#include "cell_complex.h"

// ---------------------------------------------------------------- vertex table

static uint64_t key_hash(const bk_cell_key* k) {
  uint64_t h = bk_hash_bytes(BK_FNV_OFFSET, k, sizeof *k);
  return h ^ (h >> 29);
}

static bool key_equal(const bk_cell_key* a, const bk_cell_key* b) { return memcmp(a, b, sizeof *a) == 0; }

void bk_cell_complex_init(bk_cell_complex* cx, const bk_mesh* source, const bk_vec3* seeds,
                          uint32_t seed_count) {
  memset(cx, 0, sizeof *cx);
  cx->planar_axis = -1;
  cx->source = source;
  cx->seeds = seeds;
  cx->seed_count = seed_count;
  bk_aabb box = bk_mesh_bounds(source);
  for (uint32_t i = 0; i < seed_count; ++i) {
    box.min = bk_v3_min(box.min, seeds[i]);
    box.max = bk_v3_max(box.max, seeds[i]);
  }
  // A margin keeps every box plane clear of the source, so no box face ever
  // meets the solid and the box's corners are known to lie outside it.
  // It is kept small: a cell on the outside reaches to the box, and the
  // farther it reaches, the more seeds may cut it.
  bk_vec3 extent = bk_v3_sub(box.max, box.min);
  double pad = 0.02 * fmax(extent.x, fmax(extent.y, extent.z)) + 1e-3;
  bk_vec3 margin = bk_v3(pad, pad, pad);
  cx->box = (bk_aabb){bk_v3_sub(box.min, margin), bk_v3_add(box.max, margin)};
  cx->slot_mask = 1023;
  cx->slots = bk_calloc(cx->slot_mask + 1, sizeof(uint32_t));
}

void bk_cell_complex_free(bk_cell_complex* cx) {
  free(cx->keys);
  free(cx->points);
  free(cx->slots);
  memset(cx, 0, sizeof *cx);
}

static bk_vec3 seed_of(const bk_cell_complex* cx, int32_t id) { return cx->seeds[id]; }

// Row of the bisector of seeds a < b: 2 (b - a) . x = (b - a) . (b + a).
static void bisector_row(const bk_cell_complex* cx, int32_t a, int32_t b, double row[4]) {
  bk_vec3 sa = seed_of(cx, a), sb = seed_of(cx, b);
  bk_vec3 d = bk_v3_sub(sb, sa);
  row[0] = 2.0 * d.x, row[1] = 2.0 * d.y, row[2] = 2.0 * d.z;
  row[3] = bk_v3_dot(d, bk_v3_add(sb, sa));
}

static void box_row(const bk_cell_complex* cx, int32_t id, double row[4]) {
  int plane = -id - 1, axis = plane / 2;
  row[0] = axis == 0, row[1] = axis == 1, row[2] = axis == 2;
  bk_vec3 corner = plane & 1 ? cx->box.max : cx->box.min;
  row[3] = axis == 0 ? corner.x : (axis == 1 ? corner.y : corner.z);
}

// Solves three rows [a b c | d] by Cramer's rule (one fixed order of
// operations: the same rows always give the same bits).
static bk_vec3 solve3(const double r[3][4]) {
  double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
               r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
               r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  double x = r[0][3] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
             r[0][1] * (r[1][3] * r[2][2] - r[1][2] * r[2][3]) +
             r[0][2] * (r[1][3] * r[2][1] - r[1][1] * r[2][3]);
  double y = r[0][0] * (r[1][3] * r[2][2] - r[1][2] * r[2][3]) -
             r[0][3] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
             r[0][2] * (r[1][0] * r[2][3] - r[1][3] * r[2][0]);
  double z = r[0][0] * (r[1][1] * r[2][3] - r[1][3] * r[2][1]) -
             r[0][1] * (r[1][0] * r[2][3] - r[1][3] * r[2][0]) +
             r[0][3] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  return bk_v3(x / det, y / det, z / det);
}

static double bisector_value(const bk_cell_complex* cx, int32_t a, int32_t b, bk_vec3 p) {
  bk_cell_side side = {.low = true};
  bisector_row(cx, a, b, side.row);
  return bk_cell_side_value(&side, p);
}

bk_cell_side bk_cell_side_of(const bk_cell_complex* cx, int32_t cell, int32_t other) {
  bk_cell_side side = {.low = cell < other};
  bisector_row(cx, cell < other ? cell : other, cell < other ? other : cell, side.row);
  return side;
}

static bk_vec3 compute_point(const bk_cell_complex* cx, const bk_cell_key* k) {
  const bk_mesh* m = cx->source;
  switch ((bk_cell_vertex_kind)k->kind) {
  case BK_CELL_SOURCE:
    return m->positions[k->a];
  case BK_CELL_CROSSING: {
    bk_vec3 pa = m->positions[k->a], pb = m->positions[k->b];
    double fa = bisector_value(cx, k->s[0], k->s[1], pa), fb = bisector_value(cx, k->s[0], k->s[1], pb);
    double t = fa / (fa - fb);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return bk_v3_add(pa, bk_v3_scale(bk_v3_sub(pb, pa), t));
  }
  case BK_CELL_PIERCING: {
    bk_vec3 p0 = m->positions[bk_mesh_tri_position(m, k->a, 0)];
    bk_vec3 p1 = m->positions[bk_mesh_tri_position(m, k->a, 1)];
    bk_vec3 p2 = m->positions[bk_mesh_tri_position(m, k->a, 2)];
    bk_vec3 n = bk_v3_cross(bk_v3_sub(p1, p0), bk_v3_sub(p2, p0));
    double r[3][4];
    bisector_row(cx, k->s[0], k->s[1], r[0]);
    bisector_row(cx, k->s[0], k->s[2], r[1]);
    r[2][0] = n.x, r[2][1] = n.y, r[2][2] = n.z, r[2][3] = bk_v3_dot(n, p0);
    return solve3(r);
  }
  case BK_CELL_NOISE_POINT:
    return bk_v3(0, 0, 0); // placed by bk_cell_vertex_at
  case BK_CELL_CORNER: {
    double r[3][4];
    int rows = 0;
    int32_t first = -1;
    for (int i = 0; i < 4; ++i) {
      if (k->s[i] < 0) {
        box_row(cx, k->s[i], r[rows++]);
      } else if (first < 0) {
        first = k->s[i];
      } else {
        bisector_row(cx, first, k->s[i], r[rows++]);
      }
    }
    return solve3(r);
  }
  }
  return bk_v3(0, 0, 0);
}

static void grow_slots(bk_cell_complex* cx) {
  uint32_t size = (cx->slot_mask + 1) * 2;
  free(cx->slots);
  cx->slots = bk_calloc(size, sizeof(uint32_t));
  cx->slot_mask = size - 1;
  for (uint32_t i = 0; i < cx->count; ++i) {
    uint32_t s = (uint32_t)key_hash(&cx->keys[i]) & cx->slot_mask;
    while (cx->slots[s])
      s = (s + 1) & cx->slot_mask;
    cx->slots[s] = i + 1;
  }
}

uint32_t bk_cell_vertex_find(const bk_cell_complex* cx, const bk_cell_key* key) {
  uint32_t s = (uint32_t)key_hash(key) & cx->slot_mask;
  while (cx->slots[s]) {
    if (key_equal(&cx->keys[cx->slots[s] - 1], key)) return cx->slots[s] - 1;
    s = (s + 1) & cx->slot_mask;
  }
  return UINT32_MAX;
}

static uint32_t insert(bk_cell_complex* cx, const bk_cell_key* key, const bk_vec3* point) {
  uint32_t s = (uint32_t)key_hash(key) & cx->slot_mask;
  while (cx->slots[s]) {
    if (key_equal(&cx->keys[cx->slots[s] - 1], key)) return cx->slots[s] - 1;
    s = (s + 1) & cx->slot_mask;
  }
  if (cx->count == cx->capacity) {
    cx->capacity = bk_grow_capacity(cx->capacity, cx->count + 1);
    cx->keys = bk_realloc(cx->keys, sizeof(bk_cell_key) * cx->capacity);
    cx->points = bk_realloc(cx->points, sizeof(bk_vec3) * cx->capacity);
  }
  uint32_t index = cx->count++;
  cx->keys[index] = *key;
  cx->points[index] = point ? *point : compute_point(cx, key);
  cx->slots[s] = index + 1;
  if (cx->count * 2 > cx->slot_mask) grow_slots(cx);
  return index;
}

uint32_t bk_cell_vertex(bk_cell_complex* cx, const bk_cell_key* key) { return insert(cx, key, NULL); }

uint32_t bk_cell_vertex_at(bk_cell_complex* cx, const bk_cell_key* key, bk_vec3 point) {
  return insert(cx, key, &point);
}

bool bk_cell_belongs(const bk_cell_complex* cx, bk_vec3 p, int32_t a, int32_t b) {
  if (b < 0) { // a box plane: inside the box
    int plane = -b - 1, axis = plane / 2;
    double c = axis == 0 ? p.x : (axis == 1 ? p.y : p.z);
    bk_vec3 corner = plane & 1 ? cx->box.max : cx->box.min;
    double limit = axis == 0 ? corner.x : (axis == 1 ? corner.y : corner.z);
    return plane & 1 ? c <= limit : c >= limit;
  }
  int32_t lo = a < b ? a : b, hi = a < b ? b : a;
  double f = bisector_value(cx, lo, hi, p); // > 0: nearer hi
  return a == lo ? f <= 0.0 : f > 0.0;
}

// ---------------------------------------------------------------- polytopes

struct bk_cell_builder {
  bk_cell_polytope work, next;
  uint8_t* keep; // per loop entry of `work`: on the cell's side of the plane being cut
  uint32_t keep_capacity;
  uint32_t (*segments)[2]; // new face's edges: entry -> exit
  uint32_t segment_capacity;
};

bk_cell_builder* bk_cell_builder_create(void) { return bk_calloc(1, sizeof(bk_cell_builder)); }

void bk_cell_polytope_free(bk_cell_polytope* p) {
  free(p->planes);
  free(p->face_first);
  free(p->face_count);
  free(p->loop);
  memset(p, 0, sizeof *p);
}

void bk_cell_builder_destroy(bk_cell_builder* b) {
  if (!b) return;
  bk_cell_polytope_free(&b->work);
  bk_cell_polytope_free(&b->next);
  free(b->segments);
  free(b->keep);
  free(b);
}

static void sort_ids(int32_t* s, int n) {
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && s[j - 1] > s[j]; --j) {
      int32_t t = s[j];
      s[j] = s[j - 1];
      s[j - 1] = t;
    }
}

static void add_face(bk_cell_polytope* p, int32_t plane, const uint32_t* loop, uint32_t count) {
  p->planes = bk_realloc(p->planes, sizeof(int32_t) * (p->faces + 1));
  p->face_first = bk_realloc(p->face_first, sizeof(uint32_t) * (p->faces + 1));
  p->face_count = bk_realloc(p->face_count, sizeof(uint32_t) * (p->faces + 1));
  p->planes[p->faces] = plane;
  p->face_first[p->faces] = p->loop_count;
  p->face_count[p->faces] = count;
  p->faces++;
  p->loop = bk_realloc(p->loop, sizeof(uint32_t) * (p->loop_count + count));
  memcpy(p->loop + p->loop_count, loop, sizeof(uint32_t) * count);
  p->loop_count += count;
}

static void reset(bk_cell_polytope* p) { p->faces = p->loop_count = 0; }

static void init_box(bk_cell_complex* cx, uint32_t cell, bk_cell_polytope* p) {
  static const uint8_t loops[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                      {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  uint32_t corner[8];
  for (int c = 0; c < 8; ++c) {
    bk_cell_key k = {.kind = BK_CELL_CORNER};
    k.s[0] = (int32_t)cell, k.s[1] = c & 1 ? -2 : -1, k.s[2] = c & 2 ? -4 : -3, k.s[3] = c & 4 ? -6 : -5;
    sort_ids(k.s, 4);
    corner[c] = bk_cell_vertex(cx, &k);
  }
  reset(p);
  for (int f = 0; f < 6; ++f) {
    uint32_t loop[4] = {corner[loops[f][0]], corner[loops[f][1]], corner[loops[f][2]], corner[loops[f][3]]};
    add_face(p, -(f + 1), loop, 4);
  }
}

// The vertex where the polytope edge u-v crosses the bisector with m: its
// name is the edge's three ids (the two names' common part) plus m.
static bool crossing_vertex(bk_cell_complex* cx, uint32_t u, uint32_t v, int32_t m, uint32_t* out) {
  const bk_cell_key *ku = &cx->keys[u], *kv = &cx->keys[v];
  bk_cell_key k = {.kind = BK_CELL_CORNER};
  int n = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (ku->s[i] == kv->s[j]) {
        if (n == 3) return false;
        k.s[n++] = ku->s[i];
      }
  if (n != 3) return false;
  k.s[3] = m;
  sort_ids(k.s, 4);
  *out = bk_cell_vertex(cx, &k);
  return true;
}

// Cuts the polytope by the bisector of `cell` and seed m, keeping cell's side.
static bool clip(bk_cell_builder* b, bk_cell_complex* cx, uint32_t cell, int32_t m) {
  bk_cell_polytope* p = &b->work;
  bool any_out = false, any_in = false;
  if (b->keep_capacity < p->loop_count) {
    b->keep_capacity = bk_grow_capacity(b->keep_capacity, p->loop_count);
    b->keep = bk_realloc(b->keep, b->keep_capacity);
  }
  bk_cell_side side = bk_cell_side_of(cx, (int32_t)cell, m);
  for (uint32_t i = 0; i < p->loop_count; ++i) {
    bool in = bk_cell_side_keeps(&side, cx->points[p->loop[i]]);
    b->keep[i] = in;
    any_out |= !in;
    any_in |= in;
  }
  if (!any_out) return true;
  if (!any_in) return false; // the seed itself would be cut away: coincident seeds
  bk_cell_polytope* q = &b->next;
  reset(q);
  uint32_t segments = 0;
  uint32_t scratch_capacity = 0, *scratch = NULL;
  for (uint32_t f = 0; f < p->faces; ++f) {
    const uint32_t* loop = p->loop + p->face_first[f];
    uint32_t count = p->face_count[f], out = 0;
    if (scratch_capacity < 2 * count + 2) {
      scratch_capacity = 2 * count + 2;
      scratch = bk_realloc(scratch, sizeof(uint32_t) * scratch_capacity);
    }
    uint32_t exit_vertex = UINT32_MAX, entry_vertex = UINT32_MAX;
    const uint8_t* keep = b->keep + p->face_first[f];
    for (uint32_t k = 0; k < count; ++k) {
      uint32_t u = loop[k], v = loop[(k + 1) % count];
      bool iu = keep[k], iv = keep[(k + 1) % count];
      if (iu) scratch[out++] = u;
      if (iu != iv) {
        uint32_t x = 0;
        if (!crossing_vertex(cx, u, v, m, &x)) {
          free(scratch);
          return false;
        }
        scratch[out++] = x;
        if (iu)
          exit_vertex = x;
        else
          entry_vertex = x;
      }
    }
    if (exit_vertex != UINT32_MAX) {
      if (entry_vertex == UINT32_MAX) {
        free(scratch);
        return false;
      }
      if (segments == b->segment_capacity) {
        b->segment_capacity = bk_grow_capacity(b->segment_capacity, segments + 1);
        b->segments = bk_realloc(b->segments, sizeof *b->segments * b->segment_capacity);
      }
      // This face runs exit -> entry along the new plane; the new face runs back.
      b->segments[segments][0] = entry_vertex;
      b->segments[segments][1] = exit_vertex;
      segments++;
    }
    if (out >= 3) add_face(q, p->planes[f], scratch, out);
  }
  free(scratch);
  if (segments < 3) return false;
  // Chain the segments into the new face's loop.
  uint32_t* loop = bk_alloc(sizeof(uint32_t) * segments);
  uint32_t at = 0, n = 0;
  for (; n < segments; ++n) {
    loop[n] = b->segments[at][0];
    uint32_t next = b->segments[at][1], found = UINT32_MAX;
    for (uint32_t s = 0; s < segments; ++s)
      if (b->segments[s][0] == next) found = s;
    if (found == UINT32_MAX) break;
    at = found;
    if (at == 0) {
      n++;
      break;
    }
  }
  bool closed = n == segments && at == 0;
  if (closed) add_face(q, m, loop, segments);
  free(loop);
  if (!closed) return false;
  bk_cell_polytope t = b->work;
  b->work = b->next;
  b->next = t;
  return true;
}

double bk_cell_distance(const bk_cell_complex* cx, bk_vec3 a, bk_vec3 b) {
  bk_vec3 d = bk_v3_sub(a, b);
  if (cx->planar_axis == 0) d.x = 0.0;
  if (cx->planar_axis == 1) d.y = 0.0;
  if (cx->planar_axis == 2) d.z = 0.0;
  return bk_v3_length(d);
}

double bk_cell_reach(const bk_cell_complex* cx, const bk_cell_polytope* p, uint32_t cell) {
  double r = 0.0;
  for (uint32_t i = 0; i < p->loop_count; ++i)
    r = fmax(r, bk_cell_distance(cx, cx->points[p->loop[i]], cx->seeds[cell]));
  return r;
}

bool bk_cell_polytope_build(bk_cell_builder* b, bk_cell_complex* cx, uint32_t cell, const uint32_t* near,
                            uint32_t near_count, bk_cell_polytope* out) {
  init_box(cx, cell, &b->work);
  bk_vec3 seed = cx->seeds[cell];
  double radius = bk_cell_reach(cx, &b->work, cell);
  bool stale = false; // clipping only shrinks the cell, so a stale reach is an upper bound
  for (uint32_t i = 0; i < near_count; ++i) {
    // Past twice the cell's reach no bisector can cut it any more.
    double d = bk_v3_length(bk_v3_sub(cx->seeds[near[i]], seed));
    if (d > 2.0 * radius && stale) radius = bk_cell_reach(cx, &b->work, cell), stale = false;
    if (d > 2.0 * radius) break;
    if (!clip(b, cx, cell, (int32_t)near[i])) return false;
    stale = true;
  }
  bk_cell_polytope_free(out);
  out->planes = bk_alloc(sizeof(int32_t) * b->work.faces);
  out->face_first = bk_alloc(sizeof(uint32_t) * b->work.faces);
  out->face_count = bk_alloc(sizeof(uint32_t) * b->work.faces);
  out->loop = bk_alloc(sizeof(uint32_t) * b->work.loop_count);
  memcpy(out->planes, b->work.planes, sizeof(int32_t) * b->work.faces);
  memcpy(out->face_first, b->work.face_first, sizeof(uint32_t) * b->work.faces);
  memcpy(out->face_count, b->work.face_count, sizeof(uint32_t) * b->work.faces);
  memcpy(out->loop, b->work.loop, sizeof(uint32_t) * b->work.loop_count);
  out->faces = b->work.faces;
  out->loop_count = b->work.loop_count;
  return true;
}

// ---------------------------------------------------------------- seed grid

struct bk_seed_grid {
  const bk_vec3* seeds;
  bk_aabb box;
  int n[3];
  double cell;
  uint32_t* start; // per bin, into order (n0*n1*n2 + 1)
  uint32_t* order;
};

static int bin_coord(const bk_seed_grid* g, double v, double lo, int n) {
  double c = floor((v - lo) / g->cell);
  return c >= 0.0 ? (c < n ? (int)c : n - 1) : 0; // NaN too lands in bin 0
}

bk_seed_grid* bk_seed_grid_create(const bk_vec3* seeds, uint32_t count, bk_aabb box) {
  bk_seed_grid* g = bk_calloc(1, sizeof *g);
  g->seeds = seeds;
  g->box = box;
  bk_vec3 size = bk_v3_sub(box.max, box.min);
  // About two seeds per bin.
  double volume = fmax(size.x * size.y * size.z, 1e-300);
  g->cell = cbrt(volume * 2.0 / (count ? count : 1));
  g->n[0] = (int)fmin(fmax(ceil(size.x / g->cell), 1), 1024);
  g->n[1] = (int)fmin(fmax(ceil(size.y / g->cell), 1), 1024);
  g->n[2] = (int)fmin(fmax(ceil(size.z / g->cell), 1), 1024);
  g->cell = fmax(fmax(size.x / g->n[0], size.y / g->n[1]), size.z / g->n[2]);
  size_t bins = (size_t)g->n[0] * g->n[1] * g->n[2];
  g->start = bk_calloc(bins + 1, sizeof(uint32_t));
  g->order = bk_alloc(sizeof(uint32_t) * (count ? count : 1));
  uint32_t* bin_of = bk_alloc(sizeof(uint32_t) * (count ? count : 1));
  for (uint32_t i = 0; i < count; ++i) {
    int x = bin_coord(g, seeds[i].x, box.min.x, g->n[0]), y = bin_coord(g, seeds[i].y, box.min.y, g->n[1]),
        z = bin_coord(g, seeds[i].z, box.min.z, g->n[2]);
    bin_of[i] = (uint32_t)(((size_t)z * g->n[1] + y) * g->n[0] + x);
    g->start[bin_of[i] + 1]++;
  }
  for (size_t b = 0; b < bins; ++b)
    g->start[b + 1] += g->start[b];
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * bins);
  memcpy(fill, g->start, sizeof(uint32_t) * bins);
  for (uint32_t i = 0; i < count; ++i)
    g->order[fill[bin_of[i]]++] = i;
  free(fill);
  free(bin_of);
  return g;
}

void bk_seed_grid_destroy(bk_seed_grid* g) {
  if (!g) return;
  free(g->start);
  free(g->order);
  free(g);
}

typedef struct near_entry {
  double d;
  uint32_t index;
} near_entry;

static inline int compare_near(const near_entry* a, const near_entry* b) {
  if (a->d != b->d) return a->d < b->d ? -1 : 1;
  return a->index < b->index ? -1 : (a->index > b->index);
}

double bk_seed_grid_spacing(const bk_seed_grid* g, uint32_t cell) {
  bk_vec3 p = g->seeds[cell];
  int x = bin_coord(g, p.x, g->box.min.x, g->n[0]), y = bin_coord(g, p.y, g->box.min.y, g->n[1]),
      z = bin_coord(g, p.z, g->box.min.z, g->n[2]);
  // Seeds in the 3 x 3 x 3 bins around: their density gives the spacing here.
  uint32_t count = 0, bins = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        int bx = x + dx, by = y + dy, bz = z + dz;
        if (bx < 0 || by < 0 || bz < 0 || bx >= g->n[0] || by >= g->n[1] || bz >= g->n[2]) continue;
        size_t b = ((size_t)bz * g->n[1] + by) * g->n[0] + bx;
        count += g->start[b + 1] - g->start[b];
        bins++;
      }
  return cbrt(bins * g->cell * g->cell * g->cell / (count ? count : 1));
}

uint32_t bk_seed_grid_near(const bk_seed_grid* g, uint32_t cell, double radius, uint32_t** out,
                           uint32_t* capacity) {
  bk_vec3 p = g->seeds[cell];
  int lo[3] = {bin_coord(g, p.x - radius, g->box.min.x, g->n[0]),
               bin_coord(g, p.y - radius, g->box.min.y, g->n[1]),
               bin_coord(g, p.z - radius, g->box.min.z, g->n[2])};
  int hi[3] = {bin_coord(g, p.x + radius, g->box.min.x, g->n[0]),
               bin_coord(g, p.y + radius, g->box.min.y, g->n[1]),
               bin_coord(g, p.z + radius, g->box.min.z, g->n[2])};
  near_entry* list = NULL;
  uint32_t count = 0, cap = 0;
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        size_t b = ((size_t)z * g->n[1] + y) * g->n[0] + x;
        for (uint32_t k = g->start[b]; k < g->start[b + 1]; ++k) {
          uint32_t j = g->order[k];
          if (j == cell) continue;
          bk_vec3 e = bk_v3_sub(g->seeds[j], p);
          double d = bk_v3_dot(e, e); // squared: same order
          if (d > radius * radius) continue;
          if (count == cap) {
            cap = bk_grow_capacity(cap, count + 1);
            list = bk_realloc(list, sizeof(near_entry) * cap);
          }
          list[count++] = (near_entry){d, j};
        }
      }
  // Shell sort, inline: these lists are short and sorted once per cell.
  static const uint32_t gaps[] = {57, 23, 10, 4, 1};
  for (int gi = 0; gi < 5; ++gi) {
    uint32_t gap = gaps[gi];
    for (uint32_t i = gap; i < count; ++i) {
      near_entry e = list[i];
      uint32_t j = i;
      for (; j >= gap && compare_near(&list[j - gap], &e) > 0; j -= gap)
        list[j] = list[j - gap];
      list[j] = e;
    }
  }
  if (*capacity < count) {
    *capacity = count;
    *out = bk_realloc(*out, sizeof(uint32_t) * count);
  }
  for (uint32_t i = 0; i < count; ++i)
    (*out)[i] = list[i].index;
  free(list);
  return count;
}
